/* SPDX-License-Identifier: MIT */
// near_offsets.comp - the near layer's fill from where the frame repeats itself on the device
// (../near_offsets_fill.c, ../near_offsets_search.c), one program per step (the define names
// it), in the CPU's arithmetic (its sums in double where the CPU's are; the search's eight
// float lanes in its order, `precise`), so that the host, which ranks the search's errors and
// picks the candidates by ddof_near_rules.h as the CPU does, makes the same choices:
//  STEP_REDUCE: per block of the search level, its mean of sources, known and hole (and the
//    hole map into the first box map, for the band);
//  STEP_BOX_ROWS, STEP_BOX_COLUMNS: box sums of u_radius over u_maps maps, one line each;
//  STEP_BAND: the band (known blocks within BAND of a hole block);
//  STEP_PHASES, STEP_GRID: the search's planes, and the count of known samples;
//  STEP_BAND_ROWS, STEP_BAND_TOTAL, STEP_BAND_SAMPLES: the band blocks, evenly thinned;
//  STEP_SEARCH: a grid offset's error (every second one, or those listed);
//  STEP_REFINE: a candidate's band errors around it, to the pixel;
//  STEP_VARIANCE_MAPS, STEP_VARIANCE: the band's colour variance, the kept lists emptied;
//  STEP_CANDIDATE, STEP_KEEP: a candidate's score per block, kept among each block's best;
//  STEP_COPY: each hole pixel mixes its kept candidates' copies into the smooth fill.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; };
layout(std430, binding = 1) readonly buffer ColorIn { float color_in[]; };
layout(std430, binding = 2) readonly buffer Maps { float maps[]; }; // near_layer.comp's
#ifdef STEP_COPY
layout(std430, binding = 3) buffer Rest { float rest[]; };
layout(std430, binding = 4) buffer RestCoc { float rest_coc[]; };
#else
// [0] known samples, [1] band blocks, [2] band samples, [3] their spacing; then per level
// row its band blocks and their offset; the band samples; the grid offsets to search.
layout(std430, binding = 3) buffer Ints { uint ints[]; };
#endif
// The level: mean (3 a block), known, band, hole, variance, the KEPT best costs and
// candidates per block (planes of wl x hl).
layout(std430, binding = 5) buffer Level { float level[]; };
layout(std430, binding = 6) buffer Box { float box[]; }; // 2 MAX_BOX_MAPS maps of wl x hl
// The search's grid (4 planes of gw x gh), its phases (SAMPLE_STRIDE x 4 planes of gw x hl),
// its errors (side x side), the refinement's errors (CANDIDATES x (2 reach + 1)^2).
layout(std430, binding = 7) buffer Search { float search[]; };

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_color_base;
uniform uint u_color_stride;
uniform uint u_s, u_wl, u_hl, u_gw, u_gh; // the level's blocks and the search's grid
uniform int u_reach;
uniform uint u_maps, u_radius;            // the box sums
uniform uint u_count;                     // STEP_SEARCH: the listed offsets (0: every second)
uniform int u_dx, u_dy;                   // a candidate's offset (level blocks, or pixels)
uniform uint u_current;                   // its number
uniform uint u_candidates;                // STEP_COPY: how many, and their offsets (pixels)
uniform ivec2 u_full[DDOF_NEAR_CANDIDATES];

const float INF = uintBitsToFloat(0x7f800000u);
const uint KEPT = DDOF_NEAR_KEPT;
const uint SOURCE = 2u, MATTE = 3u; // near_layer.comp's maps
// Ints' layout.
const uint SAMPLE_COUNT = 0u, BAND_TOTAL = 1u, BAND_SAMPLE_COUNT = 2u, BAND_EVERY = 3u;

uint blocks()
{
    return u_wl * u_hl;
}

uint row_counts()
{
    return 4u;
}

uint row_offsets()
{
    return 4u + u_hl;
}

uint band_samples()
{
    return 4u + 2u * u_hl;
}

uint todo()
{
    return band_samples() + DDOF_NEAR_REFINE_SAMPLES;
}

// The level's planes.
uint MEAN() { return 0u; }
uint KNOWN() { return 3u * blocks(); }
uint BAND_() { return 4u * blocks(); }
uint HOLE() { return 5u * blocks(); }
uint VARIANCE() { return 6u * blocks(); }
uint TOP_COST() { return 7u * blocks(); }
uint TOP_INDEX() { return (7u + KEPT) * blocks(); }

