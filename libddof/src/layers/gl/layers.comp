/* SPDX-License-Identifier: MIT */
// layers.comp - the per-pixel steps of the layered frame (libddof/src/layers/layers.c), one program
// per step (the define names it), one invocation per pixel of the area a step works on. Each
// is the CPU step's arithmetic in the CPU's order; `precise` keeps a GPU from fusing a
// multiply and add the CPU rounds twice, so the device's frame differs from the CPU's only by
// the diffusions' rounding.
//
// Images are float arrays in the CPU's layouts: the uploaded images (caller's strides, the CoC
// and the element's CoC as the first of several channels; each a bound section of the upload), the output (w x channels floats a
// row), and the maps of the area (area width floats a row), so that a crop is an offset.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer CocIn { float coc_in[]; }; // the upload's CoC
#ifdef STEP_FG_PREPARE // the element's sections of the upload, where OUT and SPREAD would be
layout(std430, binding = 1) readonly buffer FgColor { float fg_color[]; };
layout(std430, binding = 6) readonly buffer FgCoc { float fg_coc[]; };
#else
layout(std430, binding = 1) buffer Out { float out_px[]; };            // the result so far
#ifdef STEP_COMPOSITE // the alpha the element carries, blurred (area width a row)
layout(std430, binding = 6) readonly buffer Carried { float carried[]; };
#else
layout(std430, binding = 6) buffer Spread { float spread[]; };         // near-spread CoC
#endif
#endif
layout(std430, binding = 2) buffer MapA { float map_a[]; };
layout(std430, binding = 3) buffer MapB { float map_b[]; };
layout(std430, binding = 4) buffer MapC { float map_c[]; };            // proximity
layout(std430, binding = 5) buffer Capacity { float capacity[]; };
layout(std430, binding = 7) buffer Layer { float layer[]; };           // B or premultiplied F

uniform uint u_width;        // of the area
uniform uint u_height;
uniform uint u_channels;     // of the colour
uniform uint u_coc_base;     // coc_in[] index of the area's first CoC
uniform uint u_coc_stride;
uniform uint u_coc_step;
uniform uint u_out_base;     // out_px[] index of the area's first value
uniform uint u_out_stride;
uniform uint u_spread_base;  // spread[] index of the area's first value (frame width a row)
uniform uint u_spread_stride;
uniform uint u_has_spread;
uniform uint u_has_carried;  // STEP_COMPOSITE: the element carries part of the frame's alpha
uniform uint u_fg_base;      // fg_color[] index of the area's first element pixel
uniform uint u_fg_stride;
uniform uint u_fg_coc_base;
uniform uint u_fg_coc_stride;
uniform uint u_fg_coc_step;
uniform uint u_premultiplied;
uniform float u_t0;          // matte ramp start (the insulators: |CoC| below it)
uniform float u_inv_ramp;    // 1 / (threshold - ramp start), as the CPU rounds it
uniform float u_blend_from;  // blend only CoC >= this (-inf at level 0)
uniform uint u_blend_x0;     // the background is blended within [x0, x1) x [y0, y1)
uniform uint u_blend_y0;
uniform uint u_blend_x1;
uniform uint u_blend_y1;

// The cone height of an in-focus pixel in the proximity map (layers.c's INSULATOR).
#define INSULATOR 1048576.0

float coc_at(uint x, uint y)
{
    return coc_in[u_coc_base + y * u_coc_stride + x * u_coc_step];
}

// Fully within |c|/2 of the nearest in-focus pixel, not at all beyond |c| (layers.c).
float within_reach(float distance, float c)
{
    float d = abs(c);
    precise float t = (d - distance) / (0.5 * d);
    return d > 0.0 ? min(1.0, max(0.0, t)) : 0.0;
}

void main()
{
    uint p = global_id();
    if (p >= u_width * u_height)
        return;
    uint x = p % u_width, y = p / u_width;
#if defined(STEP_NEAR_MAP)
    // a = the near-field CoC D0.
    float c = coc_at(x, y);
    map_a[p] = c < 0.0 ? -c : 0.0;
#elif defined(STEP_SPREAD)
    // a = max(|CoC|, the dilated near CoC).
    map_a[p] = max(abs(coc_at(x, y)), map_a[p]);
#elif defined(STEP_MATTE)
    // a = the matte, capacity = 1 where it is above 0, b = |CoC|.
    float c = coc_at(x, y);
    precise float ramp = (c - u_t0) * u_inv_ramp;
    float a = min(1.0, max(0.0, ramp));
    map_a[p] = a;
    capacity[p] = a > 0.0 ? 1.0 : 0.0;
    map_b[p] = abs(c);
#elif defined(STEP_INSULATOR)
    map_c[p] = abs(coc_at(x, y)) < u_t0 ? INSULATOR : 0.0;
#elif defined(STEP_BLEND)
    // out += a w (B - out) within the blend box, not where the near spread claimed the pixel.
    if (x < u_blend_x0 || x >= u_blend_x1 || y < u_blend_y0 || y >= u_blend_y1)
        return;
    float c = coc_at(x, y);
    bool claimed = u_has_spread != 0u && spread[u_spread_base + y * u_spread_stride + x] > abs(c);
    precise float distance = INSULATOR - map_c[p];
    precise float weight = c >= u_blend_from && !claimed ? map_a[p] * within_reach(distance, c)
                                                          : 0.0;
    if (weight > 0.0)
        for (uint k = 0u; k < u_channels; k++) {
            uint o = u_out_base + y * u_out_stride + x * u_channels + k;
            precise float v = out_px[o] + weight * (layer[p * u_channels + k] - out_px[o]);
            out_px[o] = v;
        }
#elif defined(STEP_FG_PREPARE)
    // layer = the element premultiplied (alpha clamped, colour read only where alpha > 0),
    // b = its |CoC| (0 where transparent).
    uint q = u_fg_base + y * u_fg_stride + x * 4u;
    float alpha = min(1.0, max(0.0, fg_color[q + 3u]));
    float scale = u_premultiplied != 0u ? 1.0 : alpha;
    for (uint k = 0u; k < 3u; k++) {
        precise float v = alpha > 0.0 ? fg_color[q + k] * scale : 0.0;
        layer[p * 4u + k] = v;
    }
    layer[p * 4u + 3u] = alpha;
    map_b[p] = alpha > 0.0 ? abs(fg_coc[u_fg_coc_base + y * u_fg_coc_stride + x * u_fg_coc_step])
                           : 0.0;
#elif defined(STEP_HOLDS_VALUE)
    // b = 1 where the first CoC fill (c) left a value, the second fill's sources.
    map_b[p] = layer[p * 4u + 3u] > 0.0 || map_c[p] > 0.0 ? 1.0 : 0.0;
#elif defined(STEP_COMPOSITE)
    // out = F + (1 - F.a) out.
    float alpha = min(1.0, max(0.0, layer[p * 4u + 3u]));
    if (alpha <= 0.0)
        return;
    uint o = u_out_base + y * u_out_stride + x * u_channels;
    for (uint k = 0u; k < 3u; k++) {
        precise float v = layer[p * 4u + k] + (1.0 - alpha) * out_px[o + k];
        out_px[o + k] = v;
    }
    if (u_channels == 4u) {
        const float part = u_has_carried != 0u ? carried[p] : alpha;
        precise float v = part + (1.0 - alpha) * out_px[o + 3u];
        out_px[o + 3u] = v;
    }
#endif
}
