/* SPDX-License-Identifier: MIT */
/* option_values.c - what an option's kind means: how its value is parsed into cli_options,
 * whether it was given, how it overrides the preset or the sidecar, and how the report
 * writes it. The table (option_table.c) says which kind each option is. */
#include "option_table.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A choice is stored in an enum field, read and written as an int: every enum the table
 * names must be int-sized. */
_Static_assert(sizeof(ddof_preset) == sizeof(int) && sizeof(ddof_backend_kind) == sizeof(int) &&
                   sizeof(ddof_method) == sizeof(int) && sizeof(ddof_kernel) == sizeof(int) &&
                   sizeof(ddof_solver) == sizeof(int) && sizeof(ddof_precision) == sizeof(int) &&
                   sizeof(ddof_layer_mode) == sizeof(int) &&
                   sizeof(ddof_sensor_fit) == sizeof(int) &&
                   sizeof(ddof_depth_kind) == sizeof(int) &&
                   sizeof(ddof_lens_model) == sizeof(int) &&
                   sizeof(exrio_compression) == sizeof(int) &&
                   sizeof(progress_mode) == sizeof(int),
               "choices are stored as int");

/* Bytes a value of the kind takes in cli_options (and in ddof_params, ddof_camera). */
static size_t value_size(cli_option_kind kind)
{
    switch (kind) {
    case CLI_OPT_FLAG:
    case CLI_OPT_CHOICE:
        return sizeof(int);
    case CLI_OPT_STRING:
        return sizeof(const char *);
    case CLI_OPT_DOUBLE:
        return sizeof(double);
    case CLI_OPT_FLOAT:
        return sizeof(float);
    case CLI_OPT_UINT:
        return sizeof(uint32_t);
    default:
        return 0;
    }
}

static void *field(cli_options *o, const cli_option *option)
{
    return (char *)o + option->target;
}

static const void *const_field(const cli_options *o, const cli_option *option)
{
    return (const char *)o + option->target;
}

int cli_option_bad_value(const cli_option *option, const char *value, const char *want)
{
    fprintf(stderr, "ddof: %s wants %s, not '%s' (try --help)\n", option->name, want, value);
    return -1;
}

static int in_range(double v, cli_number_range range)
{
    return range == CLI_POSITIVE ? v > 0.0 : range == CLI_NON_NEGATIVE ? v >= 0.0 : 1;
}

static int parse_number(const cli_option *option, const char *text, double *out)
{
    static const char *const wants[] = {"a number", "a number > 0", "a number >= 0"};
    char *end;
    double v;
    errno = 0;
    v = strtod(text, &end);
    /* Out of a double's range: said so, not "wants a number > 0" for 1e-400 or 1e999. A
     * subnormal (5e-324, ERANGE with a value) is a number: the checks that know the option's
     * own range (0.01..100 for --pixel-aspect) judge it and name it. */
    if (end != text && *end == '\0' && errno == ERANGE && (v == 0.0 || !isfinite(v))) {
        fprintf(stderr, "ddof: %s '%s' is %s than a double can hold (try --help)\n",
                option->name, text, v == 0.0 ? "closer to 0" : "larger");
        return -1;
    }
    if (end == text || *end != '\0' || (errno != 0 && errno != ERANGE) || !isfinite(v) ||
        !in_range(v, option->range))
        return cli_option_bad_value(option, text, wants[option->range]);
    *out = v;
    return 0;
}

static int parse_uint(const cli_option *option, const char *text, uint32_t *out)
{
    const uint32_t max = option->max ? option->max : 0xffffffffu;
    char *end;
    unsigned long v;
    errno = 0;
    v = strtoul(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || text[0] == '-' || v > 0xffffffffUL ||
        v < option->min || v > max) {
        char want[64];
        if (option->max)
            snprintf(want, sizeof want, "a whole number within %u..%u", option->min, max);
        else
            snprintf(want, sizeof want, "a whole number >= %u", option->min);
        return cli_option_bad_value(option, text, want);
    }
    *out = (uint32_t)v;
    return 0;
}

static int parse_choice(const cli_option *option, const char *text, int *out)
{
    const int v = cli_choice_find(option->choices, text);
    if (v < 0) {
        char names[256], want[272];
        cli_choice_list(option->choices, " | ", names, sizeof names);
        snprintf(want, sizeof want, "one of %s", names);
        return cli_option_bad_value(option, text, want);
    }
    *out = v;
    return 0;
}

