/* SPDX-License-Identifier: MIT */
/* layers.c - the layered diffusion of docs/design.md section 1, each effect one or two ADI runs.
 *
 *  midground    the single-layer diffusion (with the near-spread CoC when that runs)
 *  near spread  one image: every near-field pixel q (CoC < 0, D0 = |CoC|) claims the pixels p
 *               around it with D(p) = max_q D0(q) - 4 |p - q| (a cone dilation, cone_dilate.c),
 *               and the midground conducts with max(|CoC|, D), so a blurred near object
 *               spreads over its edges. GPU Gems 3 ch. 28's D = max(D0, 2 D_blurred - D0)
 *               gives a similar ramp at the edge of a large object, but blurring the CoC map
 *               dilutes a small one (a 5 px light of CoC 20 over an in-focus background kept
 *               0.66 of its peak, a sharp dot in a faint halo; the cone 0.30: test_layers); the
 *               slope 4 (D falls to 0 a quarter of the CoC away) measured best of 1.5 ... 8
 *               on the accuracy study's two scenes with near objects.
 *  background   matte a from the CoC; holes where a = 0; the CoC filled into the holes (heat
 *               capacity 1 outside them, 0 in them; uniform beta of the threshold); the colour
 *               diffused with that capacity and the filled CoC; blended under the midground:
 *               out += a w (B - out), w = 1 within |CoC|/2 of an in-focus pixel, fading to 0
 *               at |CoC| (farther out no insulator was in the midground's way, and B, whose
 *               holes include the near field, would cut off the halo of a near object).
 *               Levels at t, 2t, 4t ... in turn.
 *  foreground   its CoC filled outwards (gamma = its alpha, uniform beta of its largest CoC, in
 *               two steps so that the fill reaches pixels sharing no row or column with it);
 *               its premultiplied colour and alpha diffused with gamma = 1 and the filled CoC
 *               (gamma = alpha there would give transparent pixels no capacity, and they would
 *               copy their neighbours' alpha instead of turning transparent); composited over.
 * The background layer and the foreground element work only on the part of the frame they can
 * change (their sources plus the reach of their largest CoC). Per-pixel steps run on the
 * context's threads in row chunks; the diffusions are heat_adi.c's. */
#include "layers.h"

#include "backends/backend.h"
#include "passes/cone_dilate.h"
#include "disc/disc_kernel.h"
#include "passes/far_field.h"
#include "passes/highlights.h"

#include "runtime/parallel_rows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- stages and progress ----------------------------------------------------------------- */

/* Maps one diffusion's progress into the whole call's, so the caller sees one rising fraction. */
static int stage_progress(void *user, float fraction)
{
    const layer_stages *s = user;
    return s->progress(s->user, ((float)s->current + fraction) / (float)s->count);
}

/* One diffusion with the request's solver; its figures are added to the report. */
static ddof_status diffuse(ddof_context *context, adi_request *r, layer_stages *st,
                           layers_report *report)
{
    if (st->progress) {
        r->progress = stage_progress;
        r->progress_user = st;
    }
    adi_report a;
    ddof_status status = ddof_run_adi(context, r, &a);
    st->current++;
    if (status != DDOF_OK)
        return status;
    report->adi.lines_solved += a.lines_solved;
    report->adi.lines_skipped += a.lines_skipped;
    report->adi.seconds_rows += a.seconds_rows;
    report->adi.seconds_columns += a.seconds_columns;
    report->adi.uploads += a.uploads;
    report->adi.readbacks += a.readbacks;
    report->adi.threads = a.threads;
    report->adi.max_coc = ddof_maxf(report->adi.max_coc, a.max_coc);
    if (a.device_bytes > report->adi.device_bytes)
        report->adi.device_bytes = a.device_bytes;
    if (a.substeps_run > report->adi.substeps_run)
        report->adi.substeps_run = a.substeps_run;
    return DDOF_OK;
}

/* A request for a w x h image of `channels`, with the base request's solver settings. */
static adi_request derived(const adi_request *base, const float *color, size_t color_stride,
                           uint32_t channels, float *out)
{
    adi_request r = *base;
    r.color = color;
    r.color_stride = color_stride;
    r.channels = channels;
    r.out = out;
    r.out_stride = (size_t)base->width * channels;
    r.coc = NULL;
    r.gamma = NULL;
    return r;
}

/* Points the request's CoC and its heat capacities, each where not NULL, at one of the layers'
 * own maps: one float a pixel, rows width apart. */
static void use_maps(adi_request *r, const float *coc, const float *gamma)
{
    if (coc) {
        r->coc = coc;
        r->coc_stride = r->width;
        r->coc_channels = 1;
    }
    if (gamma) {
        r->gamma = gamma;
        r->gamma_stride = r->width;
        r->gamma_channels = 1;
    }
}

/* ---- per-pixel steps ---------------------------------------------------------------------- */

