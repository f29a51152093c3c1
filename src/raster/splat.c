/* splat.c — a point cloud's points drawn as splats into a billboard's
 * images (thesis 2.4, step 3): round or square, front and back (the
 * nearest and the farthest point a texel), tile by tile. */
#include "raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A point's splat: its projection (image x, y; depth as drawn), colour. */
typedef struct splat {
  double x, y;
  float z; /* NAN: outside the view's depth range */
  uint8_t px4[4];
} splat;

static void splat_of(const bbc_mesh *m, size_t v, const bbc__camera *cam, const bbc_view *view,
                     splat *sp) {
  double s[3];
  bbc__camera_project(cam, m->positions + 3 * v, s);
  sp->x = s[0];
  sp->y = s[1];
  int slab = view->depth_max > view->depth_min; /* else every depth (bbc_view) */
  sp->z = slab && (s[2] < view->depth_min || s[2] > view->depth_max) ? NAN : (float)s[2];
  const uint8_t grey[4] = {200, 200, 200, 255}; /* no colour in the scan: light grey */
  memcpy(sp->px4, grey, 4);
  if (m->colors) memcpy(sp->px4, m->colors + 4 * v, 3);
}

/* Its pixel rectangle [r0, r1] x [r2, r3], for a splat `half` pixels across
 * half its width. */
static void splat_rect(const splat *sp, double half, int r[4]) {
  r[0] = (int)floor(sp->x - half + 0.5), r[1] = (int)floor(sp->x + half - 0.5);
  r[2] = (int)floor(sp->y - half + 0.5), r[3] = (int)floor(sp->y + half - 0.5);
  if (r[1] < r[0]) r[1] = r[0];
  if (r[3] < r[2]) r[3] = r[2];
}

/* 1 when pixel column x's centre lies in a round splat's disc, on a row
 * dy2 (its offset squared) from the splat's centre: the arithmetic of a
 * test of each pixel, dx * dx + dy * dy against r2. */
static int in_disc(int x, double sx, double dy2, double r2) {
  double dx = x + 0.5 - sx;
  return !(dx * dx + dy2 > r2);
}

/* One row's pixels [xa, xb] of a splat at depth z: the front keeps the
 * nearest, the back (when there is one) the farthest; the first of equals
 * stays. Written without branches so that it vectorises. */
static BBC__CLONES void splat_row(float *restrict df, uint8_t *restrict cf, float *restrict db,
                                  uint8_t *restrict cb, int xa, int xb, float z,
                                  const uint8_t px4[4]) {
  for (int x = xa; x <= xb; x++) {
    int near = z < df[x];
    df[x] = near ? z : df[x];
    for (int k = 0; k < 4; k++) cf[4 * x + k] = near ? px4[k] : cf[4 * x + k];
  }
  if (!db) return;
  for (int x = xa; x <= xb; x++) {
    int far = z > db[x];
    db[x] = far ? z : db[x];
    for (int k = 0; k < 4; k++) cb[4 * x + k] = far ? px4[k] : cb[4 * x + k];
  }
}

enum { SMALL_SPLAT = 8 }; /* columns under which a row's run is not worth finding */

/* A splat's pixels within [cx0, cx1] x [cy0, cy1] (and the image). A round
 * splat covers the pixels whose centre lies within its disc, and always the
 * pixel under the point (a small splat between pixel centres keeps one);
 * on each row those centres are one run of columns around the splat's
 * (the test's rounding keeps it monotonic on each side of the centre),
 * found from the circle's chord and then settled by the test itself at
 * its two ends: the pixels a test of each one would give. */
static void draw_splat(const splat *sp, double half, int smooth, int cx0, int cy0, int cx1, int cy1,
                       bbc__bake *bake, float *depth, size_t n) {
  int rc[4];
  splat_rect(sp, half, rc);
  double r2 = half * half;
  int ya = rc[2] < cy0 ? cy0 : rc[2], yb = rc[3] > cy1 ? cy1 : rc[3];
  int xa = rc[0] < cx0 ? cx0 : rc[0], xb = rc[1] > cx1 ? cx1 : rc[1];
  if (xa > xb) return;
  int ux = (int)floor(sp->x), uy = (int)floor(sp->y);
  float z = sp->z;
  size_t w = (size_t)bake->width;
  if (xb - xa < SMALL_SPLAT) { /* a few pixels a row: each tested */
    for (int y = ya; y <= yb; y++) {
      double dy = y + 0.5 - sp->y, dy2 = dy * dy;
      for (int x = xa; x <= xb; x++) {
        if (smooth && !(x == ux && y == uy) && !in_disc(x, sp->x, dy2, r2)) continue;
        size_t pi = (size_t)y * w + x;
        if (z < depth[pi]) {
          depth[pi] = z;
          memcpy(bake->front + 4 * pi, sp->px4, 4);
        }
        if (bake->back && z > depth[n + pi]) {
          depth[n + pi] = z;
          memcpy(bake->back + 4 * pi, sp->px4, 4);
        }
      }
    }
    return;
  }
  for (int y = ya; y <= yb; y++) {
    size_t row = (size_t)y * w;
    float *df = depth + row, *db = bake->back ? depth + n + row : NULL;
    uint8_t *cf = bake->front + 4 * row, *cb = bake->back ? bake->back + 4 * row : NULL;
    int s = xa, e = xb;
    if (smooth) {
      /* The centres nearest the splat's lie in column ux: when its clamped
       * column is out of the disc, the row's others are too. */
      double dy = y + 0.5 - sp->y, dy2 = dy * dy;
      int c = ux < xa ? xa : ux > xb ? xb : ux;
      if (!in_disc(c, sp->x, dy2, r2)) {
        s = xb + 1;
      } else {
        /* the chord's ends, then each settled by the test, c between */
        double hw = sqrt(r2 > dy2 ? r2 - dy2 : 0);
        double gs = ceil(sp->x - hw - 0.5), ge = floor(sp->x + hw - 0.5);
        s = gs < xa ? xa : gs > c ? c : (int)gs;
        e = ge > xb ? xb : ge < c ? c : (int)ge;
        if (in_disc(s, sp->x, dy2, r2))
          while (s > xa && in_disc(s - 1, sp->x, dy2, r2)) s--;
        else
          while (!in_disc(s, sp->x, dy2, r2)) s++;
        if (in_disc(e, sp->x, dy2, r2))
          while (e < xb && in_disc(e + 1, sp->x, dy2, r2)) e++;
        else
          while (!in_disc(e, sp->x, dy2, r2)) e--;
      }
    }
    if (s <= e) splat_row(df, cf, db, cb, s, e, z, sp->px4);
    if (smooth && y == uy && ux >= xa && ux <= xb && !(ux >= s && ux <= e))
      splat_row(df, cf, db, cb, ux, ux, z, sp->px4); /* the pixel under the point */
  }
}

