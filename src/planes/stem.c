/*
 * stem.c — the stem model: the main stem of the trunk part, for the two
 * places that need it. Thesis 2.2.4 keeps the stem apart from the foliage
 * and its branches (planes that also take leaves and branches "slice" the
 * stem); the stem billboards, which make a trunk hold from every side, are
 * beyond the thesis.
 *
 * The model: the stem's base (a centre at the foot of the trunk and a
 * radius across the up axis), its path up the trunk, its straight axis, and
 * planes through that axis. Its users see it in one of two views:
 *
 *   - the path (bbc__stem_keep), for the split's stem-only rule (parts.c):
 *     the trunk's face centroids in 32 slices up the up axis; the base is
 *     the mean of the lowest slice's centroids and their farthest distance
 *     across the up axis; each slice's centre is the mean of its centroids
 *     within 1.5 base radii of the centre of the slice below. The faces
 *     near the path stay in the trunk, the others (branches) join the
 *     foliage. The split follows a path, not a line, so that a leaning or
 *     bent stem stays in the trunk from its foot to its top.
 *   - the axis (bbc__stem_find), for step 3's stem billboards
 *     (src/cloud/cloud.c): the base is the area-weighted centre of the
 *     trunk's faces that reach into the lowest 5 % of its height and the
 *     farthest of their corners from the vertical through it; the axis, the
 *     principal direction of the faces within 2.5 base radii of it (refined
 *     twice from the up axis). A billboard is a plane, so the stem's
 *     billboards need one straight line through the stem: n planes through
 *     the axis, 180/n degrees apart, each baked with a slab as thick as the
 *     stem, so that from any side one of them is within 90/n degrees of
 *     facing the viewer and shows the whole stem (a trunk on one or two
 *     planes is a line from the side those planes are seen edge-on, and
 *     where it is thicker than their slab its middle is cut away).
 *
 * The two views have their own bases (a slice of face centroids, and faces
 * reaching into the lowest 5 % weighted by area), and their own centroid
 * arithmetic: they give different numbers, and each user's result is kept
 * exactly as it is. What they share is the rule for the up axis.
 */
#include "planes.h"
#include "vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The up axis: 0 = x, 1 = y, 2 = z; anything else is y. */
static int up_of(int up_axis) {
  return up_axis >= 0 && up_axis <= 2 ? up_axis : 1;
}

/* ------------------------------------------------------------------------ */
/* The path (the split's view)                                               */
/* ------------------------------------------------------------------------ */

enum { SLICES = 32 };

/* The trunk's faces as the path sees them, and the path. */
typedef struct stem_path {
  int up, a, b;      /* the up axis and the two across it */
  size_t n;          /* trunk faces */
  double *q;         /* their centroids */
  uint32_t *which;   /* their triangles */
  int *slice;        /* their slices */
  double hmin, hmax; /* the centroids' heights */
  double reach;      /* 1.5 base radii */
  double cx[SLICES], cy[SLICES];
  int found[SLICES]; /* a slice with centroids near the path */
} stem_path;

/* The trunk faces' centroids (q, which: sp->n of them) and their heights'
 * range. Returns 0 when out of memory. */
static int path_centroids(const bbc_mesh *m, const uint32_t *face_part, uint32_t trunk,
                          stem_path *sp) {
  size_t nf = m->triangle_count, nt = sp->n;
  int up = sp->up;
  double *q = malloc(nt * 3 * sizeof *q); /* trunk face centroids */
  uint32_t *which = malloc(nt * sizeof *which);
  if (!q || !which) {
    free(q);
    free(which);
    return 0;
  }
  double hmin = INFINITY, hmax = -INFINITY;
  size_t k = 0;
  for (size_t t = 0; t < nf; t++) {
    if (face_part[t] != trunk) continue;
    for (int i = 0; i < 3; i++) {
      q[3 * k + i] = 0;
      for (int j = 0; j < 3; j++) q[3 * k + i] += m->positions[3 * m->indices[3 * t + j] + i] / 3;
    }
    hmin = fmin(hmin, q[3 * k + up]);
    hmax = fmax(hmax, q[3 * k + up]);
    which[k++] = (uint32_t)t;
  }
  sp->q = q;
  sp->which = which;
  sp->hmin = hmin;
  sp->hmax = hmax;
  return 1;
}

/* Each centroid's slice of the height range. */
static void path_slices(stem_path *sp) {
  double dh = (sp->hmax - sp->hmin) / SLICES;
  for (size_t i = 0; i < sp->n; i++) {
    int s = (int)((sp->q[3 * i + sp->up] - sp->hmin) / dh);
    sp->slice[i] = s < 0 ? 0 : (s >= SLICES ? SLICES - 1 : s);
  }
}

