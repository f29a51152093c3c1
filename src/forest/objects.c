/* objects.c — the forest's 3D objects each frame (thesis 3.2.3), GL-free:
 * frustum culling over a grid of cells, then discrete levels of detail by
 * distance with the thesis's blending (the next level blended fully in
 * before the previous fades out, over `fade` units each way; Wimmer et al.
 * 2002). The output is one list of draw records per (model, level), so the
 * drawing layer issues one instanced draw per model, level and component.
 * Everything is allocated once in bbc_forest_cull_init. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void bbc_forest_frustum(const float m[16], double p[6][4]) {
  /* Gribb and Hartmann: rows of the matrix (column-major m[col * 4 + row]). */
  double r[4][4];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) r[i][j] = m[j * 4 + i];
  for (int k = 0; k < 3; k++)
    for (int j = 0; j < 4; j++) {
      p[2 * k][j] = r[3][j] + r[k][j];
      p[2 * k + 1][j] = r[3][j] - r[k][j];
    }
  for (int i = 0; i < 6; i++) {
    double n = sqrt(p[i][0] * p[i][0] + p[i][1] * p[i][1] + p[i][2] * p[i][2]);
    if (n > 0)
      for (int j = 0; j < 4; j++) p[i][j] /= n;
  }
}

int bbc_forest_box_in_frustum(const double p[6][4], const double lo[3], const double hi[3]) {
  int inside = 2;
  for (int i = 0; i < 6; i++) {
    /* the box corner farthest along the plane's normal, and the nearest */
    double far = p[i][3], near = p[i][3];
    for (int k = 0; k < 3; k++) {
      far += p[i][k] * (p[i][k] >= 0 ? hi[k] : lo[k]);
      near += p[i][k] * (p[i][k] >= 0 ? lo[k] : hi[k]);
    }
    if (far < 0) return 0;
    if (near < 0) inside = 1;
  }
  return inside;
}

double bbc_forest_lod_weight(const bbc_forest_lod_model *m, size_t lod, double d) {
  if (lod >= m->lod_count) return 0;
  double lo = m->ranges[2 * lod], hi = m->ranges[2 * lod + 1], f = m->fade;
  if (f <= 0) return (d >= lo && d < hi) ? 1.0 : 0.0;
  double in = lo <= 0 ? 1.0 : (d - (lo - f)) / f; /* blends in before its range */
  double out = (hi + f - d) / f;                  /* fades out after it */
  double w = in < out ? in : out;
  return w <= 0 ? 0 : w >= 1 ? 1 : w;
}

void bbc_forest_cull_free(bbc_forest_cull *c) {
  if (!c) return;
  for (size_t i = 0; i < c->model_count; i++) free((void *)c->models[i].ranges);
  free(c->models);
  free(c->bucket_base);
  free(c->placement_models);
  free(c->cell_start);
  free(c->order);
  free(c->cell_box);
  free(c->draws);
  free(c->bucket_start);
  free(c->scratch_bucket);
  free(c->scratch);
  memset(c, 0, sizeof *c);
}

