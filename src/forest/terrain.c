/* terrain.c — the forest's terrain (thesis 3.2.1), GL-free: which patches
 * of the heightmap to draw at which detail each frame, and the colour
 * texture with the lighting baked in and the objects' soft shadows (3.2.4).
 *
 * Level of detail: the thesis used Roettger et al. 1998, a quadtree refined
 * per frame on the CPU, triangle by triangle. On today's GPUs the same
 * continuous detail comes cheaper from CDLOD (Strugar 2010): the quadtree
 * chooses whole nodes by distance ranges that double per level, every node
 * is one shared grid mesh whose heights the vertex shader reads from the
 * heightmap, and the shader morphs odd vertices onto the coarser grid near
 * the end of a node's range, so neighbours meet without cracks and detail
 * changes without pops. The map's `roetger` scales the ranges. */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void bbc_forest_terrain_free(bbc_forest_terrain *t) {
  if (!t) return;
  for (int l = 0; l < t->levels && t->bounds; l++) free(t->bounds[l]);
  free(t->bounds);
  free(t->nodes);
  memset(t, 0, sizeof *t);
}

static int nodes_along(const bbc_forest_terrain *t, int level) {
  return t->squares / (t->leaf << level);
}

bbc_result bbc_forest_terrain_init(bbc_forest_terrain *t, const bbc_forest_world *w,
                                   bbc_error *err) {
  assert(t && w);
  memset(t, 0, sizeof *t);
  t->squares = w->width - 1;
  if (t->squares < 1 || w->depth != w->width || (t->squares & (t->squares - 1)))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "terrain: %d x %d vertices is not (2^n + 1)^2", w->width, w->depth);
  t->leaf = t->squares < BBC_FOREST_TERRAIN_LEAF ? t->squares : BBC_FOREST_TERRAIN_LEAF;
  while ((t->leaf << t->levels) <= t->squares && t->levels < 20) t->levels++;
  t->bounds = calloc((size_t)t->levels, sizeof *t->bounds);
  if (!t->bounds) goto oom;
  for (int l = 0; l < t->levels; l++) {
    int n = nodes_along(t, l), s = t->leaf << l;
    t->bounds[l] = malloc((size_t)n * n * 2 * sizeof(float));
    if (!t->bounds[l]) goto oom;
    for (int nz = 0; nz < n; nz++)
      for (int nx = 0; nx < n; nx++) {
        float lo = INFINITY, hi = -INFINITY;
        if (l == 0) {
          for (int z = nz * s; z <= (nz + 1) * s; z++)
            for (int x = nx * s; x <= (nx + 1) * s; x++) {
              float h = w->height[(size_t)z * w->width + x];
              lo = h < lo ? h : lo;
              hi = h > hi ? h : hi;
            }
        } else { /* from the four children */
          int cn = nodes_along(t, l - 1);
          for (int q = 0; q < 4; q++) {
            const float *c =
                t->bounds[l - 1] + 2 * ((size_t)(2 * nz + (q >> 1)) * cn + 2 * nx + (q & 1));
            lo = c[0] < lo ? c[0] : lo;
            hi = c[1] > hi ? c[1] : hi;
          }
        }
        t->bounds[l][2 * ((size_t)nz * n + nx)] = lo;
        t->bounds[l][2 * ((size_t)nz * n + nx) + 1] = hi;
      }
  }
  /* Every leaf drawn, plus a quarter per node above: a generous bound. */
  size_t leaves = (size_t)nodes_along(t, 0) * nodes_along(t, 0);
  t->capacity = leaves * 2 + 64;
  t->nodes = malloc(t->capacity * sizeof *t->nodes);
  if (!t->nodes) goto oom;
  return BBC_OK;
oom:
  bbc_forest_terrain_free(t);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "terrain: out of memory");
}

typedef struct sel {
  bbc_forest_terrain *t;
  const bbc_forest_world *w;
  double planes[6][4];
  const double *eye;
} sel;

