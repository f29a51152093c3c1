/* test_dual.c — the dual grid's building blocks (src/core/dualgrid.c):
 * the simple-validity bound never misses a valid plane, density removal is
 * exact, and the grid does not depend on the thread count. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "core/dual.h"

/* Random triangles in a ball of radius 10, sizes from tiny to large, made
 * into dual faces by the library's own dual_faces_build (grid centre at the
 * origin). */
static dual_face *random_faces(size_t n, uint64_t seed) {
  bbc__rng r = {seed};
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  m.vertex_count = 3 * n;
  m.triangle_count = n;
  m.positions = malloc(9 * n * sizeof *m.positions);
  m.indices = malloc(3 * n * sizeof *m.indices);
  uint32_t *tris = malloc(n * sizeof *tris);
  for (size_t i = 0; i < n; i++) {
    double size = i % 3 == 0 ? 0.05 : (i % 3 == 1 ? 0.5 : 3.0);
    double c[3] = {bbc__rng_range(&r, -7, 7), bbc__rng_range(&r, -7, 7), bbc__rng_range(&r, -7, 7)};
    for (int j = 0; j < 3; j++) {
      for (int k = 0; k < 3; k++)
        m.positions[9 * i + 3 * j + k] = c[k] + bbc__rng_range(&r, -size, size);
      m.indices[3 * i + j] = (uint32_t)(3 * i + j);
    }
    tris[i] = (uint32_t)i;
  }
  const double origin[3] = {0, 0, 0};
  dual_face *f = NULL;
  assert_int_equal(bbc__dual_faces_build(&m, tris, n, origin, &f), BBC_OK);
  free(m.positions);
  free(m.indices);
  free(tris);
  return f;
}

/* Direction angles of n in the frame. */
static void angles(const dual_frame *fr, const double n[3], double *theta, double *phi) {
  double a = n[0] * fr->axis_a[0] + n[1] * fr->axis_a[1] + n[2] * fr->axis_a[2];
  double b = n[0] * fr->axis_b[0] + n[1] * fr->axis_b[1] + n[2] * fr->axis_b[2];
  double u = n[0] * fr->axis_up[0] + n[1] * fr->axis_up[1] + n[2] * fr->axis_up[2];
  *theta = atan2(b, a);
  *phi = asin(u > 1 ? 1 : (u < -1 ? -1 : u));
}

/* For random valid planes of random faces, every box of directions that
 * contains the plane's direction (grid cells of several sizes, and random
 * sub-boxes as the refinement makes them) must report the face simply valid
 * with the plane's rho inside [lo, hi]. */
