/* SPDX-License-Identifier: MIT */
/* test_bad_input_params.c - the parameters of a call: values out of their ranges and the messages
 * that name them, a forced near spread without signed CoC, the presets, the backend selection
 * and the allocator hooks (bad_input_test.h). */
#include "bad_input_test.h"

static void test_params(void)
{
    ddof_params p;
    ddof_params_init(&p);
    CHECK_EQ_INT(p.struct_size, sizeof p);
    /* The measured default preset (docs/accuracy.md): the diffusion, with the solver, sub-steps
     * and k the study chose among those it sweeps (test_presets runs it on the CPU). */
    CHECK_EQ_INT(p.method, DDOF_METHOD_DIFFUSION);
    CHECK(p.solver != DDOF_SOLVER_GRUEN);
    CHECK(p.substeps >= 1 && p.substeps <= 8);
    CHECK(p.beta_scale >= DDOF_MOMENT_BETA_SCALE / 4 && p.beta_scale <= DDOF_MOMENT_BETA_SCALE * 4);
    CHECK(p.pixel_aspect == 1.0f);
    CHECK_EQ_INT(p.jacobi_iterations, 50);
    CHECK(p.progress == NULL);

    call c = good_call();
    c.params = &p;
#define BAD_PARAM(what, stmt)                                                                  \
    do {                                                                                       \
        ddof_params_init(&p);                                                                  \
        stmt;                                                                                  \
        expect(what, &c, DDOF_ERROR_BAD_PARAMETER);                                            \
    } while (0)
    BAD_PARAM("params struct_size 0", p.struct_size = 0);
    BAD_PARAM("params struct_size 4", p.struct_size = 4);
    /* Smaller than the first version of the struct (0.1 ended before coc_signed). */
    BAD_PARAM("params struct_size below version 0.1",
              p.struct_size = offsetof(ddof_params, coc_signed) - 1);
    BAD_PARAM("solver COUNT_", p.solver = DDOF_SOLVER_COUNT_);
    BAD_PARAM("solver -1", p.solver = (ddof_solver)-1);
    BAD_PARAM("substeps 0", p.substeps = 0);
    BAD_PARAM("beta_scale 0", p.beta_scale = 0.0f);
    BAD_PARAM("beta_scale -1", p.beta_scale = -1.0f);
    BAD_PARAM("beta_scale NaN", p.beta_scale = NAN);
    BAD_PARAM("beta_scale inf", p.beta_scale = INFINITY);
    BAD_PARAM("pixel_aspect 0", p.pixel_aspect = 0.0f);
    BAD_PARAM("pixel_aspect -1", p.pixel_aspect = -1.0f);
    BAD_PARAM("pixel_aspect NaN", p.pixel_aspect = NAN);
    BAD_PARAM("pixel_aspect inf", p.pixel_aspect = INFINITY);
    /* Finite, positive, but out of the documented ranges (issue 14: 1e20 gave NaN, DDOF_OK). */
    BAD_PARAM("pixel_aspect 1e20", p.pixel_aspect = 1e20f);
    BAD_PARAM("pixel_aspect 1e-20", p.pixel_aspect = 1e-20f);
    BAD_PARAM("pixel_aspect just above 100", p.pixel_aspect = nextafterf(100.0f, 200.0f));
    BAD_PARAM("pixel_aspect just below 0.01", p.pixel_aspect = nextafterf(0.01f, 0.0f));
    BAD_PARAM("beta_scale just above 1", p.beta_scale = nextafterf(1.0f, 2.0f));
    BAD_PARAM("beta_scale 1e30", p.beta_scale = 1e30f);
    BAD_PARAM("background_threshold_px above the largest CoC",
              p.background_threshold_px = 2.0f * DDOF_MAX_COC_PX);
    BAD_PARAM("near_spread_threshold_px above the largest CoC",
              p.near_spread_threshold_px = 2.0f * DDOF_MAX_COC_PX);
    BAD_PARAM("jacobi_iterations 0", (p.solver = DDOF_SOLVER_JACOBI, p.jacobi_iterations = 0));
    BAD_PARAM("method 2", p.method = (ddof_method)2);
    BAD_PARAM("precision 2", p.precision = (ddof_precision)2);
#undef BAD_PARAM
    /* The CPU backend has no Gruen solver and no packed half: a clear status, out untouched. */
    ddof_params_init(&p);
    p.solver = DDOF_SOLVER_GRUEN;
    expect("Gruen on the CPU", &c, DDOF_ERROR_UNSUPPORTED);
    ddof_params_init(&p);
    p.precision = DDOF_PRECISION_PACKED_HALF;
    expect("packed half on the CPU", &c, DDOF_ERROR_UNSUPPORTED);
}

