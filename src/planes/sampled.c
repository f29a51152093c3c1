/* sampled.c — steps 1 and 2 on a sample of a large model (issue 34): the
 * sample of a mesh part (`facesample`; a point cloud's, `pointsample`, is
 * drawn in planes.c with its normals), and every face or point of a
 * sampled part given a plane of the sample's. */
#include "grid.h"
#include "select.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* A mesh part of more than 4 x `facesample` dual faces: steps 1 and 2 on
 * a sample of about facesample of them, as a point cloud on its sample;
 * select_part then gives every face its plane. The sample: one in st of
 * the faces (every st-th from st / 2), and every face larger than st
 * faces of the mean area (a wall among leaves, which a stride could miss),
 * weighed at 1 / st of its area: each sampled face stands for st faces, a
 * large one for itself. The sample's total area scales the grid's sums. */
bbc_result bbc__sample_faces(grid_part *gp, bbc_error *err) {
  size_t fs = gp->params->face_sample > 0 ? (size_t)gp->params->face_sample : 0, n = gp->nf;
  if (!fs || n / 4 <= fs) return BBC_OK;
  size_t st = (n + fs - 1) / fs;
  double mean = 0;
  for (size_t i = 0; i < n; i++) mean += gp->faces[i].area;
  mean /= (double)n;
  double big = (double)st * mean;
  size_t ns = 0, k = 0;
  for (size_t i = 0; i < n; i++) ns += gp->faces[i].area > big || i % st == st / 2;
  dual_face *sample = malloc(ns * sizeof *sample);
  if (!sample) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  double total = 0;
  for (size_t i = 0; i < n; i++) {
    if (gp->faces[i].area > big) {
      sample[k] = gp->faces[i];
      sample[k].area /= (double)st;
    } else if (i % st == st / 2) {
      sample[k] = gp->faces[i];
    } else {
      continue;
    }
    total += sample[k++].area;
  }
  gp->all = gp->faces;
  gp->all_nf = n;
  gp->faces = sample;
  gp->nf = ns;
  gp->stride = st;
  gp->total_area = total;
  return BBC_OK;
}

/* A sampled point cloud's points (gp->stride > 1) to the part's planes
 * (sr, the grid's frame; base: the first one's index in the set): each
 * point to the first plane (not a cardboard one) it is valid for, in the
 * planes' order, like the greedy select that found them; a point valid for
 * none (what the sample's planes miss of the whole lies at their slabs'
 * edges: 0.02 % of 1M points on the Scopia pine, within 1.2 eps) to the
 * nearest. Face counts from every point, areas the sample's scaled up. */
/* What a sampled part's assignment left beyond epsilon, into the set. */
static void note_beyond(bbc_planeset *set, const grid_part *gp, size_t beyond, double far) {
  if (gp->stride > set->sample_stride) set->sample_stride = gp->stride;
  set->beyond_count += beyond;
  if (far > set->beyond_max) set->beyond_max = far;
}

/* A sampled mesh's faces likewise: a face to the first plane (not a
 * cardboard one) it is valid for, else to the one whose farthest vertex is
 * nearest; face counts its triangles, areas projected, from every face. */
