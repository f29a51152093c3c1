/*
 * base.h — what every layer of the library shares (src/base): errors and
 * callbacks, labels for repeated stages, small numeric helpers, the
 * deterministic random numbers and the thread-count rule (3-vectors are
 * vec3.h's). Not installed.
 * Every non-static symbol here starts with `bbc__` (two underscores) so it
 * never collides with a user's names or with the public API.
 */
#ifndef BBC_BASE_H
#define BBC_BASE_H

#ifdef _OPENMP
#include <omp.h>
#endif
#include "bbc.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

/* C11 does not promise M_PI; POSIX does. */
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define BBC__PRINTF(fmt, args) BBC_PRINTF(fmt, args)

/* The innermost loops of steps 1-3 compiled twice, for AVX2 and for any
 * x86-64, the one the processor supports chosen at load time (GCC's
 * function multi-versioning). The same results either way: C11 mode
 * contracts no multiply-add into FMA, and vectorising reorders no sum. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) &&       \
    !defined(__SANITIZE_ADDRESS__) /* glibc: the choice is an ifunc */
#define BBC__CLONES __attribute__((target_clones("avx2", "default")))
#else
#define BBC__CLONES
#endif

/* Sets err (when not NULL) to `code` and a formatted message; returns code. */
bbc_result bbc__fail(bbc_error *err, bbc_result code, const char *fmt, ...) BBC__PRINTF(3, 4);

/* Calls the log callback, if any, with a formatted message. */
void bbc__log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...) BBC__PRINTF(3, 4);

/* Calls the progress callback, if any. */
void bbc__progress(const bbc_callbacks *cb, const char *stage, double fraction);
/* Whether the caller's cancel callback asks to stop (see bbc_callbacks). */
int bbc__cancelled(const bbc_callbacks *cb);

/* Twice triangle t's area vector (its unnormalised normal) into c[3]. */
void bbc__triangle_cross(const bbc_mesh *m, size_t t, double *c);
/* Triangle t's area: half the length of that vector. */
double bbc__triangle_area(const bbc_mesh *m, size_t t);

/* The sRGB transfer function (IEC 61966-2-1) and its inverse, for colours
 * in [0, 1]. A material's base_color multiplies texels as stored (sRGB),
 * as an OBJ's Kd does in viewers; glTF's baseColorFactor is linear
 * (glTF 2.0, 3.9.2), so its readers and writers convert. */
double bbc__srgb_to_linear(double c);
double bbc__linear_to_srgb(double c);

/* strdup that returns NULL for a NULL input. */
char *bbc__strdup(const char *s);

/* Seconds from a monotonic clock (stage timings). */
double bbc__now_s(void);

/* A point in a plane. */
typedef struct bbc__pt2 {
  double x, y;
} bbc__pt2;
/* The convex hull of p[0..n) (reordered here) into h (room for n + 1),
 * counter-clockwise, collinear points left out; its corner count. */
size_t bbc__convex_hull_2d(bbc__pt2 *p, size_t n, bbc__pt2 *h);
/* The signed area of polygon p[0..n) (the shoelace formula; > 0
 * counter-clockwise). */
double bbc__polygon_area_2d(const bbc__pt2 *p, size_t n);
/* The eigenvector of the smallest eigenvalue of a symmetric 3 x 3 matrix
 * (cyclic Jacobi; `a` is overwritten): the normal of least spread. */
void bbc__smallest_eigenvector(double a[3][3], double out[3]);
/* The unit eigenvector of the largest eigenvalue of a symmetric 3 x 3
 * matrix by 32 steps of power iteration from `start` (deterministic); `v`
 * keeps the last good step (`start` when the matrix is zero). */
void bbc__largest_eigenvector(const double a[3][3], const double start[3], double v[3]);

/* ---- coverage-keeping binary alpha (src/base/image.c) -------------------- */
/* Which of a w x h grid's cells turn opaque (mask 1, else 0) from their
 * covered fractions frac (0..1): coverage-keeping error diffusion
 * (Floyd-Steinberg, serpentine rows, the error renormalised at the edges
 * so that none leaves the grid), so that over any small area the share of
 * opaque cells is the share covered; a cell turns opaque only where
 * cand[cell] (NULL: where frac > 0). 0, or -1 out of memory.
 * Deterministic. */
int bbc__coverage_diffuse(const float *frac, const uint8_t *cand, int w, int h, uint8_t *mask);
/* The same kept down a quadtree instead: as many opaque cells as the
 * fractions sum to (rounded), shared between each rectangle's quarters
 * (halved across and down) in proportion to their sums, by largest
 * remainder (ties: the first quarter), a cell of fraction 0 never; so a
 * grid's coverage is kept whole and every block of the tree within a cell
 * (error diffusion loses what drifts into empty cells: an impostor's far
 * mip levels 8 % thinner), at the price of blocks off the tree's grid
 * (block IoU over 8 x 8 cells at any phase: 0.935 against error
 * diffusion's 0.941 on a sparse tree's frames). `stride`: the grid's row
 * length. */
void bbc__coverage_tree(const float *frac, int w, int h, int stride, uint8_t *mask);

/* ---- impostors (src/base/octahedral.c) ---------------------------------- */
/* A model-space direction (up axis `up`: 0 x, 1 y, 2 z) in the octahedral
 * mapping's frame (+y up), as bbc_octahedral_encode takes it. */
void bbc__impostor_to_mapping(int up, const double model[3], double mapping[3]);

/* ---- deterministic random numbers (splitmix64) --------------------------- */
typedef struct bbc__rng {
  uint64_t state;
} bbc__rng;

static inline uint64_t bbc__rng_next(bbc__rng *r) {
  uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
/* Uniform in [0, 1). */
static inline double bbc__rng_uniform(bbc__rng *r) {
  return (double)(bbc__rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}
/* Uniform in [lo, hi). */
static inline double bbc__rng_range(bbc__rng *r, double lo, double hi) {
  return lo + (hi - lo) * bbc__rng_uniform(r);
}

/* The team size of a parallel region for the `threads` parameter: itself
 * when > 0, else every core OpenMP offers (1 without OpenMP). */
static inline int bbc__thread_count(int threads) {
#ifdef _OPENMP
  return threads > 0 ? threads : omp_get_max_threads();
#else
  (void)threads;
  return 1;
#endif
}

/* The `threads` parameter for the parallel loops that name no thread count
 * (library functions without the parameter, called by steps 1 and 3):
 * OpenMP's default team size of the calling thread set to `threads` when
 * it is > 0, and put back by bbc__threads_restore. */
static inline int bbc__threads_use(int threads) {
#ifdef _OPENMP
  int old = omp_get_max_threads();
  if (threads > 0) omp_set_num_threads(threads);
  return old;
#else
  (void)threads;
  return 1;
#endif
}
static inline void bbc__threads_restore(int old) {
#ifdef _OPENMP
  omp_set_num_threads(old);
#else
  (void)old;
#endif
}

#endif /* BBC_BASE_H */
