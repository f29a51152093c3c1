/* test_dual.c — the dual grid's building blocks (src/planes/dualgrid.c):
 * the simple-validity bound never misses a valid plane, density removal is
 * exact, and the grid does not depend on the thread count. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dual.h"

/* Random triangles in a ball of radius 10, sizes from tiny to large, made
 * into dual faces by the library's own dual_faces_build (grid centre at the
 * origin). With `quads`, every other pair of triangles is a planar
 * parallelogram split along a diagonal, and the faces are built by
 * dual_faces_build_merged (those pairs become faces of four vertices);
 * *count gets the number of faces. */
static dual_face *random_faces(size_t n, uint64_t seed, int quads, size_t *count) {
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
    if (quads && i % 4 == 0 && i + 1 < n) {
      /* corners c, c + a, c + a + b, c + b; triangles (0 1 2) and (0 2 3) */
      double a[3], b[3], q[4][3];
      for (int k = 0; k < 3; k++) {
        a[k] = bbc__rng_range(&r, -size, size);
        b[k] = bbc__rng_range(&r, -size, size);
      }
      for (int k = 0; k < 3; k++) {
        q[0][k] = c[k];
        q[1][k] = c[k] + a[k];
        q[2][k] = c[k] + a[k] + b[k];
        q[3][k] = c[k] + b[k];
      }
      for (int j = 0; j < 4; j++)
        for (int k = 0; k < 3; k++) m.positions[9 * i + 3 * j + k] = q[j][k];
      const uint32_t v = (uint32_t)(3 * i);
      const uint32_t ix[6] = {v, v + 1, v + 2, v, v + 2, v + 3};
      memcpy(m.indices + 3 * i, ix, sizeof ix);
      tris[i] = (uint32_t)i;
      tris[i + 1] = (uint32_t)(i + 1);
      i++;
      continue;
    }
    for (int j = 0; j < 3; j++) {
      for (int k = 0; k < 3; k++)
        m.positions[9 * i + 3 * j + k] = c[k] + bbc__rng_range(&r, -size, size);
      m.indices[3 * i + j] = (uint32_t)(3 * i + j);
    }
    tris[i] = (uint32_t)i;
  }
  const double origin[3] = {0, 0, 0};
  dual_face *f = NULL;
  *count = n;
  if (quads)
    assert_int_equal(bbc__dual_faces_build_merged(&m, tris, n, origin, 0, &f, count), BBC_OK);
  else
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
static void never_misses(int quads) {
  size_t nf;
  dual_face *faces = random_faces(3000, 7, quads, &nf);
  if (quads) assert_true(nf < 3000 * 7 / 8); /* a quarter of the triangles pair up */
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
        for (int j = 0; j < f->nv; j++) {
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
          double lo = 0, hi = 0;
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

static void test_simple_validity_never_misses(void **state) {
  (void)state;
  never_misses(0);
}

/* The same for faces of four vertices (two coplanar triangles). */
static void test_simple_validity_never_misses_quads(void **state) {
  (void)state;
  never_misses(1);
}

/* Which triangles become one face: a planar quad does, a bent one, a pair
 * facing opposite ways and a lone triangle do not; the face keeps both
 * triangles, its four corners, the summed area. */
static void test_merged_faces(void **state) {
  (void)state;
  const double p[][3] = {{0, 0, 0}, {1, 0, 0},  {1, 1, 0}, {0, 1, 0}, /* flat quad: 0 1 2, 0 2 3 */
                         {3, 0, 0}, {4, 0, 0},  {4, 1, 0}, {3, 1, 0.3}, /* bent: 4 5 6, 4 6 7 */
                         {6, 0, 0}, {7, 0, 0},  {7, 1, 0}, {6, 1, 0}, /* flipped: 8 9 10, 8 11 10 */
                         {9, 0, 0}, {10, 0, 0}, {9, 1, 0}};           /* lone: 12 13 14 */
  const uint32_t ix[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 11, 10, 12, 13, 14};
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  m.vertex_count = 15;
  m.triangle_count = 7;
  m.positions = (double *)p;
  m.indices = (uint32_t *)ix;
  uint32_t tris[7] = {0, 1, 2, 3, 4, 5, 6};
  const double origin[3] = {0, 0, 0};
  dual_face *f = NULL;
  size_t n = 0;
  assert_int_equal(bbc__dual_faces_build_merged(&m, tris, 7, origin, 0, &f, &n), BBC_OK);
  assert_int_equal(n, 6);
  assert_int_equal(f[0].nv, 4);
  assert_int_equal(f[0].mesh_index, 0);
  assert_int_equal(f[0].mesh_index2, 1);
  assert_true(fabs(f[0].area - 1.0) < 1e-12);
  for (int j = 0; j < 4; j++) /* the corners: the first triangle's, then the apex */
    for (int k = 0; k < 3; k++) assert_true(fabs(f[0].c[k] + f[0].d[j][k] - p[j][k]) < 1e-12);
  const double z[3] = {0, 0, 1};
  assert_true(bbc__dual_face_valid(&f[0], z, 0.0, 1e-9));
  for (size_t i = 1; i < n; i++) {
    assert_int_equal(f[i].nv, 3);
    assert_int_equal(f[i].mesh_index, i + 1);
    assert_int_equal(f[i].mesh_index2, UINT32_MAX);
  }
  free(f);
  /* With a flatness tolerance the bent pair (its apexes 0.28 and 0.3 from
   * the other's plane, 23 degrees) joins too when the tolerance allows. */
  assert_int_equal(bbc__dual_faces_build_merged(&m, tris, 7, origin, 0.25, &f, &n), BBC_OK);
  assert_int_equal(n, 6);
  free(f);
  assert_int_equal(bbc__dual_faces_build_merged(&m, tris, 7, origin, 0.35, &f, &n), BBC_OK);
  assert_int_equal(n, 5);
  assert_int_equal(f[1].nv, 4);
  assert_int_equal(f[1].mesh_index, 2);
  assert_int_equal(f[1].mesh_index2, 3);
  assert_true(bbc__dual_face_valid(&f[1], z, 0.15, 0.16)); /* all four near z = 0.15 */
  assert_false(bbc__dual_face_valid(&f[1], z, 0.0, 0.16)); /* the apex at z = 0.3 is not */
  free(f);
}

/* The pairing rule of dual_faces_build_merged, written out plainly: a
 * triangle and, across its edges in order, the other of the first two
 * triangles on that edge, when later, unpaired, of area > 0, in its plane,
 * facing the same way, the edge run the other way. */
static size_t pairs_by_rule(const bbc_mesh *m, uint32_t *mate) {
  size_t n = m->triangle_count, nf = 0;
  for (size_t i = 0; i < n; i++) mate[i] = UINT32_MAX;
  for (size_t i = 0; i < n; i++) {
    if (mate[i] != UINT32_MAX) continue;
    nf++;
    const uint32_t *ix = m->indices + 3 * i;
    for (int e = 0; e < 3 && mate[i] == UINT32_MAX; e++) {
      uint32_t a = ix[e], b = ix[(e + 1) % 3];
      if (a == b) continue;
      size_t first[2] = {SIZE_MAX, SIZE_MAX};
      int k = 0;
      for (size_t t = 0; t < n && k < 2; t++) {
        const uint32_t *tx = m->indices + 3 * t;
        int ha = tx[0] == a || tx[1] == a || tx[2] == a,
            hb = tx[0] == b || tx[1] == b || tx[2] == b;
        if (ha && hb) first[k++] = t;
      }
      size_t j = first[0] == i ? first[1] : (first[1] == i ? first[0] : SIZE_MAX);
      if (j == SIZE_MAX || j <= i || mate[j] != UINT32_MAX) continue;
      double ci[3], cj[3];
      bbc__triangle_cross(m, i, ci);
      bbc__triangle_cross(m, j, cj);
      double li = sqrt(ci[0] * ci[0] + ci[1] * ci[1] + ci[2] * ci[2]);
      double lj = sqrt(cj[0] * cj[0] + cj[1] * cj[1] + cj[2] * cj[2]);
      if (!(li > 0) || !(lj > 0)) continue;
      if ((ci[0] * cj[0] + ci[1] * cj[1] + ci[2] * cj[2]) / (li * lj) < 1 - 1e-6) continue;
      const uint32_t *jx = m->indices + 3 * j;
      int opposite = 0;
      for (int q = 0; q < 3; q++) opposite |= jx[q] == b && jx[(q + 1) % 3] == a;
      if (!opposite) continue;
      mate[i] = (uint32_t)j;
      mate[j] = (uint32_t)i;
    }
  }
  return nf;
}

/* Meshes with shared vertices (a grid of flat and bent cells, diagonals
 * either way, some triangles repeated or flipped, some degenerate): the
 * merged faces are exactly the rule's pairs. */
static void test_merged_faces_shared_vertices(void **state) {
  (void)state;
  enum { N = 12 };
  for (uint64_t seed = 1; seed <= 20; seed++) {
    bbc__rng r = {seed};
    bbc_mesh m;
    memset(&m, 0, sizeof m);
    m.vertex_count = (N + 1) * (N + 1);
    m.positions = malloc(3 * m.vertex_count * sizeof *m.positions);
    m.indices = malloc(3 * 4 * N * N * sizeof *m.indices);
    for (int y = 0; y <= N; y++)
      for (int x = 0; x <= N; x++) {
        double *p = m.positions + 3 * (y * (N + 1) + x);
        p[0] = x;
        p[1] = y;
        p[2] = bbc__rng_range(&r, 0, 1) < 0.1 ? bbc__rng_range(&r, 0, 0.5) : 0;
      }
    size_t nt = 0;
    for (int y = 0; y < N; y++)
      for (int x = 0; x < N; x++) {
        uint32_t a = (uint32_t)(y * (N + 1) + x), b = a + 1, c = a + N + 2, d = a + N + 1;
        double u = bbc__rng_range(&r, 0, 1);
        uint32_t t[2][3] = {{a, b, c}, {a, c, d}};
        if (u < 0.5) {
          uint32_t t2[2][3] = {{a, b, d}, {b, c, d}};
          memcpy(t, t2, sizeof t);
        }
        if (u > 0.9) { /* flipped */
          uint32_t k = t[1][1];
          t[1][1] = t[1][2];
          t[1][2] = k;
        }
        for (int k = 0; k < 2; k++) memcpy(m.indices + 3 * nt++, t[k], sizeof t[k]);
        if (u > 0.8 && u <= 0.85) memcpy(m.indices + 3 * nt++, t[0], sizeof t[0]); /* repeated */
        if (u > 0.85 && u <= 0.9) {                                                /* degenerate */
          uint32_t g[3] = {a, a, b};
          memcpy(m.indices + 3 * nt++, g, sizeof g);
        }
      }
    m.triangle_count = nt;
    uint32_t *tris = malloc(nt * sizeof *tris), *mate = malloc(nt * sizeof *mate);
    for (size_t i = 0; i < nt; i++) tris[i] = (uint32_t)i;
    const double origin[3] = {0, 0, 0};
    dual_face *f = NULL;
    size_t nf = 0;
    assert_int_equal(bbc__dual_faces_build_merged(&m, tris, nt, origin, 0, &f, &nf), BBC_OK);
    assert_int_equal(nf, pairs_by_rule(&m, mate));
    size_t k = 0, quads = 0;
    for (size_t i = 0; i < nt; i++) {
      if (mate[i] != UINT32_MAX && mate[i] < i) continue;
      assert_int_equal(f[k].mesh_index, i);
      assert_int_equal(f[k].mesh_index2, mate[i]);
      quads += mate[i] != UINT32_MAX;
      k++;
    }
    assert_true(quads > nt / 8); /* the test pairs something */
    free(f);
    free(tris);
    free(mate);
    free(m.positions);
    free(m.indices);
  }
}

/* The minimum-area rectangle of random faces holds every vertex and is no
 * larger than the bounding rectangle at any of 720 angles (its hull, with
 * the interior points dropped first, lost no vertex). */
static void test_min_rect(void **state) {
  (void)state;
  const size_t sizes[] = {5, 40, 400, 3000};
  for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
    size_t nf;
    dual_face *faces = random_faces(sizes[si], 77 + si, si % 2, &nf);
    uint32_t *which = malloc(nf * sizeof *which);
    for (size_t i = 0; i < nf; i++) which[i] = (uint32_t)i;
    const double n[3] = {0.36, 0.48, 0.8};
    double u[3], w[3], mn[2], mx[2];
    assert_int_equal(bbc__dual_min_rect(faces, which, nf, n, u, w, mn, mx), BBC_OK);
    double area = (mx[0] - mn[0]) * (mx[1] - mn[1]);
    for (size_t i = 0; i < nf; i++)
      for (int j = 0; j < faces[i].nv; j++) {
        double v[3], pu = 0, pw = 0;
        for (int k = 0; k < 3; k++) v[k] = faces[i].c[k] + faces[i].d[j][k];
        for (int k = 0; k < 3; k++) {
          pu += v[k] * u[k];
          pw += v[k] * w[k];
        }
        assert_true(pu >= mn[0] - 1e-9 && pu <= mx[0] + 1e-9);
        assert_true(pw >= mn[1] - 1e-9 && pw <= mx[1] + 1e-9);
      }
    double a[3] = {u[0], u[1], u[2]}, b[3] = {w[0], w[1], w[2]};
    for (int t = 0; t < 720; t++) {
      double c = cos(t * M_PI / 720), s = sin(t * M_PI / 720), lo[2] = {INFINITY, INFINITY},
             hi[2] = {-INFINITY, -INFINITY};
      for (size_t i = 0; i < nf; i++)
        for (int j = 0; j < faces[i].nv; j++) {
          double v[3], x = 0, y = 0;
          for (int k = 0; k < 3; k++) v[k] = faces[i].c[k] + faces[i].d[j][k];
          for (int k = 0; k < 3; k++) {
            x += v[k] * (c * a[k] + s * b[k]);
            y += v[k] * (-s * a[k] + c * b[k]);
          }
          lo[0] = fmin(lo[0], x);
          hi[0] = fmax(hi[0], x);
          lo[1] = fmin(lo[1], y);
          hi[1] = fmax(hi[1], y);
        }
      assert_true(area <= (hi[0] - lo[0]) * (hi[1] - lo[1]) * (1 + 1e-9));
    }
    free(which);
    free(faces);
  }
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
  size_t nf; /* triangles and faces of four vertices */
  dual_face *faces = random_faces(2000, 11, 1, &nf);
  double area = 0;
  for (size_t i = 0; i < nf; i++) area += faces[i].area;
  dual_grid g1, g2;
  assert_int_equal(bbc__dual_grid_init(&g1, 9, 0.6, 13, 1, area, 1), BBC_OK);
  assert_int_equal(bbc__dual_grid_init(&g2, 9, 0.6, 13, 1, area, 2), BBC_OK);
  assert_int_equal(bbc__dual_grid_accumulate(&g1, faces, NULL, nf, +1, NULL), BBC_OK);
  assert_int_equal(bbc__dual_grid_accumulate(&g2, faces, NULL, nf, +1, NULL), BBC_OK);
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
  assert_int_equal(bbc__dual_grid_accumulate(&g1, faces, odd, nf / 2, -1, NULL), BBC_OK);
  assert_int_equal(bbc__dual_grid_accumulate(&g1, faces, even, nf / 2, -1, NULL), BBC_OK);
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

/* The grid's fixed-point density against the direct formula in doubles:
 * each face adds its projected area times the fraction of a cell that its
 * range [lo, hi] covers, and as penalty the fraction that [lo - eps, lo]
 * covers (thesis Fig. 2-14, 2-15); over both members of each pair of
 * opposite directions. Rounding: positions to 2^-DUAL_FX of a cell (a
 * face's weight times that, for each of its four kinks) and 2 units. */
static void test_density_matches_direct_formula(void **state) {
  (void)state;
  size_t nf;
  dual_face *faces = random_faces(300, 5, 1, &nf);
  double area = 0;
  for (size_t i = 0; i < nf; i++) area += faces[i].area;
  dual_grid g;
  assert_int_equal(bbc__dual_grid_init(&g, 9, 0.6, 13, 1, area, 2), BBC_OK);
  assert_int_equal(bbc__dual_grid_accumulate(&g, faces, NULL, nf, +1, NULL), BBC_OK);
  size_t nd = (size_t)g.n_theta * g.n_phi, ncell = nd * g.n_rho;
  double *rc = calloc(ncell, sizeof *rc), *rp = calloc(ncell, sizeof *rp);
  double *touch = calloc(ncell, sizeof *touch); /* the tolerance */
  for (size_t d = 0; d < nd; d++)
    for (size_t i = 0; i < nf; i++) {
      double lo, hi;
      if (!dual_face_range(&faces[i], &g.dirs[d], g.eps, &lo, &hi)) continue;
      double w = dual_projected_area(&faces[i], g.dirs[d].n) * g.scale;
      for (int k = 0; k < g.n_rho; k++) {
        double r0 = g.rho_min + k * g.rho_res, r1 = r0 + g.rho_res;
        double c = fmin(hi, r1) - fmax(lo, r0), p = fmin(lo, r1) - fmax(lo - g.eps, r0);
        size_t cell = d * g.n_rho + k;
        if (c > 0) rc[cell] += w * c / g.rho_res;
        if (p > 0) rp[cell] += w * p / g.rho_res;
        if (c > -1e-9 || p > -1e-9) touch[cell] += 2 + 4 * w / (double)(1 << DUAL_FX);
      }
    }
  size_t nonzero = 0;
  for (size_t c = 0; c < ncell; c++) {
    double tol = touch[c] + 1;
    assert_true(fabs((double)g.contrib[c] - rc[c]) <= tol);
    assert_true(fabs((double)g.penalty[c] - rp[c]) <= tol);
    nonzero += rc[c] > 1e6;
  }
  assert_true(nonzero > ncell / 10);
  free(rc);
  free(rp);
  free(touch);
  bbc__dual_grid_free(&g);
  free(faces);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_simple_validity_never_misses),
      cmocka_unit_test(test_simple_validity_never_misses_quads),
      cmocka_unit_test(test_merged_faces),
      cmocka_unit_test(test_merged_faces_shared_vertices),
      cmocka_unit_test(test_min_rect),
      cmocka_unit_test(test_density_exact_and_thread_independent),
      cmocka_unit_test(test_density_matches_direct_formula),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
