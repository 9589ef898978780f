/* SPDX-License-Identifier: MIT */
/* test_aperture.c - the camera's aperture (ddof_camera.aperture_blades, _rotation_deg, _ratio):
 * a bright point far behind the focus comes out as the anti-aliased regular polygon Cycles
 * samples (edge normals at rotation + 2 pi k / blades, inscribed in the round aperture) or the
 * ellipse of the anamorphic ratio (CoC / ratio wide, CoC tall), or clipped by the cat's eye
 * toward the frame's edges, or a custom aperture image, against a reference that
 * supersamples the shape in double; its energy is kept; a rotation by one blade step changes
 * nothing; the default aperture is the 0.5 struct's (round) bit for bit; the CoC is the blur's
 * width; the bounds are checked. */
#include "test_util.h"

#include <ddof.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 224, H = 224, N = W * H, CX = 111, CY = 113 };
#define LIGHT 1000.0f
#define PI 3.14159265358979323846

static ddof_context *ctx;

/* 50 mm on a 36 mm sensor, W pixels wide, focused at 2 m; the f-number gives the CoC far away. */
static ddof_camera camera_for(double coc_far_px)
{
    ddof_camera cam;
    ddof_camera_init(&cam);
    cam.focal_length_mm = 50.0;
    cam.sensor_width_mm = 36.0;
    cam.focus_distance_m = 2.0;
    cam.fstop = 2500.0 / 2000.0 / (36.0 / W) / coc_far_px;
    return cam;
}

/* A black frame at 1000 m with one white pixel of LIGHT at (x, y); out: RGBA. *coc gets the
 * CoC the library computed for the frame (uniform). */
static ddof_status point_spread_at(const ddof_camera *cam, int x, int y, float *out, float *coc)
{
    static float color[N * 4], depth[N], coc_map[N];
    memset(color, 0, sizeof color);
    for (int i = 0; i < N; i++) {
        color[i * 4 + 3] = 1.0f;
        depth[i] = 1000.0f;
    }
    for (int c = 0; c < 3; c++)
        color[(y * W + x) * 4 + c] = LIGHT;
    ddof_status s = ddof_coc_from_camera(ctx, cam, &(ddof_image_in){depth, W, H, 1, 0},
                                         &(ddof_image){coc_map, W, H, 1, 0});
    *coc = coc_map[0];
    if (s != DDOF_OK)
        return s;
    ddof_params p;
    ddof_params_init(&p);
    return ddof_depth_of_field(ctx, &p, cam, &(ddof_image_in){color, W, H, 4, 0},
                               &(ddof_image_in){depth, W, H, 1, 0},
                               &(ddof_image){out, W, H, 4, 0}, NULL);
}

static ddof_status point_spread(const ddof_camera *cam, float *out, float *coc)
{
    return point_spread_at(cam, CX, CY, out, coc);
}

/* Whether image offset (x right, y down, pixels) from the point lies in the aperture's shape
 * for a far point: the blur is the aperture (y up) scaled to CoC / 2 across and ratio times
 * that tall. */
static int in_shape(double x, double y, double coc, double ratio, unsigned blades,
                    double rotation)
{
    const double ax = x / (0.5 * coc), ay = -y / (0.5 * coc * ratio);
    if (blades < 3)
        return ax * ax + ay * ay <= 1.0;
    double far = -INFINITY;
    for (unsigned k = 0; k < blades; k++) {
        const double a = rotation + 2.0 * PI * k / blades;
        far = fmax(far, ax * cos(a) + ay * sin(a));
    }
    return far <= cos(PI / blades);
}

/* The shape's coverage of each pixel (16 x 16 samples). */
static void reference(double coc, double ratio, unsigned blades, double rotation, double *ref)
{
    const double reach_x = 0.5 * coc + 2.0, reach_y = 0.5 * coc * ratio + 2.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            ref[y * W + x] = 0.0;
            if (fabs((double)(x - CX)) > reach_x || fabs((double)(y - CY)) > reach_y)
                continue; /* outside the shape's box */
            int hits = 0;
            for (int j = 0; j < 16; j++)
                for (int i = 0; i < 16; i++)
                    hits += in_shape(x - CX + (i + 0.5) / 16 - 0.5, y - CY + (j + 0.5) / 16 - 0.5,
                                     coc, ratio, blades, rotation);
            ref[y * W + x] = hits / 256.0;
        }
}