/* The path's base: centre (ca, cb across the up axis) and radius of the
 * lowest slice's centroids. */
static void path_base(const stem_path *sp, double *ca_out, double *cb_out, double *r0_out) {
  const double *q = sp->q;
  int a = sp->a, b = sp->b;
  double ca = 0, cb = 0, n = 0, r0 = 0;
  for (size_t i = 0; i < sp->n; i++)
    if (sp->slice[i] == 0) {
      ca += q[3 * i + a];
      cb += q[3 * i + b];
      n++;
    }
  ca /= n;
  cb /= n;
  for (size_t i = 0; i < sp->n; i++)
    if (sp->slice[i] == 0) r0 = fmax(r0, hypot(q[3 * i + a] - ca, q[3 * i + b] - cb));
  *ca_out = ca;
  *cb_out = cb;
  *r0_out = r0;
}

/* The path from the base (ca, cb) up: each slice's centre is the mean of
 * its centroids within reach of the slice below's centre (a slice without
 * any keeps that centre), so a leaning trunk keeps its stem. */
static void path_follow(stem_path *sp, double ca, double cb) {
  const double *q = sp->q;
  int a = sp->a, b = sp->b;
  for (int s = 0; s < SLICES; s++) {
    double sa = 0, sb = 0, cnt = 0;
    for (size_t i = 0; i < sp->n; i++)
      if (sp->slice[i] == s && hypot(q[3 * i + a] - ca, q[3 * i + b] - cb) <= sp->reach) {
        sa += q[3 * i + a];
        sb += q[3 * i + b];
        cnt++;
      }
    sp->found[s] = cnt > 0;
    if (cnt > 0) {
      ca = sa / cnt;
      cb = sb / cnt;
    }
    sp->cx[s] = ca;
    sp->cy[s] = cb;
  }
}

/* Moves to part `rest` the trunk faces not within reach of the path in
 * their slice; returns how many. */
static size_t path_keep(const stem_path *sp, uint32_t *face_part, uint32_t rest) {
  const double *q = sp->q;
  int a = sp->a, b = sp->b;
  size_t moved = 0;
  for (size_t i = 0; i < sp->n; i++) {
    int s = sp->slice[i];
    if (sp->found[s] && hypot(q[3 * i + a] - sp->cx[s], q[3 * i + b] - sp->cy[s]) <= sp->reach)
      continue;
    face_part[sp->which[i]] = rest;
    moved++;
  }
  return moved;
}

size_t bbc__stem_keep(const bbc_mesh *m, uint32_t *face_part, uint32_t trunk, uint32_t rest,
                      int up_axis) {
  stem_path sp;
  memset(&sp, 0, sizeof sp);
  sp.up = up_of(up_axis);
  sp.a = (sp.up + 1) % 3;
  sp.b = (sp.up + 2) % 3;
  size_t nf = m->triangle_count;
  for (size_t t = 0; t < nf; t++) sp.n += face_part[t] == trunk;
  if (sp.n == 0) return 0;
  if (!path_centroids(m, face_part, trunk, &sp)) return SIZE_MAX;
  size_t moved = 0;
  if (sp.hmax > sp.hmin) {
    sp.slice = malloc(sp.n * sizeof *sp.slice);
    if (!sp.slice) {
      free(sp.q);
      free(sp.which);
      return SIZE_MAX;
    }
    path_slices(&sp);
    double ca, cb, r0;
    path_base(&sp, &ca, &cb, &r0);
    sp.reach = 1.5 * r0;
    path_follow(&sp, ca, cb);
    moved = path_keep(&sp, face_part, rest);
    free(sp.slice);
  }
  free(sp.q);
  free(sp.which);
  return moved;
}

/* ------------------------------------------------------------------------ */
/* The axis and the planes through it (the stem billboards' view)            */
/* ------------------------------------------------------------------------ */

void bbc__stem_free(bbc__stem *s) {
  if (!s) return;
  free(s->face_mask);
  memset(s, 0, sizeof *s);
}

