/* world.c — a forest map's world, GL-free: the terrain's heights (the
 * heightmap resampled to the thesis's (2^n+1)^2 when it is not, filtered by
 * `hmapfilter`, scaled by `heightscale` and `stretch`), its colour map
 * ((2^n)^2), and every placed object as an instance on the ground: object2d
 * where the map says, rndtree/rndtree2 at random places where the colour
 * map is green (thesis Appendix B: green > 70 and red < 2/3 green),
 * deterministically (same map, same world). */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>

void bbc_forest_world_free(bbc_forest_world *w) {
  if (!w) return;
  free(w->height);
  bbc_image_free(&w->colour);
  free(w->instances);
  memset(w, 0, sizeof *w);
}

static int is_pow2_plus1(int n) {
  return n >= 2 && ((n - 1) & (n - 2)) == 0;
}

/* Bilinear sample of a w x h float grid at (x, y) in grid units. */
static float grid_at(const float *g, int w, int h, double x, double y) {
  if (x < 0) x = 0;
  if (y < 0) y = 0;
  if (x > w - 1) x = w - 1;
  if (y > h - 1) y = h - 1;
  int x0 = (int)x, y0 = (int)y, x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
  double fx = x - x0, fy = y - y0;
  double a = g[(size_t)y0 * w + x0] * (1 - fx) + g[(size_t)y0 * w + x1] * fx;
  double b = g[(size_t)y1 * w + x0] * (1 - fx) + g[(size_t)y1 * w + x1] * fx;
  return (float)(a * (1 - fy) + b * fy);
}

/* The heightmap as 0..255 floats (16-bit images keep their precision). */
static bbc_result load_heights(const char *path, float **out, int *w, int *h, int *bits,
                               bbc_error *err) {
  bbc_result r = bbc__check_input_file(path, err);
  if (r != BBC_OK) return r;
  int n;
  if (stbi_is_16_bit(path)) {
    stbi_us *px = stbi_load_16(path, w, h, &n, 1);
    if (!px) return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: %s", path, stbi_failure_reason());
    *bits = 16;
    size_t np = (size_t)*w * *h;
    *out = malloc(np * sizeof **out);
    if (*out)
      for (size_t i = 0; i < np; i++) (*out)[i] = px[i] / 257.0f;
    stbi_image_free(px);
  } else {
    stbi_uc *px = stbi_load(path, w, h, &n, 1);
    if (!px) { /* what stb does not read (run-length BMP): through bbc_image_load, grey */
      bbc_image im;
      bbc_result r2 = bbc_image_load(path, &im, err);
      if (r2 != BBC_OK) return r2;
      *w = im.width;
      *h = im.height;
      *bits = 8;
      size_t np = (size_t)*w * *h;
      *out = malloc(np * sizeof **out);
      if (*out)
        for (size_t i = 0; i < np; i++) {
          const uint8_t *p = im.rgba + 4 * i;
          (*out)[i] = (float)((p[0] * 299 + p[1] * 587 + p[2] * 114) / 1000.0);
        }
      bbc_image_free(&im);
      if (!*out) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
      return BBC_OK;
    }
    *bits = 8;
    size_t np = (size_t)*w * *h;
    *out = malloc(np * sizeof **out);
    if (*out)
      for (size_t i = 0; i < np; i++) (*out)[i] = px[i];
    stbi_image_free(px);
  }
  if (!*out) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  return BBC_OK;
}

/* `name` relative to the map's folder (absolute names as they are). */
static void resolve(const char *folder, const char *name, char *out, size_t n) {
  if (name[0] == '/' || !folder || !folder[0])
    snprintf(out, n, "%s", name);
  else
    snprintf(out, n, "%s/%s", folder, name);
}

/* Box filter of radius r, `passes` times (hmapfilter). */
static bbc_result box_filter(float *g, int w, int h, int r, int passes) {
  if (r <= 0 || passes <= 0) return BBC_OK;
  float *tmp = malloc((size_t)w * h * sizeof *tmp);
  if (!tmp) return BBC_ERROR_OUT_OF_MEMORY;
  for (int p = 0; p < passes; p++) {
    for (int y = 0; y < h; y++) /* rows into tmp */
      for (int x = 0; x < w; x++) {
        double s = 0;
        int c = 0;
        for (int k = x - r; k <= x + r; k++)
          if (k >= 0 && k < w) {
            s += g[(size_t)y * w + k];
            c++;
          }
        tmp[(size_t)y * w + x] = (float)(s / c);
      }
    for (int y = 0; y < h; y++) /* columns back */
      for (int x = 0; x < w; x++) {
        double s = 0;
        int c = 0;
        for (int k = y - r; k <= y + r; k++)
          if (k >= 0 && k < h) {
            s += tmp[(size_t)k * w + x];
            c++;
          }
        g[(size_t)y * w + x] = (float)(s / c);
      }
  }
  free(tmp);
  return BBC_OK;
}

