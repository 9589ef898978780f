/* SPDX-License-Identifier: MIT */
// highlights_find.comp - finding the highlights on the device (../highlights_find.c), one
// program per step (the define names it), so that a GL frame's colour is never read on the
// host: each row chunk's class counts and disc costs (double, in the CPU's order), their
// totals per class (the host reads these 128 pairs and applies the budget with the CPU's rule,
// ddof_highlight_rules.h), each chunk's first item, the items in row order; for the frame the
// parts sharp occluders hide (each item's runs marked, the marked pixels numbered in row
// order, each one's entries gathered in the CPU's order and merged in double, the budget left
// spent in row order, the two lists merged by row); then every item sorted into its size
// class for the drawing (highlights.comp), and each class's reach and box. The brightness and
// size classes come from tables of the CPU's class bounds (the device's log2 is not the
// host's, so the host finds where each class starts). A step that walks a line runs
// u_seg_count of its steps from u_seg_first per dispatch (llvmpipe's loop limit).
layout(local_size_x = 64) in;

struct Highlight {
    uint x;
    uint y;
    float coc;
    float e0;
    float e1;
    float e2;
    uint hidden;
};

layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; };
layout(std430, binding = 1) readonly buffer ColorIn { float color_in[]; };
layout(std430, binding = 2) buffer Counts { uint counts[]; };   // see the layout below
layout(std430, binding = 3) buffer Costs { double costs[]; };
layout(std430, binding = 4) buffer Found { Highlight found[]; }; // the items, row order
layout(std430, binding = 5) buffer Pixels { uint pixels[]; };   // marks, then numbers
layout(std430, binding = 6) buffer Scan { uint scan[]; };       // block sums
layout(std430, binding = 7) buffer Merged { Highlight merged[]; }; // hidden parts, row order
layout(std430, binding = 8) buffer Kept { Highlight kept_hidden[]; };
layout(std430, binding = 9) buffer All { Highlight all_items[]; };
layout(std430, binding = 10) buffer Sorted { Highlight sorted[]; };
layout(std430, binding = 11) buffer Classes { int classes[]; }; // 8 a class, then blocks'
layout(std430, binding = 12) readonly buffer Bounds {
    float bright_bound[128]; // the least brightness of class k (k >= 1)
    float size_bound[32];    // the least |CoC| of size class k (k >= 1)
    float landing_of[32];    // the landing threshold of each size class
};

uniform uint u_width;
uniform uint u_height;
uniform uint u_color_base;
uniform uint u_color_stride;
uniform uint u_color_step;
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_owner;      // 0: an element, premultiplied; 1: the frame; 2: a straight element
uniform uint u_coc_signed;
uniform float u_threshold; // the user's
uniform float u_kept;      // the threshold of the first class kept
uniform uint u_first;      // the first class kept
uniform uint u_area;       // 1: a highlight costs its area (an aperture image)
uniform float u_aspect;
uniform uint u_chunks;
uniform uint u_count;      // the step's items
uniform uint u_other;      // the merge's other list's count
uniform uint u_seg_first;
uniform uint u_seg_count;
uniform dvec4 u_money;     // the budget, the cost kept so far

// Counts: [chunk * 128 + k] each chunk's counts, then at TOTALS the totals, at OFFSETS each
// chunk's first item, at CURSORS each chunk's items written, at SCALARS a few words.
#define CLASSES DDOF_HIGHLIGHT_CLASSES
#define TOTALS (u_chunks * uint(CLASSES))
#define OFFSETS (TOTALS + uint(CLASSES))
#define CURSORS (OFFSETS + u_chunks)
#define SCALARS (CURSORS + u_chunks)
// scalars: 0 the offsets' running count, 1 the entries, 2 the hidden parts kept, 3 the
// scan's running sum, 4 the longest run with entries
#define BLOCK 1024u

float infinity()
{
    return uintBitsToFloat(0x7f800000u);
}

bool inside(int x, int y)
{
    return x >= 0 && y >= 0 && x < int(u_width) && y < int(u_height);
}

float coc_at(int x, int y)
{
    return coc_in[u_coc_base + uint(y) * u_coc_stride + uint(x) * u_coc_step];
}

