/* SPDX-License-Identifier: MIT */
/* far_field.c - where the far field's gather runs (far_field.h; the gather itself:
 * far_field_gather.c).
 *
 * The diffusion's kernels are a disc's approximation (the heat kernel a soft blob, the disc
 * kernels a sum of separable chains with a ringing rim), and its insulated border averages only
 * what lies inside the frame. Away from depth edges a lens's blur is plain: each point spreads
 * its light over its own disc, and there a gather draws it exactly. Near a depth edge what lies
 * behind what, and what a sharp object hides, decide the picture: the layers' diffusion stays
 * the method there.
 *
 * A depth edge is a pair of 4-neighbours whose signed CoC differs by FAR_EDGE_STEP_PX or more
 * (as the accuracy study's band counts them; 1 px lost 0.9 dB on its daylight scene, where tree
 * crowns before the sky differ by about 1-3 px across a blur of 20). A pixel takes the gather fully
 * when the nearest edge is beyond its own radius + 1 and no edge's reach (half the pair's larger
 * |CoC|, + 1) covers it; over FAR_RAMP_PX toward either it is mixed with the layers' result;
 * in-focus pixels keep theirs. Both distances are cone dilations (cone_dilate.h: the chamfer
 * distance, within 8% of Euclidean).
 *
 * An edge whose two sides both blur by FAR_BLURRED_PX or more (a tree's crown before the sky) has
 * no sharp pixel to bleed into: there the depth slices' gather (far_layers.c) draws each
 * surface with the lens's shape and lets the nearer cover the farther. The same distances,
 * counted to the sharp edges alone, say where it runs. */
#include "far_field.h"

#include "cone_dilate.h"
#include "far_field_internal.h"
#include "far_layers.h"
#include "runtime/float_ops.h"
#include "runtime/parallel_rows.h"

#include <math.h>
#include <string.h>

#define MAPS 5

typedef struct far_maps {
    const adi_request *r;
    float *radius;      /* |CoC| / 2 where the pixel blurs, else 0                    */
    float *weight;      /* minus the distance to the nearest edge, then the weight    */
    float *reach;       /* the largest (reach - distance) of any edge                  */
    float *layered;     /* as weight, counting the sharp edges only: the slices' share */
    float *sharp_reach; /* as reach, of the sharp edges                                */
    uint64_t *chunk_pixels, *chunk_layered;
    float *chunk_radius;
    int slices; /* the layered maps are wanted */
} far_maps;

/* The radius map and the seeds of the two distance maps. */
static void seed_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    (void)chunk;
    const far_maps *m = user;
    const adi_request *r = m->r;
    const uint32_t w = r->width, h = r->height;
    static const int nx[4] = {-1, 1, 0, 0}, ny[4] = {0, 0, -1, 1};
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            const float c = adi_request_coc(r, x, y), a = fabsf(c);
            m->radius[i] = a > 0.0f && a >= r->in_focus_px ? 0.5f * a : 0.0f;
            float reach = FAR_NO_EDGE, sharp = FAR_NO_EDGE;
            for (int k = 0; k < 4; k++) {
                const int64_t qx = (int64_t)x + nx[k], qy = (int64_t)y + ny[k];
                if (qx < 0 || qy < 0 || qx >= (int64_t)w || qy >= (int64_t)h)
                    continue;
                const float q = adi_request_coc(r, (uint32_t)qx, (uint32_t)qy);
                if (fabsf(q - c) < FAR_EDGE_STEP_PX)
                    continue;
                const float edge_reach = 0.5f * ddof_maxf(a, fabsf(q)) + 1.0f;
                reach = ddof_maxf(reach, edge_reach);
                if (ddof_minf(a, fabsf(q)) < FAR_BLURRED_PX)
                    sharp = ddof_maxf(sharp, edge_reach);
            }
            m->weight[i] = reach > FAR_NO_EDGE ? 0.0f : FAR_NO_EDGE;
            m->reach[i] = reach;
            m->layered[i] = sharp > FAR_NO_EDGE ? 0.0f : FAR_NO_EDGE;
            m->sharp_reach[i] = sharp;
        }
}