bbc_result bbc_forest_cull_init(bbc_forest_cull *c, const bbc_forest_world *w,
                                const bbc_forest_lod_model *models, size_t model_count,
                                const uint32_t (*pm)[2], size_t placement_count, bbc_error *err) {
  memset(c, 0, sizeof *c);
  c->instances = w->instances;
  c->instance_count = w->instance_count;
  c->model_count = model_count;
  c->placement_count = placement_count;
  c->models = calloc(model_count ? model_count : 1, sizeof *c->models);
  c->bucket_base = calloc(model_count + 1, sizeof *c->bucket_base);
  c->placement_models = calloc(placement_count ? placement_count : 1, sizeof *c->placement_models);
  if (!c->models || !c->bucket_base || !c->placement_models) goto oom;
  double max_radius = 0;
  for (size_t i = 0; i < model_count; i++) {
    c->models[i] = models[i];
    double *r = malloc((models[i].lod_count ? models[i].lod_count : 1) * 2 * sizeof *r);
    if (!r) goto oom;
    if (models[i].lod_count) memcpy(r, models[i].ranges, models[i].lod_count * 2 * sizeof *r);
    c->models[i].ranges = r;
    c->bucket_base[i] = c->bucket_count;
    c->bucket_count += models[i].lod_count;
  }
  c->bucket_base[model_count] = c->bucket_count;
  memcpy(c->placement_models, pm, placement_count * sizeof *pm);
  for (size_t p = 0; p < placement_count; p++)
    for (int k = 0; k < 2; k++)
      if (pm[p][k] != UINT32_MAX && pm[p][k] >= model_count)
        return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "placement %zu names model %u of %zu", p,
                         pm[p][k], model_count);

  /* Grid: about 64 cells along the longer side of the map. */
  double size_x = (w->width - 1) * w->spacing, size_z = (w->depth - 1) * w->spacing;
  double longer = size_x > size_z ? size_x : size_z;
  c->cell_size = longer > 0 ? longer / 64 : 1;
  c->cells_x = (int)ceil(size_x / c->cell_size) + 1;
  c->cells_z = (int)ceil(size_z / c->cell_size) + 1;
  size_t ncell = (size_t)c->cells_x * c->cells_z;
  c->cell_start = calloc(ncell + 1, sizeof *c->cell_start);
  c->order = malloc((c->instance_count ? c->instance_count : 1) * sizeof *c->order);
  c->cell_box = malloc(ncell * sizeof *c->cell_box);
  if (!c->cell_start || !c->order || !c->cell_box) goto oom;
  uint32_t *cell_of = malloc((c->instance_count ? c->instance_count : 1) * sizeof *cell_of);
  if (!cell_of) goto oom;
  for (size_t i = 0; i < ncell; i++) {
    for (int k = 0; k < 3; k++) {
      c->cell_box[i][k] = INFINITY;
      c->cell_box[i][3 + k] = -INFINITY;
    }
  }
  for (size_t i = 0; i < c->instance_count; i++) {
    const bbc_forest_instance *in = &w->instances[i];
    int cx = (int)floor(in->x / c->cell_size), cz = (int)floor(in->z / c->cell_size);
    cx = cx < 0 ? 0 : cx >= c->cells_x ? c->cells_x - 1 : cx;
    cz = cz < 0 ? 0 : cz >= c->cells_z ? c->cells_z - 1 : cz;
    cell_of[i] = (uint32_t)((size_t)cz * c->cells_x + cx);
    c->cell_start[cell_of[i] + 1]++;
    double rad = 0;
    if (in->placement < placement_count)
      for (int k = 0; k < 2; k++) {
        uint32_t m = pm[in->placement][k];
        if (m != UINT32_MAX && models[m].radius * in->scale > rad)
          rad = models[m].radius * in->scale;
      }
    if (rad > max_radius) max_radius = rad;
    float *b = c->cell_box[cell_of[i]];
    double pos[3] = {in->x, in->y, in->z};
    for (int k = 0; k < 3; k++) {
      if (pos[k] - rad < b[k]) b[k] = (float)(pos[k] - rad);
      if (pos[k] + rad > b[3 + k]) b[3 + k] = (float)(pos[k] + rad);
    }
  }
  for (size_t i = 0; i < ncell; i++) c->cell_start[i + 1] += c->cell_start[i];
  size_t *fill = malloc((ncell ? ncell : 1) * sizeof *fill);
  if (!fill) {
    free(cell_of);
    goto oom;
  }
  memcpy(fill, c->cell_start, ncell * sizeof *fill);
  for (size_t i = 0; i < c->instance_count; i++) c->order[fill[cell_of[i]]++] = (uint32_t)i;
  free(fill);
  free(cell_of);

  /* Each tree draws at most two levels of each of at most two models. */
  c->capacity = c->instance_count * 4;
  c->draws = malloc((c->capacity ? c->capacity : 1) * sizeof *c->draws);
  c->scratch = malloc((c->capacity ? c->capacity : 1) * sizeof *c->scratch);
  c->scratch_bucket = malloc((c->capacity ? c->capacity : 1) * sizeof *c->scratch_bucket);
  c->bucket_start = calloc(c->bucket_count + 1, sizeof *c->bucket_start);
  if (!c->draws || !c->scratch || !c->scratch_bucket || !c->bucket_start) goto oom;
  (void)max_radius;
  return BBC_OK;
oom:
  bbc_forest_cull_free(c);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "forest culling: out of memory");
}

/* One tree: the frustum test when `test` (a sphere of the largest model's
 * radius), then a record per level with a weight. */
