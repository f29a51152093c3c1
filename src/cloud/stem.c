/* stem.c — beyond the thesis: a stem that holds from every side (issue 11).
 * A trunk on one or two planes is a line from the side those planes are
 * seen edge-on, and where it is thicker than the slab its middle is cut
 * away. Here the trunk part's main stem is found (its base, its axis by
 * principal components of the faces near the axis) and gets `n` extra
 * billboards on planes through the axis, 180/n degrees apart, each baked
 * with a slab as thick as the stem, so that from any side one of them is
 * within 90/n degrees of facing the viewer and shows the whole stem. */
#include "cloud.h"
#include "dual.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void bbc__stem_free(bbc__stem *s) {
  if (!s) return;
  free(s->face_mask);
  memset(s, 0, sizeof *s);
}

static double dot3(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Squared distance of x from the line through c along unit d. */
static double line_dist2(const double *x, const double *c, const double *d) {
  double v[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]}, t = dot3(v, d);
  return dot3(v, v) - t * t;
}

static void centroid(const bbc_mesh *m, size_t t, double *c) {
  const uint32_t *ix = m->indices + 3 * t;
  for (int k = 0; k < 3; k++)
    c[k] =
        (m->positions[3 * ix[0] + k] + m->positions[3 * ix[1] + k] + m->positions[3 * ix[2] + k]) /
        3.0;
}

/* The lowest of a triangle's corners along the up axis. */
static double low(const bbc_mesh *m, size_t t, int up) {
  const uint32_t *ix = m->indices + 3 * t;
  return fmin(m->positions[3 * ix[0] + up],
              fmin(m->positions[3 * ix[1] + up], m->positions[3 * ix[2] + up]));
}

static double tri_area(const bbc_mesh *m, size_t t) {
  double c[3];
  bbc__triangle_cross(m, t, c);
  return 0.5 * sqrt(dot3(c, c));
}