/* Squared distance of x from the line through c along unit d. */
static double line_dist2(const double *x, const double *c, const double *d) {
  vec3 v = vsub(vload(x), vload(c));
  double t = vdot(v, vload(d));
  return vdot(v, v) - t * t;
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

/* The trunk part's faces as the axis sees them, and the axis. */
typedef struct stem_axis {
  const bbc_mesh *m;
  const uint32_t *face_part;
  uint32_t part; /* the trunk part */
  int up;
  double hmin, hmax; /* the trunk's corners' heights */
  double base[3], radius;
  double dir[3]; /* the axis: unit, up */
  uint8_t *mask; /* per triangle: 1 = a stem face */
  size_t count;  /* stem faces */
} stem_axis;

/* The part named "trunk", or -1. */
static int trunk_part(const bbc_planeset *set) {
  int part = -1;
  for (size_t p = 0; p < set->part_count; p++)
    if (!strcmp(set->parts[p].name, "trunk")) part = (int)p;
  return part;
}

static int in_trunk(const stem_axis *x, size_t t) {
  return x->face_part[t] == x->part;
}

/* The range of the trunk's corners' heights. */
static void axis_heights(stem_axis *x) {
  const bbc_mesh *m = x->m;
  double hmin = INFINITY, hmax = -INFINITY;
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (!in_trunk(x, t)) continue;
    for (int c = 0; c < 3; c++) {
      double h = m->positions[3 * m->indices[3 * t + c] + x->up];
      hmin = fmin(hmin, h);
      hmax = fmax(hmax, h);
    }
  }
  x->hmin = hmin;
  x->hmax = hmax;
}

/* The base: faces reaching into the lowest 5 % of the trunk's height; its
 * centre (area-weighted) and radius (across the up axis). Sets dir to the
 * up axis. Returns 0 when there is none (no area, or no width). */
static int axis_base(stem_axis *x) {
  const bbc_mesh *m = x->m;
  size_t nf = m->triangle_count;
  int up = x->up;
  double cut = x->hmin + 0.05 * (x->hmax - x->hmin), c0[3] = {0, 0, 0}, wsum = 0;
  for (size_t t = 0; t < nf; t++) {
    if (!in_trunk(x, t)) continue;
    if (low(m, t, up) > cut) continue;
    double c[3], a = bbc__triangle_area(m, t);
    centroid(m, t, c);
    for (int k = 0; k < 3; k++) c0[k] += a * c[k];
    wsum += a;
  }
  if (!(wsum > 0)) return 0;
  for (int k = 0; k < 3; k++) c0[k] /= wsum;
  double dir[3] = {0, 0, 0}, r0 = 0;
  dir[up] = 1;
  for (size_t t = 0; t < nf; t++) {
    if (!in_trunk(x, t)) continue;
    if (low(m, t, up) > cut) continue;
    for (int j = 0; j < 3; j++) {
      const double *p = m->positions + 3 * m->indices[3 * t + j];
      r0 = fmax(r0, sqrt(fmax(0, line_dist2(p, c0, dir))));
    }
  }
  memcpy(x->base, c0, sizeof c0);
  memcpy(x->dir, dir, sizeof dir);
  x->radius = r0;
  return r0 > 0;
}

/* Marks the trunk faces whose centroids lie within `reach` of the current
 * axis and sets `mean` to their area-weighted centre. Returns 0 when they
 * have no area. */
static int axis_faces(stem_axis *x, double reach, double mean[3]) {
  const bbc_mesh *m = x->m;
  double w = 0;
  for (size_t t = 0; t < m->triangle_count; t++) {
    x->mask[t] = 0;
    if (!in_trunk(x, t)) continue;
    double c[3];
    centroid(m, t, c);
    if (line_dist2(c, x->base, x->dir) > reach * reach) continue;
    x->mask[t] = 1;
    double a = bbc__triangle_area(m, t);
    for (int k = 0; k < 3; k++) mean[k] += a * c[k];
    w += a;
  }
  if (!(w > 0)) return 0;
  for (int k = 0; k < 3; k++) mean[k] /= w;
  return 1;
}

/* The principal direction of the marked faces (area-weighted covariance
 * about `mean`), from the current axis, turned up. */
static void axis_principal(const stem_axis *x, const double mean[3], double v[3]) {
  const bbc_mesh *m = x->m;
  double cov[3][3] = {{0}};
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (!x->mask[t]) continue;
    double c[3], a = bbc__triangle_area(m, t);
    centroid(m, t, c);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) cov[i][j] += a * (c[i] - mean[i]) * (c[j] - mean[j]);
  }
  bbc__largest_eigenvector(cov, x->dir, v); /* from the current axis */
  if (v[x->up] < 0)
    for (int i = 0; i < 3; i++) v[i] = -v[i];
}

/* The axis: principal direction of the faces near it, twice; the last
 * pass only picks the faces (mask, count). */