static void emit_tree(bbc_forest_cull *c, const bbc_forest_instance *in, double planes[6][4],
                      int test, const double eye[3], double zoom, size_t *n) {
  const uint32_t *pm = c->placement_models[in->placement];
  if (test) {
    double rad = 0;
    for (int k = 0; k < 2; k++)
      if (pm[k] != UINT32_MAX && c->models[pm[k]].radius * in->scale > rad)
        rad = c->models[pm[k]].radius * in->scale;
    for (int i = 0; i < 6; i++)
      if (planes[i][0] * in->x + planes[i][1] * in->y + planes[i][2] * in->z + planes[i][3] < -rad)
        return;
  }
  double dx = in->x - eye[0], dy = in->y - eye[1], dz = in->z - eye[2];
  double d = sqrt(dx * dx + dy * dy + dz * dz) / zoom;
  int drawn = 0;
  for (int k = 0; k < 2; k++) {
    uint32_t m = pm[k];
    if (m == UINT32_MAX) continue;
    const bbc_forest_lod_model *mod = &c->models[m];
    for (size_t l = 0; l < mod->lod_count; l++) {
      double wgt = bbc_forest_lod_weight(mod, l, d);
      if (wgt <= 0 || *n >= c->capacity) continue;
      bbc_forest_draw *dr = &c->scratch[*n];
      dr->x = in->x;
      dr->y = in->y;
      dr->z = in->z;
      dr->yaw = in->yaw_deg * (float)(3.14159265358979323846 / 180.0);
      dr->scale = in->scale;
      dr->fade = (float)wgt;
      c->scratch_bucket[(*n)++] = (uint32_t)(c->bucket_base[m] + l);
      drawn = 1;
    }
  }
  c->trees_visible += drawn;
}

/* Counting sort of the n scratch records by bucket, stable: the same
 * order every run. */
static void sort_by_bucket(bbc_forest_cull *c, size_t n) {
  memset(c->bucket_start, 0, (c->bucket_count + 1) * sizeof *c->bucket_start);
  for (size_t i = 0; i < n; i++) c->bucket_start[c->scratch_bucket[i] + 1]++;
  for (size_t b = 0; b < c->bucket_count; b++) c->bucket_start[b + 1] += c->bucket_start[b];
  for (size_t i = 0; i < n; i++) {
    uint32_t b = c->scratch_bucket[i];
    /* bucket_start[b] is advanced while filling and restored below */
    c->draws[c->bucket_start[b]++] = c->scratch[i];
  }
  for (size_t b = c->bucket_count; b > 0; b--) c->bucket_start[b] = c->bucket_start[b - 1];
  c->bucket_start[0] = 0;
}

void bbc_forest_cull_run(bbc_forest_cull *c, const float viewproj[16], const double eye[3],
                         double zoom) {
  double planes[6][4];
  bbc_forest_frustum(viewproj, planes);
  if (zoom <= 0) zoom = 1;
  size_t n = 0, ncell = (size_t)c->cells_x * c->cells_z;
  c->cells_visible = c->cells_tested_per_tree = c->trees_visible = 0;
  for (size_t cell = 0; cell < ncell; cell++) {
    size_t s = c->cell_start[cell], e = c->cell_start[cell + 1];
    if (s == e) continue;
    const float *b = c->cell_box[cell];
    double lo[3] = {b[0], b[1], b[2]}, hi[3] = {b[3], b[4], b[5]};
    int vis = bbc_forest_box_in_frustum(planes, lo, hi);
    if (!vis) continue;
    c->cells_visible++;
    if (vis == 1) c->cells_tested_per_tree++;
    for (size_t j = s; j < e; j++)
      emit_tree(c, &c->instances[c->order[j]], planes, vis == 1, eye, zoom, &n);
  }
  sort_by_bucket(c, n);
}

void bbc_forest_cull_run_flat(bbc_forest_cull *c, const float viewproj[16], const double eye[3],
                              double zoom) {
  double planes[6][4];
  bbc_forest_frustum(viewproj, planes);
  if (zoom <= 0) zoom = 1;
  size_t n = 0;
  c->cells_visible = c->cells_tested_per_tree = c->trees_visible = 0;
  for (size_t i = 0; i < c->instance_count; i++)
    emit_tree(c, &c->instances[i], planes, 1, eye, zoom, &n);
  sort_by_bucket(c, n);
}
