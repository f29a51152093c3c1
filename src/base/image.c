/* image.c — RGBA8 images in memory: allocation, the transparency test and
 * the alpha-tested mip chain that keeps the coverage of every level and of
 * every block of it. Decoding and writing files are io/image_io.c's. */
#include "base.h"

#include <assert.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

bbc_result bbc_image_alloc(bbc_image *image, int width, int height) {
  assert(image);
  memset(image, 0, sizeof *image);
  if (width <= 0 || height <= 0 || (size_t)width > (SIZE_MAX / 4) / (size_t)height)
    return BBC_ERROR_INVALID_ARGUMENT;
  image->rgba = calloc((size_t)width * (size_t)height, 4);
  if (!image->rgba) return BBC_ERROR_OUT_OF_MEMORY;
  image->width = width;
  image->height = height;
  return BBC_OK;
}

void bbc_image_free(bbc_image *image) {
  if (!image) return;
  free(image->rgba);
  memset(image, 0, sizeof *image);
}

int bbc_image_has_transparency(const bbc_image *image) {
  assert(image);
  if (!image || !image->rgba) return 0;
  size_t n = (size_t)image->width * (size_t)image->height;
  for (size_t i = 0; i < n; i++)
    if (image->rgba[4 * i + 3] != 255) return 1;
  return 0;
}

/* One level of the continuous chain: premultiplied colour and coverage
 * (0..1) per texel, averaged over 2 x 2 of the level above (clamped at
 * odd edges); plain colour sums for texels no sample covers. */
typedef struct mip_level {
  int w, h;
  float *cov;   /* w * h */
  float *pre;   /* 3 per texel: colour times coverage */
  float *plain; /* 3 per texel: colour regardless of coverage */
} mip_level;

static void mip_level_free(mip_level *m) {
  free(m->cov);
  free(m->pre);
  free(m->plain);
}

static int mip_level_alloc(mip_level *m, int w, int h) {
  size_t n = (size_t)w * h;
  m->w = w;
  m->h = h;
  m->cov = malloc(n * sizeof *m->cov);
  m->pre = malloc(n * 3 * sizeof *m->pre);
  m->plain = malloc(n * 3 * sizeof *m->plain);
  return m->cov && m->pre && m->plain;
}

/* The blocks whose texels an alpha-tested mip level picks by coverage. */
enum { MIP_BLOCK = 4 };

static void coverage_split(const float *frac, int stride, uint8_t *mask, int x0, int y0, int w,
                           int h, long t, int leaf);

