/* cull.c — the forest's 3D objects each frame (thesis 3.2.3), GL-free:
 * frustum culling over a grid of cells (in blocks of 8 x 8), then discrete
 * levels of detail by distance with the thesis's blending (the next level
 * blended fully in before the previous fades out, over `fade` units each
 * way; Wimmer et al. 2002). The work per frame is per cell: a cell in view
 * (wholly or partly: the GPU clips the rest) whose trees all take one level
 * of a model is a range of that level's static records (uploaded once); a
 * cell across an LOD switch is a "blend" range in each level it reaches,
 * whose weights the drawing layer computes per tree from the distance
 * (bbc_forest_lod_get_weight, in the vertex shader); only cells within
 * reach of level 0 (the polygon model, near the eye) across a switch or
 * the frustum's boundary are handled tree by tree, into per-frame records. The output is, per
 * (model, level), ranges of static records and per-frame records, so the drawing layer issues two
 * multi-draws per model, level, component and material. bbc_forest_cull_run_flat does the thesis's
 * per-tree work (into per-frame records) to measure against. Everything is allocated in
 * bbc_forest_cull_build. */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The culling state (opaque in bbc_forest.h). */
struct bbc_forest_cull {
  size_t model_count;
  bbc_forest_lod_model *models;    /* copies, ranges owned */
  size_t *bucket_base;             /* per model: index of its level 0's bucket */
  size_t bucket_count;             /* sum of lod_count */
  uint32_t (*placement_models)[2]; /* per placement: model ids (UINT32_MAX = none) */
  size_t placement_count;
  size_t instance_count;
  /* grid: cells_x x cells_z cells (multiples of 8), in blocks of 8 x 8 */
  int cells_x, cells_z, blocks_x, blocks_z;
  double cell_size;
  size_t cell_count;
  float (*cell_box)[6];   /* min xyz, max xyz of the trees with their radius (empty: min > max) */
  float (*cell_reach)[6]; /* min xyz, max xyz of the trees' origins (for distances) */
  float (*block_box)[6];  /* the union of a block's cell boxes */
  /* static records: every tree once per model it uses, fade 1 */
  size_t static_count;
  bbc_forest_draw *statics;
  uint8_t *static_first;       /* 1 where the model is the tree's first component */
  uint32_t *model_cell_start;  /* model m, cell k: statics[start[m * (cell_count + 1) + k]
                                * .. start[m * (cell_count + 1) + k + 1]) */
  uint32_t *model_cell_firsts; /* model m, cell k: how many of them have static_first */
  /* per frame, ranges of statics (bbc_forest_records says what they are) */
  size_t range_capacity;
  uint32_t (*ranges)[2];
  size_t *range_start;
  size_t *range_blend;
  double eye[3], zoom; /* the last frame's */
  uint32_t (*range_scratch)[2];
  uint32_t *range_bucket;
  size_t *range_last;
  /* per frame, trees handled one by one: bucket b draws
   * draws[bucket_start[b] .. bucket_start[b + 1]) */
  size_t capacity;
  bbc_forest_draw *draws;
  size_t *bucket_start;
  uint32_t *scratch_bucket;
  bbc_forest_draw *scratch;
  /* statistics of the last frame: cells in view, (model, cell)s handled tree
   * by tree, trees whose first component is in a range or a record (cells in
   * view: some may be just outside the frustum) */
  size_t cells_visible, cells_tested_per_tree, trees_visible;
  /* occlusion (bbc_forest_cull_set_occluder; NULL: none) */
  struct bbc_forest_occluder *occluder;
  const struct bbc_forest_terrain *occluder_terrain;
  size_t cells_occluded;
};

