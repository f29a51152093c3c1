/* shade.c — voxel shadowing (thesis 2.3.11): a crude, deterministic self-
 * shadowing for trees under a light straight from above. Vertices stand for
 * foliage density; each voxel is darkened by the density above it within
 * 40 % of the bounding radius, weighted down linearly with the distance. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int compare_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

bbc_result bbc_shade_vertices(const bbc_mesh *m, int voxels, double ambient, int up_axis,
                              float *shade, bbc_error *err) {
  if (voxels < 1 || voxels > 512 || up_axis < 0 || up_axis > 2 || !(ambient >= 0) || ambient > 1)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "shade: voxels must be 1..512, ambient 0..1, up axis 0..2");
  size_t nv = m->vertex_count;
  if (nv == 0) return BBC_OK;
  double ext = 0;
  for (int k = 0; k < 3; k++) ext = fmax(ext, m->bbox_max[k] - m->bbox_min[k]);
  if (!(ext > 0)) {
    for (size_t v = 0; v < nv; v++) shade[v] = 1.0f;
    return BBC_OK;
  }
  double h = ext / voxels;
  int dim[3];
  size_t cells = 1;
  for (int k = 0; k < 3; k++) {
    dim[k] = (int)ceil((m->bbox_max[k] - m->bbox_min[k]) / h);
    if (dim[k] < 1) dim[k] = 1;
    if (dim[k] > voxels) dim[k] = voxels;
    cells *= (size_t)dim[k];
  }
  uint32_t *count = calloc(cells, sizeof *count);
  float *shadow = calloc(cells, sizeof *shadow);
  size_t *cell_of = malloc(nv * sizeof *cell_of);
  float *sorted = malloc(nv * sizeof *sorted);
  if (!count || !shadow || !cell_of || !sorted) {
    free(count);
    free(shadow);
    free(cell_of);
    free(sorted);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "shade: out of memory for %zu voxels", cells);
  }
  /* Strides, with the up axis last so a column is contiguous. */
  int a0 = (up_axis + 1) % 3, a1 = (up_axis + 2) % 3, au = up_axis;
  for (size_t v = 0; v < nv; v++) {
    int c[3];
    for (int k = 0; k < 3; k++) {
      c[k] = (int)((m->positions[3 * v + k] - m->bbox_min[k]) / h);
      if (c[k] < 0) c[k] = 0;
      if (c[k] >= dim[k]) c[k] = dim[k] - 1;
    }
    cell_of[v] = ((size_t)c[a0] * dim[a1] + c[a1]) * dim[au] + c[au];
    count[cell_of[v]]++;
  }
  int reach = (int)ceil(0.4 * m->radius / h);
  if (reach < 1) reach = 1;
  size_t columns = (size_t)dim[a0] * dim[a1];
  for (size_t col = 0; col < columns; col++) {
    const uint32_t *cc = count + col * dim[au];
    float *sc = shadow + col * dim[au];
    for (int z = 0; z < dim[au]; z++) {
      double s = 0;
      for (int k = 1; k <= reach && z + k < dim[au]; k++)
        s += cc[z + k] * (1.0 - (double)k / (reach + 1));
      sc[z] = (float)s;
    }
  }
  /* The reference: the 95th percentile of the shadowed vertices' shadows. */
  size_t ns = 0;
  for (size_t v = 0; v < nv; v++)
    if (shadow[cell_of[v]] > 0) sorted[ns++] = shadow[cell_of[v]];
  qsort(sorted, ns, sizeof *sorted, compare_float);
  double ref = ns ? sorted[(size_t)(0.95 * (double)(ns - 1))] : 0;
  for (size_t v = 0; v < nv; v++) {
    double s = ref > 0 ? fmin(1.0, shadow[cell_of[v]] / ref) : 0.0;
    shade[v] = (float)(1.0 - (1.0 - ambient) * s);
  }
  free(count);
  free(shadow);
  free(cell_of);
  free(sorted);
  return BBC_OK;
}
