/* SPDX-License-Identifier: MIT */
/* report.c - the run's report on stdout and stderr (report.h). */
#include "report.h"

#include <stdio.h>
#include <string.h>

/* "3, 7-9, 12" */
static void print_failed_frames(const frame_paths *paths, const frame_result *results, int count)
{
    int i = 0, first = 1, failed = 0;
    for (i = 0; i < count; i++)
        failed += !results[i].ok;
    i = 0;
    fprintf(stderr, "ddof: failed frame%s: ", failed > 1 ? "s" : "");
    while (i < count) {
        int j = i;
        if (results[i].ok) {
            i++;
            continue;
        }
        while (j + 1 < count && !results[j + 1].ok && paths[j + 1].frame == paths[j].frame + 1)
            j++;
        if (paths[i].frame < 0)
            fprintf(stderr, "%s%s", first ? "" : ", ", paths[i].input);
        else if (j > i)
            fprintf(stderr, "%s%d-%d", first ? "" : ", ", paths[i].frame, paths[j].frame);
        else
            fprintf(stderr, "%s%d", first ? "" : ", ", paths[i].frame);
        first = 0;
        i = j + 1;
    }
    fprintf(stderr, "\n");
}

static void print_comparison(const frame_paths *p, const frame_result *r)
{
    char prefix[32] = "";
    if (p->frame >= 0)
        snprintf(prefix, sizeof prefix, "frame %d: ", p->frame);
    printf("%serror against %s (RGB; RMSE and PSNR of sRGB-encoded values clamped to [0, 1], "
           "linear RMSE unclamped):\n", prefix, p->compare);
    printf("  ddof result    RMSE %.5f  PSNR %6.2f dB  linear RMSE %.5f\n",
           r->error_result.rmse_srgb, r->error_result.psnr_srgb, r->error_result.rmse_linear);
    printf("  pinhole input  RMSE %.5f  PSNR %6.2f dB  linear RMSE %.5f\n",
           r->error_input.rmse_srgb, r->error_input.psnr_srgb, r->error_input.rmse_linear);
}

void report_plan(const cli_options *o, int count, const sequence_plan *plan)
{
    char threads[32] = "all cores";
    if (count <= 1 || o->quiet)
        return;
    if (plan->threads_per_frame > 0)
        snprintf(threads, sizeof threads, "%u thread%s", plan->threads_per_frame,
                 plan->threads_per_frame == 1 ? "" : "s");
    printf("ddof: %d frames, %u at a time, %s per frame (%s)\n", count, plan->jobs, threads,
           plan->reason);
}

void report_frame_notes(const frame_paths *paths, const frame_result *results, int count)
{
    char last_warning[PATH_MAX + 512] = "";
    int i;
    for (i = 0; i < count; i++) {
        if (results[i].ok && results[i].warning[0] &&
            strcmp(results[i].warning, last_warning) != 0) {
            fprintf(stderr, "ddof: warning: %s\n", results[i].warning);
            snprintf(last_warning, sizeof last_warning, "%s", results[i].warning);
        }
        if (results[i].compared)
            print_comparison(&paths[i], &results[i]);
    }
}

void report_summary(const cli_options *o, const frame_paths *paths,
                    const frame_result *results, int count, int failed, double seconds)
{
    int i, skipped = 0;
    for (i = 0; i < count; i++)
        skipped += results[i].skipped;
    if (failed > 0) {
        if (count > 1)
            fprintf(stderr, "ddof: %d of %d frames failed\n", failed, count);
        print_failed_frames(paths, results, count);
    } else if (count > 1 && !o->quiet) {
        if (skipped > 0)
            printf("ddof: %d frame%s written, %d skipped (already complete) in %.2f s\n",
                   count - skipped, count - skipped == 1 ? "" : "s", skipped, seconds);
        else
            printf("ddof: %d frames written in %.2f s\n", count, seconds);
    }
}
