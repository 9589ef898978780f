/* SPDX-License-Identifier: MIT */
// silhouettes.comp - the silhouettes' split on the device (../silhouettes.c), one program per
// step (the define names it), one invocation per pixel, in the CPU's arithmetic: its sums and
// shares in double, `precise` where the CPU rounds a product and a sum apart. STEP_CLEAN: the
// colour the layers diffuse, each blurred pixel of a pair holding the background alone;
// STEP_DELTA: what each pixel of a pair changes by in the result, and their count; STEP_APPLY:
// the changes added (colour channels only). The constants come from ddof_silhouette_rules.h.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; };
layout(std430, binding = 1) readonly buffer ColorIn { float color_in[]; }; // before the clean
#if defined(STEP_DELTA) || defined(STEP_APPLY)
layout(std430, binding = 2) buffer Out { float out_px[]; };
#endif
layout(std430, binding = 3) readonly buffer Matte { float matte[]; };
#ifdef STEP_CLEAN
layout(std430, binding = 4) buffer Cleaned { float cleaned[]; };
#endif
layout(std430, binding = 5) buffer Delta { float delta[]; };
layout(std430, binding = 6) buffer Counts { uint counts[]; }; // [0] cleaned, [1] split pixels

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_color_base;
uniform uint u_color_stride;
uniform float u_in_focus;
uniform uint u_ranks;        // the matte's (0: none, the shares from the colours)
uniform uint u_matte_base;
uniform uint u_matte_stride;

const int step_x[4] = int[4](-1, 1, 0, 0), step_y[4] = int[4](0, 0, -1, 1);

bool inside(int x, int y)
{
    return x >= 0 && y >= 0 && x < int(u_width) && y < int(u_height);
}

float coc_at(int x, int y)
{
    return coc_in[u_coc_base + uint(y) * u_coc_stride + uint(x) * u_coc_step];
}

bool is_sharp(float c)
{
    return abs(c) < u_in_focus || c == 0.0;
}

bool is_blurred_behind(float c)
{
    return c >= DDOF_SILHOUETTE_MIN_COC_PX;
}

float color_at(int x, int y, int c)
{
    return color_in[u_color_base + uint(y) * u_color_stride + uint(x) * u_channels + uint(c)];
}

// ---- the matte -------------------------------------------------------------------------------

uint matte_at(int x, int y)
{
    return u_matte_base + uint(y) * u_matte_stride + uint(x) * 2u * u_ranks;
}

float clamp_share(double sum)
{
    return float(sum < 0.0lf ? 0.0lf : sum > 1.0lf ? 1.0lf : sum);
}

float matte_coverage(int x, int y, uint id)
{
    uint pair = matte_at(x, y);
    double sum = 0.0lf;
    for (uint k = 0u; k < u_ranks; k++)
        if (floatBitsToUint(matte[pair + 2u * k]) == id)
            sum += double(matte[pair + 2u * k + 1u]);
    return clamp_share(sum);
}

float matte_coverage_sum(int x, int y)
{
    uint pair = matte_at(x, y);
    double sum = 0.0lf;
    for (uint k = 0u; k < u_ranks; k++)
        sum += double(matte[pair + 2u * k + 1u]);
    return clamp_share(sum);
}

float background_coverage(int x, int y, int bx, int by)
{
    uint pair = matte_at(bx, by);
    float world = 1.0 - matte_coverage_sum(bx, by);
    if (world > matte[pair + 1u])
        return 1.0 - matte_coverage_sum(x, y);
    return matte_coverage(x, y, floatBitsToUint(matte[pair]));
}

// ---- a pair ----------------------------------------------------------------------------------

// silhouettes.c's pair_colors: the pair (sharp p, blurred p + d)'s object and background
// colours and the object's share of pixel (xx, xy); false when the colours cannot tell.
bool pair_colors(int px, int py, int dir, int xx, int xy, out float object[3],
                 out float background[3], out float share, out float object_share)
{
    int dx = step_x[dir], dy = step_y[dir];
    int ox = px - dx, oy = py - dy;
    int bx = px + 2 * dx, by = py + 2 * dy;
    bool behind_inside = inside(ox, oy);
    bool thin = behind_inside && !is_sharp(coc_at(ox, oy));
    if (thin || !behind_inside) {
        ox = px;
        oy = py;
    }
    int bgx = px + dx, bgy = py + dy;
    if (inside(bx, by) && is_blurred_behind(coc_at(bx, by))) {
        bgx = bx;
        bgy = by;
    }
    for (int c = 0; c < 3; c++) {
        object[c] = color_at(ox, oy, c);
        background[c] = color_at(bgx, bgy, c);
    }
    object_share = 1.0;
    share = 0.0;
    if (u_ranks > 0u) {
        share = 1.0 - background_coverage(xx, xy, bgx, bgy);
        float at_p = 1.0 - background_coverage(px, py, bgx, bgy);
        if (at_p >= DDOF_MATTE_SOLVE_SHARE)
            for (int c = 0; c < 3; c++) {
                precise float solved = color_at(px, py, c) - (1.0 - at_p) * background[c];
                object[c] = solved / at_p;
            }
        return true;
    }
    double dot = 0.0lf, norm = 0.0lf, size = 0.0lf;
    for (int c = 0; c < 3; c++) {
        double o = double(object[c]), b = double(background[c]);
        precise double v = o - b;
        precise double dot_add = (double(color_at(xx, xy, c)) - b) * v;
        dot += dot_add;
        precise double norm_add = v * v;
        norm += norm_add;
        precise double size_add = o * o + b * b;
        size += size_add;
    }
    if (!(norm > 1e-4lf * size) || !(norm > 1e-20lf))
        return false;
    double a = dot / norm;
    if (thin) {
        object_share = DDOF_THIN_OBJECT_SHARE;
        a = xx == px && xy == py
                ? double(DDOF_THIN_OBJECT_SHARE)
                : (a < double(DDOF_THIN_NEIGHBOUR_SHARE) ? a : double(DDOF_THIN_NEIGHBOUR_SHARE));
    }
    share = float(a < 0.0lf ? 0.0lf : a > 1.0lf ? 1.0lf : a);
    return true;
}

