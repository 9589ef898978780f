/* SPDX-License-Identifier: MIT */
// far_field.comp - the far field on the device (../far_field.c, ../far_field_gather.c,
// ../far_layers.c), one program per step (the define names it), in the CPU's arithmetic and
// order: `precise` keeps a GPU from fusing a multiply and add the CPU rounds twice, the sums
// the CPU keeps in double are doubles here, and each running sum runs in one invocation in the
// CPU's order. gl_far_field.c drives the steps; the constants come from ddof_far_rules.h as
// defines. A step that walks a line runs u_seg_count of its steps from u_seg_first per
// dispatch, its running state kept in the buffers (llvmpipe ends a shader's loops silently after
// 65,535 iterations).
//
// Maps are frame-sized float arrays (width floats a row). LEVELS holds each image level's
// prefix sums, sides, image, samples and the marks of the samples wanted, at the offsets of
// the table in TABLE (8 uints a level from TABLE_LEVELS); TABLE also holds the counts the host
// reads (the T_* indices) and the cuts' difference array (from TABLE_RUNS).
layout(local_size_x = 256) in;

#define T_PIXELS 0u   // pixels with some of the gather
#define T_LAYERED 1u  // of which with a share of the slices
#define T_LARGEST 2u  // the largest radius of those (float bits; radii are >= 0)
#define T_PAIRS 3u    // edges between blurred surfaces
#define T_LO 4u       // their smallest signed CoC (ordered key)
#define T_HI 5u       // their largest (ordered key)
#define T_MEMBERS 8u  // per slice: its pixels
#define T_MEAN 12u    // per slice: the mean radius of its pixels (float bits)
#define T_REACH 16u   // the slice's largest radius where a pixel has a share (float bits)
#define TABLE_LEVELS 32u
#define TABLE_RUNS 160u
#define NO_SLICE 255.0
#define TINY 1e-6
#define GRADIENT_MAX 0.5
#define RAMP_TOLERANCE 0.25
#define GAUSS_POINT 0.28867513
#define TWO_TAPS_BELOW 4.0

#if defined(STEP_SEED) || defined(STEP_PAIRS_RANGE) || defined(STEP_PAIRS_RUNS) || \
    defined(STEP_SLICE_INDEX)
layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; };
#endif
#if defined(STEP_SLICE_IMAGE) || defined(STEP_DOWNSAMPLE) || defined(STEP_PREFIX) || \
    defined(STEP_EDGE_ROWS) || defined(STEP_EDGE_SIDES)
layout(std430, binding = 1) readonly buffer Src { float src[]; }; // the gathered image, level 0
#endif
#if defined(STEP_GATHER) || defined(STEP_SLICES_BLEND)
layout(std430, binding = 2) buffer Out { float out_px[]; };
#endif
layout(std430, binding = 3) buffer Radius { float radius[]; };
layout(std430, binding = 4) buffer Weight { float weight[]; };  // the gather's share
layout(std430, binding = 5) buffer Reach { float reach[]; };    // then a slice's radii
layout(std430, binding = 6) buffer Layered { float layered[]; };// the slices' share
layout(std430, binding = 7) buffer Sharp { float sharp[]; };    // then each pixel's slice
layout(std430, binding = 8) buffer Levels { float lv[]; };
layout(std430, binding = 9) coherent buffer Table { uint table[]; };
layout(std430, binding = 10) buffer Sink { float sink[]; };     // acc, last, state
layout(std430, binding = 11) buffer Work { float work[]; };     // a slice's image, box sums
layout(std430, binding = 12) buffer Doubles { double dbl[]; };  // running double sums

