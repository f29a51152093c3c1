/* test_atlas.c — bbc_atlas_pack: sizes on tiny cases with known answers,
 * invariants (power-of-two size, padding gaps, texels copied exactly, alpha
 * untouched) on many seeded random images, dilation colours, determinism,
 * and the errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bbc.h"
#include "io.h"
#include "test_util.h"

/* ---- helpers ------------------------------------------------------------ */

/* A w x h image of random colours; about `transparent_pct` % of the texels
 * have alpha 0 (RGB still random), the rest alpha in 1..255. */
static void random_image(bbc_image *im, int w, int h, bbc__rng *rng, int transparent_pct) {
  assert_int_equal(bbc_image_alloc(im, w, h), BBC_OK);
  for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
    uint8_t *p = im->rgba + i * 4;
    for (int c = 0; c < 3; c++) p[c] = (uint8_t)(bbc__rng_next(rng) & 255);
    int transparent = (int)(bbc__rng_next(rng) % 100) < transparent_pct;
    p[3] = transparent ? 0 : (uint8_t)(1 + bbc__rng_next(rng) % 255);
  }
}

static void fill(bbc_image *im, int w, int h, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  assert_int_equal(bbc_image_alloc(im, w, h), BBC_OK);
  for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
    im->rgba[i * 4 + 0] = r;
    im->rgba[i * 4 + 1] = g;
    im->rgba[i * 4 + 2] = b;
    im->rgba[i * 4 + 3] = a;
  }
}

static void set_texel(bbc_image *im, int x, int y, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  uint8_t *p = im->rgba + ((size_t)y * (size_t)im->width + (size_t)x) * 4;
  p[0] = r;
  p[1] = g;
  p[2] = b;
  p[3] = a;
}

static const uint8_t *texel(const bbc_image *im, int x, int y) {
  return im->rgba + ((size_t)y * (size_t)im->width + (size_t)x) * 4;
}

static void assert_rgba(const uint8_t *p, int r, int g, int b, int a) {
  if (p[0] != r || p[1] != g || p[2] != b || p[3] != a)
    fail_msg("texel is (%d,%d,%d,%d), expected (%d,%d,%d,%d)", p[0], p[1], p[2], p[3], r, g, b, a);
}

static void free_images(bbc_image *images, size_t count) {
  for (size_t i = 0; i < count; i++) bbc_image_free(&images[i]);
}

static int is_pow2(int v) {
  return v > 0 && (v & (v - 1)) == 0;
}

/* Everything the packer promises about a successful result. */
static void check_atlas(const bbc_image *images, size_t count, int padding, int max_size,
                        const bbc_image *atlas, const bbc_atlas_rect *rects) {
  int W = atlas->width, H = atlas->height;
  assert_non_null(atlas->rgba);
  assert_true(is_pow2(W));
  assert_true(is_pow2(H));
  assert_true(W == H || W == 2 * H || H == 2 * W);
  assert_true(W <= max_size && H <= max_size);

  uint8_t *covered = calloc((size_t)W * (size_t)H, 1);
  assert_non_null(covered);
  for (size_t i = 0; i < count; i++) {
    const bbc_atlas_rect *r = &rects[i];
    assert_int_equal(r->width, images[i].width);
    assert_int_equal(r->height, images[i].height);
    /* Inside the atlas with `padding` texels to every border. */
    if (r->x < padding || r->y < padding || r->x + r->width > W - padding ||
        r->y + r->height > H - padding)
      fail_msg("rect %zu (%d,%d %dx%d) is not %d texels inside the %dx%d atlas", i, r->x, r->y,
               r->width, r->height, padding, W, H);
    /* Texels copied exactly: alpha everywhere, RGB where opaque. */
    for (int y = 0; y < r->height; y++)
      for (int x = 0; x < r->width; x++) {
        const uint8_t *a = texel(atlas, r->x + x, r->y + y);
        const uint8_t *s = texel(&images[i], x, y);
        assert_int_equal(a[3], s[3]);
        if (s[3] > 0) assert_memory_equal(a, s, 3);
        size_t k = (size_t)(r->y + y) * (size_t)W + (size_t)(r->x + x);
        if (covered[k]) fail_msg("rect %zu overlaps another at (%d,%d)", i, r->x + x, r->y + y);
        covered[k] = 1;
      }
  }
  /* Alpha is 0 wherever no image lies. */
  for (size_t k = 0; k < (size_t)W * (size_t)H; k++)
    if (!covered[k] && atlas->rgba[k * 4 + 3] != 0)
      fail_msg("texel %zu outside every rect has alpha %d", k, atlas->rgba[k * 4 + 3]);
  free(covered);

  /* Gaps of at least `padding` between images: rect i grown by padding on
   * every side does not meet rect j. */
  for (size_t i = 0; i < count; i++)
    for (size_t j = i + 1; j < count; j++) {
      const bbc_atlas_rect *a = &rects[i], *b = &rects[j];
      int apart = a->x - padding >= b->x + b->width || b->x >= a->x + a->width + padding ||
                  a->y - padding >= b->y + b->height || b->y >= a->y + a->height + padding;
      if (!apart)
        fail_msg("rects %zu (%d,%d %dx%d) and %zu (%d,%d %dx%d) are closer than %d texels", i, a->x,
                 a->y, a->width, a->height, j, b->x, b->y, b->width, b->height, padding);
    }
}