/* Kernel SNR of the red channel against ref, in dB; *energy the channel's sum. */
static double snr_db(const float *out, const double *ref, double *energy)
{
    double signal = 0.0, noise = 0.0, sum = 0.0;
    for (int i = 0; i < N; i++) {
        const double e = out[i * 4] - ref[i];
        signal += ref[i] * ref[i];
        noise += e * e;
        sum += out[i * 4];
    }
    *energy = sum;
    return 10.0 * log10(signal / noise);
}

/* The point's spread `out` against the shape `ref` (any scale): ref is scaled to the light the
 * highlight pass takes out (all above its threshold, 0.25 in the default preset; the rest is
 * diffused round), then the kernel SNR must reach min_db and the light be kept within 1%. */
static void compare_spread(const float *out, double *ref, double min_db, const char *what)
{
    double total = 0.0, energy;
    for (int i = 0; i < N; i++)
        total += ref[i];
    for (int i = 0; i < N; i++)
        ref[i] *= (LIGHT - 0.25) / total;
    const double db = snr_db(out, ref, &energy);
    CHECK_MSG(db >= min_db, "%s: %.2f dB against the shape (want >= %g)", what, db, min_db);
    CHECK_MSG(fabs(energy - LIGHT) <= 0.01 * LIGHT, "%s: energy %.3f of %g", what, energy,
              (double)LIGHT);
    printf("%s: %6.2f dB, energy %.4f\n", what, db, energy / LIGHT);
}

static void check_shape(double coc_far, unsigned blades, double rotation_deg, double ratio,
                        double min_db)
{
    static float out[N * 4];
    static double ref[N];
    ddof_camera cam = camera_for(coc_far);
    cam.aperture_blades = blades;
    cam.aperture_rotation_deg = rotation_deg;
    cam.aperture_ratio = ratio;
    float coc = 0.0f;
    CHECK(point_spread(&cam, out, &coc) == DDOF_OK);
    reference(coc, ratio, blades, rotation_deg * PI / 180.0, ref);
    char what[96];
    snprintf(what, sizeof what, "blades %2u rotation %5.1f ratio %.1f CoC %5.2f px", blades,
             rotation_deg, ratio, (double)coc);
    compare_spread(out, ref, min_db, what);
}

/* The cat's eye: a light at (40, 40) of the 224 x 224 frame is the disc clipped by a disc of
 * its radius centred toward the frame's centre by catseye x radius x 0.638 (its distance from
 * the centre, 1 at a corner); its light is kept; the light mirrored through the frame's centre
 * is drawn mirrored. */
static void test_catseye(void)
{
    static float out[N * 4], mirrored[N * 4];
    static double ref[N];
    ddof_camera cam = camera_for(40.0);
    cam.aperture_catseye = 0.8;
    float coc = 0.0f;
    const int x0 = 40, y0 = 40;
    CHECK(point_spread_at(&cam, x0, y0, out, &coc) == DDOF_OK);
    const double px = x0 + 0.5 - 0.5 * W, py = y0 + 0.5 - 0.5 * H;
    const double reach = sqrt(0.5 * ((px / (0.5 * W)) * (px / (0.5 * W)) +
                                     (py / (0.5 * H)) * (py / (0.5 * H))));
    const double shift = 0.8 * 0.5 * coc * reach / sqrt(px * px + py * py);
    const double cx = -px * shift, cy = -py * shift, r = 0.5 * coc;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int hits = 0;
            for (int j = 0; j < 16; j++)
                for (int i = 0; i < 16; i++) {
                    const double u = x - x0 + (i + 0.5) / 16 - 0.5, v = y - y0 + (j + 0.5) / 16 - 0.5;
                    hits += u * u + v * v <= r * r &&
                            (u - cx) * (u - cx) + (v - cy) * (v - cy) <= r * r;
                }
            ref[y * W + x] = hits;
        }
    char what[96];
    snprintf(what, sizeof what, "cat's eye 0.8 at (40, 40), CoC %5.2f px", (double)coc);
    compare_spread(out, ref, 35.0, what);
    /* The light at the mirrored place draws the mirrored shape. */
    CHECK(point_spread_at(&cam, W - 1 - x0, H - 1 - y0, mirrored, &coc) == DDOF_OK);
    double worst = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            worst = fmax(worst, fabs((double)out[(y * W + x) * 4] -
                                     mirrored[((H - 1 - y) * W + (W - 1 - x)) * 4]));
    CHECK_MSG(worst <= 1e-3, "cat's eye mirrored through the centre differs by %g", worst);
}

