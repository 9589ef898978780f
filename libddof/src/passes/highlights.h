/* SPDX-License-Identifier: MIT */
/* highlights.h - the highlight pass: the few brightest out-of-focus pixels drawn as discs, or as
 * the aperture's polygon.
 *
 * A disc kernel is a sum of complex chains whose rim rings (about -7% of the disc's height).
 * Next to an HDR highlight a hundred times brighter than its surroundings that ring is a dark
 * band (clamped to the input's range, so black) around every bokeh disc, and the separable
 * chains leave a faint cross. So the part of a highlight above a brightness threshold is taken
 * out of the image before the diffusion and scattered afterwards as a uniform, anti-aliased
 * disc of its CoC (Unreal's Diaphragm DOF does the same for its brightest pixels): the
 * diffusion only ever sees values up to the threshold, and the disc a lens draws is drawn
 * exactly. A disc costs its rows and its rim, not its area (highlights_find.c draws spans into a
 * difference image), and the pass is bounded: its discs may cost at most DDOF_HIGHLIGHT_BUDGET
 * pixel operations per frame pixel, the brightest highlights first (the threshold is raised in
 * quarter octaves until they fit; a frame whose brightest quarter octave alone is over the
 * budget, such as a bright sky, gets no disc and is left to the diffusion).
 *
 * The scatter keeps the diffusion's rules: a far highlight's disc lands only on pixels at
 * least half as blurred and on the far side (signed CoC >= half its own), so nothing is drawn
 * over in-focus or nearer pixels, and its weights are renormalised over the pixels it lands
 * on, so the light is kept as the diffusion keeps it at an insulator. A near highlight spreads
 * over everything behind it. Where a thin sharp occluder (a bar, a strand) cuts a far
 * highlight, the part it hides is filled in across it from the visible sides and drawn too, so
 * the lens' whole disc shows around the occluder (highlights_find.c: the hidden parts). Colour
 * channels only: alpha (channel 3 of 4) is left to the diffusion. A foreground element gets
 * the same pass on its own premultiplied colour (layers.c), its discs drawn into it before the
 * composite. */
#ifndef DDOF_HIGHLIGHTS_H
#define DDOF_HIGHLIGHTS_H

#include "adi/adi.h"
#include "ddof_highlight_rules.h"

#include <math.h>

/* A pixel's brightness for the pass: its largest colour channel (colour is checked finite
 * before any pass runs, so a plain compare does; fmaxf is a library call that orders NaNs, and
 * the pass's count takes it for nine neighbours of every candidate pixel). */
static inline float ddof_highlight_brightness(const float *rgb)
{
    return ddof_maxf(rgb[0], ddof_maxf(rgb[1], rgb[2]));
}

/* Whether a pixel of this brightness and CoC is a highlight (before the budget). */
static inline int ddof_is_highlight(float brightness, float coc, float threshold)
{
    return brightness > threshold && fabsf(coc) >= DDOF_HIGHLIGHT_MIN_COC_PX;
}

/* The aperture's shape for the pass: a disc (blades 0, 1 or 2, as Cycles), or a regular
 * polygon of 3..DDOF_MAX_APERTURE_BLADES blades inscribed in the disc, turned by rotation_rad
 * (Blender's aperture_rotation), or an image; clipped by the cat's eye. An ellipse (the
 * aperture ratio) is the request's pixel aspect. Zero: a disc. */
typedef struct highlight_aperture {
    uint32_t blades;
    double rotation_rad;
    /* Optical vignetting: the shape clipped by a circle of its radius R centred catseye x R x
     * (the highlight's distance from the frame's centre, 1 at its corners) toward that centre.
     * 0: off. The frame: its centre in the image's pixels and its half width and height (a
     * crop's frame is the full frame's). */
    double catseye;
    double centre_x, centre_y, half_width, half_height;
    /* A custom aperture (ddof_camera.aperture_image): replaces the blades; NULL: none. */
    const float *image;
    uint32_t image_width, image_height;
} highlight_aperture;

/* A highlight: the seam's adi_highlight (a pixel, the signed CoC its light is drawn with
 * (highlights_find.c: highlight_coc), its colour above the threshold, taken out before the
 * diffusion, and `hidden`: 1 for a part hidden by a sharp occluder, filled in (highlights_find.c),
 * whose disc is not renormalised: the occluder keeps its share, as a lens' disc behind a bar
 * loses the strip the bar covers). */
typedef adi_highlight highlight;

typedef struct highlight_set {
    highlight *items; /* sorted by row                                                */
    uint32_t count;
    float threshold;  /* the threshold that was applied (raised to fit the budget)     */
    uint64_t cost;    /* the discs' rows and rim pixels                                */
    int over_budget;  /* none drawn: the brightest class alone was over the budget     */
    float *weights;   /* scratch for the scatter: one per highlight                    */
    uint32_t *landing;/* scratch for the scatter: (width + 1) x height                 */
    const double *aperture_sums; /* the aperture image's summed-area table, scaled to a
                                    maximum of 1: (w + 1) x (h + 1); NULL without an image */
    uint32_t hidden;  /* of count: pixels of a sharp occluder that took a far highlight's
                         hidden part (highlights_find.c: the hidden parts)                  */
} highlight_set;

