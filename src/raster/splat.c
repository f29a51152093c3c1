/* splat.c — a point cloud's points drawn as splats into a billboard's
 * images (thesis 2.4, step 3): round or square, front and back (the
 * nearest and the farthest point a texel), tile by tile. */
#include "raster.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A point's splat: its projection s, colour, and pixel rectangle. */
typedef struct splat {
  double s[3];
  uint8_t px4[4];
  int x0, x1, y0, y1;
} splat;

/* 0 when point v lies outside the view's depth range. */
static int splat_of(const bbc_mesh *m, size_t v, const bbc__camera *cam, const bbc_view *view,
                    double half, splat *sp) {
  bbc__camera_project(cam, m->positions + 3 * v, sp->s);
  if (sp->s[2] < view->depth_min || sp->s[2] > view->depth_max) return 0;
  const uint8_t grey[4] = {200, 200, 200, 255}; /* no colour in the scan: light grey */
  memcpy(sp->px4, grey, 4);
  if (m->colors) memcpy(sp->px4, m->colors + 4 * v, 3);
  sp->x0 = (int)floor(sp->s[0] - half + 0.5), sp->x1 = (int)floor(sp->s[0] + half - 0.5);
  sp->y0 = (int)floor(sp->s[1] - half + 0.5), sp->y1 = (int)floor(sp->s[1] + half - 0.5);
  if (sp->x1 < sp->x0) sp->x1 = sp->x0;
  if (sp->y1 < sp->y0) sp->y1 = sp->y0;
  return 1;
}

/* A splat's pixels within [cx0, cx1] x [cy0, cy1] (and the image). */
static void draw_splat(const splat *sp, double r2, int smooth, int cx0, int cy0, int cx1, int cy1,
                       bbc__bake *bake, float *depth, size_t n) {
  const double *s = sp->s;
  int ya = sp->y0 < cy0 ? cy0 : sp->y0, yb = sp->y1 > cy1 ? cy1 : sp->y1;
  int xa = sp->x0 < cx0 ? cx0 : sp->x0, xb = sp->x1 > cx1 ? cx1 : sp->x1;
  int ux = (int)floor(s[0]), uy = (int)floor(s[1]);
  float z = (float)s[2];
  for (int y = ya; y <= yb; y++)
    for (int x = xa; x <= xb; x++) {
      /* round splats: pixel centres within the disc, and always the pixel
       * under the point (a small splat between pixel centres keeps one) */
      double dx = x + 0.5 - s[0], dy = y + 0.5 - s[1];
      int under = x == ux && y == uy;
      if (smooth && !under && dx * dx + dy * dy > r2) continue;
      size_t pi = (size_t)y * bake->width + x;
      if (z < depth[pi]) { /* front: the point nearest the viewer */
        depth[pi] = z;
        memcpy(bake->front + 4 * pi, sp->px4, 4);
      }
      if (bake->back && z > depth[n + pi]) { /* back: the farthest */
        depth[n + pi] = z;
        memcpy(bake->back + 4 * pi, sp->px4, 4);
      }
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
  float *depth = malloc(2 * n * sizeof *depth);
  if (!depth) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
  for (size_t i = 0; i < n; i++) {
    depth[i] = FLT_MAX;
    depth[n + i] = -FLT_MAX;
  }
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
  if (!start) {
    free(depth);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
  }
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
        free(depth);
        return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "splats: out of memory");
      }
      memcpy(fill, start, nt * sizeof *fill);
    }
    for (size_t i = 0; i < count; i++) {
      splat sp;
      if (!splat_of(m, points ? points[i] : i, &cam, view, half, &sp)) continue;
      int a0 = sp.x0 < 0 ? 0 : sp.x0 / TILE, a1 = sp.x1 / TILE;
      int b0 = sp.y0 < 0 ? 0 : sp.y0 / TILE, b1 = sp.y1 / TILE;
      if (sp.x1 < 0 || sp.y1 < 0 || a0 >= tx || b0 >= ty) continue;
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
        size_t v = points ? points[list[k]] : list[k];
        splat sp;
        splat_of(m, v, &cam, view, half, &sp);
        draw_splat(&sp, half * half, smooth, cx0, cy0, cx1, cy1, bake, depth, n);
      }
    }
    free(list);
  }
  free(start);
  free(depth);
  return BBC_OK;
}