/* A ring with a dot in its upper left, 48 x 40 texels: not convex, not symmetric. */
static void ring_image(float *img, int w, int h)
{
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const double u = (i + 0.5) / w * 2.0 - 1.0, v = (j + 0.5) / h * 2.0 - 1.0;
            const double d = sqrt(u * u + v * v);
            const double du = u + 0.35, dv = v + 0.35;
            img[j * w + i] = (d > 0.7 && d < 0.95) ? 1.0f
                             : (du * du + dv * dv < 0.04) ? 0.5f : 0.0f;
        }
}

/* The image's average over [x0, x1] x [y0, y1] texels (outside it: 0), by each texel's overlap. */
static double texel_average(const float *img, int w, int h, double x0, double x1, double y0,
                            double y1)
{
    double sum = 0.0;
    for (int j = (int)floor(fmax(y0, 0.0)); j < h && j < y1; j++)
        for (int i = (int)floor(fmax(x0, 0.0)); i < w && i < x1; i++) {
            const double ox = fmin(x1, i + 1.0) - fmax(x0, (double)i);
            const double oy = fmin(y1, j + 1.0) - fmax(y0, (double)j);
            if (ox > 0.0 && oy > 0.0)
                sum += img[j * w + i] * ox * oy;
        }
    return sum / ((x1 - x0) * (y1 - y0));
}

/* A custom aperture image: each pixel of a far light's blur is the image's average over its
 * footprint (the image spanning the CoC's square, upright), energy kept; a disc image draws
 * the disc; the image's bounds are checked. */
static void test_aperture_image(void)
{
    enum { IW = 48, IH = 40 };
    static float img[IW * IH], out[N * 4];
    static double ref[N];
    ring_image(img, IW, IH);
    ddof_camera cam = camera_for(60.0);
    cam.aperture_image = img;
    cam.aperture_image_width = IW;
    cam.aperture_image_height = IH;
    cam.aperture_blades = 6; /* the image replaces the blades */
    float coc = 0.0f;
    CHECK(point_spread(&cam, out, &coc) == DDOF_OK);
    const double r = 0.5 * coc, sx = IW / (2.0 * r), sy = IH / (2.0 * r);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double dx = x - CX, dy = y - CY;
            ref[y * W + x] = fabs(dx) > r + 1.0 || fabs(dy) > r + 1.0
                                 ? 0.0
                                 : texel_average(img, IW, IH, (dx - 0.5 + r) * sx,
                                                 (dx + 0.5 + r) * sx, (dy - 0.5 + r) * sy,
                                                 (dy + 0.5 + r) * sy);
        }
    char what[96];
    snprintf(what, sizeof what, "aperture image (a ring and a dot, %dx%d) CoC %5.2f px", IW, IH,
             (double)coc);
    compare_spread(out, ref, 40.0, what);

    /* Bad images: each a camera error before anything runs. */
    static float bad[4] = {1.0f, 0.0f, 0.0f, 1.0f};
    cam.aperture_image = bad;
    cam.aperture_image_width = cam.aperture_image_height = 2;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    cam.aperture_image_width = 0;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    cam.aperture_image_width = DDOF_MAX_APERTURE_IMAGE + 1;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    cam.aperture_image_width = 2;
    const float values[] = {NAN, -1.0f, INFINITY};
    for (int i = 0; i < 3; i++) {
        bad[2] = values[i];
        CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    }
    bad[0] = bad[1] = bad[2] = bad[3] = 0.0f;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    CHECK(strstr(ddof_context_last_error(ctx), "all 0") != NULL);
}

/* The CoC a camera gives is the blur's width: the ratio divides it. */
static void test_coc_is_the_width(void)
{
    static float out[N * 4];
    ddof_camera cam = camera_for(32.0);
    float round_coc = 0.0f, oval_coc = 0.0f;
    CHECK(point_spread(&cam, out, &round_coc) == DDOF_OK);
    cam.aperture_ratio = 2.0;
    CHECK(point_spread(&cam, out, &oval_coc) == DDOF_OK);
    CHECK_MSG(fabsf(oval_coc - 0.5f * round_coc) <= 1e-5f * round_coc,
              "ratio 2: CoC %g, round %g", (double)oval_coc, (double)round_coc);
}