/* The maps made from the CoC alone, one pass of coc_map_rows each. */
typedef enum coc_map {
    NEAR_COC,   /* a = the near-field CoC D0 (|CoC| where CoC < 0, else 0)                 */
    SPREAD_COC, /* a = max(|CoC|, the dilated near CoC in a)                               */
    INSULATORS  /* proximity = INSULATOR on in-focus pixels (|CoC| below the matte's ramp
                 * start t0), else 0; the cone dilation of slope 1 then makes it
                 * INSULATOR - distance                                                   */
} coc_map;

typedef struct pixel_job {
    const layers_request *q;
    float *a, *b;      /* maps (w floats a row) or colour (w * channels) */
    const float *rgba; /* the premultiplied foreground element           */
    float t0, t1;      /* matte ramp                                      */
    float blend_from;  /* background levels: blend only CoC >= this       */
    const float *spread; /* the near-spread CoC, or NULL                  */
    size_t spread_stride;
    float *capacity;     /* background heat capacity                      */
    pixel_box blend;     /* the background is blended in here only        */
    float *proximity;    /* background: INSULATOR - distance to the nearest in-focus pixel */
    coc_map map;         /* coc_map_rows: the one it writes                                 */
} pixel_job;

/* The cone height of an in-focus pixel in the proximity map: proximity = INSULATOR - the
 * distance to the nearest one (px), exact in float to 1/8 px, beyond any image's diagonal. */
#define INSULATOR 1048576.0f

/* The map j->map, from each pixel's CoC. */
static void coc_map_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const adi_request *r = &j->q->base;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const float c = adi_request_coc(r, x, y);
            switch (j->map) {
            case NEAR_COC: j->a[i] = c < 0.0f ? -c : 0.0f; break;
            case SPREAD_COC: j->a[i] = ddof_maxf(fabsf(c), j->a[i]); break;
            case INSULATORS: j->proximity[i] = fabsf(c) < j->t0 ? INSULATOR : 0.0f; break;
            }
        }
}

/* a = matte, the blend weight (0 below t0, 1 from t1, linear between; 0 for the near field,
 * which is never background); capacity = 1 where the matte is above 0, else 0 (a hole);
 * b = |CoC|. The capacity is not the matte: heat capacity a < 1 at the same beta blurs like
 * beta / a, which would over-blur the pixels on the ramp. */
static void matte_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const adi_request *r = &j->q->base;
    const float inv = 1.0f / (j->t1 - j->t0);
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < r->width; x++) {
            const size_t i = (size_t)y * r->width + x;
            const float c = adi_request_coc(r, x, y);
            j->a[i] = ddof_minf(1.0f, ddof_maxf(0.0f, (c - j->t0) * inv));
            j->capacity[i] = j->a[i] > 0.0f ? 1.0f : 0.0f;
            j->b[i] = fabsf(c);
        }
}

/* How much the background may replace the midground at a pixel of CoC c whose nearest
 * in-focus pixel is `distance` away: fully within its blur radius |c|/2, not at all beyond
 * its diameter (the midground's blur met no insulator there), linear in between. */
static float within_reach(float distance, float c)
{
    const float d = fabsf(c);
    return d > 0.0f ? ddof_minf(1.0f, ddof_maxf(0.0f, (d - distance) / (0.5f * d))) : 0.0f;
}

/* out += a w (B - out): the midground over the background by its matte a and the reach w of
 * the in-focus pixels (within_reach); exact where a w = 0. An
 * extra level (threshold 2^k t) only replaces pixels at least as blurred as its threshold: it
 * treats less blurred ones as (partial) holes, and its blur would be too wide for them. Pixels
 * whose CoC the near spread raised show a blurred near object over them: they keep the
 * midground, or the background (which has the near object as a hole) would cut its soft edge
 * off again. */
static void blend_background_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const adi_request *r = &j->q->base;
    const uint32_t C = r->channels;
    /* Outside the blend box the midground stays as it is. */
    const uint32_t first = y0 > j->blend.y0 ? y0 : j->blend.y0;
    const uint32_t end = y1 < j->blend.y1 ? y1 : j->blend.y1;
    for (uint32_t y = first; y < end; y++) {
        float *out = r->out + (size_t)y * r->out_stride;
        const float *b = j->b + (size_t)y * r->width * C;
        const float *a = j->a + (size_t)y * r->width;
        const float *coc = r->coc + (size_t)y * r->coc_stride;
        const float *spread = j->spread ? j->spread + (size_t)y * j->spread_stride : NULL;
        const float *proximity = j->proximity + (size_t)y * r->width;
        for (uint32_t x = j->blend.x0; x < j->blend.x1; x++) {
            const float c = coc[(size_t)x * r->coc_channels];
            const int claimed = spread && spread[x] > fabsf(c);
            const float weight =
                c >= j->blend_from && !claimed
                    ? a[x] * within_reach(INSULATOR - proximity[x], c)
                    : 0.0f;
            if (weight > 0.0f)
                for (uint32_t c = 0; c < C; c++)
                    out[x * C + c] += weight * (b[x * C + c] - out[x * C + c]);
        }
    }
}