uniform uint u_width;           // the frame's
uniform uint u_height;
uniform uint u_channels;        // the gathered image's (the colour's, + coverage in a slice)
uniform uint u_frame_channels;  // OUT's
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_src_base;        // src[] index of the level-0 image's first value
uniform uint u_src_stride;      // floats a row (a pixel: u_channels)
uniform float u_in_focus;
uniform float u_aspect;         // pixel aspect
uniform uint u_slices;          // the slices' share is wanted
uniform uint u_sink;            // a slice's gather: into the sink, not OUT
uniform uint u_level;           // the level a level step works on
uniform uint u_level_count;
uniform uint u_seg_first;       // a line step's first step this dispatch
uniform uint u_seg_count;
uniform uint u_in_place;        // the prefix step: the two edge rows, their input in place
uniform float u_lo;             // the cuts: the pairs' smallest signed CoC, the bins' width
uniform float u_bin_width;
uniform uint u_bins;
uniform uint u_cut_count;
uniform float u_cut0;
uniform float u_cut1;
uniform float u_cut2;
uniform uint u_slice;           // the slice being gathered
uniform uint u_reach;           // its box's half-width
uniform uint u_acc_at;          // sink[] offsets: acc and last (u_frame_channels a pixel),
uniform uint u_last_at;         // state (2 a pixel)
uniform uint u_state_at;
uniform uint u_box_at;          // work[] offset of the box sums (the image is at 0)
uniform uint u_column_at;       // dbl[] offsets: the columns' running sums, the rows' state,
uniform uint u_rowstate_at;     // the chunks' partial sums
uniform uint u_partial_at;
uniform uint u_chunk;           // pixels a partial sum covers

// ---- the level table -------------------------------------------------------------------------

uint lw(uint k) { return table[TABLE_LEVELS + 8u * k]; }
uint lh(uint k) { return table[TABLE_LEVELS + 8u * k + 1u]; }
uint prefix_at(uint k) { return table[TABLE_LEVELS + 8u * k + 2u]; }
uint sides_at(uint k) { return table[TABLE_LEVELS + 8u * k + 3u]; }
uint image_at(uint k) { return table[TABLE_LEVELS + 8u * k + 4u]; }
uint samples_at(uint k) { return table[TABLE_LEVELS + 8u * k + 5u]; }
uint needed_at(uint k) { return table[TABLE_LEVELS + 8u * k + 6u]; }

#if defined(STEP_SEED) || defined(STEP_PAIRS_RANGE) || defined(STEP_PAIRS_RUNS) || \
    defined(STEP_SLICE_INDEX)
float coc_at(uint x, uint y)
{
    return coc_in[u_coc_base + y * u_coc_stride + x * u_coc_step];
}

// far_layers.c's blurred_edge.
bool blurred_edge(float a, float b)
{
    return abs(a - b) >= FAR_EDGE_STEP_PX && min(abs(a), abs(b)) >= FAR_BLURRED_PX;
}

// The key range.comp orders floats by.
uint ordered(float f)
{
    uint bits = floatBitsToUint(f);
    return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
}
#endif

#if defined(STEP_SLICE_IMAGE) || defined(STEP_DOWNSAMPLE) || defined(STEP_PREFIX) || \
    defined(STEP_EDGE_ROWS) || defined(STEP_EDGE_SIDES)
// Level k's pixel value, channel c (level 0: the source image).
float level_pixel(uint k, uint x, uint y, uint c)
{
    if (k == 0u)
        return src[u_src_base + y * u_src_stride + x * u_channels + c];
    return lv[image_at(k) + (y * lw(k) + x) * u_channels + c];
}
#endif

// ---- the maps (far_field.c) ------------------------------------------------------------------

#ifdef STEP_SEED
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    uint x = i % u_width, y = i / u_width;
    float c = coc_at(x, y), a = abs(c);
    radius[i] = a > 0.0 && a >= u_in_focus ? 0.5 * a : 0.0;
    float far_reach = FAR_NO_EDGE, sharp_reach = FAR_NO_EDGE;
    const int nx[4] = int[4](-1, 1, 0, 0), ny[4] = int[4](0, 0, -1, 1);
    for (int k = 0; k < 4; k++) {
        int qx = int(x) + nx[k], qy = int(y) + ny[k];
        if (qx < 0 || qy < 0 || qx >= int(u_width) || qy >= int(u_height))
            continue;
        float q = coc_at(uint(qx), uint(qy));
        if (abs(q - c) < FAR_EDGE_STEP_PX)
            continue;
        precise float edge_reach = 0.5 * max(a, abs(q)) + 1.0;
        far_reach = max(far_reach, edge_reach);
        if (min(a, abs(q)) < FAR_BLURRED_PX)
            sharp_reach = max(sharp_reach, edge_reach);
    }
    weight[i] = far_reach > FAR_NO_EDGE ? 0.0 : FAR_NO_EDGE;
    reach[i] = far_reach;
    layered[i] = sharp_reach > FAR_NO_EDGE ? 0.0 : FAR_NO_EDGE;
    sharp[i] = sharp_reach;
}
#endif

