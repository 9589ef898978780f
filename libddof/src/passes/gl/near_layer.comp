/* SPDX-License-Identifier: MIT */
// near_layer.comp - the near layer's split on the device (../near_layer.c), one program per
// step (the define names it), in the CPU's arithmetic (`precise` where the CPU rounds a
// product and a sum apart; the fringe's share in double, as there):
//  STEP_MATTE: per pixel, its matte, its weight as a source of the fill, the element's CoC, and
//    a fringe pixel split (its element and rest written);
//  STEP_PULL, STEP_PUSH: the pull-push pyramid, one level per dispatch;
//  STEP_LINES: one invocation per line (a row, a column or a diagonal: u_direction), the fill
//    across each run of non-source pixels;
//  STEP_SETTLE: a hole's line fill divided by its weight, pull-push where no line reached;
//  STEP_FINISH: the element and the rest's kept pixels, the split's figures (atomics);
//  STEP_ANALYSE: the rest's boxes, by the planner's rule (planner.c, analyse_rows).
// The constants come from ddof_near_rules.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; };
layout(std430, binding = 1) readonly buffer ColorIn { float color_in[]; };
// The split's maps, planes of width x height: the line fill's weights, the carried alpha, the
// source weights, the matte, the fringe's marks.
layout(std430, binding = 2) buffer Maps { float maps[]; };
layout(std430, binding = 3) buffer Rest { float rest[]; };       // width x channels a row
layout(std430, binding = 4) buffer RestCoc { float rest_coc[]; };
layout(std430, binding = 5) buffer Element { float element[]; }; // premultiplied RGBA
layout(std430, binding = 6) buffer ElementCoc { float element_coc[]; }; // its |CoC|
#if defined(STEP_FINISH) || defined(STEP_ANALYSE)
// [0..3] the element's box, [4] its largest |CoC| (bits), [5] its pixels, [6] the holes, [7] 1
// where it carries alpha, [8..11] the rest's background box, [12..15] the rest's near box.
layout(std430, binding = 7) buffer Facts { uint facts[]; };
#else
// Levels 1.. of the pyramid: each its values (u_values a pixel), then its weights.
layout(std430, binding = 7) buffer Pyramid { float pyramid[]; };
#endif

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_color_base;
uniform uint u_color_stride;
uniform float u_threshold;
uniform uint u_filled;        // STEP_FINISH: the holes were filled (a source exists)
// The pyramid: values per pixel, and the levels a pull or push reads and writes (level 0 is
// the frame; offsets in floats into the pyramid).
uniform uint u_values;
uniform uint u_from;
uniform uint u_fine_w, u_fine_h, u_fine_values, u_fine_weight;
uniform uint u_coarse_w, u_coarse_h, u_coarse_values, u_coarse_weight;
uniform uint u_direction;     // STEP_LINES: 0 rows, 1 columns, 2 diagonals down-right, 3 down-left
uniform float u_bg_threshold; // STEP_ANALYSE: the background edges' rule
uniform float u_bg_insulator;

const uint LINE_WEIGHT = 0u, CARRIED = 1u, SOURCE = 2u, MATTE = 3u, FRINGE = 4u;
const int MAX_VALUES = 5;

uint pixels()
{
    return u_width * u_height;
}

float map_at(uint plane, uint i)
{
    return maps[plane * pixels() + i];
}

void set_map(uint plane, uint i, float v)
{
    maps[plane * pixels() + i] = v;
}

float coc_at(uint x, uint y)
{
    return coc_in[u_coc_base + y * u_coc_stride + x * u_coc_step];
}

float color_at(uint x, uint y, uint k)
{
    return color_in[u_color_base + y * u_color_stride + x * u_channels + k];
}

float near_matte(float c)
{
    precise float t0 = 0.5 * u_threshold;
    precise float m = (-c - t0) / (u_threshold - t0);
    return m <= 0.0 ? 0.0 : m >= 1.0 ? 1.0 : m;
}

