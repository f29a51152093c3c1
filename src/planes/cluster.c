/*
 * cluster.c — face clustering by the isolation step (thesis 2.3.10, after
 * Cazals et al.): faces projected onto a plane start as one cluster, which
 * is split wherever, sorted along a direction, the next face starts beyond
 * the extent of all faces before it plus a gap. Directions: the plane's two
 * axes and both diagonals; repeated until a whole round splits nothing.
 */
#include "dual.h"

#include <stdlib.h>
#include <string.h>

typedef struct interval {
  double lo, hi;
  uint32_t face; /* position in the caller's `which` list */
} interval;

static int interval_cmp(const void *a, const void *b) {
  const interval *x = a, *y = b;
  if (x->lo < y->lo) return -1;
  if (x->lo > y->lo) return 1;
  return (x->face > y->face) - (x->face < y->face);
}

/* Orthonormal in-plane axes for normal n. */
static void plane_axes(const double n[3], double u[3], double w[3]) {
  double t[3] = {0, 0, 0};
  int k = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2)
                                  : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
  t[k] = 1;
  u[0] = n[1] * t[2] - n[2] * t[1];
  u[1] = n[2] * t[0] - n[0] * t[2];
  u[2] = n[0] * t[1] - n[1] * t[0];
  double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int i = 0; i < 3; i++) u[i] /= l;
  w[0] = n[1] * u[2] - n[2] * u[1];
  w[1] = n[2] * u[0] - n[0] * u[2];
  w[2] = n[0] * u[1] - n[1] * u[0];
}

size_t bbc__dual_cluster(const dual_face *faces, const uint32_t *which, size_t count,
                         const double n[3], double gap, uint32_t *label) {
  if (count == 0) return 0;
  double u[3], w[3];
  plane_axes(n, u, w);
  double dirs[4][3];
  for (int k = 0; k < 3; k++) {
    dirs[0][k] = u[k];
    dirs[1][k] = w[k];
    dirs[2][k] = (u[k] + w[k]) * M_SQRT1_2;
    dirs[3][k] = (u[k] - w[k]) * M_SQRT1_2;
  }
  /* order: faces grouped by cluster, cluster c occupying [start[c], start[c+1]). */
  uint32_t *order = malloc(count * sizeof *order);
  uint32_t *start = malloc((count + 1) * sizeof *start);
  uint32_t *nstart = malloc((count + 1) * sizeof *nstart);
  interval *iv = malloc(count * sizeof *iv);
  if (!order || !start || !nstart || !iv) {
    free(order);
    free(start);
    free(nstart);
    free(iv);
    memset(label, 0, count * sizeof *label); /* one cluster: still a valid answer */
    return 1;
  }
  for (size_t i = 0; i < count; i++) order[i] = (uint32_t)i;
  size_t nclusters = 1;
  start[0] = 0;
  start[1] = (uint32_t)count;
  int stable_rounds = 0;
  for (int dir = 0; stable_rounds < 4; dir = (dir + 1) % 4) {
    size_t before = nclusters, nn = 0;
    for (size_t c = 0; c < nclusters; c++) {
      size_t a = start[c], b = start[c + 1];
      for (size_t i = a; i < b; i++) {
        const dual_face *f = &faces[which[order[i]]];
        const double *e = dirs[dir];
        double cp = f->c[0] * e[0] + f->c[1] * e[1] + f->c[2] * e[2];
        double lo = cp, hi = cp;
        for (int j = 0; j < f->nv; j++) {
          double x = cp + f->d[j][0] * e[0] + f->d[j][1] * e[1] + f->d[j][2] * e[2];
          lo = fmin(lo, x);
          hi = fmax(hi, x);
        }
        iv[i].lo = lo;
        iv[i].hi = hi;
        iv[i].face = order[i];
      }
      qsort(iv + a, b - a, sizeof *iv, interval_cmp);
      nstart[nn++] = (uint32_t)a;
      double reach = iv[a].hi;
      for (size_t i = a; i < b; i++) {
        if (i > a && iv[i].lo > reach + gap) nstart[nn++] = (uint32_t)i;
        reach = fmax(reach, iv[i].hi);
        order[i] = iv[i].face;
      }
    }
    nstart[nn] = (uint32_t)count;
    memcpy(start, nstart, (nn + 1) * sizeof *start);
    nclusters = nn;
    stable_rounds = nclusters == before ? stable_rounds + 1 : 0;
  }
  /* Label 0 = the cluster with the largest projected area (ties: first). */
  size_t best = 0;
  double best_area = -1;
  for (size_t c = 0; c < nclusters; c++) {
    double area = 0;
    for (size_t i = start[c]; i < start[c + 1]; i++)
      area += dual_projected_area(&faces[which[order[i]]], n);
    if (area > best_area) {
      best_area = area;
      best = c;
    }
  }
  for (size_t c = 0; c < nclusters; c++) {
    uint32_t l = c == best ? 0 : (uint32_t)(c < best ? c + 1 : c);
    for (size_t i = start[c]; i < start[c + 1]; i++) label[order[i]] = l;
  }
  free(order);
  free(start);
  free(nstart);
  free(iv);
  return nclusters;
}
