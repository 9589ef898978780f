/* SPDX-License-Identifier: MIT */
// cone_dilate.comp - one row of libddof/src/cone_dilate.c's raster passes on the device:
// v(p) <- max_q v(q) - slope d(p, q) with the 8-connected chamfer distance, with the CPU's
// roundings (max is exact, each subtraction rounds once, in the CPU's order), so the map comes
// out bit for bit as the CPU's: the proximity map's cone heights near 2^20 round to 1/8 px,
// and a different order of roundings would move the background blend's weights by a few
// percent. The row's links to the row before it (in the pass's direction) are independent
// (all invocations); the run along the row is a chain (invocation 0). gl_layers.c dispatches
// one work group per row, rows in pass order: a whole pass in one invocation would exceed
// llvmpipe's loop limit (65535 iterations per loop, after which it silently stops).
layout(local_size_x = 256) in;

layout(std430, binding = 2) coherent buffer Map { float map[]; };

uniform uint u_row;       // index of the row's first value
uniform uint u_prev;      // index of the row before it in the pass's direction
uniform uint u_has_prev;  // 0 for the pass's first row
uniform uint u_backward;  // 0: the forward pass (run left to right), 1: the backward pass
uniform uint u_width;
uniform float u_axial;    // slope
uniform float u_diagonal; // slope * sqrt 2, as the CPU rounds it

void main()
{
    uint row = u_row, prev = u_prev;
    if (u_has_prev != 0u)
        for (uint x = gl_LocalInvocationID.x; x < u_width; x += gl_WorkGroupSize.x) {
            float v = map[row + x];
            if (x == 0u) {
                v = max(v, map[prev] - u_axial);
                if (u_width > 1u)
                    v = max(v, map[prev + 1u] - u_diagonal);
            } else if (x + 1u == u_width) {
                v = max(v, max(map[prev + x] - u_axial, map[prev + x - 1u] - u_diagonal));
            } else {
                float side = max(map[prev + x - 1u], map[prev + x + 1u]) - u_diagonal;
                v = max(v, max(map[prev + x] - u_axial, side));
            }
            map[row + x] = v;
        }
    memoryBarrierBuffer();
    barrier();
    if (gl_LocalInvocationID.x != 0u)
        return;
    if (u_backward == 0u)
        for (uint x = 1u; x < u_width; x++)
            map[row + x] = max(map[row + x], map[row + x - 1u] - u_axial);
    else
        for (uint x = u_width - 1u; x-- > 0u;)
            map[row + x] = max(map[row + x], map[row + x + 1u] - u_axial);
}
