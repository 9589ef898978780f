/* SPDX-License-Identifier: MIT */
/* test_layers_calls.c - a call that runs every layer: progress, cancellation, threads and
 * substeps; and the bad-input statuses of ddof_diffuse_layers. */
#include "layers_test.h"

typedef struct progress_log {
    int calls, bad, cancel_at;
    float last, cancel_fraction; /* the fraction of the first report answered "cancel" */
} progress_log;

static int on_progress(void *user, float fraction)
{
    progress_log *log = user;
    if (!(fraction >= 0.0f && fraction <= 1.0f && fraction >= log->last))
        log->bad++;
    log->last = fraction;
    log->calls++;
    const int cancel = log->cancel_at > 0 && log->calls >= log->cancel_at;
    if (cancel && log->calls == log->cancel_at)
        log->cancel_fraction = fraction;
    return cancel;
}

static void test_progress_threads(void)
{
    const size_t npx = (size_t)W * H, n = npx * CH;
    float *color = alloc_f(n), *coc = alloc_f(npx), *out = alloc_f(n), *out1 = alloc_f(n);
    float *fgc = alloc_f(npx * 4), *fgz = alloc_f(npx);
    float lo[CH], hi[CH], hi_fg[CH];
    bars_horizontal = 0;
    noise(color, CH, 81);
    channel_range(color, CH, lo, hi);
    memcpy(hi_fg, hi, sizeof hi);
    hi_fg[3] = 1.0f; /* the composite's alpha reaches 1 under the element */
    bars_coc(coc, 20.0f);
    for (size_t i = 0; i < npx; i++)
        coc[i] = (i % W) < W / 3 ? -coc[i] : coc[i]; /* a near third: near spread too */
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            float a = disc_dist(x, y) <= disc_radius() ? 1.0f : 0.0f;
            for (uint32_t c = 0; c < 3; c++)
                fgc[i * 4 + c] = 0.5f * a;
            fgc[i * 4 + 3] = a;
            fgz[i] = 12.0f;
        }
    ddof_foreground fg = make_fg(fgc, fgz, 1);
    ddof_params p;
    heat_params_init(&p);
    p.coc_signed = 1;
    p.background_levels = 2;
    /* Progress: monotonic within [0, 1], on calls with and without the element. The number of
     * reports varies a little with thread timing. */
    for (int with_fg = 0; with_fg < 2; with_fg++) {
        progress_log log = {0, 0, 0, 0.0f, -1.0f};
        /* The near spread forced on without the element; with it, the element is the near
         * field (forcing the spread then is DDOF_ERROR_BAD_PARAMETER). */
        p.near_spread = with_fg ? DDOF_LAYER_AUTO : DDOF_LAYER_ON;
        p.progress = on_progress;
        p.progress_user = &log;
        ddof_stats st;
        CHECK_EQ_INT(layers(&p, color, coc, with_fg ? &fg : NULL, out, CH, &st), DDOF_OK);
        CHECK(st.effects & DDOF_EFFECT_BACKGROUND);
        CHECK(st.effects & (with_fg ? DDOF_EFFECT_FOREGROUND : DDOF_EFFECT_NEAR_SPREAD));
        CHECK_MSG(log.calls > 0 && log.bad == 0, "progress: %d calls, %d out of order/range",
                  log.calls, log.bad);
        /* Cancelled at points spread over the call: CANCELLED, the output finite and in range.
         * (A cancel answered to the closing report, fraction 1, may be ignored: ddof_diffuse
         * does the same.) */
        const int calls = log.calls;
        int cancelled = 0, stride = calls > 12 ? calls / 12 : 1;
        for (int k = 1; k <= calls; k += stride) {
            progress_log c = {0, 0, k, 0.0f, -1.0f};
            p.progress_user = &c;
            fill_const(out, n, 0.5f);
            ddof_status s = layers(&p, color, coc, with_fg ? &fg : NULL, out, CH, NULL);
            double worst = 0;
            /* The element's colour 0.5 a lies within the input range of every channel. */
            size_t bad = out_of_range(out, CH, lo, with_fg ? hi_fg : hi, 1e-5, &worst);
            CHECK_MSG(bad == 0, "cancel at progress call %d (of %d, element %d): output out of "
                      "range by %g", k, calls, with_fg, worst);
            if (s == DDOF_ERROR_CANCELLED)
                cancelled++;
            else
                CHECK_MSG(s == DDOF_OK && (c.cancel_fraction < 0 || c.cancel_fraction >= 1.0f),
                          "cancel at progress call %d (of %d, fraction %g, element %d): status %d",
                          k, calls, (double)c.cancel_fraction, with_fg, (int)s);
        }
        CHECK(cancelled > 0);
        p.progress = NULL;
        p.progress_user = NULL;
    }

    /* One thread and two give the same answer. */
    ddof_context *one;
    ddof_context_options o;
    ddof_context_options_init(&o);
    o.thread_count = 1;
    CHECK_EQ_INT(ddof_context_create(&o, &one), DDOF_OK);
    CHECK_EQ_INT(layers(&p, color, coc, &fg, out, CH, NULL), DDOF_OK);
    {
        ddof_image_in ci = {color, W, H, CH, 0}, zi = {coc, W, H, 1, 0};
        ddof_image oi = {out1, W, H, CH, 0};
        CHECK_EQ_INT(ddof_diffuse_layers(one, &p, &ci, &zi, &fg, &oi, NULL), DDOF_OK);
    }
    CHECK_MSG(max_abs_diff_ff(out, out1, n) <= 1e-6, "1 vs 2 threads: %g", max_abs_diff_ff(out, out1, n));
    ddof_context_free(one);

    /* Several substeps: every layer still finite and within range. */
    p.substeps = 4;
    for (int with_fg = 0; with_fg < 2; with_fg++) {
        p.near_spread = with_fg ? DDOF_LAYER_AUTO : DDOF_LAYER_ON;
        CHECK_EQ_INT(layers(&p, color, coc, with_fg ? &fg : NULL, out, CH, NULL), DDOF_OK);
        double worst;
        CHECK_MSG(out_of_range(out, CH, lo, with_fg ? hi_fg : hi, 1e-5, &worst) == 0,
                  "4 substeps, element %d: out of range by %g", with_fg, worst);
    }
    free(color);
    free(coc);
    free(out);
    free(out1);
    free(fgc);
    free(fgz);
}

