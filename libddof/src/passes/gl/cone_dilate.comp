/* SPDX-License-Identifier: MIT */
// cone_dilate.comp - a band of rows of ../cone_dilate.c's raster passes on the device:
// v(p) <- max_q v(q) - slope d(p, q) with the 8-connected chamfer distance, with the CPU's
// roundings (max is exact, each subtraction rounds once, in the CPU's order), so the map comes
// out bit for bit as the CPU's: the proximity map's cone heights near 2^20 round to 1/8 px,
// and a different order of roundings would move the background blend's weights by a few
// percent. The row's links to the row before it (in the pass's direction) are independent
// (all invocations); the run along the row is a chain (invocation 0), and rows follow each
// other. gl_layers.c dispatches one work group per band of rows, in pass order: a whole pass
// in one invocation would exceed llvmpipe's loop limit (65,535 iterations of all its loops
// together, after which it silently stops), so a band runs at most CONE_BAND_STEPS steps, and
// a row longer than that (a frame up to 65,536 pixels wide) runs alone, its run along the row
// cut into pieces of one dispatch each, the row's links in the first.
// 8 invocations: llvmpipe runs them as one 8-lane vector, so the two barriers a row are no
// coroutine switches; the run along a row is serial whatever the group's size.
layout(local_size_x = 8) in;

layout(std430, binding = 2) coherent buffer Map { float map[]; };

uniform uint u_base;      // index of the box's first value
uniform uint u_stride;    // floats between rows
uniform uint u_height;    // rows in the box
uniform uint u_first;     // the pass's first row of this dispatch (in pass order)
uniform uint u_count;     // rows of this dispatch
uniform uint u_backward;  // 0: the forward pass (top down, left to right), 1: the backward pass
uniform uint u_width;
uniform uint u_run_first; // the run's first step this dispatch takes (0: with the row's links)
uniform uint u_run_count; // and how many (u_width - 1: the whole row)
uniform float u_axial;    // slope
uniform float u_diagonal; // slope * sqrt 2, as the CPU rounds it

// The row's links to the row before it in the pass (cone_dilate.c's from_row).
void from_row(uint row, uint prev)
{
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
}

void sync()
{
    memoryBarrierBuffer();
    barrier();
}

void main()
{
    bool first = gl_LocalInvocationID.x == 0u;
    for (uint i = u_first; i < u_first + u_count; i++) {
        uint y = u_backward != 0u ? u_height - 1u - i : i;
        uint row = u_base + y * u_stride;
        if (i > 0u && u_run_first == 0u)
            from_row(row, u_backward != 0u ? row + u_stride : row - u_stride);
        sync();
        // Step s of the run sets pixel 1 + s (forward) or u_width - 2 - s (backward).
        if (first && u_backward == 0u)
            for (uint s = u_run_first; s < u_run_first + u_run_count; s++)
                map[row + 1u + s] = max(map[row + 1u + s], map[row + s] - u_axial);
        if (first && u_backward != 0u)
            for (uint s = u_run_first; s < u_run_first + u_run_count; s++) {
                uint x = u_width - 2u - s;
                map[row + x] = max(map[row + x], map[row + x + 1u] - u_axial);
            }
        sync();
    }
}
