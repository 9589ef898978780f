/* SPDX-License-Identifier: MIT */
/* fuzz_camera_json.c - the camera sidecar parser (camera_json.c, cJSON underneath) on fuzzed
 * text. An accepted sidecar must hold the values the schema promises. */
#include "camera_json.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    camera_sidecar sidecar;
    char error[1024];
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    if (camera_sidecar_parse(text, size, "fuzz.json", &sidecar, error, sizeof error) == 0) {
        const ddof_camera *c = &sidecar.camera;
        if (!(c->focal_length_mm > 0.0 && isfinite(c->focal_length_mm) &&
              c->sensor_width_mm > 0.0 && c->fstop > 0.0 && c->focus_distance_m > 0.0 &&
              c->pixel_aspect > 0.0 && c->depth_unit_m > 0.0 && sidecar.resolution[0] >= 1 &&
              sidecar.resolution[1] >= 1 && (unsigned)c->sensor_fit <= 2u)) {
            fprintf(stderr, "fuzz_camera_json: accepted an impossible camera\n");
            abort();
        }
    } else if (!error[0]) {
        fprintf(stderr, "fuzz_camera_json: refused without a message\n");
        abort();
    }
    free(text);
    return 0;
}
