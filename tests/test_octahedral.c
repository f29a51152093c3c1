/* test_octahedral.c — the octahedral impostors' mapping (src/base/
 * octahedral.c): direction -> square -> direction, frame -> direction ->
 * frame, the halves of the sphere where they belong, and the three-frame
 * blend's weights. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "bbc.h"

/* Unit directions spread over the sphere (a Fibonacci lattice), with the
 * axes and the diagonals of the octahedron's faces and edges among them. */
static int directions(double (*d)[3], int n) {
  int k = 0;
  for (int i = 0; i < n; i++) {
    double z = 1 - (2.0 * i + 1) / n, r = sqrt(1 - z * z), phi = i * 2.399963229728653;
    d[k][0] = r * cos(phi);
    d[k][1] = z;
    d[k][2] = r * sin(phi);
    k++;
  }
  static const double extra[][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                    {0, 0, -1}, {1, 1, 1},  {-1, -1, 1}, {1, -1, -1}, {1, 0, 1},
                                    {-1, 0, 1}, {0, 1, -1}, {0, -1, 1}};
  for (size_t e = 0; e < sizeof extra / sizeof extra[0]; e++) {
    double l =
        sqrt(extra[e][0] * extra[e][0] + extra[e][1] * extra[e][1] + extra[e][2] * extra[e][2]);
    for (int c = 0; c < 3; c++) d[k][c] = extra[e][c] / l;
    k++;
  }
  return k;
}

static double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void test_round_trip(void **state) {
  (void)state;
  double d[2013][3];
  int n = directions(d, 2000);
  for (int hemi = 0; hemi < 2; hemi++)
    for (int k = 0; k < n; k++) {
      double uv[2], back[3];
      bbc_octahedral_encode(d[k], hemi, uv);
      assert_true(uv[0] >= 0 && uv[0] <= 1 && uv[1] >= 0 && uv[1] <= 1);
      bbc_octahedral_decode(uv, hemi, back);
      assert_true(fabs(dot(back, back) - 1) < 1e-12);
      if (!hemi || d[k][1] >= 0) {
        if (dot(back, d[k]) < 1 - 1e-12)
          fail_msg("hemi %d: (%g %g %g) came back (%g %g %g)", hemi, d[k][0], d[k][1], d[k][2],
                   back[0], back[1], back[2]);
      } else { /* below the horizon: onto it, the same azimuth (straight down has none) */
        double h = sqrt(d[k][0] * d[k][0] + d[k][2] * d[k][2]);
        if (h < 1e-9) continue;
        assert_true(fabs(back[1]) < 1e-12);
        assert_true(fabs((back[0] * d[k][0] + back[2] * d[k][2]) / h - 1) < 1e-9);
      }
    }
  /* where the halves go: the whole sphere's upper half inside the diamond
   * |x - 1/2| + |y - 1/2| <= 1/2, the lower half outside; the hemi map's
   * zenith in the middle, its horizon on the square's border */
  double up[3] = {0, 1, 0}, down[3] = {0, -1, 0}, uv[2];
  bbc_octahedral_encode(up, 0, uv);
  assert_true(fabs(uv[0] - 0.5) < 1e-12 && fabs(uv[1] - 0.5) < 1e-12);
  bbc_octahedral_encode(down, 0, uv);
  assert_true(fabs(fabs(uv[0] - 0.5) - 0.5) < 1e-12 && fabs(fabs(uv[1] - 0.5) - 0.5) < 1e-12);
  for (int k = 0; k < n; k++) {
    bbc_octahedral_encode(d[k], 0, uv);
    double diamond = fabs(uv[0] - 0.5) + fabs(uv[1] - 0.5);
    if (d[k][1] > 1e-9) assert_true(diamond < 0.5 + 1e-12);
    if (d[k][1] < -1e-9) assert_true(diamond > 0.5 - 1e-12);
    if (fabs(d[k][1]) < 1e-12) {
      bbc_octahedral_encode(d[k], 1, uv);
      assert_true(fabs(fmax(fabs(uv[0] - 0.5), fabs(uv[1] - 0.5)) - 0.5) < 1e-12);
    }
  }
  bbc_octahedral_encode(up, 1, uv);
  assert_true(fabs(uv[0] - 0.5) < 1e-12 && fabs(uv[1] - 0.5) < 1e-12);
}