/* The messages name the parameter and its range. */
static void expect_param_message(const char *what, ddof_params *p, const char *want)
{
    call c = good_call();
    c.params = p;
    fill_sentinel();
    CHECK_MSG(run_call(&c) == DDOF_ERROR_BAD_PARAMETER, "%s", what);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), want) != NULL, "%s: \"%s\" lacks \"%s\"",
              what, ddof_context_last_error(ctx), want);
}

/* Every CPU solver at the bounds of the ranges (largest beta_scale, smallest and largest pixel
 * aspect, one sub-step, the largest CoC on every pixel or on alternate rows): DDOF_OK and a
 * finite output, so that the ranges are ones where the solvers stay finite. */
static void test_param_bounds(void)
{
    static const ddof_solver solvers[] = {DDOF_SOLVER_THOMAS, DDOF_SOLVER_CYCLIC_REDUCTION,
                                          DDOF_SOLVER_PCR,
                                          DDOF_SOLVER_JACOBI, DDOF_SOLVER_REFERENCE_F64};
    static const float aspects[] = {0.01f, 100.0f};
    static float coc[W * H], out[W * H * CH];
    ddof_params p;
    for (int pattern = 0; pattern < 2; pattern++) {
        for (size_t i = 0; i < W * H; i++)
            coc[i] = pattern == 0 || (i / W) % 2 ? DDOF_MAX_COC_PX : 0.5f;
        for (size_t s = 0; s < sizeof solvers / sizeof solvers[0]; s++) {
            for (size_t a = 0; a < 2; a++) {
                ddof_params_init(&p);
                p.solver = solvers[s];
                p.substeps = 1;
                p.beta_scale = 1.0f;
                p.pixel_aspect = aspects[a];
                p.jacobi_iterations = 50;
                const ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc, W, H, 1, 0};
                const ddof_image oi = {out, W, H, CH, 0};
                ddof_status st = ddof_diffuse(ctx, &p, &ci, &zi, &oi, NULL);
                size_t bad = 0;
                for (size_t i = 0; i < W * H * CH; i++)
                    bad += !isfinite(out[i]);
                CHECK_MSG(st == DDOF_OK && bad == 0,
                          "%s, pixel aspect %g, CoC pattern %d: status %d, %zu non-finite",
                          ddof_solver_name(solvers[s]), (double)aspects[a], pattern, (int)st, bad);
            }
        }
    }
    ddof_params_init(&p);
    p.pixel_aspect = 1e20f;
    expect_param_message("pixel_aspect 1e20", &p, "params.pixel_aspect 1.00000002e+20 must be "
                         "within 0.01..100");
    ddof_params_init(&p);
    p.beta_scale = 2.0f;
    expect_param_message("beta_scale 2", &p, "params.beta_scale 2 must be > 0 and at most 1");
}

/* Issue 14: a forced near spread with a foreground element was ignored with DDOF_OK (the same
 * force with unsigned CoC is an error); a CoC just above the limit was printed as the limit. */
static void test_forced_near_spread_and_messages(void)
{
    static float fg_color[W * H * 4], fg_coc[W * H];
    ddof_foreground fg;
    ddof_params p;
    ddof_foreground_init(&fg);
    fg.color = (ddof_image_in){fg_color, W, H, 4, 0};
    fg.coc = (ddof_image_in){fg_coc, W, H, 1, 0};
    ddof_params_init(&p);
    p.coc_signed = 1;
    const ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc_buf, W, H, 1, 0};
    const ddof_image oi = {out_buf, W, H, CH, 0};
    reset_inputs();
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, &fg, &oi, NULL), DDOF_OK);
    p.near_spread = DDOF_LAYER_ON;
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &p, &ci, &zi, NULL, &oi, NULL), DDOF_OK);
    fill_sentinel();
    check_failure("near spread forced on with a foreground element",
                  ddof_diffuse_layers(ctx, &p, &ci, &zi, &fg, &oi, NULL),
                  DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    CHECK_MSG(strstr(ddof_context_last_error(ctx), "foreground element") != NULL, "%s",
              ddof_context_last_error(ctx));

    coc_buf[5] = 100000.01f;
    {
        call c = good_call();
        fill_sentinel();
        CHECK_EQ_INT(run_call(&c), DDOF_ERROR_BAD_COC);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "is 100000.008;") != NULL, "%s",
                  ddof_context_last_error(ctx));
    }
    reset_inputs();
}

static int same_settings(const ddof_params *a, const ddof_params *b)
{
    return a->method == b->method && a->solver == b->solver && a->substeps == b->substeps &&
           a->beta_scale == b->beta_scale && a->background == b->background &&
           a->background_levels == b->background_levels && a->near_spread == b->near_spread &&
           a->precision == b->precision && a->struct_size == b->struct_size;
}