#ifdef STEP_MATTE
// near_layer.c's split_fringe: pixel (x, y) beside the element, split when its near neighbour
// is much brighter than what lies beyond.
bool split_fringe(uint x, uint y, uint i)
{
    float near = 0.0;
    uint fx = 0u, fy = 0u;
    for (uint ny = y > 0u ? y - 1u : 0u; ny <= y + 1u && ny < u_height; ny++)
        for (uint nx = x > 0u ? x - 1u : 0u; nx <= x + 1u && nx < u_width; nx++) {
            const float nc = coc_at(nx, ny);
            if (near_matte(nc) >= 1.0 && -nc > near) {
                near = -nc;
                fx = nx;
                fy = ny;
            }
        }
    if (near <= 0.0)
        return false;
    const int bx = 2 * int(x) - int(fx), by = 2 * int(y) - int(fy);
    const bool beyond = bx >= 0 && by >= 0 && bx < int(u_width) && by < int(u_height);
    const uint sx = beyond ? uint(bx) : x, sy = beyond ? uint(by) : y;
    vec3 c, f, b;
    for (uint k = 0u; k < 3u; k++) {
        c[k] = color_at(x, y, k);
        f[k] = color_at(fx, fy, k);
        b[k] = color_at(sx, sy, k);
    }
    const float fmax = f.r > max(f.g, f.b) ? f.r : max(f.g, f.b);
    const float bmax = b.r > max(b.g, b.b) ? b.r : max(b.g, b.b);
    if (!(fmax > DDOF_NEAR_FRINGE_CONTRAST * bmax))
        return false;
    precise double num = 0.0lf, den = 0.0lf;
    for (uint k = 0u; k < 3u; k++) {
        num += (double(c[k]) - double(b[k])) * (double(f[k]) - double(b[k]));
        den += (double(f[k]) - double(b[k])) * (double(f[k]) - double(b[k]));
    }
    float a = 0.0;
    if (den > 1e-12lf) {
        const float share = float(num / den);
        a = DDOF_NEAR_FRINGE_MAX_SHARE < (0.0 > share ? 0.0 : share)
                ? DDOF_NEAR_FRINGE_MAX_SHARE
                : (0.0 > share ? 0.0 : share);
    }
    for (uint k = 0u; k < 3u; k++) // a F <= C in every channel: the rest stays >= 0
        if (f[k] > 0.0 && a * f[k] > c[k])
            a = 0.0 > c[k] / f[k] ? 0.0 : c[k] / f[k];
    for (uint k = 0u; k < u_channels; k++) {
        precise float e = k < 3u ? a * f[k] : 0.0;
        const float in_k = color_at(x, y, k);
        precise float r = (in_k - e) / (1.0 - a);
        rest[i * u_channels + k] = k < 3u ? (0.0 > r ? 0.0 : r) : in_k;
        if (k < 3u)
            element[i * 4u + k] = e;
    }
    element[i * 4u + 3u] = a;
    rest_coc[i] = coc_at(x, y);
    set_map(MATTE, i, a);
    element_coc[i] = near;
    set_map(FRINGE, i, 1.0);
    return true;
}

void main()
{
    const uint i = global_id();
    if (i >= pixels())
        return;
    const uint x = i % u_width, y = i / u_width;
    const float c = coc_at(x, y);
    const float m = near_matte(c);
    set_map(FRINGE, i, 0.0);
    if (m <= 0.0 && split_fringe(x, y, i)) {
        set_map(SOURCE, i, 1.0 - map_at(MATTE, i));
        return;
    }
    set_map(MATTE, i, m);
    element_coc[i] = abs(c);
    precise float near_source = 1.0 + c / u_threshold;
    set_map(SOURCE, i, m > 0.0 ? 0.0 : c >= 0.0 ? 1.0 : near_source);
}
#endif

