/* shade.c — voxel shadowing (thesis 2.3.11): a crude, deterministic self-
 * shadowing for trees under a light straight from above. Vertices stand for
 * foliage density; each voxel is darkened by the density above it within
 * 40 % of the bounding radius, weighted down linearly with the distance. */
#include "cloud.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The k-th smallest of a[n] (k < n; a is reordered): the value sorting
 * would put at a[k], in linear time (quickselect, the middle element as
 * pivot, three-way partition): linear where a sort of a million-vertex
 * tree's shadows is n log n. */
static float kth_smallest(float *a, size_t n, size_t k) {
  size_t lo = 0, hi = n; /* the k-th lies in [lo, hi) */
  while (hi - lo > 1) {
    float p = a[lo + (hi - lo) / 2];
    size_t lt = lo, i = lo, gt = hi; /* [lo,lt) < p, [lt,i) == p, [gt,hi) > p */
    while (i < gt) {
      float x = a[i];
      if (x < p) {
        a[i++] = a[lt];
        a[lt++] = x;
      } else if (x > p) {
        a[i] = a[--gt];
        a[gt] = x;
      } else {
        i++;
      }
    }
    if (k < lt)
      hi = lt;
    else if (k >= gt)
      lo = gt;
    else
      return p;
  }
  return a[lo];
}

/* The voxel grid of 2.3.11: per voxel the vertices in it and the shadow
 * cast on it, normalised by the 95th percentile of the shadowed vertices'
 * shadows (light = 1 - (1 - ambient) * min(1, shadow / ref)). */
typedef struct shade_grid {
  double h;        /* voxel side */
  int dim[3];      /* voxels per model axis */
  int a0, a1, au;  /* the axes: a column of voxels runs along au (up) */
  uint32_t *count; /* per voxel: vertices in it */
  float *shadow;   /* per voxel */
  size_t *cell_of; /* per vertex */
  double ref;
} shade_grid;

static void shade_grid_free(shade_grid *g) {
  free(g->count);
  free(g->shadow);
  free(g->cell_of);
  memset(g, 0, sizeof *g);
}

static bbc_result shade_grid_build(const bbc_mesh *m, int voxels, int up_axis, shade_grid *g,
                                   bbc_error *err) {
  memset(g, 0, sizeof *g);
  size_t nv = m->vertex_count;
  double ext = 0;
  for (int k = 0; k < 3; k++) ext = fmax(ext, m->bbox_max[k] - m->bbox_min[k]);
  if (nv == 0 || !(ext > 0)) return BBC_OK; /* no grid: everything lit */
  double h = ext / voxels;
  size_t cells = 1;
  for (int k = 0; k < 3; k++) {
    g->dim[k] = (int)ceil((m->bbox_max[k] - m->bbox_min[k]) / h);
    if (g->dim[k] < 1) g->dim[k] = 1;
    if (g->dim[k] > voxels) g->dim[k] = voxels;
    cells *= (size_t)g->dim[k];
  }
  g->h = h;
  g->count = calloc(cells, sizeof *g->count);
  g->shadow = calloc(cells, sizeof *g->shadow);
  g->cell_of = malloc(nv * sizeof *g->cell_of);
  float *sorted = malloc(nv * sizeof *sorted);
  if (!g->count || !g->shadow || !g->cell_of || !sorted) {
    shade_grid_free(g);
    free(sorted);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "shade: out of memory for %zu voxels", cells);
  }
  /* Strides, with the up axis last so a column is contiguous. */
  g->a0 = (up_axis + 1) % 3;
  g->a1 = (up_axis + 2) % 3;
  g->au = up_axis;
  const int *dim = g->dim;
  for (size_t v = 0; v < nv; v++) {
    int c[3];
    for (int k = 0; k < 3; k++) {
      c[k] = (int)((m->positions[3 * v + k] - m->bbox_min[k]) / h);
      if (c[k] < 0) c[k] = 0;
      if (c[k] >= dim[k]) c[k] = dim[k] - 1;
    }
    g->cell_of[v] = ((size_t)c[g->a0] * dim[g->a1] + c[g->a1]) * dim[g->au] + c[g->au];
    g->count[g->cell_of[v]]++;
  }
  int reach = (int)ceil(0.4 * m->radius / h);
  if (reach < 1) reach = 1;
  size_t columns = (size_t)dim[g->a0] * dim[g->a1];
  for (size_t col = 0; col < columns; col++) {
    const uint32_t *cc = g->count + col * dim[g->au];
    float *sc = g->shadow + col * dim[g->au];
    for (int z = 0; z < dim[g->au]; z++) {
      double s = 0;
      for (int k = 1; k <= reach && z + k < dim[g->au]; k++)
        s += cc[z + k] * (1.0 - (double)k / (reach + 1));
      sc[z] = (float)s;
    }
  }
  /* The reference: the 95th percentile of the shadowed vertices' shadows. */
  size_t ns = 0;
  for (size_t v = 0; v < nv; v++)
    if (g->shadow[g->cell_of[v]] > 0) sorted[ns++] = g->shadow[g->cell_of[v]];
  g->ref = ns ? kth_smallest(sorted, ns, (size_t)(0.95 * (double)(ns - 1))) : 0;
  free(sorted);
  return BBC_OK;
}