/* ---------------------------------------------------------------------------------------- */
/* Bad input                                                                                */

#define BW 40u
#define BH 30u
static float b_color[BW * BH * 4], b_coc[BW * BH], b_out[BW * BH * 4], b_sent[BW * BH * 4];
static float b_fgc[BW * BH * 4], b_fgz[BW * BH];

typedef struct bad_call {
    ddof_params params;
    ddof_image_in color, coc;
    ddof_image out;
    ddof_foreground fg;
    int use_fg;
} bad_call;

static bad_call good_bad_call(void)
{
    bad_call c;
    memset(&c, 0, sizeof c);
    heat_params_init(&c.params);
    c.params.coc_signed = 1;
    c.color = (ddof_image_in){b_color, BW, BH, 4, 0};
    c.coc = (ddof_image_in){b_coc, BW, BH, 1, 0};
    c.out = (ddof_image){b_out, BW, BH, 4, 0};
    ddof_foreground_init(&c.fg);
    c.fg.color = (ddof_image_in){b_fgc, BW, BH, 4, 0};
    c.fg.coc = (ddof_image_in){b_fgz, BW, BH, 1, 0};
    c.use_fg = 1;
    return c;
}

static void reset_bad_inputs(void)
{
    test_rng rng = {61};
    for (size_t i = 0; i < BW * BH; i++) {
        for (int c = 0; c < 4; c++) {
            b_color[i * 4 + c] = (float)test_uniform(&rng);
            b_fgc[i * 4 + c] = 0.5f * (float)test_uniform(&rng); /* premultiplied: rgb <= a */
        }
        b_fgc[i * 4 + 3] = 0.5f + 0.5f * (float)test_uniform(&rng);
        b_coc[i] = (float)(30.0 * test_uniform(&rng) - 10.0);
        b_fgz[i] = (float)(20.0 * test_uniform(&rng));
    }
    const uint32_t bits = 0x7FC0BEEFu;
    for (size_t i = 0; i < BW * BH * 4; i++)
        memcpy(&b_sent[i], &bits, 4);
}

