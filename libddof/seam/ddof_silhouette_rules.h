/* SPDX-License-Identifier: MIT */
/* ddof_silhouette_rules.h - the silhouettes' split's constants, shared by the CPU's pass
 * (libddof/src/passes/silhouettes.c, which says why each has its value) and the device's
 * (libddof/src/passes/gl/silhouettes.comp, which gets them as defines). */
#ifndef DDOF_SILHOUETTE_RULES_H
#define DDOF_SILHOUETTE_RULES_H

/* The smallest CoC (px) of the blurred side: below it a pixel's mixture is blurred so little
 * that splitting it changes nothing a viewer sees. */
#define DDOF_SILHOUETTE_MIN_COC_PX 4.0f
/* The smallest object share of p from which its colour gives the object's (the matte's
 * path): below it the background's error dominates the solve. */
#define DDOF_MATTE_SOLVE_SHARE 0.3f
/* A sharp pixel one pixel across along the pair (a wire, a strand) has no pixel inside it that
 * shows the object unmixed: it is O itself, and its colour alone cannot tell a bright wire
 * covering half of it from a faint one covering all. A render's depth names the surface its
 * pixel's centre sees, so such a pixel is partly background, and its blurred neighbours, whose
 * centres miss the object, hold less of it than it does. Both shares below are the values that
 * the accuracy study's Cryptomattes and its scenes support (docs/design.md, "Mixed pixels at
 * silhouettes"): the object covers 0.69 and 0.74 of such a pixel on the mean in thin_bars and
 * thin_strands, and a neighbour 0.25 and 0.28 of what the pixel holds (90th percentile 0.65,
 * 0.58), where its colour's projection on O, misled by the background's texture, says more. */
#define DDOF_THIN_OBJECT_SHARE 0.7f    /* the object's share of the thin pixel p               */
#define DDOF_THIN_NEIGHBOUR_SHARE 0.5f /* the largest share of O = p that its neighbour q holds */

#endif