/* ---- sizes with known answers ------------------------------------------- */

static void pack_sizes(const int *wh, size_t count, int padding, int expect_w, int expect_h) {
  bbc_image images[8];
  bbc_atlas_rect rects[8];
  assert_true(count <= 8);
  for (size_t i = 0; i < count; i++) fill(&images[i], wh[2 * i], wh[2 * i + 1], 9, 8, 7, 255);
  bbc_image atlas;
  bbc_error err;
  assert_int_equal(bbc_atlas_pack(images, count, padding, 1024, &atlas, rects, &err), BBC_OK);
  if (atlas.width != expect_w || atlas.height != expect_h)
    fail_msg("atlas %dx%d, expected %dx%d", atlas.width, atlas.height, expect_w, expect_h);
  check_atlas(images, count, padding, 1024, &atlas, rects);
  bbc_image_free(&atlas);
  free_images(images, count);
}

static void test_known_sizes(void **state) {
  (void)state;
  pack_sizes((const int[]){1, 1}, 1, 0, 1, 1);
  pack_sizes((const int[]){1, 1, 1, 1}, 2, 0, 2, 1); /* 2:1, wide first */
  pack_sizes((const int[]){1, 2}, 1, 0, 1, 2);       /* tall when wide cannot fit */
  pack_sizes((const int[]){1, 1}, 1, 1, 4, 4);       /* 3x3 needed: 4x2 too low */
  pack_sizes((const int[]){4, 4, 4, 4, 4, 4, 4, 4}, 4, 0, 8, 8);
  pack_sizes((const int[]){4, 4, 4, 4}, 2, 0, 8, 4);
  pack_sizes((const int[]){5, 5}, 1, 0, 8, 8);
  pack_sizes((const int[]){3, 3, 3, 3}, 2, 1, 16, 8); /* 1+3+1+3+1 = 9 > 8 both ways */
  pack_sizes((const int[]){3, 3}, 1, 2, 8, 8);        /* 3 + 2 + 2 = 7 */
  pack_sizes((const int[]){60, 30, 60, 30}, 2, 0, 64, 64);
  pack_sizes((const int[]){64, 32}, 1, 0, 64, 32);
}

static void test_empty(void **state) {
  (void)state;
  bbc_image atlas;
  bbc_error err;
  assert_int_equal(bbc_atlas_pack(NULL, 0, 2, 64, &atlas, NULL, &err), BBC_OK);
  assert_int_equal(atlas.width, 1);
  assert_int_equal(atlas.height, 1);
  assert_rgba(atlas.rgba, 0, 0, 0, 0);
  bbc_image_free(&atlas);
}

/* ---- many images -------------------------------------------------------- */

enum { RANDOM_COUNT = 200 };

static void make_random_set(bbc_image *images, size_t count, uint64_t seed, int max_side) {
  bbc__rng rng = {seed};
  for (size_t i = 0; i < count; i++) {
    int w = 1 + (int)(bbc__rng_next(&rng) % (uint64_t)max_side);
    int h = 1 + (int)(bbc__rng_next(&rng) % (uint64_t)max_side);
    random_image(&images[i], w, h, &rng, 30);
  }
}

