/* SPDX-License-Identifier: MIT */
/* test_gl_long_lines.c - lines up to DDOF_MAX_DIMENSION on a GL backend (issue 22): llvmpipe
 * ends a shader invocation's loops after 65,535 iterations in all, silently, so one invocation
 * per line (Thomas, the disc kernel's complex Thomas) went wrong from about 32,768 pixels on.
 * A row of 65,536 pixels and a column of 65,536, each with a bright point and a uniform CoC,
 * against the CPU (Thomas, the 2x2 disc, cyclic reduction); a line the device cannot solve
 * must be a clear DDOF_ERROR_UNSUPPORTED with the output untouched, never a wrong image with
 * DDOF_OK. Frame rows of 65,533..65,536 pixels through the Jacobi solver against the CPU.
 * Usage: test_gl_long_lines osmesa|egl [LENGTH...] */
#include "gl_test.h"

static int run_case(ddof_context *gl, ddof_context *cpu, uint32_t n, int column,
                    ddof_kernel kernel, ddof_solver solver)
{
    const uint32_t w = column ? 1 : n, h = column ? n : 1;
    float *color = malloc((size_t)n * sizeof *color), *coc = malloc((size_t)n * sizeof *coc);
    float *want = malloc((size_t)n * sizeof *want), *got = malloc((size_t)n * sizeof *got);
    int failed = 0;
    for (uint32_t i = 0; i < n; i++) {
        color[i] = (i % 4099u) == 7u ? 100.0f : 0.25f + 0.5f * (float)((i * 37u) % 101u) / 101.0f;
        coc[i] = 12.0f;
        got[i] = -1.0f;
    }
    ddof_params p;
    ddof_params_init(&p);
    p.kernel = kernel;
    p.solver = solver;
    p.highlights = DDOF_LAYER_OFF;
    const ddof_image_in in = {color, w, h, 1, 0}, map = {coc, w, h, 1, 0};
    const ddof_status sc = ddof_diffuse(cpu, &p, &in, &map, &(ddof_image){want, w, h, 1, 0}, NULL);
    const ddof_status sg = ddof_diffuse(gl, &p, &in, &map, &(ddof_image){got, w, h, 1, 0}, NULL);
    for (uint32_t i = 0; sg != DDOF_OK && i < n; i++)
        if (got[i] != -1.0f) { /* a refusal leaves the output as it was */
            printf("FAIL %u: refused, but the output was written\n", n);
            failed = 1;
            break;
        }
    if (sc != DDOF_OK) {
        printf("FAIL %u %s kernel %d: CPU %d %s\n", n, column ? "column" : "row", (int)kernel,
               (int)sc, ddof_context_last_error(cpu));
        failed = 1;
    } else if (sg == DDOF_ERROR_UNSUPPORTED && solver == DDOF_SOLVER_THOMAS &&
               strstr(ddof_context_last_error(gl), "longer than this software renderer")) {
        printf("ok   %u %s kernel %d: refused: %s\n", n, column ? "column" : "row",
               (int)kernel, ddof_context_last_error(gl));
    } else if (sg != DDOF_OK) {
        printf("FAIL %u %s kernel %d: GL %d %s\n", n, column ? "column" : "row", (int)kernel,
               (int)sg, ddof_context_last_error(gl));
        failed = 1;
    } else {
        size_t wrong = 0;
        double worst = 0.0;
        for (uint32_t i = 0; i < n; i++) {
            const double d = fabs((double)got[i] - (double)want[i]);
            if (!(d <= 1e-3 * (1.0 + fabs((double)want[i]))))
                wrong++;
            if (!(d <= worst))
                worst = isnan(d) ? INFINITY : d;
        }
        printf("%s %u %s kernel %d: %zu values wrong, largest error %.3g\n",
               wrong ? "FAIL" : "ok  ", n, column ? "column" : "row", (int)kernel, wrong, worst);
        failed |= wrong != 0;
    }
    free(color);
    free(coc);
    free(want);
    free(got);
    return failed;
}

/* A frame row of n pixels through the Jacobi solver (issue 40): jacobi_init.comp once looped
 * over a whole line in one invocation, so with the frame's heat capacities llvmpipe ended it
 * short of a 65,534-pixel row's end and the last pixels' first guess was garbage (R up to 57.7
 * from inputs <= 0.92, alpha != 1). Against the CPU, and within the input's range. The frame's
 * near field is split off as the near layer, or with near_layer off spread by the cone
 * dilation, whose run along a row once ran whole in one invocation: llvmpipe ended it short of
 * a 65,535- or 65,536-pixel row's end (25 values off by up to 0.024; the near layer's
 * background level: the first pixels, off by 0.108). */