#ifdef STEP_WEIGHT
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    float rho = radius[i];
    precise float room = min(-weight[i] - rho - 1.0, -reach[i]);
    float w = rho > 0.0 ? min(max(room / FAR_RAMP_PX, 0.0), 1.0) : 0.0;
    float share = 0.0;
    if (u_slices != 0u && rho > 0.0 && w < 1.0) {
        precise float open = min(-layered[i] - rho - 1.0, -sharp[i]);
        share = min(max(open / FAR_RAMP_PX, 0.0), 1.0);
    }
    weight[i] = w;
    layered[i] = share;
    if (w > 0.0 || share > 0.0) {
        atomicAdd(table[T_PIXELS], 1u);
        atomicMax(table[T_LARGEST], floatBitsToUint(rho));
    }
    if (share > 0.0)
        atomicAdd(table[T_LAYERED], 1u);
}
#endif

// ---- the depth slices (far_layers.c) ---------------------------------------------------------

#if defined(STEP_PAIRS_RANGE) || defined(STEP_PAIRS_RUNS)
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    uint x = i % u_width, y = i / u_width;
    float c = coc_at(x, y);
    float next[2] = float[2](x + 1u < u_width ? coc_at(x + 1u, y) : c,
                             y + 1u < u_height ? coc_at(x, y + 1u) : c);
    for (int k = 0; k < 2; k++) {
        if (!blurred_edge(c, next[k]))
            continue;
        float plo = min(c, next[k]), phi = max(c, next[k]);
#ifdef STEP_PAIRS_RANGE
        atomicAdd(table[T_PAIRS], 1u);
        atomicMin(table[T_LO], ordered(plo));
        atomicMax(table[T_HI], ordered(phi));
#else
        // ddof_far_separated and ddof_far_pair_bins
        float cuts[3] = float[3](u_cut0, u_cut1, u_cut2);
        bool separated = false;
        for (uint j = 0u; j < u_cut_count; j++)
            separated = separated || (plo < cuts[j] && cuts[j] <= phi);
        if (separated)
            continue;
        uint b0 = uint(floor((plo - u_lo) / u_bin_width)) + 1u;
        float last = floor((phi - u_lo) / u_bin_width);
        uint b1 = uint(last < float(u_bins) ? last : float(u_bins));
        if (b0 <= b1) {
            atomicAdd(table[TABLE_RUNS + b0], 1u);
            atomicAdd(table[TABLE_RUNS + b1 + 1u], 0xffffffffu);
        }
#endif
    }
}
#endif

#ifdef STEP_SLICE_INDEX
// Each blurred pixel's slice (into SHARP, spent), the sink's start where a pixel has a share,
// and the slices' partial counts and radius sums over chunks of u_chunk pixels (one
// invocation a chunk, in the CPU's order within it).
void main()
{
    uint chunk = global_id();
    uint pixels = u_width * u_height;
    uint first = chunk * u_chunk;
    if (first >= pixels)
        return;
    uint end = min(first + u_chunk, pixels);
    double sums[4] = double[4](0.0lf, 0.0lf, 0.0lf, 0.0lf);
    double counts[4] = double[4](0.0lf, 0.0lf, 0.0lf, 0.0lf);
    float cuts[3] = float[3](u_cut0, u_cut1, u_cut2);
    for (uint i = first; i < end; i++) {
        float k = NO_SLICE;
        if (radius[i] > 0.0) {
            float c = coc_at(i % u_width, i / u_width);
            uint s = 0u;
            while (s < u_cut_count && cuts[s] <= c)
                s++;
            k = float(s);
            sums[s] += double(radius[i]);
            counts[s] += 1.0lf;
        }
        sharp[i] = k;
        if (layered[i] > 0.0) {
            sink[u_state_at + 2u * i] = 1.0;
            sink[u_state_at + 2u * i + 1u] = 0.0;
            for (uint c = 0u; c < u_frame_channels; c++) {
                sink[u_acc_at + i * u_frame_channels + c] = 0.0;
                sink[u_last_at + i * u_frame_channels + c] = 0.0;
            }
        }
    }
    for (uint s = 0u; s < 4u; s++) {
        dbl[u_partial_at + chunk * 8u + s] = sums[s];
        dbl[u_partial_at + chunk * 8u + 4u + s] = counts[s];
    }
}
#endif