static void node_box(const sel *s, int level, int nx, int nz, double lo[3], double hi[3]) {
  int n = nodes_along(s->t, level), size = s->t->leaf << level;
  const float *b = s->t->bounds[level] + 2 * ((size_t)nz * n + nx);
  lo[0] = nx * size * s->w->spacing;
  lo[2] = nz * size * s->w->spacing;
  hi[0] = (nx + 1) * size * s->w->spacing;
  hi[2] = (nz + 1) * size * s->w->spacing;
  lo[1] = b[0];
  hi[1] = b[1];
}

static int sphere_meets_box(const double c[3], double r, const double lo[3], const double hi[3]) {
  double d2 = 0;
  for (int k = 0; k < 3; k++) {
    double v = c[k] < lo[k] ? lo[k] - c[k] : c[k] > hi[k] ? c[k] - hi[k] : 0;
    d2 += v * v;
  }
  return d2 <= r * r;
}

static void add(sel *s, int x, int z, int size, int level, int quarter) {
  bbc_forest_terrain *t = s->t;
  if (t->node_count >= t->capacity) return;
  bbc_forest_terrain_node *n = &t->nodes[t->node_count++];
  n->x = x;
  n->z = z;
  n->size = size;
  n->level = level;
  n->quarter = quarter;
}

static void select_node(sel *s, int level, int nx, int nz) {
  double lo[3], hi[3];
  node_box(s, level, nx, nz, lo, hi);
  if (!bbc_forest_frustum_test_box(s->planes, lo, hi)) return;
  int size = s->t->leaf << level;
  if (level == 0 || !sphere_meets_box(s->eye, s->t->range[level - 1], lo, hi)) {
    add(s, nx * size, nz * size, size, level, -1);
    return;
  }
  for (int q = 0; q < 4; q++) {
    int cx = 2 * nx + (q & 1), cz = 2 * nz + (q >> 1);
    double clo[3], chi[3];
    node_box(s, level - 1, cx, cz, clo, chi);
    if (sphere_meets_box(s->eye, s->t->range[level - 1], clo, chi))
      select_node(s, level - 1, cx, cz);
    else if (bbc_forest_frustum_test_box(s->planes, clo, chi))
      add(s, cx * (size / 2), cz * (size / 2), size / 2, level, q);
  }
}

void bbc_forest_terrain_select(bbc_forest_terrain *t, const bbc_forest_world *w,
                               const float viewproj[16], const double eye[3], double detail) {
  assert(t && w && viewproj && eye);
  double leaf_world = t->leaf * w->spacing;
  /* 3.5 leaves at least, so neighbours differ by one level at most; every
   * change of `detail` shows (keys 1 and 2) */
  double r0 = leaf_world * (3.5 + (detail > 0 ? detail : 0) / 4);
  for (int l = 0; l < t->levels; l++) {
    t->range[l] = r0 * (double)(1u << l);
    double prev = l ? t->range[l - 1] : 0;
    t->morph_start[l] = prev + (t->range[l] - prev) * 0.7;
  }
  sel s = {t, w, {{0}}, eye};
  bbc_forest_frustum_from_matrix(viewproj, s.planes);
  t->node_count = 0;
  int root = t->levels - 1, n = nodes_along(t, root);
  for (int z = 0; z < n; z++)
    for (int x = 0; x < n; x++) select_node(&s, root, x, z);
}

