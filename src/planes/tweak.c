/*
 * tweak.c — what happens to a plane once the greedy select found it:
 * coplanar optimisation (thesis 2.3.2), post-plane tweaking (2.3.3), and the
 * minimum-area bounding rectangle of its faces (convex hull and rotating
 * calipers; used for cardboard planes, 2.3.7, and for the billboards).
 */
#include "dual.h"
#include "vec3.h"

#include <stdlib.h>
#include <string.h>

int bbc__dual_coplanar(const dual_face *faces, const uint32_t *which, size_t count, double tol,
                       double n[3], double *rho) {
  if (count == 0) return 0;
  const dual_face *f0 = &faces[which[0]];
  double n0[3] = {f0->n[0], f0->n[1], f0->n[2]};
  double r0 = vdot(vload(n0), vload(f0->c));
  /* Compare normals and points, not (theta, phi, rho): at the poles of the
   * parameterisation any theta describes the same plane (2.3.2). */
  for (size_t i = 1; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    double cr[3] = {f->n[1] * n0[2] - f->n[2] * n0[1], f->n[2] * n0[0] - f->n[0] * n0[2],
                    f->n[0] * n0[1] - f->n[1] * n0[0]};
    if (vdot(vload(cr), vload(cr)) > 1e-12) return 0;
    for (int j = 0; j < f->nv; j++) {
      double v[3] = {f->c[0] + f->d[j][0], f->c[1] + f->d[j][1], f->c[2] + f->d[j][2]};
      if (fabs(vdot(vload(n0), vload(v)) - r0) > tol) return 0;
    }
  }
  /* Keep the orientation of the plane it replaces. */
  if (vdot(vload(n0), vload(n)) < 0) {
    for (int k = 0; k < 3; k++) n0[k] = -n0[k];
    r0 = -r0;
  }
  memcpy(n, n0, sizeof n0);
  *rho = r0;
  return 1;
}

static double projected_area_sum(const dual_face *faces, const uint32_t *which, size_t count,
                                 const double n[3]) {
  double a = 0;
  for (size_t i = 0; i < count; i++) a += dual_projected_area(&faces[which[i]], n);
  return a;
}

/* Eq. 2-7/2-8 with normals flipped to face away from reference point q. */
static int refined_plane(const dual_face *faces, const uint32_t *which, size_t count,
                         const double q[3], double n[3], double *rho) {
  double s[3] = {0, 0, 0}, p[3] = {0, 0, 0}, area = 0;
  for (size_t i = 0; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    double qc[3] = {q[0] - f->c[0], q[1] - f->c[1], q[2] - f->c[2]};
    double sg = vdot(vload(qc), vload(f->n)) > 0 ? -1.0 : 1.0; /* q in front: invert */
    for (int k = 0; k < 3; k++) {
      s[k] += sg * f->area * f->n[k];
      p[k] += f->area * f->c[k];
    }
    area += f->area;
  }
  double l = sqrt(vdot(vload(s), vload(s)));
  if (!(l > 0) || !(area > 0)) return 0;
  for (int k = 0; k < 3; k++) {
    n[k] = s[k] / l;
    p[k] /= area;
  }
  *rho = vdot(vload(n), vload(p));
  return 1;
}