vec4 raw_at(int x, int y)
{
    uint p = u_color_base + uint(y) * u_color_stride + uint(x) * u_color_step;
    return vec4(color_in[p], color_in[p + 1u], color_in[p + 2u],
                u_color_step >= 4u ? color_in[p + 3u] : 1.0);
}

// highlights_find.c's seen: the frame's pixel as it is, an element's as its steps
// premultiply it (highlights.h's ddof_element_pixel).
vec3 seen_at(int x, int y)
{
    vec4 px = raw_at(x, y);
    if (u_owner == 1u)
        return px.rgb;
    float alpha = min(1.0, max(0.0, px.a));
    float scale = u_owner == 0u ? 1.0 : alpha;
    precise vec3 v = px.rgb * scale;
    return alpha > 0.0 ? v : vec3(0.0);
}

float brightness(vec3 c)
{
    return max(c.r, max(c.g, c.b));
}

// highlight_coc: the CoC of the brightest pixel of the 3 x 3 neighbourhood (itself on a tie),
// of the colour as it lies.
float highlight_coc(int x, int y)
{
    int x0 = max(x - 1, 0), x1 = min(x + 1, int(u_width) - 1);
    int y0 = max(y - 1, 0), y1 = min(y + 1, int(u_height) - 1);
    int bx = x, by = y;
    float best = brightness(raw_at(x, y).rgb);
    for (int v = y0; v <= y1; v++)
        for (int u = x0; u <= x1; u++) {
            float l = brightness(raw_at(u, v).rgb);
            if (l > best) {
                best = l;
                bx = u;
                by = v;
            }
        }
    return coc_at(bx, by);
}