#ifdef STEP_SLICE_MEAN
// The slices' members and mean radii from the chunks' partial sums (one invocation).
void main()
{
    if (global_id() != 0u)
        return;
    uint chunks = (u_width * u_height + u_chunk - 1u) / u_chunk;
    for (uint s = 0u; s < 4u; s++) {
        double sum = 0.0lf, count = 0.0lf;
        for (uint c = 0u; c < chunks; c++) {
            sum += dbl[u_partial_at + c * 8u + s];
            count += dbl[u_partial_at + c * 8u + 4u + s];
        }
        table[T_MEMBERS + s] = uint(count);
        table[T_MEAN + s] = floatBitsToUint(count > 0.0lf ? float(sum / count) : 0.0);
    }
}
#endif

#ifdef STEP_SLICE_IMAGE
// The slice's premultiplied colour and coverage (far_layers.c's image_rows, its first half).
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    uint x = i % u_width, y = i / u_width, colours = u_channels - 1u;
    float a = sharp[i] == float(u_slice) ? 1.0 : 0.0;
    for (uint c = 0u; c < colours; c++)
        work[i * u_channels + c] = a * src[u_src_base + y * u_src_stride + x * colours + c];
    work[i * u_channels + colours] = a;
}
#endif

#ifdef STEP_SLICE_BOX
// Running sums of coverage and coverage x radius over [x - reach, x + reach] along each row
// (image_rows' second half), one invocation a row, the sums carried in dbl between dispatches.
void main()
{
    uint y = global_id();
    if (y >= u_height)
        return;
    int reach_px = int(u_reach), w = int(u_width);
    double cover = u_seg_first == 0u ? 0.0lf : dbl[u_rowstate_at + 2u * y];
    double weighted = u_seg_first == 0u ? 0.0lf : dbl[u_rowstate_at + 2u * y + 1u];
    uint row = y * u_width;
    int first = -reach_px - 1 + int(u_seg_first);
    for (int x = first; x < first + int(u_seg_count); x++) {
        int enter = x + reach_px, leave = x - reach_px - 1;
        if (enter >= 0 && enter < w && sharp[row + uint(enter)] == float(u_slice)) {
            cover += 1.0lf;
            weighted += double(radius[row + uint(enter)]);
        }
        if (leave >= 0 && sharp[row + uint(leave)] == float(u_slice)) {
            cover -= 1.0lf;
            weighted -= double(radius[row + uint(leave)]);
        }
        if (x >= 0) {
            work[u_box_at + 2u * (row + uint(x))] = float(cover);
            work[u_box_at + 2u * (row + uint(x)) + 1u] = float(weighted);
        }
    }
    dbl[u_rowstate_at + 2u * y] = cover;
    dbl[u_rowstate_at + 2u * y + 1u] = weighted;
}
#endif

#ifdef STEP_SLICE_RADII
// The slice's radius map (into REACH, spent): the pixel's own on the slice, else the mean of
// the slice's radii within the box (far_layers.c's slice_radii), one invocation a column, its
// running sums in dbl; the largest radius of a pixel with a share into the table.
void main()
{
    uint x = global_id();
    if (x >= u_width)
        return;
    int reach_px = int(u_reach), h = int(u_height);
    double count = u_seg_first == 0u ? 0.0lf : dbl[u_column_at + 2u * x];
    double sum = u_seg_first == 0u ? 0.0lf : dbl[u_column_at + 2u * x + 1u];
    float mean = uintBitsToFloat(table[T_MEAN + u_slice]);
    float largest = 0.0;
    int first = -reach_px - 1 + int(u_seg_first);
    for (int y = first; y < first + int(u_seg_count); y++) {
        int enter = y + reach_px, leave = y - reach_px - 1;
        if (enter >= 0 && enter < h) {
            uint b = u_box_at + 2u * (uint(enter) * u_width + x);
            count += double(work[b]);
            sum += double(work[b + 1u]);
        }
        if (leave >= 0) {
            uint b = u_box_at + 2u * (uint(leave) * u_width + x);
            count -= double(work[b]);
            sum -= double(work[b + 1u]);
        }
        if (y < 0)
            continue;
        uint i = uint(y) * u_width + x;
        float rho = radius[i];
        if (sharp[i] != float(u_slice))
            rho = count > 0.5lf ? float(sum / count) : mean;
        reach[i] = rho;
        if (layered[i] > 0.0)
            largest = max(largest, rho);
    }
    dbl[u_column_at + 2u * x] = count;
    dbl[u_column_at + 2u * x + 1u] = sum;
    atomicMax(table[T_REACH], floatBitsToUint(largest));
}
#endif