// The search buffer's parts.
uint grid_plane() { return u_gw * u_gh; }
uint phase_plane() { return u_gw * u_hl; }
uint PHASES() { return 4u * grid_plane(); }
uint ERRORS() { return PHASES() + DDOF_NEAR_SAMPLE_STRIDE * 4u * phase_plane(); }
uint side() { return uint(2 * u_reach / DDOF_NEAR_OFFSET_STEP + 1); }
uint REFINE() { return ERRORS() + side() * side(); }

float color_at(uint x, uint y, uint k)
{
    return color_in[u_color_base + y * u_color_stride + x * u_channels + k];
}

float map_at(uint plane, uint i)
{
    return maps[plane * u_width * u_height + i];
}

// near_offsets_internal.h's offsets_is_source: a whole source, inside the frame.
bool is_source(int x, int y)
{
    return x >= 0 && y >= 0 && x < int(u_width) && y < int(u_height) &&
           map_at(SOURCE, uint(y) * u_width + uint(x)) >= 1.0;
}

float sq_distance3(vec3 a, vec3 b)
{
    precise float s = 0.0;
    for (uint k = 0u; k < 3u; k++)
        s += (a[k] - b[k]) * (a[k] - b[k]);
    return s;
}

vec3 mean_at(uint b)
{
    return vec3(level[MEAN() + 3u * b], level[MEAN() + 3u * b + 1u], level[MEAN() + 3u * b + 2u]);
}

#ifdef STEP_REDUCE
void main()
{
    const uint b = global_id();
    if (b >= blocks())
        return;
    const uint bx = b % u_wl, by = b / u_wl;
    double sum[3] = double[3](0.0lf, 0.0lf, 0.0lf);
    uint pixels = 0u, sources = 0u, holes = 0u;
    for (uint y = by * u_s; y < (by + 1u) * u_s && y < u_height; y++)
        for (uint x = bx * u_s; x < (bx + 1u) * u_s && x < u_width; x++) {
            const uint i = y * u_width + x;
            pixels++;
            holes += map_at(MATTE, i) >= 1.0 ? 1u : 0u;
            if (map_at(SOURCE, i) < 1.0)
                continue;
            sources++;
            for (uint k = 0u; k < 3u; k++)
                sum[k] += double(color_at(x, y, k));
        }
    // Clamped so that squared differences stay finite (the scores only rank candidates).
    for (uint k = 0u; k < 3u; k++) {
        const double m = sources > 0u ? sum[k] / double(sources) : 0.0lf;
        level[MEAN() + 3u * b + k] = float(m < -DDOF_NEAR_MEAN_LIMIT ? -DDOF_NEAR_MEAN_LIMIT
                                           : m > DDOF_NEAR_MEAN_LIMIT ? DDOF_NEAR_MEAN_LIMIT
                                                                       : m);
    }
    level[KNOWN() + b] = sources == pixels ? 1.0 : 0.0;
    level[HOLE() + b] = holes > 0u ? 1.0 : 0.0;
    box[b] = holes > 0u ? 1.0 : 0.0;
}
#endif

#if defined(STEP_BOX_ROWS) || defined(STEP_BOX_COLUMNS)
// Box sums of radius r along one line of n values `stride` floats apart (clipped at the line's
// ends): a running sum in double (near_offsets_fill.c's box_line).
void box_line(uint in_at, uint out_at, uint n, uint stride, uint r)
{
    double s = 0.0lf;
    for (uint i = 0u; i <= r && i < n; i++)
        s += double(box[in_at + i * stride]);
    for (uint i = 0u; i < n; i++) {
        box[out_at + i * stride] = float(s);
        if (i + r + 1u < n)
            s += double(box[in_at + (i + r + 1u) * stride]);
        if (i >= r)
            s -= double(box[in_at + (i - r) * stride]);
    }
}

void main()
{
    const uint id = global_id();
#ifdef STEP_BOX_ROWS
    const uint lines = u_hl;
#else
    const uint lines = u_wl;
#endif
    if (id >= u_maps * lines)
        return;
    const uint m = id / lines, line = id % lines;
    const uint first = m * blocks(), second = (DDOF_NEAR_MAX_BOX_MAPS + m) * blocks();
#ifdef STEP_BOX_ROWS
    box_line(first + line * u_wl, second + line * u_wl, u_wl, 1u, u_radius);
#else
    box_line(second + line, first + line, u_hl, u_wl, u_radius);
#endif
}
#endif

#ifdef STEP_BAND
void main()
{
    const uint b = global_id();
    if (b < blocks())
        level[BAND_() + b] = level[KNOWN() + b] > 0.0 && box[b] > 0.0 ? 1.0 : 0.0;
}
#endif

