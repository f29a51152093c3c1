/* image.c — RGBA8 images: allocation, decoding with stb_image, PNG output
 * with stb_image_write through an atomic file. */
#include "internal.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

bbc_result bbc_image_alloc(bbc_image *image, int width, int height) {
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

/* stb allocates with malloc (Debian's build uses the default STBI_MALLOC),
 * so the pixels can be owned directly and released with free(). */
static bbc_result take_stb_pixels(unsigned char *px, int w, int h, bbc_image *image) {
  image->rgba = px;
  image->width = w;
  image->height = h;
  return BBC_OK;
}

bbc_result bbc_image_load(const char *path, bbc_image *image, bbc_error *err) {
  memset(image, 0, sizeof *image);
  bbc_result r = bbc__check_input_file(path, err);
  if (r != BBC_OK) return r;
  int w, h, n;
  unsigned char *px = stbi_load(path, &w, &h, &n, 4);
  if (!px)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: cannot decode image: %s", path,
                     stbi_failure_reason());
  return take_stb_pixels(px, w, h, image);
}

bbc_result bbc_image_load_memory(const void *data, size_t size, bbc_image *image, bbc_error *err) {
  memset(image, 0, sizeof *image);
  if (!data || size == 0 || size > INT_MAX)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "embedded image is empty or too large");
  int w, h, n;
  unsigned char *px = stbi_load_from_memory(data, (int)size, &w, &h, &n, 4);
  if (!px)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "cannot decode embedded image: %s",
                     stbi_failure_reason());
  return take_stb_pixels(px, w, h, image);
}

static void write_to_file(void *context, void *data, int size) {
  fwrite(data, 1, (size_t)size, (FILE *)context);
}

bbc_result bbc_image_write_png(const char *path, const bbc_image *image, bbc_error *err) {
  if (!image || !image->rgba || image->width <= 0 || image->height <= 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: no image to write", path);
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, path, err);
  if (r != BBC_OK) return r;
  int ok = stbi_write_png_to_func(write_to_file, af.fp, image->width, image->height, 4, image->rgba,
                                  image->width * 4);
  if (!ok) {
    bbc__atomic_abort(&af);
    return bbc__fail(err, BBC_ERROR_IO, "%s: PNG encoding failed", path);
  }
  return bbc__atomic_commit(&af, err);
}

int bbc_image_has_transparency(const bbc_image *image) {
  if (!image || !image->rgba) return 0;
  size_t n = (size_t)image->width * (size_t)image->height;
  for (size_t i = 0; i < n; i++)
    if (image->rgba[4 * i + 3] != 255) return 1;
  return 0;
}