bbc_result bbc__render_splats(const bbc_mesh *m, const uint32_t *points, size_t count,
                              const bbc_view *view, bbc__bake *bake, double size_px, int smooth,
                              bbc_error *err) {
  if (m->kind != BBC_MESH_POINTS || !bake->front)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "splats: needs points and a front image");
  bbc__camera cam;
  bbc_result r = bbc__check_view(view, bake->width, bake->height, &cam, err);
  if (r != BBC_OK) return r;
  size_t n = (size_t)bake->width * bake->height;
  float *depth = bbc__depth_front_back(n);
  if (!depth) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
  double half = 0.5 * (size_px >= 1 ? size_px : 1);
  /* Tiles of 64 x 64 pixels, each drawn with the points whose splat
   * reaches it, in the points' order: every pixel sees the same points in
   * the same order as a pass over all points would (the same image, ties
   * included), while the depth and colour being written stay in cache (a
   * 2048-pixel texture of ss 4 is 64 MB; points in file order hit it at
   * random). */
  enum { TILE = 64 };
  int tx = (bake->width + TILE - 1) / TILE, ty = (bake->height + TILE - 1) / TILE;
  size_t nt = (size_t)tx * ty;
  size_t *start = calloc(nt + 1, sizeof *start);
  splat *sp = malloc((count ? count : 1) * sizeof *sp); /* each point projected once */
  if (!start || !sp) {
    free(start);
    free(sp);
    free(depth);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
  }
  for (size_t i = 0; i < count; i++) splat_of(m, points ? points[i] : i, &cam, view, &sp[i]);
  for (int pass = 0; pass < 2; pass++) {
    uint32_t *list = NULL;
    size_t *fill = NULL;
    if (pass == 1) {
      for (size_t t = 0; t < nt; t++) start[t + 1] += start[t];
      list = malloc((start[nt] ? start[nt] : 1) * sizeof *list);
      fill = malloc(nt * sizeof *fill);
      if (!list || !fill) {
        free(list);
        free(fill);
        free(start);
        free(sp);
        free(depth);
        return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
      }
      memcpy(fill, start, nt * sizeof *fill);
    }
    for (size_t i = 0; i < count; i++) {
      if (isnan(sp[i].z)) continue;
      int rc[4];
      splat_rect(&sp[i], half, rc);
      int a0 = rc[0] < 0 ? 0 : rc[0] / TILE, a1 = rc[1] / TILE;
      int b0 = rc[2] < 0 ? 0 : rc[2] / TILE, b1 = rc[3] / TILE;
      if (rc[1] < 0 || rc[3] < 0 || a0 >= tx || b0 >= ty) continue;
      if (a1 >= tx) a1 = tx - 1;
      if (b1 >= ty) b1 = ty - 1;
      for (int b = b0; b <= b1; b++)
        for (int a = a0; a <= a1; a++) {
          size_t t = (size_t)b * tx + a;
          if (pass == 0)
            start[t + 1]++;
          else
            list[fill[t]++] = (uint32_t)i;
        }
    }
    if (pass == 0) continue;
    free(fill);
    for (size_t t = 0; t < nt; t++) {
      int cx0 = (int)(t % (size_t)tx) * TILE, cy0 = (int)(t / (size_t)tx) * TILE;
      int cx1 = cx0 + TILE - 1, cy1 = cy0 + TILE - 1;
      if (cx1 >= bake->width) cx1 = bake->width - 1;
      if (cy1 >= bake->height) cy1 = bake->height - 1;
      for (size_t k = start[t]; k < start[t + 1]; k++) {
#if defined(__GNUC__)
        /* a tile's points lie anywhere among millions: fetched ahead */
        if (k + 16 < start[t + 1]) __builtin_prefetch(&sp[list[k + 16]]);
#endif
        draw_splat(&sp[list[k]], half, smooth, cx0, cy0, cx1, cy1, bake, depth, n);
      }
    }
    free(list);
  }
  if (bake->front_depth) memcpy(bake->front_depth, depth, n * sizeof *depth);
  free(sp);
  free(start);
  free(depth);
  return BBC_OK;
}
