/*
 * dualgrid.c — step 1 of the Billboard Cloud algorithm: the dual grid of
 * plane space, simple validity and density (thesis 2.1.3-2.1.7).
 *
 * Simple validity, made safe. The thesis bounds a vertex's validity range
 * over a cell by evaluating its dual sheet (Eq. 2-3) at the cell's four
 * corners; the sheet can peak inside the cell, so that bound can miss valid
 * planes. Here the bound is derived instead of sampled. For any direction n
 * of a cell whose directions lie within chord distance r of the centre n_c
 * (|n - n_c| <= r), and a face with centroid c and vertex offsets d_i:
 *     v_i . n = c . n + d_i . n,  |c . (n - n_c)| <= |c| r,
 *     |d_i . (n - n_c)| <= |d_i| r.
 * A plane (n, rho) is valid when max_i v_i.n - eps <= rho <= min_i v_i.n + eps,
 * so every valid rho of the cell lies in
 *     [c.n_c + max_i d_i.n_c - (|c| + dmax) r - eps,
 *      c.n_c + min_i d_i.n_c + (|c| + dmax) r + eps],
 * and no plane of the cell is valid when the face's thickness along n_c,
 * max_i d_i.n_c - min_i d_i.n_c, exceeds 2 eps + 2 dmax r. Coupling the
 * vertices through the shared centroid term makes this tighter than
 * intersecting per-vertex bounds, and it never misses a valid plane. It costs
 * four dot products per face and direction.
 */
#include "dual.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

void bbc__dual_frame_init(dual_frame *f, int up_axis) {
  memset(f, 0, sizeof *f);
  /* (a, b, up) right-handed: a x b = up (cyclic axis order). */
  int a = (up_axis + 1) % 3, b = (up_axis + 2) % 3;
  f->axis_a[a] = 1;
  f->axis_b[b] = 1;
  f->axis_up[up_axis] = 1;
}

void bbc__dual_normal(const dual_frame *f, double theta, double phi, double n[3]) {
  double ct = cos(theta), st = sin(theta), cp = cos(phi), sp = sin(phi);
  for (int k = 0; k < 3; k++)
    n[k] = ct * cp * f->axis_a[k] + st * cp * f->axis_b[k] + sp * f->axis_up[k];
}

void bbc__dual_dir_of_box(const dual_frame *f, const dual_box *b, dual_dir *out) {
  double tc = 0.5 * (b->t0 + b->t1), pc = 0.5 * (b->p0 + b->p1);
  bbc__dual_normal(f, tc, pc, out->n);
  out->phi = pc;
  /* The farthest direction of a theta-phi rectangle from its centre is a
   * corner: along an edge of constant phi the distance grows with
   * |theta - tc|, and along an edge of constant theta n . n_c is a cosine
   * of phi minus an angle within [-90, 90] deg, whose minimum over an
   * interval of [-90, 90] deg is at an end. */
  double r2 = 0;
  const double ts[2] = {b->t0, b->t1}, ps[2] = {b->p0, b->p1};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      double m[3];
      bbc__dual_normal(f, ts[i], ps[j], m);
      double dx = m[0] - out->n[0], dy = m[1] - out->n[1], dz = m[2] - out->n[2];
      double q = dx * dx + dy * dy + dz * dz;
      if (q > r2) r2 = q;
    }
  out->radius = sqrt(r2) * (1 + 1e-12) + 1e-15; /* rounding margin */
}

int bbc__dual_face_valid(const dual_face *f, const double n[3], double rho, double eps) {
  double cc = f->c[0] * n[0] + f->c[1] * n[1] + f->c[2] * n[2] - rho;
  double tol = eps * (1 + 1e-12);
  for (int i = 0; i < f->nv; i++) {
    double dist = cc + f->d[i][0] * n[0] + f->d[i][1] * n[1] + f->d[i][2] * n[2];
    if (fabs(dist) > tol) return 0;
  }
  return 1;
}