void bbc_forest_frustum_from_matrix(const float m[16], double p[6][4]) {
  assert(m && p);
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

int bbc_forest_frustum_test_box(const double p[6][4], const double lo[3], const double hi[3]) {
  assert(p && lo && hi);
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

double bbc_forest_lod_get_weight(const bbc_forest_lod_model *m, size_t lod, double d) {
  assert(m);
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
  for (size_t i = 0; c->models && i < c->model_count; i++) free((void *)c->models[i].ranges);
  free(c->models);
  free(c->bucket_base);
  free(c->placement_models);
  free(c->cell_box);
  free(c->cell_reach);
  free(c->block_box);
  free(c->statics);
  free(c->static_first);
  free(c->model_cell_start);
  free(c->model_cell_firsts);
  free(c->ranges);
  free(c->range_start);
  free(c->range_scratch);
  free(c->range_bucket);
  free(c->range_last);
  free(c->range_blend);
  free(c->draws);
  free(c->bucket_start);
  free(c->scratch_bucket);
  free(c->scratch);
  free(c);
}

static void box_empty(float b[6]) {
  for (int k = 0; k < 3; k++) {
    b[k] = INFINITY;
    b[3 + k] = -INFINITY;
  }
}

static void box_grow(float b[6], const double lo[3], const double hi[3]) {
  for (int k = 0; k < 3; k++) {
    if (lo[k] < b[k]) b[k] = (float)lo[k];
    if (hi[k] > b[3 + k]) b[3 + k] = (float)hi[k];
  }
}

/* The cell of a position: blocks of 8 x 8 cells, numbered block by block
 * and row by row inside a block (so a block's cells are consecutive). */
static size_t cell_of(const bbc_forest_cull *c, double x, double z) {
  int cx = (int)floor(x / c->cell_size), cz = (int)floor(z / c->cell_size);
  cx = cx < 0 ? 0 : cx >= c->cells_x ? c->cells_x - 1 : cx;
  cz = cz < 0 ? 0 : cz >= c->cells_z ? c->cells_z - 1 : cz;
  return ((size_t)(cz / 8) * c->blocks_x + (size_t)(cx / 8)) * 64 + (size_t)(cz % 8) * 8 +
         (size_t)(cx % 8);
}

/* Every placement's models and every instance's placement exist, and the
 * records' count fits. */
static bbc_result check_references(const bbc_forest_world *w, size_t model_count,
                                   const uint32_t (*pm)[2], size_t placement_count,
                                   bbc_error *err) {
  for (size_t p = 0; p < placement_count; p++)
    for (int k = 0; k < 2; k++)
      if (pm[p][k] != UINT32_MAX && pm[p][k] >= model_count)
        return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "placement %zu names model %u of %zu", p,
                         pm[p][k], model_count);
  for (size_t i = 0; i < w->instance_count; i++)
    if (w->instances[i].placement >= placement_count)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "instance %zu names placement %u of %zu", i,
                       w->instances[i].placement, placement_count);
  if (w->instance_count > UINT32_MAX / 4)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "forest culling: %zu objects are too many",
                     w->instance_count);
  return BBC_OK;
}

/* Copies of the models (with their own ranges), each model's first bucket
 * (one per level), and the placements' models; 0 when out of memory. */
static int copy_models(bbc_forest_cull *c, const bbc_forest_lod_model *models, size_t model_count,
                       const uint32_t (*pm)[2], size_t placement_count) {
  c->models = calloc(model_count ? model_count : 1, sizeof *c->models);
  c->bucket_base = calloc(model_count + 1, sizeof *c->bucket_base);
  c->placement_models = calloc(placement_count ? placement_count : 1, sizeof *c->placement_models);
  if (!c->models || !c->bucket_base || !c->placement_models) return 0;
  for (size_t i = 0; i < model_count; i++) {
    c->models[i] = models[i];
    c->models[i].ranges = NULL; /* the caller's until the copy exists */
    double *r = malloc((models[i].lod_count ? models[i].lod_count : 1) * 2 * sizeof *r);
    if (!r) return 0;
    if (models[i].lod_count) memcpy(r, models[i].ranges, models[i].lod_count * 2 * sizeof *r);
    c->models[i].ranges = r;
    c->bucket_base[i] = c->bucket_count;
    c->bucket_count += models[i].lod_count;
  }
  c->bucket_base[model_count] = c->bucket_count;
  if (placement_count) memcpy(c->placement_models, pm, placement_count * sizeof *pm);
  return 1;
}