#ifdef STEP_PHASES
// Per float of the phases: the level split by x modulo SAMPLE_STRIDE (beyond its edge: unknown).
void main()
{
    const uint id = global_id();
    if (id >= DDOF_NEAR_SAMPLE_STRIDE * phase_plane())
        return;
    const uint phase = id / phase_plane(), y = (id % phase_plane()) / u_gw, q = id % u_gw;
    const uint x = q * DDOF_NEAR_SAMPLE_STRIDE + phase, b = y * u_wl + x;
    const uint to = PHASES() + phase * 4u * phase_plane() + y * u_gw + q;
    for (uint k = 0u; k < 4u; k++)
        search[to + k * phase_plane()] =
            x >= u_wl ? 0.0 : k < 3u ? level[MEAN() + 3u * b + k] : level[KNOWN() + b];
}
#endif

#ifdef STEP_GRID
void main()
{
    const uint g = global_id();
    if (g >= grid_plane())
        return;
    const uint gx = g % u_gw, gy = g / u_gw;
    const uint b = gy * DDOF_NEAR_SAMPLE_STRIDE * u_wl + gx * DDOF_NEAR_SAMPLE_STRIDE;
    for (uint k = 0u; k < 4u; k++)
        search[k * grid_plane() + g] = k < 3u ? level[MEAN() + 3u * b + k] : level[KNOWN() + b];
    if (level[KNOWN() + b] > 0.0)
        atomicAdd(ints[SAMPLE_COUNT], 1u);
}
#endif

#ifdef STEP_BAND_ROWS
void main()
{
    const uint y = global_id();
    if (y >= u_hl)
        return;
    uint count = 0u;
    for (uint x = 0u; x < u_wl; x++)
        count += level[BAND_() + y * u_wl + x] > 0.0 ? 1u : 0u;
    ints[row_counts() + y] = count;
}
#endif

#ifdef STEP_BAND_TOTAL
// One invocation: the rows' offsets, the band's blocks and their spacing (collect_band_samples).
void main()
{
    if (global_id() != 0u)
        return;
    uint total = 0u;
    for (uint y = 0u; y < u_hl; y++) {
        ints[row_offsets() + y] = total;
        total += ints[row_counts() + y];
    }
    const uint every = total / (DDOF_NEAR_REFINE_SAMPLES / u_s) + 1u;
    ints[BAND_TOTAL] = total;
    ints[BAND_EVERY] = every;
    ints[BAND_SAMPLE_COUNT] = (total + every - 1u) / every;
}
#endif

#ifdef STEP_BAND_SAMPLES
void main()
{
    const uint y = global_id();
    if (y >= u_hl)
        return;
    const uint every = ints[BAND_EVERY];
    uint seen = ints[row_offsets() + y];
    for (uint x = 0u; x < u_wl; x++) {
        const uint b = y * u_wl + x;
        if (!(level[BAND_() + b] > 0.0))
            continue;
        if (seen % every == 0u)
            ints[band_samples() + seen / every] = b;
        seen++;
    }
}
#endif

