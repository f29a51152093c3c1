/* sampled.c — steps 1 and 2 on a sample of a large model: the sample of a
 * mesh part (`facesample`; a point cloud's, `pointsample`, is drawn in
 * planes.c with its normals), and every face or point of a sampled part
 * given a plane within epsilon: one of the sample's, else one that the
 * greedy select finds for the leftovers alone (the bound holds, sampled or
 * not). */
#include "grid.h"
#include "select.h"

#include <assert.h>
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

/* What a sampled part's assignment found beyond epsilon of the sample's
 * planes, into the set. */
static void note_beyond(bbc_planeset *set, const grid_part *gp, size_t beyond, double far) {
  if (gp->stride > set->sample_stride) set->sample_stride = gp->stride;
  set->beyond_count += beyond;
  if (far > set->beyond_max) set->beyond_max = far;
}

/* The leftovers of part pi (left[0..nl-1]: faces or points within epsilon
 * of none of the sample's planes, in the part's frame) get planes of their
 * own: the greedy select on them alone, which ends when each is valid for
 * its plane (2.3.4's parachute when nothing better), its planes appended
 * to the set after the part's (set->plane_count moves on). */
static bbc_result cover_leftovers(bbc_planeset *set, const grid_part *gp, size_t pi,
                                  const dual_face *left, size_t nl, double eps, bbc_error *err) {
  if (!nl) return BBC_OK;
  const bbc_params *p = gp->params;
  double area = 0;
  for (size_t i = 0; i < nl; i++) area += left[i].area;
  dual_grid g;
  if (bbc__dual_grid_init(&g, p->res_deg, eps, gp->radius, p->up_axis, area, p->threads) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory for the grid");
  select_result sr;
  bbc_result r = bbc__dual_grid_accumulate(&g, left, NULL, nl, +1, NULL);
  if (r == BBC_OK) r = bbc__select_planes(left, nl, &g, p, eps, gp->radius, NULL, &sr);
  bbc__dual_grid_free(&g);
  if (r != BBC_OK) return bbc__fail(err, r, "plane selection failed: %s", bbc_result_string(r));
  bbc_plane *planes = realloc(set->planes, (set->plane_count + sr.plane_count) * sizeof *planes);
  if (!planes) {
    bbc__select_result_free(&sr);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  }
  set->planes = planes;
  size_t base = set->plane_count;
  for (size_t k = 0; k < sr.plane_count; k++) {
    planes[base + k] = bbc__plane_to_model(&sr.planes[k], gp, pi, base);
    planes[base + k].leftover = 1;
    if (planes[base + k].kind == BBC_PLANE_CARDBOARD) continue;
    planes[base + k].face_count = 0;
    if (!left[0].point) planes[base + k].area = 0; /* projected below; a point's: the select's */
  }
  for (size_t i = 0; i < nl; i++) {
    const dual_face *f = &left[i];
    assert(sr.face_plane[i] < sr.plane_count);
    uint32_t k = (uint32_t)(base + sr.face_plane[i]);
    bbc_plane *pl = &planes[k];
    set->face_plane[f->mesh_index] = k;
    pl->face_count++;
    if (f->mesh_index2 != UINT32_MAX) {
      set->face_plane[f->mesh_index2] = k;
      pl->face_count++;
    }
    if (!f->point) pl->area += dual_projected_area(f, pl->normal);
  }
  set->plane_count += sr.plane_count;
  set->parts[pi].plane_count += sr.plane_count;
  set->leftover_planes += sr.plane_count;
  bbc__select_result_free(&sr);
  return BBC_OK;
}

/* The signed distances of item i of a sampled part (a face of gp->all, or
 * a point) from plane pl (the grid's frame): [*lo, *hi]. */
static void item_range(const grid_part *gp, size_t i, const bbc_plane *pl, double *lo, double *hi) {
  const double *nn = pl->normal;
  if (gp->all) {
    const dual_face *f = &gp->all[i];
    double cc = f->c[0] * nn[0] + f->c[1] * nn[1] + f->c[2] * nn[2] - pl->d;
    *lo = *hi = cc + f->d[0][0] * nn[0] + f->d[0][1] * nn[1] + f->d[0][2] * nn[2];
    for (int v = 1; v < f->nv; v++) {
      double dv = cc + f->d[v][0] * nn[0] + f->d[v][1] * nn[1] + f->d[v][2] * nn[2];
      if (dv < *lo) *lo = dv;
      if (dv > *hi) *hi = dv;
    }
  } else {
    const float *x = gp->points + 3 * i;
    *lo = *hi = nn[0] * x[0] + nn[1] * x[1] + nn[2] * x[2] - pl->d;
  }
}

/* The mesh triangle or point item i of a sampled part stands for. */
static uint32_t item_index(const grid_part *gp, size_t i) {
  return gp->all ? gp->all[i].mesh_index : gp->tris[i];
}

/* Leftovers (miss[i] set) that a plane of the sample's takes by moving
 * along its normal: its items' signed distances span [lo, hi] within
 * epsilon; a leftover whose own span keeps the union within 2 epsilon
 * joins the first such plane (items in order), and each plane whose span
 * grew past epsilon is moved to its middle, where every item it holds lies
 * within epsilon again. miss[i] is cleared for those that joined; returns
 * how many of the `left` are left. */
static size_t absorb(bbc_planeset *set, const grid_part *gp, const select_result *sr, size_t base,
                     double eps, uint8_t *miss, size_t n_items, size_t left) {
  size_t count = sr->plane_count;
  if (!left || !count) return left;
  double *lo = malloc(2 * count * sizeof *lo), *hi = lo + count;
  if (!lo) return left; /* out of memory: they get planes of their own */
  for (size_t k = 0; k < count; k++) {
    lo[k] = HUGE_VAL;
    hi[k] = -HUGE_VAL;
  }
  for (size_t i = 0; i < n_items; i++) {
    if (miss[i]) continue;
    size_t k = set->face_plane[item_index(gp, i)] - base;
    double a, b;
    item_range(gp, i, &sr->planes[k], &a, &b);
    if (a < lo[k]) lo[k] = a;
    if (b > hi[k]) hi[k] = b;
  }
  double width = 2 * eps * (1 - 1e-9);
  for (size_t i = 0; i < n_items && left; i++) {
    if (!miss[i]) continue;
    for (size_t k = 0; k < count; k++) {
      if (sr->planes[k].kind == BBC_PLANE_CARDBOARD || !(hi[k] >= lo[k])) continue;
      double a, b;
      item_range(gp, i, &sr->planes[k], &a, &b);
      double l = a < lo[k] ? a : lo[k], h = b > hi[k] ? b : hi[k];
      if (h - l > width) continue;
      lo[k] = l;
      hi[k] = h;
      uint32_t pk = (uint32_t)(base + k);
      set->face_plane[item_index(gp, i)] = pk;
      if (gp->all && gp->all[i].mesh_index2 != UINT32_MAX)
        set->face_plane[gp->all[i].mesh_index2] = pk;
      miss[i] = 0;
      left--;
      break;
    }
  }
  for (size_t k = 0; k < count; k++)
    if (hi[k] >= lo[k] && (lo[k] < -eps || hi[k] > eps))
      set->planes[base + k].d += 0.5 * (lo[k] + hi[k]);
  free(lo);
  return left;
}

/* Every item of a sampled part (n: its faces or points) to the first plane
 * of the sample's (not a cardboard one) it is valid for, in the planes'
 * order like the greedy select that found them; miss[i] set for those
 * valid for none, counted (and their triangles, the farthest's distance)
 * into the set. Returns how many items missed. */
static size_t first_valid(bbc_planeset *set, const grid_part *gp, const select_result *sr,
                          size_t base, double eps, uint8_t *miss, size_t n) {
  const bbc_plane *pl = sr->planes;
  size_t count = sr->plane_count;
  double tol = eps * (1 + 1e-12); /* bbc__dual_face_valid's: valid when d <= tol */
  int nt = bbc__thread_count(gp->params->threads);
  (void)nt;
  size_t beyond = 0, nl = 0;
  double far = 0;
#pragma omp parallel for schedule(static, 4096) num_threads(nt) if (n > 65536) \
    reduction(+ : beyond, nl) reduction(max : far)
  for (size_t i = 0; i < n; i++) {
    size_t best = SIZE_MAX;
    double near_d = HUGE_VAL;
    for (size_t k = 0; k < count && best == SIZE_MAX; k++) {
      if (pl[k].kind == BBC_PLANE_CARDBOARD) continue;
      double lo, hi;
      item_range(gp, i, &pl[k], &lo, &hi);
      double d = fmax(-lo, hi);
      if (d <= tol) best = k;
      if (d < near_d) near_d = d;
    }
    int two = gp->all && gp->all[i].mesh_index2 != UINT32_MAX;
    if (best == SIZE_MAX) {
      miss[i] = 1;
      nl++;
      beyond += two ? 2 : 1;
      if (near_d > far) far = near_d;
      continue;
    }
    uint32_t k = (uint32_t)(base + best);
    set->face_plane[item_index(gp, i)] = k;
    if (two) set->face_plane[gp->all[i].mesh_index2] = k;
  }
  note_beyond(set, gp, beyond, far / eps);
  return nl;
}

/* A sampled mesh's faces (gp->stride > 1) to the part's planes (sr, the
 * grid's frame; base: the first one's index in the set): a face to the
 * first plane (not a cardboard one) it is valid for, in the planes' order
 * like the greedy select that found them; the faces valid for none (what
 * the sample's planes miss of the whole lies at their slabs' edges: 0.1 %
 * of the Scopia pine's) to planes of their own (cover_leftovers). Face
 * counts its triangles, areas projected, from every face. */
static bbc_result assign_faces(bbc_planeset *set, const grid_part *gp, size_t pi,
                               const select_result *sr, size_t base, double eps, bbc_error *err) {
  uint8_t *miss = calloc(gp->all_nf ? gp->all_nf : 1, 1);
  if (!miss) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  size_t count = sr->plane_count, nl = first_valid(set, gp, sr, base, eps, miss, gp->all_nf);
  nl = absorb(set, gp, sr, base, eps, miss, gp->all_nf, nl);
  for (size_t k = base; k < base + count; k++)
    if (set->planes[k].kind != BBC_PLANE_CARDBOARD) {
      set->planes[k].face_count = 0;
      set->planes[k].area = 0;
    }
  for (size_t i = 0; i < gp->all_nf; i++) {
    if (miss[i]) continue;
    const dual_face *f = &gp->all[i];
    bbc_plane *p = &set->planes[set->face_plane[f->mesh_index]];
    p->face_count += f->mesh_index2 != UINT32_MAX ? 2 : 1;
    p->area += dual_projected_area(f, p->normal);
  }
  dual_face *left = nl ? malloc(nl * sizeof *left) : NULL;
  bbc_result r = nl && !left
                     ? bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory")
                     : BBC_OK;
  for (size_t i = 0, j = 0; r == BBC_OK && i < gp->all_nf; i++)
    if (miss[i]) left[j++] = gp->all[i];
  free(miss);
  if (r == BBC_OK) r = cover_leftovers(set, gp, pi, left, nl, eps, err);
  free(left);
  return r;
}

/* A sampled point cloud's points likewise: a point to the first plane it
 * is valid for, the points valid for none (0.1 % of 1M points on the Scopia
 * pine) to planes of their own. Face counts from every point, areas the
 * sample's scaled up. */
static bbc_result assign_points(bbc_planeset *set, const grid_part *gp, size_t pi,
                                const select_result *sr, size_t base, double eps, bbc_error *err) {
  uint8_t *miss = calloc(gp->n ? gp->n : 1, 1);
  if (!miss) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  size_t count = sr->plane_count, nl = first_valid(set, gp, sr, base, eps, miss, gp->n);
  nl = absorb(set, gp, sr, base, eps, miss, gp->n, nl);
  double up = (double)gp->n / (double)gp->nf;
  for (size_t k = base; k < base + count; k++) {
    set->planes[k].area *= up;
    if (set->planes[k].kind != BBC_PLANE_CARDBOARD) set->planes[k].face_count = 0;
  }
  for (size_t i = 0; i < gp->n; i++)
    if (!miss[i]) set->planes[set->face_plane[gp->tris[i]]].face_count++;
  /* the leftovers as points of the part's frame, without normals (valid
   * for any plane within epsilon of them) */
  dual_face *left = nl ? calloc(nl, sizeof *left) : NULL;
  bbc_result r = nl && !left
                     ? bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory")
                     : BBC_OK;
  for (size_t i = 0, j = 0; r == BBC_OK && i < gp->n; i++) {
    if (!miss[i]) continue;
    dual_face *f = &left[j++];
    for (int k = 0; k < 3; k++) f->c[k] = gp->points[3 * i + k];
    f->area = 1;
    f->point = 1;
    f->nv = 3;
    f->mesh_index = gp->tris[i];
    f->mesh_index2 = UINT32_MAX;
    f->c_len = sqrt(f->c[0] * f->c[0] + f->c[1] * f->c[1] + f->c[2] * f->c[2]);
  }
  free(miss);
  if (r == BBC_OK) r = cover_leftovers(set, gp, pi, left, nl, eps, err);
  free(left);
  return r;
}

/* A sampled part's faces or points (gp->stride > 1) to planes: its own
 * (sr, the grid's frame; base: the first one's index in the set, whose
 * sr->plane_count planes the set counts already), and the leftovers' after
 * them. */
bbc_result bbc__assign_sampled(bbc_planeset *set, const grid_part *gp, size_t pi,
                               const select_result *sr, size_t base, double eps, bbc_error *err) {
  return gp->all ? assign_faces(set, gp, pi, sr, base, eps, err)
                 : assign_points(set, gp, pi, sr, base, eps, err);
}