/* bbc_image_mipmaps and, with `mask`, bbc_image_mipmaps_masked. */
static bbc_result mip_chain(const bbc_image *base, const uint8_t *mask_in, bbc_image **levels,
                            int *count, bbc_error *err) {
  assert(base && levels && count);
  *levels = NULL;
  *count = 0;
  if (!base->rgba || base->width < 1 || base->height < 1)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "mipmaps of an empty image");
  int n = 0;
  for (int w = base->width, h = base->height; w > 1 || h > 1; n++) {
    w = w > 1 ? w / 2 : 1;
    h = h > 1 ? h / 2 : 1;
  }
  if (n == 0) return BBC_OK;
  bbc_image *out = calloc((size_t)n, sizeof *out);
  mip_level prev = {0}, cur = {0};
  uint8_t *mask = NULL; /* an alpha-tested level's opaque texels */
  if (!out || !mip_level_alloc(&prev, base->width, base->height)) goto oom;
  size_t n0 = (size_t)base->width * base->height;
  for (size_t i = 0; i < n0; i++) {
    const uint8_t *p = base->rgba + 4 * i;
    float a = mask_in ? (mask_in[i] != 0) : p[3] / 255.0f; /* what the texel weighs */
    prev.cov[i] = a;
    for (int k = 0; k < 3; k++) {
      prev.pre[3 * i + k] = p[k] * a;
      prev.plain[3 * i + k] = p[k];
    }
  }
  int alpha_tested = !mask_in && bbc_image_has_transparency(base);
  for (int l = 0; l < n; l++) {
    int w = prev.w > 1 ? prev.w / 2 : 1, h = prev.h > 1 ? prev.h / 2 : 1;
    if (!mip_level_alloc(&cur, w, h)) goto oom;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        float c = 0, pre[3] = {0}, plain[3] = {0};
        for (int dy = 0; dy < 2; dy++)
          for (int dx = 0; dx < 2; dx++) {
            int sx = 2 * x + dx < prev.w ? 2 * x + dx : prev.w - 1;
            int sy = 2 * y + dy < prev.h ? 2 * y + dy : prev.h - 1;
            size_t s = (size_t)sy * prev.w + sx;
            c += prev.cov[s];
            for (int k = 0; k < 3; k++) {
              pre[k] += prev.pre[3 * s + k];
              plain[k] += prev.plain[3 * s + k];
            }
          }
        size_t d = (size_t)y * w + x;
        cur.cov[d] = c / 4;
        for (int k = 0; k < 3; k++) {
          cur.pre[3 * d + k] = pre[k] / 4;
          cur.plain[3 * d + k] = plain[k] / 4;
        }
      }
    if (bbc_image_alloc(&out[l], w, h) != BBC_OK) goto oom;
    size_t nt = (size_t)w * h;
    /* Which texels are opaque: as many as the level's coverage sums to,
     * shared down a quadtree (as bbc__coverage_tree) to blocks of 4 x 4
     * texels, in each of them its most covered: every part of the level
     * keeps the coverage it has (a threshold over the whole level keeps
     * the total but fills dense parts and empties sparse ones: a palm's
     * thin fronds gone from its far levels), and a solid leaf stays solid
     * (a dither of its edge would thin under a bilinear alpha test). */
    if (alpha_tested) {
      if (!mask && !(mask = malloc(nt))) goto oom; /* level 1, the largest */
      double total = 0;
      for (size_t i = 0; i < nt; i++) total += cur.cov[i];
      coverage_split(cur.cov, w, mask, 0, 0, w, h, (long)floor(total + 0.5), MIP_BLOCK);
    }
    for (size_t i = 0; i < nt; i++) {
      uint8_t *p = out[l].rgba + 4 * i;
      int opaque = alpha_tested && mask[i];
      for (int k = 0; k < 3; k++) {
        float v = cur.cov[i] > 1e-6f ? cur.pre[3 * i + k] / cur.cov[i] : cur.plain[3 * i + k];
        p[k] = (uint8_t)(v > 255 ? 255 : v + 0.5f);
      }
      p[3] = alpha_tested ? (opaque ? 255 : 0) : mask_in ? 255 : (uint8_t)(cur.cov[i] * 255 + 0.5f);
    }
    mip_level_free(&prev);
    prev = cur;
    memset(&cur, 0, sizeof cur);
  }
  mip_level_free(&prev);
  free(mask);
  *levels = out;
  *count = n;
  return BBC_OK;
oom:
  free(mask);
  mip_level_free(&prev);
  mip_level_free(&cur);
  for (int l = 0; out && l < n; l++) bbc_image_free(&out[l]);
  free(out);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "mipmaps: out of memory");
}

bbc_result bbc_image_mipmaps(const bbc_image *base, bbc_image **levels, int *count,
                             bbc_error *err) {
  return mip_chain(base, NULL, levels, count, err);
}

bbc_result bbc_image_mipmaps_masked(const bbc_image *base, const uint8_t *mask, bbc_image **levels,
                                    int *count, bbc_error *err) {
  assert(mask);
  return mip_chain(base, mask, levels, count, err);
}