// ddof_highlight_brightness_class, from the table of its bounds.
int brightness_class(float l)
{
    int lo = 0, hi = CLASSES - 1; // the class: the last k with bright_bound[k] <= l
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (l >= bright_bound[mid])
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

// ddof_highlight_size_class, from the table.
int size_class(float coc)
{
    if (u_coc_signed != 0u && coc < 0.0)
        return DDOF_HIGHLIGHT_SIZE_CLASSES;
    float a = abs(coc);
    int k = 0;
    while (k + 1 < DDOF_HIGHLIGHT_SIZE_CLASSES && a >= size_bound[k + 1])
        k++;
    return k;
}

// highlight_class: -1 when (x, y) is no highlight; else its class, and its light's CoC.
int highlight_class(int x, int y, vec3 px, out float coc)
{
    coc = 0.0;
    float l = brightness(px);
    if (!(l > u_threshold && abs(coc_at(x, y)) >= DDOF_HIGHLIGHT_MIN_COC_PX))
        return -1;
    coc = highlight_coc(x, y);
    if (!(abs(coc) >= DDOF_HIGHLIGHT_MIN_COC_PX))
        return -1;
    return brightness_class(l);
}

// ddof_highlight_disc_cost
double disc_cost(float coc)
{
    precise double r = 0.5LF * double(abs(coc)) + 0.5LF;
    precise double c;
    if (u_area != 0u)
        c = 2.0LF * (2.0LF * r + 1.0LF) * (2.0LF * r * double(u_aspect) + 1.0LF);
    else
        c = 2.0LF * r * double(u_aspect) + 1.0LF + 4.0LF * 3.14159265358979LF * r;
    return c;
}

// The excess of a kept pixel of colour px: the part above the kept threshold, hue kept.
vec3 excess_of(vec3 px)
{
    float keep = u_kept / brightness(px);
    precise vec3 e = px * (1.0 - keep);
    return e;
}

uint chunk_rows(uint c)
{
    return min(DDOF_ROWS_PER_CHUNK, u_height - c * DDOF_ROWS_PER_CHUNK);
}

#ifdef STEP_COUNT
// Chunk c's counts and costs per class, its pixels in row order, u_seg_count a dispatch.
void main()
{
    uint c = global_id();
    if (c >= u_chunks)
        return;
    if (u_seg_first == 0u)
        for (uint k = 0u; k < uint(CLASSES); k++) {
            counts[c * uint(CLASSES) + k] = 0u;
            costs[c * uint(CLASSES) + k] = 0.0LF;
        }
    uint pixels = chunk_rows(c) * u_width;
    uint end = min(u_seg_first + u_seg_count, pixels);
    for (uint i = u_seg_first; i < end; i++) {
        int x = int(i % u_width), y = int(c * DDOF_ROWS_PER_CHUNK + i / u_width);
        float coc;
        int k = highlight_class(x, y, seen_at(x, y), coc);
        if (k < 0)
            continue;
        counts[c * uint(CLASSES) + uint(k)]++;
        precise double sum = costs[c * uint(CLASSES) + uint(k)] + disc_cost(coc);
        costs[c * uint(CLASSES) + uint(k)] = sum;
    }
}
#endif

#ifdef STEP_TOTALS
// Class k's total over the chunks, in the chunks' order.
void main()
{
    uint k = global_id();
    if (k >= uint(CLASSES))
        return;
    uint n = 0u;
    precise double cost = 0.0LF;
    for (uint c = 0u; c < u_chunks; c++) {
        n += counts[c * uint(CLASSES) + k];
        cost = cost + costs[c * uint(CLASSES) + k];
    }
    counts[TOTALS + k] = n;
    costs[TOTALS + k] = cost;
}
#endif

#ifdef STEP_OFFSETS
// Each chunk's first item: the kept classes' counts of the chunks before it (one invocation,
// u_seg_count chunks a dispatch).
void main()
{
    if (global_id() != 0u)
        return;
    uint at = u_seg_first == 0u ? 0u : counts[SCALARS];
    if (u_seg_first == 0u)
        for (uint s = 1u; s < 8u; s++)
            counts[SCALARS + s] = 0u;
    uint end = min(u_seg_first + u_seg_count, u_chunks);
    for (uint c = u_seg_first; c < end; c++) {
        counts[OFFSETS + c] = at;
        counts[CURSORS + c] = at;
        for (uint k = u_first; k < uint(CLASSES); k++)
            at += counts[c * uint(CLASSES) + k];
    }
    counts[SCALARS] = at;
}
#endif

#ifdef STEP_FILL
// Chunk c's items in row order, from its first.
void main()
{
    uint c = global_id();
    if (c >= u_chunks)
        return;
    uint pixels = chunk_rows(c) * u_width;
    uint end = min(u_seg_first + u_seg_count, pixels);
    uint at = counts[CURSORS + c];
    for (uint i = u_seg_first; i < end; i++) {
        int x = int(i % u_width), y = int(c * DDOF_ROWS_PER_CHUNK + i / u_width);
        float coc;
        vec3 px = seen_at(x, y);
        int k = highlight_class(x, y, px, coc);
        if (k < int(u_first))
            continue;
        vec3 e = excess_of(px);
        found[at] = Highlight(uint(x), uint(y), coc, e.r, e.g, e.b, 0u);
        at++;
    }
    counts[CURSORS + c] = at;
}
#endif

// ---- the parts hidden by sharp occluders (the frame's) ---------------------------------------

const ivec2 hidden_step[8] = ivec2[8](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(-1, 1),
                                      ivec2(-1, 0), ivec2(0, -1), ivec2(-1, -1), ivec2(1, -1));

bool is_sharp(int x, int y)
{
    return abs(coc_at(x, y)) < DDOF_HIGHLIGHT_SHARP_PX;
}

// kept_highlight: whether (x, y) is a kept far highlight, with its excess and CoC.
bool kept_highlight(int x, int y, out vec3 e, out float coc)
{
    e = vec3(0.0);
    vec3 px = raw_at(x, y).rgb;
    int k = highlight_class(x, y, px, coc);
    if (k < int(u_first) || (u_coc_signed != 0u && coc < 0.0))
        return false;
    e = excess_of(px);
    return true;
}

bool lands(float threshold, int x, int y)
{
    float c = coc_at(x, y);
    return (u_coc_signed != 0u ? c : abs(c)) >= threshold;
}

int visible_width(ivec2 h, int d, int limit)
{
    int x = h.x, y = h.y, m = 1;
    for (; m < limit; m++) {
        x += hidden_step[d].x;
        y += hidden_step[d].y;
        vec3 e;
        float coc;
        if (!inside(x, y) || !kept_highlight(x, y, e, coc))
            break;
    }
    return m;
}

// hidden_run: the run of sharp pixels from highlight h (at hp, of CoC hcoc) in direction d.
int hidden_run(ivec2 hp, float hcoc, int d, out vec3 end_e, out float end_coc, out int ramp)
{
    end_e = vec3(0.0);
    end_coc = hcoc;
    ramp = 0;
    if (u_coc_signed != 0u && hcoc < 0.0)
        return 0;
    float radius = 0.5 * abs(hcoc);
    int limit = radius < float(DDOF_MAX_DIMENSION) ? int(radius) : int(DDOF_MAX_DIMENSION);
    float landing = landing_of[size_class(hcoc)];
    int x = hp.x, y = hp.y, n = 0;
    for (;;) {
        x += hidden_step[d].x;
        y += hidden_step[d].y;
        if (!inside(x, y))
            return 0;
        if (!is_sharp(x, y))
            break;
        if (++n > limit)
            return 0;
    }
    if (n == 0 || !lands(landing, x, y))
        return 0;
    if (kept_highlight(x, y, end_e, end_coc)) {
        if (d >= 4)
            return 0;
    } else {
        if (hidden_step[d].x != 0 && hidden_step[d].y != 0)
            return 0;
        end_e = vec3(0.0);
        end_coc = hcoc;
        ramp = visible_width(hp, (d + 4) % 8, n) + 1;
        return n;
    }
    ramp = n + 1;
    return n;
}

#ifdef STEP_MARK
// Each item's hidden runs: their pixels marked, their entries counted.
void main()
{
    uint i = global_id();
    if (i >= u_count)
        return;
    Highlight h = found[i];
    ivec2 hp = ivec2(int(h.x), int(h.y));
    uint entries = 0u;
    for (int d = 0; d < 8; d++) {
        vec3 e;
        float coc;
        int ramp;
        int run = hidden_run(hp, h.coc, d, e, coc, ramp);
        int n = min(run, ramp - 1);
        for (int k = 1; k <= n; k++) {
            ivec2 p = hp + k * hidden_step[d];
            atomicAdd(pixels[uint(p.y) * u_width + uint(p.x)], 1u);
        }
        entries += uint(max(n, 0));
        if (n > 0)
            atomicMax(counts[SCALARS + 4u], uint(n));
    }
    if (entries != 0u)
        atomicAdd(counts[SCALARS + 1u], entries);
}
#endif

#ifdef STEP_CLEAR
void main()
{
    uint p = global_id();
    if (p < u_width * u_height)
        pixels[p] = 0u;
}
#endif

// ---- numbering flagged elements in order (a scan) --------------------------------------------

#ifdef STEP_SCAN_BLOCKS
// Block b's flagged pixels (marked: pixels[p] != 0).
void main()
{
    uint b = global_id();
    uint n = u_width * u_height;
    if (b * BLOCK >= n)
        return;
    uint sum = 0u;
    for (uint p = b * BLOCK; p < min(n, (b + 1u) * BLOCK); p++)
        sum += pixels[p] != 0u ? 1u : 0u;
    scan[b] = sum;
}
#endif

#ifdef STEP_SCAN_TOP
// The blocks' running sums (one invocation, u_seg_count blocks a dispatch).
void main()
{
    if (global_id() != 0u)
        return;
    uint blocks = (u_width * u_height + BLOCK - 1u) / BLOCK;
    uint at = u_seg_first == 0u ? 0u : counts[SCALARS + 3u];
    for (uint b = u_seg_first; b < min(u_seg_first + u_seg_count, blocks); b++) {
        uint sum = scan[b];
        scan[b] = at;
        at += sum;
    }
    counts[SCALARS + 3u] = at;
}
#endif

#ifdef STEP_SCAN_NUMBER
// Each marked pixel's number in row order, plus 1 (0: not marked).
void main()
{
    uint b = global_id();
    uint n = u_width * u_height;
    if (b * BLOCK >= n)
        return;
    uint at = scan[b];
    for (uint p = b * BLOCK; p < min(n, (b + 1u) * BLOCK); p++)
        if (pixels[p] != 0u)
            pixels[p] = ++at;
}
#endif

#ifdef STEP_GATHER
// Each marked pixel's entries, found by walking back from it in the 8 directions to the item
// whose run covers it, merged in the CPU's order (by item, then direction) in double.
void main()
{
    uint p = global_id();
    if (p >= u_width * u_height || pixels[p] == 0u)
        return;
    ivec2 at = ivec2(int(p % u_width), int(p / u_width));
    uint keys[8];
    float ew[8], ecoc[8];
    vec3 eex[8];
    int n = 0;
    for (int d = 0; d < 8; d++) {
        ivec2 q = at - hidden_step[d];
        int k = 1;
        while (inside(q.x, q.y) && is_sharp(q.x, q.y) && k <= int(counts[SCALARS + 4u])) {
            q -= hidden_step[d];
            k++;
        }
        vec3 he;
        float hcoc;
        if (!inside(q.x, q.y) || !kept_highlight(q.x, q.y, he, hcoc))
            continue;
        vec3 e;
        float coc;
        int ramp;
        int run = hidden_run(q, hcoc, d, e, coc, ramp);
        if (k > min(run, ramp - 1))
            continue;
        precise float length = float(run + 1) *
                               (hidden_step[d].x != 0 && hidden_step[d].y != 0 ? 1.41421356
                                                                                 : 1.0);
        precise float w = 1.0 / (length * length);
        precise float t = float(k) / float(ramp);
        precise float c = w * (hcoc + (coc - hcoc) * t);
        precise vec3 ex = w * (he + (e - he) * t);
        uint key = (uint(q.y) * u_width + uint(q.x)) * 8u + uint(d);
        int j = n++;
        while (j > 0 && keys[j - 1] > key) {
            keys[j] = keys[j - 1];
            ew[j] = ew[j - 1];
            ecoc[j] = ecoc[j - 1];
            eex[j] = eex[j - 1];
            j--;
        }
        keys[j] = key;
        ew[j] = w;
        ecoc[j] = c;
        eex[j] = ex;
    }
    precise double w = 0.0LF, coc = 0.0LF, e0 = 0.0LF, e1 = 0.0LF, e2 = 0.0LF;
    for (int j = 0; j < n; j++) {
        w = w + double(ew[j]);
        coc = coc + double(ecoc[j]);
        e0 = e0 + double(eex[j].r);
        e1 = e1 + double(eex[j].g);
        e2 = e2 + double(eex[j].b);
    }
    merged[pixels[p] - 1u] = Highlight(uint(at.x), uint(at.y), float(coc / w), float(e0 / w),
                                       float(e1 / w), float(e2 / w), 1u);
}
#endif

#ifdef STEP_SPEND
// The merged parts in row order, each kept while the budget left allows (one invocation,
// u_seg_count a dispatch).
void main()
{
    if (global_id() != 0u)
        return;
    precise double cost = u_seg_first == 0u ? u_money.y : costs[TOTALS + uint(CLASSES)];
    uint n = u_seg_first == 0u ? 0u : counts[SCALARS + 2u];
    for (uint j = u_seg_first; j < min(u_seg_first + u_seg_count, u_count); j++) {
        double c = disc_cost(merged[j].coc);
        precise double next = cost + c;
        if (next <= u_money.x) {
            cost = next;
            kept_hidden[n++] = merged[j];
        }
    }
    costs[TOTALS + uint(CLASSES)] = cost;
    counts[SCALARS + 2u] = n;
}
#endif

uint key_of(Highlight h)
{
    return h.y * u_width + h.x;
}

#ifdef STEP_MERGE
// The visible items (found, u_count) and the kept hidden parts (u_other), both in row order and
// never on one pixel, merged by row: each goes after the other list's items before it.
void main()
{
    uint i = global_id();
    if (i >= u_count + u_other)
        return;
    bool visible = i < u_count;
    Highlight h = visible ? found[i] : kept_hidden[i - u_count];
    uint key = key_of(h);
    uint lo = 0u, hi = visible ? u_other : u_count;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        uint other = visible ? key_of(kept_hidden[mid]) : key_of(found[mid]);
        if (other < key)
            lo = mid + 1u;
        else
            hi = mid;
    }
    all_items[(visible ? i : i - u_count) + lo] = h;
}
#endif

