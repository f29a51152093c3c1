/* outline.c — each billboard's outline tightened around its opaque texels
 * (`outline`, `maxtris`): the convex hull of the texels its front and back
 * images keep (grown by a texel, so that a client's filtering finds every
 * opaque texel inside), cut down to a few corners by removing, one at a
 * time, the edge whose removal adds the least area (its neighbours extended
 * to meet), inside the billboard's rectangle. A GPU then shades the quad's
 * empty corners no more: fewer fragments for a few more vertices. */
#include "cloud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef bbc__pt2 pt; /* (s, t) on the billboard's rectangle as (x, y) */

static double cross3(pt o, pt a, pt b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* A billboard's outline as points, and points as its outline. */
static void outline_points(const bbc_cloud_billboard *cb, pt *h) {
  for (int c = 0; c < cb->corner_count; c++) h[c] = (pt){cb->corners[c][0], cb->corners[c][1]};
}

static void set_outline(bbc_cloud_billboard *cb, const pt *h, size_t n) {
  cb->corner_count = (int)n;
  for (size_t c = 0; c < n; c++) {
    cb->corners[c][0] = h[c].x;
    cb->corners[c][1] = h[c].y;
  }
}

/* Removing edge i (p[i] to p[i+1]) of a convex polygon: where its two
 * neighbouring edges, extended, meet (*x) and the area that adds; -1 when
 * they do not meet beyond it or meet outside the unit square. */
static double edge_removal(const pt *p, size_t n, size_t i, pt *x) {
  pt a = p[(i + n - 1) % n], b = p[i], c = p[(i + 1) % n], d = p[(i + 2) % n];
  double d1s = b.x - a.x, d1t = b.y - a.y, d2s = d.x - c.x, d2t = d.y - c.y;
  double den = d1s * d2t - d1t * d2s;
  if (!(den > 1e-15)) return -1; /* the turns sum to 180 degrees or more */
  double k = ((c.x - b.x) * d2t - (c.y - b.y) * d2s) / den;
  if (k < 0) return -1;
  x->x = b.x + k * d1s;
  x->y = b.y + k * d1t;
  const double tol = 1e-9;
  if (x->x < -tol || x->x > 1 + tol || x->y < -tol || x->y > 1 + tol) return -1;
  x->x = fmin(1, fmax(0, x->x));
  x->y = fmin(1, fmax(0, x->y));
  return 0.5 * fabs(cross3(b, *x, c));
}

/* Polygon p (n corners, convex, counter-clockwise) cut down to at most
 * most corners; its new corner count, 0 when it cannot be. */
static size_t reduce(pt *p, size_t n, int most) {
  while (n > (size_t)most && n > 3) {
    size_t best = n;
    double best_add = INFINITY;
    pt best_x = {0, 0};
    for (size_t i = 0; i < n; i++) {
      pt x;
      double add = edge_removal(p, n, i, &x);
      if (add >= 0 && add < best_add) {
        best_add = add;
        best = i;
        best_x = x;
      }
    }
    if (best == n) return 0;
    /* p[best] becomes x, p[best + 1] goes */
    size_t j = (best + 1) % n;
    p[best] = best_x;
    memmove(&p[j], &p[j + 1], (n - 1 - j) * sizeof *p);
    n--;
  }
  return n;
}

/* The opaque texels' (alpha > 0) hull corners of a billboard's images, in
 * (s, t) of its rectangle (t up, rows top first), each texel grown by
 * `margin` texels. *out: room for 4 x rows. Returns the corner count
 * (0: no opaque texel). */
static size_t opaque_points(const bbc_image *const im[2], int margin, pt *out) {
  size_t n = 0;
  int w = im[0]->width, h = im[0]->height;
  for (int y = 0; y < h; y++) {
    int x0 = w, x1 = -1;
    for (int k = 0; k < 2; k++) {
      if (!im[k] || !im[k]->rgba) continue;
      const uint8_t *row = im[k]->rgba + 4 * (size_t)y * w;
      for (int x = 0; x < w; x++)
        if (row[4 * x + 3]) {
          if (x < x0) x0 = x;
          break;
        }
      for (int x = w - 1; x >= 0; x--)
        if (row[4 * x + 3]) {
          if (x > x1) x1 = x;
          break;
        }
    }
    if (x1 < x0) continue;
    double l = fmax(0, x0 - margin) / w, r = fmin(w, x1 + 1 + margin) / (double)w;
    double top = 1 - fmax(0, y - margin) / h, bot = 1 - fmin(h, y + 1 + margin) / (double)h;
    out[n++] = (pt){l, top};
    out[n++] = (pt){r, top};
    out[n++] = (pt){l, bot};
    out[n++] = (pt){r, bot};
  }
  return n;
}

/* An outline of more than `most` corners (a rectangle clipped to its faces'
 * bounds) cut down to `most`, growing inside the rectangle. */
static void cut_corners(bbc_cloud_billboard *cb, int most) {
  if (cb->corner_count <= most) return;
  pt h[10];
  outline_points(cb, h);
  size_t n = reduce(h, (size_t)cb->corner_count, most);
  if (n) set_outline(cb, h, n);
}

/* One billboard's outline from its images, at most `most` corners; kept
 * as it is when the images have no opaque texel or the new one is no
 * smaller. */
static bbc_result tighten(bbc_cloud_billboard *cb, const bbc__baked *b, int most) {
  const bbc_image *im[2] = {&b->front, b->back.rgba ? &b->back : NULL};
  if (!im[0]->rgba || im[0]->width <= 0 || im[0]->height <= 0) return BBC_OK;
  if (im[1] && (im[1]->width != im[0]->width || im[1]->height != im[0]->height)) return BBC_OK;
  size_t cap = 4 * (size_t)im[0]->height;
  pt *p = malloc(cap * sizeof *p), *h = malloc((cap + 12) * sizeof *h);
  if (!p || !h) {
    free(p);
    free(h);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  size_t n = opaque_points(im, 1, p);
  size_t nh = n >= 3 ? bbc__convex_hull_2d(p, n, h) : 0;
  if (nh >= 3 && (int)nh > most) {
    pt lo = h[0], hi = h[0]; /* the hull's box, should no edge be removable */
    for (size_t c = 1; c < nh; c++) {
      lo.x = fmin(lo.x, h[c].x);
      lo.y = fmin(lo.y, h[c].y);
      hi.x = fmax(hi.x, h[c].x);
      hi.y = fmax(hi.y, h[c].y);
    }
    nh = reduce(h, nh, most);
    if (!nh) {
      h[0] = lo;
      h[1] = (pt){hi.x, lo.y};
      h[2] = hi;
      h[3] = (pt){lo.x, hi.y};
      nh = 4;
    }
  }
  if (nh < 3) { /* no opaque texel: the outline itself, cut */
    cut_corners(cb, most);
  } else if ((int)nh <= most) {
    pt old[10];
    outline_points(cb, old);
    if (bbc__polygon_area_2d(h, nh) < bbc__polygon_area_2d(old, (size_t)cb->corner_count) - 1e-12 ||
        cb->corner_count > most)
      set_outline(cb, h, nh);
  }
  free(p);
  free(h);
  return BBC_OK;
}

bbc_result bbc__tight_outlines(bbc_cloud *cl, const bbc__baked *bk, int most, int max_tris,
                               size_t other_tris, int sides) {
  size_t nk = cl->billboard_count;
  int tight = most >= 3;
  if (!tight) most = 10;
  if (most > 10) most = 10;
  if (max_tris > 0 && nk && sides > 0) {
    /* the corners the budget leaves each billboard: corners - 2 triangles a side */
    size_t left = (size_t)max_tris > other_tris ? (size_t)max_tris - other_tris : 0;
    size_t each = left / ((size_t)sides * nk) + 2;
    if (each < (size_t)most) most = each < 4 ? 4 : (int)each; /* quads at least */
  }
  for (size_t k = 0; k < nk; k++) {
    if (!tight) {
      cut_corners(&cl->billboards[k], most);
      continue;
    }
    bbc_result r = tighten(&cl->billboards[k], &bk[k], most);
    if (r != BBC_OK) return r;
  }
  return BBC_OK;
}
