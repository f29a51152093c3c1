/* bc1.c — BC1 (S3TC DXT1) blocks of an RGBA8 image, 4 bits a texel, and
 * back. Blocks whose texels are all opaque go through stb_dxt (Debian's
 * libstb-dev; its four-colour mode). A block with a transparent texel (alpha
 * < 128) is written in BC1's three-colour mode — c0 <= c1, the fourth index
 * transparent black — so binary alpha survives exactly: the endpoints are
 * the opaque texels' extremes along their principal axis. Format:
 * Microsoft's BC1 description (DirectX "Texture Block Compression in
 * Direct3D 11"), EXT_texture_compression_s3tc. */
#include "base.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#define STB_DXT_STATIC
#define STB_DXT_IMPLEMENTATION
#include <stb/stb_dxt.h>

size_t bbc_bc1_size(int width, int height) {
  size_t bw = ((size_t)(width > 0 ? width : 0) + 3) / 4,
         bh = ((size_t)(height > 0 ? height : 0) + 3) / 4;
  return bw * bh * 8;
}

static unsigned to565(const double c[3]) {
  int r = (int)lround(fmin(fmax(c[0], 0), 255) * 31 / 255.0);
  int g = (int)lround(fmin(fmax(c[1], 0), 255) * 63 / 255.0);
  int b = (int)lround(fmin(fmax(c[2], 0), 255) * 31 / 255.0);
  return (unsigned)(r << 11 | g << 5 | b);
}

static void from565(unsigned c, int out[3]) {
  int r = (int)(c >> 11) & 31, g = (int)(c >> 5) & 63, b = (int)c & 31;
  out[0] = (r << 3) | (r >> 2);
  out[1] = (g << 2) | (g >> 4);
  out[2] = (b << 3) | (b >> 2);
}

static void put_block(uint8_t *dst, unsigned c0, unsigned c1, uint32_t idx) {
  dst[0] = (uint8_t)c0;
  dst[1] = (uint8_t)(c0 >> 8);
  dst[2] = (uint8_t)c1;
  dst[3] = (uint8_t)(c1 >> 8);
  for (int i = 0; i < 4; i++) dst[4 + i] = (uint8_t)(idx >> (8 * i));
}

/* A block with transparent texels: three-colour mode. */
static void encode_punch_through(const uint8_t px[16][4], uint8_t *dst) {
  double mean[3] = {0, 0, 0};
  int n = 0;
  for (int i = 0; i < 16; i++)
    if (px[i][3] >= 128) {
      for (int k = 0; k < 3; k++) mean[k] += px[i][k];
      n++;
    }
  if (!n) { /* all transparent */
    put_block(dst, 0, 0, 0xffffffffu);
    return;
  }
  for (int k = 0; k < 3; k++) mean[k] /= n;
  /* the principal axis of the opaque colours (power iteration on their
   * covariance), then their extremes along it */
  double cov[3][3] = {{0}}, axis[3] = {1, 1, 1};
  for (int i = 0; i < 16; i++)
    if (px[i][3] >= 128)
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) cov[a][b] += (px[i][a] - mean[a]) * (px[i][b] - mean[b]);
  for (int it = 0; it < 8; it++) {
    double v[3] = {0, 0, 0}, len = 0;
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) v[a] += cov[a][b] * axis[b];
    for (int a = 0; a < 3; a++) len += v[a] * v[a];
    if (len < 1e-12) break;
    for (int a = 0; a < 3; a++) axis[a] = v[a] / sqrt(len);
  }
  double lo = 1e300, hi = -1e300;
  for (int i = 0; i < 16; i++)
    if (px[i][3] >= 128) {
      double t = 0;
      for (int a = 0; a < 3; a++) t += (px[i][a] - mean[a]) * axis[a];
      lo = fmin(lo, t);
      hi = fmax(hi, t);
    }
  double e0[3], e1[3];
  for (int a = 0; a < 3; a++) {
    e0[a] = mean[a] + lo * axis[a];
    e1[a] = mean[a] + hi * axis[a];
  }
  unsigned c0 = to565(e0), c1 = to565(e1);
  if (c0 > c1) { /* three-colour mode wants c0 <= c1 */
    unsigned t = c0;
    c0 = c1;
    c1 = t;
  }
  int p[3][3];
  from565(c0, p[0]);
  from565(c1, p[1]);
  for (int a = 0; a < 3; a++) p[2][a] = (p[0][a] + p[1][a]) / 2;
  uint32_t idx = 0;
  for (int i = 0; i < 16; i++) {
    unsigned best = 3;
    if (px[i][3] >= 128) {
      long bd = -1;
      static const unsigned code[3] = {0, 1, 2};
      for (int c = 0; c < 3; c++) {
        long d = 0;
        for (int a = 0; a < 3; a++) d += (long)(px[i][a] - p[c][a]) * (px[i][a] - p[c][a]);
        if (bd < 0 || d < bd) {
          bd = d;
          best = code[c];
        }
      }
    }
    idx |= (uint32_t)best << (2 * i);
  }
  put_block(dst, c0, c1, idx);
}

