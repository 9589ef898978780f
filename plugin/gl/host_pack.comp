/* SPDX-License-Identifier: MIT */
// host_pack.comp - a host application's textures (ddof_gl_host_diffuse) into the working
// layout: RGBA colour from texture unit 0, the CoC diameter in px from the first channel of
// texture unit 1 (its sign ignored; below u_in_focus it conducts as 0, as on the CPU). Level 0
// of each, read with texelFetch (no filtering).
// FROM_DEPTH (ddof_gl_host_diffuse_depth): texture unit 1 holds depth instead, and the CoC is
// the camera's, d = k |1 - S1 / Z| (libddof/seam/ddof_camera_terms.h), in float. A depth that
// is NaN, zero or negative (+inf is the sky) is a bad input: the smallest such pixel index goes
// to first_bad, and the host stops before anything is written.
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, binding = 0) writeonly buffer CocOut { float coc_out[]; };
layout(std430, binding = 3) buffer Counters { uint counters[]; }; // [2]: the largest |CoC|
layout(std430, binding = 4) writeonly buffer ValueOut { vec4 value_out[]; };

layout(binding = 0) uniform sampler2D u_color;
layout(binding = 1) uniform sampler2D u_coc;

uniform uint u_width;
uniform uint u_height;
uniform float u_in_focus; // params.in_focus_threshold_px

#ifdef FROM_DEPTH
layout(std430, binding = 1) buffer FirstBad { uint first_bad; };
uniform float u_k_px;          // the CoC of a point at infinity
uniform float u_focus;         // S1 in depth units
uniform uint u_radial;         // depth is the distance to the camera
uniform float u_centre_x;      // the full frame's centre in this image's pixel coordinates
uniform float u_centre_y;
uniform float u_pixel_w_over_f; // a pixel's size over the focal length
uniform float u_pixel_h_over_f;

// The CoC of pixel xy, or -1 for a bad depth (by its bits: no NaN test a compiler may fold).
float coc_from_depth(uvec2 xy)
{
    float z = texelFetch(u_coc, ivec2(xy), 0).x;
    uint bits = floatBitsToUint(z);
    if ((bits & 0x7fffffffu) > 0x7f800000u || (bits & 0x80000000u) != 0u || bits == 0u)
        return -1.0;
    if (u_radial != 0u) { // planar Z of a point at distance r seen through the pixel's centre
        vec2 s = (vec2(xy) + 0.5 - vec2(u_centre_x, u_centre_y)) *
                 vec2(u_pixel_w_over_f, u_pixel_h_over_f);
        z /= sqrt(1.0 + dot(s, s));
    }
    return min(u_k_px * abs(1.0 - u_focus / z), MAX_COC);
}
#endif

shared uint group_largest;

// Pixel xy's colour and CoC packed; its |CoC| before the in-focus cut is returned.
float pack(uvec2 xy)
{
    uint p = xy.y * u_width + xy.x;
    value_out[p] = texelFetch(u_color, ivec2(xy), 0);
#ifdef FROM_DEPTH
    float d = coc_from_depth(xy);
    if (d < 0.0) {
        atomicMin(first_bad, p);
        d = 0.0;
    }
#else
    float d = abs(texelFetch(u_coc, ivec2(xy), 0).x);
#endif
    coc_out[p] = d >= u_in_focus ? d : 0.0;
    return d;
}

// The largest |CoC| before the cut goes to counters[2], one atomic a group (pack.comp's rule).
void main()
{
    uvec2 xy = gl_GlobalInvocationID.xy;
    if (gl_LocalInvocationIndex == 0u)
        group_largest = 0u;
    barrier();
    if (xy.x < u_width && xy.y < u_height)
        atomicMax(group_largest, floatBitsToUint(pack(xy)));
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        atomicMax(counters[2], group_largest);
}