/* The foreground element as premultiplied RGBA in a (alpha clamped to [0, 1]; colour only read
 * where alpha > 0) and its |CoC| in b (0 where transparent). */
static void foreground_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const layers_request *q = j->q;
    const uint32_t w = q->base.width;
    for (uint32_t y = y0; y < y1; y++) {
        const float *fg = q->fg.color + (size_t)y * q->fg.color_stride;
        const float *coc = q->fg.coc + (size_t)y * q->fg.coc_stride;
        for (uint32_t x = 0; x < w; x++) {
            float *p = j->a + ((size_t)y * w + x) * 4;
            ddof_element_pixel(fg + (size_t)x * 4, q->fg.premultiplied, p);
            j->b[(size_t)y * w + x] =
                p[3] > 0.0f ? fabsf(coc[(size_t)x * q->fg.coc_channels]) : 0.0f;
        }
    }
}

/* a = 1 where the first CoC fill left a value (an element pixel, or one it reached), else 0:
 * the sources of the second fill. */
static void holds_value_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const size_t w = j->q->base.width;
    for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; i++)
        j->a[i] = j->rgba[i * 4 + 3] > 0.0f || j->b[i] > 0.0f ? 1.0f : 0.0f;
}

/* out = F + (1 - F.a) out on the colour channels; with 4 channels the alpha channel likewise,
 * the element's part of it being its coverage F.a, or the blurred carried alpha in b. */
static void composite_foreground_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const pixel_job *j = user;
    const adi_request *r = &j->q->base;
    const uint32_t C = r->channels;
    for (uint32_t y = y0; y < y1; y++) {
        float *out = r->out + (size_t)y * r->out_stride;
        const float *f = j->a + (size_t)y * r->width * 4;
        const float *carried = j->b ? j->b + (size_t)y * r->width : NULL;
        for (uint32_t x = 0; x < r->width; x++) {
            const float alpha = ddof_minf(1.0f, ddof_maxf(0.0f, f[x * 4 + 3]));
            if (alpha <= 0.0f)
                continue;
            for (uint32_t c = 0; c < 3; c++)
                out[x * C + c] = f[x * 4 + c] + (1.0f - alpha) * out[x * C + c];
            if (C == 4)
                out[x * 4 + 3] = (carried ? carried[x] : alpha) + (1.0f - alpha) * out[x * 4 + 3];
        }
    }
}

/* Largest value of a w x h map. */
static float map_max(const float *map, size_t count)
{
    float m = 0.0f;
    for (size_t i = 0; i < count; i++)
        m = ddof_maxf(m, map[i]);
    return m;
}

/* ---- where an effect can matter ------------------------------------------------------------ */

/* The part of a request inside box, as a request of its own: pointers moved, sizes cut,
 * strides unchanged. */
static layers_request crop(const layers_request *q, pixel_box b)
{
    layers_request c = *q;
    adi_request *r = &c.base;
    r->color += (size_t)b.y0 * r->color_stride + (size_t)b.x0 * r->channels;
    r->out += (size_t)b.y0 * r->out_stride + (size_t)b.x0 * r->channels;
    if (r->coc)
        r->coc += (size_t)b.y0 * r->coc_stride + (size_t)b.x0 * r->coc_channels;
    if (c.fg.color) {
        c.fg.color += (size_t)b.y0 * c.fg.color_stride + (size_t)b.x0 * 4;
        c.fg.coc += (size_t)b.y0 * c.fg.coc_stride + (size_t)b.x0 * c.fg.coc_channels;
    }
    if (c.fg.carried_alpha)
        c.fg.carried_alpha += (size_t)b.y0 * c.fg.carried_stride + b.x0;
    r->width = b.x1 - b.x0;
    r->height = b.y1 - b.y0;
    return c;
}

/* ---- the effects -------------------------------------------------------------------------- */

static float *scratch(ddof_context *context, int slot, size_t floats, ddof_status *status)
{
    float *p = ddof_scratch_get(context, slot, floats * sizeof(float));
    if (!p && *status == DDOF_OK)
        *status = ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                            "could not allocate %zu bytes for a layer", floats * sizeof(float));
    return p;
}

/* Near spread: writes the spread CoC (w x h, 1 channel) into *spread_coc. The dilation runs on
 * `b`: the near pixels' box grown by the farthest any of them reaches (max_near / slope,
 * layers_dispatch.c). */
