/* SPDX-License-Identifier: MIT */
/* cli_test.h - what the `ddof` command's tests share: the command run as a user runs it (its
 * output in the scratch folder's run.out and run.err), a small test scene written as EXR, and
 * the library called directly on the same data, for outputs checked bit for bit against it.
 * Each test_cli_<theme> program takes DDOF_BINARY CASE SCRATCH_DIR and runs one case. */
#ifndef DDOF_CLI_TEST_H
#define DDOF_CLI_TEST_H

#include "exr_test_util.h"

#include <ddof.h>

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define W 48
#define H 32
#define N ((size_t)W * H)

/* The command under test and the case's scratch folder, from the command line. */
extern const char *ddof_bin;
extern const char *dir;

/* Runs ddof with the NULL-terminated arguments; output in dir/run.out, dir/run.err. */
int ddof(const char *first, ...);
/* The last run's standard output and error (allocated; "" when missing). */
char *out_text(void);
char *err_text(void);
/* Whether the last run's stderr (stdout) holds `what`; prints it when not. */
int err_contains(const char *what);
int out_contains(const char *what);
/* Waits for a temporary file in `where` that stays (see cli_test.c). */
void wait_for_temp(const char *where);

typedef struct scene {
    float rgba[4][N]; /* planes R, G, B, A */
    float z[N];
    float coc[N];
} scene;

/* A chequered, coloured pattern over depths from 1 m to 20 m with a sharp band and a highlight;
 * `variant` shifts the chequer. */
void make_scene(scene *s, int variant);
/* Writes R, G, B, A, Z (and C, the CoC, when with_coc) as a FLOAT EXR. */
void write_scene(const char *path, const scene *s, int with_coc);

typedef enum { REF_CAMERA, REF_CURVE, REF_CHANNEL } ref_kind;

typedef struct reference {
    ref_kind kind;
    ddof_camera camera;
    ddof_curve curve;
    const char *preset;  /* ddof_params_init_preset by name; NULL: ddof_params_init */
    uint32_t substeps;   /* 0: the preset's */
    int heat_kernel;     /* 1: DDOF_KERNEL_HEAT (--kernel heat); 0: the preset's kernel */
    uint32_t aperture_blades; /* REF_CHANNEL: > 0 gives the frame a camera with that many
                               * blades (--aperture-blades), its aperture only */
} reference;

/* A 50 mm lens on a 36 mm sensor at this f-stop and focus distance. */
void camera_50mm(ddof_camera *c, double fstop, double focus);
/* The library on the scene as the command calls it; out: interleaved RGBA. */
void library_result(const scene *s, const reference *ref, float *out, ddof_stats *stats);
/* Differing values between an output EXR's R, G, B, A and an interleaved RGBA reference. */
int compare_output(const char *path, const float *ref, int exact, double tolerance, int half);

typedef struct cli_case {
    const char *name;
    int (*run)(void);
} cli_case;

/* Reads DDOF_BINARY CASE SCRATCH_DIR, empties the scratch folder and runs the case named. */
int cli_test_main(int argc, char **argv, const char *program, const cli_case *cases,
                  size_t count);

#endif
