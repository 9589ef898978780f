/* SPDX-License-Identifier: MIT */
/* options.h - the `ddof` command line parsed into cli_options (cli_options.h) with the table of
 * options (option_table.h), and the usage text. */
#ifndef DDOF_CLI_OPTIONS_H
#define DDOF_CLI_OPTIONS_H

#include "cli_options.h"

#include <stdio.h>

/* Parses argv with the table of options (option_table.h). Returns 0 to run, 1 when it printed
 * help or the version (exit 0), or -1 after printing a usage error to stderr (exit 2). */
int cli_parse_options(int argc, char **argv, cli_options *options);

/* Whether the frame gets a camera: the CoC's (a camera source), or, with --coc-channel, the
 * aperture's alone (--camera or an aperture flag: a renderer's CoC pass has a lens shape too). */
int cli_options_camera_wanted(const cli_options *o);

/* The usage text, from the table of options (usage.c). */
void cli_usage(FILE *to);

#endif