static ddof_status near_spread(ddof_context *context, const layers_request *q, pixel_box b,
                               const float **spread_coc)
{
    const adi_request *r = &q->base;
    const size_t pixels = (size_t)r->width * r->height;
    ddof_status status = DDOF_OK;
    /* d becomes the spread CoC */
    float *d = scratch(context, DDOF_SCRATCH_NEAR_SPREAD, pixels, &status);
    if (status != DDOF_OK)
        return status;
    pixel_job job = {.q = q, .a = d, .map = NEAR_COC};
    ddof_parallel_rows(context, r->height, coc_map_rows, &job);
    if (!box_is_empty(b))
        ddof_cone_dilate(d + (size_t)b.y0 * r->width + b.x0, b.x1 - b.x0, b.y1 - b.y0, r->width,
                         DDOF_NEAR_SPREAD_SLOPE);
    job.map = SPREAD_COC;
    ddof_parallel_rows(context, r->height, coc_map_rows, &job);
    *spread_coc = d;
    return DDOF_OK;
}

/* One background level with matte ramp [ramp_start, threshold], blended into r->out. */
static ddof_status background_level(ddof_context *context, const layers_request *q,
                                    const float *color, size_t color_stride, float ramp_start,
                                    float threshold, float blend_from, const float *spread,
                                    size_t spread_stride, pixel_box blend, layer_stages *st,
                                    layers_report *report)
{
    const adi_request *r = &q->base;
    const size_t pixels = (size_t)r->width * r->height;
    ddof_status status = DDOF_OK;
    float *matte = scratch(context, DDOF_SCRATCH_LAYER_MATTE, pixels, &status);
    float *coc_abs = scratch(context, DDOF_SCRATCH_LAYER_COC_ABS, pixels, &status);
    float *filled = scratch(context, DDOF_SCRATCH_LAYER_FILLED, pixels, &status);
    float *layer = scratch(context, DDOF_SCRATCH_LAYER_COLOR, pixels * r->channels, &status);
    float *capacity = scratch(context, DDOF_SCRATCH_LAYER_CAPACITY, pixels, &status);
    if (status != DDOF_OK)
        return status;
    pixel_job job = {.q = q, .a = matte, .b = coc_abs, .t0 = ramp_start, .t1 = threshold,
                     .blend_from = blend_from, .spread = spread, .spread_stride = spread_stride,
                     .capacity = capacity, .blend = blend};
    ddof_parallel_rows(context, r->height, matte_rows, &job);

    /* The CoC flows into the holes, every link at the threshold. */
    adi_request fill = derived(r, coc_abs, r->width, 1, filled);
    fill.uniform_coc = threshold;
    fill.substeps = 1;
    fill.disc = NULL; /* the CoC itself spreads by plain heat */
    use_maps(&fill, NULL, capacity);
    if ((status = diffuse(context, &fill, st, report)) != DDOF_OK)
        return status;

    /* The colour, with the holes holding no heat of their own. */
    adi_request bg = derived(r, color, color_stride, r->channels, layer);
    use_maps(&bg, filled, capacity);
    if ((status = diffuse(context, &bg, st, report)) != DDOF_OK)
        return status;

    /* The filled CoC is spent: its buffer becomes the proximity map. */
    job.b = layer;
    job.proximity = filled;
    job.map = INSULATORS;
    ddof_parallel_rows(context, r->height, coc_map_rows, &job);
    ddof_cone_dilate(filled, r->width, r->height, r->width, 1.0f);
    ddof_parallel_rows(context, r->height, blend_background_rows, &job);
    return DDOF_OK;
}


/* Away from the element's own depth edges (its CoC filled outwards is smooth) its blur is the
 * lens's shape too (far_field.h): each point's premultiplied colour and coverage over its own
 * disc, blended over the diffusion's result (blur->out) toward such edges, from the element
 * before its blur (blur->color). So a blurred near object's interior and its see-through rim
 * are the lens's, not the diffusion's blob. */
static ddof_status gather_element(ddof_context *context, const adi_request *blur,
                                  layers_report *report)
{
    const double t0 = ddof_seconds();
    far_field_report far;
    const ddof_status status =
        ddof_far_field(context, blur, blur->color, blur->color_stride, 0, &far);
    if (status != DDOF_OK)
        return status;
    if (far.pixels)
        report->effects |= DDOF_EFFECT_FAR_FIELD;
    report->seconds_far_field += ddof_seconds() - t0;
    return DDOF_OK;
}

/* What the element's blur does besides the diffusion, on the frame's settings: its own
 * highlights (found by ddof_find_element_highlights) and the far field's gather. */
typedef struct element_extras {
    const adi_highlights *lights; /* taken out of it, drawn into its blur; NULL: none     */
    int gather;                   /* the far field gathers its blur (far_field not off) */
} element_extras;