/* The grid: about 48 trees per cell, 16 to 128 cells along the longer side,
 * in whole blocks of 8 x 8; its boxes empty and its per-(model, cell) tables
 * zero. 0 when out of memory. */
static int make_grid(bbc_forest_cull *c, const bbc_forest_world *w, size_t model_count) {
  double size_x = (w->width - 1) * w->spacing, size_z = (w->depth - 1) * w->spacing;
  double longer = size_x > size_z ? size_x : size_z;
  double side = ceil(sqrt((double)w->instance_count / 48.0));
  side = side < 16 ? 16 : side > 128 ? 128 : side;
  c->cell_size = longer > 0 ? longer / side : 1;
  int nx = (int)ceil(size_x / c->cell_size), nz = (int)ceil(size_z / c->cell_size);
  c->blocks_x = (nx < 1 ? 1 : nx + 7) / 8;
  c->blocks_z = (nz < 1 ? 1 : nz + 7) / 8;
  if (c->blocks_x < 1) c->blocks_x = 1;
  if (c->blocks_z < 1) c->blocks_z = 1;
  c->cells_x = c->blocks_x * 8;
  c->cells_z = c->blocks_z * 8;
  size_t ncell = c->cell_count = (size_t)c->cells_x * c->cells_z;
  size_t nblock = (size_t)c->blocks_x * c->blocks_z;
  c->cell_box = malloc(ncell * sizeof *c->cell_box);
  c->cell_reach = malloc(ncell * sizeof *c->cell_reach);
  c->block_box = malloc(nblock * sizeof *c->block_box);
  c->model_cell_start = calloc((model_count ? model_count : 1) * (ncell + 1), sizeof(uint32_t));
  c->model_cell_firsts = calloc((model_count ? model_count : 1) * ncell, sizeof(uint32_t));
  if (!c->cell_box || !c->cell_reach || !c->block_box || !c->model_cell_start ||
      !c->model_cell_firsts)
    return 0;
  for (size_t i = 0; i < ncell; i++) {
    box_empty(c->cell_box[i]);
    box_empty(c->cell_reach[i]);
  }
  for (size_t i = 0; i < nblock; i++) box_empty(c->block_box[i]);
  return 1;
}

/* Counts the records of each (model, cell) into model_cell_start (then its
 * running sums: where each (model, cell) starts) and grows the cells' and
 * blocks' boxes; returns the records' total. */
static size_t count_records(bbc_forest_cull *c, const bbc_forest_world *w,
                            const bbc_forest_lod_model *models, size_t model_count,
                            const uint32_t (*pm)[2]) {
  size_t ncell = c->cell_count;
  uint32_t *start = c->model_cell_start;
  for (size_t i = 0; i < w->instance_count; i++) {
    const bbc_forest_instance *in = &w->instances[i];
    size_t cell = cell_of(c, in->x, in->z);
    double rad = 0;
    for (int k = 0; k < 2; k++) {
      uint32_t m = pm[in->placement][k];
      if (m == UINT32_MAX || (k == 1 && m == pm[in->placement][0])) continue;
      start[m * (ncell + 1) + cell + 1]++;
      c->static_count++;
      if (models[m].radius * in->scale > rad) rad = models[m].radius * in->scale;
    }
    double pos[3] = {in->x, in->y, in->z};
    double lo[3] = {pos[0] - rad, pos[1] - rad, pos[2] - rad};
    double hi[3] = {pos[0] + rad, pos[1] + rad, pos[2] + rad};
    box_grow(c->cell_box[cell], lo, hi);
    box_grow(c->cell_reach[cell], pos, pos);
    box_grow(c->block_box[cell / 64], lo, hi);
  }
  size_t total = 0;
  for (size_t m = 0; m < model_count; m++) {
    uint32_t *s = start + m * (ncell + 1);
    s[0] = (uint32_t)total;
    for (size_t k = 0; k < ncell; k++) {
      if (s[k + 1]) c->range_capacity += models[m].lod_count; /* a blend range per level */
      s[k + 1] += s[k];
    }
    total = s[ncell];
  }
  return total;
}

