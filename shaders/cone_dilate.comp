/* SPDX-License-Identifier: MIT */
// cone_dilate.comp - libddof/src/cone_dilate.c on the device: v(p) <- max_q v(q) - slope d(p, q)
// with the 8-connected chamfer distance, in the same two raster passes with the same roundings
// (max is exact, each subtraction rounds once, in the CPU's order), so the map comes out bit
// for bit as the CPU's: the proximity map's cone heights near 2^20 round to 1/8 px, and a
// different order of roundings would move the background blend's weights by a few percent.
// One work group: a row's links to the row before are independent (all invocations), the run
// along the row is a chain (invocation 0), and rows follow each other.
layout(local_size_x = 256) in;

layout(std430, binding = 2) buffer Map { float map[]; };

uniform uint u_base;   // index of the box's first value
uniform uint u_width;  // of the box
uniform uint u_height;
uniform uint u_stride; // floats between rows
uniform float u_axial;    // slope
uniform float u_diagonal; // slope * sqrt 2, as the CPU rounds it

// One row from the row before it (dir = -1 forward, +1 backward), cone_dilate.c's from_row.
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
    for (uint y = 0u; y < u_height; y++) {
        uint row = u_base + y * u_stride;
        if (y > 0u)
            from_row(row, row - u_stride);
        sync();
        if (first)
            for (uint x = 1u; x < u_width; x++)
                map[row + x] = max(map[row + x], map[row + x - 1u] - u_axial);
        sync();
    }
    for (uint y = u_height; y-- > 0u;) {
        uint row = u_base + y * u_stride;
        if (y + 1u < u_height)
            from_row(row, row + u_stride);
        sync();
        if (first)
            for (uint x = u_width - 1u; x-- > 0u;)
                map[row + x] = max(map[row + x], map[row + x + 1u] - u_axial);
        sync();
    }
}