static void test_simple_validity_never_misses(void **state) {
  (void)state;
  const size_t nf = 3000;
  dual_face *faces = random_faces(nf, 7);
  bbc__rng r = {99};
  size_t checked = 0;
  for (int up = 0; up < 3; up++) {
    dual_frame fr;
    bbc__dual_frame_init(&fr, up);
    for (size_t i = 0; i < nf; i++) {
      const dual_face *f = &faces[i];
      double eps = (i % 4 + 1) * 0.05;
      for (int t = 0; t < 4; t++) {
        /* A random direction near the face normal (so that valid planes
         * exist also for large faces), then a rho inside the exact range. */
        double n[3];
        double spread = t == 0 ? 0.05 : (t == 1 ? 0.3 : 1.5);
        for (int k = 0; k < 3; k++) n[k] = f->n[k] + bbc__rng_range(&r, -spread, spread);
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++) n[k] /= l;
        double vmax = -1e300, vmin = 1e300;
        for (int j = 0; j < 3; j++) {
          double v = 0;
          for (int k = 0; k < 3; k++) v += (f->c[k] + f->d[j][k]) * n[k];
          vmax = v > vmax ? v : vmax;
          vmin = v < vmin ? v : vmin;
        }
        if (vmax - eps > vmin + eps) continue; /* no valid plane along n */
        double rho = bbc__rng_range(&r, vmax - eps, vmin + eps);
        assert_true(bbc__dual_face_valid(f, n, rho, eps));
        double th, ph;
        angles(&fr, n, &th, &ph);
        for (int res = 1; res <= 4; res++) {
          /* A box of size res * 4.5 degrees at a random offset around n. */
          double size = res * 4.5 * M_PI / 180;
          double ot = bbc__rng_uniform(&r) * size, op = bbc__rng_uniform(&r) * size;
          dual_box b = {th - ot, th - ot + size, ph - op, ph - op + size, 0, 0};
          if (b.p0 < -M_PI / 2) {
            b.p0 = -M_PI / 2;
            b.p1 = b.p0 + size;
          }
          if (b.p1 > M_PI / 2) {
            b.p1 = M_PI / 2;
            b.p0 = b.p1 - size;
          }
          dual_dir d;
          bbc__dual_dir_of_box(&fr, &b, &d);
          double lo, hi;
          if (!dual_face_range(f, &d, eps, &lo, &hi))
            fail_msg("face %zu: a valid plane's box reported empty (res %d)", i, res);
          if (rho < lo || rho > hi)
            fail_msg("face %zu: rho %g outside [%g, %g] (res %d)", i, rho, lo, hi, res);
          checked++;
        }
      }
    }
  }
  assert_true(checked > 10000);
  free(faces);
}

static int grids_equal(const dual_grid *a, const dual_grid *b) {
  size_t n = (size_t)a->n_theta * a->n_phi * a->n_rho;
  return !memcmp(a->contrib, b->contrib, n * sizeof *a->contrib) &&
         !memcmp(a->penalty, b->penalty, n * sizeof *a->penalty);
}

/* Adding every face and removing them again in another order and in
 * subsets leaves exactly zero; 1 and 2 threads build identical grids. */
static void test_density_exact_and_thread_independent(void **state) {
  (void)state;
  const size_t nf = 2000;
  dual_face *faces = random_faces(nf, 11);
  double area = 0;
  for (size_t i = 0; i < nf; i++) area += faces[i].area;
  dual_grid g1, g2;
  assert_int_equal(bbc__dual_grid_init(&g1, 9, 0.6, 13, 1, area, 1), BBC_OK);
  assert_int_equal(bbc__dual_grid_init(&g2, 9, 0.6, 13, 1, area, 2), BBC_OK);
  bbc__dual_grid_accumulate(&g1, faces, NULL, nf, +1, NULL);
  bbc__dual_grid_accumulate(&g2, faces, NULL, nf, +1, NULL);
  assert_true(grids_equal(&g1, &g2));
  size_t ncell = (size_t)g1.n_theta * g1.n_phi * g1.n_rho, nonzero = 0;
  for (size_t c = 0; c < ncell; c++) nonzero += g1.contrib[c] != 0;
  assert_true(nonzero > ncell / 10);
  /* Remove odd faces, then even ones, in reverse order. */
  uint32_t *odd = malloc(nf / 2 * sizeof *odd), *even = malloc(nf / 2 * sizeof *even);
  for (size_t i = 0; i < nf / 2; i++) {
    odd[i] = (uint32_t)(nf - 1 - 2 * i);
    even[i] = (uint32_t)(nf - 2 - 2 * i);
  }
  bbc__dual_grid_accumulate(&g1, faces, odd, nf / 2, -1, NULL);
  bbc__dual_grid_accumulate(&g1, faces, even, nf / 2, -1, NULL);
  for (size_t c = 0; c < ncell; c++) {
    assert_int_equal(g1.contrib[c], 0);
    assert_int_equal(g1.penalty[c], 0);
  }
  free(odd);
  free(even);
  bbc__dual_grid_free(&g1);
  bbc__dual_grid_free(&g2);
  free(faces);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_simple_validity_never_misses),
      cmocka_unit_test(test_density_exact_and_thread_independent),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