bbc_result bbc_forest_terrain_bake_colour(const bbc_forest_world *w, const double light[3],
                                          const double (*shadow)[2], bbc_image *out,
                                          bbc_error *err) {
  int cw = w->width - 1, ch = w->depth - 1;
  bbc_result r = bbc_image_alloc(out, cw, ch);
  if (r != BBC_OK) return bbc__fail(err, r, "terrain colour: out of memory");
  float *lit = malloc((size_t)cw * ch * sizeof *lit);
  if (!lit) {
    bbc_image_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "terrain colour: out of memory");
  }
  double L[3] = {0, 1, 0}; /* no light: flat ground's factor everywhere (1) */
  if (light) memcpy(L, light, sizeof L);
  double ln = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  if (ln <= 0) {
    L[0] = L[2] = 0;
    L[1] = ln = 1;
  }
  for (int k = 0; k < 3; k++) L[k] /= ln;
  /* Lambert with ambient, scaled so that flat ground keeps its colour. */
  const double ambient = 0.45;
  double flat = ambient + (1 - ambient) * (L[1] > 0 ? L[1] : 0);
  double hi_h = w->height[0], lo_h = w->height[0];
  for (size_t i = 0; i < (size_t)w->width * w->depth; i++) {
    if (w->height[i] > hi_h) hi_h = w->height[i];
    if (w->height[i] < lo_h) lo_h = w->height[i];
  }
  for (int z = 0; z < ch; z++)
    for (int x = 0; x < cw; x++) {
      const float *h0 = w->height + (size_t)z * w->width + x, *h1 = h0 + w->width;
      double dx = ((h0[1] + h1[1]) - (h0[0] + h1[0])) / (2 * w->spacing);
      double dz = ((h1[0] + h1[1]) - (h0[0] + h0[1])) / (2 * w->spacing);
      double n[3] = {-dx, 1, -dz}, nl = sqrt(dx * dx + 1 + dz * dz);
      double d = (n[0] * L[0] + n[1] * L[1] + n[2] * L[2]) / nl;
      lit[(size_t)z * cw + x] =
          light ? (float)((ambient + (1 - ambient) * (d > 0 ? d : 0)) / flat) : 1.0f;
      uint8_t *p = out->rgba + 4 * ((size_t)z * cw + x);
      if (w->colour.rgba) {
        memcpy(p, w->colour.rgba + 4 * ((size_t)z * cw + x), 4);
      } else { /* grass, turning to rock where steep */
        double slope = sqrt(dx * dx + dz * dz);
        double rock = slope < 0.4 ? 0 : slope > 0.9 ? 1 : (slope - 0.4) / 0.5;
        double up = hi_h > lo_h ? (h0[0] - lo_h) / (hi_h - lo_h) : 0;
        double g[3] = {70 + 40 * up, 118 + 20 * up, 48 + 10 * up}, s[3] = {122, 116, 104};
        for (int k = 0; k < 3; k++) p[k] = (uint8_t)(g[k] * (1 - rock) + s[k] * rock);
      }
      p[3] = 255;
    }
  /* Soft shadows: a dark disc under every object that casts one. */
  for (size_t i = 0; shadow && i < w->instance_count; i++) {
    const bbc_forest_instance *in = &w->instances[i];
    double rad = shadow[in->placement][0], cut = shadow[in->placement][1];
    if (rad <= 0) continue;
    if (cut >= rad) cut = rad * 0.999;
    double cx = in->x / w->spacing, cz = in->z / w->spacing, rt = rad / w->spacing;
    int x0 = (int)floor(cx - rt), x1 = (int)ceil(cx + rt);
    int z0 = (int)floor(cz - rt), z1 = (int)ceil(cz + rt);
    for (int z = z0 < 0 ? 0 : z0; z <= z1 && z < ch; z++)
      for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < cw; x++) {
        double ddx = (x + 0.5 - cx) * w->spacing, ddz = (z + 0.5 - cz) * w->spacing;
        double dist = sqrt(ddx * ddx + ddz * ddz);
        if (dist >= rad) continue;
        double f = dist <= cut ? 1 : (rad - dist) / (rad - cut);
        lit[(size_t)z * cw + x] *= (float)(1 - 0.55 * f);
      }
  }
  for (size_t i = 0; i < (size_t)cw * ch; i++) {
    double f = lit[i] < 0.25f ? 0.25 : lit[i];
    for (int k = 0; k < 3; k++) {
      double v = out->rgba[4 * i + k] * f;
      out->rgba[4 * i + k] = (uint8_t)(v > 255 ? 255 : v + 0.5);
    }
  }
  free(lit);
  return BBC_OK;
}