static ddof_status foreground(ddof_context *context, const layers_request *q,
                              const element_extras *extras, layer_stages *st,
                              layers_report *report)
{
    const adi_request *r = &q->base;
    const size_t pixels = (size_t)r->width * r->height;
    ddof_status status = DDOF_OK;
    float *premultiplied = scratch(context, DDOF_SCRATCH_LAYER_COLOR, pixels * 4, &status);
    float *coc_abs = scratch(context, DDOF_SCRATCH_LAYER_COC_ABS, pixels, &status);
    float *filled = scratch(context, DDOF_SCRATCH_LAYER_FILLED, pixels, &status);
    if (status != DDOF_OK)
        return status;
    pixel_job job = {.q = q, .a = premultiplied, .b = coc_abs};
    ddof_parallel_rows(context, r->height, foreground_rows, &job);

    /* The element's own highlights (a near light is usually in it): taken out of its
     * premultiplied colour here, drawn into it after its blur. */
    const adi_highlights *lights = extras->lights && extras->lights->count ? extras->lights
                                                                           : NULL;
    const float *element = premultiplied;
    if (lights) {
        const double t0 = ddof_seconds();
        const adi_request er = derived(r, premultiplied, (size_t)r->width * 4, 4, premultiplied);
        float *base = ddof_highlight_base_image(context, &er);
        if (!base)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate the highlight pass's %ux%u image", r->width,
                             r->height);
        ddof_take_out_highlights(context, &er, lights->items, lights->count, base);
        element = base;
        report->seconds_highlights += ddof_seconds() - t0;
    }

    /* Its CoC flows outwards into the transparent pixels, at its own largest size. One ADI
     * step reaches only the pixels that share a row or a column with the element (each pass
     * sees its own line's sources only); a second, whose sources are every pixel holding a
     * value by then (a cross through the element, which every row crosses), reaches the rest.
     * Without it the halo would be cut along the element's bounding box. */
    adi_request fill = derived(r, coc_abs, r->width, 1, filled);
    fill.uniform_coc = map_max(coc_abs, pixels);
    fill.substeps = 1;
    fill.disc = NULL; /* the CoC itself spreads by plain heat */
    fill.gamma = premultiplied + 3;
    fill.gamma_stride = (size_t)r->width * 4;
    fill.gamma_channels = 4;
    if ((status = diffuse(context, &fill, st, report)) != DDOF_OK)
        return status;
    float *sources = coc_abs; /* free now */
    pixel_job reach = {.q = q, .a = sources, .b = filled, .rgba = premultiplied};
    ddof_parallel_rows(context, r->height, holds_value_rows, &reach);
    adi_request spread = fill;
    spread.color = filled;
    spread.color_stride = r->width;
    spread.out = filled; /* in place */
    use_maps(&spread, NULL, sources);
    if ((status = diffuse(context, &spread, st, report)) != DDOF_OK)
        return status;

    /* Premultiplied colour and alpha spread together: coverage falls below 1. In place, unless
     * the far field gathers from the element afterwards. */
    const int gather = extras->gather;
    if (gather && element == premultiplied) {
        float *copy = scratch(context, DDOF_SCRATCH_ELEMENT_SHARP, pixels * 4, &status);
        if (status != DDOF_OK)
            return status;
        memcpy(copy, premultiplied, pixels * 4 * sizeof(float));
        element = copy;
    }
    adi_request blur = derived(r, element, (size_t)r->width * 4, 4, premultiplied);
    use_maps(&blur, filled, NULL);
    if ((status = diffuse(context, &blur, st, report)) != DDOF_OK)
        return status;
    if (gather && (status = gather_element(context, &blur, report)) != DDOF_OK)
        return status;
    if (lights) {
        /* Light added to the element's colour, over whatever lies behind it; it lands where
         * the element's spread CoC reaches (|CoC| at least half the disc's: the element's
         * blur, never the sharp pixels beside it). */
        const double t0 = ddof_seconds();
        ddof_draw_highlights(context, &blur, lights, ddof_highlight_base_image(context, &blur));
        report->effects |= DDOF_EFFECT_HIGHLIGHTS;
        report->seconds_highlights += ddof_seconds() - t0;
    }

    job.b = NULL;
    if (q->fg.carried_alpha && r->channels == 4) {
        /* The element's part of the frame's alpha channel, blurred as its colour is. */
        float *carried = scratch(context, DDOF_SCRATCH_LAYER_MATTE, pixels, &status);
        if (status != DDOF_OK)
            return status;
        adi_request alpha = derived(r, q->fg.carried_alpha, q->fg.carried_stride, 1, carried);
        use_maps(&alpha, filled, NULL);
        if ((status = diffuse(context, &alpha, st, report)) != DDOF_OK)
            return status;
        job.b = carried;
    }
    ddof_parallel_rows(context, r->height, composite_foreground_rows, &job);
    return DDOF_OK;
}

/* The background layer's levels, blended into r->out near the edges where it changes
 * anything. `color` is what the midground diffused, `spread` the near-spread CoC or NULL;
 * the levels and their settings are the request's. */
