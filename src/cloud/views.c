/*
 * views.c — the algorithm's internals as coloured geometry (thesis Appendix A
 * `show bbc`), GL-free: a face's validity domain on the dual grid,
 * discretised (the cells step 1 counts it in) and continuous (the exact
 * sheets), the grid's density, and the model's faces around a plane. The
 * viewer (src/gl/viewer.c) only draws what this builds.
 *
 * Grid views live in a box: theta (-180..180 deg) along x in [-2, 2], phi
 * (-90..90 deg) along z in [1, -1], rho (the grid's range) along y in
 * [0, 2]. The box's edges are drawn with theta red, rho green, phi blue.
 */
#include "base.h"
#include "grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void bbc_geometry_free(bbc_geometry *g) {
  if (!g) return;
  free(g->tris);
  free(g->lines);
  memset(g, 0, sizeof *g);
}

typedef struct builder {
  bbc_geometry *g;
  size_t tri_cap, line_cap;
  int failed;
} builder;

static void vertex(float *o, const double p[3], const float rgb[3]) {
  for (int k = 0; k < 3; k++) o[k] = (float)p[k];
  memcpy(o + 3, rgb, 3 * sizeof *rgb);
}

/* Room for one more item of `per` floats in a growing array; NULL when out
 * of memory (the builder then fails). */
static float *push(builder *b, float **items, size_t *count, size_t *cap, size_t per) {
  if (b->failed) return NULL;
  if (*count == *cap) {
    size_t n = *cap ? 2 * *cap : 4096;
    float *t = realloc(*items, n * per * sizeof *t);
    if (!t) {
      b->failed = 1;
      return NULL;
    }
    *items = t;
    *cap = n;
  }
  return *items + per * (*count)++;
}

static void tri(builder *b, const double p0[3], const double p1[3], const double p2[3],
                const float rgb[3]) {
  float *o = push(b, &b->g->tris, &b->g->tri_count, &b->tri_cap, 18);
  if (!o) return;
  vertex(o, p0, rgb);
  vertex(o + 6, p1, rgb);
  vertex(o + 12, p2, rgb);
}

static void line(builder *b, const double p0[3], const double p1[3], const float rgb[3]) {
  float *o = push(b, &b->g->lines, &b->g->line_count, &b->line_cap, 12);
  if (!o) return;
  vertex(o, p0, rgb);
  vertex(o + 6, p1, rgb);
}

static void quad(builder *b, const double p[4][3], const float rgb[3]) {
  tri(b, p[0], p[1], p[2], rgb);
  tri(b, p[0], p[2], p[3], rgb);
}

