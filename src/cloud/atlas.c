/* atlas.c — packing the billboard textures of a cloud into one
 * power-of-two texture. Thesis 3.3 did this with an external tool
 * (AVEsplitter); one atlas per cloud means one texture bind and one draw
 * call per tree.
 *
 * Packing: stb_rect_pack's skyline packer (Debian's libstb) on rectangles
 * grown by `padding`, tried on atlas sizes of ascending area (1x1, 2x1,
 * 1x2, 2x2, 4x2, 2x4, ...; square or 2:1, the wide 2:1 shape before the tall
 * one) up to max_size x max_size; the first size where everything fits
 * wins. Each image's rectangle is grown by `padding` to the right and
 * bottom and the packing area is shrunk by `padding` on the right and
 * bottom, then everything is shifted by `padding`: this leaves at least
 * `padding` texels between any two images and between any image and the
 * atlas border.
 *
 * Dilation ("colour bleeding"): bilinear filtering and mipmaps average
 * texels across the edge of an alpha mask; with straight alpha the RGB of
 * transparent texels is then blended in and, being usually black, darkens
 * the silhouettes. So transparent texels (alpha 0) near opaque ones
 * (alpha > 0) take the mean RGB of their already coloured 8-neighbours,
 * ring by ring, for max(padding, 4) rings. Alpha never changes. Transparent
 * texels out of reach keep what they had: 0 between images, the image's own
 * RGB inside an image.
 *
 * count == 0 gives a 1x1 transparent atlas and BBC_OK (a cloud without
 * billboards still has a valid, if empty, texture); rects may then be NULL.
 *
 * Deterministic: the packing order is fixed here (height, then width
 * descending, ties by index) and each rectangle is handed to stb_rect_pack
 * on its own, so the result never depends on qsort's order for ties; the
 * dilation of a texel depends only on the previous ring. No global state. */
#include "cloud.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_rect_pack.h>

/* Largest power of two an int holds: the atlas side never exceeds it. */
#define ATLAS_MAX_SIDE (1 << 30)

static int is_pow2(int v) {
  return v > 0 && (v & (v - 1)) == 0;
}

/* Packing order: tall images first (the skyline heuristic wastes least
 * space that way), then wide ones, then by index so equal sizes never
 * depend on the sort algorithm. */
typedef struct order_key {
  int w, h;
  size_t index;
} order_key;

static int order_compare(const void *a, const void *b) {
  const order_key *p = a, *q = b;
  if (p->h != q->h) return p->h > q->h ? -1 : 1;
  if (p->w != q->w) return p->w > q->w ? -1 : 1;
  return p->index < q->index ? -1 : p->index > q->index;
}

/* Tries one atlas size. Returns 1 when every rectangle fits; their
 * positions are then in rr[]. `nodes` holds count + 1 entries: the skyline
 * gains at most one node per packed rectangle, so with
 * allow_out_of_mem the packer never quantizes widths and never runs out. */
static int try_pack(const order_key *order, stbrp_rect *rr, size_t count, int width, int height,
                    int padding, stbrp_node *nodes) {
  if (width - padding <= 0 || height - padding <= 0) return 0;
  stbrp_context ctx;
  stbrp_init_target(&ctx, width - padding, height - padding, nodes, (int)(count + 1));
  stbrp_setup_allow_out_of_mem(&ctx, 1);
  for (size_t k = 0; k < count; k++) {
    stbrp_rect *r = &rr[order[k].index];
    r->id = (int)k;
    r->w = order[k].w + padding;
    r->h = order[k].h + padding;
    /* One rectangle per call: stb sorts a batch with qsort, whose order for
     * equal sizes is not specified; one at a time keeps ours. */
    if (!stbrp_pack_rects(&ctx, r, 1)) return 0;
  }
  return 1;
}

/* One ring of dilation. `state` per texel: 0 = not coloured, 1 = coloured
 * (opaque, or dilated in an earlier ring), 2 = in this ring. `ring` lists
 * this ring's texels (state 2); each takes the rounded mean RGB of its
 * coloured 8-neighbours. Only state-1 texels are read, so the order in
 * which the ring is processed does not matter. */
