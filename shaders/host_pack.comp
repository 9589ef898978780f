/* SPDX-License-Identifier: MIT */
// host_pack.comp - a host application's textures (ddof_gl_host_diffuse) into the working
// layout: RGBA colour from texture unit 0, the CoC diameter in px from the first channel of
// texture unit 1 (its sign ignored; below u_in_focus it conducts as 0, as on the CPU). Level 0
// of each, read with texelFetch (no filtering).
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, binding = 0) writeonly buffer CocOut { float coc_out[]; };
layout(std430, binding = 4) writeonly buffer ValueOut { vec4 value_out[]; };

layout(binding = 0) uniform sampler2D u_color;
layout(binding = 1) uniform sampler2D u_coc;

uniform uint u_width;
uniform uint u_height;
uniform float u_in_focus; // params.in_focus_threshold_px

void main()
{
    uvec2 xy = gl_GlobalInvocationID.xy;
    if (xy.x >= u_width || xy.y >= u_height)
        return;
    uint p = xy.y * u_width + xy.x;
    value_out[p] = texelFetch(u_color, ivec2(xy), 0);
    float d = abs(texelFetch(u_coc, ivec2(xy), 0).x);
    coc_out[p] = d >= u_in_focus ? d : 0.0;
}