/* An axis-aligned box, solid (faces shaded by direction) or as edges. */
static void box(builder *b, const double lo[3], const double hi[3], const float rgb[3], int solid) {
  double c[8][3];
  for (int i = 0; i < 8; i++)
    for (int k = 0; k < 3; k++) c[i][k] = (i >> k) & 1 ? hi[k] : lo[k];
  if (!solid) {
    for (int i = 0; i < 8; i++)
      for (int k = 0; k < 3; k++)
        if (!((i >> k) & 1)) line(b, c[i], c[i | 1 << k], rgb);
    return;
  }
  /* faces: -x +x -y +y -z +z, lit from above and the front */
  static const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                              {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  static const float shade[6] = {0.70f, 0.80f, 0.55f, 1.0f, 0.62f, 0.88f};
  for (int s = 0; s < 6; s++) {
    float col[3] = {rgb[0] * shade[s], rgb[1] * shade[s], rgb[2] * shade[s]};
    double q[4][3];
    for (int v = 0; v < 4; v++) memcpy(q[v], c[f[s][v]], sizeof q[v]);
    quad(b, q, col);
  }
}

/* ---- the grid's box ---------------------------------------------------------- */

typedef struct grid_frame {
  const dual_grid *g;
  double rho_max;
} grid_frame;

static void grid_point(const grid_frame *f, double theta, double phi, double rho, double p[3]) {
  p[0] = theta / M_PI * 2.0;
  p[1] = (rho - f->g->rho_min) / (f->rho_max - f->g->rho_min) * 2.0;
  p[2] = -phi / (M_PI / 2);
}

static void grid_axes(builder *b) {
  static const float grey[3] = {0.55f, 0.55f, 0.55f}, red[3] = {0.9f, 0.15f, 0.1f},
                     green[3] = {0.1f, 0.7f, 0.2f}, blue[3] = {0.15f, 0.3f, 0.95f};
  double lo[3] = {-2, 0, -1}, hi[3] = {2, 2, 1};
  box(b, lo, hi, grey, 0);
  double o[3] = {-2, 0, 1}, x[3] = {2, 0, 1}, y[3] = {-2, 2, 1}, z[3] = {-2, 0, -1};
  line(b, o, x, red);   /* theta */
  line(b, o, y, green); /* rho */
  line(b, o, z, blue);  /* phi */
}

static void cell_bounds(const grid_frame *f, size_t dir, int k, double lo[3], double hi[3],
                        double inset) {
  dual_box c;
  bbc__dual_grid_cell_box(f->g, dir, k, &c);
  double a[3], z[3];
  grid_point(f, c.t0, c.p0, c.r0, a);
  grid_point(f, c.t1, c.p1, c.r1, z);
  for (int i = 0; i < 3; i++) {
    double l = fmin(a[i], z[i]), h = fmax(a[i], z[i]), m = 0.5 * (l + h);
    lo[i] = m - (m - l) * (1 - inset);
    hi[i] = m + (h - m) * (1 - inset);
  }
}

/* The cells the face is simply valid for (step 1's test, dualgrid.c). */
static void discrete_domain(builder *b, const grid_frame *f, const dual_face *face, int solid) {
  static const float blue[3] = {0.45f, 0.75f, 1.0f}, wire[3] = {0.2f, 0.45f, 0.9f};
  const dual_grid *g = f->g;
  size_t nd = (size_t)g->n_theta * g->n_phi;
  for (size_t d = 0; d < nd; d++) {
    double lo, hi;
    if (!dual_face_range(face, &g->dirs[d], g->eps, &lo, &hi)) continue;
    int k0 = (int)floor((lo - g->rho_min) / g->rho_res);
    int k1 = (int)floor((hi - g->rho_min) / g->rho_res);
    if (k0 < 0) k0 = 0;
    if (k1 > g->n_rho - 1) k1 = g->n_rho - 1;
    for (int k = k0; k <= k1; k++) {
      double a[3], z[3];
      cell_bounds(f, d, k, a, z, solid ? 0.08 : 0.0);
      box(b, a, z, solid ? blue : wire, solid);
    }
  }
}

/* The exact validity range of rho for direction n: the face's (vertex < 0)
 * or one vertex's. 0 when empty. */
static int exact_range(const dual_face *face, int vertex, const double n[3], double eps, double *lo,
                       double *hi) {
  double a[4]; /* a triangle's fourth is its first */
  for (int v = 0; v < 4; v++) {
    a[v] = 0;
    for (int k = 0; k < 3; k++) a[v] += (face->c[k] + face->d[v][k]) * n[k];
  }
  if (vertex >= 0) {
    *lo = a[vertex] - eps;
    *hi = a[vertex] + eps;
    return 1;
  }
  *lo = fmax(fmax(a[0], a[3]), fmax(a[1], a[2])) - eps;
  *hi = fmin(fmin(a[0], a[3]), fmin(a[1], a[2])) + eps;
  return *lo <= *hi;
}

/* The continuous domain: its lower sheet orange, its upper sheet yellow,
 * sampled 4 times finer than the grid; `volume` adds lines between them. */
static void continuous_domain(builder *b, const grid_frame *f, const dual_face *face, int vertex,
                              int volume) {
  static const float lower[3] = {1.0f, 0.55f, 0.1f}, upper[3] = {0.95f, 0.85f, 0.1f},
                     between[3] = {0.85f, 0.5f, 0.2f};
  const dual_grid *g = f->g;
  int st = 4 * g->n_theta, sp = 4 * g->n_phi;
  size_t n = (size_t)(st + 1) * (sp + 1);
  double *lo = malloc(n * sizeof *lo), *hi = malloc(n * sizeof *hi);
  unsigned char *ok = malloc(n);
  if (!lo || !hi || !ok) {
    free(lo);
    free(hi);
    free(ok);
    b->failed = 1;
    return;
  }
  for (int j = 0; j <= sp; j++)
    for (int i = 0; i <= st; i++) {
      size_t s = (size_t)j * (st + 1) + i;
      double th = -M_PI + 2 * M_PI * i / st, ph = -M_PI / 2 + M_PI * j / sp, nn[3];
      bbc__dual_normal(&g->frame, th, ph, nn);
      ok[s] = (unsigned char)exact_range(face, vertex, nn, g->eps, &lo[s], &hi[s]);
      /* within the grid's range of rho (the rest is the opposite direction's) */
      if (ok[s] && (lo[s] < g->rho_min || hi[s] > f->rho_max)) ok[s] = 0;
    }
  for (int j = 0; j < sp; j++)
    for (int i = 0; i < st; i++) {
      size_t s[4] = {(size_t)j * (st + 1) + i, (size_t)j * (st + 1) + i + 1,
                     (size_t)(j + 1) * (st + 1) + i + 1, (size_t)(j + 1) * (st + 1) + i};
      if (!ok[s[0]] || !ok[s[1]] || !ok[s[2]] || !ok[s[3]]) continue;
      double th[4] = {i, i + 1, i + 1, i}, ph[4] = {j, j, j + 1, j + 1};
      double ql[4][3], qh[4][3];
      for (int v = 0; v < 4; v++) {
        double t = -M_PI + 2 * M_PI * th[v] / st, p = -M_PI / 2 + M_PI * ph[v] / sp;
        grid_point(f, t, p, lo[s[v]], ql[v]);
        grid_point(f, t, p, hi[s[v]], qh[v]);
      }
      quad(b, ql, lower);
      quad(b, qh, upper);
      if (volume && i % 2 == 0 && j % 2 == 0) line(b, ql[0], qh[0], between);
    }
  free(lo);
  free(hi);
  free(ok);
}

/* Blue (low) through green and yellow to red (high). */
static void heat(double t, float rgb[3]) {
  static const float stops[5][3] = {{0.1f, 0.2f, 0.9f},
                                    {0.1f, 0.7f, 0.9f},
                                    {0.2f, 0.8f, 0.2f},
                                    {0.95f, 0.85f, 0.1f},
                                    {0.9f, 0.1f, 0.1f}};
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  double x = t * 4;
  int i = (int)x;
  if (i > 3) i = 3;
  double u = x - i;
  for (int k = 0; k < 3; k++) rgb[k] = (float)(stops[i][k] * (1 - u) + stops[i + 1][k] * u);
}

/* Every cell with density above 2 % of the largest as a cube, its size and
 * colour by density (what the greedy select reads: contribution minus the
 * penalty, 2.1.5-2.1.7). */
static void density(builder *b, const grid_frame *f) {
  const dual_grid *g = f->g;
  size_t nc = (size_t)g->n_theta * g->n_phi * g->n_rho;
  double top = 0;
  for (size_t c = 0; c < nc; c++) {
    double d = (double)g->contrib[c] - g->penalty_factor * (double)g->penalty[c];
    if (d > top) top = d;
  }
  if (top <= 0) return;
  for (size_t c = 0; c < nc; c++) {
    double d = ((double)g->contrib[c] - g->penalty_factor * (double)g->penalty[c]) / top;
    if (d < 0.02) continue;
    double a[3], z[3];
    cell_bounds(f, c / (size_t)g->n_rho, (int)(c % (size_t)g->n_rho), a, z,
                1 - fmax(0.25, cbrt(d)) * 0.92);
    float rgb[3];
    heat(d, rgb);
    box(b, a, z, rgb, 1);
  }
}

/* ---- the grid's parts and faces ------------------------------------------------ */

size_t bbc_grid_get_part_count(const bbc_grid *g) {
  return g->part_count;
}

const char *bbc_grid_get_part_name(const bbc_grid *g, size_t part) {
  return part < g->part_count ? g->part[part].name : NULL;
}

size_t bbc_grid_get_part_faces(const bbc_grid *g, size_t part) {
  return part < g->part_count ? g->part[part].nf : 0;
}

int64_t bbc_grid_get_face_triangle(const bbc_grid *g, size_t part, size_t face) {
  if (part >= g->part_count || face >= g->part[part].nf) return -1;
  return g->part[part].faces[face].mesh_index;
}

int bbc_grid_get_face_vertex_count(const bbc_grid *g, size_t part, size_t face) {
  if (part >= g->part_count || face >= g->part[part].nf) return 0;
  return g->part[part].faces[face].nv;
}

size_t bbc_grid_get_largest_face(const bbc_grid *g, size_t part) {
  size_t best = 0;
  if (part >= g->part_count) return 0;
  for (size_t i = 1; i < g->part[part].nf; i++)
    if (g->part[part].faces[i].area > g->part[part].faces[best].area) best = i;
  return best;
}

double bbc_grid_get_epsilon(const bbc_grid *g, size_t part) {
  if (part >= g->part_count || !g->level_count) return 0;
  return g->levels[g->current].eps_abs[part];
}

bbc_result bbc_grid_view_build(const bbc_grid *grid, const bbc_grid_view_options *o,
                               bbc_geometry *out, bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (o->part >= grid->part_count || !grid->part[o->part].n)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "the grid has no part %zu with faces",
                     o->part);
  const grid_part *gp = &grid->part[o->part];
  if (o->face >= gp->nf)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "part %s has %zu faces, not face %zu",
                     gp->name, gp->nf, o->face);
  if (o->vertex < -1 || o->vertex > gp->faces[o->face].nv - 1)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "vertex %d: -1 (the face) or 0 to %d",
                     o->vertex, gp->faces[o->face].nv - 1);
  if (!grid->level_count)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "the grid has no density yet: run step 1");
  grid_frame f;
  f.g = &grid->levels[grid->current].g[o->part];
  f.rho_max = f.g->rho_min + f.g->n_rho * f.g->rho_res;
  builder b = {out, 0, 0, 0};
  grid_axes(&b);
  const dual_face *face = &gp->faces[o->face];
  switch (o->kind) {
  case BBC_GRID_VIEW_DOMAIN:
    discrete_domain(&b, &f, face, 1);
    break;
  case BBC_GRID_VIEW_CONTINUOUS:
    continuous_domain(&b, &f, face, o->vertex, o->volume);
    break;
  case BBC_GRID_VIEW_BOTH:
    discrete_domain(&b, &f, face, 0);
    continuous_domain(&b, &f, face, o->vertex, o->volume);
    break;
  case BBC_GRID_VIEW_DENSITY:
    density(&b, &f);
    break;
  default:
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "no grid view %d", (int)o->kind);
  }
  out->center[0] = 0;
  out->center[1] = 1;
  out->center[2] = 0;
  out->radius = sqrt(6.0);
  if (b.failed) {
    bbc_geometry_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "grid view: out of memory");
  }
  return BBC_OK;
}

