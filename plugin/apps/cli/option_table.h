/* SPDX-License-Identifier: MIT */
/* option_table.h - every option of the `ddof` command, described once: its spelling, its
 * argument, its help line, what it sets in cli_options, and where it shows in the --stats
 * settings. The usage text (usage.c), the parser (options.c), the preset/camera overrides
 * (main.c) and the report (stats_json.c) all walk this one table. */
#ifndef DDOF_CLI_OPTION_TABLE_H
#define DDOF_CLI_OPTION_TABLE_H

#include "choices.h"
#include "cli_options.h"

#include <stddef.h>
#include <stdint.h>

/* What an option's value is; it decides how the value is parsed, whether it was given, and
 * how the report writes it. */
typedef enum cli_option_kind {
    CLI_OPT_FLAG,    /* no value: the int at target becomes 1                               */
    CLI_OPT_STRING,  /* the argument itself, a const char * at target                       */
    CLI_OPT_CHOICE,  /* one of choices' names: an int-sized enum at target                  */
    CLI_OPT_DOUBLE,  /* a number within range: a double at target                           */
    CLI_OPT_FLOAT,   /* a number within range: a float at target                            */
    CLI_OPT_UINT,    /* a whole number within min..max: a uint32_t at target                */
    CLI_OPT_OTHER,   /* apply alone says what the value does                                */
    CLI_OPT_HELP,    /* prints the usage, exit 0                                            */
    CLI_OPT_VERSION  /* prints the version, exit 0                                          */
} cli_option_kind;

typedef enum cli_number_range {
    CLI_ANY_NUMBER = 0,
    CLI_POSITIVE,    /* > 0  */
    CLI_NON_NEGATIVE /* >= 0 */
} cli_number_range;

/* The usage's sections, in the order printed. */
typedef enum cli_option_section {
    CLI_SECTION_INPUT = 0,
    CLI_SECTION_COC,
    CLI_SECTION_QUALITY,
    CLI_SECTION_LAYERS,
    CLI_SECTION_OUTPUT,
    CLI_SECTION_REPORTING,
    CLI_SECTION_COUNT_
} cli_option_section;

typedef struct cli_option cli_option;

/* Applies value (NULL for a flag) to o; on a bad value prints why to stderr, returns -1. */
typedef int (*cli_option_apply_fn)(const cli_option *option, const char *value, cli_options *o);

struct cli_option {
    const char *name;          /* "--fstop"                                                 */
    const char *short_name;    /* "-o", or NULL                                             */
    const char *alias;         /* an older spelling still accepted, not shown; or NULL      */
    const char *arg;           /* the usage's placeholder ("MM"); NULL for a flag or choice */
    const char *help;          /* the usage's help, lines split by '\n'                     */
    cli_option_section section;
    cli_option_kind kind;
    size_t target;             /* offsetof(cli_options, ...): where the value goes          */
    const cli_choices *choices;/* CLI_OPT_CHOICE: the names                                  */
    cli_number_range range;    /* CLI_OPT_DOUBLE, CLI_OPT_FLOAT                              */
    uint32_t min, max;         /* CLI_OPT_UINT; max 0: no upper limit                        */
    int to_camera;             /* 1: target is a field of cli_options.camera, over the sidecar */
    int to_params;             /* 1: target is a field of cli_options.params, over the preset */
    const char *setting;       /* its key in the --stats "settings"; NULL: not reported     */
    cli_option_apply_fn apply; /* does the work instead of the kind's parse; or NULL        */
    const char *example;       /* CLI_OPT_OTHER: a valid value, for the table's own test   */
};

extern const cli_option cli_option_table[];
extern const size_t cli_option_count;

/* ddof_curve's six numbers by name, in the order --curve takes them and the --stats settings
 * write them. */
typedef struct cli_curve_number {
    const char *name;
    size_t field; /* offsetof(ddof_curve, ...): a double */
} cli_curve_number;

extern const cli_curve_number cli_curve_numbers[6];

/* The option spelled name (its name, short name or alias), or NULL. */
const cli_option *cli_option_find(const char *name);

/* The kind's parse: value into o at option->target. -1 after printing why to stderr. */
int cli_option_parse_value(const cli_option *option, const char *value, cli_options *o);

/* Prints "ddof: NAME wants WANT, not 'VALUE' (try --help)"; returns -1. */
int cli_option_bad_value(const cli_option *option, const char *value, const char *want);

/* The placeholder the usage shows: the option's arg, or its choices "a|b|c"; "" for a flag. */
void cli_option_placeholder(const cli_option *option, char *out, size_t out_size);

/* The offset in ddof_params (ddof_camera) of a to_params (to_camera) option's field. */
static inline size_t cli_option_params_field(const cli_option *option)
{
    return option->target - offsetof(cli_options, params);
}

static inline size_t cli_option_camera_field(const cli_option *option)
{
    return option->target - offsetof(cli_options, camera);
}

/* One option's kind applied to the whole (option_values.c): its value over the params' when
 * the user gave it; a camera value given as a flag (o->camera_given) over the sidecar's. Others
 * are left alone. */
void cli_option_override_params(const cli_option *option, const cli_options *o,
                                ddof_params *params);
void cli_option_override_camera(const cli_option *option, const cli_options *o,
                                ddof_camera *camera);

/* The same over every option of the table (option_overrides.c): the library's preset < flags,
 * the sidecar < flags. */
void cli_options_override_params(const cli_options *o, ddof_params *params);
void cli_options_override_camera(const cli_options *o, ddof_camera *camera);

/* An option's value as the --stats settings write it: from the resolved params for those
 * that override them (what ran, the preset's included), else the option's own value. */
typedef struct cli_setting {
    enum { CLI_SETTING_NONE, CLI_SETTING_TEXT, CLI_SETTING_NUMBER, CLI_SETTING_BOOL } type;
    const char *text;
    double number;
} cli_setting;

cli_setting cli_option_setting(const cli_option *option, const cli_options *o,
                               const ddof_params *params);

#endif