/* The static records, (model, cell) by (model, cell), each marked when it
 * is its tree's first; 0 when out of memory. */
static int place_records(bbc_forest_cull *c, const bbc_forest_world *w, size_t model_count,
                         const uint32_t (*pm)[2], size_t total) {
  size_t ncell = c->cell_count;
  c->statics = malloc((total ? total : 1) * sizeof *c->statics);
  c->static_first = malloc(total ? total : 1);
  uint32_t *fill = malloc((model_count ? model_count : 1) * (ncell + 1) * sizeof *fill);
  if (!c->statics || !c->static_first || !fill) {
    free(fill);
    return 0;
  }
  memcpy(fill, c->model_cell_start, (model_count ? model_count : 1) * (ncell + 1) * sizeof *fill);
  for (size_t i = 0; i < w->instance_count; i++) {
    const bbc_forest_instance *in = &w->instances[i];
    size_t cell = cell_of(c, in->x, in->z);
    for (int k = 0; k < 2; k++) {
      uint32_t m = pm[in->placement][k];
      if (m == UINT32_MAX || (k == 1 && m == pm[in->placement][0])) continue;
      uint32_t at = fill[m * (ncell + 1) + cell]++;
      bbc_forest_draw *d = &c->statics[at];
      d->x = in->x;
      d->y = in->y;
      d->z = in->z;
      d->yaw = in->yaw_deg * (float)(3.14159265358979323846 / 180.0);
      d->scale = in->scale;
      d->fade = 1;
      c->static_first[at] = k == 0;
      if (k == 0) c->model_cell_firsts[m * ncell + cell]++;
    }
  }
  free(fill);
  return 1;
}

/* Per frame: a range per (model, cell, level) at most; records for trees
 * one by one (the flat way): each record in at most two levels. 0 when out
 * of memory. */
static int frame_buffers(bbc_forest_cull *c) {
  c->ranges = malloc((c->range_capacity ? c->range_capacity : 1) * sizeof *c->ranges);
  c->range_scratch = malloc((c->range_capacity ? c->range_capacity : 1) * sizeof *c->range_scratch);
  c->range_bucket = malloc((c->range_capacity ? c->range_capacity : 1) * sizeof *c->range_bucket);
  c->range_start = calloc(c->bucket_count + 1, sizeof *c->range_start);
  c->range_last = malloc((c->bucket_count ? c->bucket_count : 1) * 2 * sizeof *c->range_last);
  c->range_blend = calloc(c->bucket_count + 1, sizeof *c->range_blend);
  c->capacity = c->static_count * 2;
  c->draws = malloc((c->capacity ? c->capacity : 1) * sizeof *c->draws);
  c->scratch = malloc((c->capacity ? c->capacity : 1) * sizeof *c->scratch);
  c->scratch_bucket = malloc((c->capacity ? c->capacity : 1) * sizeof *c->scratch_bucket);
  c->bucket_start = calloc(c->bucket_count + 1, sizeof *c->bucket_start);
  return c->ranges && c->range_scratch && c->range_bucket && c->range_start && c->range_last &&
         c->range_blend && c->draws && c->scratch && c->scratch_bucket && c->bucket_start;
}

