/* SPDX-License-Identifier: MIT */
// highlights.comp - the highlight pass on the device: the highlights taken out of the colour
// (../highlights_find.c's base) and drawn into the result (../highlights_draw.c with
// ../aperture.c's shapes), one program per step (the define names it), in the CPU's arithmetic
// and order: `precise` where the CPU rounds a product and a sum apart, its double sums in
// double, each row's differences added in the CPU's order of highlights. gl_highlights.c sorts
// the highlights into their size classes on the host (they are a list, not an image) and runs
// each class: its landing counts, its weights, its differences, their running sums. A step
// that walks a line runs u_seg_count of its steps from u_seg_first per dispatch (llvmpipe ends
// a shader's loops silently after 65,535 iterations). Constants: ddof_highlight_rules.h.
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
layout(std430, binding = 2) buffer Out { float out_px[]; };
layout(std430, binding = 3) buffer Base { float base[]; };
layout(std430, binding = 4) readonly buffer Items { Highlight items[]; }; // by class, then row
layout(std430, binding = 5) readonly buffer Shape { // ddof_highlight_rules.h's ddof_highlight_shape
    double catseye;           // 0: no cat's eye
    double centre_x;
    double centre_y;
    double inv_half_width;
    double inv_half_height;
    float aspect;             // rows per unit of the shape's y
    float apothem;
    uint sides;               // 0: a disc (or the image)
    uint image_width;         // 0: no aperture image
    uint image_height;
    float normal[32];         // the polygon's edge normals, x and y
};
layout(std430, binding = 6) readonly buffer Sums { double sums[]; };  // the image's table
layout(std430, binding = 7) buffer Landing { uint landing[]; };
layout(std430, binding = 8) buffer Weights { float weights[]; };
layout(std430, binding = 9) buffer Diff { float diff[]; };
layout(std430, binding = 10) buffer State { double state[]; };       // running double sums

uniform uint u_width;
uniform uint u_height;
uniform uint u_channels;
uniform uint u_coc_base;
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_color_base;
uniform uint u_color_stride;
uniform uint u_count;       // the highlights (take-out), or the class's
uniform uint u_first;       // the class's first highlight
uniform uint u_coc_signed;
uniform float u_threshold;  // the class's landing threshold
uniform int u_reach_rows;   // the class's largest half height
uniform int u_bx0;          // the class's box [bx0, bx1) x [by0, by1)
uniform int u_bx1;
uniform int u_by0;
uniform int u_by1;
uniform uint u_seg_first;
uniform uint u_seg_count;

#define INT_MIN (-2147483647 - 1)
#define FLT_MAX 3.402823466e+38

float infinity()
{
    return uintBitsToFloat(0x7f800000u);
}

float radius_of(Highlight h)
{
    return 0.5 * abs(h.coc);
}

float coc_at(int x, int y)
{
    return coc_in[u_coc_base + uint(y) * u_coc_stride + uint(x) * u_coc_step];
}

// highlights_classes.h's lands
bool lands(int x, int y)
{
    float c = coc_at(x, y);
    return (u_coc_signed != 0u ? c : abs(c)) >= u_threshold;
}

// ---- the aperture (aperture.c) ---------------------------------------------------------------

struct Row {
    int inner_l, inner_r, outer_l, outer_r;
    float v, v2;
    bool clipped;
    float clip_x, clip_y;
};

float rim_margin()
{
    return aspect >= 1.0 ? 0.5 : 0.5 / aspect;
}

int half_height(Highlight h)
{
    precise float reach = (radius_of(h) + rim_margin()) * aspect;
    return int(ceil(reach));
}

vec2 normal_of(uint k)
{
    return vec2(normal[2u * k], normal[2u * k + 1u]);
}

float polygon_distance(Highlight h, float dx, float v, bool pixels)
{
    float sign_ = h.coc < 0.0 ? -1.0 : 1.0;
    float px = sign_ * dx, py = -sign_ * v;
    float far_ = -infinity();
    uint edge = 0u;
    for (uint k = 0u; k < sides; k++) {
        vec2 n = normal_of(k);
        precise float d = px * n.x + py * n.y;
        if (d > far_) {
            far_ = d;
            edge = k;
        }
    }
    precise float units = far_ - apothem * radius_of(h);
    if (!pixels)
        return units;
    vec2 n = normal_of(edge);
    float ny = n.y / aspect;
    precise float length2 = n.x * n.x + ny * ny;
    return units / sqrt(length2);
}

