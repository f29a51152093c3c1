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
