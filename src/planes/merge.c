/*
 * merge.c — merging redundant planes after step 2's greedy select (an
 * extension, parameter `merge`), smallest planes first:
 *  (a) a plane whose every face is also valid for some other plane is
 *      dissolved, each face going to the plane that suits its orientation
 *      best (the greedy select restricts a plane to the faces simply valid
 *      for its grid cell, so late planes often hold faces an earlier plane
 *      could have taken);
 *  (b) otherwise, a plane whose faces all lie within 2 eps of a larger
 *      plane is merged into it when one plane -- the larger one, the
 *      post-tweaked plane (Eq. 2-7/2-8) of both sets of faces, or their
 *      least-squares plane -- keeps every face valid (clustering often
 *      splits one layer of sparse leaves in two).
 * A cardboard plane (2.3.7) is never merged; it goes with its mother.
 */
#include "select.h"

#include <stdlib.h>
#include <string.h>

typedef struct merge_ctx {
  const dual_face *faces;
  size_t nf, np;
  double eps;
  select_result *out;
  uint32_t *list;   /* the faces of the plane being merged */
  uint32_t *other;  /* the faces of a plane it may merge into, then its own */
  uint32_t *target; /* per face of list: the plane it would go to (a) */
  uint32_t *order;  /* the planes, ascending face count */
  uint8_t *alive;   /* per plane */
} merge_ctx;

/* Faces assigned to plane pi, into list; returns their number. */
static size_t faces_of(const select_result *out, size_t nf, uint32_t pi, uint32_t *list) {
  size_t n = 0;
  for (size_t f = 0; f < nf; f++)
    if (out->face_plane[f] == pi) list[n++] = (uint32_t)f;
  return n;
}

static void move_faces(select_result *out, const uint32_t *list, size_t n, uint32_t to) {
  for (size_t i = 0; i < n; i++) out->face_plane[list[i]] = to;
  out->planes[to].face_count += n;
}

static void recompute_area(const dual_face *faces, select_result *out, size_t nf, uint32_t pi) {
  double a = 0;
  for (size_t f = 0; f < nf; f++)
    if (out->face_plane[f] == pi) a += dual_projected_area(&faces[f], out->planes[pi].normal);
  out->planes[pi].area = a;
}

/* Every plane alive, in ascending face count, ties by index (insertion
 * sort: there are few planes). */
static void order_by_size(merge_ctx *mc) {
  size_t np = mc->np;
  uint32_t *order = mc->order;
  for (size_t i = 0; i < np; i++) {
    order[i] = (uint32_t)i;
    mc->alive[i] = 1;
  }
  for (size_t i = 1; i < np; i++) {
    uint32_t x = order[i];
    size_t j = i;
    while (j > 0 && mc->out->planes[order[j - 1]].face_count > mc->out->planes[x].face_count) {
      order[j] = order[j - 1];
      j--;
    }
    order[j] = x;
  }
}

/* (a) Dissolves plane pi (its n faces in list) when each of them is valid
 * for some other plane: each goes to the one it covers the most area of.
 * Returns 1 when dissolved. */
static int dissolve(merge_ctx *mc, uint32_t pi, size_t n) {
  const dual_face *faces = mc->faces;
  select_result *out = mc->out;
  const uint32_t *list = mc->list;
  int ok = 1;
  for (size_t i = 0; i < n && ok; i++) {
    double best = -1;
    uint32_t best_q = UINT32_MAX;
    for (size_t q = 0; q < mc->np; q++) {
      const bbc_plane *pq = &out->planes[q];
      if (q == pi || !mc->alive[q] || pq->kind == BBC_PLANE_CARDBOARD) continue;
      if (!bbc__dual_face_valid(&faces[list[i]], pq->normal, pq->d, mc->eps)) continue;
      double a = dual_projected_area(&faces[list[i]], pq->normal);
      if (a > best) {
        best = a;
        best_q = (uint32_t)q;
      }
    }
    mc->target[i] = best_q;
    ok = best_q != UINT32_MAX;
  }
  if (!ok) return 0;
  for (size_t i = 0; i < n; i++) {
    uint32_t *target = mc->target;
    out->face_plane[list[i]] = target[i];
    out->planes[target[i]].face_count++;
    out->planes[target[i]].area +=
        dual_projected_area(&faces[list[i]], out->planes[target[i]].normal);
  }
  return 1;
}

/* (b) Whether the n faces of list can join plane q: they lie within 2 eps
 * of it, and q, or q refitted to both sets of faces (post-tweaked, else
 * least squares; points: least squares only, 2.4.4), keeps every face
 * valid. A refit replaces q's plane. */
