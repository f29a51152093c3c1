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
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct cell_key {
  uint64_t key;
  uint32_t point;
} cell_key;

static int key_cmp(const void *x, const void *y) {
  const cell_key *a = x, *b = y;
  if (a->key != b->key) return a->key < b->key ? -1 : 1;
  return (a->point > b->point) - (a->point < b->point);
}

static uint64_t pack(int64_t i, int64_t j, int64_t k) {
  return ((uint64_t)(i & 0x1FFFFF) << 42) | ((uint64_t)(j & 0x1FFFFF) << 21) |
         (uint64_t)(k & 0x1FFFFF);
}

/* First index of `key` in the sorted keys, n when absent. */
static size_t find_key(const cell_key *keys, size_t n, uint64_t key) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (keys[mid].key < key)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < n && keys[lo].key == key ? lo : n;
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
  cell_key *keys = malloc(n * sizeof *keys);
  if (!keys) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "point normals: out of memory");
  for (size_t v = 0; v < n; v++) {
    const double *p = m->positions + 3 * v;
    keys[v].key = pack((int64_t)floor((p[0] - m->bbox_min[0]) / h),
                       (int64_t)floor((p[1] - m->bbox_min[1]) / h),
                       (int64_t)floor((p[2] - m->bbox_min[2]) / h));
    keys[v].point = (uint32_t)v;
  }
  qsort(keys, n, sizeof *keys, key_cmp);
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
          uint64_t key = pack(c[0] + dx, c[1] + dy, c[2] + dz);
          for (size_t j = find_key(keys, n, key); j < n && keys[j].key == key; j++) {
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
  free(keys);
  return BBC_OK;
}