/* Presets: known ones are valid params (the good call succeeds with each), an unknown one is
 * an error that still leaves the default preset, and ddof_params_init is the default preset. */
static void test_presets(void)
{
    ddof_params p, d;
    ddof_params_init(&d);
    for (int i = 0; i < DDOF_PRESET_COUNT_; i++) {
        CHECK_EQ_INT(ddof_params_init_preset(&p, (ddof_preset)i), DDOF_OK);
        CHECK(ddof_preset_name((ddof_preset)i) != NULL);
        call c = good_call();
        c.params = &p;
        CHECK_MSG(run_call(&c) == DDOF_OK, "preset %s: %s", ddof_preset_name((ddof_preset)i),
                  ddof_context_last_error(ctx));
    }
    CHECK_EQ_INT(ddof_params_init_preset(&p, DDOF_PRESET_DEFAULT), DDOF_OK);
    CHECK(same_settings(&p, &d));
    CHECK_EQ_INT(ddof_params_init_preset(&p, DDOF_PRESET_COUNT_), DDOF_ERROR_BAD_PARAMETER);
    CHECK(same_settings(&p, &d));
    CHECK(ddof_preset_name(DDOF_PRESET_COUNT_) == NULL);
    CHECK_EQ_INT(ddof_params_init_preset((ddof_params *)NULL, DDOF_PRESET_DEFAULT), DDOF_ERROR_NULL_POINTER);
}

/* Backends: a GL backend that cannot be loaded is a status and a sentence, the context keeps
 * working on the CPU; AUTO falls back to the CPU and says why. */
static void test_backend_selection(void)
{
    ddof_backend_info info = {.struct_size = sizeof info};
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    CHECK(strstr(info.renderer, "CPU") != NULL);
    const char *missing = "/nonexistent/libddof_gl.so";
    for (int k = DDOF_BACKEND_EGL; k < DDOF_BACKEND_COUNT_; k++) {
        CHECK_EQ_INT(ddof_context_set_backend(ctx, (ddof_backend_kind)k, missing),
                     DDOF_ERROR_BACKEND_UNAVAILABLE);
        CHECK_MSG(strstr(ddof_context_last_error(ctx), "could not be loaded") != NULL,
                  "backend %s: \"%s\"", ddof_backend_name((ddof_backend_kind)k),
                  ddof_context_last_error(ctx));
        CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
        CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    }
    /* A plugin named by the environment is the only one tried, like an explicit path. */
    CHECK_EQ_INT(setenv("DDOF_GL_PLUGIN", missing, 1), 0);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_OSMESA, NULL),
                 DDOF_ERROR_BACKEND_UNAVAILABLE);
    CHECK(strstr(ddof_context_last_error(ctx), missing) != NULL);
    CHECK_EQ_INT(unsetenv("DDOF_GL_PLUGIN"), 0);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_AUTO, missing), DDOF_OK);
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_OK);
    CHECK_EQ_INT(info.kind, DDOF_BACKEND_CPU);
    CHECK_MSG(strstr(info.note, "CPU") != NULL, "auto note \"%s\"", info.note);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_COUNT_, NULL),
                 DDOF_ERROR_BAD_PARAMETER);
    CHECK_EQ_INT(ddof_context_set_backend(NULL, DDOF_BACKEND_CPU, NULL), DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_context_backend_info(ctx, NULL), DDOF_ERROR_NULL_POINTER);
    info.struct_size = 4;
    CHECK_EQ_INT(ddof_context_backend_info(ctx, &info), DDOF_ERROR_BAD_PARAMETER);
    CHECK(ddof_backend_name(DDOF_BACKEND_COUNT_) == NULL);
    CHECK_EQ_INT(ddof_context_set_backend(ctx, DDOF_BACKEND_CPU, NULL), DDOF_OK);
    call c = good_call();
    ddof_stats st = {.struct_size = sizeof st};
    CHECK_EQ_INT(ddof_diffuse(ctx, c.params, &c.color, &c.coc, &c.out, &st), DDOF_OK);
    CHECK_EQ_INT(st.backend, DDOF_BACKEND_CPU);
    CHECK_EQ_INT(st.method, DDOF_METHOD_DIFFUSION);
    CHECK_EQ_INT(st.device_bytes, 0);
    /* The solver's scratch: at least one line batch of the image's rows. */
    CHECK_MSG(st.host_bytes >= (uint64_t)W * CH * sizeof(float), "host_bytes %llu",
              (unsigned long long)st.host_bytes);
}

/* Counting allocator: balance check, and failure injection (the allocation after `budget`
 * successful ones fails; budget < 0: never fails). */