bbc_result bbc_forest_cull_build(const bbc_forest_world *w, const bbc_forest_lod_model *models,
                                 size_t model_count, const uint32_t (*pm)[2],
                                 size_t placement_count, bbc_forest_cull **out, bbc_error *err) {
  assert(w && out);
  *out = NULL;
  bbc_result r = check_references(w, model_count, pm, placement_count, err);
  if (r != BBC_OK) return r;
  bbc_forest_cull *c = calloc(1, sizeof *c);
  if (!c) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "forest culling: out of memory");
  c->instance_count = w->instance_count;
  c->model_count = model_count;
  c->placement_count = placement_count;
  if (!copy_models(c, models, model_count, pm, placement_count) || !make_grid(c, w, model_count))
    goto oom;
  /* Count the records of each (model, cell), then place them. */
  size_t total = count_records(c, w, models, model_count, pm);
  if (!place_records(c, w, model_count, pm, total) || !frame_buffers(c)) goto oom;
  *out = c;
  return BBC_OK;
oom:
  bbc_forest_cull_free(c);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "forest culling: out of memory");
}

/* A box against the frustum: 0 outside, else which planes cross it (bit
 * i for plane i; 0 = wholly inside) plus 1 << 6. */
static unsigned box_planes(const double p[6][4], const float b[6], unsigned test) {
  unsigned crossing = 0;
  for (int i = 0; i < 6; i++) {
    if (!(test & (1u << i))) continue;
    double far = p[i][3], near = p[i][3];
    for (int k = 0; k < 3; k++) {
      far += p[i][k] * (p[i][k] >= 0 ? b[3 + k] : b[k]);
      near += p[i][k] * (p[i][k] >= 0 ? b[k] : b[3 + k]);
    }
    if (far < 0) return 0;
    if (near < 0) crossing |= 1u << i;
  }
  return crossing | 1u << 6;
}

/* Records i of model m one by one (the flat way): the frustum test (a
 * sphere of the model's radius), then a record per level with a weight. */
static void emit_records(bbc_forest_cull *c, size_t m, uint32_t s, uint32_t e,
                         const double planes[6][4], const double eye[3], double zoom, size_t *n) {
  const bbc_forest_lod_model *mod = &c->models[m];
  for (uint32_t i = s; i < e; i++) {
    const bbc_forest_draw *in = &c->statics[i];
    double rad = mod->radius * in->scale;
    int out = 0;
    for (int j = 0; j < 6 && !out; j++) {
      const double *q = planes[j];
      out = q[0] * in->x + q[1] * in->y + q[2] * in->z + q[3] < -rad;
    }
    if (out) continue;
    double dx = in->x - eye[0], dy = in->y - eye[1], dz = in->z - eye[2];
    double d = sqrt(dx * dx + dy * dy + dz * dz) / zoom;
    int drawn = 0;
    for (size_t l = 0; l < mod->lod_count; l++) {
      double wgt = bbc_forest_lod_get_weight(mod, l, d);
      if (wgt <= 0 || *n >= c->capacity) continue;
      bbc_forest_draw *dr = &c->scratch[*n];
      *dr = *in;
      dr->fade = (float)wgt;
      c->scratch_bucket[(*n)++] = (uint32_t)(c->bucket_base[m] + l);
      drawn = 1;
    }
    c->trees_visible += drawn && c->static_first[i];
  }
}

/* Which level of `m` every distance in [dmin, dmax] draws whole and alone:
 * the level, -1 when none draws anything there, -2 when it is mixed (a
 * switch, a blend or a partial weight lies inside). */
static int classify(const bbc_forest_lod_model *m, double dmin, double dmax) {
  int found = -1;
  double f = m->fade > 0 ? m->fade : 0;
  for (size_t l = 0; l < m->lod_count; l++) {
    double lo = m->ranges[2 * l], hi = m->ranges[2 * l + 1];
    int overlaps, whole;
    if (f > 0) {
      overlaps = (lo <= 0 || dmax > lo - f) && dmin < hi + f;
      whole = (lo <= 0 || dmin >= lo) && dmax <= hi;
    } else {
      overlaps = dmax >= lo && dmin < hi;
      whole = dmin >= lo && dmax < hi;
    }
    if (!overlaps) continue;
    if (!whole || found != -1) return -2;
    found = (int)l;
  }
  return found;
}