static ddof_status run_background(ddof_context *context, const layers_request *q,
                                  const adi_layers_request *d, const float *color,
                                  size_t color_stride, const float *spread, layer_stages *st,
                                  layers_report *report)
{
    const adi_request *r = &q->base;
    ddof_status status = DDOF_OK;
    const double t0 = ddof_seconds();
    /* The layer only changes pixels near its edges (where a far CoC meets an in-focus
     * pixel): it is computed on those plus twice its reach, and blended within its reach,
     * so the crop's insulated border never shows. Forced on without edges, it covers all. */
    const uint32_t reach =
        ddof_background_reach_px(r->disc, r->beta_scale, report->adi.max_coc,
                                 d->background_threshold_px, d->background_levels);
    const pixel_box edges = {d->background_edges.x0, d->background_edges.y0,
                             d->background_edges.x1, d->background_edges.y1};
    const pixel_box area = box_grow(edges, 2 * reach, r->width, r->height);
    const pixel_box near = box_grow(edges, reach, r->width, r->height);
    const pixel_box blend = {near.x0 - area.x0, near.y0 - area.y0, near.x1 - area.x0,
                             near.y1 - area.y0};
    const layers_request sub = crop(q, area);
    color += (size_t)area.y0 * color_stride + (size_t)area.x0 * r->channels;
    if (spread)
        spread += (size_t)area.y0 * r->width + area.x0;
    for (uint32_t level = 0; level < d->background_levels; level++) {
        const float threshold = ddof_background_threshold(d->background_threshold_px, level);
        const float ramp_start =
            ddof_background_ramp_start(threshold, level, d->background_ramp_start_px);
        status = background_level(context, &sub, color, color_stride, ramp_start, threshold,
                                  ddof_background_blend_from(threshold, level), spread,
                                  r->width, blend, st, report);
        if (status != DDOF_OK)
            return status;
    }
    report->effects |= DDOF_EFFECT_BACKGROUND;
    report->seconds_background = ddof_seconds() - t0;
    return DDOF_OK;
}

/* The diffusions behind the element: the midground and two per background level (the CoC
 * fill, the colour). */
static uint32_t layer_diffusions(uint32_t background_levels)
{
    return 1 + 2 * background_levels;
}

/* An element's: its CoC filled in two steps, its colour, and the alpha it may carry. */
static uint32_t element_diffusions(int carried_alpha)
{
    return carried_alpha ? 4u : 3u;
}

static uint32_t element_stages(const layers_request *q, const frame_plan *plan)
{
    return plan->foreground ? element_diffusions(q->fg.carried_alpha != NULL) : 0u;
}

layer_stages ddof_layer_stages(const layers_request *q, const frame_plan *plan)
{
    const adi_request *r = &q->base;
    return (layer_stages){r->progress, r->progress_user, 0,
                          layer_diffusions(plan->background ? q->params->background_levels : 0) +
                              element_stages(q, plan)};
}

/* The element (q->fg, its area `area`) blurred and composited over q->base.out. */
static ddof_status element(ddof_context *context, const layers_request *q, pixel_box area,
                           const element_extras *extras, layer_stages *st,
                           layers_report *report)
{
    const double t0 = ddof_seconds();
    const layers_request sub = crop(q, area);
    const ddof_status status = foreground(context, &sub, extras, st, report);
    if (status != DDOF_OK)
        return status;
    report->effects |= DDOF_EFFECT_FOREGROUND;
    report->seconds_foreground += ddof_seconds() - t0;
    return DDOF_OK;
}

static pixel_box pixel_box_of(adi_box b)
{
    return (pixel_box){b.x0, b.y0, b.x1, b.y1};
}

/* The colours of a request's passes: *split, what the silhouettes' split reads (the colour
 * with the highlights taken out, into the highlight pass's base image), and base->color, what
 * the layers diffuse (that, with the silhouettes' objects taken out too); *pairs: whether the
 * frame has a silhouette pair. */
static ddof_status pass_colors(ddof_context *context, const adi_layers_request *d,
                               const object_matte *matte, adi_request *base, const float **split,
                               size_t *split_stride, int *pairs, adi_layers_report *out)
{
    const adi_request *r = &d->base;
    *base = *r;
    *pairs = 0;
    *split = r->color;
    *split_stride = r->color_stride;
    if (d->highlights.count) {
        const double t0 = ddof_seconds();
        float *taken = ddof_highlight_base_image(context, r);
        if (!taken)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate the highlight pass's %ux%u image", r->width,
                             r->height);
        ddof_take_out_highlights(context, r, d->highlights.items, d->highlights.count, taken);
        base->color = taken;
        base->color_stride = (size_t)r->width * r->channels;
        out->seconds_highlights += ddof_seconds() - t0;
    } else if (r->out == r->color && (d->background_levels || d->far_field || d->silhouettes)) {
        /* Diffusing in place overwrites the colour the background layer, the far field and
         * the silhouettes still read (the highlights' take-out above is a copy already). */
        const size_t row = (size_t)r->width * r->channels;
        float *copy = ddof_scratch_get(context, DDOF_SCRATCH_LAYER_COLOR_COPY,
                                       row * r->height * sizeof(float));
        if (!copy)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate %zu bytes for a layer",
                             row * r->height * sizeof(float));
        for (uint32_t y = 0; y < r->height; y++)
            memcpy(copy + y * row, r->color + (size_t)y * r->color_stride, row * sizeof(float));
        base->color = copy;
        base->color_stride = row;
    }
    *split = base->color;
    *split_stride = base->color_stride;
    if (!d->silhouettes)
        return DDOF_OK;
    const double t0 = ddof_seconds();
    const ddof_status status = ddof_clean_silhouettes(context, r, matte, &base->color,
                                                      &base->color_stride, pairs);
    out->seconds_silhouettes += ddof_seconds() - t0;
    return status;
}

