/* hull.c — the convex hull of points in a plane (Andrew's monotone chain),
 * for a billboard's minimum-area rectangle (src/planes/tweak.c) and its
 * tight outline (src/cloud/outline.c). */
#include "base.h"

#include <math.h>
#include <stdlib.h>

static int pt_cmp(const void *a, const void *b) {
  const bbc__pt2 *p = a, *q = b;
  if (p->x != q->x) return p->x < q->x ? -1 : 1;
  if (p->y != q->y) return p->y < q->y ? -1 : 1;
  return 0;
}

static double cross2(bbc__pt2 o, bbc__pt2 a, bbc__pt2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* Drops the points strictly inside the polygon of the extreme points in
 * eight directions (Akl and Toussaint's heuristic): they cannot be hull
 * vertices, and most of a billboard's points are such. The polygon's
 * vertices lie on the hull in counter-clockwise order; "strictly" has a
 * margin far above the rounding of cross2, so no hull point is dropped and
 * the hull comes out the same.
 * Returns the number kept (in their order). */
static size_t drop_interior(bbc__pt2 *p, size_t n) {
  if (n < 16) return n;
  /* extremes of x, x + y, y, y - x, -x, -x - y, -y, x - y: counter-clockwise */
  size_t e[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double best[8];
  double lo = p[0].x, hi = p[0].x, big = 0;
  for (int k = 0; k < 8; k++) best[k] = -INFINITY;
  for (size_t i = 0; i < n; i++) {
    double x = p[i].x, y = p[i].y;
    const double v[8] = {x, x + y, y, y - x, -x, -x - y, -y, x - y};
    for (int k = 0; k < 8; k++)
      if (v[k] > best[k]) {
        best[k] = v[k];
        e[k] = i;
      }
    lo = fmin(lo, fmin(x, y));
    hi = fmax(hi, fmax(x, y));
    big = fmax(big, fmax(fabs(x), fabs(y)));
  }
  bbc__pt2 poly[8];
  int m = 0;
  for (int k = 0; k < 8; k++) {
    bbc__pt2 q = p[e[k]];
    if (m == 0 || q.x != poly[m - 1].x || q.y != poly[m - 1].y) poly[m++] = q;
  }
  while (m > 1 && poly[m - 1].x == poly[0].x && poly[m - 1].y == poly[0].y) m--;
  if (m < 3) return n;
  /* cross2's rounding: a few ulps of the coordinates times the span */
  double span = hi - lo, tol = 1e-9 * span * fmax(span, big);
  if (!(tol > 0)) return n;
  size_t k = 0;
  for (size_t i = 0; i < n; i++) {
    int inside = 1;
    for (int j = 0; j < m && inside; j++) inside = cross2(poly[j], poly[(j + 1) % m], p[i]) > tol;
    if (!inside) p[k++] = p[i];
  }
  return k;
}

size_t bbc__convex_hull_2d(bbc__pt2 *p, size_t n, bbc__pt2 *h) {
  n = drop_interior(p, n);
  qsort(p, n, sizeof *p, pt_cmp);
  size_t k = 0;
  for (size_t i = 0; i < n; i++) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0) k--;
    h[k++] = p[i];
  }
  for (size_t i = n - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i]) <= 0) k--;
    h[k++] = p[i];
  }
  return k > 1 ? k - 1 : k;
}

double bbc__polygon_area_2d(const bbc__pt2 *p, size_t n) {
  double a = 0;
  for (size_t i = 0; i < n; i++) {
    const bbc__pt2 *q = &p[(i + 1) % n];
    a += p[i].x * q->y - q->x * p[i].y;
  }
  return 0.5 * a;
}