#ifdef STEP_SLICES_BLEND
// The slices' composite into OUT, the farthest covering what is left (far_layers.c).
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    float share = layered[i];
    if (!(share > 0.0) || !(sink[u_state_at + 2u * i + 1u] > 0.0))
        return;
    float left = sink[u_state_at + 2u * i];
    for (uint c = 0u; c < u_frame_channels; c++) {
        uint o = i * u_frame_channels + c;
        precise float v = sink[u_acc_at + o] + left * sink[u_last_at + o] - out_px[o];
        out_px[o] += share * v;
    }
}
#endif

// ---- the levels (far_field_gather.c's build_levels) ------------------------------------------

#ifdef STEP_DOWNSAMPLE
// Level u_level from the level before: means of 2 x 2 boxes (the last row or column
// repeated); its marks cleared.
void main()
{
    uint k = u_level, i = global_id();
    uint w = lw(k), h = lh(k);
    if (i >= w * h)
        return;
    uint x = i % w, y = i / w;
    uint sw = lw(k - 1u), sh = lh(k - 1u);
    uint ya = 2u * y, yb = 2u * y + 1u < sh ? 2u * y + 1u : 2u * y;
    uint xa = 2u * x, xb = 2u * x + 1u < sw ? 2u * x + 1u : 2u * x;
    for (uint c = 0u; c < u_channels; c++) {
        precise float s = level_pixel(k - 1u, xa, ya, c) + level_pixel(k - 1u, xb, ya, c) +
                          level_pixel(k - 1u, xa, yb, c) + level_pixel(k - 1u, xb, yb, c);
        lv[image_at(k) + i * u_channels + c] = 0.25 * s;
    }
    lv[needed_at(k) + i] = 0.0;
}
#endif

#ifdef STEP_PREFIX
// Each row's running sums from 0, one invocation a row: the level's rows from its image, or
// (u_in_place) the two edge rows from the means EDGE_ROWS left in place.
void main()
{
    uint k = u_level, j = global_id();
    uint w = lw(k), rows = u_in_place != 0u ? 2u : lh(k);
    if (j >= rows)
        return;
    uint row = u_in_place != 0u ? lh(k) + j : j;
    uint p = prefix_at(k) + row * (w + 1u) * u_channels;
    if (u_seg_first == 0u)
        for (uint c = 0u; c < u_channels; c++) {
            if (u_in_place == 0u)
                lv[p + c] = 0.0;
        }
    uint end = min(u_seg_first + u_seg_count, w);
    for (uint x = u_seg_first; x < end; x++)
        for (uint c = 0u; c < u_channels; c++) {
            float in_value = u_in_place != 0u ? lv[p + (x + 1u) * u_channels + c]
                                              : level_pixel(k, x, row, c);
            lv[p + (x + 1u) * u_channels + c] = lv[p + x * u_channels + c] + in_value;
        }
}
#endif

#if defined(STEP_EDGE_ROWS) || defined(STEP_EDGE_SIDES)
// The mean of `count` level-0 pixels from (x, y), `dx`, `dy` a step, the last repeated past
// `available` (far_field_gather.c's mean_of, its sum in double).
float mean_of(uint x, uint y, uint dx, uint dy, uint count, uint available, uint c)
{
    double sum = 0.0lf;
    for (uint i = 0u; i < count; i++) {
        uint at = i < available ? i : available - 1u;
        sum += double(level_pixel(0u, x + at * dx, y + at * dy, c));
    }
    return float(sum / double(count));
}
#endif