static void weight_rows(void *user, uint32_t y0, uint32_t y1, uint32_t chunk)
{
    const far_maps *m = user;
    const uint32_t w = m->r->width;
    uint64_t pixels = 0, layered = 0;
    float largest = 0.0f;
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            const float rho = m->radius[i];
            const float room = ddof_minf(-m->weight[i] - rho - 1.0f, -m->reach[i]);
            const float weight = rho > 0.0f ? ddof_minf(ddof_maxf(room / FAR_RAMP_PX, 0.0f), 1.0f)
                                            : 0.0f;
            float share = 0.0f;
            if (m->slices && rho > 0.0f && weight < 1.0f) {
                const float open = ddof_minf(-m->layered[i] - rho - 1.0f, -m->sharp_reach[i]);
                share = ddof_minf(ddof_maxf(open / FAR_RAMP_PX, 0.0f), 1.0f);
            }
            m->weight[i] = weight;
            m->layered[i] = share;
            if (weight > 0.0f || share > 0.0f) {
                pixels++;
                largest = ddof_maxf(largest, rho);
            }
            layered += share > 0.0f;
        }
    m->chunk_pixels[chunk] = pixels;
    m->chunk_layered[chunk] = layered;
    m->chunk_radius[chunk] = largest;
}

/* The four distance maps are independent: one dilation per task, side by side. */
static void dilate_task(void *user, uint32_t task, uint32_t thread)
{
    (void)thread;
    const far_maps *m = user;
    float *const maps[4] = {m->weight, m->reach, m->layered, m->sharp_reach};
    ddof_cone_dilate(maps[task], m->r->width, m->r->height, m->r->width, 1.0f);
}

ddof_status ddof_far_field(ddof_context *context, const adi_request *r, const float *color,
                           size_t color_stride, int slices, far_field_report *report)
{
    memset(report, 0, sizeof *report);
    const size_t pixels = (size_t)r->width * r->height;
    const uint32_t chunks = ddof_row_chunks(r->height);
    uint64_t *chunk_pixels = ddof_scratch_get(
        context, DDOF_SCRATCH_FAR_FIELD_MAPS,
        (size_t)chunks * (2 * sizeof(uint64_t) + sizeof(float)) + MAPS * pixels * sizeof(float));
    if (!chunk_pixels)
        return ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY,
                         "could not allocate the far field's %ux%u maps", r->width, r->height);
    uint64_t *chunk_layered = chunk_pixels + chunks;
    float *chunk_radius = (float *)(void *)(chunk_layered + chunks);
    float *maps = chunk_radius + chunks;
    far_maps m = {.r = r, .radius = maps, .weight = maps + pixels, .reach = maps + 2 * pixels,
                  .layered = maps + 3 * pixels, .sharp_reach = maps + 4 * pixels,
                  .chunk_pixels = chunk_pixels, .chunk_layered = chunk_layered,
                  .chunk_radius = chunk_radius, .slices = slices};
    ddof_parallel_rows(context, r->height, seed_rows, &m);
    thread_pool_run(context->pool, slices ? 4 : 2, dilate_task, &m, NULL, NULL);
    ddof_parallel_rows(context, r->height, weight_rows, &m);
    float largest = 0.0f;
    uint64_t layered = 0;
    for (uint32_t c = 0; c < chunks; c++) {
        report->pixels += chunk_pixels[c];
        layered += chunk_layered[c];
        largest = ddof_maxf(largest, chunk_radius[c]);
    }
    if (!report->pixels)
        return DDOF_OK;
    ddof_status status = DDOF_OK;
    if (layered) {
        far_layers_report sliced;
        status = ddof_far_layers(context, r, color, color_stride, m.radius, m.layered, largest,
                                 &sliced);
        if (status != DDOF_OK)
            return status;
        report->layered_pixels = sliced.pixels;
        report->slices = sliced.slices;
    }
    far_gather g = {.r = r, .color = color, .color_stride = color_stride, .radius = m.radius,
                    .weight = m.weight};
    status = ddof_far_field_gather(context, &g, largest);
    report->levels = g.level_count;
    return status;
}