double bbc_forest_world_get_height(const bbc_forest_world *w, double x, double z) {
  assert(w);
  if (!w->height) return 0;
  return grid_at(w->height, w->width, w->depth, x / w->spacing, z / w->spacing);
}

int bbc_forest_world_is_green(const bbc_forest_world *w, double x, double z) {
  assert(w);
  if (!w->colour.rgba) return 1; /* no colour map: everywhere */
  int cx = (int)floor(x / w->spacing * w->colour.width / (w->width - 1));
  int cz = (int)floor(z / w->spacing * w->colour.height / (w->depth - 1));
  if (cx < 0 || cz < 0 || cx >= w->colour.width || cz >= w->colour.height) return 0;
  const uint8_t *p = w->colour.rgba + 4 * ((size_t)cz * w->colour.width + cx);
  return p[1] > 70 && 3 * (int)p[0] < 2 * (int)p[1];
}

/* A failure of the map's command at `line` (0: of the map as a whole):
 * "MAP:LINE: " before what went wrong. */
static bbc_result at_line(const bbc_forest_map *map, int line, bbc_result r, bbc_error *err) {
  if (err && map->name) {
    char prefix[320];
    if (line > 0)
      snprintf(prefix, sizeof prefix, "%.256s:%d: ", map->name, line);
    else
      snprintf(prefix, sizeof prefix, "%.256s: ", map->name);
    size_t pl = strlen(prefix), ml = strlen(err->message), cap = sizeof err->message - 1;
    if (pl + ml > cap) ml = cap - pl; /* pl <= 320 < cap */
    memmove(err->message + pl, err->message, ml);
    memcpy(err->message, prefix, pl);
    err->message[pl + ml] = 0;
  }
  return r;
}

/* The terrain's heights from the map's heightmap at `path`: resampled to
 * (2^n + 1)^2 when it is not, as the thesis's terrain algorithm needs,
 * filtered (hmapfilter), scaled (heightscale); the spacing is `stretch`. */
