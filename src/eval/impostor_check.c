/* impostor_check.c — how well an impostor's frames show their model
 * (issue 49): along each frame's own direction the impostor draws that
 * frame alone, a render of its model; judged on the frame's own texels
 * against the model drawn 4 x finer, so that the measure is the frame's
 * resolution and not a resampling of it. */
#include "raster.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Block IoU of two square pictures of the same square (b's side m times
 * a's): per block of bs x bs pixels of a (m bs x m bs of b) from pixel
 * `off` across and down, as many as fit, the covered fractions (alpha >=
 * 128), sum min / sum max; 1 where neither covers anything. */
static double block_iou(const bbc_image *a, const bbc_image *b, int bs, int off) {
  int m = b->width / a->width;
  double smin = 0, smax = 0;
  for (int by = off; by + bs <= a->width; by += bs)
    for (int bx = off; bx + bs <= a->width; bx += bs) {
      double f[2];
      const bbc_image *im[2] = {a, b};
      for (int k = 0; k < 2; k++) {
        int z = k ? m : 1, w = im[k]->width;
        long n = 0;
        for (int y = by * z; y < (by + bs) * z; y++)
          for (int x = bx * z; x < (bx + bs) * z; x++)
            n += im[k]->rgba[4 * ((size_t)y * w + x) + 3] >= 128;
        f[k] = (double)n / ((double)bs * bs * z * z);
      }
      smin += fmin(f[0], f[1]);
      smax += fmax(f[0], f[1]);
    }
  return smax > 0 ? smin / smax : 1;
}

bbc_result bbc_impostor_check(const bbc_mesh *mesh, const bbc_impostor *imp, double *per_frame,
                              double *worst, double *mean, bbc_error *err) {
  assert(mesh && imp && worst && mean);
  *worst = *mean = 0;
  int s = imp->frame_size, n = imp->frames;
  if (n < 2 || s < 8 || !imp->albedo.rgba)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "impostor check: needs frames of 8 texels or more");
  bbc_image a = {0}, b = {0};
  if (bbc_image_alloc(&a, s, s) != BBC_OK || bbc_image_alloc(&b, 4 * s, 4 * s) != BBC_OK) {
    bbc_image_free(&a);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "impostor check: out of memory");
  }
  bbc_result r = BBC_OK;
  double lo = 1, sum = 0;
  for (int j = 0; j < n && r == BBC_OK; j++)
    for (int i = 0; i < n && r == BBC_OK; i++) {
      bbc_view v;
      bbc_impostor_frame_view(imp, i, j, &v);
      /* points splatted as the frames splat them: 3.5 pixels of a 256-pixel
       * picture of the model, round */
      v.point_size_px = (float)(3.5 * (2 * imp->radius / 256.0) * (4 * s / (2 * imp->half_extent)));
      v.point_round = 1;
      r = bbc_impostor_render(imp, &v, &a, err);
      if (r == BBC_OK) r = bbc_render_ortho(mesh, &v, &b, err);
      if (r != BBC_OK) break;
      /* the mean over the block grid's 8 phases (moved by 0..7 texels
       * across and down), so that no grid of the frame's own is favoured */
      double q = 0;
      for (int off = 0; off < 8; off++) q += block_iou(&a, &b, 8, off) / 8;
      if (per_frame) per_frame[(size_t)j * n + i] = q;
      lo = fmin(lo, q);
      sum += q;
    }
  bbc_image_free(&a);
  bbc_image_free(&b);
  if (r != BBC_OK) return r;
  *worst = lo;
  *mean = sum / ((double)n * n);
  return BBC_OK;
}