void polygon_span(Highlight h, float v, float t, out float lo, out float hi)
{
    float sign_ = h.coc < 0.0 ? -1.0 : 1.0;
    precise float limit = apothem * radius_of(h) + t;
    lo = -infinity();
    hi = infinity();
    for (uint k = 0u; k < sides; k++) {
        vec2 n = normal_of(k);
        float c = sign_ * n.x;
        precise float e = limit + sign_ * v * n.y;
        if (c > 1e-6)
            hi = min(hi, e / c);
        else if (c < -1e-6)
            lo = max(lo, e / c);
        else if (e < 0.0)
            lo = infinity();
    }
}

bool clip_offset(Highlight h, out float x, out float y)
{
    x = 0.0;
    y = 0.0;
    if (catseye <= 0.0lf)
        return false;
    double px = double(h.x) + 0.5lf - centre_x, py = double(h.y) + 0.5lf - centre_y;
    double a = px * inv_half_width, b = py * inv_half_height;
    precise double spread = a * a + b * b;
    double reach = sqrt(0.5lf * spread);
    double ux = -px, uy = -py / double(aspect);
    precise double length2 = ux * ux + uy * uy;
    double len = sqrt(length2);
    if (!(len > 0.0lf))
        return false;
    double shift = catseye * min(reach, 1.0lf) * double(radius_of(h)) / len;
    x = float(ux * shift);
    y = float(uy * shift);
    return true;
}

bool clip_row(Highlight h, float margin, inout Row row)
{
    float dv = row.v - row.clip_y, dv2 = dv * dv;
    float outer_r = radius_of(h) + margin, inner_r = radius_of(h) - margin;
    if (dv2 >= outer_r * outer_r)
        return false;
    precise float room = outer_r * outer_r - dv2;
    float reach = sqrt(room);
    int lo = int(floor(row.clip_x - reach)), hi = int(ceil(row.clip_x + reach));
    row.outer_l = row.outer_l > lo ? row.outer_l : lo;
    row.outer_r = row.outer_r < hi ? row.outer_r : hi;
    if (row.outer_l > row.outer_r)
        return false;
    if (row.inner_l <= row.inner_r && inner_r > 0.0 && dv2 <= inner_r * inner_r) {
        precise float inner_room = inner_r * inner_r - dv2;
        float in_ = sqrt(inner_room);
        int a = int(ceil(row.clip_x - in_)), b = int(floor(row.clip_x + in_));
        row.inner_l = row.inner_l > a ? row.inner_l : a;
        row.inner_r = row.inner_r < b ? row.inner_r : b;
    } else {
        row.inner_l = 1;
        row.inner_r = -1;
    }
    if (row.inner_l > row.inner_r) {
        int c = (row.outer_l + row.outer_r) / 2;
        row.inner_l = c + 1;
        row.inner_r = c - 1;
    }
    return true;
}

bool shape_row_at(Highlight h, int dy, out Row row)
{
    row = Row(0, 0, 0, 0, 0.0, 0.0, false, 0.0, 0.0);
    float margin = rim_margin();
    float outer_r = radius_of(h) + margin, inner_r = outer_r - 2.0 * margin;
    float v = float(dy) / aspect, v2 = v * v;
    if (v2 >= outer_r * outer_r)
        return false;
    row.v = v;
    row.v2 = v2;
    int reach = int(ceil(radius_of(h) + 0.5));
    if (image_width > 0u) {
        row.outer_l = -reach;
        row.outer_r = reach;
        row.inner_l = 1;
        row.inner_r = -1;
        return true;
    }
    if (sides == 0u) {
        precise float room = outer_r * outer_r - v2;
        int outer = int(ceil(sqrt(room)));
        outer = outer > reach ? reach : outer;
        int inner = -1;
        if (inner_r > 0.0 && v2 <= inner_r * inner_r) {
            precise float inner_room = inner_r * inner_r - v2;
            inner = int(floor(sqrt(inner_room)));
        }
        row.outer_l = -outer;
        row.outer_r = outer;
        row.inner_l = inner >= 0 ? -inner : 1;
        row.inner_r = inner >= 0 ? inner : -1;
        return true;
    }
    float lo, hi, in_lo, in_hi;
    polygon_span(h, v, margin, lo, hi);
    if (!(lo < hi))
        return false;
    row.outer_l = lo < float(-reach) ? -reach : int(floor(lo));
    row.outer_r = hi > float(reach) ? reach : int(ceil(hi));
    polygon_span(h, v, -margin, in_lo, in_hi);
    if (in_lo <= in_hi && ceil(in_lo) <= floor(in_hi)) {
        row.inner_l = int(ceil(in_lo));
        row.inner_r = int(floor(in_hi));
    } else {
        precise float mid = 0.5 * (lo + hi);
        int middle = int(roundEven(mid));
        int c = middle < row.outer_l ? row.outer_l : middle > row.outer_r ? row.outer_r : middle;
        row.inner_l = c + 1;
        row.inner_r = c - 1;
    }
    return true;
}