static int parse_into(const cli_option *option, const char *value, cli_options *o)
{
    void *to = field(o, option);
    double number;
    int one = 1, choice;
    float single;
    switch (option->kind) {
    case CLI_OPT_FLAG:
        memcpy(to, &one, sizeof one);
        return 0;
    case CLI_OPT_STRING:
        memcpy(to, &value, sizeof value);
        return 0;
    case CLI_OPT_CHOICE:
        if (parse_choice(option, value, &choice) != 0)
            return -1;
        memcpy(to, &choice, sizeof choice);
        return 0;
    case CLI_OPT_DOUBLE:
        if (parse_number(option, value, &number) != 0)
            return -1;
        memcpy(to, &number, sizeof number);
        return 0;
    case CLI_OPT_FLOAT:
        if (parse_number(option, value, &number) != 0)
            return -1;
        single = (float)number;
        memcpy(to, &single, sizeof single);
        return 0;
    case CLI_OPT_UINT:
        return parse_uint(option, value, (uint32_t *)to);
    default:
        return 0; /* the help, the version and the others act in their apply or the parser */
    }
}

int cli_option_parse_value(const cli_option *option, const char *value, cli_options *o)
{
    if (parse_into(option, value, o) != 0)
        return -1;
    if (option->to_params)
        o->params_given[cli_option_params_field(option)] = 1;
    if (option->to_camera)
        o->camera_given[cli_option_camera_field(option)] = 1;
    return 0;
}

void cli_option_placeholder(const cli_option *option, char *out, size_t out_size)
{
    if (option->kind == CLI_OPT_CHOICE && !option->arg)
        cli_choice_list(option->choices, "|", out, out_size);
    else
        snprintf(out, out_size, "%s", option->arg ? option->arg : "");
}

void cli_option_override_params(const cli_option *option, const cli_options *o,
                                 ddof_params *params)
{
    if (option->to_params && cli_param_given(o, cli_option_params_field(option)))
        memcpy((char *)params + cli_option_params_field(option), const_field(o, option),
               value_size(option->kind));
}

void cli_option_override_camera(const cli_option *option, const cli_options *o,
                                ddof_camera *camera)
{
    if (option->to_camera && cli_camera_given(o, cli_option_camera_field(option)))
        memcpy((char *)camera + cli_option_camera_field(option), const_field(o, option),
               value_size(option->kind));
}

/* The number stored at `from` by an option of a numeric kind (UINT, FLOAT, DOUBLE). */
static double stored_number(cli_option_kind kind, const void *from)
{
    uint32_t count;
    float single;
    double number;
    switch (kind) {
    case CLI_OPT_UINT:
        memcpy(&count, from, sizeof count);
        return count;
    case CLI_OPT_FLOAT:
        memcpy(&single, from, sizeof single);
        return single;
    default:
        memcpy(&number, from, sizeof number);
        return number;
    }
}

cli_setting cli_option_setting(const cli_option *option, const cli_options *o,
                               const ddof_params *params)
{
    cli_setting s = {CLI_SETTING_NONE, NULL, 0.0};
    const void *from = option->to_params
                           ? (const char *)params + cli_option_params_field(option)
                           : const_field(o, option);
    int choice, flag;
    if (!option->setting)
        return s;
    switch (option->kind) {
    case CLI_OPT_FLAG:
        memcpy(&flag, from, sizeof flag);
        s.type = CLI_SETTING_BOOL;
        s.number = flag != 0;
        break;
    case CLI_OPT_STRING:
        memcpy(&s.text, from, sizeof s.text);
        s.type = s.text ? CLI_SETTING_TEXT : CLI_SETTING_NONE;
        break;
    case CLI_OPT_CHOICE:
        memcpy(&choice, from, sizeof choice);
        s.type = CLI_SETTING_TEXT;
        s.text = cli_choice_name(option->choices, choice);
        break;
    case CLI_OPT_UINT:
    case CLI_OPT_FLOAT:
    case CLI_OPT_DOUBLE:
        s.type = CLI_SETTING_NUMBER;
        s.number = stored_number(option->kind, from);
        break;
    default:
        break;
    }
    return s;
}
