/* SPDX-License-Identifier: MIT */
// range.comp - the per-channel range of a packed (masked) colour, which the disc kernel clamps
// its result to (libddof/src/lens_adi.c; gl_lens_input_range on the host for run()). Floats
// are turned into uints whose order is the floats' order, so atomicMin/Max reduce them.
layout(local_size_x = 256) in;

layout(std430, binding = 3) readonly buffer Values { vec4 values[]; };
layout(std430, binding = 6) buffer Range { uint range[]; }; // lo keys [0..3], hi keys [4..7]

uniform uint u_pixels;
uniform uint u_channels;

uint ordered(float f)
{
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

void main()
{
    uint p = global_id();
    if (p >= u_pixels)
        return;
    vec4 v = values[p];
    for (uint c = 0u; c < u_channels; c++) {
        atomicMin(range[c], ordered(v[c]));
        atomicMax(range[4u + c], ordered(v[c]));
    }
}
