/* SPDX-License-Identifier: MIT */
// lens_thomas.comp - one component of the disc kernel along one direction, one invocation per
// line: the component's chain of u_steps complex implicit steps (libddof/src/adi/lens_adi.c), each
// the weighted-mean Thomas elimination of libddof/src/solvers/lens_solver.c with
// beta = kappa_m * b:
//
//     e_i = gamma_i + q_{i-1}, s_i = q_{i-1} / e_i, w_i = beta_i / (beta_i + e_i), q_i = e_i w_i
//     D_i = x_i + s_i (D_{i-1} - x_i),  y_i = D_i + w_i (y_{i+1} - D_i)
//
// in float, as on the CPU (|s|, |w| <= 1: every step is a complex lerp). The chain works in place
// on the complex image T (dst, dst_im): D over x in the forward sweep, y over D in the back one.
// Rows (u_real_input) start from the masked colour in src and leave T_c; columns run on T_c and,
// instead of writing their last step back, fold it into the output as a change,
// out = x + sum_c Re(mix_c (Z_c - x)), so that a pixel without links (Z_c = x exactly) comes out
// bit for bit, clamped to the input's range (u_lo, u_hi) as on the CPU. A singular run (linked pixels that all have gamma 0) keeps its input through the
// chain: nothing outside it depends on it (its end links are 0, so s = 0 behind it and w = 0
// before it), so its pixels are simply never written.
layout(local_size_x = 64) in;

layout(std430, binding = 5) buffer ImagBuffer { vec4 dst_im[]; }; // T, imaginary part
layout(std430, binding = 6) buffer Weights { vec2 weights[]; };   // w of each step, [i][line]
layout(std430, binding = 7) buffer Running { vec4 running[]; };   // x + the changes so far

uniform uint u_steps;
uniform float u_kappa_re[3];
uniform float u_kappa_im[3];
uniform float u_mix_re;
uniform float u_mix_im;
uniform uint u_real_input; // rows: the chain starts from src (real)
uniform uint u_fold;       // 0 rows; columns: 1 first, 2 middle, 3 last, 4 only component
uniform float u_lo[4];     // the input's range per channel: the output is clamped to it
uniform float u_hi[4];

vec2 cmul(vec2 a, vec2 b)
{
    return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// num / den as num conj(den) / |den|^2. den is 0 only with num (the sector argument of
// lens_solver.h); clamping |den|^2 makes that 0 without a branch.
vec2 cdiv(vec2 num, vec2 den)
{
    float d2 = max(den.x * den.x + den.y * den.y, FLT_MIN);
    return vec2((num.x * den.x + num.y * den.y) / d2, (num.y * den.x - num.x * den.y) / d2);
}

bool singular(uint p)
{
    return u_flag_bit != 0u && (flags[p] & u_flag_bit) != 0u;
}

// The last step's result at p (columns): folded into the output.
void fold(uint p, vec4 zr, vec4 zi)
{
    vec4 x = src[p];
    vec4 change = u_mix_re * (zr - x) - u_mix_im * zi;
    if (u_fold == 1u)
        running[p] = x + change;
    else if (u_fold == 2u)
        running[p] = running[p] + change;
    else if (u_fold == 3u) // x is read here only, by this invocation
        src[p] = clamp(running[p] + change, vec4(u_lo[0], u_lo[1], u_lo[2], u_lo[3]),
                       vec4(u_hi[0], u_hi[1], u_hi[2], u_hi[3]));
    else
        src[p] = clamp(x + change, vec4(u_lo[0], u_lo[1], u_lo[2], u_lo[3]),
                       vec4(u_hi[0], u_hi[1], u_hi[2], u_hi[3]));
}

void main()
{
    uint line = global_id();
    if (line >= u_lines)
        return;
    for (uint m = 0u; m < u_steps; m++) {
        vec2 kappa = vec2(u_kappa_re[m], u_kappa_im[m]);
        bool from_src = m == 0u && u_real_input != 0u;
        bool last = m + 1u == u_steps && u_fold != 0u;
        vec2 q = vec2(0.0); // nothing comes in from the left of element 0
        vec4 dr = vec4(0.0), di = vec4(0.0);
        float here = coc[pixel(line, 0u)];
        for (uint i = 0u; i < u_n; i++) {
            uint p = pixel(line, i);
            float b = 0.0;
            if (i + 1u < u_n) {
                float next = coc[pixel(line, i + 1u)];
                b = conductance(here, next);
                here = next;
            }
            vec2 e = vec2(heat_at(p) + q.x, q.y);
            vec2 s = cdiv(q, e);
            vec2 beta = kappa * b;
            vec2 w = cdiv(beta, beta + e);
            weights[i * u_lines + line] = w;
            q = cmul(e, w);
            vec4 xr = from_src ? src[p] : dst[p];
            vec4 xi = from_src ? vec4(0.0) : dst_im[p];
            if (i == 0u) {
                dr = xr;
                di = xi;
            } else {
                vec4 hr = dr - xr, hi = di - xi;
                dr = xr + s.x * hr - s.y * hi;
                di = xi + s.x * hi + s.y * hr;
            }
            if (!singular(p)) {
                dst[p] = dr;
                dst_im[p] = di;
            } else if (from_src) { // T starts as the input
                dst[p] = xr;
                dst_im[p] = xi;
            }
        }
        // dr, di hold D_{n-1} = y_{n-1}; walk back.
        vec4 yr = dr, yi = di;
        for (int i = int(u_n) - 1; i >= 0; i--) {
            uint p = pixel(line, uint(i));
            if (i + 1 < int(u_n)) {
                vec2 w = weights[uint(i) * u_lines + line];
                vec4 vr = dst[p], vi = dst_im[p];
                vec4 hr = yr - vr, hi = yi - vi;
                yr = vr + (w.x * hr - w.y * hi);
                yi = vi + (w.x * hi + w.y * hr);
            }
            bool keep = singular(p);
            if (last)
                fold(p, keep ? dst[p] : yr, keep ? dst_im[p] : yi);
            else if (!keep) {
                dst[p] = yr;
                dst_im[p] = yi;
            }
        }
    }
}
