/* SPDX-License-Identifier: MIT */
// thomas.comp - Thomas elimination, one invocation per line (DDOF_SOLVER_THOMAS).
//
// The weighted-mean form of libddof/src/solvers/solver_thomas.c: the eliminated row's excess q only
// ever grows by non-negative terms, each step is a lerp with one weight in [0, 1], so outputs
// are convex combinations of inputs even at beta ~ 1e8. The running value is carried in double
// (GL 4.0+ core has fp64): as on the CPU, rounding a moving average with a memory longer than
// the line to float at every step compounds (1.8e-5 against 6.6e-7 on 4096-pixel lines).
//
// Neighbouring invocations are neighbouring lines, so the back-substitution weights are laid
// out [i][line]: their accesses are coalesced in both passes; the image itself is coalesced in
// the column pass (neighbouring columns) and strided in the row pass.
layout(local_size_x = 64) in;

layout(std430, binding = 6) buffer Weights { float weights[]; }; // [i][line]

dvec4 lerp(vec4 a, dvec4 b, float k)
{
    dvec4 da = dvec4(a);
    return da + double(k) * (b - da);
}

void main()
{
    uint line = global_id();
    if (line >= u_lines)
        return;
    float q = 0.0; // nothing comes in from the left of element 0
    uint p0 = pixel(line, 0u);
    dvec4 run = dvec4(src[p0]); // D_0 = x_0
    float here = coc[p0];
    for (uint i = 0u; i < u_n; i++) {
        uint p = pixel(line, i);
        float b = 0.0;
        if (i + 1u < u_n) {
            float next = coc[pixel(line, i + 1u)];
            float m = min(here, next);
            precise float beta = (u_scale * m) * m;
            b = beta >= FLT_MIN ? beta : 0.0;
            here = next;
        }
        float e = heat_at(p) + q;
        float s = q / max(e, FLT_MIN);
        float w = b / max(b + e, FLT_MIN);
        weights[i * u_lines + line] = w;
        q = e * w;
        if (i > 0u)
            run = lerp(src[p], run, s);
        dst[p] = vec4(run);
    }
    // run holds D_{n-1} = y_{n-1} unrounded; walk back.
    store_result(pixel(line, u_n - 1u), vec4(run));
    for (int i = int(u_n) - 2; i >= 0; i--) {
        uint p = pixel(line, uint(i));
        run = lerp(dst[p], run, weights[uint(i) * u_lines + line]);
        store_result(p, vec4(run));
    }
}