#ifdef STEP_EDGE_ROWS
// Level u_level's continuation above and below the frame: the frame's top and bottom rows
// reduced by 2^k along the row, left in place in the prefix's two edge rows for PREFIX; the
// corners' sides (one invocation an item: 2 x the level's width).
void main()
{
    uint k = u_level, i = global_id();
    uint w = lw(k), h = lh(k), s = 1u << k;
    if (i >= 2u * w)
        return;
    uint bottom = i / w, x = i % w;
    uint y = bottom != 0u ? u_height - 1u : 0u;
    uint x0 = x * s < u_width ? x * s : u_width - 1u;
    uint p = prefix_at(k) + (h + bottom) * (w + 1u) * u_channels;
    for (uint c = 0u; c < u_channels; c++) {
        lv[p + (x + 1u) * u_channels + c] = mean_of(x0, y, 1u, 0u, s, u_width - x0, c);
        if (x == 0u) {
            lv[p + c] = 0.0;
            uint side = sides_at(k) + (h + bottom) * 2u * u_channels;
            lv[side + c] = level_pixel(0u, 0u, y, c);
            lv[side + u_channels + c] = level_pixel(0u, u_width - 1u, y, c);
        }
    }
}
#endif

#ifdef STEP_EDGE_SIDES
// The frame's left and right columns reduced to level u_level's rows (one invocation a row).
void main()
{
    uint k = u_level, y = global_id();
    uint h = lh(k), s = 1u << k;
    if (y >= h)
        return;
    uint y0 = y * s < u_height ? y * s : u_height - 1u;
    uint side = sides_at(k) + y * 2u * u_channels;
    for (uint c = 0u; c < u_channels; c++) {
        lv[side + c] = mean_of(0u, y0, 0u, 1u, s, u_height - y0, c);
        lv[side + u_channels + c] = mean_of(u_width - 1u, y0, 0u, 1u, s, u_height - y0, c);
    }
}
#endif

// ---- the gather (far_field_gather.c) ---------------------------------------------------------

#if defined(STEP_MARK) || defined(STEP_SAMPLES) || defined(STEP_GATHER)
uint level_of(float rho)
{
    float extent = rho * max(1.0, u_aspect);
    uint k = 0u;
    while (k + 1u < u_level_count && extent > FAR_LEVEL_RADIUS * float(1u << k))
        k++;
    return k;
}

float on_level(uint x, float s)
{
    return (float(x) + 0.5) / s - 0.5;
}

// The four samples frame pixel (x, y) interpolates on level k: their indices and weights.
void cell_of(uint k, uint x, uint y, out uint index[4], out float fu, out float fv)
{
    float s = float(1u << k);
    uint w = lw(k), h = lh(k);
    float cu = min(max(on_level(x, s), 0.0), float(w - 1u));
    float cv = min(max(on_level(y, s), 0.0), float(h - 1u));
    uint i0 = uint(cu), j0 = uint(cv);
    uint i1 = i0 + 1u < w ? i0 + 1u : i0, j1 = j0 + 1u < h ? j0 + 1u : j0;
    index[0] = j0 * w + i0;
    index[1] = j0 * w + i1;
    index[2] = j1 * w + i0;
    index[3] = j1 * w + i1;
    fu = cu - float(i0);
    fv = cv - float(j0);
}
#endif

#if defined(STEP_SAMPLES) || defined(STEP_GATHER)
// The integral of level row `row` from the frame's left edge to t, times scale, into sum.
void add_integral(uint k, int row, float t, float scale, inout float sum[FAR_FIELD_MAX_CHANNELS])
{
    uint w = lw(k), h = lh(k);
    uint index = row < 0 ? h : row >= int(h) ? h + 1u : uint(row);
    uint p = prefix_at(k) + index * (w + 1u) * u_channels;
    precise float u = t + 0.5;
    if (u <= 0.0) {
        uint side = sides_at(k) + index * 2u * u_channels;
        for (uint c = 0u; c < u_channels; c++) {
            precise float add = scale * u * lv[side + c];
            sum[c] += add;
        }
    } else if (u >= float(w)) {
        uint side = sides_at(k) + index * 2u * u_channels + u_channels;
        uint end = p + w * u_channels;
        for (uint c = 0u; c < u_channels; c++) {
            precise float add = scale * (lv[end + c] + (u - float(w)) * lv[side + c]);
            sum[c] += add;
        }
    } else {
        uint i = uint(u);
        precise float f = u - float(i);
        uint x0 = p + i * u_channels, x1 = x0 + u_channels;
        for (uint c = 0u; c < u_channels; c++) {
            precise float add = scale * (lv[x0 + c] + f * (lv[x1 + c] - lv[x0 + c]));
            sum[c] += add;
        }
    }
}