/* ---- the model's faces ----------------------------------------------------------- */

bbc_result bbc_faces_view_build(const bbc_mesh *mesh, const uint8_t *state, size_t selected,
                                bbc_geometry *out, bbc_error *err) {
  static const float grey[3] = {0.5f, 0.5f, 0.5f}, blue[3] = {0.15f, 0.35f, 0.95f},
                     yellow[3] = {1.0f, 0.9f, 0.0f}, cross[3] = {0.9f, 0.1f, 0.1f};
  memset(out, 0, sizeof *out);
  if (mesh->kind != BBC_MESH_TRIANGLES || !mesh->triangle_count)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT, "the faces view needs a triangle mesh");
  builder b = {out, 0, 0, 0};
  for (size_t t = 0; t < mesh->triangle_count; t++) {
    int s = t == selected ? 3 : state ? state[t] : BBC_FACE_REMAINING;
    if (s == BBC_FACE_DONE || s == 3) continue;
    const uint32_t *ix = mesh->indices + 3 * t;
    const double *p[3] = {mesh->positions + 3 * ix[0], mesh->positions + 3 * ix[1],
                          mesh->positions + 3 * ix[2]};
    if (s == BBC_FACE_REMAINING) {
      for (int e = 0; e < 3; e++) line(&b, p[e], p[(e + 1) % 3], grey);
    } else {
      tri(&b, p[0], p[1], p[2], blue);
    }
  }
  if (selected < mesh->triangle_count) {
    /* the selected face last, and a cross through it: a leaf is small */
    const uint32_t *ix = mesh->indices + 3 * selected;
    const double *p[3] = {mesh->positions + 3 * ix[0], mesh->positions + 3 * ix[1],
                          mesh->positions + 3 * ix[2]};
    tri(&b, p[0], p[1], p[2], yellow);
    double c[3], r = 0.12 * (mesh->radius > 0 ? mesh->radius : 1);
    for (int k = 0; k < 3; k++) c[k] = (p[0][k] + p[1][k] + p[2][k]) / 3;
    for (int k = 0; k < 3; k++) {
      double a[3], z[3];
      memcpy(a, c, sizeof a);
      memcpy(z, c, sizeof z);
      a[k] -= r;
      z[k] += r;
      line(&b, a, z, cross);
    }
  }
  memcpy(out->center, mesh->center, sizeof out->center);
  out->radius = mesh->radius > 0 ? mesh->radius : 1;
  if (b.failed) {
    bbc_geometry_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "faces view: out of memory");
  }
  return BBC_OK;
}