static void dilate_ring(uint8_t *rgba, uint8_t *state, int width, int height, const size_t *ring,
                        size_t ring_count) {
  /* The ring's texels are independent: any split over threads. */
#pragma omp parallel for schedule(static) if (ring_count > 16384)
  for (size_t k = 0; k < ring_count; k++) {
    size_t i = ring[k];
    int x = (int)(i % (size_t)width), y = (int)(i / (size_t)width);
    unsigned sum[3] = {0, 0, 0}, n = 0;
    for (int dy = -1; dy <= 1; dy++) {
      int yy = y + dy;
      if (yy < 0 || yy >= height) continue;
      for (int dx = -1; dx <= 1; dx++) {
        int xx = x + dx;
        if (xx < 0 || xx >= width || (dx == 0 && dy == 0)) continue;
        size_t j = (size_t)yy * (size_t)width + (size_t)xx;
        if (state[j] != 1) continue;
        for (int c = 0; c < 3; c++) sum[c] += rgba[j * 4 + (size_t)c];
        n++;
      }
    }
    /* n > 0: a texel joins a ring only next to a coloured one. */
    for (int c = 0; c < 3; c++) rgba[i * 4 + (size_t)c] = (uint8_t)((sum[c] + n / 2) / n);
  }
  for (size_t k = 0; k < ring_count; k++) state[ring[k]] = 1;
}

/* Appends the uncoloured 8-neighbours of texel i to `next` (marking them
 * state 2 so that each is listed once). */
static size_t collect_neighbours(uint8_t *state, int width, int height, size_t i, size_t *next,
                                 size_t n) {
  int x = (int)(i % (size_t)width), y = (int)(i / (size_t)width);
  for (int dy = -1; dy <= 1; dy++) {
    int yy = y + dy;
    if (yy < 0 || yy >= height) continue;
    for (int dx = -1; dx <= 1; dx++) {
      int xx = x + dx;
      if (xx < 0 || xx >= width) continue;
      size_t j = (size_t)yy * (size_t)width + (size_t)xx;
      if (state[j] != 0) continue;
      state[j] = 2;
      next[n++] = j;
    }
  }
  return n;
}

/* Colour bleeding over the whole atlas, `rings` rings outward from the
 * texels with alpha > 0. Returns BBC_ERROR_OUT_OF_MEMORY or BBC_OK. */
static bbc_result dilate(bbc_image *atlas, int rings) {
  size_t total = (size_t)atlas->width * (size_t)atlas->height;
  uint8_t *state = malloc(total);
  if (!state) return BBC_ERROR_OUT_OF_MEMORY;
  for (size_t i = 0; i < total; i++) state[i] = atlas->rgba[i * 4 + 3] > 0;

  /* First ring: a full scan. Later rings: neighbours of the previous one,
   * so the cost follows the dilated band, not rings x atlas area. */
  size_t cap = 1024, n = 0;
  size_t *ring = malloc(cap * sizeof *ring);
  size_t *next = NULL;
  if (!ring) goto oom;
  for (size_t i = 0; i < total; i++) {
    if (state[i] != 1) continue;
    if (cap - n < 8) {
      size_t *grown = realloc(ring, 2 * cap * sizeof *ring);
      if (!grown) goto oom;
      ring = grown;
      cap *= 2;
    }
    n = collect_neighbours(state, atlas->width, atlas->height, i, ring, n);
  }
  size_t next_cap = 1024;
  next = malloc(next_cap * sizeof *next);
  if (!next) goto oom;
  for (int r = 0; r < rings && n > 0; r++) {
    dilate_ring(atlas->rgba, state, atlas->width, atlas->height, ring, n);
    if (r + 1 == rings) break;
    size_t m = 0;
    for (size_t k = 0; k < n; k++) {
      if (next_cap - m < 8) {
        size_t *grown = realloc(next, 2 * next_cap * sizeof *next);
        if (!grown) goto oom;
        next = grown;
        next_cap *= 2;
      }
      m = collect_neighbours(state, atlas->width, atlas->height, ring[k], next, m);
    }
    size_t *t = ring;
    ring = next;
    next = t;
    size_t tc = cap;
    cap = next_cap;
    next_cap = tc;
    n = m;
  }
  free(next);
  free(ring);
  free(state);
  return BBC_OK;
oom:
  free(next);
  free(ring);
  free(state);
  return BBC_ERROR_OUT_OF_MEMORY;
}