static bbc_result build_heights(const bbc_forest_map *map, const char *path, bbc_forest_world *w,
                                bbc_error *err) {
  float *raw = NULL;
  int rw = 0, rh = 0, bits = 8;
  bbc_result r = load_heights(path, &raw, &rw, &rh, &bits, err);
  if (r != BBC_OK) return r;
  if (rw < 2 || rh < 2) {
    free(raw);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: a heightmap needs at least 2 x 2 pixels", path);
  }
  w->heightmap_bits = bits;
  /* (2^n + 1)^2, as the thesis's terrain algorithm needs; else resampled. */
  int side = rw > rh ? rw : rh, n = 2;
  while (n + 1 < side && n < (1 << 14)) n *= 2;
  int target = n + 1;
  if (rw == rh && is_pow2_plus1(rw)) target = rw;
  w->width = w->depth = target;
  w->height = malloc((size_t)target * target * sizeof *w->height);
  if (!w->height) {
    free(raw);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  for (int y = 0; y < target; y++)
    for (int x = 0; x < target; x++)
      w->height[(size_t)y * target + x] = grid_at(raw, rw, rh, (double)x * (rw - 1) / (target - 1),
                                                  (double)y * (rh - 1) / (target - 1));
  free(raw);
  if (target != rw || target != rh)
    snprintf(w->note, sizeof w->note, "%s: %d x %d resampled to %d x %d (the thesis's 2^n+1)",
             map->hmap, rw, rh, target, target);
  if (box_filter(w->height, target, target, map->hmap_filter_radius, map->hmap_filter_passes) !=
      BBC_OK) {
    bbc_forest_world_free(w);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  for (size_t i = 0; i < (size_t)target * target; i++)
    w->height[i] = (float)(w->height[i] * map->heightscale);
  w->spacing = map->stretch;
  return BBC_OK;
}

/* The colour map at `path`: (2^n)^2 = one texel per terrain square, else
 * resampled to it (nearest texel). The world is freed on failure. */
static bbc_result build_colours(const bbc_forest_map *map, const char *path, bbc_forest_world *w,
                                bbc_error *err) {
  int target = w->width;
  bbc_image c;
  bbc_result r = bbc_image_load(path, &c, err);
  if (r != BBC_OK) {
    bbc_forest_world_free(w);
    return r;
  }
  int cs = target - 1;
  if (c.width == cs && c.height == cs) {
    w->colour = c;
  } else {
    r = bbc_image_alloc(&w->colour, cs, cs);
    if (r != BBC_OK) {
      bbc_image_free(&c);
      bbc_forest_world_free(w);
      return bbc__fail(err, r, "%s: out of memory", path);
    }
    for (int y = 0; y < cs; y++) /* nearest texel */
      for (int x = 0; x < cs; x++) {
        int sx = (int)((x + 0.5) * c.width / cs), sy = (int)((y + 0.5) * c.height / cs);
        memcpy(w->colour.rgba + 4 * ((size_t)y * cs + x), c.rgba + 4 * ((size_t)sy * c.width + sx),
               4);
      }
    size_t len = strlen(w->note);
    snprintf(w->note + len, sizeof w->note - len, "%s%s: %d x %d resampled to %d x %d",
             len ? "; " : "", map->colmap, c.width, c.height, cs, cs);
    bbc_image_free(&c);
  }
  return BBC_OK;
}

/* The share of the colour map's texels that are green (1 without one). */
static double green_fraction(const bbc_forest_world *w) {
  double fraction = 1.0;
  if (w->colour.rgba) {
    size_t g = 0, nt = (size_t)w->colour.width * w->colour.height;
    for (size_t i = 0; i < nt; i++) {
      const uint8_t *p = w->colour.rgba + 4 * i;
      g += p[1] > 70 && 3 * (int)p[0] < 2 * (int)p[1];
    }
    fraction = (double)g / (double)nt;
  }
  return fraction;
}

/* Instances: object2d where written, rndtree where green (each placement
 * from its own random stream, a bounded number of tries). The world is
 * freed on failure. */
static bbc_result place_instances(const bbc_forest_map *map, bbc_forest_world *w, bbc_error *err) {
  size_t total = 0;
  for (size_t i = 0; i < map->placement_count; i++) total += map->placements[i].count;
  if (total > 100000000u) {
    bbc_forest_world_free(w);
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "map: %zu objects (at most 100,000,000)", total);
  }
  w->instances = malloc((total ? total : 1) * sizeof *w->instances);
  if (!w->instances) {
    bbc_forest_world_free(w);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "map: out of memory for %zu objects", total);
  }
  double extent = (w->width - 1) * w->spacing;
  for (size_t i = 0; i < map->placement_count; i++) {
    const bbc_forest_placement *p = &map->placements[i];
    bbc__rng rng = {0x5EED0F0E57ull ^ ((uint64_t)(i + 1) * 0xD1B54A32D192ED03ull)};
    size_t placed = 0;
    if (p->kind == BBC_FOREST_OBJECT2D) {
      bbc_forest_instance *in = &w->instances[w->instance_count++];
      in->placement = (uint32_t)i;
      in->x = (float)p->x;
      in->z = (float)p->y;
      in->y = (float)(bbc_forest_world_get_height(w, p->x, p->y) + p->altitude);
      in->yaw_deg = (float)p->rotation_deg[1];
      in->scale = (float)p->scale;
      continue;
    }
    /* Random places on green ground; a bounded number of tries. */
    size_t tries = 0, max_tries = p->count * 64 + 1024;
    while (placed < p->count && tries < max_tries) {
      tries++;
      double x = bbc__rng_uniform(&rng) * extent, z = bbc__rng_uniform(&rng) * extent;
      double yaw = bbc__rng_uniform(&rng) * 360.0;
      if (!bbc_forest_world_is_green(w, x, z)) continue;
      bbc_forest_instance *in = &w->instances[w->instance_count++];
      in->placement = (uint32_t)i;
      in->x = (float)x;
      in->z = (float)z;
      in->y = (float)(bbc_forest_world_get_height(w, x, z) + p->altitude);
      in->yaw_deg = (float)(p->random ? yaw : p->rotation_deg[1]);
      in->scale = (float)p->scale;
      placed++;
    }
    if (placed < p->count) w->placements_short++;
  }
  return BBC_OK;
}

/* bbc_forest_world_build; *line: the map line of the command being served
 * (hmap, then colmap, then 0 for the placements). */
static bbc_result world_build(const bbc_forest_map *map, const char *folder, bbc_forest_world *w,
                              bbc_error *err, int *line) {
  memset(w, 0, sizeof *w);
  char path[4096];
  *line = map->hmap_line;
  resolve(folder, map->hmap, path, sizeof path);
  bbc_result r = build_heights(map, path, w, err);
  if (r != BBC_OK) return r;
  if (map->colmap) {
    *line = map->colmap_line;
    resolve(folder, map->colmap, path, sizeof path);
    r = build_colours(map, path, w, err);
    if (r != BBC_OK) return r;
  }
  *line = 0;
  w->green_fraction = green_fraction(w);
  return place_instances(map, w, err);
}

bbc_result bbc_forest_world_build(const bbc_forest_map *map, const char *folder,
                                  bbc_forest_world *w, bbc_error *err) {
  assert(map && w);
  int line = 0;
  bbc_result r = world_build(map, folder, w, err, &line);
  return r == BBC_OK ? r : at_line(map, line, r, err);
}
