/* SPDX-License-Identifier: MIT */
/* float_ops.h - tiny helpers the hot loops share. */
#ifndef DDOF_FLOAT_OPS_H
#define DDOF_FLOAT_OPS_H

#if defined(__GNUC__)
#  define DDOF_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#  define DDOF_ALWAYS_INLINE inline
#endif

/* Hot kernels are compiled for several x86-64 levels and the best one for the running CPU is
 * picked when the library loads (GCC/Clang function multi-versioning through ifunc), so one
 * binary uses AVX-512 or AVX2 where present and stays runnable on any x86-64. */
#if defined(__x86_64__) && defined(__GNUC__) && defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
#  define DDOF_MULTIVERSION __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#  define DDOF_MULTIVERSION
#endif

/* Hint that memory will be read (rw 0) or written (rw 1) soon; a no-op elsewhere. */
#if defined(__GNUC__)
#  define DDOF_PREFETCH(address, rw) __builtin_prefetch((address), (rw), 3)
#else
#  define DDOF_PREFETCH(address, rw) ((void)(address))
#endif

/* fminf/fmaxf are library calls under strict C11 (they must order NaNs); inputs here are never
 * NaN, so these compile to single min/max instructions and vectorise. */
static inline float ddof_minf(float a, float b) { return a < b ? a : b; }
static inline float ddof_maxf(float a, float b) { return a > b ? a : b; }

#endif