/* Turning a polygon by one blade step draws the same polygon. */
static void test_rotation_symmetry(void)
{
    static float a[N * 4], b[N * 4];
    ddof_camera cam = camera_for(40.0);
    float coc;
    cam.aperture_blades = 4;
    cam.aperture_rotation_deg = 10.0;
    CHECK(point_spread(&cam, a, &coc) == DDOF_OK);
    cam.aperture_rotation_deg = 100.0;
    CHECK(point_spread(&cam, b, &coc) == DDOF_OK);
    double worst = 0.0;
    for (int i = 0; i < N * 4; i++)
        worst = fmax(worst, fabs((double)a[i] - b[i]));
    /* cos/sin of angles 90 degrees apart agree to float rounding, not bit for bit. */
    CHECK_MSG(worst <= 1e-3, "4 blades at 10 and 100 degrees differ by %g", worst);
}

/* The default aperture (round, ratio 1) is what a 0.5 caller's camera, without the fields,
 * gets: the same output bit for bit; so are 1 and 2 blades (round, as Cycles). */
static void test_default_is_round(void)
{
    static float a[N * 4], b[N * 4];
    ddof_camera cam = camera_for(30.0);
    float coc;
    CHECK(point_spread(&cam, a, &coc) == DDOF_OK);
    ddof_camera old = cam;
    old.struct_size = (uint32_t)DDOF_CAMERA_SIZE_0_5;
    old.aperture_blades = 6; /* past the old struct: not read */
    CHECK(point_spread(&old, b, &coc) == DDOF_OK);
    CHECK(memcmp(a, b, sizeof a) == 0);
    cam.aperture_blades = 2;
    cam.aperture_rotation_deg = 33.0;
    CHECK(point_spread(&cam, b, &coc) == DDOF_OK);
    CHECK(memcmp(a, b, sizeof a) == 0);
}

static void test_bounds(void)
{
    ddof_camera cam = camera_for(30.0);
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    cam.aperture_blades = DDOF_MAX_APERTURE_BLADES;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    cam.aperture_blades = DDOF_MAX_APERTURE_BLADES + 1;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    cam = camera_for(30.0);
    const double rotations[] = {NAN, INFINITY, 360.5, -361.0};
    for (int i = 0; i < 4; i++) {
        cam.aperture_rotation_deg = rotations[i];
        CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    }
    cam.aperture_rotation_deg = -360.0;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    const double ratios[] = {0.0, -1.0, NAN, 0.0099, 100.5, INFINITY};
    for (int i = 0; i < 6; i++) {
        cam.aperture_ratio = ratios[i];
        CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    }
    cam.aperture_ratio = 0.01;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    cam.aperture_ratio = 1.0;
    const double catseyes[] = {-0.01, 1.01, NAN};
    for (int i = 0; i < 3; i++) {
        cam.aperture_catseye = catseyes[i];
        CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    }
    cam.aperture_catseye = 1.0;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_OK);
    cam.aperture_ratio = 0.01;
    /* The diffusion takes the product with the pixel aspect: 0.5 x 0.01 is past its range. */
    cam.pixel_aspect = 0.5;
    CHECK(ddof_camera_check(ctx, &cam) == DDOF_ERROR_BAD_CAMERA);
    CHECK(strstr(ddof_context_last_error(ctx), "aperture_ratio") != NULL);
}

/* A renderer's CoC pass with the camera's aperture (ddof_frame.camera beside ddof_frame.coc,
 * version 0.9): the same image, bit for bit, as from depth and that camera, for a hexagon, an
 * ellipse and an aperture image; without the camera the highlight is round. */