bbc_result bbc__dual_points_build(const bbc_mesh *m, const uint32_t *idx, size_t count,
                                  const double center[3], const float *normals, int normals_local,
                                  dual_face **out) {
  dual_face *fs = calloc(count ? count : 1, sizeof *fs);
  if (!fs) return BBC_ERROR_OUT_OF_MEMORY;
    /* Faces are independent: any split over threads gives the same bytes. */
#pragma omp parallel for schedule(static) if (count > 4096)
  for (size_t i = 0; i < count; i++) {
    dual_face *f = &fs[i];
    for (int k = 0; k < 3; k++) f->c[k] = m->positions[3 * (size_t)idx[i] + k] - center[k];
    f->area = 1;
    f->point = 1;
    f->nv = 3;
    f->mesh_index2 = UINT32_MAX;
    f->c_len = sqrt(f->c[0] * f->c[0] + f->c[1] * f->c[1] + f->c[2] * f->c[2]);
    f->mesh_index = idx[i];
    if (normals)
      for (int k = 0; k < 3; k++) f->n[k] = normals[3 * (normals_local ? i : (size_t)idx[i]) + k];
  }
  *out = fs;
  return BBC_OK;
}

/* A face's corners v[nv] (relative to the grid's centre): c their mean,
 * d each one's offset from it (a triangle's d[3] repeats d[0]), d_max the
 * largest offset. */
static void set_corners(dual_face *f, const double (*v)[3], int nv) {
  for (int k = 0; k < 3; k++) {
    double sum = v[0][k];
    for (int j = 1; j < nv; j++) sum += v[j][k];
    f->c[k] = sum / nv;
  }
  f->d_max = 0;
  for (int j = 0; j < nv; j++) {
    double l2 = 0;
    for (int k = 0; k < 3; k++) {
      f->d[j][k] = v[j][k] - f->c[k];
      l2 += f->d[j][k] * f->d[j][k];
    }
    if (l2 > f->d_max * f->d_max) f->d_max = sqrt(l2);
  }
  if (nv == 3) memcpy(f->d[3], f->d[0], sizeof f->d[3]);
  f->nv = nv;
}

bbc_result bbc__dual_faces_build(const bbc_mesh *m, const uint32_t *tris, size_t count,
                                 const double center[3], dual_face **out) {
  dual_face *fs = malloc((count ? count : 1) * sizeof *fs);
  if (!fs) return BBC_ERROR_OUT_OF_MEMORY;
    /* Faces are independent: any split over threads gives the same bytes. */
#pragma omp parallel for schedule(static) if (count > 4096)
  for (size_t i = 0; i < count; i++) {
    dual_face *f = &fs[i];
    uint32_t t = tris[i];
    const uint32_t *ix = m->indices + 3 * t;
    double v[3][3];
    for (int j = 0; j < 3; j++)
      for (int k = 0; k < 3; k++) v[j][k] = m->positions[3 * ix[j] + k] - center[k];
    set_corners(f, (const double(*)[3])v, 3);
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
      e1[k] = v[1][k] - v[0][k];
      e2[k] = v[2][k] - v[0][k];
    }
    double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    double l = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    f->area = 0.5 * l;
    for (int k = 0; k < 3; k++) f->n[k] = l > 0 ? cr[k] / l : 0;
    f->c_len = sqrt(f->c[0] * f->c[0] + f->c[1] * f->c[1] + f->c[2] * f->c[2]);
    f->mesh_index = t;
    f->mesh_index2 = UINT32_MAX;
    f->point = 0;
  }
  *out = fs;
  return BBC_OK;
}

/* The triangles around each vertex (positions in `tris`, increasing, each
 * triangle once a vertex): vertex v's are at[start[v] .. start[v + 1]).
 * Vertex-ordered lists stay cache-friendly where a hash table of edges
 * misses on every lookup. */
typedef struct vertex_tris {
  uint32_t *start, *at;
} vertex_tris;

/* 1 when corner e of triangle ix is not a repeat of an earlier corner. */
static int first_corner(const uint32_t *ix, int e) {
  return (e < 1 || ix[e] != ix[0]) && (e < 2 || ix[e] != ix[1]);
}