bbc_result bbc_image_encode_bc1(const bbc_image *im, uint8_t *out, bbc_error *err) {
  assert(im && out);
  if (!im->rgba || im->width < 1 || im->height < 1)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "BC1: an empty image");
  int bw = (im->width + 3) / 4, bh = (im->height + 3) / 4;
  for (int by = 0; by < bh; by++)
    for (int bx = 0; bx < bw; bx++) {
      uint8_t px[16][4];
      int transparent = 0;
      for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) { /* edges: the last row and column repeated */
          int sx = bx * 4 + x < im->width ? bx * 4 + x : im->width - 1;
          int sy = by * 4 + y < im->height ? by * 4 + y : im->height - 1;
          memcpy(px[y * 4 + x], im->rgba + 4 * ((size_t)sy * im->width + sx), 4);
          transparent |= px[y * 4 + x][3] < 128;
        }
      uint8_t *dst = out + 8 * ((size_t)by * bw + bx);
      if (transparent) {
        encode_punch_through((const uint8_t(*)[4])px, dst);
      } else {
        stb_compress_dxt_block(dst, &px[0][0], 0, STB_DXT_HIGHQUAL);
      }
    }
  return BBC_OK;
}

bbc_result bbc_bc1_decode(const uint8_t *blocks, int width, int height, bbc_image *out,
                          bbc_error *err) {
  assert(blocks && out);
  bbc_result r = bbc_image_alloc(out, width, height);
  if (r != BBC_OK) return bbc__fail(err, r, "BC1: out of memory for %d x %d", width, height);
  int bw = (width + 3) / 4, bh = (height + 3) / 4;
  for (int by = 0; by < bh; by++)
    for (int bx = 0; bx < bw; bx++) {
      const uint8_t *b = blocks + 8 * ((size_t)by * bw + bx);
      unsigned c0 = b[0] | b[1] << 8, c1 = b[2] | b[3] << 8;
      uint32_t idx =
          (uint32_t)b[4] | (uint32_t)b[5] << 8 | (uint32_t)b[6] << 16 | (uint32_t)b[7] << 24;
      int p[4][4];
      from565(c0, p[0]);
      from565(c1, p[1]);
      p[0][3] = p[1][3] = 255;
      for (int a = 0; a < 3; a++)
        if (c0 > c1) {
          p[2][a] = (2 * p[0][a] + p[1][a]) / 3;
          p[3][a] = (p[0][a] + 2 * p[1][a]) / 3;
        } else {
          p[2][a] = (p[0][a] + p[1][a]) / 2;
          p[3][a] = 0;
        }
      p[2][3] = 255;
      p[3][3] = c0 > c1 ? 255 : 0;
      for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
          int X = bx * 4 + x, Y = by * 4 + y;
          if (X >= width || Y >= height) continue;
          const int *c = p[(idx >> (2 * (y * 4 + x))) & 3];
          uint8_t *d = out->rgba + 4 * ((size_t)Y * width + X);
          for (int a = 0; a < 4; a++) d[a] = (uint8_t)c[a];
        }
    }
  return BBC_OK;
}

int bbc_image_alpha_is_binary(const bbc_image *im) {
  for (size_t i = 0; im && im->rgba && i < (size_t)im->width * im->height; i++)
    if (im->rgba[4 * i + 3] != 0 && im->rgba[4 * i + 3] != 255) return 0;
  return 1;
}

int bbc_image_alpha_is_soft_mask(const bbc_image *im) {
  int soft = 0;
  for (size_t i = 0; im && im->rgba && i < (size_t)im->width * im->height; i++) {
    uint8_t a = im->rgba[4 * i + 3];
    if (a > 64 && a < 192) return 0;
    soft |= a != 0 && a != 255;
  }
  return soft;
}

void bbc_image_alpha_binarise(bbc_image *im) {
  for (size_t i = 0; im && im->rgba && i < (size_t)im->width * im->height; i++)
    im->rgba[4 * i + 3] = im->rgba[4 * i + 3] >= 128 ? 255 : 0;
}