#if defined(STEP_PULL) || defined(STEP_PUSH) || defined(STEP_LINES) || defined(STEP_SETTLE)
// The coarse level's values at fine pixel (x, y), bilinearly (near_layer.c's upsample).
void upsample(uint values, uint w, uint h, uint x, uint y, out float result[MAX_VALUES])
{
    precise float u = max(0.0, 0.5 * float(x) - 0.25);
    precise float t = max(0.0, 0.5 * float(y) - 0.25);
    uint x0 = uint(u), y0 = uint(t);
    x0 = x0 < w ? x0 : w - 1u;
    y0 = y0 < h ? y0 : h - 1u;
    const uint x1 = x0 + 1u < w ? x0 + 1u : x0;
    const uint y1 = y0 + 1u < h ? y0 + 1u : y0;
    precise float fx = min(1.0, u - float(x0)), fy = min(1.0, t - float(y0));
    const uint a = values + (y0 * w + x0) * u_values, b = values + (y0 * w + x1) * u_values;
    const uint c = values + (y1 * w + x0) * u_values, d = values + (y1 * w + x1) * u_values;
    for (uint k = 0u; k < u_values; k++) {
        precise float top = pyramid[a + k] + fx * (pyramid[b + k] - pyramid[a + k]);
        precise float bottom = pyramid[c + k] + fx * (pyramid[d + k] - pyramid[c + k]);
        result[k] = top + fy * (bottom - top);
    }
}
#endif

#ifdef STEP_PULL
// The values and weight of pixel (x, y) of the fine level: level 0 is the frame.
float fetch(uint x, uint y, out float v[MAX_VALUES])
{
    if (u_from == 0u) {
        const uint i = y * u_width + x;
        const float source = map_at(SOURCE, i);
        if (source <= 0.0)
            return 0.0;
        const bool split = map_at(FRINGE, i) > 0.0; // a split fringe pixel: its rest's part
        for (uint k = 0u; k < u_channels; k++)
            v[k] = split ? rest[i * u_channels + k] : color_at(x, y, k);
        v[u_channels] = coc_at(x, y);
        return source;
    }
    const uint i = y * u_fine_w + x;
    for (uint k = 0u; k < u_values; k++)
        v[k] = pyramid[u_fine_values + i * u_values + k];
    return pyramid[u_fine_weight + i];
}

void main()
{
    const uint i = global_id();
    if (i >= u_coarse_w * u_coarse_h)
        return;
    const uint x = i % u_coarse_w, y = i / u_coarse_w;
    precise float sum[MAX_VALUES] = float[MAX_VALUES](0.0, 0.0, 0.0, 0.0, 0.0);
    float v[MAX_VALUES];
    precise float total = 0.0;
    for (uint dy = 0u; dy < 2u; dy++)
        for (uint dx = 0u; dx < 2u; dx++) {
            const uint fx = 2u * x + dx, fy = 2u * y + dy;
            if (fx >= u_fine_w || fy >= u_fine_h)
                continue;
            const float w = fetch(fx, fy, v);
            if (w <= 0.0)
                continue;
            total += w;
            for (uint k = 0u; k < u_values; k++)
                sum[k] += w * v[k];
        }
    for (uint k = 0u; k < u_values; k++)
        pyramid[u_coarse_values + i * u_values + k] = total > 0.0 ? sum[k] / total : 0.0;
    pyramid[u_coarse_weight + i] = min(1.0, total);
}
#endif

#ifdef STEP_PUSH
void main()
{
    const uint i = global_id();
    if (i >= u_fine_w * u_fine_h)
        return;
    const float w = pyramid[u_fine_weight + i];
    if (w >= 1.0)
        return;
    float up[MAX_VALUES];
    upsample(u_coarse_values, u_coarse_w, u_coarse_h, i % u_fine_w, i / u_fine_w, up);
    for (uint k = 0u; k < u_values; k++) {
        const uint at = u_fine_values + i * u_values + k;
        precise float mixed = w * pyramid[at] + (1.0 - w) * up[k];
        pyramid[at] = mixed;
    }
    pyramid[u_fine_weight + i] = 1.0;
}
#endif