bool row_at(Highlight h, int dy, out Row row)
{
    if (!shape_row_at(h, dy, row))
        return false;
    row.clipped = clip_offset(h, row.clip_x, row.clip_y);
    return !row.clipped || clip_row(h, rim_margin(), row);
}

float circle_weight(float r, float u, float v)
{
    precise float u2 = u * u, v2 = v * v;
    float d = sqrt(u2 + v2);
    if (aspect == 1.0) {
        precise float w = r + 0.5 - d;
        return w;
    }
    precise float g2 = u2 + v2 / (aspect * aspect);
    float grad = d > 0.0 ? sqrt(g2) / d : 1.0;
    precise float w = 0.5 - (d - r) / grad;
    return w;
}

double image_integral(double x, double y)
{
    uint w = image_width, h = image_height;
    x = x < 0.0lf ? 0.0lf : x > double(w) ? double(w) : x;
    y = y < 0.0lf ? 0.0lf : y > double(h) ? double(h) : y;
    uint i = uint(x), j = uint(y);
    i = i >= w ? w - 1u : i;
    j = j >= h ? h - 1u : j;
    double fx = x - double(i), fy = y - double(j);
    uint s00 = j * (w + 1u) + i, s01 = s00 + (w + 1u);
    precise double top = (1.0lf - fx) * sums[s00] + fx * sums[s00 + 1u];
    precise double bottom = (1.0lf - fx) * sums[s01] + fx * sums[s01 + 1u];
    precise double value = (1.0lf - fy) * top + fy * bottom;
    return value;
}

float image_weight(Highlight h, Row row, int dx)
{
    double r = double(radius_of(h)), half_v = 0.5lf / double(aspect);
    double sx = double(image_width) / (2.0lf * r), sy = double(image_height) / (2.0lf * r);
    precise double x0 = (double(dx) - 0.5lf + r) * sx, x1 = (double(dx) + 0.5lf + r) * sx;
    precise double y0 = (double(row.v) - half_v + r) * sy, y1 = (double(row.v) + half_v + r) * sy;
    if (h.coc < 0.0) {
        double fx0 = double(image_width) - x1, fy0 = double(image_height) - y1;
        x1 = double(image_width) - x0;
        y1 = double(image_height) - y0;
        x0 = fx0;
        y0 = fy0;
    }
    precise double sum = image_integral(x1, y1) - image_integral(x0, y1) -
                         image_integral(x1, y0) + image_integral(x0, y0);
    precise double area = (x1 - x0) * (y1 - y0);
    return float(sum / area);
}

float rim_weight(Highlight h, Row row, int dx)
{
    float w;
    if (image_width > 0u)
        w = image_weight(h, row, dx);
    else if (sides > 0u)
        w = 0.5 - polygon_distance(h, float(dx), row.v, aspect != 1.0);
    else
        w = circle_weight(radius_of(h), float(dx), row.v);
    if (row.clipped)
        w = min(w, circle_weight(radius_of(h), float(dx) - row.clip_x, row.v - row.clip_y));
    return w <= 0.0 ? 0.0 : w >= 1.0 ? 1.0 : w;
}

int rim_column(Row row, int k, int side)
{
    int x = side < 0 ? row.inner_l - k : row.inner_r + k;
    if (side > 0 && x == row.inner_l - k)
        return INT_MIN;
    return (side < 0 ? x >= row.outer_l : x <= row.outer_r) ? x : INT_MIN;
}

