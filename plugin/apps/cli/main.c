/* SPDX-License-Identifier: MIT */
/* main.c - `ddof`: depth of field for EXR renders and frame sequences (docs/cli.md).
 *
 * Order of work: signals first (so that every later thread inherits the blocked mask), then
 * options; everything that can be checked once (camera values, output directories, output !=
 * input) is checked before the first frame is read (run_setup.c), so that a 240-frame job with
 * a typo fails in a second, not after frame 1 or frame 240; then the frames (sequence.c, each
 * one frame_job.c), the report (report.c) and the --stats file. --cards and --list are runs of
 * their own (cards_run.c, list.c). */
#include "cards_run.h"
#include "cli_clock.h"
#include "list.h"
#include "option_table.h"
#include "options.h"
#include "output_file.h"
#include "progress.h"
#include "report.h"
#include "run_setup.h"
#include "sequence.h"
#include "stats_json.h"

#include <ddof.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The frames, their report and the --stats file. Returns the exit status. */
static int run_frames(const cli_options *o)
{
    frame_setup setup;
    frame_paths *paths = NULL;
    frame_result *results = NULL;
    sequence_plan plan;
    progress *bar = NULL;
    char error[2048];
    uint64_t pixels = 0;
    double t0;
    int count = 0, failed, stats_failed = 0;
    const int rc = run_setup_prepare(o, &setup, &paths, &count, &pixels);

    if (rc != 0)
        return rc;
    plan = sequence_plan_for(o, count, pixels);
    results = calloc((size_t)count, sizeof *results);
    bar = progress_create(count > 1 && (o->progress == PROGRESS_ALWAYS ||
                                        (o->progress == PROGRESS_AUTO && isatty(STDERR_FILENO))),
                          count, (int)plan.jobs);
    if (!results || !bar) {
        fprintf(stderr, "ddof: out of memory\n");
        free(paths);
        free(results);
        free(setup.aperture_pixels);
        progress_free(bar);
        return CLI_EXIT_FAILED;
    }
    report_plan(o, count, &plan);

    t0 = cli_now();
    failed = sequence_run(&setup, paths, results, count, &plan, bar, error, sizeof error);
    progress_finish(bar);
    if (failed < 0) {
        fprintf(stderr, "ddof: %s\n", error);
        failed = count;
    }
    report_frame_notes(paths, results, count);
    if (o->stats_path &&
        stats_json_write(o->stats_path, &setup, paths, results, count, plan.jobs,
                         plan.threads_per_frame, cli_now() - t0, error, sizeof error) != 0) {
        /* The frames are not to blame: said apart from them. */
        fprintf(stderr, "ddof: --stats: %s\n", error);
        stats_failed = 1;
    }
    report_summary(o, paths, results, count, failed, cli_now() - t0);
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        if (errno == EPIPE)
            output_broken_pipe("standard output");
        /* Closed (>&-), full or failing: the frames' lines are lost, so the run failed. */
        fprintf(stderr, "ddof: cannot write the standard output%s%s: the frames' report is "
                "lost\n", errno ? ": " : "", errno ? strerror(errno) : "");
        stats_failed = 1;
    }
    free(paths);
    free(results);
    free(setup.aperture_pixels);
    progress_free(bar);
    return failed > 0 || stats_failed ? CLI_EXIT_FAILED : CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    cli_options options;
    int rc;
    if (output_signals_install() != 0) {
        fprintf(stderr, "ddof: cannot set up signal handling\n");
        return CLI_EXIT_FAILED;
    }
    rc = cli_parse_options(argc, argv, &options);
    if (rc != 0)
        rc = rc > 0 ? CLI_EXIT_OK : CLI_EXIT_USAGE;
    else if (options.cards_json)
        rc = cards_run(&options);
    else if (options.list_only)
        rc = list_run(&options);
    else
        rc = run_frames(&options);
    output_signals_shutdown();
    return rc;
}