#ifdef STEP_LINES
bool is_source(uint x, uint y)
{
    return map_at(SOURCE, y * u_width + x) > 0.0;
}

// A line's end value at source pixel (x, y): level END_LEVEL's mean there (u_fine_*: level 1).
void end_value(uint x, uint y, out float v[MAX_VALUES])
{
    const uint i = (y >> DDOF_NEAR_END_LEVEL) * u_fine_w + (x >> DDOF_NEAR_END_LEVEL);
    for (uint k = 0u; k < u_values; k++)
        v[k] = pyramid[u_fine_values + i * u_values + k];
}

// The run's interpolation at one of its pixels (near_layer.c's across_run) into the rest.
void visit(uint x, uint y, float v[MAX_VALUES], float w)
{
    const uint p = y * u_width + x;
    if (u_direction == 0u) {
        set_map(LINE_WEIGHT, p, w);
        for (uint k = 0u; k < u_channels; k++) {
            precise float s = w * v[k];
            rest[p * u_channels + k] = s;
        }
        precise float s = w * v[u_channels];
        rest_coc[p] = s;
        return;
    }
    if (map_at(MATTE, p) < 1.0 || w <= 0.0)
        return;
    precise float total = map_at(LINE_WEIGHT, p) + w;
    set_map(LINE_WEIGHT, p, total);
    for (uint k = 0u; k < u_channels; k++) {
        precise float s = rest[p * u_channels + k] + w * v[k];
        rest[p * u_channels + k] = s;
    }
    precise float s = rest_coc[p] + w * v[u_channels];
    rest_coc[p] = s;
}

void main()
{
    const uint d = global_id();
    int x0, y0, dx, dy;
    uint length;
    if (u_direction == 0u) {
        if (d >= u_height)
            return;
        x0 = 0, y0 = int(d), dx = 1, dy = 0, length = u_width;
    } else if (u_direction == 1u) {
        if (d >= u_width)
            return;
        x0 = int(d), y0 = 0, dx = 0, dy = 1, length = u_height;
    } else {
        // near_layer.c's diagonal(): each starts on the top row, then down the side it comes from
        if (d >= u_width + u_height - 1u)
            return;
        dx = u_direction == 2u ? 1 : -1;
        dy = 1;
        const uint sx = d < u_width ? (dx > 0 ? d : u_width - 1u - d)
                                    : (dx > 0 ? 0u : u_width - 1u);
        const uint sy = d < u_width ? 0u : d - u_width + 1u;
        const uint across = dx > 0 ? u_width - sx : sx + 1u, down = u_height - sy;
        x0 = int(sx), y0 = int(sy), length = across < down ? across : down;
    }
    const float step = dx != 0 && dy != 0 ? 1.41421356 : 1.0;
    float before[MAX_VALUES], after[MAX_VALUES], v[MAX_VALUES];
    uint a = 0u;
    while (a < length) {
        if (is_source(uint(x0 + int(a) * dx), uint(y0 + int(a) * dy))) {
            a++;
            continue;
        }
        uint b = a;
        while (b < length && !is_source(uint(x0 + int(b) * dx), uint(y0 + int(b) * dy)))
            b++;
        const bool has_before = a > 0u, has_after = b < length;
        if (has_before)
            end_value(uint(x0 + int(a - 1u) * dx), uint(y0 + int(a - 1u) * dy), before);
        if (has_after)
            end_value(uint(x0 + int(b) * dx), uint(y0 + int(b) * dy), after);
        precise float run = float(b - a + 1u) * step;
        for (uint i = a; i < b; i++) {
            float w = 0.0;
            if (has_before && has_after) {
                precise float t = float(i - a + 1u) / float(b - a + 1u);
                for (uint k = 0u; k < u_values; k++) {
                    precise float mixed = before[k] + t * (after[k] - before[k]);
                    v[k] = mixed;
                }
                w = 1.0 / (run * run);
            } else if (has_before || has_after) {
                for (uint k = 0u; k < u_values; k++)
                    v[k] = has_before ? before[k] : after[k];
                w = 0.25 / (run * run);
            } else {
                for (uint k = 0u; k < u_values; k++)
                    v[k] = 0.0;
            }
            visit(uint(x0 + int(i) * dx), uint(y0 + int(i) * dy), v, w);
        }
        a = b + 1u;
    }
}
#endif

