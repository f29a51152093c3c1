/* octahedral.c — the direction <-> frame mapping of octahedral impostors
 * (docs/impostors.md): a unit direction folded onto the
 * octahedron |x| + |y| + |z| = 1 and unfolded onto the square [0, 1]^2
 * (Engelhardt and Dachsbacher 2008; the survey of Cigolle et al. 2014,
 * "A Survey of Efficient Representations for Independent Unit Vectors"),
 * or for a hemi-octahedral impostor its upper half alone turned by 45
 * degrees to fill the square; an N x N grid of frames at the square's grid
 * points (frame (i, j) at (i, j) / (N - 1)); and the three frames a view
 * between them blends, with their weights. The up axis is +y. */
#include "base.h"

#include <assert.h>
#include <math.h>
#include <string.h>

static double sign1(double v) {
  return v < 0 ? -1.0 : 1.0;
}

void bbc_octahedral_encode(const double d[3], int hemi, double uv[2]) {
  assert(d && uv);
  /* z-up octahedral coordinates: a = x, b = z, up = y */
  double a = d[0], b = d[2], up = d[1];
  double s = fabs(a) + fabs(b) + fabs(up);
  if (!(s > 0)) {
    uv[0] = uv[1] = 0.5;
    return;
  }
  a /= s, b /= s, up /= s;
  double x, y;
  if (hemi) {
    if (up < 0) { /* below the horizon: onto it */
      double t = fabs(a) + fabs(b);
      up = 0;
      if (t > 0) a /= t, b /= t;
    }
    x = a + b;
    y = a - b;
  } else if (up >= 0) {
    x = a;
    y = b;
  } else { /* the lower half folded out over the square's corners */
    x = (1 - fabs(b)) * sign1(a);
    y = (1 - fabs(a)) * sign1(b);
  }
  uv[0] = 0.5 * x + 0.5;
  uv[1] = 0.5 * y + 0.5;
}

void bbc_octahedral_decode(const double uv[2], int hemi, double d[3]) {
  assert(uv && d);
  double x = 2 * uv[0] - 1, y = 2 * uv[1] - 1, a, b, up;
  if (hemi) {
    a = 0.5 * (x + y);
    b = 0.5 * (x - y);
    up = 1 - fabs(a) - fabs(b);
  } else {
    a = x;
    b = y;
    up = 1 - fabs(x) - fabs(y);
    if (up < 0) { /* the lower half */
      double fa = (1 - fabs(y)) * sign1(x), fb = (1 - fabs(x)) * sign1(y);
      a = fa;
      b = fb;
    }
  }
  double l = sqrt(a * a + b * b + up * up);
  d[0] = a / l;
  d[1] = up / l;
  d[2] = b / l;
}

void bbc_octahedral_frame_dir(int n, int i, int j, int hemi, double d[3]) {
  assert(n >= 2 && d);
  double uv[2] = {(double)i / (n - 1), (double)j / (n - 1)};
  bbc_octahedral_decode(uv, hemi, d);
}

void bbc_octahedral_blend(const double d[3], int n, int hemi, int frame[3][2], double weight[3]) {
  assert(d && n >= 2 && frame && weight);
  double uv[2];
  bbc_octahedral_encode(d, hemi, uv);
  double gx = uv[0] * (n - 1), gy = uv[1] * (n - 1);
  int i = (int)floor(gx), j = (int)floor(gy);
  if (i > n - 2) i = n - 2;
  if (j > n - 2) j = n - 2;
  if (i < 0) i = 0;
  if (j < 0) j = 0;
  double fx = gx - i, fy = gy - j;
  /* the grid square split along its diagonal from (i, j) to (i+1, j+1) */
  frame[0][0] = i, frame[0][1] = j;
  frame[2][0] = i + 1, frame[2][1] = j + 1;
  if (fx >= fy) {
    frame[1][0] = i + 1, frame[1][1] = j;
    weight[0] = 1 - fx;
    weight[1] = fx - fy;
    weight[2] = fy;
  } else {
    frame[1][0] = i, frame[1][1] = j + 1;
    weight[0] = 1 - fy;
    weight[1] = fy - fx;
    weight[2] = fx;
  }
}

/* A direction of the mapping's frame (+y up) in a model whose up axis is
 * `up` (a cyclic permutation of the axes: +y onto up), and back. */
static void to_model(int up, const double c[3], double m[3]) {
  m[(up + 2) % 3] = c[0];
  m[up] = c[1];
  m[(up + 1) % 3] = c[2];
}

void bbc__impostor_to_mapping(int up, const double m[3], double c[3]) {
  c[0] = m[(up + 2) % 3];
  c[1] = m[up];
  c[2] = m[(up + 1) % 3];
}

void bbc_impostor_frame_basis(const bbc_impostor *imp, int i, int j, double dir[3], double right[3],
                              double up[3]) {
  assert(imp && dir && right && up && imp->frames >= 2);
  int ax = (int)imp->up >= 0 && imp->up <= 2 ? (int)imp->up : 1;
  double c[3];
  bbc_octahedral_frame_dir(imp->frames, i, j, imp->hemi, c);
  to_model(ax, c, dir);
  /* The image's up: the model's, or for a view along it (from straight
   * above or below) the mapping's -z (the same for every such frame). */
  double hint[3] = {0, 0, 0}, f[3] = {-dir[0], -dir[1], -dir[2]};
  if (fabs(dir[ax]) > 0.999)
    hint[(ax + 1) % 3] = -1;
  else
    hint[ax] = 1;
  double r[3] = {f[1] * hint[2] - f[2] * hint[1], f[2] * hint[0] - f[0] * hint[2],
                 f[0] * hint[1] - f[1] * hint[0]};
  double l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  for (int k = 0; k < 3; k++) right[k] = r[k] / l;
  up[0] = right[1] * f[2] - right[2] * f[1];
  up[1] = right[2] * f[0] - right[0] * f[2];
  up[2] = right[0] * f[1] - right[1] * f[0];
}

void bbc_impostor_frame_view(const bbc_impostor *imp, int i, int j, bbc_view *view) {
  assert(imp && view);
  double dir[3], right[3], up[3];
  bbc_impostor_frame_basis(imp, i, j, dir, right, up);
  memset(view, 0, sizeof *view);
  for (int k = 0; k < 3; k++) {
    view->direction[k] = -dir[k];
    view->up[k] = up[k];
    view->center[k] = imp->center[k];
  }
  view->half_extent = imp->half_extent;
}

void bbc_impostor_options_default(bbc_impostor_options *o) {
  assert(o);
  memset(o, 0, sizeof *o);
}

void bbc_impostor_free(bbc_impostor *imp) {
  if (!imp) return;
  bbc_image_free(&imp->albedo);
  bbc_image_free(&imp->normal);
  memset(imp, 0, sizeof *imp);
}
