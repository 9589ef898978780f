/* SPDX-License-Identifier: MIT */
// line.glsl - the tridiagonal rows of one ADI pass, shared by every solver kernel.
//
// A pass solves `u_lines` independent lines of `u_n` unknowns each; unknown i of line l is the
// pixel l * u_across + i * u_along of the row-major working image (rows: along 1, across the
// width; columns: along the width, across 1). Per line, as in libddof/src/solvers/solver.h:
//
//     (E + A + C) y_i - A y_{i-1} - C y_{i+1} = E u_i,   A = beta_{i-1}, C = beta_i, E = gamma_i
//
// kept in the *excess* form of reduction_rows.h: the diagonal is never formed by subtraction,
// elimination only adds non-negative terms, and every value is written as a step from u. That
// is what keeps beta ~ 1e8 (CoC 10,000 px) exact enough in float.

layout(std430, binding = 0) buffer CocBuffer { float coc[]; };     // |CoC| in px per pixel
layout(std430, binding = 1) buffer HeatBuffer { float heat[]; };   // gamma per pixel
layout(std430, binding = 2) buffer FlagBuffer { uint flags[]; };   // singular-run marks
layout(std430, binding = 3) buffer SrcBuffer { vec4 src[]; };      // the pass's input
layout(std430, binding = 4) buffer DstBuffer { vec4 dst[]; };      // the pass's output

uniform uint u_n;          // unknowns per line
uniform uint u_lines;      // lines in the pass
uniform uint u_line0;      // first line of this dispatch (pyramid solvers work in batches)
uniform uint u_batch_lines;// lines of this dispatch
uniform uint u_along;      // pixel step between unknowns
uniform uint u_across;     // pixel step between lines
uniform float u_scale;     // k / substeps (times aspect^2 for columns)
uniform uint u_has_gamma;  // 0: gamma is 1 everywhere
uniform uint u_flag_bit;   // 1 rows, 2 columns, 0 no singular runs to keep
uniform uint u_write_mask; // channels a kernel writes (packed Gruen solves in channel groups)

uint pixel(uint line, uint i)
{
    return line * u_across + i * u_along;
}

// The link between two pixels: k * min(|d_a|, |d_b|)^2, flushed to 0 below FLT_MIN
// (ddof_link_beta). The disc kernel's programs define LENS_MIN_LINK and get its real link
// instead: min^2 times the axis' scale, 0 below that floor (lens_adi.c, lens_link), with the
// CPU's order of operations. `precise` keeps the products from being reassociated.
float conductance(float coc_a, float coc_b)
{
    float m = min(coc_a, coc_b);
#ifdef LENS_MIN_LINK
    precise float b = (m * m) * u_scale;
    return b >= LENS_MIN_LINK ? b : 0.0;
#else
    precise float b = (u_scale * m) * m;
    return b >= FLT_MIN ? b : 0.0;
#endif
}

// Link i -> i+1; 0 past either end (insulated borders).
float link_beta(uint line, int i)
{
    if (i < 0 || uint(i) + 1u >= u_n)
        return 0.0;
    return conductance(coc[pixel(line, uint(i))], coc[pixel(line, uint(i) + 1u)]);
}

float heat_at(uint p)
{
    return u_has_gamma != 0u ? heat[p] : 1.0;
}

struct Row {
    float a; // link to the lower neighbour at the current distance
    float c; // link to the upper neighbour
    float e; // excess: the row sum, >= 0 (gamma at level 0)
    vec4 u;  // source value: the right-hand side is e * u
};

Row zero_row()
{
    Row r;
    r.a = 0.0;
    r.c = 0.0;
    r.e = 0.0;
    r.u = vec4(0.0);
    return r;
}

// Level-0 row i, computed on the fly from the CoC (no coefficient storage); a row that does
// not exist has no links, no excess and value 0, so every weight on it is 0.
Row row0(uint line, int i)
{
    if (i < 0 || uint(i) >= u_n)
        return zero_row();
    uint p = pixel(line, uint(i));
    Row r;
    r.a = link_beta(line, i - 1);
    r.c = link_beta(line, i);
    r.e = heat_at(p);
    r.u = src[p];
    return r;
}

// row + alpha lo + g hi, with alpha and g cancelling row's links to lo and hi
// (reduction_rows.h, eliminate): all weights are shares in [0, 1].
Row eliminate(Row r, Row lo, Row hi)
{
    float alpha = share(r.a, lo.e + lo.a + lo.c);
    float g = share(r.c, hi.e + hi.a + hi.c);
    float elo = alpha * lo.e, ehi = g * hi.e;
    Row o;
    o.e = r.e + elo + ehi;
    o.a = alpha * lo.a;
    o.c = g * hi.c;
    float wlo = share(elo, o.e), whi = share(ehi, o.e);
    o.u = r.u + wlo * (lo.u - r.u) + whi * (hi.u - r.u);
    return o;
}

// The row's unknown, given its neighbours' solutions (solver_cr.c, substitute).
vec4 substitute(Row r, vec4 ylo, vec4 yhi)
{
    float b = r.e + r.a + r.c;
    return r.u + share(r.a, b) * (ylo - r.u) + share(r.c, b) * (yhi - r.u);
}

// Writes a solution into the image. A run of pixels whose gamma are all 0 is singular (nothing
// holds heat): it keeps the value it had before the pass, as libddof/src/adi/heat_adi.c does.
void store_result(uint p, vec4 y)
{
    if (u_flag_bit != 0u && (flags[p] & u_flag_bit) != 0u)
        y = src[p];
    if (u_write_mask == 15u) {
        dst[p] = y;
    } else {
        if ((u_write_mask & 1u) != 0u) dst[p].x = y.x;
        if ((u_write_mask & 2u) != 0u) dst[p].y = y.y;
        if ((u_write_mask & 4u) != 0u) dst[p].z = y.z;
        if ((u_write_mask & 8u) != 0u) dst[p].w = y.w;
    }
}