#ifdef STEP_SEARCH
// The search's error of grid offset (row, col) (near_offsets_search.c's search_error).
float search_error(uint row, uint col)
{
    const int dy = -u_reach + int(row) * DDOF_NEAR_OFFSET_STEP;
    const int dx = -u_reach + int(col) * DDOF_NEAR_OFFSET_STEP;
    if (abs(dx) < DDOF_NEAR_MIN_OFFSET && abs(dy) < DDOF_NEAR_MIN_OFFSET)
        return INF;
    const int stride = int(DDOF_NEAR_SAMPLE_STRIDE);
    const int gx0 = dx < 0 ? (-dx + stride - 1) / stride : 0;
    const int gy0 = dy < 0 ? (-dy + stride - 1) / stride : 0;
    // The CPU's (wl - dx + stride - 1) / stride truncates toward zero: nothing below 1.
    const int nx = int(u_wl) - dx + stride - 1, ny = int(u_hl) - dy + stride - 1;
    int gx1 = nx > 0 ? nx / stride : 0, gy1 = ny > 0 ? ny / stride : 0;
    gx1 = gx1 < int(u_gw) ? gx1 : int(u_gw);
    gy1 = gy1 < int(u_gh) ? gy1 : int(u_gh);
    const int phase = dx & (stride - 1), q = (dx - phase) / stride;
    const uint phase_base = PHASES() + uint(phase) * 4u * phase_plane();
    double sum = 0.0lf, used = 0.0lf;
    for (int gy = gy0; gy < gy1; gy++) {
        const uint at = uint(gy) * u_gw + uint(gx0);
        const uint to = uint(gy * stride + dy) * u_gw + uint(gx0 + q);
        const int count = gx1 - gx0;
        precise float s[DDOF_NEAR_SEARCH_LANES], u[DDOF_NEAR_SEARCH_LANES];
        for (int l = 0; l < DDOF_NEAR_SEARCH_LANES; l++) {
            s[l] = 0.0;
            u[l] = 0.0;
        }
        int i = 0;
        for (; i + DDOF_NEAR_SEARCH_LANES <= count; i += DDOF_NEAR_SEARCH_LANES)
            for (int l = 0; l < DDOF_NEAR_SEARCH_LANES; l++) {
                const uint a = at + uint(i + l), b = phase_base + to + uint(i + l);
                precise float k = search[3u * grid_plane() + a] * search[3u * phase_plane() + b];
                precise float d0 = search[a] - search[b];
                precise float d1 = search[grid_plane() + a] - search[phase_plane() + b];
                precise float d2 = search[2u * grid_plane() + a] - search[2u * phase_plane() + b];
                s[l] += k * (d0 * d0 + d1 * d1 + d2 * d2);
                u[l] += k;
            }
        for (; i < count; i++) {
            const uint a = at + uint(i), b = phase_base + to + uint(i);
            precise float k = search[3u * grid_plane() + a] * search[3u * phase_plane() + b];
            precise float d0 = search[a] - search[b];
            precise float d1 = search[grid_plane() + a] - search[phase_plane() + b];
            precise float d2 = search[2u * grid_plane() + a] - search[2u * phase_plane() + b];
            s[0] += k * (d0 * d0 + d1 * d1 + d2 * d2);
            u[0] += k;
        }
        for (int l = 0; l < DDOF_NEAR_SEARCH_LANES; l++) {
            sum += double(s[l]);
            used += double(u[l]);
        }
    }
    return used > 0.0lf && used >= DDOF_NEAR_MIN_OVERLAP * double(ints[SAMPLE_COUNT])
               ? float(sum / used)
               : INF;
}

void main()
{
    const uint id = global_id();
    const uint n = side();
    if (u_count == 0u) { // the coarse pass: every second offset in x and y, the others none
        if (id >= n * n)
            return;
        const uint row = id / n, col = id % n;
        search[ERRORS() + id] = row % 2u == 0u && col % 2u == 0u ? search_error(row, col) : INF;
        return;
    }
    if (id >= u_count)
        return;
    const uint g = ints[todo() + id];
    search[ERRORS() + g] = search_error(g / n, g % n);
}
#endif

#ifdef STEP_REFINE
// The mean squared difference of the frame's band sources (one pixel per sampled band block)
// and their copies moved by the candidate's start + this invocation's (ex, ey), pixels.
void main()
{
    const int reach = int(u_s) * DDOF_NEAR_OFFSET_STEP / 2, n = 2 * reach + 1;
    const uint id = global_id();
    if (id >= uint(n * n))
        return;
    const int dx = u_dx + int(id % uint(n)) - reach, dy = u_dy + int(id / uint(n)) - reach;
    double sum = 0.0lf;
    uint used = 0u;
    const uint count = ints[BAND_SAMPLE_COUNT];
    for (uint k = 0u; k < count; k++) {
        const uint b = ints[band_samples() + k];
        const int x = int((b % u_wl) * u_s), y = int((b / u_wl) * u_s);
        if (!is_source(x + dx, y + dy))
            continue;
        vec3 a, c;
        for (uint j = 0u; j < 3u; j++) {
            a[j] = color_at(uint(x), uint(y), j);
            c[j] = color_at(uint(x + dx), uint(y + dy), j);
        }
        sum += double(sq_distance3(a, c));
        used++;
    }
    search[REFINE() + u_current * uint(n * n) + id] = used > 0u ? float(sum / double(used)) : INF;
}
#endif

#ifdef STEP_VARIANCE_MAPS
void main()
{
    const uint b = global_id();
    if (b >= blocks())
        return;
    const float w = level[BAND_() + b];
    box[b] = w;
    for (uint k = 0u; k < 3u; k++) {
        const float m = level[MEAN() + 3u * b + k];
        precise float wm = w * m;
        precise float wmm = wm * m;
        box[(1u + k) * blocks() + b] = wm;
        box[(4u + k) * blocks() + b] = wmm;
    }
}
#endif