static int joins(merge_ctx *mc, uint32_t q, size_t n) {
  const dual_face *faces = mc->faces;
  const uint32_t *list = mc->list;
  double eps = mc->eps;
  bbc_plane *pq = &mc->out->planes[q];
  /* Only planes the faces lie close to (within 2 eps) are tried. */
  int near = 1;
  for (size_t i = 0; i < n && near; i++)
    near = bbc__dual_face_valid(&faces[list[i]], pq->normal, pq->d, 2 * eps);
  if (!near) return 0;
  size_t m = faces_of(mc->out, mc->nf, q, mc->other);
  int all = 1;
  for (size_t i = 0; i < n && all; i++)
    all = bbc__dual_face_valid(&faces[list[i]], pq->normal, pq->d, eps);
  if (all) return 1;
  memcpy(mc->other + m, list, n * sizeof *list);
  double nn[3] = {pq->normal[0], pq->normal[1], pq->normal[2]}, rr = pq->d;
  /* points: no tweaking (2.4.4); a refit by least squares only */
  if ((!faces[list[0]].point && bbc__dual_posttweak(faces, mc->other, m + n, eps, nn, &rr)) ||
      bbc__dual_fit_plane(faces, mc->other, m + n, eps, nn, &rr)) {
    memcpy(pq->normal, nn, sizeof nn);
    pq->d = rr;
    if (pq->kind == BBC_PLANE_STANDARD && !faces[list[0]].point) pq->kind = BBC_PLANE_POSTTWEAKED;
    return 1;
  }
  return 0;
}

/* (b) The larger plane (after position oi of the order, largest first)
 * the n faces of list join, or UINT32_MAX. */
static uint32_t larger_to_join(merge_ctx *mc, size_t oi, size_t n) {
  uint32_t into = UINT32_MAX;
  for (size_t oj = mc->np; oj-- > oi + 1 && into == UINT32_MAX;) {
    uint32_t q = mc->order[oj];
    if (!mc->alive[q] || mc->out->planes[q].kind == BBC_PLANE_CARDBOARD) continue;
    if (joins(mc, q, n)) into = q;
  }
  return into;
}

/* Plane order[oi]: dissolved (a), merged into a larger one (b), or kept. */
static void merge_one(merge_ctx *mc, size_t oi) {
  select_result *out = mc->out;
  uint32_t pi = mc->order[oi];
  if (out->planes[pi].kind == BBC_PLANE_CARDBOARD || !mc->alive[pi]) return;
  size_t n = faces_of(out, mc->nf, pi, mc->list);
  if (!dissolve(mc, pi, n)) {
    /* (b) merge into a larger plane the faces lie close to, largest first. */
    uint32_t into = larger_to_join(mc, oi, n);
    if (into == UINT32_MAX) return;
    move_faces(out, mc->list, n, into);
    recompute_area(mc->faces, out, mc->nf, into);
  }
  mc->alive[pi] = 0;
  for (size_t q = 0; q < mc->np; q++) /* its cardboard plane goes with it */
    if (out->planes[q].kind == BBC_PLANE_CARDBOARD && out->planes[q].mother == (int32_t)pi)
      mc->alive[q] = 0;
}

/* Drops the planes no longer alive and renumbers the rest. */
static void compact(merge_ctx *mc) {
  select_result *out = mc->out;
  uint32_t *remap = mc->order; /* reuse */
  size_t k = 0;
  for (size_t i = 0; i < mc->np; i++) {
    remap[i] = mc->alive[i] ? (uint32_t)k : UINT32_MAX;
    if (mc->alive[i]) out->planes[k++] = out->planes[i];
  }
  out->plane_count = k;
  for (size_t i = 0; i < k; i++)
    if (out->planes[i].mother >= 0) out->planes[i].mother = (int32_t)remap[out->planes[i].mother];
  for (size_t f = 0; f < mc->nf; f++) out->face_plane[f] = remap[out->face_plane[f]];
}

bbc_result bbc__merge_planes(const dual_face *faces, size_t nf, double eps, select_result *out) {
  size_t np = out->plane_count;
  if (np < 2) return BBC_OK;
  merge_ctx mc = {faces, nf, np, eps, out, NULL, NULL, NULL, NULL, NULL};
  mc.list = malloc(nf * sizeof *mc.list);
  mc.other = malloc(nf * sizeof *mc.other);
  mc.target = malloc(nf * sizeof *mc.target);
  mc.order = malloc(np * sizeof *mc.order);
  mc.alive = malloc(np);
  bbc_result r = BBC_OK;
  if (!mc.list || !mc.other || !mc.target || !mc.order || !mc.alive) {
    r = BBC_ERROR_OUT_OF_MEMORY;
  } else {
    order_by_size(&mc);
    for (size_t oi = 0; oi < np; oi++) merge_one(&mc, oi);
    compact(&mc);
  }
  free(mc.list);
  free(mc.other);
  free(mc.target);
  free(mc.order);
  free(mc.alive);
  return r;
}
