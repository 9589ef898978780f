/* SPDX-License-Identifier: MIT */
// pack.comp - the caller's images (uploaded as they lie: strided rows, 1..4 channels, the CoC
// and gamma as the first of several channels) into the solver's working layout: one vec4 per
// pixel, |CoC| and gamma as one float each. Where gamma is 0 the colour is not read (it may be
// NaN): it becomes 0, as in libddof/src/adi/heat_adi.c. The largest |CoC| before the in-focus
// cut goes to counters[2] (the report's, as the CPU's solvers measure it), one atomic a group.
layout(local_size_x = 256) in;

layout(std430, binding = 3) buffer Counters { uint counters[]; };

layout(std430, binding = 0) writeonly buffer CocOut { float coc_out[]; };
layout(std430, binding = 1) writeonly buffer HeatOut { float heat_out[]; };
layout(std430, binding = 4) writeonly buffer ValueOut { vec4 value_out[]; };
layout(std430, binding = 5) readonly buffer RawColor { float raw_color[]; };
layout(std430, binding = 6) readonly buffer RawCoc { float raw_coc[]; };
layout(std430, binding = 7) readonly buffer RawHeat { float raw_heat[]; };

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_color_offset;  // floats before the first pixel (device-resident images)
uniform uint u_color_stride;  // floats
uniform uint u_has_coc;       // 0: every pixel has u_uniform_coc
uniform float u_uniform_coc;
uniform uint u_coc_offset;
uniform uint u_coc_stride;
uniform uint u_coc_channels;
uniform float u_in_focus;     // a |CoC| below this conducts as 0 (never a uniform CoC)
uniform uint u_has_gamma;
uniform uint u_gamma_offset;
uniform uint u_gamma_stride;
uniform uint u_gamma_channels;

shared uint group_largest;

void pack(uint p)
{
    uint x = p % u_width, y = p / u_width;
    float g = u_has_gamma != 0u
                  ? raw_heat[u_gamma_offset + y * u_gamma_stride + x * u_gamma_channels]
                  : 1.0;
    vec4 v = vec4(0.0);
    if (g > 0.0)
        for (uint c = 0u; c < u_channels; c++)
            v[c] = raw_color[u_color_offset + y * u_color_stride + x * u_channels + c];
    value_out[p] = v;
    float d = abs(u_uniform_coc);
    if (u_has_coc != 0u)
        d = abs(raw_coc[u_coc_offset + y * u_coc_stride + x * u_coc_channels]);
    atomicMax(group_largest, floatBitsToUint(d)); // |CoC| >= 0: its bits order as it does
    coc_out[p] = u_has_coc == 0u || d >= u_in_focus ? d : 0.0;
    if (u_has_gamma != 0u)
        heat_out[p] = g;
}

void main()
{
    uint p = global_id();
    if (gl_LocalInvocationIndex == 0u)
        group_largest = 0u;
    barrier();
    if (p < u_width * u_height)
        pack(p);
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        atomicMax(counters[2], group_largest);
}