static void test_coc_image_takes_the_aperture(void)
{
    static float color[N * 4], depth[N], coc[N], from_depth[N * 4], from_coc[N * 4];
    static float round[N * 4];
    static float aperture[16 * 16];
    for (int i = 0; i < 256; i++)
        aperture[i] = (i / 16 + i % 16) % 5 ? 1.0f : 0.0f;
    memset(color, 0, sizeof color);
    for (int i = 0; i < N; i++) {
        color[i * 4 + 3] = 1.0f;
        depth[i] = i % W < W / 2 ? 1000.0f : 20.0f; /* two depths: an edge, two CoCs */
    }
    for (int c = 0; c < 3; c++)
        color[(CY * W + CX) * 4 + c] = LIGHT;
    for (int k = 0; k < 3; k++) {
        ddof_camera cam = camera_for(32.0);
        if (k == 0) {
            cam.aperture_blades = 6;
            cam.aperture_rotation_deg = 15.0;
        } else if (k == 1) {
            cam.aperture_ratio = 1.7;
        } else {
            cam.aperture_image = aperture;
            cam.aperture_image_width = cam.aperture_image_height = 16;
        }
        ddof_params p;
        ddof_params_init(&p);
        ddof_frame f;
        ddof_frame_init(&f);
        f.color = (ddof_image_in){color, W, H, 4, 0};
        f.depth = (ddof_image_in){depth, W, H, 1, 0};
        f.camera = &cam;
        f.coc_out = (ddof_image){coc, W, H, 1, 0};
        CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){from_depth, W, H, 4, 0}, NULL) ==
              DDOF_OK);
        ddof_frame_init(&f);
        f.color = (ddof_image_in){color, W, H, 4, 0};
        f.coc = (ddof_image_in){coc, W, H, 1, 0};
        f.camera = &cam;
        p.coc_signed = 1; /* coc_out is signed, as the camera's CoC is */
        ddof_stats st = {.struct_size = sizeof st};
        CHECK_MSG(ddof_render_frame(ctx, &p, &f, &(ddof_image){from_coc, W, H, 4, 0}, &st) ==
                      DDOF_OK, "%s", ddof_context_last_error(ctx));
        CHECK_MSG(memcmp(from_depth, from_coc, sizeof from_coc) == 0,
                  "aperture %d: the CoC image with the camera differs from depth", k);
        f.camera = NULL;
        CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){round, W, H, 4, 0}, NULL) ==
              DDOF_OK);
        CHECK_MSG(memcmp(round, from_coc, sizeof round) != 0,
                  "aperture %d: the camera changed nothing", k);
    }
    /* The camera gives no CoC: with depth too it is two sources, as before. */
    ddof_camera cam = camera_for(32.0);
    ddof_frame f;
    ddof_frame_init(&f);
    f.color = (ddof_image_in){color, W, H, 4, 0};
    f.coc = (ddof_image_in){coc, W, H, 1, 0};
    f.depth = (ddof_image_in){depth, W, H, 1, 0};
    f.camera = &cam;
    ddof_params p;
    ddof_params_init(&p);
    CHECK(ddof_render_frame(ctx, &p, &f, &(ddof_image){round, W, H, 4, 0}, NULL) ==
          DDOF_ERROR_BAD_PARAMETER);
}

int main(void)
{
    ddof_context_options o;
    ddof_context_options_init(&o);
    CHECK(ddof_context_create(&o, &ctx) == DDOF_OK);
    /* 37-49 dB measured (the bar: >= 25 dB against the hexagon at D = 32 and 80 px, >= 30
     * for highlights). The rim is anti-aliased over half a pixel measured in pixels, so an
     * ellipse's ends are as sharp as its sides (with half a unit of its stretched axes they
     * were a pixel wide: 30.0 dB). */
    check_shape(32.0, 6, 15.0, 1.0, 35.0);
    check_shape(80.0, 6, 15.0, 1.0, 35.0);
    check_shape(32.0, 5, 0.0, 1.0, 35.0);
    check_shape(48.0, 3, -20.0, 1.0, 35.0);
    check_shape(64.0, 7, 40.0, 1.5, 35.0);
    check_shape(32.0, 0, 0.0, 1.0, 40.0);
    check_shape(64.0, 0, 0.0, 2.0, 40.0);
    check_shape(32.0, 0, 0.0, 0.5, 40.0);
    test_catseye();
    test_aperture_image();
    test_coc_is_the_width();
    test_rotation_symmetry();
    test_default_is_round();
    test_bounds();
    test_coc_image_takes_the_aperture();
    ddof_context_free(ctx);
    return test_report("test_aperture");
}