static void test_random_many(void **state) {
  (void)state;
  for (int padding = 0; padding <= 3; padding++) {
    bbc_image images[RANDOM_COUNT];
    bbc_atlas_rect rects[RANDOM_COUNT];
    make_random_set(images, RANDOM_COUNT, 1234 + (uint64_t)padding, 64);
    bbc_image atlas;
    bbc_error err;
    bbc_result r = bbc_atlas_pack(images, RANDOM_COUNT, padding, 4096, &atlas, rects, &err);
    if (r != BBC_OK) fail_msg("%s", err.message);
    check_atlas(images, RANDOM_COUNT, padding, 4096, &atlas, rects);
    /* Reasonably tight: the padded images cover more than a quarter of the
     * atlas (a power-of-two step costs at most 2x). */
    size_t need = 0;
    for (size_t i = 0; i < RANDOM_COUNT; i++)
      need += (size_t)(images[i].width + padding) * (size_t)(images[i].height + padding);
    size_t area = (size_t)atlas.width * (size_t)atlas.height;
    if (need * 4 < area)
      fail_msg("atlas %dx%d for %zu padded texels", atlas.width, atlas.height, need);
    bbc_image_free(&atlas);
    free_images(images, RANDOM_COUNT);
  }
}

static void test_one_large_many_small(void **state) {
  (void)state;
  enum { N = 101 };
  bbc_image images[N];
  bbc_atlas_rect rects[N];
  bbc__rng rng = {99};
  make_random_set(images + 1, N - 1, 77, 16);
  random_image(&images[0], 250, 200, &rng, 50);
  bbc_image atlas;
  bbc_error err;
  bbc_result r = bbc_atlas_pack(images, N, 2, 1024, &atlas, rects, &err);
  if (r != BBC_OK) fail_msg("%s", err.message);
  check_atlas(images, N, 2, 1024, &atlas, rects);
  /* The large image needs 254x204 with its padding; the small ones fill
   * the strip below it, so the smallest possible atlas, 256x256, holds all. */
  assert_int_equal(atlas.width, 256);
  assert_int_equal(atlas.height, 256);
  bbc_image_free(&atlas);
  free_images(images, N);
}

/* ---- determinism -------------------------------------------------------- */

static void test_deterministic(void **state) {
  (void)state;
  bbc_image images[RANDOM_COUNT];
  make_random_set(images, RANDOM_COUNT, 4242, 32);
  /* Equal sizes as well: ties must not depend on the sort. */
  for (size_t i = 0; i < 40; i++) {
    bbc_image_free(&images[i]);
    bbc__rng rng = {i};
    random_image(&images[i], 8, 8, &rng, 20);
  }
  bbc_atlas_rect rects[2][RANDOM_COUNT];
  bbc_image atlas[2];
  for (int k = 0; k < 2; k++)
    assert_int_equal(bbc_atlas_pack(images, RANDOM_COUNT, 2, 2048, &atlas[k], rects[k], NULL),
                     BBC_OK);
  assert_int_equal(atlas[0].width, atlas[1].width);
  assert_int_equal(atlas[0].height, atlas[1].height);
  assert_memory_equal(rects[0], rects[1], sizeof rects[0]);
  assert_memory_equal(atlas[0].rgba, atlas[1].rgba,
                      (size_t)atlas[0].width * (size_t)atlas[0].height * 4);
  check_atlas(images, RANDOM_COUNT, 2, 2048, &atlas[0], rects[0]);
  bbc_image_free(&atlas[0]);
  bbc_image_free(&atlas[1]);
  free_images(images, RANDOM_COUNT);
}

/* ---- dilation ----------------------------------------------------------- */

static void test_dilation_red(void **state) {
  (void)state;
  /* 3x3, transparent blue, an opaque red texel in the middle; padding 2 ->
   * a 7x7 need -> 8x8 atlas, image at (2,2), red at (3,3). Four rings reach
   * every texel of the atlas (Chebyshev distance <= 4). */
  bbc_image im;
  fill(&im, 3, 3, 0, 0, 255, 0);
  set_texel(&im, 1, 1, 255, 0, 0, 255);
  bbc_image atlas;
  bbc_atlas_rect rect;
  assert_int_equal(bbc_atlas_pack(&im, 1, 2, 64, &atlas, &rect, NULL), BBC_OK);
  assert_int_equal(atlas.width, 8);
  assert_int_equal(atlas.height, 8);
  assert_int_equal(rect.x, 2);
  assert_int_equal(rect.y, 2);
  check_atlas(&im, 1, 2, 64, &atlas, &rect);
  for (int y = 0; y < 8; y++)
    for (int x = 0; x < 8; x++)
      assert_rgba(texel(&atlas, x, y), 255, 0, 0, (x == 3 && y == 3) ? 255 : 0);
  bbc_image_free(&atlas);
  bbc_image_free(&im);
}

