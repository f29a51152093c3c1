/* mips.c — the mipmaps of a model's textures that step 3 reads a baked
 * light's colours from: as a GPU makes them (glGenerateMipmap), each level
 * the 2x2 box average of the one before, every channel on its own, so that
 * the colour of transparent texels bleeds in as it does on screen; and the
 * textures' alpha tests as bits. */
#include "raster.h"

#include <stdlib.h>

bbc_result bbc__mips_build(const bbc_mesh *m, bbc__mips **out, bbc_error *err) {
  *out = NULL;
  if (!m->texture_count) return BBC_OK;
  bbc__mips *mips = calloc(m->texture_count, sizeof *mips);
  if (!mips) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "mipmaps: out of memory");
  for (size_t t = 0; t < m->texture_count; t++) {
    const bbc_image *base = &m->textures[t].image;
    if (!base->rgba || base->width < 1 || base->height < 1) continue;
    int n = 0;
    for (int w = base->width, h = base->height; w > 1 || h > 1;
         w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1)
      n++;
    mips[t].level = calloc(n ? (size_t)n : 1, sizeof *mips[t].level);
    if (!mips[t].level) {
      bbc__mips_free(mips, m->texture_count);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "mipmaps: out of memory");
    }
    const bbc_image *prev = base;
    for (int k = 0; k < n; k++) {
      bbc_image *img = &mips[t].level[k];
      int w = prev->width > 1 ? prev->width / 2 : 1, h = prev->height > 1 ? prev->height / 2 : 1;
      if (bbc_image_alloc(img, w, h) != BBC_OK) {
        bbc__mips_free(mips, m->texture_count);
        return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "mipmaps: out of memory");
      }
      mips[t].levels = k + 1;
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          int x0 = 2 * x < prev->width ? 2 * x : prev->width - 1;
          int y0 = 2 * y < prev->height ? 2 * y : prev->height - 1;
          int x1 = x0 + 1 < prev->width ? x0 + 1 : x0, y1 = y0 + 1 < prev->height ? y0 + 1 : y0;
          const uint8_t *p00 = prev->rgba + 4 * ((size_t)y0 * prev->width + x0);
          const uint8_t *p01 = prev->rgba + 4 * ((size_t)y0 * prev->width + x1);
          const uint8_t *p10 = prev->rgba + 4 * ((size_t)y1 * prev->width + x0);
          const uint8_t *p11 = prev->rgba + 4 * ((size_t)y1 * prev->width + x1);
          uint8_t *o = img->rgba + 4 * ((size_t)y * w + x);
          for (int c = 0; c < 4; c++) o[c] = (uint8_t)((p00[c] + p01[c] + p10[c] + p11[c] + 2) / 4);
        }
      prev = img;
    }
  }
  *out = mips;
  return BBC_OK;
}

void bbc__mips_free(bbc__mips *mips, size_t count) {
  if (!mips) return;
  for (size_t t = 0; t < count; t++) {
    for (int k = 0; k < mips[t].levels; k++) bbc_image_free(&mips[t].level[k]);
    free(mips[t].level);
  }
  free(mips);
}

bbc_result bbc__alpha_bits_build(const bbc_mesh *m, bbc__alpha_bits **out, bbc_error *err) {
  *out = NULL;
  if (!m->texture_count) return BBC_OK;
  bbc__alpha_bits *ab = calloc(m->texture_count, sizeof *ab);
  if (!ab) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "alpha bits: out of memory");
  for (size_t t = 0; t < m->texture_count; t++) {
    const bbc_image *img = &m->textures[t].image;
    if (!img->rgba || img->width < 1 || img->height < 1) continue;
    int tx = (img->width + 7) / 8, ty = (img->height + 7) / 8;
    ab[t].bits = calloc((size_t)tx * ty, sizeof *ab[t].bits);
    if (!ab[t].bits) {
      bbc__alpha_bits_free(ab, m->texture_count);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "alpha bits: out of memory");
    }
    ab[t].tiles_x = tx;
    for (int y = 0; y < img->height; y++)
      for (int x = 0; x < img->width; x++)
        if (img->rgba[4 * ((size_t)y * img->width + x) + 3] >= 128)
          ab[t].bits[(size_t)(y / 8) * tx + x / 8] |= (uint64_t)1 << ((y % 8) * 8 + x % 8);
  }
  *out = ab;
  return BBC_OK;
}

void bbc__alpha_bits_free(bbc__alpha_bits *ab, size_t count) {
  if (!ab) return;
  for (size_t t = 0; t < count; t++) free(ab[t].bits);
  free(ab);
}
