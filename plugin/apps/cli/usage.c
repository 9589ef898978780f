/* SPDX-License-Identifier: MIT */
/* usage.c - `ddof --help`: the prose around the options, and the options themselves as the
 * table (option_table.c) describes them. */
#include "option_table.h"
#include "options.h"

#include <stdio.h>
#include <string.h>

/* The help column: a name and placeholder longer than this pushes its first line right. */
#define HELP_COLUMN 26

static const char *const section_titles[CLI_SECTION_COUNT_] = {
    [CLI_SECTION_INPUT] = "Input channels (found automatically; name them when a file is "
                          "ambiguous):\n",
    [CLI_SECTION_COC] = "Circle of confusion (one source; default: camera):\n",
    [CLI_SECTION_QUALITY] = "Quality, method, solver, backend:\n",
    [CLI_SECTION_LAYERS] = "Layers (Kass et al. 3.1, 3.2; the planner runs them when the scene "
                           "calls for them;\nmodes and levels default to the preset's):\n",
    [CLI_SECTION_OUTPUT] = "Output:\n",
    [CLI_SECTION_REPORTING] = "Sequences and reporting:\n",
};

static void print_intro(FILE *to)
{
    fputs("usage: ddof IN.exr -o OUT.exr [--camera CAMERA.json | camera flags | --curve ... |\n"
          "                               --coc-channel NAME] [options]\n"
          "       ddof render_####.exr -o dof_####.exr --frames 1-240 [options]\n"
          "       ddof --list IN.exr\n"
          "\n"
          "Depth of field for a pinhole render (linear colour + depth) by simulated heat "
          "diffusion.\n"
          "Reads Blender's multilayer EXR (ViewLayer.Combined.RGBA + ViewLayer.Depth.Z) or a "
          "single\n"
          "layer (R, G, B, A, Z). With no quality options it uses the default preset.\n",
          to);
}

/* "  -o, --output FILE.exr   the result ...", continued lines under the help column. */
static void print_option(FILE *to, const cli_option *option)
{
    char placeholder[256], left[320];
    const char *line = option->help;
    int width;
    cli_option_placeholder(option, placeholder, sizeof placeholder);
    snprintf(left, sizeof left, "%s%s%s%s%s", option->short_name ? option->short_name : "",
             option->short_name ? ", " : "", option->name, placeholder[0] ? " " : "",
             placeholder);
    width = fprintf(to, "  %s", left);
    fprintf(to, "%*s", width < HELP_COLUMN ? HELP_COLUMN - width : 2, "");
    while (line) {
        const char *end = strchr(line, '\n');
        const int length = end ? (int)(end - line) : (int)strlen(line);
        fprintf(to, "%.*s\n", length, line);
        line = end ? end + 1 : NULL;
        if (line)
            fprintf(to, "%*s", HELP_COLUMN, "");
    }
}

static void print_exit_statuses(FILE *to)
{
    fputs("Exit status: 0 all frames written; 1 some frame failed (listed at the end); 2 usage "
          "error;\n"
          "3 the backend is unavailable or cannot run the solver or precision asked for;\n"
          "129/130/141/143 interrupted by SIGHUP/SIGINT/SIGPIPE (or a closed stdout)/SIGTERM\n"
          "(temporary files removed).\n",
          to);
}

/* One preset's line. The values are the library's (the accuracy study writes them): asked,
 * never copied. */
static void print_preset(FILE *to, ddof_preset preset, const ddof_params *p)
{
    const char *background = cli_choice_name(&cli_choices_layer_mode, (int)p->background);
    const char *near_spread = cli_choice_name(&cli_choices_layer_mode, (int)p->near_spread);
    const char *near_layer = cli_choice_name(&cli_choices_layer_mode, (int)p->near_layer);
    const char *far_field = cli_choice_name(&cli_choices_layer_mode, (int)p->far_field);
    const char *split = cli_choice_name(&cli_choices_layer_mode, (int)p->silhouettes);
    const char *edges = cli_choice_name(&cli_choices_layer_mode, (int)p->blurred_edges);
    const char *levels = p->background_levels == 1 ? "" : "s";
    fprintf(to, "  %-8s %s", ddof_preset_name(preset),
            cli_choice_name(&cli_choices_method, (int)p->method));
    if (p->method == DDOF_METHOD_DIFFUSION && p->kernel != DDOF_KERNEL_HEAT)
        fprintf(to, ", %s, %s kernel, background %s (%u level%s), near layer %s, near spread %s, "
                "far field %s, blurred edges %s, silhouettes %s",
                ddof_solver_name(p->solver), ddof_kernel_name(p->kernel), background,
                p->background_levels, levels, near_layer, near_spread, far_field, edges, split);
    else if (p->method == DDOF_METHOD_DIFFUSION)
        fprintf(to, ", %s, %u sub-step%s, k %g, background %s (%u level%s), near layer %s, "
                "near spread %s, far field %s, blurred edges %s, silhouettes %s",
                ddof_solver_name(p->solver), p->substeps, p->substeps == 1 ? "" : "s",
                (double)p->beta_scale, background, p->background_levels, levels, near_layer,
                near_spread, far_field, edges, split);
    fputc('\n', to);
}

void cli_usage(FILE *to)
{
    int section, preset;
    size_t i;
    print_intro(to);
    for (section = 0; section < CLI_SECTION_COUNT_; section++) {
        fprintf(to, "\n%s", section_titles[section]);
        for (i = 0; i < cli_option_count; i++)
            if (cli_option_table[i].section == (cli_option_section)section)
                print_option(to, &cli_option_table[i]);
    }
    fputc('\n', to);
    print_exit_statuses(to);
    fprintf(to, "\nPresets of this libddof (%s):\n", ddof_version_string());
    for (preset = 0; preset < DDOF_PRESET_COUNT_; preset++) {
        ddof_params params;
        if (ddof_params_init_preset(&params, (ddof_preset)preset) == DDOF_OK)
            print_preset(to, (ddof_preset)preset, &params);
    }
}
