/* SPDX-License-Identifier: MIT */
// jacobi_sweep.comp - one Jacobi sweep over every pixel of the pass (DDOF_SOLVER_JACOBI):
//   y_i <- x_i + wlo (y_{i-1} - x_i) + whi (y_{i+1} - x_i),  w = link / (gamma + A + C)
// reading only the previous sweep (double-buffered), as solver_jacobi.c. The last sweep
// writes the pass's output, where singular runs keep their values.
layout(local_size_x = 256) in;

layout(std430, binding = 6) buffer Current { vec4 current[]; };
layout(std430, binding = 7) buffer Next { vec4 next_values[]; };

uniform uint u_last;

void main()
{
    uint p = global_id();
    if (p >= u_n * u_lines)
        return;
    uint i = (p / u_along) % u_n, line = (p / u_across) % u_lines;
    float left = link_beta(line, int(i) - 1), right = link_beta(line, int(i));
    float b = heat_at(p) + left + right;
    vec4 s = src[p];
    vec4 ylo = i > 0u ? current[pixel(line, i - 1u)] : vec4(0.0);
    vec4 yhi = i + 1u < u_n ? current[pixel(line, i + 1u)] : vec4(0.0);
    vec4 y = s + share(left, b) * (ylo - s) + share(right, b) * (yhi - s);
    if (u_last != 0u && u_flag_bit != 0u && (flags[p] & u_flag_bit) != 0u)
        y = s;
    next_values[p] = y;
}