void bbc_faces_get_state(const bbc_planeset *set, size_t selected, uint8_t *state, size_t count) {
  uint32_t plane = set && selected < set->face_count ? set->face_plane[selected] : UINT32_MAX;
  for (size_t t = 0; t < count; t++)
    state[t] = set && t < set->face_count && set->face_plane[t] == plane ? BBC_FACE_VALID
                                                                         : BBC_FACE_REMAINING;
}

/* ---- show model's overlays ------------------------------------------------------- */

bbc_result bbc_vertex_domains_view_build(const bbc_mesh *mesh, double eps, bbc_geometry *out,
                                         bbc_error *err) {
  static const float blue[3] = {0.45f, 0.75f, 1.0f};
  memset(out, 0, sizeof *out);
  if (!(eps > 0))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "vertex domains need an epsilon > 0");
  builder b = {out, 0, 0, 0};
  /* at most 200,000 vertices drawn: every k-th of a larger model */
  size_t stride = mesh->vertex_count > 200000 ? (mesh->vertex_count + 199999) / 200000 : 1;
  for (size_t v = 0; v < mesh->vertex_count; v += stride) {
    const double *p = mesh->positions + 3 * v;
    double c[6][3];
    for (int k = 0; k < 6; k++) {
      memcpy(c[k], p, sizeof c[k]);
      c[k][k / 2] += k % 2 ? eps : -eps;
    }
    /* an octahedron of radius eps: the planes valid for the vertex are those
     * that meet its eps-ball */
    static const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int t = 0; t < 8; t++) {
      float shade = 0.7f + 0.3f * (float)(t % 4) / 3.0f, col[3];
      for (int k = 0; k < 3; k++) col[k] = blue[k] * shade;
      tri(&b, c[f[t][0]], c[f[t][1]], c[f[t][2]], col);
    }
  }
  memcpy(out->center, mesh->center, sizeof out->center);
  out->radius = mesh->radius > 0 ? mesh->radius : 1;
  if (b.failed) {
    bbc_geometry_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "vertex domains: out of memory");
  }
  return BBC_OK;
}

bbc_result bbc_shade_view_build(const bbc_mesh *mesh, int voxels, double ambient, bbc_axis up_axis,
                                bbc_geometry *out, bbc_error *err) {
  memset(out, 0, sizeof *out);
  float *vox;
  size_t n;
  bbc_result r = bbc_shade_voxels(mesh, voxels, ambient, up_axis, &vox, &n, err);
  if (r != BBC_OK) return r;
  double half = 0.45 * bbc_shade_get_voxel_size(mesh, voxels);
  builder b = {out, 0, 0, 0};
  for (size_t i = 0; i < n; i++) {
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
      lo[k] = vox[4 * i + k] - half;
      hi[k] = vox[4 * i + k] + half;
    }
    float l = vox[4 * i + 3], rgb[3] = {l, l, l * 0.9f};
    box(&b, lo, hi, rgb, 1);
  }
  free(vox);
  memcpy(out->center, mesh->center, sizeof out->center);
  out->radius = mesh->radius > 0 ? mesh->radius : 1;
  if (b.failed) {
    bbc_geometry_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "shadow voxels: out of memory");
  }
  return BBC_OK;
}