static bbc_result vertex_tris_build(const bbc_mesh *m, const uint32_t *tris, size_t count,
                                    vertex_tris *vt) {
  size_t nv = m->vertex_count;
  vt->start = calloc(nv + 1, sizeof *vt->start);
  vt->at = malloc((count ? 3 * count : 1) * sizeof *vt->at);
  if (!vt->start || !vt->at) return BBC_ERROR_OUT_OF_MEMORY;
  for (size_t i = 0; i < count; i++) {
    const uint32_t *ix = m->indices + 3 * (size_t)tris[i];
    for (int e = 0; e < 3; e++)
      if (first_corner(ix, e)) vt->start[ix[e] + 1]++;
  }
  for (size_t v = 0; v < nv; v++) vt->start[v + 1] += vt->start[v];
  uint32_t *fill = malloc((nv ? nv : 1) * sizeof *fill);
  if (!fill) return BBC_ERROR_OUT_OF_MEMORY;
  memcpy(fill, vt->start, nv * sizeof *fill);
  for (size_t i = 0; i < count; i++) {
    const uint32_t *ix = m->indices + 3 * (size_t)tris[i];
    for (int e = 0; e < 3; e++)
      if (first_corner(ix, e)) vt->at[fill[ix[e]]++] = (uint32_t)i;
  }
  free(fill);
  return BBC_OK;
}

/* The other of the first two triangles on edge (a, b) (positions in
 * `tris`) when triangle i is one of them; UINT32_MAX when there is none. */
static uint32_t edge_mate(const bbc_mesh *m, const uint32_t *tris, const vertex_tris *vt,
                          uint32_t a, uint32_t b, uint32_t i) {
  uint32_t first[2] = {UINT32_MAX, UINT32_MAX};
  int n = 0;
  for (uint32_t k = vt->start[a]; k < vt->start[a + 1] && n < 2; k++) {
    const uint32_t *jx = m->indices + 3 * (size_t)tris[vt->at[k]];
    if (jx[0] == b || jx[1] == b || jx[2] == b) first[n++] = vt->at[k];
  }
  if (first[0] == i) return first[1];
  return first[1] == i ? first[0] : UINT32_MAX;
}

/* How far two triangles sharing an edge are from one plane: the larger
 * distance of each one's apex from the other's plane. */
static double bend(const bbc_mesh *m, const uint32_t *ix, const uint32_t *jx, const dual_face *a,
                   const dual_face *b) {
  double worst = 0;
  for (int side = 0; side < 2; side++) {
    const uint32_t *p = side ? ix : jx, *q = side ? jx : ix; /* apex of p, plane of q */
    const dual_face *fq = side ? b : a;
    for (int k = 0; k < 3; k++) {
      uint32_t v = p[k];
      if (v == q[0] || v == q[1] || v == q[2]) continue;
      const double *x = m->positions + 3 * (size_t)v, *o = m->positions + 3 * (size_t)q[0];
      double dist =
          fabs((x[0] - o[0]) * fq->n[0] + (x[1] - o[1]) * fq->n[1] + (x[2] - o[2]) * fq->n[2]);
      worst = dist > worst ? dist : worst;
    }
  }
  return worst;
}