// ---- the drawing's order: by size class, row order kept --------------------------------------

#define SIZE_CLASSES (DDOF_HIGHLIGHT_SIZE_CLASSES + 1)
// classes: [k * 8] count, first, reach_rows, reach_x, bx0, bx1, by0, by1; then from
// BLOCK_COUNTS each block's count per class, turned into its first per class.
#define BLOCK_COUNTS (SIZE_CLASSES * 8)
#define SORT_BLOCK 256u

#ifdef STEP_SORT_COUNT
void main()
{
    uint b = global_id();
    if (b * SORT_BLOCK >= u_count)
        return;
    int n[SIZE_CLASSES];
    for (int k = 0; k < SIZE_CLASSES; k++)
        n[k] = 0;
    for (uint i = b * SORT_BLOCK; i < min(u_count, (b + 1u) * SORT_BLOCK); i++)
        n[size_class(all_items[i].coc)]++;
    for (int k = 0; k < SIZE_CLASSES; k++)
        classes[BLOCK_COUNTS + int(b) * SIZE_CLASSES + k] = n[k];
}
#endif

#ifdef STEP_SORT_TOP
// Class k's count and each block's first item within the class (an invocation a class).
void main()
{
    int k = int(global_id());
    if (k >= SIZE_CLASSES)
        return;
    uint blocks = (u_count + SORT_BLOCK - 1u) / SORT_BLOCK;
    int at = 0;
    for (uint b = 0u; b < blocks; b++) {
        int n = classes[BLOCK_COUNTS + int(b) * SIZE_CLASSES + k];
        classes[BLOCK_COUNTS + int(b) * SIZE_CLASSES + k] = at;
        at += n;
    }
    classes[k * 8] = at;
    classes[k * 8 + 2] = 0;
    classes[k * 8 + 3] = 0;
    classes[k * 8 + 4] = 2147483647;
    classes[k * 8 + 5] = -2147483647 - 1;
    classes[k * 8 + 6] = 2147483647;
    classes[k * 8 + 7] = -2147483647 - 1;
}
#endif