static double voxel_light(const shade_grid *g, size_t cell, double ambient) {
  double s = g->ref > 0 ? fmin(1.0, g->shadow[cell] / g->ref) : 0.0;
  return 1.0 - (1.0 - ambient) * s;
}

static int shade_args_ok(int voxels, double ambient, int up_axis) {
  return !(voxels < 1 || voxels > 512 || up_axis < 0 || up_axis > 2 || !(ambient >= 0) ||
           ambient > 1);
}

bbc_result bbc_shade_vertices(const bbc_mesh *m, int voxels, double ambient, bbc_axis up_axis,
                              float *shade, bbc_error *err) {
  assert(m && shade);
  if (!shade_args_ok(voxels, ambient, up_axis))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "shade: voxels must be 1..512, ambient 0..1, up axis 0..2");
  shade_grid g;
  bbc_result r = shade_grid_build(m, voxels, up_axis, &g, err);
  if (r != BBC_OK) return r;
  for (size_t v = 0; v < m->vertex_count; v++)
    shade[v] = g.cell_of ? (float)voxel_light(&g, g.cell_of[v], ambient) : 1.0f;
  shade_grid_free(&g);
  return BBC_OK;
}

bbc_result bbc_shade_voxels(const bbc_mesh *m, int voxels, double ambient, bbc_axis up_axis,
                            float **boxes, size_t *count, bbc_error *err) {
  assert(m && boxes && count);
  *boxes = NULL;
  *count = 0;
  if (!shade_args_ok(voxels, ambient, up_axis))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "shade: voxels must be 1..512, ambient 0..1, up axis 0..2");
  shade_grid g;
  bbc_result r = shade_grid_build(m, voxels, up_axis, &g, err);
  if (r != BBC_OK || !g.count) return r;
  size_t cells = (size_t)g.dim[0] * g.dim[1] * g.dim[2], n = 0;
  for (size_t c = 0; c < cells; c++) n += g.count[c] > 0;
  float *b = malloc((n ? n : 1) * 4 * sizeof *b);
  if (!b) {
    shade_grid_free(&g);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "shade: out of memory");
  }
  size_t k = 0;
  for (size_t c = 0; c < cells; c++) {
    if (!g.count[c]) continue;
    /* cell index = (i0 * dim[a1] + i1) * dim[au] + iu */
    size_t iu = c % (size_t)g.dim[g.au], rest = c / (size_t)g.dim[g.au];
    size_t i1 = rest % (size_t)g.dim[g.a1], i0 = rest / (size_t)g.dim[g.a1];
    size_t idx[3];
    idx[g.a0] = i0;
    idx[g.a1] = i1;
    idx[g.au] = iu;
    for (int a = 0; a < 3; a++) b[4 * k + a] = (float)(m->bbox_min[a] + (idx[a] + 0.5) * g.h);
    b[4 * k + 3] = (float)voxel_light(&g, c, ambient);
    k++;
  }
  *boxes = b;
  *count = n;
  shade_grid_free(&g);
  return BBC_OK;
}

double bbc_shade_get_voxel_size(const bbc_mesh *m, int voxels) {
  assert(m);
  double ext = 0;
  for (int k = 0; k < 3; k++) ext = fmax(ext, m->bbox_max[k] - m->bbox_min[k]);
  return voxels > 0 ? ext / voxels : 0;
}
