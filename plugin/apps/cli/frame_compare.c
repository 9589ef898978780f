/* SPDX-License-Identifier: MIT */
/* frame_compare.c - the frame against its ground truth (frame_compare.h). */
#include "frame_compare.h"

#include "exrio_layout.h"
#include "frame_input.h"
#include "input_file.h"

#include <stdlib.h>
#include <string.h>

int frame_compare_with_truth(const frame_paths *paths, const float *color, const float *out,
                             int channels, const exrio_part *part, frame_result *result)
{
    exrio_image truth;
    exrio_layout layout;
    exrio_layout_request request;
    char error[1024];
    unsigned char *wanted;
    float *rgb;
    const size_t pixels = (size_t)part->width * part->height;
    int i;

    if (input_file_open_exr(paths->compare, "ground truth", &truth, error, sizeof error) != EXRIO_OK)
        return frame_fail(result, "ground truth: %s", error);
    memset(&request, 0, sizeof request);
    if (exrio_find_layout(&truth, &request, &layout, error, sizeof error) != EXRIO_LAYOUT_OK) {
        exrio_close(&truth);
        return frame_fail(result, "ground truth: %s", error);
    }
    if (!frame_same_window(&truth.parts[layout.part].data_window, &part->data_window)) {
        frame_fail(result, "ground truth %s is %ux%u, the input is %ux%u: mismatched sizes",
                   paths->compare, truth.parts[layout.part].width, truth.parts[layout.part].height,
                   part->width, part->height);
        exrio_close(&truth);
        return -1;
    }
    wanted = calloc((size_t)truth.channel_count, 1);
    if (!wanted) {
        exrio_close(&truth);
        return frame_fail(result, "out of memory");
    }
    for (i = 0; i < 3; i++)
        wanted[layout.color[i]] = 1;
    if (exrio_load(&truth, wanted, error, sizeof error) != EXRIO_OK) {
        free(wanted);
        exrio_close(&truth);
        return frame_fail(result, "ground truth: %s", error);
    }
    free(wanted);
    rgb = frame_interleave(&truth, layout.color, 3, pixels);
    exrio_close(&truth);
    if (!rgb)
        return frame_fail(result, "out of memory");
    compare_rgb(out, channels, rgb, 3, pixels, &result->error_result);
    compare_rgb(color, channels, rgb, 3, pixels, &result->error_input);
    result->compared = 1;
    free(rgb);
    return 0;
}