static int run_jacobi_frame(ddof_context *gl, ddof_context *cpu, uint32_t n, int near_layer)
{
    float *color = malloc((size_t)n * 4 * sizeof *color), *depth = malloc((size_t)n * sizeof *depth);
    float *want = malloc((size_t)n * 4 * sizeof *want), *got = malloc((size_t)n * 4 * sizeof *got);
    for (uint32_t i = 0; i < n; i++) {
        color[i * 4 + 0] = (float)(i % 13u) / 13.0f;
        color[i * 4 + 1] = color[i * 4 + 2] = 0.5f;
        color[i * 4 + 3] = 1.0f;
        depth[i] = 1.0f + (float)(i % 50u) * 0.5f;
    }
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50.0;
    cam.fstop = 1.4;
    cam.focus_distance_m = 3.0;
    ddof_params p;
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_JACOBI;
    p.near_layer = near_layer ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, n, 1, 4, 0};
    f.depth = (ddof_image_in){depth, n, 1, 1, 0};
    f.camera = &cam;
    const ddof_status sc = ddof_render_frame(cpu, &p, &f, &(ddof_image){want, n, 1, 4, 0}, NULL);
    const ddof_status sg = ddof_render_frame(gl, &p, &f, &(ddof_image){got, n, 1, 4, 0}, NULL);
    int failed = 0;
    if (sc != DDOF_OK || sg != DDOF_OK) {
        printf("FAIL %u jacobi frame row%s: CPU %d, GL %d %s\n", n,
               near_layer ? "" : ", near spread", (int)sc, (int)sg, ddof_context_last_error(gl));
        failed = 1;
    } else {
        size_t wrong = 0;
        double worst = 0.0;
        for (size_t i = 0; i < (size_t)n * 4; i++) {
            const double d = fabs((double)got[i] - (double)want[i]);
            if (!(d <= 1e-3) || got[i] > 1.0f || got[i] < 0.0f)
                wrong++;
            if (!(d <= worst))
                worst = isnan(d) ? INFINITY : d;
        }
        printf("%s %u jacobi frame row%s: %zu values wrong, largest error %.3g\n",
               wrong ? "FAIL" : "ok  ", n, near_layer ? "" : ", near spread", wrong, worst);
        failed = wrong != 0;
    }
    free(color);
    free(depth);
    free(want);
    free(got);
    return failed;
}

int main(int argc, char **argv)
{
    const ddof_backend_kind kind = backend_from_name(argc > 1 ? argv[1] : NULL);
    ddof_context *gl = gl_context_for(kind);
    if (!gl)
        return GL_TEST_SKIP;
    ddof_context *cpu = make_context(0);
    /* The longest line Thomas solves on llvmpipe (backend_table.c), and the library's limit. */
    static const uint32_t fixed[] = {32500, 65536};
    int failed = 0;
    const int count = argc > 2 ? argc - 2 : 2;
    for (int k = 0; k < count; k++) {
        const uint32_t n = argc > 2 ? (uint32_t)strtoul(argv[k + 2], NULL, 10) : fixed[k];
        for (int column = 0; column < 2; column++) {
            failed |= run_case(gl, cpu, n, column, DDOF_KERNEL_HEAT, DDOF_SOLVER_THOMAS);
            failed |= run_case(gl, cpu, n, column, DDOF_KERNEL_DISC_2X2, DDOF_SOLVER_THOMAS);
            /* Cyclic reduction runs a level per dispatch: solved, and right. */
            failed |= run_case(gl, cpu, n, column, DDOF_KERNEL_HEAT,
                               DDOF_SOLVER_CYCLIC_REDUCTION);
        }
    }
    if (argc <= 2)
        for (uint32_t n = 65533; n <= 65536; n++)
            for (int near_layer = 0; near_layer < 2; near_layer++)
                failed |= run_jacobi_frame(gl, cpu, n, near_layer);
    ddof_context_free(gl);
    ddof_context_free(cpu);
    printf("test_gl_long_lines: %s\n", failed ? "FAILED" : "passed");
    return failed;
}
