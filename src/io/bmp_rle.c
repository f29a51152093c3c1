/* bmp_rle.c — run-length encoded BMP images (BI_RLE8 and BI_RLE4), which
 * stb_image does not read: old terrain heightmaps come that way. Format:
 * Microsoft's BITMAPINFOHEADER with a palette; runs of (count, index) pairs
 * and escapes 0 = end of line, 1 = end of bitmap, 2 = move (dx, dy),
 * n >= 3 = n literal indices padded to 16 bits. Every read is checked
 * against the file's size. */
#include "io.h"

#include <stdlib.h>
#include <string.h>

static uint32_t u32(const uint8_t *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint16_t u16(const uint8_t *p) {
  return (uint16_t)(p[0] | p[1] << 8);
}

int bbc__is_bmp_rle(const uint8_t *d, size_t n) {
  if (n < 54 || d[0] != 'B' || d[1] != 'M') return 0;
  uint32_t comp = u32(d + 30);
  return comp == 1 || comp == 2;
}

bbc_result bbc__bmp_rle_decode(const uint8_t *d, size_t n, const char *name, bbc_image *out,
                               bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (!bbc__is_bmp_rle(d, n))
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: not a run-length encoded BMP", name);
  uint32_t data_at = u32(d + 10), hsize = u32(d + 14);
  int32_t w = (int32_t)u32(d + 18), h = (int32_t)u32(d + 22);
  uint16_t bits = u16(d + 28);
  uint32_t comp = u32(d + 30), colours = u32(d + 46);
  int top_down = h < 0;
  if (top_down) h = -h;
  if (w <= 0 || h <= 0 || w > 65536 || h > 65536 || (uint64_t)w * h > 256u * 1024 * 1024)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: BMP of %d x %d pixels", name, (int)w, (int)h);
  if ((comp == 1 && bits != 8) || (comp == 2 && bits != 4))
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: RLE BMP with %u bits per pixel", name, bits);
  uint32_t max_colours = 1u << bits;
  if (colours == 0 || colours > max_colours) colours = max_colours;
  if (hsize < 40 || 14 + (uint64_t)hsize + 4ull * colours > n || data_at >= n)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: truncated BMP header or palette", name);
  const uint8_t *pal = d + 14 + hsize;
  if (bbc_image_alloc(out, w, h) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
  /* pixels not written by the runs (moves) stay palette entry 0 */
  for (size_t i = 0; i < (size_t)w * h; i++) {
    uint8_t *o = out->rgba + 4 * i;
    o[0] = pal[2];
    o[1] = pal[1];
    o[2] = pal[0];
    o[3] = 255;
  }
  size_t p = data_at;
  int32_t x = 0, y = 0; /* y counts rows from the file's first row */
#define PUT(idx)                                                                                   \
  do {                                                                                             \
    uint32_t ix_ = (idx);                                                                          \
    if (x < w && y < h && ix_ < colours) {                                                         \
      int32_t row_ = top_down ? y : h - 1 - y;                                                     \
      uint8_t *o_ = out->rgba + 4 * ((size_t)row_ * w + x);                                        \
      o_[0] = pal[4 * ix_ + 2];                                                                    \
      o_[1] = pal[4 * ix_ + 1];                                                                    \
      o_[2] = pal[4 * ix_];                                                                        \
    }                                                                                              \
    x++;                                                                                           \
  } while (0)
  while (p + 1 < n && y < h) {
    uint8_t count = d[p], val = d[p + 1];
    p += 2;
    if (count > 0) {
      for (int i = 0; i < count; i++)
        PUT(bits == 8 ? val : (i & 1) ? (uint32_t)(val & 15) : (uint32_t)(val >> 4));
    } else if (val == 0) {
      x = 0;
      y++;
    } else if (val == 1) {
      break;
    } else if (val == 2) {
      if (p + 1 >= n) break;
      x += d[p];
      y += d[p + 1];
      p += 2;
    } else {
      size_t bytes = bits == 8 ? val : (val + 1u) / 2;
      if (p + bytes > n) {
        bbc_image_free(out);
        return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: truncated RLE data", name);
      }
      for (int i = 0; i < val; i++)
        PUT(bits == 8 ? d[p + i]
            : (i & 1) ? (uint32_t)(d[p + i / 2] & 15)
                      : (uint32_t)(d[p + i / 2] >> 4));
      p += bytes + (bytes & 1);
    }
  }
#undef PUT
  return BBC_OK;
}