typedef struct counting {
    long allocs, frees, live;
    long budget;
} counting;

static void *c_alloc(void *user, size_t size)
{
    counting *c = user;
    if (c->budget == 0)
        return NULL;
    if (c->budget > 0)
        c->budget--;
    void *p = malloc(size);
    if (p) {
        c->allocs++;
        c->live++;
    }
    return p;
}

static void c_free(void *user, void *ptr)
{
    counting *c = user;
    if (ptr) {
        c->frees++;
        c->live--;
        free(ptr);
    }
}

static void test_allocator(void)
{
    counting cnt = {0, 0, 0, -1};
    ddof_allocator a = {c_alloc, c_free, &cnt};
    ddof_context_options o;
    ddof_context_options_init(&o);
    o.allocator = &a;
    o.thread_count = 2;

    /* Context creation with the k-th allocation failing: OOM ("an allocation failed"), no leak,
     * no context. */
    for (long k = 0; k < 8; k++) {
        cnt = (counting){0, 0, 0, k};
        ddof_context *c = (ddof_context *)&cnt;
        ddof_status s = ddof_context_create(&o, &c);
        if (s == DDOF_OK) {
            ddof_context_free(c);
        } else {
            CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY,
                      "create, allocation %ld fails: status %d (%s)", k, (int)s,
                      ddof_status_string(s));
            CHECK(c == NULL);
        }
        CHECK_MSG(cnt.live == 0, "create, allocation %ld fails: %ld blocks leaked", k, cnt.live);
    }

    ddof_image_in ci = {color_buf, W, H, CH, 0}, zi = {coc_buf, W, H, 1, 0};
    ddof_image oi = {out_buf, W, H, CH, 0};
    ddof_params p;
    heat_params_init(&p);
    for (int solver = 0; solver < TEST_CPU_SOLVER_COUNT; solver++) {
        /* A fresh context whose allocator dies right after creation: the first call needs
         * scratch memory and must fail cleanly before writing anything. */
        cnt = (counting){0, 0, 0, -1};
        ddof_context *c = NULL;
        CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_OK);
        if (!c)
            return;
        cnt.budget = 0;
        p.solver = (ddof_solver)solver;
        fill_sentinel();
        ddof_status s = ddof_diffuse(c, &p, &ci, &zi, &oi, NULL);
        CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY, "%s without memory: %d",
                  ddof_solver_name(p.solver), (int)s);
        CHECK_MSG(out_untouched(), "%s: out written before the allocation failed",
                  ddof_solver_name(p.solver));
        CHECK(ddof_context_last_error(c)[0] != '\0');
        /* ... and works again once memory is back. */
        cnt.budget = -1;
        CHECK_EQ_INT(ddof_diffuse(c, &p, &ci, &zi, &oi, NULL), DDOF_OK);
        CHECK_MSG(cnt.allocs > 1, "the custom allocator was not used for the solve");
        ddof_context_free(c);
        CHECK_MSG(cnt.live == 0, "allocator: %ld allocations, %ld frees", cnt.allocs,
                  cnt.frees);
    }

    /* ddof_depth_of_field without memory. */
    cnt = (counting){0, 0, 0, -1};
    ddof_context *c = NULL;
    CHECK_EQ_INT(ddof_context_create(&o, &c), DDOF_OK);
    if (!c)
        return;
    float depth[W * H];
    for (size_t i = 0; i < W * H; i++)
        depth[i] = 1.0f + (float)(i % 17);
    ddof_image_in di = {depth, W, H, 1, 0};
    ddof_camera cam;
    ddof_camera_init(&cam);
    p.solver = DDOF_SOLVER_THOMAS;
    cnt.budget = 0;
    fill_sentinel();
    ddof_status s = ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL);
    CHECK_EQ_INT(s, DDOF_ERROR_OUT_OF_MEMORY);
    CHECK(out_untouched());
    cnt.budget = 1; /* the CoC buffer, then nothing for the solver */
    s = ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL);
    CHECK_MSG(s == DDOF_ERROR_OUT_OF_MEMORY, "depth_of_field, 2nd allocation fails: %d", (int)s);
    CHECK(out_untouched());
    cnt.budget = -1;
    CHECK_EQ_INT(ddof_depth_of_field(c, &p, &cam, &ci, &di, &oi, NULL), DDOF_OK);
    ddof_context_free(c);
    CHECK_MSG(cnt.live == 0, "allocator: %ld allocations, %ld frees", cnt.allocs, cnt.frees);
}

int main(void)
{
    bad_input_test_begin();

    test_params();
    test_param_bounds();
    test_forced_near_spread_and_messages();
    test_allocator();
    test_presets();
    test_backend_selection();

    return bad_input_test_end("test_bad_input_params");
}