int rim_steps(Row row)
{
    int left = row.inner_l - row.outer_l, right = row.outer_r - row.inner_r;
    return left > right ? left : right;
}

// highlights_draw.c's interior_span: [a, b] within the image.
void interior_span(Highlight h, Row row, out int a, out int b)
{
    a = int(h.x) + row.inner_l < 0 ? 0 : int(h.x) + row.inner_l;
    b = int(h.x) + row.inner_r >= int(u_width) ? int(u_width) - 1 : int(h.x) + row.inner_r;
}

#define RIM_NONE 0
#define RIM_OFF 1
#define RIM_ON 2

int rim_pixel(Highlight h, Row row, int k, int side, out int x, out float w)
{
    x = 0;
    w = 0.0;
    int dx = rim_column(row, k, side);
    if (dx == INT_MIN)
        return RIM_NONE;
    w = rim_weight(h, row, dx);
    x = int(h.x) + dx;
    return w > 0.0 && x >= 0 && x < int(u_width) ? RIM_ON : RIM_OFF;
}

// ---- the steps ---------------------------------------------------------------------------------

#ifdef STEP_COPY
// The colour, packed (width x channels floats a row), the base the highlights come out of.
void main()
{
    uint i = global_id();
    if (i >= u_width * u_height)
        return;
    uint x = i % u_width, y = i / u_width;
    for (uint c = 0u; c < u_channels; c++)
        base[i * u_channels + c] = color_in[u_color_base + y * u_color_stride + x * u_channels + c];
}
#endif

#ifdef STEP_TAKE_OUT
// Each found highlight's excess taken out of its pixel (not the hidden parts').
void main()
{
    uint i = global_id();
    if (i >= u_count || items[i].hidden != 0u)
        return;
    Highlight h = items[i];
    uint p = (h.y * u_width + h.x) * u_channels;
    base[p] -= h.e0;
    base[p + 1u] -= h.e1;
    base[p + 2u] -= h.e2;
}
#endif

uint landing_at(int y, int x)
{
    return uint(y - u_by0) * uint(u_bx1 - u_bx0 + 1) + uint(x - u_bx0);
}

#ifdef STEP_LANDING
// A box row's prefix counts of the pixels the class lands on, u_seg_count columns a dispatch.
void main()
{
    int y = u_by0 + int(global_id());
    if (y >= u_by1)
        return;
    if (u_seg_first == 0u)
        landing[landing_at(y, u_bx0)] = 0u;
    int end = min(u_bx0 + int(u_seg_first + u_seg_count), u_bx1);
    for (int x = u_bx0 + int(u_seg_first); x < end; x++)
        landing[landing_at(y, x + 1)] = landing[landing_at(y, x)] + (lands(x, y) ? 1u : 0u);
}
#endif

#ifdef STEP_WEIGH
// Each highlight of the class: 1 / its weights' sum over the pixels it lands on (those past the
// frame's edges count), its rows u_seg_count a dispatch from the class's top row, the partial
// sum in `state`.
void main()
{
    uint i = global_id();
    if (i >= u_count)
        return;
    Highlight h = items[u_first + i];
    int reach = half_height(h);
    double sum = u_seg_first == 0u ? 0.0lf : state[i];
    int first = -u_reach_rows + int(u_seg_first);
    int last = min(first + int(u_seg_count) - 1, u_reach_rows);
    for (int dy = max(first, -reach); dy <= min(last, reach); dy++) {
        int y = int(h.y) + dy;
        Row row;
        if (!row_at(h, dy, row))
            continue;
        bool row_inside = y >= 0 && y < int(u_height);
        if (row.inner_l <= row.inner_r) {
            int whole = row.inner_r + 1 - row.inner_l;
            int a = 0, b = -1;
            if (row_inside)
                interior_span(h, row, a, b);
            sum += double(whole - (a <= b ? b + 1 - a : 0));
            if (a <= b)
                sum += h.hidden != 0u ? double(b + 1 - a)
                                      : double(landing[landing_at(y, b + 1)] -
                                               landing[landing_at(y, a)]);
        }
        int steps = rim_steps(row);
        for (int k = 1; k <= steps; k++)
            for (int side = -1; side <= 1; side += 2) {
                int x;
                float w;
                int place = rim_pixel(h, row, k, side, x, w);
                if (place == RIM_NONE)
                    continue;
                if (place == RIM_OFF || !row_inside)
                    sum += double(w);
                else if (h.hidden != 0u || lands(x, y))
                    sum += double(w);
            }
    }
    state[i] = sum;
    if (last >= u_reach_rows)
        weights[u_first + i] = sum > 0.0lf ? float(1.0lf / sum) : 0.0;
}
#endif

