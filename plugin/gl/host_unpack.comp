/* SPDX-License-Identifier: MIT */
// host_unpack.comp - the result into the host's output texture, bound as image unit 0 with the
// format the program was built for (OUT_FORMAT: rgba32f or rgba16f).
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, binding = 3) readonly buffer Values { vec4 values[]; };
layout(binding = 0, OUT_FORMAT) uniform writeonly image2D u_out;

uniform uint u_width;
uniform uint u_height;

void main()
{
    uvec2 xy = gl_GlobalInvocationID.xy;
    if (xy.x >= u_width || xy.y >= u_height)
        return;
    imageStore(u_out, ivec2(xy), values[xy.y * u_width + xy.x]);
}
