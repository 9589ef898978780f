/* SPDX-License-Identifier: MIT */
/* cards.h - the per-polygon depth of field (ddof_render_cards): a card reduced to what drawing
 * it needs, shared by the checks (cards.c), the ordering (cards_order.c) and the drawing
 * (cards_draw.c). All in double: the geometry decides which pixels a card covers. */
#ifndef DDOF_CARDS_H
#define DDOF_CARDS_H

#ifndef DDOF_EXPERIMENTAL
#define DDOF_EXPERIMENTAL
#endif
#include "ddof_backend_seam.h"
#include "runtime/internal.h"

#define CARDS_MAX_STRIPS 64u    /* ddof_cards_params.strips at most */
#define CARDS_DEFAULT_STRIPS 8u /* and by default */

/* The screen: continuous pixel coordinates (x right, y down, pixel (i, j) covers
 * [i, i+1) x [j, j+1)) and the camera's CoC. A ray through screen point (x, y) has the
 * direction (ray_a x + ray_bx, -(ray_c y) + ray_by, -1), so planar depth Z = n.O / n.D. */
typedef struct cards_view {
    double ray_a, ray_bx, ray_c, ray_by;
    double k_px;        /* CoC diameter in horizontal pixels of a point at infinity */
    double focus_m;     /* S1 */
    double aspect;      /* pixel width / height: a CoC of d px spans d * aspect rows */
    uint32_t width, height;
} cards_view;

/* One checked card. */
typedef struct card_setup {
    uint32_t index;                  /* in the caller's list, for messages */
    uint32_t n;                      /* vertices */
    double p[DDOF_CARD_MAX_VERTICES][3];
    double normal[3], origin[3];     /* unit normal, centroid (n.origin != 0: not edge-on) */
    double e1[3], e2[3];             /* the plane's axes */
    double uv[DDOF_CARD_MAX_VERTICES][2]; /* the caller's texture coordinates */
    double uv_affine[2][3];          /* u, v = a0 + a1 s + a2 q with s, q along e1, e2 */
    double texel_reach_m;            /* half a texel's diagonal on the card, metres: how far a
                                        texel whose centre is in the card reaches out of it */
    double screen[DDOF_CARD_MAX_VERTICES][2]; /* projected vertices */
    double expanded[DDOF_CARD_MAX_VERTICES][2]; /* counter-clockwise on screen (y down) */
    double box[4];                   /* expanded bounds: x0, y0, x1, y1 */
    int visible;                     /* 0: edge-on, or nothing on the image */
    ddof_image_in texture;
    size_t texture_stride;           /* floats */
} card_setup;

/* Checks card `c` and fills `s` (visible 0 when it draws nothing); a failure names it. */
ddof_status cards_setup(ddof_context *context, const cards_view *view,
                        const ddof_cards_params *params, const ddof_card *card, uint32_t index,
                        card_setup *s);

/* Fills c->expanded, c->box and c->visible from c->screen (cards_order.c). */
void cards_expand(const cards_view *view, const ddof_cards_params *params, card_setup *c);

/* The drawing order, far to near, into `order` (count entries); an error names the cards. */
ddof_status cards_order(ddof_context *context, const card_setup *cards, uint32_t count,
                        uint32_t *order);

/* A card's summed-area tables (cards_table.c), kept from card to card of one frame. */
typedef struct card_table {
    double *sum;     /* (tw + 1) x (th + 1) x 4: texels in rows < j, columns < i */
    uint32_t *count; /* (tw + 1) x (th + 1): of those, texels not wholly zero */
    size_t capacity; /* cells allocated */
    uint32_t tw, th;
} card_table;

/* Builds card `c`'s tables into `t`, growing it as needed. */
ddof_status cards_table_build(ddof_context *context, const card_setup *c, card_table *t);
void cards_table_free(ddof_context *context, card_table *t);

/* The visible cards of `order` (far to near) drawn into out by the context's backend, or by
 * the CPU's where its device does not draw them (cards_request.c: the seam's request). */
ddof_status cards_render(ddof_context *context, const cards_view *view,
                         const ddof_cards_params *params, const card_setup *setups,
                         const uint32_t *order, uint32_t count, const ddof_image *out,
                         size_t out_stride);

/* The CPU table's render_cards (cards_draw.c): the request's cards drawn into its out, which
 * it writes whole; a failure is recorded in the context. */
ddof_status ddof_draw_cards_on_cpu(ddof_context *context, const adi_cards_request *request);

#define CARDS_PI 3.14159265358979323846

#endif