static void test_dilation_average_and_reach(void **state) {
  (void)state;
  /* 3x1: red | transparent | green, padding 0 -> 4x2 atlas (4x1 is not a
   * permitted shape). The middle texel averages both neighbours; the others
   * copy the opaque texels they touch. */
  bbc_image im;
  fill(&im, 3, 1, 1, 2, 3, 0);
  set_texel(&im, 0, 0, 255, 0, 0, 255);
  set_texel(&im, 2, 0, 0, 255, 0, 10);
  bbc_image atlas;
  bbc_atlas_rect rect;
  assert_int_equal(bbc_atlas_pack(&im, 1, 0, 64, &atlas, &rect, NULL), BBC_OK);
  assert_int_equal(atlas.width, 4);
  assert_int_equal(atlas.height, 2);
  assert_rgba(texel(&atlas, 0, 0), 255, 0, 0, 255);
  assert_rgba(texel(&atlas, 1, 0), 128, 128, 0, 0);
  assert_rgba(texel(&atlas, 2, 0), 0, 255, 0, 10);
  assert_rgba(texel(&atlas, 3, 0), 0, 255, 0, 0);
  /* Second row, same ring: only texels coloured before it count. */
  assert_rgba(texel(&atlas, 0, 1), 255, 0, 0, 0);
  assert_rgba(texel(&atlas, 1, 1), 128, 128, 0, 0);
  assert_rgba(texel(&atlas, 2, 1), 0, 255, 0, 0);
  assert_rgba(texel(&atlas, 3, 1), 0, 255, 0, 0);
  bbc_image_free(&atlas);
  bbc_image_free(&im);

  /* 16x16 transparent (10,20,30) with one opaque white texel at (0,0),
   * padding 0: four rings colour the texels within Chebyshev distance 4;
   * beyond that the image keeps its own RGB. */
  fill(&im, 16, 16, 10, 20, 30, 0);
  set_texel(&im, 0, 0, 255, 255, 255, 255);
  assert_int_equal(bbc_atlas_pack(&im, 1, 0, 64, &atlas, &rect, NULL), BBC_OK);
  assert_int_equal(atlas.width, 16);
  assert_int_equal(atlas.height, 16);
  for (int y = 0; y < 16; y++)
    for (int x = 0; x < 16; x++) {
      int d = x > y ? x : y;
      if (d == 0)
        assert_rgba(texel(&atlas, x, y), 255, 255, 255, 255);
      else if (d <= 4)
        assert_rgba(texel(&atlas, x, y), 255, 255, 255, 0);
      else
        assert_rgba(texel(&atlas, x, y), 10, 20, 30, 0);
    }
  bbc_image_free(&atlas);

  /* Padding 6 > 4: six rings. */
  assert_int_equal(bbc_atlas_pack(&im, 1, 6, 64, &atlas, &rect, NULL), BBC_OK);
  assert_int_equal(atlas.width, 32);
  assert_int_equal(rect.x, 6);
  assert_rgba(texel(&atlas, rect.x + 6, rect.y + 6), 255, 255, 255, 0);
  assert_rgba(texel(&atlas, rect.x + 7, rect.y), 10, 20, 30, 0);
  assert_rgba(texel(&atlas, 0, 0), 255, 255, 255, 0);
  assert_rgba(texel(&atlas, 31, 31), 0, 0, 0, 0);
  bbc_image_free(&atlas);
  bbc_image_free(&im);
}

/* ---- errors ------------------------------------------------------------- */

static void expect_failure(const bbc_image *images, size_t count, int padding, int max_size,
                           bbc_atlas_rect *rects, bbc_result code, const char *needle) {
  bbc_image atlas = {7, 7, NULL};
  bbc_error err;
  memset(&err, 0, sizeof err);
  bbc_result r = bbc_atlas_pack(images, count, padding, max_size, &atlas, rects, &err);
  if (r != code)
    fail_msg("got %s (%s), expected %s", bbc_result_string(r), err.message,
             bbc_result_string(code));
  assert_int_equal(err.code, code);
  assert_int_equal(atlas.width, 0);
  assert_int_equal(atlas.height, 0);
  assert_null(atlas.rgba);
  if (needle && !strstr(err.message, needle))
    fail_msg("message \"%s\" does not mention \"%s\"", err.message, needle);
  bbc_image_free(&atlas);
}

