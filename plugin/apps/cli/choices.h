/* SPDX-License-Identifier: MIT */
/* choices.h - the named values an option can take (--solver thomas, --background on, ...),
 * each list written once: from the library's name functions where it has them, else here.
 * The usage text, the parser's messages and the --stats report all spell values through
 * these lists, so a value added to the library shows up everywhere at once. */
#ifndef DDOF_CLI_CHOICES_H
#define DDOF_CLI_CHOICES_H

#include <stddef.h>

typedef struct cli_choices {
    /* The name of value 0 .. count-1; NULL for a value the command does not offer (the
     * host-GL backend needs a host's GL context; the EXR uint pixel type holds no colour). */
    const char *(*name_of)(int value);
    int count;
} cli_choices;

/* From the library (ddof_*_name up to the enum's COUNT_). */
extern const cli_choices cli_choices_preset;  /* ddof_preset */
extern const cli_choices cli_choices_solver;  /* ddof_solver */
extern const cli_choices cli_choices_kernel;  /* ddof_kernel */
extern const cli_choices cli_choices_backend; /* ddof_backend_kind, without HOST_GL */
/* Enums of ddof.h that have no name function: the command's names, in the enum's order. */
extern const cli_choices cli_choices_method;      /* ddof_method: diffusion, cod4 */
extern const cli_choices cli_choices_precision;   /* ddof_precision */
extern const cli_choices cli_choices_layer_mode;  /* ddof_layer_mode: auto, off, on */
extern const cli_choices cli_choices_sensor_fit;  /* ddof_sensor_fit */
extern const cli_choices cli_choices_depth_kind;  /* ddof_depth_kind */
extern const cli_choices cli_choices_lens;        /* ddof_lens_model */
/* The EXR side and the command's own. */
extern const cli_choices cli_choices_pixel_type;  /* exrio_pixel_type, without UINT */
extern const cli_choices cli_choices_compression; /* exrio_compression it can write */
extern const cli_choices cli_choices_progress;    /* progress_mode */

/* The name of value, or "?" when it has none (for reports, which must print something). */
const char *cli_choice_name(const cli_choices *choices, int value);

/* The value whose name is text (any case), or -1. */
int cli_choice_find(const cli_choices *choices, const char *text);

/* The names joined by separator ("a|b|c" for the usage, " | " for messages); cut short,
 * never overrun, when out is too small. */
void cli_choice_list(const cli_choices *choices, const char *separator, char *out,
                     size_t out_size);

#endif
