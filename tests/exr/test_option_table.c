/* SPDX-License-Identifier: MIT */
/* test_option_table.c - walks the `ddof` command's table of options (option_table.h): every
 * option is in the usage text with its placeholder and help; each parses with a valid value,
 * in both spellings (--name value, --name=value), and changes what it says it changes (the
 * options, the preset's params, the sidecar's camera, the --stats settings); each refuses a
 * bad value with a message that names it. Runs the parser in this process, its stderr and
 * stdout caught in files of the scratch folder.
 *
 *   test_option_table SCRATCH_DIR */
#include "exr_test_util.h"
#include "option_table.h"
#include "options.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *dir;

/* What cli_parse_options printed to one stream (1 or 2) is caught in dir/caught.txt. */
typedef struct caught {
    int fd, saved;
} caught;

static caught catch_begin(int fd)
{
    caught c = {fd, -1};
    const int file = open(test_path(dir, "caught.txt"), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    fflush(fd == 1 ? stdout : stderr);
    if (file < 0)
        return c;
    c.saved = dup(fd);
    dup2(file, fd);
    close(file);
    return c;
}

/* The text caught (free it). */
static char *catch_end(caught c)
{
    char *text;
    fflush(c.fd == 1 ? stdout : stderr);
    if (c.saved >= 0) {
        dup2(c.saved, c.fd);
        close(c.saved);
    }
    text = test_read_file(test_path(dir, "caught.txt"), NULL);
    return text ? text : calloc(1, 1);
}

/* Parses argv (NULL-terminated), its stderr caught into *err (free it; NULL: not kept). */
static int parse(const char *const *args, cli_options *o, char **err)
{
    char *argv[16];
    int argc = 0;
    caught c = catch_begin(2);
    char *text;
    int rc;
    while (args[argc] && argc < 15) {
        argv[argc] = (char *)args[argc];
        argc++;
    }
    argv[argc] = NULL;
    rc = cli_parse_options(argc, argv, o);
    text = catch_end(c);
    if (err)
        *err = text;
    else
        free(text);
    return rc;
}

/* A value the option takes that differs from its default (the last choice, 3, ...). */
static const char *valid_value(const cli_option *option, char *buffer, size_t size)
{
    int v;
    switch (option->kind) {
    case CLI_OPT_CHOICE:
        for (v = option->choices->count - 1; v >= 0; v--)
            if (option->choices->name_of(v))
                return option->choices->name_of(v);
        return "?";
    case CLI_OPT_UINT:
        snprintf(buffer, size, "%u", option->max ? option->max : option->min + 2);
        return buffer;
    case CLI_OPT_DOUBLE:
    case CLI_OPT_FLOAT:
        return "3";
    case CLI_OPT_STRING:
        return "some.exr";
    case CLI_OPT_OTHER:
        return option->example;
    default:
        return NULL;
    }
}

/* The argv that goes with one option: the input, --list (so that no -o or camera is needed;
 * not for --list itself; --cards takes -o instead of both), what the option needs beside it,
 * then "--name value" or "--name=value". */
static void build_argv(const cli_option *option, const char *value, int joined,
                       const char **args, char *joined_buffer, size_t size)
{
    int n = 0;
    args[n++] = "ddof";
    if (!strcmp(option->name, "--cards")) { /* its own input: an output instead */
        args[n++] = "-o";
        args[n++] = "out.exr";
    } else {
        args[n++] = "in.exr";
    }
    if (strcmp(option->name, "--list") != 0 && strcmp(option->name, "--cards") != 0)
        args[n++] = "--list";
    if (!strcmp(option->name, "--coc-signed")) {
        args[n++] = "--coc-channel";
        args[n++] = "C";
    }
    if (value && joined) {
        snprintf(joined_buffer, size, "%s=%s", option->name, value);
        args[n++] = joined_buffer;
    } else {
        args[n++] = option->name;
        if (value)
            args[n++] = value;
    }
    args[n] = NULL;
}

static void check_in_usage(const char *usage, const cli_option *option)
{
    char placeholder[256], line[512], help[128];
    const char *newline = strchr(option->help, '\n');
    cli_option_placeholder(option, placeholder, sizeof placeholder);
    snprintf(line, sizeof line, "  %s%s%s%s%s", option->short_name ? option->short_name : "",
             option->short_name ? ", " : "", option->name, placeholder[0] ? " " : "",
             placeholder);
    snprintf(help, sizeof help, "%.*s",
             newline ? (int)(newline - option->help) : (int)strlen(option->help), option->help);
    CHECK_MSG(strstr(usage, line) != NULL, "usage lacks '%s'", line);
    CHECK_MSG(option->help[0] && strstr(usage, help) != NULL, "usage lacks %s's help '%s'",
              option->name, help);
}

/* --name value and --name=value give the same options, and they differ from those without
 * the option. */
static void check_valid(const cli_option *option)
{
    const char *base_args[8], *args[8], *joined_args[8];
    char buffer[32], joined[128], *err = NULL;
    const char *value = valid_value(option, buffer, sizeof buffer);
    cli_options base, o, oj;
    ddof_params preset, params;
    ddof_camera camera0, camera;
    int n;

    build_argv(option, value, 0, args, joined, sizeof joined);
    memcpy(base_args, args, sizeof args);
    for (n = 0; args[n];)
        n++;
    base_args[n - (value ? 2 : 1)] = NULL; /* the same without the option under test */
    (void)parse(base_args, &base, NULL);
    CHECK_MSG(parse(args, &o, &err) == 0, "%s %s: %s", option->name, value ? value : "", err);
    free(err);
    CHECK_MSG(memcmp(&o, &base, sizeof o) != 0, "%s %s changes no option", option->name,
              value ? value : "");
    if (value) {
        build_argv(option, value, 1, joined_args, joined, sizeof joined);
        CHECK_MSG(parse(joined_args, &oj, NULL) == 0, "%s", joined);
        if (option->kind == CLI_OPT_STRING) {
            const char *a, *b;
            memcpy(&a, (const char *)&o + option->target, sizeof a);
            memcpy(&b, (const char *)&oj + option->target, sizeof b);
            CHECK_MSG(a && b && !strcmp(a, b), "%s", joined);
        } else {
            CHECK_MSG(memcmp(&o, &oj, sizeof o) == 0, "%s differs from %s %s", joined,
                      option->name, value);
        }
    }

    /* Given, it overrides the preset; not given (the defaults), it does not. */
    (void)ddof_params_init_preset(&preset, base.preset);
    params = preset;
    cli_options_override_params(&base, &params);
    CHECK_MSG(memcmp(&params, &preset, sizeof params) == 0, "%s: the default overrides",
              option->name);
    if (option->to_params) {
        (void)ddof_params_init_preset(&params, o.preset);
        cli_options_override_params(&o, &params);
        CHECK_MSG(memcmp(&params, &preset, sizeof params) != 0, "%s %s leaves the params",
                  option->name, value);
    }
    if (option->to_camera) {
        ddof_camera_init(&camera0);
        camera = camera0;
        cli_options_override_camera(&o, &camera);
        CHECK_MSG(memcmp(&camera, &camera0, sizeof camera) != 0, "%s %s leaves the camera",
                  option->name, value);
    }
    if (option->setting) {
        const cli_setting s = cli_option_setting(option, &o, &params);
        CHECK_MSG(s.type != CLI_SETTING_NONE, "%s: no setting %s", option->name,
                  option->setting);
        if (s.type == CLI_SETTING_TEXT && option->kind == CLI_OPT_CHOICE)
            CHECK_MSG(!strcmp(s.text, value), "%s: setting %s is %s, not %s", option->name,
                      option->setting, s.text, value);
    }
}

/* A bad value (or a value for a flag, or an empty one) is -1 with a message naming it. */
static void check_invalid(const cli_option *option)
{
    const char *args[8];
    char joined[128], want[160], *err = NULL;
    const char *bad = "bogus";
    cli_options o;
    if (option->kind == CLI_OPT_FLAG) {
        build_argv(option, "1", 1, args, joined, sizeof joined);
        snprintf(want, sizeof want, "ddof: %s takes no value", option->name);
    } else if (option->kind == CLI_OPT_STRING) {
        build_argv(option, "", 1, args, joined, sizeof joined);
        snprintf(want, sizeof want, "ddof: %s needs a non-empty value", option->name);
    } else {
        build_argv(option, bad, 0, args, joined, sizeof joined);
        snprintf(want, sizeof want, "ddof: %s wants ", option->name);
    }
    CHECK_MSG(parse(args, &o, &err) == -1 && strstr(err, want) &&
                  (option->kind == CLI_OPT_FLAG || option->kind == CLI_OPT_STRING ||
                   strstr(err, "not 'bogus'")),
              "%s: bad value: '%s'", option->name, err);
    free(err);
    if (option->kind != CLI_OPT_FLAG) { /* the value missing at the end */
        build_argv(option, NULL, 0, args, joined, sizeof joined);
        snprintf(want, sizeof want, "ddof: %s needs a value", option->name);
        CHECK_MSG(parse(args, &o, &err) == -1 && strstr(err, want), "%s: no value: '%s'",
                  option->name, err);
        free(err);
    }
}

/* Each spelling belongs to one option, each settings key to one. */
static void check_unique(void)
{
    size_t i, j;
    for (i = 0; i < cli_option_count; i++) {
        const cli_option *a = &cli_option_table[i];
        const char *spellings[3] = {a->name, a->short_name, a->alias};
        int k;
        for (k = 0; k < 3; k++)
            if (spellings[k])
                CHECK_MSG(cli_option_find(spellings[k]) == a, "%s is two options",
                          spellings[k]);
        for (j = i + 1; j < cli_option_count; j++)
            if (a->setting && cli_option_table[j].setting)
                CHECK_MSG(strcmp(a->setting, cli_option_table[j].setting) != 0,
                          "setting %s twice", a->setting);
    }
}

int main(int argc, char **argv)
{
    caught c;
    char *usage;
    size_t i;
    if (argc != 2) {
        fprintf(stderr, "usage: test_option_table SCRATCH_DIR\n");
        return 2;
    }
    dir = argv[1];
    test_fresh_dir(dir);

    c = catch_begin(1);
    cli_usage(stdout);
    usage = catch_end(c);
    check_unique();
    for (i = 0; i < cli_option_count; i++) {
        const cli_option *option = &cli_option_table[i];
        check_in_usage(usage, option);
        if (option->kind == CLI_OPT_HELP || option->kind == CLI_OPT_VERSION) {
            const char *args[] = {"ddof", option->name, NULL};
            cli_options o;
            char *out;
            c = catch_begin(1);
            CHECK_MSG(parse(args, &o, NULL) == 1, "%s", option->name);
            out = catch_end(c);
            CHECK_MSG(out[0] != '\0', "%s printed nothing", option->name);
            free(out);
            continue;
        }
        check_valid(option);
        check_invalid(option);
    }
    free(usage);
    printf("%zu options walked\n", cli_option_count);
    return test_finish("test_option_table");
}