int bbc__dual_posttweak(const dual_face *faces, const uint32_t *which, size_t count, double eps,
                        double n[3], double *rho) {
  if (count == 0) return 0;
  double old_area = projected_area_sum(faces, which, count, n);
  /* Reference points: the grid origin (the part's centre of gravity) and
   * the faces' own centre of gravity (Fig. 2-33 shows each failing alone). */
  double cg[3] = {0, 0, 0}, area = 0;
  for (size_t i = 0; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    for (int k = 0; k < 3; k++) cg[k] += f->area * f->c[k];
    area += f->area;
  }
  for (int k = 0; k < 3; k++) cg[k] = area > 0 ? cg[k] / area : 0;
  const double origin[3] = {0, 0, 0};
  const double *refs[2] = {origin, cg};
  int found = 0;
  double best_n[3], best_rho = 0, best_area = old_area * (1 - 1e-12);
  for (int r = 0; r < 2; r++) {
    double m[3], rr;
    if (!refined_plane(faces, which, count, refs[r], m, &rr)) continue;
    if (vdot(vload(m), vload(n)) < 0) { /* keep the orientation */
      for (int k = 0; k < 3; k++) m[k] = -m[k];
      rr = -rr;
    }
    double a = projected_area_sum(faces, which, count, m);
    if (a < best_area) continue;
    int ok = 1;
    for (size_t i = 0; i < count && ok; i++)
      ok = bbc__dual_face_valid(&faces[which[i]], m, rr, eps);
    if (!ok) continue;
    found = 1;
    best_area = a;
    memcpy(best_n, m, sizeof best_n);
    best_rho = rr;
  }
  if (!found) return 0;
  memcpy(n, best_n, sizeof best_n);
  *rho = best_rho;
  return 1;
}

int bbc__dual_fit_plane(const dual_face *faces, const uint32_t *which, size_t count, double eps,
                        double n[3], double *rho) {
  if (count == 0) return 0;
  /* Area-weighted least squares over the vertices: the plane through their
   * weighted centroid normal to the direction of least spread. */
  double w = 0, m[3] = {0, 0, 0};
  for (size_t i = 0; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    for (int k = 0; k < 3; k++) m[k] += f->area * f->c[k];
    w += f->area;
  }
  if (!(w > 0)) return 0;
  for (int k = 0; k < 3; k++) m[k] /= w;
  double cov[3][3] = {{0}};
  for (size_t i = 0; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    double wv = f->nv == 3 ? f->area : f->area * 0.75; /* the face's weight over its vertices */
    for (int j = 0; j < f->nv; j++) {
      double p[3] = {f->c[0] + f->d[j][0] - m[0], f->c[1] + f->d[j][1] - m[1],
                     f->c[2] + f->d[j][2] - m[2]};
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) cov[a][b] += wv * p[a] * p[b];
    }
  }
  double e[3];
  bbc__smallest_eigenvector(cov, e);
  double l = sqrt(vdot(vload(e), vload(e)));
  if (!(l > 0)) return 0;
  for (int k = 0; k < 3; k++) e[k] /= l;
  if (vdot(vload(e), vload(n)) < 0)
    for (int k = 0; k < 3; k++) e[k] = -e[k];
  double r = vdot(vload(e), vload(m));
  for (size_t i = 0; i < count; i++)
    if (!bbc__dual_face_valid(&faces[which[i]], e, r, eps)) return 0;
  memcpy(n, e, sizeof e);
  *rho = r;
  return 1;
}

/* ---- minimum-area bounding rectangle ------------------------------------- */

typedef bbc__pt2 pt2;

/* The plane's in-plane axes a, b for normal n. */
static void plane_axes(const double n[3], double a[3], double b[3]) {
  double t[3] = {0, 0, 0};
  int kk = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2)
                                   : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
  t[kk] = 1;
  a[0] = n[1] * t[2] - n[2] * t[1];
  a[1] = n[2] * t[0] - n[0] * t[2];
  a[2] = n[0] * t[1] - n[1] * t[0];
  double la = sqrt(vdot(vload(a), vload(a)));
  for (int k = 0; k < 3; k++) a[k] /= la;
  b[0] = n[1] * a[2] - n[2] * a[1];
  b[1] = n[2] * a[0] - n[0] * a[2];
  b[2] = n[0] * a[1] - n[1] * a[0];
}

static bbc_result min_rect_of(pt2 *p, size_t np, const double a[3], const double b[3], double u[3],
                              double w[3], double min_uv[2], double max_uv[2]);

