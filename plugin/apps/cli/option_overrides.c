/* SPDX-License-Identifier: MIT */
/* option_overrides.c - what the options given do to the whole: the library's preset < flags,
 * the camera sidecar < flags, each option as its kind says (option_values.c), over the table
 * (option_table.c). */
#include "option_table.h"

void cli_options_override_params(const cli_options *o, ddof_params *params)
{
    for (size_t i = 0; i < cli_option_count; i++)
        cli_option_override_params(&cli_option_table[i], o, params);
}

void cli_options_override_camera(const cli_options *o, ddof_camera *camera)
{
    for (size_t i = 0; i < cli_option_count; i++)
        cli_option_override_camera(&cli_option_table[i], o, camera);
}