/* A range of static records for `bucket`, whole (blend 0) or weighted by
 * the distance (blend 1); joined to the bucket's last range of the same
 * kind when they touch. */
static void add_range(bbc_forest_cull *c, size_t bucket, int blend, uint32_t first, uint32_t count,
                      size_t *nr) {
  size_t key = 2 * bucket + (size_t)blend, last = c->range_last[key];
  if (last != SIZE_MAX && c->range_scratch[last][0] + c->range_scratch[last][1] == first) {
    c->range_scratch[last][1] += count;
    return;
  }
  c->range_scratch[*nr][0] = first;
  c->range_scratch[*nr][1] = count;
  c->range_bucket[*nr] = (uint32_t)key;
  c->range_last[key] = (*nr)++;
}

/* Counting sorts (stable: the same order every run) of the ranges and of
 * the per-frame records by bucket. */
static void sort_by_bucket(bbc_forest_cull *c, size_t n, size_t nr) {
  size_t nb = c->bucket_count;
  memset(c->bucket_start, 0, (nb + 1) * sizeof *c->bucket_start);
  for (size_t i = 0; i < n; i++) c->bucket_start[c->scratch_bucket[i] + 1]++;
  for (size_t b = 0; b < nb; b++) c->bucket_start[b + 1] += c->bucket_start[b];
  for (size_t i = 0; i < n; i++) c->draws[c->bucket_start[c->scratch_bucket[i]]++] = c->scratch[i];
  for (size_t b = nb; b > 0; b--) c->bucket_start[b] = c->bucket_start[b - 1];
  c->bucket_start[0] = 0;
  /* the ranges by key (2 x bucket + blend): whole ranges, then blend ones */
  memset(c->range_start, 0, (nb + 1) * sizeof *c->range_start);
  memset(c->range_blend, 0, (nb + 1) * sizeof *c->range_blend);
  for (size_t i = 0; i < nr; i++) {
    uint32_t key = c->range_bucket[i];
    if (key & 1)
      c->range_blend[key / 2 + 1]++;
    else
      c->range_start[key / 2 + 1]++;
  }
  size_t at = 0;
  for (size_t b = 0; b < nb; b++) { /* starts: whole ranges of b, then its blend ranges */
    size_t whole = c->range_start[b + 1], blend = c->range_blend[b + 1];
    c->range_start[b] = at;
    c->range_blend[b] = at + whole;
    at += whole + blend;
  }
  c->range_start[nb] = c->range_blend[nb] = at;
  size_t *fill = c->range_last; /* 2 per bucket, free again after the frame's ranges */
  for (size_t b = 0; b < nb; b++) {
    fill[2 * b] = c->range_start[b];
    fill[2 * b + 1] = c->range_blend[b];
  }
  for (size_t i = 0; i < nr; i++) {
    uint32_t *r = c->ranges[fill[c->range_bucket[i]]++];
    r[0] = c->range_scratch[i][0];
    r[1] = c->range_scratch[i][1];
  }
}

/* A frame's start: the statistics cleared, no ranges, the frustum's
 * planes; returns the zoom (1 when not positive). */
static double frame_begin(bbc_forest_cull *c, const float viewproj[16], double zoom,
                          double planes[6][4]) {
  c->cells_visible = c->cells_tested_per_tree = c->trees_visible = c->cells_occluded = 0;
  for (size_t b = 0; b < 2 * c->bucket_count; b++) c->range_last[b] = SIZE_MAX;
  bbc_forest_frustum_from_matrix(viewproj, planes);
  zoom = zoom <= 0 ? 1 : zoom;
  c->zoom = zoom;
  return zoom;
}