#ifdef STEP_SCATTER
// A box row's differences: the class's highlights from u_seg_first (u_seg_count a dispatch)
// whose shapes reach the row, each its interior span and its rim pixels, in the CPU's order.
void main()
{
    int y = u_by0 + int(global_id());
    if (y >= u_by1)
        return;
    uint row_at_ = uint(y) * u_width * 3u;
    if (u_seg_first == 0u)
        for (int x = u_bx0; x < u_bx1; x++)
            for (uint c = 0u; c < 3u; c++)
                diff[row_at_ + uint(x) * 3u + c] = 0.0;
    // The first of the class's highlights (in row order) whose shape may reach the row.
    uint lo = 0u, hi = u_count;
    while (lo < hi) {
        uint mid = lo + (hi - lo) / 2u;
        if (int(items[u_first + mid].y) + u_reach_rows < y)
            lo = mid + 1u;
        else
            hi = mid;
    }
    uint end = min(u_count, u_seg_first + u_seg_count);
    for (uint i = max(lo, u_seg_first); i < end && int(items[u_first + i].y) - u_reach_rows <= y;
         i++) {
        Highlight h = items[u_first + i];
        int dy = y - int(h.y);
        int reach = half_height(h);
        Row row;
        if (dy < -reach || dy > reach || !row_at(h, dy, row))
            continue;
        float k = weights[u_first + i];
        float e[3] = float[3](h.e0 * k, h.e1 * k, h.e2 * k);
        if (row.inner_l <= row.inner_r) {
            int a, b;
            interior_span(h, row, a, b);
            if (a <= b)
                for (uint c = 0u; c < 3u; c++) {
                    diff[row_at_ + uint(a) * 3u + c] += e[c];
                    if (b + 1 < u_bx1)
                        diff[row_at_ + uint(b + 1) * 3u + c] -= e[c];
                }
        }
        int steps = rim_steps(row);
        for (int kk = 1; kk <= steps; kk++)
            for (int side = -1; side <= 1; side += 2) {
                int x;
                float w;
                if (rim_pixel(h, row, kk, side, x, w) != RIM_ON)
                    continue;
                for (uint c = 0u; c < 3u; c++) {
                    float v = e[c] * w;
                    diff[row_at_ + uint(x) * 3u + c] += v;
                    if (x + 1 < u_bx1)
                        diff[row_at_ + uint(x + 1) * 3u + c] -= v;
                }
            }
    }
}
#endif

#ifdef STEP_SUM
// A box row's differences summed along it (in double, u_seg_count columns a dispatch, the sums
// carried in `state`) and added where the class lands, kept within float's range.
void main()
{
    uint yy = global_id();
    int y = u_by0 + int(yy);
    if (y >= u_by1)
        return;
    double sum[3];
    for (uint c = 0u; c < 3u; c++)
        sum[c] = u_seg_first == 0u ? 0.0lf : state[yy * 3u + c];
    uint row_at_ = uint(y) * u_width * 3u;
    int end = min(u_bx0 + int(u_seg_first + u_seg_count), u_bx1);
    for (int x = u_bx0 + int(u_seg_first); x < end; x++) {
        for (uint c = 0u; c < 3u; c++)
            sum[c] += double(diff[row_at_ + uint(x) * 3u + c]);
        if (lands(x, y))
            for (uint c = 0u; c < 3u; c++) {
                uint o = (uint(y) * u_width + uint(x)) * u_channels + c;
                double v = double(out_px[o]) + sum[c];
                out_px[o] = float(v > FLT_MAX ? FLT_MAX : v < -FLT_MAX ? -FLT_MAX : v);
            }
    }
    for (uint c = 0u; c < 3u; c++)
        state[yy * 3u + c] = sum[c];
}
#endif