bbc_result bbc__dual_min_rect(const dual_face *faces, const uint32_t *which, size_t count,
                              const double n[3], double u[3], double w[3], double min_uv[2],
                              double max_uv[2]) {
  double a[3], b[3];
  plane_axes(n, a, b);
  size_t np = 4 * count;
  pt2 *p = malloc((np ? np : 1) * sizeof *p);
  if (!p) return BBC_ERROR_OUT_OF_MEMORY;
  np = 0;
  for (size_t i = 0; i < count; i++) {
    const dual_face *f = &faces[which[i]];
    for (int j = 0; j < f->nv; j++) {
      double v[3] = {f->c[0] + f->d[j][0], f->c[1] + f->d[j][1], f->c[2] + f->d[j][2]};
      p[np].x = vdot(vload(v), vload(a));
      p[np++].y = vdot(vload(v), vload(b));
    }
  }
  bbc_result r = min_rect_of(p, np, a, b, u, w, min_uv, max_uv);
  free(p);
  return r;
}

bbc_result bbc__points_min_rect(const bbc_mesh *m, const uint32_t *which, size_t count,
                                const double n[3], double u[3], double w[3], double min_uv[2],
                                double max_uv[2]) {
  double a[3], b[3];
  plane_axes(n, a, b);
  pt2 *p = malloc((count ? count : 1) * sizeof *p);
  if (!p) return BBC_ERROR_OUT_OF_MEMORY;
  for (size_t i = 0; i < count; i++) {
    const double *v = m->positions + 3 * (size_t)which[i];
    p[i].x = vdot(vload(v), vload(a));
    p[i].y = vdot(vload(v), vload(b));
  }
  bbc_result r = min_rect_of(p, count, a, b, u, w, min_uv, max_uv);
  free(p);
  return r;
}

/* The minimum-area rectangle of 2D points p[np] (coordinates along a and
 * b): its axes and extents (np = 0: axes a, b, an empty rectangle). The
 * points are reordered. */
static bbc_result min_rect_of(pt2 *p, size_t np, const double a[3], const double b[3], double u[3],
                              double w[3], double min_uv[2], double max_uv[2]) {
  pt2 *h = np ? malloc((2 * np + 2) * sizeof *h) : NULL;
  if (!h) {
    memcpy(u, a, 3 * sizeof *u);
    memcpy(w, b, 3 * sizeof *w);
    min_uv[0] = min_uv[1] = max_uv[0] = max_uv[1] = 0;
    return np ? BBC_ERROR_OUT_OF_MEMORY : BBC_OK;
  }
  size_t hn = bbc__convex_hull_2d(p, np, h);
  /* Rotating calipers: the minimum rectangle has a side on a hull edge. */
  double best = INFINITY, bc = 1, bs = 0;
  /* Every edge of zero length (all points in one spot): the unrotated
   * bounds, so the rectangle is always written. */
  int any_edge = 0;
  for (size_t e = 0; e < hn; e++) {
    pt2 p0 = h[e], p1 = h[(e + 1) % hn];
    if (p1.x != p0.x || p1.y != p0.y) any_edge = 1;
  }
  for (size_t e = 0; e < (hn > 1 && any_edge ? hn : 1); e++) {
    double c = 1, s = 0;
    if (hn > 1 && any_edge) {
      pt2 p0 = h[e], p1 = h[(e + 1) % hn];
      double dx = p1.x - p0.x, dy = p1.y - p0.y, l = sqrt(dx * dx + dy * dy);
      if (!(l > 0)) continue;
      c = dx / l;
      s = dy / l;
    }
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (size_t i = 0; i < hn; i++) {
      double x = h[i].x * c + h[i].y * s, y = -h[i].x * s + h[i].y * c;
      x0 = fmin(x0, x);
      x1 = fmax(x1, x);
      y0 = fmin(y0, y);
      y1 = fmax(y1, y);
    }
    double area = (x1 - x0) * (y1 - y0);
    if (area < best) {
      best = area;
      bc = c;
      bs = s;
      min_uv[0] = x0;
      max_uv[0] = x1;
      min_uv[1] = y0;
      max_uv[1] = y1;
    }
  }
  for (int k = 0; k < 3; k++) {
    u[k] = bc * a[k] + bs * b[k];
    w[k] = -bs * a[k] + bc * b[k];
  }
  free(h);
  return BBC_OK;
}
