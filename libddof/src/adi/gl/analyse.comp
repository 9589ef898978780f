/* SPDX-License-Identifier: MIT */
// analyse.comp - one invocation per line, once per direction and call (the CoC and gamma are
// the same for every substep): counts lines with a conductive link (the CPU path's
// lines_solved), and with heat capacities marks the singular runs (links joining pixels whose
// gamma are all 0), which keep their values (store_result). The largest CoC is the packing's.
layout(local_size_x = 64) in;

layout(std430, binding = 6) buffer Counters { uint counters[]; }; // active rows, columns

uniform uint u_counter; // 0 rows, 1 columns

void main()
{
    uint line = global_id();
    if (line >= u_lines)
        return;
    bool conducts = false, holds_heat = false;
    uint start = 0u;
    for (uint i = 0u; i < u_n; i++) {
        uint p = pixel(line, i);
        float b = link_beta(line, int(i));
        conducts = conducts || b > 0.0;
        if (u_has_gamma == 0u)
            continue;
        holds_heat = holds_heat || heat[p] > 0.0;
        if (i + 1u < u_n && b > 0.0)
            continue;
        // i ends a run [start, i]: mark it (rows write the flag word, columns add their bit).
        for (uint k = start; k <= i; k++) {
            uint q = pixel(line, k);
            uint bit = holds_heat ? 0u : u_flag_bit;
            flags[q] = u_flag_bit == 1u ? bit : (flags[q] | bit);
        }
        start = i + 1u;
        holds_heat = false;
    }
    if (conducts)
        atomicAdd(counters[u_counter], 1u);
}
