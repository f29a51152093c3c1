/*
 * pointnormals.c — normals for a point cloud's points, where the file has
 * none: the direction of least spread of each point's neighbours
 * (principal component analysis of the points within one cell of a uniform
 * grid around it). Plane selection weighs a point by how squarely a plane
 * meets its surface (parameter `pointnormals`), as it weighs a triangle by
 * its projected area: without it, planes that slice across a scan take as
 * many points as the walls they cut (the thesis's "slicing", 2.4.5).
 * Deterministic: each point's normal depends on its neighbours only, summed
 * in index order, whatever the number of threads.
 */
#include "planes.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct cell_key {
  uint64_t key;
  uint32_t point;
} cell_key;

static uint64_t pack(int64_t i, int64_t j, int64_t k) {
  return ((uint64_t)(i & 0x1FFFFF) << 42) | ((uint64_t)(j & 0x1FFFFF) << 21) |
         (uint64_t)(k & 0x1FFFFF);
}

/* The keys sorted by key, ties in point order (they come in point order):
 * a stable radix sort on the key's bytes, skipping the bytes all keys
 * share (cell coordinates take far fewer than their 21 bits). Returns the
 * sorted array (keys or tmp). */
static cell_key *sort_keys(cell_key *keys, cell_key *tmp, size_t n) {
  size_t(*count)[256] = calloc(8, sizeof *count);
  if (!count) return NULL;
  for (size_t i = 0; i < n; i++)
    for (int b = 0; b < 8; b++) count[b][(keys[i].key >> (8 * b)) & 255]++;
  cell_key *src = keys, *dst = tmp;
  for (int b = 0; b < 8; b++) {
    if (count[b][(src[0].key >> (8 * b)) & 255] == n) continue; /* one value: order stands */
    size_t at = 0;
    for (int d = 0; d < 256; d++) {
      size_t c = count[b][d];
      count[b][d] = at;
      at += c;
    }
    for (size_t i = 0; i < n; i++) dst[count[b][(src[i].key >> (8 * b)) & 255]++] = src[i];
    cell_key *t = src;
    src = dst;
    dst = t;
  }
  free(count);
  return src;
}

/* The cells: each distinct key's run [start, end) in the sorted keys, found
 * by an open-addressing hash of the key (keys use 63 bits: all ones marks an
 * empty slot). */
typedef struct cell_run {
  uint64_t key;
  size_t start, end;
} cell_run;

typedef struct cell_table {
  cell_run *slot;
  uint64_t mask;
  int shift;
} cell_table;

static size_t cell_slot(const cell_table *t, uint64_t key) {
  return (size_t)((key * 0x9E3779B97F4A7C15ull) >> t->shift);
}

static int cell_table_build(cell_table *t, const cell_key *keys, size_t n) {
  size_t runs = 0;
  for (size_t i = 0; i < n; i++) runs += !i || keys[i].key != keys[i - 1].key;
  int bits = 4;
  while (((size_t)1 << bits) < 2 * runs) bits++;
  t->mask = ((uint64_t)1 << bits) - 1;
  t->shift = 64 - bits;
  t->slot = malloc(((size_t)1 << bits) * sizeof *t->slot);
  if (!t->slot) return 0;
  for (size_t s = 0; s <= t->mask; s++) t->slot[s].key = UINT64_MAX;
  for (size_t i = 0; i < n;) {
    size_t j = i + 1;
    while (j < n && keys[j].key == keys[i].key) j++;
    size_t s = cell_slot(t, keys[i].key);
    while (t->slot[s].key != UINT64_MAX) s = (s + 1) & t->mask;
    t->slot[s] = (cell_run){keys[i].key, i, j};
    i = j;
  }
  return 1;
}

/* The run of `key` in the sorted keys: start == end when it has no points. */
static cell_run cell_find(const cell_table *t, uint64_t key) {
  for (size_t s = cell_slot(t, key);; s = (s + 1) & t->mask) {
    if (t->slot[s].key == key) return t->slot[s];
    if (t->slot[s].key == UINT64_MAX) return (cell_run){key, 0, 0};
  }
}

bbc_result bbc_points_estimate_normals(const bbc_mesh *m, int threads, float *normals,
                                       bbc_error *err) {
  assert(m && normals);
  return bbc__points_estimate_normals_at(m, NULL, m->vertex_count, threads, normals, err);
}