/* The silhouettes' split and the highlights' discs over the layers' result. The discs are
 * drawn through the split's colour buffer, the last of its readers, so they come after the
 * split: a disc then lands whole behind a mixed pixel's object share. With an object matte the
 * shares are the render's own, and the split comes after the discs (drawn through the split's
 * scratch, still free): a mixed pixel's background share then shows the disc behind it and its
 * object share hides it, as a strand across a light does through a lens. The colours' guess of
 * the share errs too often for that: it would cut dark notches into the discs. */
static ddof_status split_and_draw(ddof_context *context, const adi_layers_request *d,
                                  const object_matte *matte, const float *color,
                                  size_t color_stride, int pairs, adi_layers_report *out)
{
    const adi_request *r = &d->base;
    const adi_highlights *h = &d->highlights;
    const int discs_first = pairs && h->count && matte->ranks;
    silhouette_report split = {0};
    double t0 = ddof_seconds();
    if (discs_first) {
        float *scratch = ddof_silhouettes_scratch(context, r);
        if (!scratch)
            return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                             "could not allocate the silhouettes' %ux%u image", r->width,
                             r->height);
        ddof_draw_highlights(context, r, h, scratch);
        out->seconds_highlights += ddof_seconds() - t0;
        t0 = ddof_seconds();
    }
    if (pairs) {
        const ddof_status status =
            ddof_split_silhouettes(context, r, matte, color, color_stride, &split);
        if (status != DDOF_OK)
            return status;
        out->silhouette_pixels = split.pixels;
        out->seconds_silhouettes += ddof_seconds() - t0;
    }
    if (h->count && !discs_first) {
        t0 = ddof_seconds();
        ddof_draw_highlights(context, r, h, ddof_highlight_base_image(context, r));
        out->seconds_highlights += ddof_seconds() - t0;
    }
    return DDOF_OK;
}

/* The run's first stage: the highlights it draws found, the frame's and the element's own,
 * into `found` (the request with their lists). */
static ddof_status find_highlights(ddof_context *context, const adi_layers_request *d,
                                   adi_layers_request *found, adi_layers_report *out)
{
    *found = *d;
    const double t0 = ddof_seconds();
    ddof_status status = DDOF_OK;
    if (d->highlights.find) {
        highlight_set set;
        status = ddof_find_highlights(context, &d->base, d->highlights.threshold,
                                      (int)d->highlights.coc_signed, d->highlights.image_sums,
                                      HIGHLIGHTS_OF_FRAME, NULL, &set);
        found->highlights.items = set.items;
        found->highlights.count = set.count;
        out->highlights_count = set.count;
        out->highlights_hidden = set.hidden;
        out->highlights_over_budget = (uint32_t)set.over_budget;
        out->highlights_threshold = set.threshold;
        out->highlights_cost = set.cost;
    }
    if (status == DDOF_OK && d->fg_color && d->fg_highlights.find) {
        const layers_request q = {
            .base = d->base,
            .fg = {.color = d->fg_color, .color_stride = d->fg_color_stride, .coc = d->fg_coc,
                   .coc_stride = d->fg_coc_stride, .coc_channels = d->fg_coc_channels,
                   .premultiplied = (int)d->fg_premultiplied}};
        highlight_set set;
        status = ddof_find_element_highlights(context, &q, pixel_box_of(d->fg_area),
                                              d->fg_highlights.threshold,
                                              d->fg_highlights.image_sums, &set);
        found->fg_highlights.items = set.items;
        found->fg_highlights.count = set.count;
    }
    out->seconds_highlights += ddof_seconds() - t0;
    return status;
}

