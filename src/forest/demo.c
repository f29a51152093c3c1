/* demo.c — a procedural landscape for `make demo`'s forest map, so that a
 * map needs nothing downloaded: hills, a ridge, a lake, meadows, forest
 * floor, rock and shore, as a heightmap and a colour map. */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static double hash2(int x, int z, uint32_t seed) {
  uint32_t h = (uint32_t)x * 374761393u + (uint32_t)z * 668265263u + seed * 2246822519u;
  h = (h ^ (h >> 13)) * 1274126177u;
  h ^= h >> 16;
  return (h & 0xFFFFFF) / (double)0x1000000;
}

static double value_noise(double x, double z, uint32_t seed) {
  int x0 = (int)floor(x), z0 = (int)floor(z);
  double fx = x - x0, fz = z - z0;
  fx = fx * fx * (3 - 2 * fx);
  fz = fz * fz * (3 - 2 * fz);
  double a = hash2(x0, z0, seed), b = hash2(x0 + 1, z0, seed);
  double c = hash2(x0, z0 + 1, seed), d = hash2(x0 + 1, z0 + 1, seed);
  return (a * (1 - fx) + b * fx) * (1 - fz) + (c * (1 - fx) + d * fx) * fz;
}

static double fbm(double x, double z, int octaves, uint32_t seed) {
  double s = 0, amp = 0.5, norm = 0;
  for (int o = 0; o < octaves; o++) {
    s += amp * value_noise(x, z, seed + (uint32_t)o * 7919u);
    norm += amp;
    x *= 2.03;
    z *= 2.03;
    amp *= 0.5;
  }
  return s / norm;
}

static double smooth(double e0, double e1, double x) {
  double t = (x - e0) / (e1 - e0);
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  return t * t * (3 - 2 * t);
}

/* Height 0..1 at map position (u, v) in 0..1. */
static double demo_height(double u, double v, uint32_t seed) {
  double h = 0.22 + 0.42 * fbm(u * 3.0, v * 3.0, 5, seed);
  h += 0.30 * smooth(0.55, 1.0, u * 0.8 + (1 - v) * 0.5) * fbm(u * 5, v * 5, 3, seed + 99);
  double du = u - 0.60, dv = v - 0.62;
  double dist = sqrt(du * du + dv * dv) * (0.8 + 0.4 * fbm(u * 6, v * 6, 2, seed + 31));
  double bowl = smooth(0.26, 0.05, dist);
  return h * (1 - bowl) + 0.10 * bowl;
}

/* Islands: the same noise, most of it under the sea, and the map's border
 * sinking so no island touches the edge. */
static double islands_height(double u, double v, uint32_t seed) {
  double base = fbm(u * 5.0, v * 5.0, 5, seed);
  double edge = fabs(u - 0.5) > fabs(v - 0.5) ? fabs(u - 0.5) : fabs(v - 0.5);
  base -= 0.3 * smooth(0.3, 0.48, edge);
  double h = 0.15 + (base - 0.54) * 1.1;
  return h < 0.02 ? 0.02 + 0.01 * fbm(u * 20, v * 20, 2, seed + 5) : h;
}

static double terrain_height(double u, double v, uint32_t seed, bbc_forest_demo_kind kind) {
  return kind == BBC_FOREST_DEMO_ISLANDS ? islands_height(u, v, seed) : demo_height(u, v, seed);
}

bbc_result bbc_forest_demo_terrain(int size, uint32_t seed, bbc_forest_demo_kind kind,
                                   bbc_image *height, bbc_image *colour, double *water_level,
                                   bbc_error *err) {
  assert(height && colour && water_level);
  memset(height, 0, sizeof *height);
  memset(colour, 0, sizeof *colour);
  if (size < 16 || size > 4096 || (size & (size - 1)))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "demo terrain: size %d is not a power of two from 16 to 4096", size);
  if (kind != BBC_FOREST_DEMO_HILLS && kind != BBC_FOREST_DEMO_ISLANDS)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "demo terrain: unknown kind %d", (int)kind);
  if (bbc_image_alloc(height, size + 1, size + 1) != BBC_OK ||
      bbc_image_alloc(colour, size, size) != BBC_OK) {
    bbc_image_free(height);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "demo terrain: out of memory");
  }
  const double water = 0.15;
  *water_level = water * 255;
  for (int z = 0; z <= size; z++)
    for (int x = 0; x <= size; x++) {
      double h = terrain_height((double)x / size, (double)z / size, seed, kind);
      uint8_t g = (uint8_t)(h < 0 ? 0 : h > 1 ? 255 : h * 255 + 0.5);
      uint8_t *p = height->rgba + 4 * ((size_t)z * (size + 1) + x);
      p[0] = p[1] = p[2] = g;
      p[3] = 255;
    }
  for (int z = 0; z < size; z++)
    for (int x = 0; x < size; x++) {
      double u = (x + 0.5) / size, v = (z + 0.5) / size, e = 1.0 / size;
      double h = terrain_height(u, v, seed, kind);
      double gx =
          (terrain_height(u + e, v, seed, kind) - terrain_height(u - e, v, seed, kind)) / (2 * e);
      double gz =
          (terrain_height(u, v + e, seed, kind) - terrain_height(u, v - e, seed, kind)) / (2 * e);
      double slope = sqrt(gx * gx + gz * gz);
      double meadow = fbm(u * 4.5, v * 4.5, 4, seed + 555);
      double grain = fbm(u * 60, v * 60, 2, seed + 777) - 0.5;
      double c[3];
      double shore = kind == BBC_FOREST_DEMO_ISLANDS ? 0.018 : 0.012;
      if (h < water + shore) { /* lake floor and shore */
        c[0] = 158;
        c[1] = 146;
        c[2] = 104;
      } else if (slope > (kind == BBC_FOREST_DEMO_ISLANDS ? 5.0 : 3.2) || h > 0.80) { /* rock */
        c[0] = 128;
        c[1] = 123;
        c[2] = 114;
      } else if (meadow > 0.57 &&
                 kind == BBC_FOREST_DEMO_HILLS) { /* meadow: too yellow for trees */
        c[0] = 150;
        c[1] = 172;
        c[2] = 82;
      } else { /* forest floor */
        c[0] = 58;
        c[1] = 104;
        c[2] = 40;
      }
      uint8_t *p = colour->rgba + 4 * ((size_t)z * size + x);
      for (int k = 0; k < 3; k++) {
        double val = c[k] * (1 + 0.18 * grain);
        p[k] = (uint8_t)(val < 0 ? 0 : val > 255 ? 255 : val + 0.5);
      }
      /* keep the vegetation rule's answer whatever the grain did */
      if (c[1] == 104 && !(p[1] > 70 && 3 * p[0] < 2 * p[1])) {
        p[0] = 58;
        p[1] = 104;
      }
      p[3] = 255;
    }
  return BBC_OK;
}