float linear_slope(float before, float here, float after, uint left, uint right)
{
    if (left == 0u || right == 0u)
        return left + right != 0u ? (after - before) / float(left + right) : 0.0;
    float a = (here - before) / float(left), b = (after - here) / float(right);
    precise float tolerance = RAMP_TOLERANCE * max(abs(a), abs(b)) + 1e-3;
    if (abs(a - b) > tolerance)
        return 0.0;
    return (after - before) / float(left + right);
}

void radius_gradient(uint x, uint y, out float gx, out float gy)
{
    uint w = u_width, h = u_height;
    float here = radius[y * w + x];
    float reach_px = max(1.0, here);
    uint span = reach_px < float(DDOF_MAX_DIMENSION) ? uint(reach_px) : uint(DDOF_MAX_DIMENSION);
    uint xa = x > span ? x - span : 0u, xb = w - 1u - x > span ? x + span : w - 1u;
    uint ya = y > span ? y - span : 0u, yb = h - 1u - y > span ? y + span : h - 1u;
    gx = linear_slope(radius[y * w + xa], here, radius[y * w + xb], x - xa, xb - x);
    gy = linear_slope(radius[ya * w + x], here, radius[yb * w + x], y - ya, yb - y);
}

// The gather on level k centred at (u0, v0) of radius rho and gradient (gx, gy) into out.
void conic_gather(uint k, float u0, float v0, float rho, float gx, float gy,
                  out float result[FAR_FIELD_MAX_CHANNELS])
{
    float aspect = u_aspect, inv_aspect = 1.0 / aspect;
    float s = float(1u << k);
    precise float shrunk = rho * rho - (s * s - 1.0) / 3.0;
    float radius_k = sqrt(max(shrunk, 0.25 * s * s)) / s;
    float bx = gx;
    precise float bv = gy * aspect;
    precise float g2 = bx * bx + bv * bv;
    if (g2 > GRADIENT_MAX * GRADIENT_MAX) {
        float f = GRADIENT_MAX / sqrt(g2);
        bx *= f;
        bv *= f;
    }
    precise float a = 1.0 - bx * bx;
    float inv_a = 1.0 / a, root_a = sqrt(a);
    precise float q = a - bv * bv;
    precise float top = radius_k * (bv - root_a) / q, bottom = radius_k * (bv + root_a) / q;
    precise float top_row = v0 + top * aspect - 0.5, bottom_row = v0 + bottom * aspect + 0.5;
    int j0 = int(ceil(top_row)), j1 = int(floor(bottom_row));
    float sum[FAR_FIELD_MAX_CHANNELS] = float[FAR_FIELD_MAX_CHANNELS](0.0, 0.0, 0.0, 0.0, 0.0);
    float weights = 0.0;
    int taps = radius_k < TWO_TAPS_BELOW ? 2 : 1;
    float offset = taps == 2 ? GAUSS_POINT : 0.0, share = 1.0 / float(taps);
    int shift = taps - 1;
    int count = (j1 - j0 + 1) * taps;
    float first_row = float(j0);
    for (int t = 0; t < count; t++) {
        float row = first_row + float(t >> shift);
        float side = offset * float(2 * (t & shift) - 1);
        precise float v = (row + side - v0) * inv_aspect;
        precise float b = radius_k + bv * v;
        precise float d = b * b - a * v * v;
        if (b <= 0.0 || d <= 0.0)
            continue;
        float root = sqrt(d);
        precise float lo = (bx * b - root) * inv_a, hi = (bx * b + root) * inv_a;
        precise float tap_weight = share * (a * a) / (b * b);
        int j = j0 + (t >> shift);
        add_integral(k, j, u0 + hi, tap_weight, sum);
        add_integral(k, j, u0 + lo, -tap_weight, sum);
        precise float add = tap_weight * (hi - lo);
        weights += add;
    }
    if (weights <= 0.0) {
        // A disc thinner than a row: its centre's row.
        precise float lo = (bx * radius_k - radius_k) * inv_a;
        precise float hi = (bx * radius_k + radius_k) * inv_a;
        int j = int(floor(v0 + 0.5));
        add_integral(k, j, u0 + hi, 1.0, sum);
        add_integral(k, j, u0 + lo, -1.0, sum);
        weights = hi - lo;
    }
    for (uint c = 0u; c < FAR_FIELD_MAX_CHANNELS; c++)
        result[c] = sum[c] / weights;
}
#endif