// silhouettes.c's blurred_shares: the mean over a blurred pixel's pairs of a, a O, a B, of
// a (1 - O's object share) and of that times B. Returns the pairs.
int blurred_shares(int x, int y, out double a_mean, out double object[3],
                   out double background[3], out double mixed, out double mixed_background[3])
{
    a_mean = 0.0lf;
    mixed = 0.0lf;
    for (int c = 0; c < 3; c++) {
        object[c] = 0.0lf;
        background[c] = 0.0lf;
        mixed_background[c] = 0.0lf;
    }
    int pairs = 0;
    for (int dir = 0; dir < 4; dir++) {
        int px = x - step_x[dir], py = y - step_y[dir];
        float o_colour[3], b_colour[3], a, o;
        if (!inside(px, py) || !is_sharp(coc_at(px, py)) ||
            !pair_colors(px, py, dir, x, y, o_colour, b_colour, a, o))
            continue;
        a_mean += double(a);
        precise double mixed_add = double(a) * (1.0lf - double(o));
        mixed += mixed_add;
        for (int c = 0; c < 3; c++) {
            precise double object_add = double(a) * double(o_colour[c]);
            object[c] += object_add;
            precise double background_add = double(a) * double(b_colour[c]);
            background[c] += background_add;
            precise double mixed_background_add =
                double(a) * (1.0lf - double(o)) * double(b_colour[c]);
            mixed_background[c] += mixed_background_add;
        }
        pairs++;
    }
    if (pairs > 0) {
        a_mean /= double(pairs);
        mixed /= double(pairs);
        for (int c = 0; c < 3; c++) {
            object[c] /= double(pairs);
            background[c] /= double(pairs);
            mixed_background[c] /= double(pairs);
        }
    }
    return pairs;
}

#ifdef STEP_CLEAN
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    int x = int(i % u_width), y = int(i / u_width);
    for (uint c = 0u; c < u_channels; c++)
        cleaned[i * u_channels + c] = color_at(x, y, int(c));
    if (!is_blurred_behind(coc_at(x, y)))
        return;
    double a, object[3], background[3], mixed, mixed_background[3];
    if (blurred_shares(x, y, a, object, background, mixed, mixed_background) == 0)
        return;
    for (int c = 0; c < 3; c++)
        cleaned[i * u_channels + uint(c)] += float(background[c] - object[c]);
    atomicAdd(counts[0], 1u);
}
#endif

#ifdef STEP_DELTA
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    int x = int(i % u_width), y = int(i / u_width);
    float c = coc_at(x, y);
    float d[3] = float[3](0.0, 0.0, 0.0);
    int pairs = 0;
    if (is_blurred_behind(c)) {
        // silhouettes.c's blurred_side
        double a, object[3], background[3], mixed, mixed_background[3];
        pairs = blurred_shares(x, y, a, object, background, mixed, mixed_background);
        for (int k = 0; k < 3 && pairs > 0; k++) {
            precise double v = object[k] + (mixed - a) * double(out_px[i * u_channels + uint(k)]) -
                               mixed_background[k];
            d[k] = float(v);
        }
    } else if (is_sharp(c)) {
        // silhouettes.c's sharp_side
        double sum[3] = double[3](0.0lf, 0.0lf, 0.0lf);
        for (int dir = 0; dir < 4; dir++) {
            int qx = x + step_x[dir], qy = y + step_y[dir];
            float o_colour[3], b_colour[3], a, o;
            if (!inside(qx, qy) || !is_blurred_behind(coc_at(qx, qy)) ||
                !pair_colors(x, y, dir, x, y, o_colour, b_colour, a, o))
                continue;
            uint q = (uint(qy) * u_width + uint(qx)) * u_channels;
            for (int k = 0; k < 3; k++) {
                precise double add =
                    (1.0lf - double(a)) * (double(out_px[q + uint(k)]) - double(b_colour[k]));
                sum[k] += add;
            }
            pairs++;
        }
        for (int k = 0; k < 3 && pairs > 0; k++)
            d[k] = float(sum[k] / double(pairs));
    }
    for (int k = 0; k < 3; k++)
        delta[i * 3u + uint(k)] = d[k];
    if (pairs > 0)
        atomicAdd(counts[1], 1u);
}
#endif

#ifdef STEP_APPLY
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height || counts[1] == 0u)
        return;
    for (uint k = 0u; k < 3u; k++)
        out_px[i * u_channels + k] += delta[i * 3u + k];
}
#endif