bbc_result bbc__dual_faces_build_merged(const bbc_mesh *m, const uint32_t *tris, size_t count,
                                        const double center[3], double flat_tol, dual_face **out,
                                        size_t *out_count) {
  dual_face *tf;
  bbc_result r = bbc__dual_faces_build(m, tris, count, center, &tf);
  if (r != BBC_OK) return r;
  vertex_tris vt = {NULL, NULL};
  uint32_t *mate = malloc((count ? count : 1) * sizeof *mate);
  if (!mate || vertex_tris_build(m, tris, count, &vt) != BBC_OK) {
    free(vt.start);
    free(vt.at);
    free(mate);
    free(tf);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < count; i++) mate[i] = UINT32_MAX;
  /* Pairs in order: a triangle and the first unpaired neighbour across one
   * of its edges (taken in order) that lies in its plane, facing the same
   * way, the edge run in opposite directions. */
  size_t nf = 0;
  for (size_t i = 0; i < count; i++) {
    if (mate[i] != UINT32_MAX) continue;
    nf++;
    const uint32_t *ix = m->indices + 3 * (size_t)tris[i];
    for (int e = 0; e < 3 && mate[i] == UINT32_MAX; e++) {
      if (ix[e] == ix[(e + 1) % 3]) continue; /* a degenerate edge */
      uint32_t j = edge_mate(m, tris, &vt, ix[e], ix[(e + 1) % 3], (uint32_t)i);
      if (j == UINT32_MAX || j <= i || mate[j] != UINT32_MAX) continue;
      const dual_face *a = &tf[i], *b = &tf[j];
      if (!(a->area > 0) || !(b->area > 0)) continue;
      double dot = a->n[0] * b->n[0] + a->n[1] * b->n[1] + a->n[2] * b->n[2];
      if (dot < 1 - 1e-6 && !(dot >= 0.866 && flat_tol > 0)) continue;
      const uint32_t *jx = m->indices + 3 * (size_t)tris[j];
      int opposite = 0;
      for (int k = 0; k < 3; k++) opposite |= jx[k] == ix[(e + 1) % 3] && jx[(k + 1) % 3] == ix[e];
      if (!opposite) continue;
      if (dot < 1 - 1e-6 && bend(m, ix, jx, a, b) > flat_tol) continue;
      mate[i] = (uint32_t)j;
      mate[j] = (uint32_t)i;
    }
  }
  free(vt.start);
  free(vt.at);
  dual_face *fs = malloc((nf ? nf : 1) * sizeof *fs);
  if (!fs) {
    free(mate);
    free(tf);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  size_t k = 0;
  for (size_t i = 0; i < count; i++) {
    if (mate[i] != UINT32_MAX && mate[i] < i) continue; /* the second of a pair */
    dual_face *f = &fs[k++];
    if (mate[i] == UINT32_MAX) {
      *f = tf[i];
      continue;
    }
    const dual_face *a = &tf[i], *b = &tf[mate[i]];
    /* the four corners: the first triangle's, then the second's apex */
    const uint32_t *ix = m->indices + 3 * (size_t)tris[i];
    const uint32_t *jx = m->indices + 3 * (size_t)tris[mate[i]];
    int apex = 0;
    for (int q = 0; q < 3; q++)
      if (jx[q] != ix[0] && jx[q] != ix[1] && jx[q] != ix[2]) apex = q;
    const uint32_t corner[4] = {ix[0], ix[1], ix[2], jx[apex]};
    double v[4][3];
    for (int q = 0; q < 4; q++)
      for (int c = 0; c < 3; c++) v[q][c] = m->positions[3 * (size_t)corner[q] + c] - center[c];
    memset(f, 0, sizeof *f);
    set_corners(f, (const double(*)[3])v, 4);
    double nn[3], l = 0;
    for (int c = 0; c < 3; c++) {
      nn[c] = a->area * a->n[c] + b->area * b->n[c];
      l += nn[c] * nn[c];
    }
    l = sqrt(l);
    for (int c = 0; c < 3; c++) f->n[c] = l > 0 ? nn[c] / l : a->n[c];
    f->area = a->area + b->area;
    f->c_len = sqrt(f->c[0] * f->c[0] + f->c[1] * f->c[1] + f->c[2] * f->c[2]);
    f->mesh_index = a->mesh_index;
    f->mesh_index2 = b->mesh_index;
  }
  free(mate);
  free(tf);
  *out = fs;
  *out_count = nf;
  return BBC_OK;
}

bbc_result bbc__dual_grid_init(dual_grid *g, int res_deg, double eps, double radius, int up_axis,
                               double total_area, int threads) {
  memset(g, 0, sizeof *g);
  bbc__dual_frame_init(&g->frame, up_axis);
  g->n_theta = 360 / res_deg;
  g->n_phi = 180 / res_deg;
  g->res_rad = res_deg * M_PI / 180.0;
  g->eps = eps;
  /* rho resolution 2 eps (Eq. 2-6); at most 4096 rho cells so that a tiny
   * eps cannot make the grid explode (memory stays below ~60 MB at res 9). */
  double rho_max = radius + eps;
  g->rho_res = 2 * eps;
  if (rho_max / g->rho_res > 4096) g->rho_res = rho_max / 4096;
  /* The first cell is centred on rho = 0: planes through the centre of
   * gravity then lie inside one cell instead of on the grid's edge, where
   * their density would be split between a direction and its opposite. */
  g->rho_min = -0.5 * g->rho_res;
  g->n_rho = (int)ceil((rho_max - g->rho_min) / g->rho_res);
  if (g->n_rho < 1) g->n_rho = 1;
  g->penalty_factor = 10.0;                                       /* thesis 2.1.7 */
  g->scale = total_area > 0 ? 1099511627776.0 / total_area : 1.0; /* 2^40 */
  g->threads = threads;
  size_t nd = (size_t)g->n_theta * g->n_phi, nc = nd * g->n_rho;
  g->dirs = malloc(nd * sizeof *g->dirs);
  g->contrib = calloc(nc, sizeof *g->contrib);
  g->penalty = calloc(nc, sizeof *g->penalty);
  if (!g->dirs || !g->contrib || !g->penalty) {
    bbc__dual_grid_free(g);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (int j = 0; j < g->n_phi; j++)
    for (int i = 0; i < g->n_theta; i++) {
      dual_box b = {-M_PI + i * g->res_rad,
                    -M_PI + (i + 1) * g->res_rad,
                    -M_PI / 2 + j * g->res_rad,
                    -M_PI / 2 + (j + 1) * g->res_rad,
                    0,
                    0};
      bbc__dual_dir_of_box(&g->frame, &b, &g->dirs[(size_t)j * g->n_theta + i]);
    }
  return BBC_OK;
}

bbc_result bbc__dual_grid_copy(dual_grid *dst, const dual_grid *src) {
  *dst = *src;
  size_t nd = (size_t)src->n_theta * src->n_phi, nc = nd * src->n_rho;
  dst->dirs = malloc(nd * sizeof *dst->dirs);
  dst->contrib = malloc(nc * sizeof *dst->contrib);
  dst->penalty = malloc(nc * sizeof *dst->penalty);
  if (!dst->dirs || !dst->contrib || !dst->penalty) {
    bbc__dual_grid_free(dst);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  memcpy(dst->dirs, src->dirs, nd * sizeof *dst->dirs);
  memcpy(dst->contrib, src->contrib, nc * sizeof *dst->contrib);
  memcpy(dst->penalty, src->penalty, nc * sizeof *dst->penalty);
  return BBC_OK;
}

void bbc__dual_grid_free(dual_grid *g) {
  free(g->dirs);
  free(g->contrib);
  free(g->penalty);
  memset(g, 0, sizeof *g);
}

void bbc__dual_grid_cell_box(const dual_grid *g, size_t dir, int k, dual_box *b) {
  int i = (int)(dir % (size_t)g->n_theta), j = (int)(dir / (size_t)g->n_theta);
  b->t0 = -M_PI + i * g->res_rad;
  b->t1 = b->t0 + g->res_rad;
  b->p0 = -M_PI / 2 + j * g->res_rad;
  b->p1 = b->p0 + g->res_rad;
  b->r0 = g->rho_min + k * g->rho_res;
  b->r1 = b->r0 + g->rho_res;
}

/* One thread's block of direction pairs: their directions as
 * structure-of-arrays (so that the range pass vectorises), their grid
 * columns, and the same columns in difference form while faces are added
 * (contribution and penalty of a, then of b). */
typedef struct pair_block {
  size_t m;                    /* pairs */
  double *nx, *ny, *nz, *rad;  /* centre normals and chord radii */
  double *lo, *hi, *proj, *ok; /* one face's ranges, shares and validity */
  double *tr;                  /* the boxes' trigonometry for points: 8 arrays of m */
  size_t *dir_a, *dir_b;       /* the pair's two directions */
  int64_t *diff;               /* 6 kink arrays of n_rho + 2 a pair */
} pair_block;

/* A point's ranges [lo, hi] over the boxes [q0, q1) of a block
 * (dual_point_extremes_at, which vectorises), widened by eps. tr: the
 * boxes' trigonometry, 8 arrays of m (ct0, st0, ct1, st1, cp0, sp0, cp1,
 * sp1). */
static inline void point_ranges(double a, double b, double c, const double *restrict tr, size_t m,
                                size_t q0, size_t q1, double eps, double *restrict lo,
                                double *restrict hi) {
  const double *restrict ct0 = tr, *restrict st0 = tr + m, *restrict ct1 = tr + 2 * m;
  const double *restrict st1 = tr + 3 * m, *restrict cp0 = tr + 4 * m, *restrict sp0 = tr + 5 * m;
  const double *restrict cp1 = tr + 6 * m, *restrict sp1 = tr + 7 * m;
  double R = sqrt(a * a + b * b);
  for (size_t q = q0; q < q1; q++) {
    double mn, mx;
    dual_point_extremes_at(a, b, c, R, ct0[q], st0[q], ct1[q], st1[q], cp0[q], sp0[q], cp1[q],
                           sp1[q], &mn, &mx);
    lo[q] = mn - eps;
    hi[q] = mx + eps;
  }
}

/* Faces [f0, f1) of `which` (or of faces) into a block's columns: blocks
 * of directions whose columns stay in the first-level cache. */
static BBC__CLONES void add_faces(const dual_grid *g, const dual_face *faces, const uint32_t *which,
                                  size_t f0, size_t f1, pair_block *blk) {
  const size_t m = blk->m, st = (size_t)g->n_rho + 2;
  const double eps = g->eps, scale = g->scale;
  const int nr = g->n_rho;
  const double rmin = g->rho_min, inv = 1.0 / g->rho_res, e = eps * inv;
  const double *nx = blk->nx, *ny = blk->ny, *nz = blk->nz, *rad = blk->rad, *tr = blk->tr;
  double *lo = blk->lo, *hi = blk->hi, *proj = blk->proj, *ok = blk->ok;
  int64_t *diff = blk->diff;
  size_t qblock = 16384 / (6 * st * sizeof *diff);
  if (qblock < 1) qblock = 1;
  for (size_t q0 = 0; q0 < m; q0 += qblock) {
    size_t q1 = m - q0 > qblock ? q0 + qblock : m, mq = q1 - q0;
    for (size_t f = f0; f < f1; f++) {
      const dual_face *fc = &faces[which ? which[f] : f];
      double parea = fc->area * scale;
      if (fc->point) { /* 2.4.2: a point's exact range over each direction box */
        double pa, pb, pc;
        dual_point_frame(&g->frame, fc->c, &pa, &pb, &pc);
        int oriented = fc->n[0] != 0 || fc->n[1] != 0 || fc->n[2] != 0;
        point_ranges(pa, pb, pc, tr, m, q0, q1, eps, lo, hi);
        for (size_t q = q0; q < q1; q++) {
          ok[q] = 1;
          proj[q] = oriented ? parea * fabs(fc->n[0] * nx[q] + fc->n[1] * ny[q] + fc->n[2] * nz[q])
                             : parea;
        }
      } else {
        /* Range pass (dual_face_range's arithmetic), then the shares. */
        dual_face_ranges(fc, nx + q0, ny + q0, nz + q0, rad + q0, mq, eps, lo + q0, hi + q0,
                         ok + q0);
        for (size_t q = q0; q < q1; q++) {
          double pn = fc->n[0] * nx[q] + fc->n[1] * ny[q] + fc->n[2] * nz[q];
          proj[q] = parea * (pn < 0 ? -pn : pn);
        }
      }
      /* Scatter pass: the direction and its opposite (the range of -n
       * is [-hi, -lo]), positions in cells from the column's lower end. */
      for (size_t q = q0; q < q1; q++) {
        if (ok[q] == 0 || !(proj[q] > 0)) continue;
        int64_t w = (int64_t)(proj[q] + 0.5);
        int64_t *d = diff + 6 * st * q;
        dual_column_add(d, st, nr, (lo[q] - rmin) * inv, (hi[q] - rmin) * inv, e, w);
        dual_column_add(d + 3 * st, st, nr, (-hi[q] - rmin) * inv, (-lo[q] - rmin) * inv, e, w);
      }
    }
  }
}

bbc_result bbc__dual_grid_accumulate(dual_grid *g, const dual_face *faces, const uint32_t *which,
                                     size_t count, int sign, const bbc_callbacks *cb) {
  /* Directions come in opposite pairs: (i, j) and (i + n_theta/2, n_phi-1-j)
   * have opposite normals, so one evaluation serves both (the range of -n is
   * [-hi, -lo]). Pairs are numbered by their first member. */
  int nth = g->n_theta, nph = g->n_phi;
  size_t npairs = (size_t)nth * nph / 2;
  assert(sign == 1 || sign == -1);
  int nt = bbc__thread_count(g->threads), failed = 0;
  /* Each thread owns a fixed block of pairs and adds every face to them: no
   * two threads write the same cell, and integer sums make the result
   * independent of the partition. */
#ifdef _OPENMP
#pragma omp parallel num_threads(nt)
#endif
  {
    int tid = 0, tn = 1;
#ifdef _OPENMP
    tid = omp_get_thread_num();
    tn = omp_get_num_threads();
#endif
    /* Pairs dealt in turn (tid, tid + tn, ...): neighbouring directions
     * cost alike, so a contiguous share would not balance. */
    size_t mine = npairs > (size_t)tid ? (npairs - (size_t)tid + (size_t)tn - 1) / (size_t)tn : 0;
    size_t nb = mine ? mine : 1;
    /* Structure-of-arrays copies of this block's directions, so the range
     * pass below vectorises. */
    double *buf = malloc(nb * 17 * sizeof *buf);
    size_t *dir_a = malloc(nb * 2 * sizeof *dir_a);
    int64_t *diff = calloc(nb * 6 * ((size_t)g->n_rho + 2), sizeof *diff);
    if (!buf || !dir_a || !diff) {
#ifdef _OPENMP
#pragma omp atomic write
#endif
      failed = 1;
    } else {
      double *nx = buf, *ny = buf + nb, *nz = buf + 2 * nb, *rad = buf + 3 * nb;
      double *lo = buf + 4 * nb, *hi = buf + 5 * nb, *proj = buf + 6 * nb, *ok = buf + 7 * nb;
      double *tr = buf + 9 * nb; /* the directions' boxes for points: 8 arrays of nb */
      size_t *dir_b = dir_a + nb;
      for (size_t k = 0; k < mine; k++) {
        size_t q = (size_t)tid + k * (size_t)tn;
        /* Pair q: rows j < n_phi-1-j, then the first half of a middle row. */
        size_t half_rows = (size_t)(nph / 2), i, j;
        if (q < half_rows * nth) {
          j = q / nth;
          i = q % nth;
        } else {
          j = (size_t)nph / 2;
          i = q - half_rows * nth;
        }
        size_t a = j * nth + i;
        size_t b = (size_t)(nph - 1 - (int)j) * nth + (i + nth / 2) % nth;
        const dual_dir *d = &g->dirs[a];
        nx[k] = d->n[0];
        ny[k] = d->n[1];
        nz[k] = d->n[2];
        rad[k] = d->radius;
        dual_box box;
        bbc__dual_grid_cell_box(g, a, 0, &box);
        dual_box_trig bt;
        dual_box_trig_of(&box, &bt);
        const double trig[8] = {bt.ct0, bt.st0, bt.ct1, bt.st1, bt.cp0, bt.sp0, bt.cp1, bt.sp1};
        for (int t = 0; t < 8; t++) tr[(size_t)t * nb + k] = trig[t];
        dir_a[k] = a;
        dir_b[k] = b;
      }
      size_t m = mine;
      pair_block blk = {m, nx, ny, nz, rad, lo, hi, proj, ok, tr, dir_a, dir_b, diff};
      for (size_t f0 = 0; f0 < count; f0 += 256) {
        size_t f1 = count - f0 > 256 ? f0 + 256 : count;
        add_faces(g, faces, which, f0, f1, &blk);
        if (tid == 0 && cb) bbc__progress(cb, "grid", (double)f1 / count);
      }
      const int nr = g->n_rho;
      const size_t st = (size_t)nr + 2;
      for (size_t q = 0; q < m; q++) {
        int64_t *d = diff + 6 * st * q;
        dual_kinks_fold(d, st, nr, sign, g->contrib + dir_a[q] * (size_t)nr,
                        g->penalty + dir_a[q] * (size_t)nr);
        dual_kinks_fold(d + 3 * st, st, nr, sign, g->contrib + dir_b[q] * (size_t)nr,
                        g->penalty + dir_b[q] * (size_t)nr);
      }
    }
    free(diff);
    free(buf);
    free(dir_a);
  }
  return failed ? BBC_ERROR_OUT_OF_MEMORY : BBC_OK;
}