#ifdef STEP_VARIANCE
void main()
{
    const uint b = global_id();
    if (b >= blocks())
        return;
    const double count = double(box[b]);
    precise double v = 0.0lf;
    if (count > double(DDOF_NEAR_MIN_BAND_SAMPLES))
        for (uint k = 0u; k < 3u; k++) {
            precise double m = double(box[(1u + k) * blocks() + b]) / count;
            v += double(box[(4u + k) * blocks() + b]) / count - m * m;
        }
    level[VARIANCE() + b] = float(v > 0.0lf ? v : 0.0lf);
    for (uint k = 0u; k < KEPT; k++) {
        level[TOP_COST() + b * KEPT + k] = INF;
        level[TOP_INDEX() + b * KEPT + k] = 0.0;
    }
}
#endif

#if defined(STEP_CANDIDATE) || defined(STEP_KEEP)
// Whether block b moved by the candidate's offset (u_dx, u_dy blocks) lands on a known block,
// which is then t.
bool lands_on_known(uint b, out uint t)
{
    const int tx = int(b % u_wl) + u_dx, ty = int(b / u_wl) + u_dy;
    t = 0u;
    if (tx < 0 || ty < 0 || tx >= int(u_wl) || ty >= int(u_hl))
        return false;
    t = uint(ty) * u_wl + uint(tx);
    return level[KNOWN() + t] > 0.0;
}
#endif

#ifdef STEP_CANDIDATE
void main()
{
    const uint b = global_id();
    if (b >= blocks())
        return;
    uint t;
    const bool used = level[BAND_() + b] > 0.0 && lands_on_known(b, t);
    box[b] = used ? sq_distance3(mean_at(b), mean_at(t)) : 0.0;
    box[blocks() + b] = used ? 1.0 : 0.0;
}
#endif

#ifdef STEP_KEEP
void main()
{
    const uint b = global_id();
    if (b >= blocks())
        return;
    uint t;
    const float samples = box[blocks() + b];
    if (level[HOLE() + b] <= 0.0 || !(samples > DDOF_NEAR_MIN_BAND_SAMPLES) ||
        !lands_on_known(b, t))
        return;
    const float cost = box[b] / samples;
    const uint tc = TOP_COST() + b * KEPT, ti = TOP_INDEX() + b * KEPT;
    if (!(cost < level[tc + KEPT - 1u]))
        return; // NaN (an overflow) included
    uint k = KEPT - 1u;
    for (; k > 0u && cost < level[tc + k - 1u]; k--) {
        level[tc + k] = level[tc + k - 1u];
        level[ti + k] = level[ti + k - 1u];
    }
    level[tc + k] = cost;
    level[ti + k] = float(u_current);
}
#endif

#ifdef STEP_COPY
float coc_at(uint x, uint y)
{
    return coc_in[u_coc_base + y * u_coc_stride + x * u_coc_step];
}

void main()
{
    const uint p = global_id();
    if (p >= u_width * u_height || map_at(MATTE, p) < 1.0)
        return;
    const uint x = p % u_width, y = p / u_width;
    const uint b = (y / u_s) * u_wl + x / u_s;
    const uint tc = TOP_COST() + b * KEPT, ti = TOP_INDEX() + b * KEPT;
    const float c_min = level[tc], v = level[VARIANCE() + b];
    precise float share = v / (v + c_min);
    share *= share;
    if (!(share > 0.0 && share <= 1.0))
        return; // no candidate (c_min infinite), nothing varies, or an overflow
    precise float sum[5] = float[5](0.0, 0.0, 0.0, 0.0, 0.0);
    precise float total = 0.0;
    for (uint k = 0u; k < KEPT && level[tc + k] < INF; k++) {
        const ivec2 d = u_full[uint(level[ti + k])];
        const int sx = int(x) + d.x, sy = int(y) + d.y;
        if (!is_source(sx, sy))
            continue;
        precise float q = (level[tc + k] - c_min) /
                          (DDOF_NEAR_SOFTNESS * c_min + DDOF_NEAR_SOFT_FLOOR);
        const float w = exp(-min(50.0, q));
        for (uint i = 0u; i < u_channels; i++)
            sum[i] += w * color_at(uint(sx), uint(sy), i);
        sum[u_channels] += w * coc_at(uint(sx), uint(sy));
        total += w;
    }
    if (!(total > 0.0))
        return;
    for (uint i = 0u; i < u_channels; i++) {
        precise float r = rest[p * u_channels + i];
        rest[p * u_channels + i] = r + share * (sum[i] / total - r);
    }
    precise float r = rest_coc[p];
    rest_coc[p] = r + share * (sum[u_channels] / total - r);
}
#endif
