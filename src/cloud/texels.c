/* texels.c — a supersampled image down to its texels (quality 2, thesis
 * 2.3.9): which texels end opaque by their samples' coverage, their mean
 * colours or normals, and the colours transparent texels carry for a GPU's
 * filtering. Billboards' bakes and impostors' frames share them. */
#include "cloud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The covered fraction of texel (x, y) of a k x k supersampled image (its
 * samples' alphas; with taps, bbc__bake.taps, those drawn at their centres:
 * a sample drawn by a face passing its alpha test at a tap only makes the
 * texel a candidate) and whether any sample covers it (*n > 0). */
static float texel_share(const bbc_image *img, const uint8_t *taps, int k, int x, int y,
                         unsigned *n) {
  unsigned shares = 0;
  *n = 0;
  for (int j = 0; j < k; j++)
    for (int q = 0; q < k; q++) {
      size_t si = (size_t)(y * k + j) * img->width + (x * k + q);
      unsigned a = img->rgba[4 * si + 3];
      *n += a > 0;
      shares += !taps || taps[si] ? a : 0;
    }
  return (float)shares / (float)(255 * k * k);
}

/* quality 2: which texels of a k x k supersampled image end opaque
 * (mask[texel] = 1). Growing (thesis 2.3.9, `dither 0`): at least
 * `min_opaque` of its k^2 samples are. Dithering (`dither 1`):
 * coverage-preserving error diffusion of each texel's covered fraction
 * (bbc__coverage_diffuse), so that over any small area the fraction of
 * opaque texels is the fraction the original covers, and a texel none of
 * whose samples is covered never turns opaque (its share of the error
 * moves on to covered neighbours). */
bbc_result bbc__alpha_mask(const bbc_image *img, const uint8_t *taps, int k, int dither,
                           unsigned min_opaque, uint8_t *mask, uint8_t *cand) {
  int w = img->width / k, h = img->height / k;
  float *frac = dither ? malloc((size_t)w * h * sizeof *frac) : NULL;
  if (dither && !frac) return BBC_ERROR_OUT_OF_MEMORY;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      unsigned n;
      size_t at = (size_t)y * w + x;
      float share = texel_share(img, taps, k, x, y, &n);
      cand[at] = n > 0;
      if (dither)
        frac[at] = share;
      else
        mask[at] = n > 0 && n >= min_opaque;
    }
  int r = dither ? bbc__coverage_diffuse(frac, cand, w, h, mask) : 0;
  free(frac);
  return r < 0 ? BBC_ERROR_OUT_OF_MEMORY : BBC_OK;
}

/* Downsamples a k x k supersampled image to its texels: a texel with
 * covered samples gets their mean (normals renormalised; is_normal 2: the
 * mean normal kept, shorter where the samples' normals differ), opaque when
 * `mask` says so, else with alpha 0 (the colour kept for refinement;
 * bbc__clear_masked removes it). */
bbc_result bbc__downsample_masked(bbc_image *img, int k, int is_normal, const uint8_t *mask) {
  bbc_image dst;
  bbc_result r = bbc_image_alloc(&dst, img->width / k, img->height / k);
  if (r != BBC_OK) return r;
  for (int y = 0; y < dst.height; y++)
    for (int x = 0; x < dst.width; x++) {
      unsigned sum[3] = {0, 0, 0}, n = 0;
      for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
          const uint8_t *s = img->rgba + 4 * ((size_t)(y * k + j) * img->width + (x * k + i));
          if (!s[3]) continue;
          for (int c = 0; c < 3; c++) sum[c] += s[c];
          n++;
        }
      uint8_t *d = dst.rgba + 4 * ((size_t)y * dst.width + x);
      if (!n) continue;
      if (is_normal) {
        double v[3], len = 0;
        for (int c = 0; c < 3; c++) {
          v[c] = (double)sum[c] / n / 127.5 - 1.0;
          len += v[c] * v[c];
        }
        len = sqrt(len);
        for (int c = 0; c < 3; c++) {
          double u = is_normal == 2 ? (len > 1 ? len : 1) : len;
          double e = len > 1e-9 ? 127.5 * (v[c] / u + 1.0) : (c == 2 ? 255 : 127.5);
          d[c] = (uint8_t)(e > 255 ? 255 : e < 0 ? 0 : e + 0.5 > 255 ? 255 : e + 0.5);
        }
      } else {
        for (int c = 0; c < 3; c++) d[c] = (uint8_t)((sum[c] + n / 2) / n);
      }
      d[3] = mask[(size_t)y * dst.width + x] ? 255 : 0;
    }
  bbc_image_free(img);
  *img = dst;
  return BBC_OK;
}

/* Texels that are not opaque in `mask` become (0, 0, 0, 0); opaque ones
 * alpha 255. */
void bbc__clear_masked(bbc_image *img, const uint8_t *mask) {
  if (!img->rgba) return;
  size_t n = (size_t)img->width * img->height;
  for (size_t i = 0; i < n; i++)
    if (mask[i])
      img->rgba[4 * i + 3] = 255;
    else
      memset(img->rgba + 4 * i, 0, 4);
}