/* Validates the arguments; BBC_OK or an error with a message. */
static bbc_result check_args(const bbc_image *images, size_t count, int padding, int max_size,
                             const bbc_atlas_rect *rects, bbc_error *err) {
  if (count > 0 && !images)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "atlas: %zu images but no image array",
                     count);
  if (count > 0 && !rects)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "atlas: %zu images but no rect array", count);
  if (padding < 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "atlas: padding %d is negative", padding);
  if (!is_pow2(max_size) || max_size > ATLAS_MAX_SIDE)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "atlas: max_size %d is not a power of two between 1 and %d", max_size,
                     ATLAS_MAX_SIDE);
  if (count > (size_t)INT32_MAX - 1)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "atlas: %zu images are too many", count);
  for (size_t i = 0; i < count; i++)
    if (images[i].width <= 0 || images[i].height <= 0 || !images[i].rgba)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "atlas: image %zu is empty (%dx%d)", i,
                       images[i].width, images[i].height);
  return BBC_OK;
}

/* Cheap lower bounds first: a side no image fits in, or an area smaller
 * than the padded images', is never tried. 64-bit arithmetic: sides up to
 * 2^30 plus padding do not overflow. An image too large for max_size is
 * an error. */
static bbc_result lower_bounds(const bbc_image *images, size_t count, int padding, int max_size,
                               long long *need_w_out, long long *need_h_out,
                               unsigned long long *need_area_out, bbc_error *err) {
  long long need_w = 0, need_h = 0;
  unsigned long long need_area = 0;
  size_t widest = 0, tallest = 0;
  for (size_t i = 0; i < count; i++) {
    long long w = (long long)images[i].width + 2LL * padding;
    long long h = (long long)images[i].height + 2LL * padding;
    if (w > need_w) need_w = w, widest = i;
    if (h > need_h) need_h = h, tallest = i;
    need_area += (unsigned long long)(images[i].width + (long long)padding) *
                 (unsigned long long)(images[i].height + (long long)padding);
  }
  *need_w_out = need_w;
  *need_h_out = need_h;
  *need_area_out = need_area;
  if (need_w > max_size || need_h > max_size) {
    size_t i = need_w > max_size ? widest : tallest;
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                     "atlas: image %zu (%dx%d) with %d texels of padding does not fit in "
                     "max_size %dx%d",
                     i, images[i].width, images[i].height, padding, max_size, max_size);
  }
  return BBC_OK;
}

/* The smallest atlas size everything fits in, tried by ascending area 2^e:
 * e even -> square, e odd -> 2:1, wide first. Squares and 2:1 never share
 * an area, so "smallest area, ties square first" reduces to this order.
 * *found_w stays 0 when no size up to max_size fits. */
static void find_size(const order_key *order, stbrp_rect *rr, size_t count, int padding,
                      int max_size, long long need_w, long long need_h,
                      unsigned long long need_area, stbrp_node *nodes, int *found_w, int *found_h) {
  int log_max = 0;
  while ((1 << log_max) < max_size) log_max++;
  for (int e = 0; e <= 2 * log_max && !*found_w; e++) {
    int shapes[2][2];
    int shape_count = 0;
    if (e % 2 == 0) {
      shapes[shape_count][0] = 1 << (e / 2);
      shapes[shape_count++][1] = 1 << (e / 2);
    } else {
      shapes[shape_count][0] = 1 << (e / 2 + 1);
      shapes[shape_count++][1] = 1 << (e / 2);
      shapes[shape_count][0] = 1 << (e / 2);
      shapes[shape_count++][1] = 1 << (e / 2 + 1);
    }
    for (int s = 0; s < shape_count; s++) {
      int w = shapes[s][0], h = shapes[s][1];
      if (w > max_size || h > max_size || w < need_w || h < need_h) continue;
      unsigned long long inner =
          (unsigned long long)(w - padding) * (unsigned long long)(h - padding);
      if (inner < need_area) continue;
      if (try_pack(order, rr, count, w, h, padding, nodes)) {
        *found_w = w;
        *found_h = h;
        break;
      }
    }
  }
}