bbc_result bbc__points_estimate_normals_at(const bbc_mesh *m, const uint32_t *idx, size_t count,
                                           int threads, float *normals, bbc_error *err) {
  assert(m && normals);
  size_t n = m->vertex_count;
  if (!n || !count) return BBC_OK;
  double ext[3], diag2 = 0;
  for (int k = 0; k < 3; k++) {
    ext[k] = m->bbox_max[k] - m->bbox_min[k];
    diag2 += ext[k] * ext[k];
  }
  if (!(diag2 > 0)) {
    for (size_t i = 0; i < count; i++)
      normals[3 * i] = 0, normals[3 * i + 1] = 0, normals[3 * i + 2] = 1;
    return BBC_OK;
  }
  /* Cells holding about 12 points of a surface: a scan of n points over an
   * area of about the box's two largest sides has (area / n)^(1/2) between
   * points. */
  double e[3] = {ext[0], ext[1], ext[2]};
  for (int i = 0; i < 2; i++)
    for (int j = i + 1; j < 3; j++)
      if (e[j] > e[i]) {
        double t = e[i];
        e[i] = e[j];
        e[j] = t;
      }
  double area = 2 * (e[0] * e[1] + e[0] * e[2] + e[1] * e[2]);
  double h = sqrt(12.0 * area / (double)n);
  if (!(h > 0)) h = sqrt(diag2) * 1e-3;
  cell_key *buf = malloc(n * sizeof *buf), *tmp = malloc(n * sizeof *tmp);
  if (!buf || !tmp) {
    free(buf);
    free(tmp);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "point normals: out of memory");
  }
  for (size_t v = 0; v < n; v++) {
    const double *p = m->positions + 3 * v;
    buf[v].key = pack((int64_t)floor((p[0] - m->bbox_min[0]) / h),
                      (int64_t)floor((p[1] - m->bbox_min[1]) / h),
                      (int64_t)floor((p[2] - m->bbox_min[2]) / h));
    buf[v].point = (uint32_t)v;
  }
  cell_key *keys = sort_keys(buf, tmp, n);
  /* the sort's other buffer goes before the cells' table comes (10M points:
   * 160 MB each) */
  if (keys) free(keys == buf ? tmp : buf);
  cell_table cells = {0};
  if (!keys || !cell_table_build(&cells, keys, n)) {
    if (keys) {
      free(keys);
    } else {
      free(buf);
      free(tmp);
    }
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "point normals: out of memory");
  }
  int nt = bbc__thread_count(threads);
  (void)nt;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 4096) num_threads(nt)
#endif
  for (size_t i = 0; i < count; i++) {
    size_t v = idx ? idx[i] : i;
    const double *p = m->positions + 3 * v;
    int64_t c[3];
    for (int k = 0; k < 3; k++) c[k] = (int64_t)floor((p[k] - m->bbox_min[k]) / h);
    /* the neighbours within h, in cell then index order */
    double s[3] = {0, 0, 0}, ss[3][3] = {{0}};
    size_t cnt = 0;
    for (int dz = -1; dz <= 1; dz++)
      for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
          cell_run run = cell_find(&cells, pack(c[0] + dx, c[1] + dy, c[2] + dz));
          for (size_t j = run.start; j < run.end; j++) {
            const double *q = m->positions + 3 * (size_t)keys[j].point;
            double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > h * h) continue;
            for (int a = 0; a < 3; a++) {
              s[a] += d[a];
              for (int b = 0; b < 3; b++) ss[a][b] += d[a] * d[b];
            }
            cnt++;
          }
        }
    float *o = normals + 3 * i;
    if (cnt < 3) { /* too few neighbours: no preferred direction */
      o[0] = o[1] = o[2] = 0;
      continue;
    }
    double cov[3][3];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) cov[a][b] = ss[a][b] / cnt - s[a] * s[b] / ((double)cnt * cnt);
    double nv[3];
    bbc__smallest_eigenvector(cov, nv);
    double l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    for (int k = 0; k < 3; k++) o[k] = (float)(l > 0 ? nv[k] / l : 0);
  }
  free(cells.slot);
  free(keys);
  return BBC_OK;
}