#ifdef STEP_MARK
// Marks the samples the frame's pixels interpolate (every pixel writes 1 to its four).
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height || !(weight[i] > 0.0))
        return;
    uint k = level_of(radius[i]);
    if (k == 0u)
        return;
    uint index[4];
    float fu, fv;
    cell_of(k, i % u_width, i / u_width, index, fu, fv);
    for (int corner = 0; corner < 4; corner++)
        lv[needed_at(k) + index[corner]] = 1.0;
}
#endif

#ifdef STEP_SAMPLES
// The gather at level u_level's marked samples, read from the level below.
void main()
{
    uint k = u_level, i = global_id();
    uint w = lw(k);
    if (i >= w * lh(k) || !(lv[needed_at(k) + i] > 0.0))
        return;
    float s = float(1u << k);
    precise float cx = (float(i % w) + 0.5) * s - 0.5;
    precise float cy = (float(i / w) + 0.5) * s - 0.5;
    uint x = uint(min(cx + 0.5, float(u_width - 1u)));
    uint y = uint(min(cy + 0.5, float(u_height - 1u)));
    float gx, gy;
    radius_gradient(x, y, gx, gy);
    precise float rho = radius[y * u_width + x] + gx * (cx - float(x)) + gy * (cy - float(y));
    float f = float(1u << (k - 1u));
    precise float u0 = (cx + 0.5) / f - 0.5, v0 = (cy + 0.5) / f - 0.5;
    float result[FAR_FIELD_MAX_CHANNELS];
    conic_gather(k - 1u, u0, v0, rho, gx, gy, result);
    for (uint c = 0u; c < u_channels; c++)
        lv[samples_at(k) + i * u_channels + c] = result[c];
}
#endif

#ifdef STEP_GATHER
// Each pixel with a share: its gather (level 0, or the samples of its level interpolated),
// blended into OUT by its weight, or (u_sink) composited over the slices before.
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    float w = weight[i];
    if (w <= 0.0)
        return;
    uint x = i % u_width, y = i / u_width;
    float rho = radius[i];
    uint k = level_of(rho);
    float v[FAR_FIELD_MAX_CHANNELS];
    if (k == 0u) {
        float gx, gy;
        radius_gradient(x, y, gx, gy);
        conic_gather(0u, float(x), float(y), rho, gx, gy, v);
    } else {
        uint index[4];
        float fu, fv;
        cell_of(k, x, y, index, fu, fv);
        uint at = samples_at(k);
        for (uint c = 0u; c < u_channels; c++) {
            float s00 = lv[at + index[0] * u_channels + c];
            float s01 = lv[at + index[1] * u_channels + c];
            float s10 = lv[at + index[2] * u_channels + c];
            float s11 = lv[at + index[3] * u_channels + c];
            precise float top = s00 + fu * (s01 - s00);
            precise float bottom = s10 + fu * (s11 - s10);
            precise float value = top + fv * (bottom - top);
            v[c] = value;
        }
    }
    if (u_sink != 0u) {
        // far_layer_sink.h's ddof_far_layer_take
        uint channels = u_frame_channels;
        float cover = min(v[channels], 1.0);
        if (!(cover > TINY))
            return;
        uint st = u_state_at + 2u * i;
        float left = 1.0 - sink[st + 1u];
        float covers = left > TINY ? min(cover / left, 1.0) : 1.0;
        float held = sink[st];
        for (uint c = 0u; c < channels; c++) {
            float last = v[c] / cover;
            sink[u_last_at + i * channels + c] = last;
            precise float add = held * covers * last;
            sink[u_acc_at + i * channels + c] += add;
        }
        sink[st] = held * (1.0 - covers);
        sink[st + 1u] += cover;
        return;
    }
    for (uint c = 0u; c < u_frame_channels; c++) {
        uint o = i * u_frame_channels + c;
        precise float add = w * (v[c] - out_px[o]);
        out_px[o] += add;
    }
}
#endif