#ifndef NDEBUG
/* Whether the rectangles lie at least `padding` texels apart (the packer's
 * promise; checked for up to 4,096 of them, debug builds only). */
static int rects_apart(const bbc_atlas_rect *r, size_t n, int padding) {
  for (size_t i = 0; i < n && n <= 4096; i++)
    for (size_t j = i + 1; j < n; j++)
      if (r[i].x - padding < r[j].x + r[j].width && r[j].x < r[i].x + r[i].width + padding &&
          r[i].y - padding < r[j].y + r[j].height && r[j].y < r[i].y + r[i].height + padding)
        return 0;
  return 1;
}
#endif

/* Each image copied to its packed place (shifted by `padding`), which
 * rects[] records. */
static void place_images(const bbc_image *images, size_t count, int padding, const stbrp_rect *rr,
                         bbc_image *atlas, bbc_atlas_rect *rects) {
  for (size_t i = 0; i < count; i++) {
    const bbc_image *im = &images[i];
    bbc_atlas_rect *dst = &rects[i];
    dst->x = rr[i].x + padding;
    dst->y = rr[i].y + padding;
    dst->width = im->width;
    dst->height = im->height;
    size_t row = (size_t)im->width * 4;
    for (int y = 0; y < im->height; y++)
      memcpy(atlas->rgba + ((size_t)(dst->y + y) * (size_t)atlas->width + (size_t)dst->x) * 4,
             im->rgba + (size_t)y * row, row);
  }
}

bbc_result bbc_atlas_pack(const bbc_image *images, size_t count, int padding, int max_size,
                          bbc_image *atlas, bbc_atlas_rect *rects, bbc_error *err) {
  if (!atlas) return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "atlas: no output image");
  memset(atlas, 0, sizeof *atlas);
  bbc_result r = check_args(images, count, padding, max_size, rects, err);
  if (r != BBC_OK) return r;
  if (count == 0) {
    r = bbc_image_alloc(atlas, 1, 1);
    if (r != BBC_OK) return bbc__fail(err, r, "atlas: out of memory");
    return BBC_OK;
  }
  long long need_w, need_h;
  unsigned long long need_area;
  r = lower_bounds(images, count, padding, max_size, &need_w, &need_h, &need_area, err);
  if (r != BBC_OK) return r;

  order_key *order = malloc(count * sizeof *order);
  stbrp_rect *rr = calloc(count, sizeof *rr);
  stbrp_node *nodes = malloc((count + 1) * sizeof *nodes);
  if (!order || !rr || !nodes) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "atlas: out of memory for %zu images", count);
    goto done;
  }
  for (size_t i = 0; i < count; i++) {
    order[i].w = images[i].width;
    order[i].h = images[i].height;
    order[i].index = i;
  }
  qsort(order, count, sizeof *order, order_compare);
  int found_w = 0, found_h = 0;
  find_size(order, rr, count, padding, max_size, need_w, need_h, need_area, nodes, &found_w,
            &found_h);
  if (!found_w) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                  "atlas: %zu images need %llu texels with %d texels of padding; they do not "
                  "fit in max_size %dx%d",
                  count, need_area, padding, max_size, max_size);
    goto done;
  }

  r = bbc_image_alloc(atlas, found_w, found_h);
  if (r != BBC_OK) {
    r = bbc__fail(err, r, "atlas: out of memory for a %dx%d atlas", found_w, found_h);
    goto done;
  }
  place_images(images, count, padding, rr, atlas, rects);
  for (size_t i = 0; i < count; i++) /* every image inside the atlas, at its own size */
    assert(rects[i].x >= 0 && rects[i].y >= 0 && rects[i].width == images[i].width &&
           rects[i].height == images[i].height && rects[i].x + rects[i].width <= found_w &&
           rects[i].y + rects[i].height <= found_h);
  assert(rects_apart(rects, count, padding)); /* and none in another's padding */
  r = dilate(atlas, padding > 4 ? padding : 4);
  if (r != BBC_OK) {
    bbc_image_free(atlas);
    r = bbc__fail(err, r, "atlas: out of memory while dilating a %dx%d atlas", found_w, found_h);
  }

done:
  if (r != BBC_OK) memset(rects, 0, count * sizeof *rects);
  free(nodes);
  free(rr);
  free(order);
  return r;
}