/* Finds the highlights of r (colour with 3 or 4 channels, its signed or unsigned CoC), a
 * highlight costing its rows and rim, or its area with an aperture image (aperture may be NULL):
 * pixels whose largest colour channel exceeds `threshold` and whose |CoC| >= the minimum
 * (aperture_sums: the aperture image's table from ddof_aperture_sums, or NULL),
 * and writes `base` (width x height x channels floats, packed) = the colour with their excess
 * taken out. set->count 0: none (base is then not written). Memory from the context.
 * The frame's (owner): where a sharp occluder (|CoC| < DDOF_HIGHLIGHT_SHARP_PX) at most a far
 * highlight's radius wide cuts it, the occluder's pixels get the hidden part, filled across
 * the occluder from the highlight's visible pixels, as extra highlights (within the budget);
 * their discs land, like any far disc, only around the occluder. */
/* Whose highlights a search finds: the frame's (hidden parts added; in
 * DDOF_SCRATCH_HIGHLIGHTS) or a foreground element's, read as its steps premultiply it
 * (ddof_element_pixel; none hidden; in DDOF_SCRATCH_ELEMENT_HIGHLIGHTS), so that both sets
 * live through the layers' run. */
typedef enum highlight_owner {
    HIGHLIGHTS_OF_ELEMENT = 0,          /* r->color: the element as given, premultiplied    */
    HIGHLIGHTS_OF_FRAME = 1,
    HIGHLIGHTS_OF_STRAIGHT_ELEMENT = 2, /* the element as given, its colour not premultiplied */
} highlight_owner;

/* A foreground element's pixel as its steps see it: alpha clamped to [0, 1], the colour
 * multiplied by it unless premultiplied, 0 where alpha is not positive (whatever the colour
 * holds there). */
static inline void ddof_element_pixel(const float *fg, int premultiplied, float out[4])
{
    const float alpha = ddof_minf(1.0f, ddof_maxf(0.0f, fg[3]));
    const float scale = premultiplied ? 1.0f : alpha;
    for (int c = 0; c < 3; c++)
        out[c] = alpha > 0.0f ? fg[c] * scale : 0.0f;
    out[3] = alpha;
}

ddof_status ddof_find_highlights(ddof_context *context, const adi_request *r, float threshold,
                                 int coc_signed, const double *aperture_sums,
                                 highlight_owner owner, float *base, highlight_set *set);

/* The aperture image's summed-area table, scaled so that its largest texel is 1: sums[j][i]
 * holds the texels of rows < j and columns < i ((w + 1) x (h + 1), the context's scratch);
 * NULL without an image (aperture->image NULL) or without memory (the error recorded). The
 * finds and draws of a frame take it (aperture_sums; NULL: none). */
const double *ddof_aperture_sums(ddof_context *context, const highlight_aperture *aperture);

/* ddof_find_highlights with base NULL finds the highlights without writing the base colour:
 * a run_layers request takes them out itself (ddof_take_out_highlights, or on a device). */

/* base = r's colour (width x height x channels floats, packed) with each found highlight's
 * excess taken out (not the hidden parts', which the colour never held): what
 * ddof_find_highlights writes into its base. */
void ddof_take_out_highlights(ddof_context *context, const adi_request *r,
                              const highlight *items, uint32_t count, float *base);

/* The set ddof_find_highlights made from its items (their allocation holds the scatter's
 * scratch after them), for ddof_scatter_highlights. */
highlight_set ddof_highlight_set_of(const highlight *items, uint32_t count,
                                    const double *aperture_sums);

/* Adds each highlight's excess to r->out as its disc (aperture NULL) or the aperture's shape.
 * scratch: width x height x 3 floats (the base image of ddof_find_highlights may serve: it is
 * not needed any more). */
void ddof_scatter_highlights(ddof_context *context, const adi_request *r, int coc_signed,
                             const highlight_aperture *aperture, const highlight_set *set,
                             float *scratch);

/* ddof_scatter_highlights of a run_layers request's highlights (ddof_find_highlights' items,
 * whose allocation holds the scatter's scratch) with its aperture. */
void ddof_draw_highlights(ddof_context *context, const adi_request *r, const adi_highlights *h,
                          float *scratch);

/* The image ddof_find_highlights writes its base colour into (the context's scratch, width x
 * height x channels floats), or NULL when it cannot be had. */
static inline float *ddof_highlight_base_image(ddof_context *context, const adi_request *r)
{
    return ddof_scratch_get(context, DDOF_SCRATCH_HIGHLIGHT_BASE,
                            (size_t)r->width * r->height * r->channels * sizeof(float));
}

#endif