#ifdef STEP_SORT_FIRST
// Each class's first item (one invocation).
void main()
{
    if (global_id() != 0u)
        return;
    int at = 0;
    for (int k = 0; k < SIZE_CLASSES; k++) {
        classes[k * 8 + 1] = at;
        at += classes[k * 8];
    }
}
#endif

#ifdef STEP_SORT_PLACE
void main()
{
    uint b = global_id();
    if (b * SORT_BLOCK >= u_count)
        return;
    for (uint i = b * SORT_BLOCK; i < min(u_count, (b + 1u) * SORT_BLOCK); i++) {
        Highlight h = all_items[i];
        int k = size_class(h.coc);
        int at = classes[k * 8 + 1] + classes[BLOCK_COUNTS + int(b) * SIZE_CLASSES + k]++;
        sorted[at] = h;
    }
}
#endif

#ifdef STEP_SORT_BOXES
// Each class's largest half height and half width, and the box its shapes cover
// (gl_highlights.c's prepare: ddof_highlight_rules.h's reaches).
void main()
{
    uint i = global_id();
    if (i >= u_count)
        return;
    Highlight h = sorted[i];
    int k = size_class(h.coc);
    float radius = 0.5 * abs(h.coc);
    float margin = u_aspect >= 1.0 ? 0.5 : 0.5 / u_aspect;
    precise float rows = (radius + margin) * u_aspect;
    int reach = int(ceil(rows));
    precise float columns = radius + 0.5;
    int reach_x = int(ceil(columns)) + 1;
    atomicMax(classes[k * 8 + 2], reach);
    atomicMax(classes[k * 8 + 3], reach_x);
    atomicMin(classes[k * 8 + 4], int(h.x) - reach_x);
    atomicMax(classes[k * 8 + 5], int(h.x) + reach_x + 1);
    atomicMin(classes[k * 8 + 6], int(h.y) - reach);
    atomicMax(classes[k * 8 + 7], int(h.y) + reach + 1);
}
#endif