bbc_result bbc__stem_find(const bbc_mesh *m, const bbc_planeset *set, int planes, int up_axis,
                          bbc__stem *out, bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (planes <= 0 || m->kind != BBC_MESH_TRIANGLES || !set->face_part) return BBC_OK;
  if (planes > BBC__STEM_MAX) planes = BBC__STEM_MAX;
  int part = -1;
  for (size_t p = 0; p < set->part_count; p++)
    if (!strcmp(set->parts[p].name, "trunk")) part = (int)p;
  if (part < 0) return BBC_OK; /* no trunk part: nothing to hold */
  int up = up_axis >= 0 && up_axis <= 2 ? up_axis : 1;
  size_t nf = m->triangle_count;
  double hmin = INFINITY, hmax = -INFINITY;
  for (size_t t = 0; t < nf; t++) {
    if (set->face_part[t] != (uint32_t)part) continue;
    for (int c = 0; c < 3; c++) {
      double h = m->positions[3 * m->indices[3 * t + c] + up];
      hmin = fmin(hmin, h);
      hmax = fmax(hmax, h);
    }
  }
  if (!(hmax > hmin)) return BBC_OK;
  /* The base: faces reaching into the lowest 5 % of the trunk's height;
   * its centre (area-weighted) and radius (across the up axis). */
  double cut = hmin + 0.05 * (hmax - hmin), c0[3] = {0, 0, 0}, wsum = 0;
  for (size_t t = 0; t < nf; t++) {
    if (set->face_part[t] != (uint32_t)part) continue;
    if (low(m, t, up) > cut) continue;
    double c[3], a = tri_area(m, t);
    centroid(m, t, c);
    for (int k = 0; k < 3; k++) c0[k] += a * c[k];
    wsum += a;
  }
  if (!(wsum > 0)) return BBC_OK;
  for (int k = 0; k < 3; k++) c0[k] /= wsum;
  double dir[3] = {0, 0, 0}, r0 = 0;
  dir[up] = 1;
  for (size_t t = 0; t < nf; t++) {
    if (set->face_part[t] != (uint32_t)part) continue;
    if (low(m, t, up) > cut) continue;
    for (int j = 0; j < 3; j++) {
      const double *x = m->positions + 3 * m->indices[3 * t + j];
      r0 = fmax(r0, sqrt(fmax(0, line_dist2(x, c0, dir))));
    }
  }
  if (!(r0 > 0)) return BBC_OK;
  /* The axis: principal direction of the faces near it, twice. */
  uint8_t *mask = calloc(nf ? nf : 1, 1);
  if (!mask) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "stem: out of memory");
  double reach = 2.5 * r0;
  for (int it = 0; it < 3; it++) {
    double mean[3] = {0, 0, 0}, cov[3][3] = {{0}}, w = 0;
    for (size_t t = 0; t < nf; t++) {
      mask[t] = 0;
      if (set->face_part[t] != (uint32_t)part) continue;
      double c[3];
      centroid(m, t, c);
      if (line_dist2(c, c0, dir) > reach * reach) continue;
      mask[t] = 1;
      double a = tri_area(m, t);
      for (int k = 0; k < 3; k++) mean[k] += a * c[k];
      w += a;
    }
    if (!(w > 0)) break;
    for (int k = 0; k < 3; k++) mean[k] /= w;
    if (it == 2) break; /* the last pass only picks the faces */
    for (size_t t = 0; t < nf; t++) {
      if (!mask[t]) continue;
      double c[3], a = tri_area(m, t);
      centroid(m, t, c);
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) cov[i][j] += a * (c[i] - mean[i]) * (c[j] - mean[j]);
    }
    double v[3];
    bbc__largest_eigenvector(cov, dir, v); /* from the current axis */
    if (v[up] < 0)
      for (int i = 0; i < 3; i++) v[i] = -v[i];
    if (v[up] < 0.5) break;     /* leaning more than 60 degrees: not a stem */
    memcpy(dir, v, sizeof dir); /* through the base centre along the new direction */
  }
  size_t count = 0;
  for (size_t t = 0; t < nf; t++) count += mask[t];
  if (!count) {
    free(mask);
    return BBC_OK;
  }
  /* Planes through the axis: normals e1 cos + e2 sin, 180/n degrees apart. */
  double e1[3] = {0, 0, 0}, e2[3];
  e1[(up + 1) % 3] = 1;
  double t1 = dot3(e1, dir);
  for (int k = 0; k < 3; k++) e1[k] -= t1 * dir[k];
  double l1 = sqrt(dot3(e1, e1));
  for (int k = 0; k < 3; k++) e1[k] /= l1;
  e2[0] = dir[1] * e1[2] - dir[2] * e1[1];
  e2[1] = dir[2] * e1[0] - dir[0] * e1[2];
  e2[2] = dir[0] * e1[1] - dir[1] * e1[0];
  for (int p = 0; p < planes; p++) {
    double a = M_PI * p / planes, n[3];
    for (int k = 0; k < 3; k++) n[k] = cos(a) * e1[k] + sin(a) * e2[k];
    double d = dot3(n, c0);
    /* u along the axis, w = n x u (so that u x w = n). */
    double u[3] = {dir[0], dir[1], dir[2]};
    double w[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
    double mn[2] = {INFINITY, INFINITY}, mx[2] = {-INFINITY, -INFINITY}, slab = 0;
    for (size_t t = 0; t < nf; t++) {
      if (!mask[t]) continue;
      for (int j = 0; j < 3; j++) {
        const double *x = m->positions + 3 * m->indices[3 * t + j];
        double s = dot3(x, u), q = dot3(x, w);
        mn[0] = fmin(mn[0], s);
        mx[0] = fmax(mx[0], s);
        mn[1] = fmin(mn[1], q);
        mx[1] = fmax(mx[1], q);
        slab = fmax(slab, fabs(dot3(x, n) - d));
      }
    }
    bbc_plane *pl = &out->planes[p];
    memcpy(pl->normal, n, sizeof n);
    pl->d = d;
    pl->kind = BBC_PLANE_STEM;
    pl->part = (uint32_t)part;
    pl->face_count = count;
    pl->mother = -1;
    pl->coverage_pct = 100;
    bbc_billboard *b = &out->rects[p];
    b->plane = UINT32_MAX; /* not a plane of the set */
    memcpy(b->u, u, sizeof u);
    memcpy(b->w, w, sizeof w);
    b->width = mx[0] - mn[0];
    b->height = mx[1] - mn[1];
    for (int k = 0; k < 3; k++) b->origin[k] = d * n[k] + mn[0] * u[k] + mn[1] * w[k];
    pl->area = b->width * b->height;
    out->slab[p] = slab * (1 + 1e-9) + 1e-12 * (hmax - hmin);
  }
  out->count = (size_t)planes;
  out->face_mask = mask;
  out->face_count = count;
  memcpy(out->axis, dir, sizeof dir);
  memcpy(out->base, c0, sizeof c0);
  out->base_radius = r0;
  return BBC_OK;
}
