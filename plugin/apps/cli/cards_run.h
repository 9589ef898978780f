/* SPDX-License-Identifier: MIT */
/* cards_run.h - --cards: one frame of a scene of textured cards (cards_scene.h) rendered by
 * ddof_render_cards and written as an EXR. */
#ifndef DDOF_CLI_CARDS_RUN_H
#define DDOF_CLI_CARDS_RUN_H

#include "options.h"

/* Bad input is exit 2 with nothing written; a failed write exit 1. Returns the exit status. */
int cards_run(const cli_options *o);

#endif

