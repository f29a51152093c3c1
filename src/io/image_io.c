/* image_io.c — images in files and in memory: decoding with stb_image (and
 * run-length encoded BMP, bmp_rle.c), PNG output (our encoder over zlib) and
 * DDS output with mip levels, every file atomic. */
#include "io.h"

#include <assert.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>
#include <zlib.h>

/* stb allocates with malloc (Debian's build uses the default STBI_MALLOC),
 * so the pixels can be owned directly and released with free(). */
static bbc_result take_stb_pixels(unsigned char *px, int w, int h, bbc_image *image) {
  image->rgba = px;
  image->width = w;
  image->height = h;
  return BBC_OK;
}

/* The most pixels a texture may have (16384 x 8192: 512 MB decoded); a
 * header that claims more is refused before anything is decoded (a
 * damaged or hostile embedded image can ask for gigabytes). */
#define BBC_IMAGE_MAX_PIXELS ((size_t)1 << 27)

static bbc_result check_size(int ok, int w, int h, const char *what, bbc_error *err) {
  if (ok && w > 0 && h > 0 && (size_t)w * (size_t)h > BBC_IMAGE_MAX_PIXELS)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                     "%s: an image of %d x %d pixels, more than the %zu a texture may have", what,
                     w, h, BBC_IMAGE_MAX_PIXELS);
  return BBC_OK;
}

bbc_result bbc_image_load(const char *path, bbc_image *image, bbc_error *err) {
  assert(path && image);
  memset(image, 0, sizeof *image);
  bbc_result r = bbc__check_input_file(path, err);
  if (r != BBC_OK) return r;
  int w = 0, h = 0, n = 0;
  int known = stbi_info(path, &w, &h, &n); /* before w and h are read */
  r = check_size(known, w, h, path, err);
  if (r != BBC_OK) return r;
  unsigned char *px = stbi_load(path, &w, &h, &n, 4);
  if (!px) {
    const char *why = stbi_failure_reason();
    char *data = NULL;
    size_t size = 0;
    /* run-length encoded BMP: ours */
    if (bbc__read_whole_file(path, &data, &size, NULL) == BBC_OK &&
        bbc__is_bmp_rle((const uint8_t *)data, size)) {
      r = bbc__bmp_rle_decode((const uint8_t *)data, size, path, image, err);
      free(data);
      return r;
    }
    free(data);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: cannot decode image: %s", path, why);
  }
  return take_stb_pixels(px, w, h, image);
}

bbc_result bbc_image_load_memory(const void *data, size_t size, bbc_image *image, bbc_error *err) {
  assert((data || size == 0) && image);
  memset(image, 0, sizeof *image);
  if (!data || size == 0 || size > INT_MAX)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "embedded image is empty or too large");
  int w = 0, h = 0, n = 0;
  int known = stbi_info_from_memory(data, (int)size, &w, &h, &n); /* before w and h are read */
  bbc_result r = check_size(known, w, h, "embedded image", err);
  if (r != BBC_OK) return r;
  unsigned char *px = stbi_load_from_memory(data, (int)size, &w, &h, &n, 4);
  if (!px && bbc__is_bmp_rle(data, size))
    return bbc__bmp_rle_decode(data, size, "embedded image", image, err);
  if (!px)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "cannot decode embedded image: %s",
                     stbi_failure_reason());
  return take_stb_pixels(px, w, h, image);
}

static uint8_t paeth(int a, int b, int c) {
  int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
  return (uint8_t)(pa <= pb && pa <= pc ? a : (pb <= pc ? b : c));
}

/* Row y filtered with `filter` into out (1 + 4 w bytes). */
static void png_filter_row(const bbc_image *im, int y, int filter, uint8_t *out) {
  size_t n = 4 * (size_t)im->width;
  const uint8_t *r = im->rgba + (size_t)y * n, *u = y > 0 ? r - n : NULL;
  out[0] = (uint8_t)filter;
  uint8_t *o = out + 1;
  for (size_t i = 0; i < n; i++) {
    int a = i >= 4 ? r[i - 4] : 0, b = u ? u[i] : 0, c = u && i >= 4 ? u[i - 4] : 0;
    int pred = filter == 1 ? a : filter == 2 ? b : filter == 4 ? paeth(a, b, c) : 0;
    o[i] = (uint8_t)(r[i] - pred);
  }
}

static void put_be32(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)(v >> 24);
  p[1] = (uint8_t)(v >> 16);
  p[2] = (uint8_t)(v >> 8);
  p[3] = (uint8_t)v;
}

/* Appends a chunk (length, type, data, CRC of type and data) at *at. */
static void png_chunk(uint8_t *buf, size_t *at, const char *type, const uint8_t *data, size_t len) {
  uint8_t *p = buf + *at;
  put_be32(p, (uint32_t)len);
  memcpy(p + 4, type, 4);
  if (len && data != p + 8) memmove(p + 8, data, len);
  uLong crc = crc32(0L, p + 4, (uInt)(len + 4));
  put_be32(p + 8 + len, (uint32_t)crc);
  *at += 12 + len;
}

