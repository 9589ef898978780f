/* SPDX-License-Identifier: MIT */
/* gl_cards.h - ddof_render_cards' cards drawn by the device (gl_cards.c). */
#ifndef DDOF_GL_CARDS_H
#define DDOF_GL_CARDS_H

#include "gl_device.h"

/* Draws the request's cards and reads the frame back into request->out; the device's context
 * must be current. On failure a status and a sentence in message. */
ddof_status gl_cards_render(ddof_device *device, const adi_cards_request *request,
                            char *message, size_t message_size);

#endif