/* frame -> direction -> frame: a frame seen along its own direction blends
 * itself alone; every frame's direction is distinct */
static void test_frames(void **state) {
  (void)state;
  for (int hemi = 0; hemi < 2; hemi++)
    for (int n = 2; n <= 16; n += 7) {
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
          double d[3], w[3];
          int f[3][2];
          bbc_octahedral_frame_dir(n, i, j, hemi, d);
          assert_true(fabs(dot(d, d) - 1) < 1e-12);
          bbc_octahedral_blend(d, n, hemi, f, w);
          /* the whole sphere's border points are one direction seen from
           * several (the fold): the frame found shows the same direction */
          int found = 0;
          for (int k = 0; k < 3; k++) {
            if (w[k] < 1 - 1e-9) continue;
            double e[3];
            bbc_octahedral_frame_dir(n, f[k][0], f[k][1], hemi, e);
            found = dot(e, d) > 1 - 1e-9;
          }
          if (!found) fail_msg("hemi %d n %d: frame (%d, %d) is not its own view", hemi, n, i, j);
          for (int i2 = 0; i2 < n; i2++)
            for (int j2 = 0; j2 < n; j2++) {
              if (i2 == i && j2 == j) continue;
              double e[3];
              bbc_octahedral_frame_dir(n, i2, j2, hemi, e);
              /* distinct, but for the whole sphere's folded border */
              int border = !hemi && (i == 0 || j == 0 || i == n - 1 || j == n - 1);
              if (!border) assert_true(dot(e, d) < 1 - 1e-9);
            }
        }
    }
}

/* the blend: weights >= 0 summing to 1, frames on the grid, the nearest
 * frame weighted most, and the weights continuous in the direction */
static void test_blend(void **state) {
  (void)state;
  double d[2013][3];
  int n = directions(d, 2000);
  const int grid = 12;
  for (int hemi = 0; hemi < 2; hemi++)
    for (int k = 0; k < n; k++) {
      if (hemi && d[k][1] < 0) continue;
      int f[3][2];
      double w[3];
      bbc_octahedral_blend(d[k], grid, hemi, f, w);
      double sum = 0, mix[3] = {0, 0, 0};
      for (int c = 0; c < 3; c++) {
        assert_true(w[c] >= -1e-12 && w[c] <= 1 + 1e-12);
        assert_true(f[c][0] >= 0 && f[c][0] < grid && f[c][1] >= 0 && f[c][1] < grid);
        sum += w[c];
        double e[3];
        bbc_octahedral_frame_dir(grid, f[c][0], f[c][1], hemi, e);
        for (int a = 0; a < 3; a++) mix[a] += w[c] * e[a];
      }
      assert_true(fabs(sum - 1) < 1e-12);
      /* the frames' directions, so weighted, point near the view (within
       * the grid's spacing: 180 / 11 degrees of the whole sphere's equator) */
      double ml = sqrt(dot(mix, mix));
      if (dot(mix, d[k]) / ml < cos(16.4 * 3.14159265358979 / 180))
        fail_msg("hemi %d: the blend of (%g %g %g) points %g degrees away", hemi, d[k][0], d[k][1],
                 d[k][2], acos(dot(mix, d[k]) / ml) * 180 / 3.14159265358979);
      /* a small turn moves the weights a little (away from the fold) */
      double uv[2];
      bbc_octahedral_encode(d[k], hemi, uv);
      if (!hemi && fabs(uv[0] - 0.5) + fabs(uv[1] - 0.5) > 0.45) continue;
      double t[3] = {d[k][0] + 1e-4, d[k][1], d[k][2] - 1e-4}, l = sqrt(dot(t, t));
      for (int c = 0; c < 3; c++) t[c] /= l;
      int g[3][2];
      double v[3];
      bbc_octahedral_blend(t, grid, hemi, g, v);
      for (int a = 0; a < 3; a++) { /* each frame's weight, 0 where not among the three */
        double wa = w[a], va = 0;
        for (int b = 0; b < 3; b++)
          if (g[b][0] == f[a][0] && g[b][1] == f[a][1]) va = v[b];
        assert_true(fabs(wa - va) < 0.01);
      }
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_frames),
      cmocka_unit_test(test_blend),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
