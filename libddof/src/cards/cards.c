/* SPDX-License-Identifier: MIT */
/* cards.c - ddof_render_cards: the camera's view, each card checked and reduced to its plane,
 * its uv map and its expanded screen polygon (docs/cards.md). */
#include "cards.h"

#include "backends/backend.h"
#include "camera/coc.h"
#include "ddof_camera_terms.h"

#include <math.h>
#include <string.h>

static cards_view view_of(const ddof_camera *camera, uint32_t width, uint32_t height)
{
    const ddof_camera_terms t = ddof_camera_terms_of(camera, width, height);
    /* Blender's camera: the frame's centre on the axis, a pixel pixel_w/f wide at unit depth. */
    return (cards_view){
        .ray_a = t.pixel_w_over_f,
        .ray_bx = (t.window_x - 0.5 * t.frame_width) * t.pixel_w_over_f,
        .ray_c = t.pixel_h_over_f,
        .ray_by = (0.5 * t.frame_height - t.window_y) * t.pixel_h_over_f,
        .k_px = t.k_px,
        .focus_m = camera->focus_distance_m,
        .aspect = camera->pixel_aspect,
        .width = width,
        .height = height,
    };
}

static ddof_status read_params(ddof_context *context, const ddof_cards_params *caller,
                               ddof_cards_params *p)
{
    ddof_cards_params_init_sized(p, sizeof *p);
    if (!caller)
        return DDOF_OK;
    ddof_status status = ddof_read_struct(context, caller, DDOF_CARDS_PARAMS_SIZE_0_5, p,
                                          sizeof *p, "cards params");
    if (status != DDOF_OK)
        return status;
    if ((unsigned)p->expansion > DDOF_CARDS_EXPAND_CENTROID || p->strips < 1 ||
        p->strips > CARDS_MAX_STRIPS)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER,
                         "cards params: expansion %u must be 0 or 1, strips %u within 1..%u",
                         (unsigned)p->expansion, p->strips, CARDS_MAX_STRIPS);
    return DDOF_OK;
}

/* A card's texture (validated by cards_setup) sharing no byte with the output: the CPU reads
 * the texture while it writes the output. */
static ddof_status check_texture_apart(ddof_context *context, const ddof_card *card,
                                       uint32_t index, const ddof_image *out)
{
    char what[48];
    snprintf(what, sizeof what, "card %u texture", index);
    const ddof_image_in *t = &card->texture;
    return ddof_check_apart(context, "the output image",
                            ddof_image_bytes_of(out->pixels, out->width, out->height,
                                                out->channels, out->row_stride),
                            what,
                            ddof_image_bytes_of(t->pixels, t->width, t->height, t->channels,
                                                t->row_stride));
}

static ddof_status check_out(ddof_context *context, const ddof_image *out, size_t *stride)
{
    if (!out)
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "out is NULL");
    ddof_status status = ddof_check_image(context, "out", out->pixels, out->width, out->height,
                                          out->channels, out->row_stride, stride);
    if (status == DDOF_OK && out->channels != 4)
        return ddof_fail(context, DDOF_ERROR_BAD_CHANNELS,
                         "out has %u channels; cards render premultiplied RGBA (4)",
                         out->channels);
    return status;
}

static ddof_status render_cards(ddof_context *context, const ddof_cards_params *params,
                                const ddof_camera *camera, const ddof_card *cards,
                                uint32_t card_count, const ddof_image *out)
{
    if (!camera || (!cards && card_count))
        return ddof_fail(context, DDOF_ERROR_NULL_POINTER, "camera or cards is NULL");
    ddof_cards_params p;
    ddof_camera cam;
    size_t out_stride = 0;
    ddof_status status = read_params(context, params, &p);
    if (status == DDOF_OK)
        status = ddof_read_camera(context, camera, &cam);
    if (status == DDOF_OK)
        status = check_out(context, out, &out_stride);
    if (status != DDOF_OK)
        return status;
    const cards_view view = view_of(&cam, out->width, out->height);
    card_setup *setups = NULL;
    uint32_t *order = NULL;
    if (card_count) {
        setups = ddof_alloc(&context->allocator, (size_t)card_count * sizeof *setups);
        order = ddof_alloc(&context->allocator, (size_t)card_count * sizeof *order);
        if (!setups || !order)
            status = ddof_fail(context, DDOF_ERROR_OUT_OF_MEMORY, "no memory for %u cards",
                               card_count);
    }
    for (uint32_t i = 0; status == DDOF_OK && i < card_count; i++) {
        status = cards_setup(context, &view, &p, &cards[i], i, &setups[i]);
        if (status == DDOF_OK)
            status = check_texture_apart(context, &cards[i], i, out);
    }
    if (status == DDOF_OK)
        status = cards_order(context, setups, card_count, order);
    if (status == DDOF_OK)
        status = cards_render(context, &view, &p, setups, order, card_count, out, out_stride);
    ddof_free(&context->allocator, setups);
    ddof_free(&context->allocator, order);
    return status;
}

ddof_status ddof_render_cards(ddof_context *context, const ddof_cards_params *params,
                              const ddof_camera *camera, const ddof_card *cards,
                              uint32_t card_count, const ddof_image *out)
{
    DDOF_EXCLUSIVE_CALL(context, render_cards(context, params, camera, cards, card_count, out));
}