static void axis_refine(stem_axis *x) {
  double reach = 2.5 * x->radius;
  for (int it = 0; it < 3; it++) {
    double mean[3] = {0, 0, 0};
    if (!axis_faces(x, reach, mean)) break;
    if (it == 2) break; /* the last pass only picks the faces */
    double v[3];
    axis_principal(x, mean, v);
    if (v[x->up] < 0.5) break;        /* leaning more than 60 degrees: not a stem */
    memcpy(x->dir, v, sizeof x->dir); /* through the base centre along the new direction */
  }
  x->count = 0;
  for (size_t t = 0; t < x->m->triangle_count; t++) x->count += x->mask[t];
}

/* Stem plane p of `planes` through the axis, normal e1 cos + e2 sin at
 * 180 p / planes degrees: its plane, its billboard (the stem faces' bounds
 * on it) and its slab (all the stem faces inside). */
static void axis_plane(const stem_axis *x, const double e1[3], const double e2[3], int p,
                       int planes, bbc__stem *out) {
  const bbc_mesh *m = x->m;
  const double *dir = x->dir;
  double a = M_PI * p / planes, n[3];
  for (int k = 0; k < 3; k++) n[k] = cos(a) * e1[k] + sin(a) * e2[k];
  double d = vdot(vload(n), vload(x->base));
  /* u along the axis, w = n x u (so that u x w = n). */
  double u[3] = {dir[0], dir[1], dir[2]};
  double w[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
  double mn[2] = {INFINITY, INFINITY}, mx[2] = {-INFINITY, -INFINITY}, slab = 0;
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (!x->mask[t]) continue;
    for (int j = 0; j < 3; j++) {
      const double *q = m->positions + 3 * m->indices[3 * t + j];
      double s = vdot(vload(q), vload(u)), r = vdot(vload(q), vload(w));
      mn[0] = fmin(mn[0], s);
      mx[0] = fmax(mx[0], s);
      mn[1] = fmin(mn[1], r);
      mx[1] = fmax(mx[1], r);
      slab = fmax(slab, fabs(vdot(vload(q), vload(n)) - d));
    }
  }
  bbc_plane *pl = &out->planes[p];
  memcpy(pl->normal, n, sizeof n);
  pl->d = d;
  pl->kind = BBC_PLANE_STEM;
  pl->part = x->part;
  pl->face_count = x->count;
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
  out->slab[p] = slab * (1 + 1e-9) + 1e-12 * (x->hmax - x->hmin);
}

/* Planes through the axis: normals e1 cos + e2 sin, 180/n degrees apart. */
static void axis_planes(const stem_axis *x, int planes, bbc__stem *out) {
  const double *dir = x->dir;
  int up = x->up;
  double e1[3] = {0, 0, 0}, e2[3];
  e1[(up + 1) % 3] = 1;
  double t1 = vdot(vload(e1), vload(dir));
  for (int k = 0; k < 3; k++) e1[k] -= t1 * dir[k];
  double l1 = sqrt(vdot(vload(e1), vload(e1)));
  for (int k = 0; k < 3; k++) e1[k] /= l1;
  e2[0] = dir[1] * e1[2] - dir[2] * e1[1];
  e2[1] = dir[2] * e1[0] - dir[0] * e1[2];
  e2[2] = dir[0] * e1[1] - dir[1] * e1[0];
  for (int p = 0; p < planes; p++) axis_plane(x, e1, e2, p, planes, out);
}

bbc_result bbc__stem_find(const bbc_mesh *m, const bbc_planeset *set, int planes, int up_axis,
                          bbc__stem *out, bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (planes <= 0 || m->kind != BBC_MESH_TRIANGLES || !set->face_part) return BBC_OK;
  if (planes > BBC__STEM_MAX) planes = BBC__STEM_MAX;
  int part = trunk_part(set);
  if (part < 0) return BBC_OK; /* no trunk part: nothing to hold */
  stem_axis x;
  memset(&x, 0, sizeof x);
  x.m = m;
  x.face_part = set->face_part;
  x.part = (uint32_t)part;
  x.up = up_of(up_axis);
  axis_heights(&x);
  if (!(x.hmax > x.hmin)) return BBC_OK;
  if (!axis_base(&x)) return BBC_OK;
  size_t nf = m->triangle_count;
  x.mask = calloc(nf ? nf : 1, 1);
  if (!x.mask) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "stem: out of memory");
  axis_refine(&x);
  if (!x.count) {
    free(x.mask);
    return BBC_OK;
  }
  axis_planes(&x, planes, out);
  out->count = (size_t)planes;
  out->face_mask = x.mask;
  out->face_count = x.count;
  memcpy(out->axis, x.dir, sizeof x.dir);
  memcpy(out->base, x.base, sizeof x.base);
  out->base_radius = x.radius;
  return BBC_OK;
}