void bbc_forest_cull_run(bbc_forest_cull *c, const float viewproj[16], const double eye[3],
                         double zoom) {
  assert(c && viewproj && eye);
  double planes[6][4];
  zoom = frame_begin(c, viewproj, zoom, planes);
  memcpy(c->eye, eye, sizeof c->eye);
  size_t n = 0, nr = 0, ncell = c->cell_count, nblock = (size_t)c->blocks_x * c->blocks_z;
  int occ = c->occluder && c->occluder_terrain;
  if (occ) bbc_forest_occluder_begin(c->occluder, c->occluder_terrain, eye);
  for (size_t blk = 0; blk < nblock; blk++) {
    const float *bb = c->block_box[blk];
    if (bb[0] > bb[3]) continue;
    unsigned bvis = box_planes(planes, bb, 63);
    if (!bvis) continue;
    if (occ && bbc_forest_occluder_hides(c->occluder, bb)) {
      for (size_t cell = blk * 64; cell < blk * 64 + 64; cell++)
        c->cells_occluded += c->cell_box[cell][0] <= c->cell_box[cell][3] &&
                             box_planes(planes, c->cell_box[cell], bvis & 63 ? bvis & 63 : 0);
      continue;
    }
    for (size_t cell = blk * 64; cell < blk * 64 + 64; cell++) {
      const float *b = c->cell_box[cell];
      if (b[0] > b[3]) continue;
      /* only the planes that cross the block can cross its cells */
      unsigned vis = bvis & 63 ? box_planes(planes, b, bvis & 63) : bvis;
      if (!vis) continue;
      if (occ && bbc_forest_occluder_hides(c->occluder, b)) {
        c->cells_occluded++;
        continue;
      }
      int crossing = (vis & 63) != 0; /* the frustum's boundary crosses the cell */
      c->cells_visible++;
      /* the nearest and farthest tree origin the cell can hold */
      const float *r = c->cell_reach[cell];
      double near2 = 0, far2 = 0;
      for (int k = 0; k < 3; k++) {
        double lo = r[k] - eye[k], hi = r[3 + k] - eye[k];
        double nk = lo > 0 ? lo : hi < 0 ? -hi : 0;
        double fk = fabs(lo) > fabs(hi) ? fabs(lo) : fabs(hi);
        near2 += nk * nk;
        far2 += fk * fk;
      }
      double dmin = sqrt(near2) / zoom, dmax = sqrt(far2) / zoom;
      for (size_t m = 0; m < c->model_count; m++) {
        const uint32_t *st = c->model_cell_start + m * (ncell + 1) + cell;
        if (st[0] == st[1]) continue;
        const bbc_forest_lod_model *mod = &c->models[m];
        int cls = classify(mod, dmin, dmax);
        if (cls == -1) continue;
        /* near the eye, within reach of level 0 (the polygon model, the
         * most vertices), a cell across a switch or the frustum's boundary
         * is handled tree by tree, so that trees beyond level 0's reach or
         * outside the view do not send its vertices */
        double f = mod->fade > 0 ? mod->fade : 0;
        if ((cls == -2 || crossing) && mod->lod_count > 1 && dmin <= mod->ranges[1] + f) {
          emit_records(c, m, st[0], st[1], planes, eye, zoom, &n);
          c->cells_tested_per_tree++;
          continue;
        }
        c->trees_visible += c->model_cell_firsts[m * ncell + cell];
        if (cls >= 0) { /* one level draws every tree whole: a range */
          add_range(c, c->bucket_base[m] + (size_t)cls, 0, st[0], st[1] - st[0], &nr);
          continue;
        }
        /* across a switch: a blend range in every level the cell reaches */
        for (size_t l = 0; l < mod->lod_count; l++) {
          double lo = mod->ranges[2 * l], hi = mod->ranges[2 * l + 1];
          if ((lo <= 0 || dmax >= lo - f) && dmin <= hi + f)
            add_range(c, c->bucket_base[m] + l, 1, st[0], st[1] - st[0], &nr);
        }
      }
    }
  }
  sort_by_bucket(c, n, nr);
}

