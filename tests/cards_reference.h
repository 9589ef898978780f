/* SPDX-License-Identifier: MIT */
/* cards_reference.h - the geometry of the cards' brute-force references (tests/test_cards.c,
 * tests/test_cards_uv.c, study/cards/mip_vs_sat.c), written from the definition rather than
 * from the library: Blender's camera with a horizontal sensor fit and square pixels, looking
 * down -z, row 0 at the top; a card's plane met by a ray. */
#ifndef DDOF_CARDS_REFERENCE_H
#define DDOF_CARDS_REFERENCE_H

#include "ddof.h"

/* The direction (z = -1) of the ray through point (x, y) of a width x height image, in
 * pixels from its top-left corner. */
static inline void cards_ref_ray(const ddof_camera *cam, int width, int height, double x,
                                 double y, double d[3])
{
    const double pw = cam->sensor_width_mm / width;
    d[0] = (x - 0.5 * width) * pw / cam->focal_length_mm;
    d[1] = (0.5 * height - y) * pw / cam->focal_length_mm;
    d[2] = -1.0;
}

/* Where ray d meets the parallelogram of corners c (4 x 3 doubles: c0 the origin, c1 - c0
 * along u, c3 - c0 along v): its depth *z and (u, v), 0..1 on the parallelogram. 0 when the
 * plane is behind. */
static inline int cards_ref_hit(const double *c, const double d[3], double *z, double *u,
                                double *v)
{
    const double p[4][3] = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]},
                            {c[9], c[10], c[11]}};
    double e1[3], e2[3], n[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = p[1][a] - p[0][a];
        e2[a] = p[3][a] - p[0][a];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double t = (n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]) /
                     (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
    if (!(t > 0.0))
        return 0;
    double q[3];
    for (int a = 0; a < 3; a++)
        q[a] = t * d[a] - p[0][a];
    *z = t;
    *u = (q[0] * e1[0] + q[1] * e1[1] + q[2] * e1[2]) /
         (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    *v = (q[0] * e2[0] + q[1] * e2[1] + q[2] * e2[2]) /
         (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    return 1;
}

#endif