#ifdef STEP_SETTLE
void main()
{
    const uint p = global_id();
    if (p >= pixels() || map_at(MATTE, p) < 1.0)
        return;
    const float w = map_at(LINE_WEIGHT, p);
    if (w > 0.0) {
        for (uint k = 0u; k < u_channels; k++)
            rest[p * u_channels + k] /= w;
        rest_coc[p] /= w;
        return;
    }
    float pp[MAX_VALUES]; // pull-push where no line reached (u_coarse_*: level 1)
    upsample(u_coarse_values, u_coarse_w, u_coarse_h, p % u_width, p / u_width, pp);
    for (uint k = 0u; k < u_channels; k++)
        rest[p * u_channels + k] = pp[k];
    rest_coc[p] = pp[u_channels];
}
#endif

#ifdef STEP_FINISH
void main()
{
    const uint i = global_id();
    if (i >= pixels())
        return;
    const uint x = i % u_width, y = i / u_width;
    const float c = coc_at(x, y);
    const float m = map_at(MATTE, i);
    if (u_channels == 4u) {
        const float alpha = color_at(x, y, 3u);
        set_map(CARRIED, i, m * alpha);
        if (m > 0.0 && alpha != 1.0)
            atomicOr(facts[7], 1u);
    }
    if (m > 0.0) {
        atomicAdd(facts[5], 1u);
        atomicMin(facts[0], x);
        atomicMin(facts[1], y);
        atomicMax(facts[2], x + 1u);
        atomicMax(facts[3], y + 1u);
        atomicMax(facts[4], floatBitsToUint(element_coc[i]));
    }
    if (map_at(FRINGE, i) > 0.0)
        return; // split by STEP_MATTE: element and rest written
    for (uint k = 0u; k < 3u; k++) {
        precise float e = m * color_at(x, y, k);
        element[i * 4u + k] = e;
    }
    element[i * 4u + 3u] = m;
    if (m >= 1.0 && u_filled != 0u) {
        atomicAdd(facts[6], 1u); // a hole, filled by the lines and the offsets
    } else {
        for (uint k = 0u; k < u_channels; k++)
            rest[i * u_channels + k] = color_at(x, y, k);
        rest_coc[i] = c;
    }
}
#endif

#ifdef STEP_ANALYSE
float rest_abs(uint x, uint y)
{
    return abs(rest_coc[y * u_width + x]);
}

void main()
{
    const uint i = global_id();
    if (i >= pixels())
        return;
    const uint x = i % u_width, y = i / u_width;
    const float c = rest_coc[i];
    if (c < 0.0) {
        atomicMin(facts[12], x);
        atomicMin(facts[13], y);
        atomicMax(facts[14], x + 1u);
        atomicMax(facts[15], y + 1u);
    }
    if (!(c >= u_bg_threshold))
        return;
    float m = uintBitsToFloat(0x7f800000u); // planner.c's min_neighbour: the 4 neighbours
    if (x > 0u)
        m = min(m, rest_abs(x - 1u, y));
    if (x + 1u < u_width)
        m = min(m, rest_abs(x + 1u, y));
    if (y > 0u)
        m = min(m, rest_abs(x, y - 1u));
    if (y + 1u < u_height)
        m = min(m, rest_abs(x, y + 1u));
    if (m < u_bg_insulator) {
        atomicMin(facts[8], x);
        atomicMin(facts[9], y);
        atomicMax(facts[10], x + 1u);
        atomicMax(facts[11], y + 1u);
    }
}
#endif