static void expect_bad(const char *what, bad_call c, ddof_status want1, ddof_status want2)
{
    memcpy(b_out, b_sent, sizeof b_out);
    ddof_status s = ddof_diffuse_layers(ctx, &c.params, &c.color, &c.coc,
                                        c.use_fg ? &c.fg : NULL, &c.out, NULL);
    CHECK_MSG(s == want1 || s == want2, "%s: status %d (%s), want %d (%s)", what, (int)s,
              ddof_status_string(s), (int)want1, ddof_status_string(want1));
    CHECK_MSG(!memcmp(b_out, b_sent, sizeof b_out), "%s: output touched", what);
    CHECK_MSG(ddof_context_last_error(ctx)[0] != '\0', "%s: no last error", what);
    if (verbose)
        printf("bad input, %s: %s\n", what, ddof_context_last_error(ctx));
}

static void test_bad_input(void)
{
    reset_bad_inputs();
    {
        bad_call c = good_bad_call();
        ddof_status s = ddof_diffuse_layers(ctx, &c.params, &c.color, &c.coc, &c.fg, &c.out, NULL);
        CHECK_MSG(s == DDOF_OK, "the good call fails: %d (%s)", (int)s, ddof_context_last_error(ctx));
    }
    bad_call c;
#define BAD(what, change, w1, w2) \
    do {                          \
        c = good_bad_call();      \
        change;                   \
        expect_bad(what, c, w1, w2); \
    } while (0)
    BAD("element colour narrower", c.fg.color.width = BW - 1, DDOF_ERROR_SIZE_MISMATCH,
        DDOF_ERROR_SIZE_MISMATCH);
    BAD("element colour shorter", c.fg.color.height = BH - 1, DDOF_ERROR_SIZE_MISMATCH,
        DDOF_ERROR_SIZE_MISMATCH);
    BAD("element CoC narrower", c.fg.coc.width = BW - 1, DDOF_ERROR_SIZE_MISMATCH,
        DDOF_ERROR_SIZE_MISMATCH);
    BAD("element CoC shorter", c.fg.coc.height = BH - 2, DDOF_ERROR_SIZE_MISMATCH,
        DDOF_ERROR_SIZE_MISMATCH);
    BAD("element with 3 channels", c.fg.color.channels = 3, DDOF_ERROR_BAD_CHANNELS,
        DDOF_ERROR_SIZE_MISMATCH);
    BAD("element with 5 channels", c.fg.color.channels = 5, DDOF_ERROR_BAD_CHANNELS,
        DDOF_ERROR_BAD_CHANNELS);
    BAD("1-channel colour with an element", (c.color.channels = 1, c.out.channels = 1),
        DDOF_ERROR_BAD_CHANNELS, DDOF_ERROR_SIZE_MISMATCH);
    BAD("2-channel colour with an element", (c.color.channels = 2, c.out.channels = 2),
        DDOF_ERROR_BAD_CHANNELS, DDOF_ERROR_SIZE_MISMATCH);
    BAD("element struct_size 0", c.fg.struct_size = 0, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("element colour pixels NULL", c.fg.color.pixels = NULL, DDOF_ERROR_NULL_POINTER,
        DDOF_ERROR_NULL_POINTER);
    BAD("element CoC pixels NULL", c.fg.coc.pixels = NULL, DDOF_ERROR_NULL_POINTER,
        DDOF_ERROR_NULL_POINTER);
    BAD("element stride not a multiple of 4", c.fg.color.row_stride = BW * 16 + 2,
        DDOF_ERROR_BAD_STRIDE, DDOF_ERROR_BAD_STRIDE);
    BAD("element stride smaller than a row", c.fg.coc.row_stride = BW * 4 - 4,
        DDOF_ERROR_BAD_STRIDE, DDOF_ERROR_BAD_STRIDE);

    /* Bad values in the element, where its alpha > 0 (everywhere here). */
    BAD("element colour NaN", b_fgc[4 * 17 + 1] = NAN, DDOF_ERROR_BAD_COLOR, DDOF_ERROR_BAD_COLOR);
    reset_bad_inputs();
    BAD("element alpha NaN", b_fgc[4 * 23 + 3] = NAN, DDOF_ERROR_BAD_COLOR, DDOF_ERROR_BAD_COLOR);
    reset_bad_inputs();
    BAD("element colour +inf", b_fgc[4 * 5] = INFINITY, DDOF_ERROR_BAD_COLOR, DDOF_ERROR_BAD_COLOR);
    reset_bad_inputs();
    BAD("element CoC NaN", b_fgz[99] = NAN, DDOF_ERROR_BAD_COC, DDOF_ERROR_BAD_COC);
    reset_bad_inputs();
    BAD("element CoC +inf", b_fgz[7] = INFINITY, DDOF_ERROR_BAD_COC, DDOF_ERROR_BAD_COC);
    reset_bad_inputs();
    BAD("element CoC above the limit", b_fgz[8] = 2.0f * DDOF_MAX_COC_PX, DDOF_ERROR_BAD_COC,
        DDOF_ERROR_BAD_COC);
    reset_bad_inputs();

    /* Parameters of the layers. */
    BAD("threshold == ramp start", c.params.background_threshold_px = 2.0f,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("threshold < ramp start", (c.params.background_ramp_start_px = 10.0f),
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("threshold NaN", c.params.background_threshold_px = NAN, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("threshold +inf", c.params.background_threshold_px = INFINITY, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("ramp start negative", c.params.background_ramp_start_px = -1.0f,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("ramp start NaN", c.params.background_ramp_start_px = NAN, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("background levels 0", c.params.background_levels = 0, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("background levels 9", c.params.background_levels = 9, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("near spread threshold 0", c.params.near_spread_threshold_px = 0.0f,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("near spread threshold -1", c.params.near_spread_threshold_px = -1.0f,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("near spread threshold NaN", c.params.near_spread_threshold_px = NAN,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    BAD("background mode 3", c.params.background = (ddof_layer_mode)3, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
    BAD("near spread mode 7", c.params.near_spread = (ddof_layer_mode)7,
        DDOF_ERROR_BAD_PARAMETER, DDOF_ERROR_BAD_PARAMETER);
    /* Unsigned CoC with a negative value (b_coc holds some). */
    BAD("negative CoC, coc_signed 0", (c.params.coc_signed = 0, c.use_fg = 0),
        DDOF_ERROR_BAD_COC, DDOF_ERROR_BAD_COC);
    BAD("signed CoC below -limit", (b_coc[3] = -2.0f * DDOF_MAX_COC_PX, c.use_fg = 0),
        DDOF_ERROR_BAD_COC, DDOF_ERROR_BAD_COC);
    reset_bad_inputs();
    BAD("params struct_size 0", c.params.struct_size = 0, DDOF_ERROR_BAD_PARAMETER,
        DDOF_ERROR_BAD_PARAMETER);
#undef BAD

    /* NULLs. */
    c = good_bad_call();
    memcpy(b_out, b_sent, sizeof b_out);
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, NULL, &c.color, &c.coc, &c.fg, &c.out, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_diffuse_layers(NULL, &c.params, &c.color, &c.coc, &c.fg, &c.out, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &c.params, NULL, &c.coc, &c.fg, &c.out, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &c.params, &c.color, NULL, &c.fg, &c.out, NULL),
                 DDOF_ERROR_NULL_POINTER);
    CHECK(!memcmp(b_out, b_sent, sizeof b_out));

    /* A success clears the last error. */
    c = good_bad_call();
    CHECK_EQ_INT(ddof_diffuse_layers(ctx, &c.params, &c.color, &c.coc, &c.fg, &c.out, NULL),
                 DDOF_OK);
    CHECK(ddof_context_last_error(ctx)[0] == '\0');
    CHECK(all_finite(b_out, sizeof b_out / sizeof b_out[0]));
}

int main(void)
{
    layers_test_begin();
    test_progress_threads();
    test_bad_input();
    return layers_test_end("test_layers_calls");
}