/* Deflates src (n bytes) at `level` into a new buffer, raw (no zlib
 * header) when `raw`; with `dict` (dict_len bytes) as the data before it,
 * ending byte-aligned without the final block when `more` follows. */
static int deflate_part(const uint8_t *src, size_t n, int level, int raw, const uint8_t *dict,
                        size_t dict_len, int more, uint8_t **out, size_t *out_len) {
  z_stream z;
  memset(&z, 0, sizeof z);
  if (deflateInit2(&z, level, Z_DEFLATED, raw ? -15 : 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) return 0;
  if (dict_len && deflateSetDictionary(&z, dict, (uInt)dict_len) != Z_OK) {
    deflateEnd(&z);
    return 0;
  }
  uLong bound = deflateBound(&z, (uLong)n) + 16;
  uint8_t *buf = malloc(bound);
  if (!buf) {
    deflateEnd(&z);
    return 0;
  }
  z.next_in = (Bytef *)src;
  z.avail_in = (uInt)n;
  z.next_out = buf;
  z.avail_out = (uInt)bound;
  int rc = deflate(&z, more ? Z_FULL_FLUSH : Z_FINISH);
  size_t len = z.total_out;
  deflateEnd(&z);
  if (more ? rc != Z_OK || z.avail_in : rc != Z_STREAM_END) {
    free(buf);
    return 0;
  }
  *out = buf;
  *out_len = len;
  return 1;
}

bbc_result bbc__png_encode(const bbc_image *im, uint8_t **out, size_t *out_size) {
  *out = NULL;
  *out_size = 0;
  if (!im || !im->rgba || im->width <= 0 || im->height <= 0) return BBC_ERROR_INVALID_ARGUMENT;
  size_t row = 1 + 4 * (size_t)im->width, n = row * (size_t)im->height;
  if (n > 0x7fffffffu) return BBC_ERROR_INVALID_ARGUMENT; /* zlib's uInt, one IDAT */
  uint8_t *raw = malloc(n);
  if (!raw) return BBC_ERROR_OUT_OF_MEMORY;
  /* The filter: every eighth row, each way, at level 1 (the four at once). */
  static const int filters[4] = {0, 1, 2, 4};
  size_t sample_rows = ((size_t)im->height + 7) / 8, trial_len[4];
  int failed = 0;
#pragma omp parallel for schedule(static, 1)
  for (int f = 0; f < 4; f++) {
    uint8_t *rows = malloc(sample_rows * row), *z = NULL;
    size_t zl = SIZE_MAX;
    if (rows) {
      for (size_t m = 0; m < sample_rows; m++)
        png_filter_row(im, (int)(8 * m), filters[f], rows + m * row);
      if (!deflate_part(rows, sample_rows * row, 1, 1, NULL, 0, 0, &z, &zl)) zl = SIZE_MAX;
    }
    if (zl == SIZE_MAX) {
#pragma omp atomic write
      failed = 1;
    }
    trial_len[f] = zl;
    free(rows);
    free(z);
  }
  int best = 0;
  for (int f = 1; f < 4; f++)
    if (trial_len[f] < trial_len[best]) best = f;
#pragma omp parallel for schedule(static)
  for (int y = 0; y < im->height; y++) png_filter_row(im, y, filters[best], raw + (size_t)y * row);
  /* The zlib stream: deflated in parts of whole rows, each part with the
   * 32 KB before it as its dictionary, compressed at once (pigz's way: the
   * parts are fixed by the size, so the file does not depend on the
   * threads), then the header and the Adler-32 of the whole. */
  enum { PARTS = 8 };
  size_t nparts = n / 262144 < 1 ? 1 : (n / 262144 > PARTS ? PARTS : n / 262144), cut[PARTS + 1];
  for (size_t k = 0; k <= nparts; k++) cut[k] = (size_t)im->height * k / nparts * row;
  uint8_t *part[PARTS] = {NULL};
  size_t part_len[PARTS] = {0};
  uLong part_adler[PARTS];
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < (int)nparts; k++) {
    part_adler[k] = adler32(adler32(0L, Z_NULL, 0), raw + cut[k], (uInt)(cut[k + 1] - cut[k]));
    size_t d = cut[k] < 32768 ? cut[k] : 32768;
    if (!deflate_part(raw + cut[k], cut[k + 1] - cut[k], 4, 1, raw + cut[k] - d, d,
                      k + 1 < (int)nparts, &part[k], &part_len[k])) {
#pragma omp atomic write
      failed = 1;
    }
  }
  uLong adler = part_adler[0];
  for (size_t k = 1; k < nparts; k++)
    adler = adler32_combine(adler, part_adler[k], (z_off_t)(cut[k + 1] - cut[k]));
  free(raw);
  /* signature, IHDR, IDAT (zlib header, parts, Adler-32), IEND */
  size_t zlen = 2 + 4;
  for (size_t k = 0; k < nparts; k++) zlen += part_len[k];
  uint8_t *buf = failed ? NULL : malloc(8 + 25 + 12 + zlen + 12);
  if (!buf) {
    for (size_t k = 0; k < nparts; k++) free(part[k]);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  memcpy(buf, sig, 8);
  uint8_t ihdr[13];
  put_be32(ihdr, (uint32_t)im->width);
  put_be32(ihdr + 4, (uint32_t)im->height);
  ihdr[8] = 8;  /* bits per channel */
  ihdr[9] = 6;  /* RGBA */
  ihdr[10] = 0; /* deflate */
  ihdr[11] = 0; /* adaptive filtering */
  ihdr[12] = 0; /* no interlace */
  size_t at = 8;
  png_chunk(buf, &at, "IHDR", ihdr, 13);
  uint8_t *z = buf + at + 8; /* the IDAT's data, written in place */
  z[0] = 0x78;               /* deflate, 32 KB window */
  z[1] = 0x5e;               /* a fast level (2-5); (0x78 << 8 | 0x5e) % 31 == 0 */
  size_t zo = 2;
  for (size_t k = 0; k < nparts; k++) {
    memcpy(z + zo, part[k], part_len[k]);
    zo += part_len[k];
    free(part[k]);
  }
  put_be32(z + zo, (uint32_t)adler);
  png_chunk(buf, &at, "IDAT", z, zlen);
  png_chunk(buf, &at, "IEND", NULL, 0);
  *out = buf;
  *out_size = at;
  return BBC_OK;
}

bbc_result bbc_image_write_png(const char *path, const bbc_image *image, bbc_error *err) {
  assert(path && image);
  if (!image || !image->rgba || image->width <= 0 || image->height <= 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: no image to write", path);
  uint8_t *png = NULL;
  size_t size = 0;
  bbc_result r = bbc__png_encode(image, &png, &size);
  if (r != BBC_OK) return bbc__fail(err, r, "%s: PNG encoding failed", path);
  bbc__atomic_file af;
  r = bbc__atomic_open(&af, path, err);
  if (r != BBC_OK) {
    free(png);
    return r;
  }
  int ok = fwrite(png, 1, size, af.fp) == size;
  free(png);
  if (!ok) {
    bbc__atomic_abort(&af);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
  }
  return bbc__atomic_commit(&af, err);
}

/* Little-endian 32-bit words into a DDS header. */
static void dds_word(uint8_t *h, int i, uint32_t v) {
  for (int k = 0; k < 4; k++) h[4 * i + k] = (uint8_t)(v >> (8 * k));
}

bbc_result bbc_image_write_dds(const char *path, const bbc_image *image, bbc_error *err) {
  assert(path && image);
  if (!image || !image->rgba || image->width <= 0 || image->height <= 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: no image to write", path);
  bbc_image *levels = NULL;
  int count = 0;
  bbc_result r = bbc_image_mipmaps(image, &levels, &count, err);
  if (r != BBC_OK) return r;
  /* The header (Microsoft's DDS_HEADER, 124 bytes after the magic): caps,
   * height, width, pitch, pixel format and mip count are given; RGBA8 as
   * 32-bit pixels with R in the lowest byte (DDPF_RGB | DDPF_ALPHAPIXELS);
   * a complex mipmapped texture. */
  uint8_t h[128];
  memset(h, 0, sizeof h);
  memcpy(h, "DDS ", 4);
  dds_word(h, 1, 124);
  dds_word(h, 2, 0x1 | 0x2 | 0x4 | 0x8 | 0x1000 | 0x20000);
  dds_word(h, 3, (uint32_t)image->height);
  dds_word(h, 4, (uint32_t)image->width);
  dds_word(h, 5, (uint32_t)image->width * 4);
  dds_word(h, 7, (uint32_t)count + 1);
  dds_word(h, 19, 32);         /* DDS_PIXELFORMAT: its size, */
  dds_word(h, 20, 0x40 | 0x1); /* flags, */
  dds_word(h, 22, 32);         /* bits per pixel and the masks */
  dds_word(h, 23, 0x000000ffu);
  dds_word(h, 24, 0x0000ff00u);
  dds_word(h, 25, 0x00ff0000u);
  dds_word(h, 26, 0xff000000u);
  dds_word(h, 27, 0x8 | 0x1000 | 0x400000);
  bbc__atomic_file af;
  r = bbc__atomic_open(&af, path, err);
  if (r == BBC_OK) {
    int ok = fwrite(h, 1, sizeof h, af.fp) == sizeof h;
    for (int l = -1; ok && l < count; l++) {
      const bbc_image *im = l < 0 ? image : &levels[l];
      size_t n = (size_t)im->width * im->height * 4;
      ok = fwrite(im->rgba, 1, n, af.fp) == n;
    }
    if (ok) {
      r = bbc__atomic_commit(&af, err);
    } else {
      int e = errno;
      bbc__atomic_abort(&af);
      r = bbc__fail(err, BBC_ERROR_IO, "%s: write failed: %s", path, strerror(e));
    }
  }
  for (int l = 0; l < count; l++) bbc_image_free(&levels[l]);
  free(levels);
  return r;
}