static void test_too_big(void **state) {
  (void)state;
  bbc_image images[5];
  bbc_atlas_rect rects[5];
  fill(&images[0], 65, 1, 1, 1, 1, 255);
  expect_failure(images, 1, 0, 64, rects, BBC_ERROR_OUT_OF_RANGE, "64x64");
  /* Fits alone, not with its padding. */
  bbc_image_free(&images[0]);
  fill(&images[0], 62, 2, 1, 1, 1, 255);
  expect_failure(images, 1, 2, 64, rects, BBC_ERROR_OUT_OF_RANGE, "64x64");
  bbc_image_free(&images[0]);
  /* Too much area in total: 5 x 32x32 > 64x64. */
  for (int i = 0; i < 5; i++) fill(&images[i], 32, 32, 1, 1, 1, 255);
  expect_failure(images, 5, 0, 64, rects, BBC_ERROR_OUT_OF_RANGE, "64x64");
  /* The area would do (3 x 33x33 < 64x64) but no packing exists. */
  free_images(images, 5);
  for (int i = 0; i < 3; i++) fill(&images[i], 33, 33, 1, 1, 1, 255);
  expect_failure(images, 3, 0, 64, rects, BBC_ERROR_OUT_OF_RANGE, "3 images");
  /* ... and with room they pack. */
  bbc_image atlas;
  assert_int_equal(bbc_atlas_pack(images, 3, 0, 128, &atlas, rects, NULL), BBC_OK);
  check_atlas(images, 3, 0, 128, &atlas, rects);
  assert_int_equal(atlas.width, 128);
  assert_int_equal(atlas.height, 64);
  bbc_image_free(&atlas);
  free_images(images, 3);
}

static void test_invalid_arguments(void **state) {
  (void)state;
  bbc_image im;
  bbc_atlas_rect rect;
  fill(&im, 2, 2, 1, 2, 3, 255);
  expect_failure(NULL, 1, 0, 64, &rect, BBC_ERROR_INVALID_ARGUMENT, NULL);
  expect_failure(&im, 1, 0, 64, NULL, BBC_ERROR_INVALID_ARGUMENT, NULL);
  expect_failure(&im, 1, -1, 64, &rect, BBC_ERROR_INVALID_ARGUMENT, "padding");
  expect_failure(&im, 1, 0, 0, &rect, BBC_ERROR_INVALID_ARGUMENT, "max_size");
  expect_failure(&im, 1, 0, 48, &rect, BBC_ERROR_INVALID_ARGUMENT, "max_size");
  expect_failure(&im, 1, 0, -64, &rect, BBC_ERROR_INVALID_ARGUMENT, "max_size");
  bbc_image empty = {0, 4, im.rgba};
  expect_failure(&empty, 1, 0, 64, &rect, BBC_ERROR_INVALID_ARGUMENT, "image 0");
  bbc_image no_pixels[2] = {im, {2, 2, NULL}};
  bbc_atlas_rect rects2[2];
  expect_failure(no_pixels, 2, 0, 64, rects2, BBC_ERROR_INVALID_ARGUMENT, "image 1");
  assert_int_equal(bbc_atlas_pack(&im, 1, 0, 64, NULL, &rect, NULL), BBC_ERROR_INVALID_ARGUMENT);
  /* Still packs with valid arguments, and max_size 1 takes a 1x1 image. */
  bbc_image atlas;
  assert_int_equal(bbc_atlas_pack(&im, 1, 0, 2, &atlas, &rect, NULL), BBC_OK);
  assert_int_equal(atlas.width, 2);
  bbc_image_free(&atlas);
  bbc_image one;
  fill(&one, 1, 1, 5, 6, 7, 8);
  assert_int_equal(bbc_atlas_pack(&one, 1, 0, 1, &atlas, &rect, NULL), BBC_OK);
  assert_rgba(atlas.rgba, 5, 6, 7, 8);
  bbc_image_free(&atlas);
  expect_failure(&one, 1, 1, 2, &rect, BBC_ERROR_OUT_OF_RANGE, "padding");
  bbc_image_free(&one);
  bbc_image_free(&im);
}