/* The colour of every transparent texel (alpha 0) becomes that of its
 * nearest opaque ones (breadth first, the mean of the neighbours filled
 * before it), alpha kept: a GPU's filtering and mipmaps then mix no black
 * (or, in a normal map, no bogus normal) into the edges of leaves. */
bbc_result bbc__fill_transparent(bbc_image *img) {
  int w = img->width, h = img->height;
  size_t n = (size_t)w * h;
  if (!img->rgba || !n) return BBC_OK;
  uint8_t *done = malloc(n);
  uint32_t *queue = malloc(n * sizeof *queue);
  if (!done || !queue) {
    free(done);
    free(queue);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  size_t head = 0, tail = 0;
  for (size_t i = 0; i < n; i++) done[i] = img->rgba[4 * i + 3] != 0;
  static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (size_t i = 0; i < n; i++) {
    if (done[i]) continue;
    int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
    for (int k = 0; k < 4; k++) {
      int X = x + dx[k], Y = y + dy[k];
      if (X >= 0 && Y >= 0 && X < w && Y < h && done[(size_t)Y * w + X]) {
        queue[tail++] = (uint32_t)i;
        done[i] = 2; /* queued */
        break;
      }
    }
  }
  while (head < tail) {
    size_t i = queue[head++];
    int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
    unsigned sum[3] = {0, 0, 0}, cnt = 0;
    for (int k = 0; k < 4; k++) {
      int X = x + dx[k], Y = y + dy[k];
      if (X < 0 || Y < 0 || X >= w || Y >= h) continue;
      size_t j = (size_t)Y * w + X;
      if (done[j] == 1) {
        for (int c = 0; c < 3; c++) sum[c] += img->rgba[4 * j + c];
        cnt++;
      } else if (!done[j]) {
        done[j] = 2;
        queue[tail++] = (uint32_t)j;
      }
    }
    for (int c = 0; c < 3 && cnt; c++) img->rgba[4 * i + c] = (uint8_t)((sum[c] + cnt / 2) / cnt);
    done[i] = 1;
  }
  free(done);
  free(queue);
  return BBC_OK;
}

/* Marks the texels of a w x h image whose centre lies in triangle (a, b,
 * c) (texel units, x right, y down; wrapped into the image), and those the
 * corners lie in. */
static void mark_triangle(const double *a, const double *b, const double *c, int w, int h,
                          uint8_t *used) {
  double x0 = fmin(a[0], fmin(b[0], c[0])), x1 = fmax(a[0], fmax(b[0], c[0]));
  double y0 = fmin(a[1], fmin(b[1], c[1])), y1 = fmax(a[1], fmax(b[1], c[1]));
  const double *p[3] = {a, b, c};
  for (int k = 0; k < 3; k++) {
    long X = (long)floor(p[k][0]) % w, Y = (long)floor(p[k][1]) % h;
    used[(size_t)(Y < 0 ? Y + h : Y) * w + (size_t)(X < 0 ? X + w : X)] = 1;
  }
  double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (area == 0) return;
  for (long y = (long)ceil(y0 - 0.5); y + 0.5 <= y1; y++)
    for (long x = (long)ceil(x0 - 0.5); x + 0.5 <= x1; x++) {
      double px = x + 0.5, py = y + 0.5;
      double e0 = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
      double e1 = (c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]);
      double e2 = (a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]);
      if (area < 0) e0 = -e0, e1 = -e1, e2 = -e2;
      if (e0 < 0 || e1 < 0 || e2 < 0) continue;
      long X = x % w, Y = y % h;
      used[(size_t)(Y < 0 ? Y + h : Y) * w + (size_t)(X < 0 ? X + w : X)] = 1;
    }
}

/* The mip levels that keep the used texels' islands (4-connected, of at
 * least 2 % of them) apart: halvings until a texel is a quarter of the
 * smallest side of their boxes; -1 out of memory. */
static int islands_apart(const uint8_t *used, int w, int h) {
  size_t n = (size_t)w * h, total = 0;
  for (size_t i = 0; i < n; i++) total += used[i] != 0;
  uint8_t *seen = calloc(n, 1);
  uint32_t *stack = malloc(n * sizeof *stack);
  if (!seen || !stack) {
    free(seen);
    free(stack);
    return -1;
  }
  int side = w > h ? w : h;
  for (size_t i = 0; i < n; i++) {
    if (!used[i] || seen[i]) continue;
    size_t top = 0, area = 0;
    int x0 = w, x1 = -1, y0 = h, y1 = -1;
    stack[top++] = (uint32_t)i;
    seen[i] = 1;
    while (top) {
      size_t j = stack[--top];
      int x = (int)(j % (size_t)w), y = (int)(j / (size_t)w);
      area++;
      x0 = x < x0 ? x : x0;
      x1 = x > x1 ? x : x1;
      y0 = y < y0 ? y : y0;
      y1 = y > y1 ? y : y1;
      static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; k++) {
        int X = x + dx[k], Y = y + dy[k];
        if (X < 0 || Y < 0 || X >= w || Y >= h) continue;
        size_t q = (size_t)Y * w + X;
        if (used[q] && !seen[q]) {
          seen[q] = 1;
          stack[top++] = (uint32_t)q;
        }
      }
    }
    int s = x1 - x0 + 1 < y1 - y0 + 1 ? x1 - x0 + 1 : y1 - y0 + 1;
    if (50 * area >= total && s < side) side = s;
  }
  free(seen);
  free(stack);
  int levels = 0;
  while ((4 << (levels + 1)) <= side) levels++;
  return levels;
}

