/* SPDX-License-Identifier: MIT */
// gruen_cramer.comp - the top of Gruen's reduction: a closed system of 1, 2 or 3 unknowns
// solved by Cramer's rule. The determinant and cofactors are expanded into sums of products
// of non-negative terms (for this M-matrix in excess form every one of them is), so each
// solution is a weighted mean of the source values with positive weights, however large the
// links: y_k = sum_i W_ki u_i / sum_i W_ki with W_ki = cofactor_ki * e_i. One invocation per line.
layout(local_size_x = 64) in;

vec4 mean3(vec4 u0, float w0, vec4 u1, float w1, vec4 u2, float w2, vec4 uk)
{
    float t = w0 + w1 + w2;
    return uk + share(w0, t) * (u0 - uk) + share(w1, t) * (u1 - uk) + share(w2, t) * (u2 - uk);
}

void main()
{
    uint ll = global_id();
    if (ll >= u_batch_lines)
        return;
    uint m = u_level0 != 0u ? u_n : u_src_count;
    Row r0 = level_row(ll, 0), r1 = level_row(ll, 1), r2 = level_row(ll, 2);
    if (m == 1u) {
        store_solution(ll, 0u, r0.u);
    } else if (m == 2u) {
        // [[e0 + c0, -c0], [-a1, e1 + a1]]: det = e0 e1 + e0 a1 + c0 e1
        float e0 = r0.e, e1 = r1.e, c0 = r0.c, a1 = r1.a;
        store_solution(ll, 0u, mean3(r0.u, (e1 + a1) * e0, r1.u, c0 * e1, r0.u, 0.0, r0.u));
        store_solution(ll, 1u, mean3(r0.u, a1 * e0, r1.u, (e0 + c0) * e1, r1.u, 0.0, r1.u));
    } else {
        // [[e0 + c0, -c0, 0], [-a1, e1 + a1 + c1, -c1], [0, -a2, e2 + a2]]
        float e0 = r0.e, e1 = r1.e, e2 = r2.e;
        float c0 = r0.c, a1 = r1.a, c1 = r1.c, a2 = r2.a;
        float b0 = e0 + c0, b2 = e2 + a2;
        float adj00 = e1 * e2 + e1 * a2 + a1 * e2 + a1 * a2 + c1 * e2; // b1 b2 - c1 a2
        float adj22 = e0 * e1 + e0 * a1 + e0 * c1 + c0 * e1 + c0 * c1; // b0 b1 - c0 a1
        store_solution(ll, 0u, mean3(r0.u, adj00 * e0, r1.u, c0 * b2 * e1, r2.u, c0 * c1 * e2, r0.u));
        store_solution(ll, 1u, mean3(r0.u, a1 * b2 * e0, r1.u, b0 * b2 * e1, r2.u, b0 * c1 * e2, r1.u));
        store_solution(ll, 2u, mean3(r0.u, a1 * a2 * e0, r1.u, b0 * a2 * e1, r2.u, adj22 * e2, r2.u));
    }
}
