/* SPDX-License-Identifier: MIT */
// jacobi_init.comp - the Jacobi sweeps' first guess: y = x, except in holes (gamma = 0), which
// take the nearest value along the line that holds heat (the last one before, or the first one
// for leading holes), as libddof/src/solvers/solver_jacobi.c does: starting from 0 an unconverged
// Jacobi would pull its neighbours out of the input's range.
//
// One invocation per segment of SEGMENT pixels of a line, never per whole line: a software
// renderer ends an invocation's loops after 65,535 iterations in all (backend_table.c), which
// a line of 65,536 pixels and its search for the first heat exceed. Stage 0 (with gamma only)
// records each segment's first and last pixel that holds heat; stage 1 finds, from those
// records, the last one before its segment (else the line's first) and writes the segment.
layout(local_size_x = 64) in;

#define SEGMENT 1024u
#define NONE 0xffffffffu

layout(std430, binding = 6) buffer Guess { vec4 guess[]; };
layout(std430, binding = 7) buffer Marks { uint marks[]; }; // (first, last) per line and segment

uniform uint u_stage; // 0: mark the segments, 1: write the guess

void main()
{
    uint segments = (u_n + SEGMENT - 1u) / SEGMENT;
    uint id = global_id();
    if (id >= u_lines * segments)
        return;
    uint line = id / segments, segment = id % segments;
    uint i0 = segment * SEGMENT, i1 = min(i0 + SEGMENT, u_n);
    if (u_stage == 0u) {
        uint first = NONE, last = NONE;
        for (uint i = i0; i < i1; i++)
            if (heat[pixel(line, i)] > 0.0) {
                first = first == NONE ? i : first;
                last = i;
            }
        marks[2u * id] = first;
        marks[2u * id + 1u] = last;
        return;
    }
    uint from = NONE;
    if (u_has_gamma != 0u) {
        uint base = 2u * line * segments;
        for (uint s = segment; s > 0u && from == NONE; s--)
            from = marks[base + 2u * (s - 1u) + 1u];
        for (uint s = 0u; s < segments && from == NONE; s++)
            from = marks[base + 2u * s];
    }
    vec4 last = from != NONE ? src[pixel(line, from)] : vec4(0.0);
    for (uint i = i0; i < i1; i++) {
        uint p = pixel(line, i);
        vec4 v = src[p];
        if (from != NONE) {
            if (heat[p] > 0.0)
                last = v;
            else
                v = last;
        }
        guess[p] = v;
    }
}