static void assign_faces(bbc_planeset *set, const grid_part *gp, const select_result *sr,
                         size_t base, double eps) {
  const bbc_plane *pl = sr->planes;
  size_t count = sr->plane_count;
  double tol = eps * (1 + 1e-12); /* bbc__dual_face_valid's: valid when d <= tol */
  int nt = bbc__thread_count(gp->params->threads);
  (void)nt;
  size_t beyond = 0;
  double far = 0;
#pragma omp parallel for schedule(static, 4096) num_threads(nt) if (gp->all_nf > 65536) \
    reduction(+ : beyond) reduction(max : far)
  for (size_t i = 0; i < gp->all_nf; i++) {
    const dual_face *f = &gp->all[i];
    size_t best = SIZE_MAX, near = 0;
    double near_d = HUGE_VAL;
    for (size_t k = 0; k < count && best == SIZE_MAX; k++) {
      if (pl[k].kind == BBC_PLANE_CARDBOARD) continue;
      const double *nn = pl[k].normal;
      double cc = f->c[0] * nn[0] + f->c[1] * nn[1] + f->c[2] * nn[2] - pl[k].d, d = 0;
      for (int v = 0; v < f->nv; v++) {
        double dv = fabs(cc + f->d[v][0] * nn[0] + f->d[v][1] * nn[1] + f->d[v][2] * nn[2]);
        if (dv > d) d = dv;
      }
      if (d <= tol) best = k;
      if (d < near_d) {
        near_d = d;
        near = k;
      }
    }
    if (best == SIZE_MAX) {
      beyond += f->mesh_index2 != UINT32_MAX ? 2 : 1;
      if (near_d > far) far = near_d;
    }
    uint32_t k = (uint32_t)(base + (best != SIZE_MAX ? best : near));
    set->face_plane[f->mesh_index] = k;
    if (f->mesh_index2 != UINT32_MAX) set->face_plane[f->mesh_index2] = k;
  }
  for (size_t k = base; k < base + count; k++)
    if (set->planes[k].kind != BBC_PLANE_CARDBOARD) {
      set->planes[k].face_count = 0;
      set->planes[k].area = 0;
    }
  for (size_t i = 0; i < gp->all_nf; i++) {
    const dual_face *f = &gp->all[i];
    bbc_plane *p = &set->planes[set->face_plane[f->mesh_index]];
    p->face_count += f->mesh_index2 != UINT32_MAX ? 2 : 1;
    p->area += dual_projected_area(f, p->normal);
  }
  note_beyond(set, gp, beyond, far / eps);
}

static void assign_points(bbc_planeset *set, const grid_part *gp, const select_result *sr,
                          size_t base, double eps) {
  const bbc_plane *pl = sr->planes;
  size_t count = sr->plane_count;
  double tol = eps * (1 + 1e-12);
  int nt = bbc__thread_count(gp->params->threads);
  (void)nt;
  size_t beyond = 0;
  double far = 0;
#pragma omp parallel for schedule(static, 4096) num_threads(nt) if (gp->n > 65536) \
    reduction(+ : beyond) reduction(max : far)
  for (size_t i = 0; i < gp->n; i++) {
    const float *x = gp->points + 3 * i;
    size_t best = SIZE_MAX, near = 0;
    double near_d = HUGE_VAL;
    for (size_t k = 0; k < count && best == SIZE_MAX; k++) {
      if (pl[k].kind == BBC_PLANE_CARDBOARD) continue;
      double d =
          fabs(pl[k].normal[0] * x[0] + pl[k].normal[1] * x[1] + pl[k].normal[2] * x[2] - pl[k].d);
      if (d <= tol) best = k;
      if (d < near_d) {
        near_d = d;
        near = k;
      }
    }
    if (best == SIZE_MAX) {
      beyond++;
      if (near_d > far) far = near_d;
    }
    set->face_plane[gp->tris[i]] = (uint32_t)(base + (best != SIZE_MAX ? best : near));
  }
  note_beyond(set, gp, beyond, far / eps);
  double up = (double)gp->n / (double)gp->nf;
  for (size_t k = base; k < base + count; k++) {
    set->planes[k].area *= up;
    if (set->planes[k].kind != BBC_PLANE_CARDBOARD) set->planes[k].face_count = 0;
  }
  for (size_t i = 0; i < gp->n; i++) set->planes[set->face_plane[gp->tris[i]]].face_count++;
}

/* A sampled part's faces or points (gp->stride > 1) to its planes (sr,
 * the grid's frame; base: the first one's index in the set). */
void bbc__assign_sampled(bbc_planeset *set, const grid_part *gp, const select_result *sr,
                         size_t base, double eps) {
  if (gp->all)
    assign_faces(set, gp, sr, base, eps);
  else
    assign_points(set, gp, sr, base, eps);
}