ddof_status ddof_run_layers_on_cpu(ddof_context *context, const adi_layers_request *request,
                                   adi_layers_report *out)
{
    *out = (adi_layers_report){0};
    adi_layers_request found;
    ddof_status status = find_highlights(context, request, &found, out);
    if (status != DDOF_OK)
        return status;
    const adi_layers_request *d = &found;
    const adi_request *r = &d->base;
    layers_report report = {0};
    layer_stages st = {r->progress, r->progress_user, 0,
                       layer_diffusions(d->background_levels) +
                           (d->fg_color ? element_diffusions(d->fg_carried_alpha != NULL) : 0u)};
    /* What the layers diffuse: the highlights and the silhouettes' objects taken out. */
    const object_matte matte = {d->matte, d->matte_stride, d->matte ? d->matte_ranks : 0u};
    adi_request base;
    const float *split_color;
    size_t split_stride;
    int pairs;
    if ((status = pass_colors(context, d, &matte, &base, &split_color, &split_stride, &pairs,
                              out)) != DDOF_OK)
        return status;
    layers_request q = {.base = base};
    adi_request mid = base;
    const float *spread = NULL;
    if (d->near_spread) {
        const double t0 = ddof_seconds();
        if ((status = near_spread(context, &q, pixel_box_of(d->near_dilate), &spread)) !=
            DDOF_OK)
            return status;
        use_maps(&mid, spread, NULL);
        report.seconds_foreground += ddof_seconds() - t0;
    }
    if ((status = diffuse(context, &mid, &st, &report)) != DDOF_OK)
        return status;
    if (d->background_levels &&
        (status = run_background(context, &q, d, base.color, base.color_stride, spread, &st,
                                 &report)) != DDOF_OK)
        return status;
    far_field_report far = {0};
    if (d->far_field) {
        const double t0 = ddof_seconds();
        if ((status = ddof_far_field(context, r, base.color, base.color_stride,
                                     (int)d->far_slices, &far)) != DDOF_OK)
            return status;
        out->seconds_far_field = ddof_seconds() - t0;
    }
    if ((status = split_and_draw(context, d, &matte, split_color, split_stride, pairs, out)) !=
        DDOF_OK)
        return status;
    if (d->fg_color) {
        q.fg = (layers_element){.color = d->fg_color, .color_stride = d->fg_color_stride,
                                .coc = d->fg_coc, .coc_stride = d->fg_coc_stride,
                                .coc_channels = d->fg_coc_channels,
                                .premultiplied = (int)d->fg_premultiplied,
                                .carried_alpha = d->fg_carried_alpha,
                                .carried_stride = d->fg_carried_stride,
                                .max_coc = d->fg_max_coc};
        const element_extras extras = {.lights = &d->fg_highlights,
                                       .gather = (int)d->fg_gather};
        if ((status = element(context, &q, pixel_box_of(d->fg_area), &extras, &st, &report)) !=
            DDOF_OK)
            return status;
    }
    out->adi = report.adi;
    out->seconds_background = report.seconds_background;
    out->seconds_foreground = report.seconds_foreground;
    out->far_pixels = far.pixels;
    out->far_layered_pixels = far.layered_pixels;
    out->far_slices = far.slices;
    out->far_levels = far.levels;
    out->element_effects =
        report.effects & ((uint32_t)DDOF_EFFECT_FAR_FIELD | (uint32_t)DDOF_EFFECT_HIGHLIGHTS);
    return DDOF_OK;
}

pixel_box ddof_element_area(const layers_request *q)
{
    const adi_request *r = &q->base;
    /* The element's blur reaches no further than its largest CoC carries. */
    const uint32_t reach = ddof_kernel_reach_px(r->disc, r->beta_scale, q->fg.max_coc);
    return box_grow(q->fg.box, reach, r->width, r->height);
}

ddof_status ddof_find_element_highlights(ddof_context *context, const layers_request *q,
                                         pixel_box area, float threshold,
                                         const double *aperture_sums, highlight_set *set)
{
    memset(set, 0, sizeof *set);
    /* The element as given, read as its steps premultiply it (no copy of it here). */
    const layers_request sub = crop(q, area);
    adi_request er = derived(&sub.base, sub.fg.color, sub.fg.color_stride, 4, NULL);
    er.coc = sub.fg.coc;
    er.coc_stride = sub.fg.coc_stride;
    er.coc_channels = sub.fg.coc_channels;
    return ddof_find_highlights(context, &er, threshold, 0, aperture_sums,
                                sub.fg.premultiplied ? HIGHLIGHTS_OF_ELEMENT
                                                     : HIGHLIGHTS_OF_STRAIGHT_ELEMENT,
                                NULL, set);
}

adi_highlights ddof_request_highlights(const layers_request *q, int find, int coc_signed,
                                       const double *aperture_sums)
{
    const highlight_aperture *a = &q->aperture;
    return (adi_highlights){.find = (uint32_t)find,
                            .threshold = q->params->highlight_threshold,
                            .coc_signed = (uint32_t)coc_signed, .blades = a->blades,
                            .rotation_rad = a->rotation_rad, .catseye = a->catseye,
                            .centre_x = a->centre_x, .centre_y = a->centre_y,
                            .half_width = a->half_width, .half_height = a->half_height,
                            .image_sums = aperture_sums, .image_width = a->image_width,
                            .image_height = a->image_height};
}

