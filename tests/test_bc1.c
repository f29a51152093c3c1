/* test_bc1.c — the BC1 codec (src/base/bc1.c): binary alpha kept exactly,
 * colours within what 4 bits a texel allow, sizes that are not multiples of
 * 4, the same bytes every time. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "bbc.h"

/* A smooth colour field with a binary alpha mask of blobs (like an atlas
 * of leaves); `holes` 0: opaque everywhere. */
static void leafy(bbc_image *im, int w, int h, int holes) {
  assert_int_equal(bbc_image_alloc(im, w, h), BBC_OK);
  uint32_t s = 12345;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      uint8_t *p = im->rgba + 4 * ((size_t)y * w + x);
      p[0] = (uint8_t)(60 + 120 * x / w);
      p[1] = (uint8_t)(90 + 100 * y / h);
      p[2] = (uint8_t)(40 + 40 * (x + y) / (w + h));
      s = s * 1664525u + 1013904223u;
      double blob = sin(x * 0.7) * cos(y * 0.5) + ((s >> 16) % 100) / 400.0;
      p[3] = holes && blob < 0.1 ? 0 : 255;
      if (!p[3]) p[0] = p[1] = p[2] = 0;
    }
}

static double psnr_opaque(const bbc_image *a, const bbc_image *b) {
  double se = 0;
  size_t n = 0;
  for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
    if (a->rgba[4 * i + 3] < 128) continue;
    for (int k = 0; k < 3; k++) {
      double d = (double)a->rgba[4 * i + k] - b->rgba[4 * i + k];
      se += d * d;
    }
    n += 3;
  }
  return n && se > 0 ? 10 * log10(255.0 * 255.0 / (se / n)) : 99;
}

static void round_trip(int w, int h, int holes, double min_psnr) {
  bbc_image im, back;
  leafy(&im, w, h, holes);
  size_t n = bbc_bc1_size(w, h);
  assert_int_equal(n, (size_t)((w + 3) / 4) * ((h + 3) / 4) * 8);
  uint8_t *a = malloc(n), *b = malloc(n);
  bbc_error err;
  assert_int_equal(bbc_image_encode_bc1(&im, a, &err), BBC_OK);
  assert_int_equal(bbc_image_encode_bc1(&im, b, &err), BBC_OK);
  assert_memory_equal(a, b, n); /* deterministic */
  assert_int_equal(bbc_bc1_decode(a, w, h, &back, &err), BBC_OK);
  size_t transparent = 0;
  for (size_t i = 0; i < (size_t)w * h; i++) {
    assert_int_equal(back.rgba[4 * i + 3], im.rgba[4 * i + 3]); /* the alpha, exactly */
    transparent += im.rgba[4 * i + 3] == 0;
  }
  assert_true(holes ? transparent > (size_t)w * h / 10 : transparent == 0);
  double p = psnr_opaque(&im, &back);
  if (p < min_psnr) fail_msg("%dx%d holes %d: PSNR %.1f dB < %.1f", w, h, holes, p, min_psnr);
  assert_true(bbc_image_alpha_is_binary(&back));
  bbc_image_free(&back);
  bbc_image_free(&im);
  free(a);
  free(b);
}

static void test_round_trips(void **state) {
  (void)state;
  round_trip(64, 64, 0, 38);
  round_trip(64, 64, 1, 34);
  round_trip(37, 21, 1, 34); /* partial blocks */
  round_trip(1, 1, 0, 38);
  round_trip(3, 5, 1, 24); /* its gradient crosses 120 levels in 3 texels */
}

/* A wholly transparent block decodes transparent; a one-colour block keeps
 * its colour to 565's precision. */
static void test_special_blocks(void **state) {
  (void)state;
  bbc_image im, back;
  assert_int_equal(bbc_image_alloc(&im, 8, 4), BBC_OK);
  for (int i = 0; i < 32; i++) {
    uint8_t *p = im.rgba + 4 * i;
    int left = (i % 8) < 4;
    p[0] = left ? 0 : 200;
    p[1] = left ? 0 : 100;
    p[2] = left ? 0 : 50;
    p[3] = left ? 0 : 255;
  }
  uint8_t blocks[16];
  bbc_error err;
  assert_int_equal(bbc_image_encode_bc1(&im, blocks, &err), BBC_OK);
  assert_int_equal(bbc_bc1_decode(blocks, 8, 4, &back, &err), BBC_OK);
  for (int i = 0; i < 32; i++) {
    const uint8_t *p = back.rgba + 4 * i;
    if ((i % 8) < 4) {
      assert_int_equal(p[3], 0);
    } else {
      assert_int_equal(p[3], 255);
      assert_true(abs(p[0] - 200) <= 4 && abs(p[1] - 100) <= 2 && abs(p[2] - 50) <= 4);
    }
  }
  assert_int_equal(bbc_image_alpha_is_binary(&im), 1);
  im.rgba[3] = 7;
  assert_int_equal(bbc_image_alpha_is_binary(&im), 0);
  bbc_image_free(&back);
  bbc_image_free(&im);
}

/* A mask with softened edges (softalpha) is told from a real alpha ramp
 * and made binary again at 128. */
static void test_soft_mask(void **state) {
  (void)state;
  bbc_image im;
  assert_int_equal(bbc_image_alloc(&im, 4, 1), BBC_OK);
  const uint8_t a[4] = {0, 50, 205, 255};
  for (int i = 0; i < 4; i++) im.rgba[4 * i + 3] = a[i];
  assert_int_equal(bbc_image_alpha_is_soft_mask(&im), 1);
  assert_int_equal(bbc_image_alpha_is_binary(&im), 0);
  im.rgba[4 * 1 + 3] = 128; /* a ramp's middle */
  assert_int_equal(bbc_image_alpha_is_soft_mask(&im), 0);
  im.rgba[4 * 1 + 3] = 50;
  bbc_image_alpha_binarise(&im);
  const uint8_t b[4] = {0, 0, 255, 255};
  for (int i = 0; i < 4; i++) assert_int_equal(im.rgba[4 * i + 3], b[i]);
  assert_int_equal(bbc_image_alpha_is_soft_mask(&im), 0); /* binary: nothing soft */
  bbc_image_free(&im);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trips),
      cmocka_unit_test(test_special_blocks),
      cmocka_unit_test(test_soft_mask),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