/* Our PNG encoder: what it writes decodes (stb_image) to the same texels,
 * for noise, a smooth gradient (where a filter pays), and thin images; the
 * header is PNG's; the gradient compresses to a fraction of its size. */
static void test_png_roundtrip(void **state) {
  (void)state;
  bbc__rng rng = {99};
  const int sizes[][2] = {{37, 23}, {64, 64}, {1, 1}, {1, 50}, {50, 1}, {700, 501}};
  for (int c = 0; c < 6; c++) {
    bbc_image im;
    int w = sizes[c][0], h = sizes[c][1];
    if (c == 1) {
      assert_int_equal(bbc_image_alloc(&im, w, h), BBC_OK);
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          uint8_t *p = im.rgba + 4 * ((size_t)y * w + x);
          p[0] = (uint8_t)(3 * x);
          p[1] = (uint8_t)(2 * y);
          p[2] = (uint8_t)(x + y);
          p[3] = 255;
        }
    } else {
      random_image(&im, w, h, &rng, 30);
    }
    uint8_t *png = NULL;
    size_t size = 0;
    assert_int_equal(bbc__png_encode(&im, &png, &size), BBC_OK);
    assert_true(size > 8 + 25 + 12 + 12);
    assert_memory_equal(png, "\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
    assert_memory_equal(png + size - 12, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
    bbc_image back;
    bbc_error e;
    assert_int_equal(bbc_image_load_memory(png, size, &back, &e), BBC_OK);
    assert_int_equal(back.width, w);
    assert_int_equal(back.height, h);
    assert_memory_equal(back.rgba, im.rgba, 4 * (size_t)w * h);
    if (c == 1) assert_true(size < (size_t)w * h); /* under a byte a texel */
#ifdef _OPENMP
    /* A large image goes in parts compressed at once: the same bytes
     * whatever the number of threads. */
    int was = omp_get_max_threads();
    omp_set_num_threads(1);
    uint8_t *one = NULL;
    size_t one_size = 0;
    assert_int_equal(bbc__png_encode(&im, &one, &one_size), BBC_OK);
    omp_set_num_threads(was);
    assert_int_equal(one_size, size);
    assert_memory_equal(one, png, size);
    free(one);
#endif
    free(png);
    bbc_image_free(&back);
    bbc_image_free(&im);
  }
}

/* An image whose header claims more pixels than a texture may have is
 * refused before it is decoded (fuzz_scene found one asking for 2 GB). */
static void test_huge_header_refused(void **state) {
  (void)state;
  /* PNG signature and an IHDR of 12000 x 12000 RGBA (576 MB: below stb's own
   * 1 GB limit), nothing after it */
  uint8_t png[33] = {0x89, 'P',  'N', 'G', '\r', '\n', 0x1a, '\n', 0,    0, 0,
                     13,   'I',  'H', 'D', 'R',  0,    0,    0x2e, 0xe0, 0, 0,
                     0x2e, 0xe0, 8,   6,   0,    0,    0,    0,    0,    0, 0};
  bbc_image img;
  bbc_error err;
  assert_int_equal(bbc_image_load_memory(png, sizeof png, &img, &err), BBC_ERROR_OUT_OF_RANGE);
  assert_non_null(strstr(err.message, "12000 x 12000"));
  assert_null(img.rgba);
  /* the same header at 64 x 64 is not refused for its size (its data is missing) */
  png[18] = 0;
  png[19] = 64;
  png[22] = 0;
  png[23] = 64;
  bbc_result r = bbc_image_load_memory(png, sizeof png, &img, &err);
  assert_int_not_equal(r, BBC_ERROR_OUT_OF_RANGE);
  if (r == BBC_OK) bbc_image_free(&img);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_known_sizes),
      cmocka_unit_test(test_empty),
      cmocka_unit_test(test_random_many),
      cmocka_unit_test(test_one_large_many_small),
      cmocka_unit_test(test_deterministic),
      cmocka_unit_test(test_dilation_red),
      cmocka_unit_test(test_dilation_average_and_reach),
      cmocka_unit_test(test_too_big),
      cmocka_unit_test(test_invalid_arguments),
      cmocka_unit_test(test_png_roundtrip),
      cmocka_unit_test(test_huge_header_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