bbc_result bbc_mesh_texture_padded(const bbc_mesh *m, int texture, bbc_image *out, int *levels,
                                   uint8_t **used_out, bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (used_out) *used_out = NULL;
  if (!m || texture < 0 || (size_t)texture >= m->texture_count || !m->textures[texture].image.rgba)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "texture %d: no such image", texture);
  const bbc_image *src = &m->textures[texture].image;
  int w = src->width, h = src->height;
  size_t n = (size_t)w * h;
  if (bbc_image_alloc(out, w, h) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "padded texture: out of memory");
  memcpy(out->rgba, src->rgba, 4 * n);
  if (levels) /* every level */
    for (*levels = 0; (1 << *levels) < (w > h ? w : h);) ++*levels;
  if (!m->uvs || m->kind == BBC_MESH_POINTS) return BBC_OK;
  uint8_t *used = calloc(n, 1), *alpha = malloc(n);
  if (!used || !alpha) {
    free(used);
    free(alpha);
    bbc_image_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "padded texture: out of memory");
  }
  int any = 0, all = 0;
  for (size_t t = 0; t < m->triangle_count && !all; t++) {
    const bbc_material *ma = &m->materials[m->face_material ? m->face_material[t] : 0];
    if (ma->texture != texture && ma->normal_map != texture + 1 && ma->occlusion_map != texture + 1)
      continue;
    double q[3][2];
    for (int k = 0; k < 3; k++) {
      const float *uv = m->uvs + 2 * (size_t)m->indices[3 * t + k];
      q[k][0] = uv[0] * w;
      q[k][1] = (1.0 - uv[1]) * h; /* v up, rows from the top */
    }
    double x0 = fmin(q[0][0], fmin(q[1][0], q[2][0])), y0 = fmin(q[0][1], fmin(q[1][1], q[2][1]));
    double x1 = fmax(q[0][0], fmax(q[1][0], q[2][0])), y1 = fmax(q[0][1], fmax(q[1][1], q[2][1]));
    if (!(x1 - x0 >= 0 && y1 - y0 >= 0)) { /* no number: all of it */
      all = 1;
      break;
    }
    if ((x1 - x0) * (y1 - y0) > 16.0 * w * h) { /* repeating many times: all of it */
      all = 1;
      break;
    }
    double sx = floor(x0 / w) * w, sy = floor(y0 / h) * h;
    for (int k = 0; k < 3; k++) {
      q[k][0] -= sx;
      q[k][1] -= sy;
    }
    mark_triangle(q[0], q[1], q[2], w, h, used);
    any = 1;
  }
  bbc_result r = BBC_OK;
  if (any && !all && levels) {
    int k = islands_apart(used, w, h);
    if (k < 0) r = BBC_ERROR_OUT_OF_MEMORY;
    if (k >= 0 && k < *levels) *levels = k;
  }
  if (r == BBC_OK && any && !all) {
    /* one texel more around what is used: a bilinear fetch's neighbours */
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        if (used[(size_t)y * w + x] != 1) continue;
        for (int dy = -1; dy <= 1; dy++)
          for (int dx = -1; dx <= 1; dx++) {
            int X = x + dx, Y = y + dy;
            if (X >= 0 && Y >= 0 && X < w && Y < h && !used[(size_t)Y * w + X])
              used[(size_t)Y * w + X] = 2;
          }
      }
    for (size_t i = 0; i < n; i++) {
      alpha[i] = out->rgba[4 * i + 3];
      out->rgba[4 * i + 3] = used[i] ? 255 : 0;
    }
    if (bbc__fill_transparent(out) != BBC_OK) r = BBC_ERROR_OUT_OF_MEMORY;
    for (size_t i = 0; i < n; i++) out->rgba[4 * i + 3] = alpha[i];
  }
  if (r == BBC_OK && any && !all && used_out) { /* the reached texels, not the ring */
    for (size_t i = 0; i < n; i++) used[i] = used[i] == 1;
    *used_out = used;
    used = NULL;
  }
  free(used);
  free(alpha);
  if (r != BBC_OK) {
    bbc_image_free(out);
    return bbc__fail(err, r, "padded texture: out of memory");
  }
  return BBC_OK;
}