int bbc__coverage_diffuse(const float *frac, const uint8_t *cand, int w, int h, uint8_t *mask) {
  float *err = calloc(2 * ((size_t)w + 2), sizeof *err);
  if (!err) return -1;
  for (int y = 0; y < h; y++) {
    float *cur = err + (y % 2) * ((size_t)w + 2) + 1;
    float *nxt = err + ((y + 1) % 2) * ((size_t)w + 2) + 1;
    memset(nxt - 1, 0, ((size_t)w + 2) * sizeof *nxt);
    int dir = y % 2 ? -1 : 1;
    for (int i = 0; i < w; i++) {
      int x = dir > 0 ? i : w - 1 - i;
      size_t at = (size_t)y * w + x;
      float v = frac[at] + cur[x];
      uint8_t on = (cand ? cand[at] != 0 : frac[at] > 0) && v >= 0.5f;
      /* The error goes to the neighbours inside the grid, the weights
       * renormalised, so that none leaves over an edge. */
      float e = v - on;
      int right = x + dir >= 0 && x + dir < w, below = y + 1 < h;
      int left_below = below && x - dir >= 0 && x - dir < w;
      float wr = right ? 7.0f : 0, wlb = left_below ? 3.0f : 0, wb = below ? 5.0f : 0;
      float wrb = right && below ? 1.0f : 0, sum = wr + wlb + wb + wrb;
      if (sum > 0) {
        e /= sum;
        cur[x + dir] += e * wr;
        nxt[x - dir] += e * wlb;
        nxt[x] += e * wb;
        nxt[x + dir] += e * wrb;
      }
      mask[at] = on;
    }
  }
  free(err);
  return 0;
}
/* The quadtree's rectangle (x0, y0, w, h) given `t` opaque cells; a
 * rectangle of at most leaf x leaf cells turns its t most covered cells
 * opaque (leaf 1: split down to single cells). */
static void coverage_split(const float *frac, int stride, uint8_t *mask, int x0, int y0, int w,
                           int h, long t, int leaf) {
  if (w <= 0 || h <= 0) return;
  if (w == 1 && h == 1) {
    mask[(size_t)y0 * stride + x0] = t > 0 && frac[(size_t)y0 * stride + x0] > 0;
    return;
  }
  if (w <= leaf && h <= leaf) { /* the t most covered cells (ties: the first) */
    for (int y = y0; y < y0 + h; y++)
      for (int x = x0; x < x0 + w; x++) mask[(size_t)y * stride + x] = 0;
    for (long k = 0; k < t; k++) {
      size_t best = SIZE_MAX;
      for (int y = y0; y < y0 + h; y++)
        for (int x = x0; x < x0 + w; x++) {
          size_t at = (size_t)y * stride + x;
          if (!mask[at] && frac[at] > 0 && (best == SIZE_MAX || frac[at] > frac[best])) best = at;
        }
      if (best == SIZE_MAX) break;
      mask[best] = 1;
    }
    return;
  }
  int w1 = (w + 1) / 2, h1 = (h + 1) / 2;
  int xs[4] = {x0, x0 + w1, x0, x0 + w1}, ys[4] = {y0, y0, y0 + h1, y0 + h1};
  int ws[4] = {w1, w - w1, w1, w - w1}, hs[4] = {h1, h1, h - h1, h - h1};
  double sum[4] = {0, 0, 0, 0}, total = 0, rem[4];
  long cap[4] = {0, 0, 0, 0}, n[4], left = t;
  for (int q = 0; q < 4; q++) {
    for (int y = ys[q]; y < ys[q] + hs[q]; y++)
      for (int x = xs[q]; x < xs[q] + ws[q]; x++) {
        float f = frac[(size_t)y * stride + x];
        sum[q] += f;
        cap[q] += f > 0;
      }
    total += sum[q];
  }
  for (int q = 0; q < 4; q++) {
    double want = total > 0 ? (double)t * sum[q] / total : 0;
    n[q] = (long)floor(want);
    if (n[q] > cap[q]) n[q] = cap[q];
    rem[q] = want - (double)n[q];
    left -= n[q];
  }
  while (left > 0) {
    int best = -1;
    for (int q = 0; q < 4; q++)
      if (n[q] < cap[q] && (best < 0 || rem[q] > rem[best])) best = q;
    if (best < 0) break;
    n[best]++;
    rem[best] -= 1;
    left--;
  }
  for (int q = 0; q < 4; q++)
    coverage_split(frac, stride, mask, xs[q], ys[q], ws[q], hs[q], n[q], leaf);
}

void bbc__coverage_tree(const float *frac, int w, int h, int stride, uint8_t *mask) {
  double total = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) total += frac[(size_t)y * stride + x];
  coverage_split(frac, stride, mask, 0, 0, w, h, (long)floor(total + 0.5), 1);
}
