/* SPDX-License-Identifier: MIT */
// jacobi_init.comp - the Jacobi sweeps' first guess, one invocation per line: y = x, except in
// holes (gamma = 0), which take the nearest value along the line that holds heat (the last one
// before, or the first one for leading holes), as libddof/src/solver_jacobi.c does: starting
// from 0 an unconverged Jacobi would pull its neighbours out of the input's range.
layout(local_size_x = 64) in;

layout(std430, binding = 6) buffer Guess { vec4 guess[]; };

void main()
{
    uint line = global_id();
    if (line >= u_lines)
        return;
    int first = -1;
    if (u_has_gamma != 0u)
        for (uint i = 0u; i < u_n && first < 0; i++)
            if (heat[pixel(line, i)] > 0.0)
                first = int(i);
    vec4 last = first >= 0 ? src[pixel(line, uint(first))] : vec4(0.0);
    for (uint i = 0u; i < u_n; i++) {
        uint p = pixel(line, i);
        vec4 v = src[p];
        if (u_has_gamma != 0u && first >= 0) {
            if (heat[p] > 0.0)
                last = v;
            else
                v = last;
        }
        guess[p] = v;
    }
}
