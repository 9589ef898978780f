/* SPDX-License-Identifier: MIT */
// range.comp - the per-channel range of a packed (masked) colour, which the disc kernel clamps
// its result to (libddof/src/adi/lens_adi.c; gl_lens_input_range on the host for run()). Floats
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

shared uint lo_keys[256][4];
shared uint hi_keys[256][4];

// Each work group reduces its pixels in shared memory and makes one atomic per channel: one
// per pixel would serialise every invocation of the frame on the same 8 words.
void main()
{
    uint p = global_id(), i = gl_LocalInvocationID.x;
    vec4 v = p < u_pixels ? values[p] : vec4(0.0);
    for (uint c = 0u; c < 4u; c++) {
        bool used = p < u_pixels && c < u_channels;
        lo_keys[i][c] = used ? ordered(v[c]) : 0xffffffffu;
        hi_keys[i][c] = used ? ordered(v[c]) : 0u;
    }
    barrier();
    for (uint half_size = 128u; half_size > 0u; half_size /= 2u) {
        if (i < half_size)
            for (uint c = 0u; c < 4u; c++) {
                lo_keys[i][c] = min(lo_keys[i][c], lo_keys[i + half_size][c]);
                hi_keys[i][c] = max(hi_keys[i][c], hi_keys[i + half_size][c]);
            }
        barrier();
    }
    if (i == 0u)
        for (uint c = 0u; c < u_channels; c++) {
            atomicMin(range[c], lo_keys[0][c]);
            atomicMax(range[4u + c], hi_keys[0][c]);
        }
}