void bbc_forest_cull_run_flat(bbc_forest_cull *c, const float viewproj[16], const double eye[3],
                              double zoom) {
  assert(c && viewproj && eye);
  double planes[6][4];
  zoom = frame_begin(c, viewproj, zoom, planes);
  memcpy(c->eye, eye, sizeof c->eye);
  size_t n = 0, ncell = c->cell_count;
  for (size_t m = 0; m < c->model_count; m++) {
    const uint32_t *st = c->model_cell_start + m * (ncell + 1);
    emit_records(c, m, st[0], st[ncell], planes, eye, zoom, &n);
  }
  sort_by_bucket(c, n, 0);
}

size_t bbc_forest_cull_get_bucket_model(const bbc_forest_cull *c, size_t b, size_t *level) {
  assert(c);
  size_t m = 0;
  while (m + 1 < c->model_count && c->bucket_base[m + 1] <= b) m++;
  if (level) *level = b - c->bucket_base[m];
  return m;
}

size_t bbc_forest_cull_get_bucket_size(const bbc_forest_cull *c, size_t b) {
  assert(c);
  if (b >= c->bucket_count) return 0;
  size_t n = c->bucket_start[b + 1] - c->bucket_start[b];
  for (size_t r = c->range_start[b]; r < c->range_start[b + 1]; r++) n += c->ranges[r][1];
  return n;
}

void bbc_forest_cull_copy_bucket(const bbc_forest_cull *c, size_t b, bbc_forest_draw *out) {
  assert(c && out);
  if (b >= c->bucket_count) return;
  size_t level, m = bbc_forest_cull_get_bucket_model(c, b, &level);
  for (size_t r = c->range_start[b]; r < c->range_start[b + 1]; r++) {
    memcpy(out, c->statics + c->ranges[r][0], c->ranges[r][1] * sizeof *out);
    if (r >= c->range_blend[b]) /* weighted as the drawing layer weights them */
      for (uint32_t i = 0; i < c->ranges[r][1]; i++) {
        double dx = out[i].x - c->eye[0], dy = out[i].y - c->eye[1], dz = out[i].z - c->eye[2];
        double d = sqrt(dx * dx + dy * dy + dz * dz) / c->zoom;
        out[i].fade = (float)bbc_forest_lod_get_weight(&c->models[m], level, d);
      }
    out += c->ranges[r][1];
  }
  size_t s = c->bucket_start[b], e = c->bucket_start[b + 1];
  memcpy(out, c->draws + s, (e - s) * sizeof *out);
}

void bbc_forest_cull_set_occluder(bbc_forest_cull *c, struct bbc_forest_occluder *occluder,
                                  const struct bbc_forest_terrain *terrain) {
  assert(c);
  c->occluder = occluder;
  c->occluder_terrain = terrain;
}

void bbc_forest_cull_get_records(const bbc_forest_cull *c, bbc_forest_records *r) {
  assert(c && r);
  *r = (bbc_forest_records){
      .model_count = c->model_count,
      .models = c->models,
      .bucket_base = c->bucket_base,
      .bucket_count = c->bucket_count,
      .cell_count = c->cell_count,
      .static_count = c->static_count,
      .statics = c->statics,
      .static_first = c->static_first,
      .model_cell_start = c->model_cell_start,
      .ranges = (const uint32_t(*)[2])c->ranges,
      .range_start = c->range_start,
      .range_blend = c->range_blend,
      .draws = c->draws,
      .bucket_start = c->bucket_start,
      .eye = {c->eye[0], c->eye[1], c->eye[2]},
      .zoom = c->zoom,
      .cells_visible = c->cells_visible,
      .cells_tested_per_tree = c->cells_tested_per_tree,
      .trees_visible = c->trees_visible,
      .cells_occluded = c->cells_occluded,
  };
}
