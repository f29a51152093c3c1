/* texels.c — a supersampled image down to its texels (quality 2, thesis
 * 2.3.9): which texels end opaque by their samples' coverage, their mean
 * colours or normals, and the colours transparent texels carry for a GPU's
 * filtering. Billboards' bakes and impostors' frames share them. */
#include "cloud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* quality 2: which texels of a k x k supersampled image end opaque (mask[texel] = 1).
 * Growing (thesis 2.3.9, `dither 0`): at least `min_opaque` of its k^2
 * samples are. Dithering (`dither 1`): coverage-preserving error diffusion
 * (Floyd-Steinberg, serpentine rows) of each texel's covered fraction, so
 * that over any small area the fraction of opaque texels is the fraction
 * the original covers, and a texel none of whose samples is covered never
 * turns opaque (its share of the error moves on to covered neighbours). */
/* The covered fraction of texel (x, y) of a k x k supersampled image (its
 * samples' alphas; with taps, those drawn at their centres) and whether any
 * sample covers it (*n > 0). */
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

bbc_result bbc__alpha_mask(const bbc_image *img, const uint8_t *taps, int k, int dither,
                           unsigned min_opaque, uint8_t *mask, uint8_t *cand) {
  int w = img->width / k, h = img->height / k;
  if (dither == 2) { /* coverage kept down a quadtree */
    float *frac = malloc((size_t)w * h * sizeof *frac);
    if (!frac) return BBC_ERROR_OUT_OF_MEMORY;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        unsigned n;
        frac[(size_t)y * w + x] = texel_share(img, taps, k, x, y, &n);
        cand[(size_t)y * w + x] = n > 0;
      }
    bbc__coverage_tree(frac, w, h, w, mask);
    free(frac);
    return BBC_OK;
  }
  float *err = dither ? calloc(2 * ((size_t)w + 2), sizeof *err) : NULL;
  if (dither && !err) return BBC_ERROR_OUT_OF_MEMORY;
  for (int y = 0; y < h; y++) {
    float *cur = err ? err + (y % 2) * ((size_t)w + 2) + 1 : NULL;
    float *nxt = err ? err + ((y + 1) % 2) * ((size_t)w + 2) + 1 : NULL;
    if (nxt) memset(nxt - 1, 0, ((size_t)w + 2) * sizeof *nxt);
    int dir = y % 2 ? -1 : 1;
    for (int i = 0; i < w; i++) {
      int x = dir > 0 ? i : w - 1 - i;
      /* covered samples, and their share: bbc__bake.taps, a sample drawn by
       * a face passing its alpha test at a tap only makes the texel a
       * candidate, its coverage the samples' centres' */
      unsigned n;
      float share = texel_share(img, taps, k, x, y, &n);
      uint8_t on;
      if (!dither) {
        on = n > 0 && n >= min_opaque;
      } else {
        float v = share + cur[x];
        on = n > 0 && v >= 0.5f;
        /* The error goes to the neighbours inside the image, the weights
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
      }
      mask[(size_t)y * w + x] = on;
      cand[(size_t)y * w + x] = n > 0;
    }
  }
  free(err);
  return BBC_OK;
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
