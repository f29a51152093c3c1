/*
 * planes.c — bbc_planes_find: steps 1 and 2 over the parts of a model.
 * Reads like the thesis's list of steps; the algorithms live in parts.c,
 * parts_geometry.c and stem.c (the split), dualgrid.c (step 1: the dual
 * grid), select.c, cluster.c, tweak.c and merge.c (step 2: select, cluster,
 * tweak, merge); search.c the search over epsilon for maxplanes and
 * minplanes.
 *
 *   1. split the faces into parts (trunk / foliage, thesis 2.2.4, 3.1.1);
 *   2. per part: its own parameters, epsilon in percent of the WHOLE model's
 *      radius, its own centre of gravity as the grid centre (2.1.4);
 *      step 1: dual grid and density; step 2: greedy select;
 *   3. the parts' planes together: back to the model's frame, one face ->
 *      plane table.
 */
#include "grid.h"
#include "planes.h"
#include "select.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Two triangles of a part join into one face for steps 1 and 2 when they
 * bend by less than this times the part's radius (1.7 % of epsilon at the
 * default 6 %, 0.1 at 1 %): modelled needles and leaves are often quads
 * folded that little. */
#define FLAT_TOL 1e-3

void bbc_planes_options_default(bbc_planes_options *o) {
  assert(o);
  memset(o, 0, sizeof *o);
  bbc_params_default(&o->params);
  o->split.mode = BBC_SPLIT_AUTO;
}

static int same_text(const char *a, const char *b) {
  return (!a && !b) || (a && b && !strcmp(a, b));
}

/* The parameters part `name` is found with. */

int bbc_planes_options_stale_step(const bbc_planes_options *a, const bbc_planes_options *b,
                                  const char **which) {
  assert(a && b);
  static _Thread_local char name[64];
  const bbc_split_options *sa = &a->split, *sb = &b->split;
  if (which) *which = NULL;
  if (sa->mode != sb->mode || sa->branches_with_trunk != sb->branches_with_trunk ||
      sa->up != sb->up || !same_text(sa->trunk_patterns, sb->trunk_patterns) ||
      !same_text(sa->foliage_patterns, sb->foliage_patterns) || !same_text(sa->rest, sb->rest)) {
    if (which) *which = "split";
    return 1;
  }
  const char *w = NULL;
  int first = bbc_params_stale_step(&a->params, &b->params, &w);
  if (which) *which = w;
  /* each part as it will be found: its override, else the common parameters */
  static const char *const parts[3] = {"trunk", "foliage", "all"};
  for (int k = 0; k < 3; k++) {
    const bbc_params *pa = bbc__part_params(a, parts[k]), *pb = bbc__part_params(b, parts[k]);
    if (pa == &a->params && pb == &b->params) continue; /* no override: compared above */
    const char *pw = NULL;
    int step = bbc_params_stale_step(pa, pb, &pw);
    /* a part's own setting is named before what it changed in common */
    if (step && (!first || step <= first)) {
      first = step;
      snprintf(name, sizeof name, "%s.%s", parts[k], pw);
      if (which) *which = name;
    }
  }
  return first;
}

void bbc_planeset_free(bbc_planeset *s) {
  if (!s) return;
  free(s->planes);
  free(s->face_plane);
  free(s->parts);
  free(s->face_part);
  memset(s, 0, sizeof *s);
}

/* Area-weighted centre and bounding radius of a set of triangles. */
static void part_frame(const bbc_mesh *m, const uint32_t *tris, size_t n, double center[3],
                       double *radius, double *total_area) {
  long double s[3] = {0, 0, 0}, area = 0;
  for (size_t i = 0; i < n; i++) {
    const uint32_t *ix = m->indices + 3 * tris[i];
    const double *a = m->positions + 3 * ix[0], *b = m->positions + 3 * ix[1],
                 *c = m->positions + 3 * ix[2];
    double ar = bbc__triangle_area(m, tris[i]);
    for (int k = 0; k < 3; k++) s[k] += (long double)ar * (a[k] + b[k] + c[k]) / 3.0;
    area += ar;
  }
  for (int k = 0; k < 3; k++) center[k] = area > 0 ? (double)(s[k] / area) : 0;
  double r2 = 0;
  for (size_t i = 0; i < n; i++)
    for (int j = 0; j < 3; j++) {
      const double *p = m->positions + 3 * m->indices[3 * tris[i] + j];
      double d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
      double q = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      if (q > r2) r2 = q;
    }
  *radius = sqrt(r2);
  *total_area = (double)area;
}

/* A point cloud's frame: the mean of its points, the radius around it, and
 * its points' total weight (1 each). */
static void points_frame(const bbc_mesh *m, double center[3], double *radius, double *total) {
  long double s[3] = {0, 0, 0};
  size_t n = m->vertex_count;
  for (size_t v = 0; v < n; v++)
    for (int k = 0; k < 3; k++) s[k] += m->positions[3 * v + k];
  for (int k = 0; k < 3; k++) center[k] = n ? (double)(s[k] / n) : 0;
  double r2 = 0;
  for (size_t v = 0; v < n; v++) {
    const double *p = m->positions + 3 * v;
    double d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
    double q = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (q > r2) r2 = q;
  }
  *radius = sqrt(r2);
  *total = (double)n;
}

const bbc_params *bbc__part_params(const bbc_planes_options *o, const char *name) {
  for (size_t i = 0; i < o->part_override_count; i++)
    if (!strcasecmp(o->part_overrides[i].part, name)) return &o->part_overrides[i].params;
  return &o->params;
}

/* ---- step 1: the grid ------------------------------------------------------ */

void bbc_planes_options_copy(bbc_planes_options *dst, char text[3][4096],
                             const bbc_planes_options *src) {
  *dst = *src;
  const char **t[3] = {&dst->split.trunk_patterns, &dst->split.foliage_patterns, &dst->split.rest};
  for (int k = 0; k < 3; k++)
    if (*t[k]) {
      snprintf(text[k], 4096, "%s", *t[k]);
      *t[k] = text[k];
    }
  memset(&dst->callbacks, 0, sizeof dst->callbacks);
}

const bbc_planes_options *bbc_grid_get_options(const bbc_grid *g) {
  return &g->options;
}

void bbc_grid_free(bbc_grid *g) {
  if (!g) return;
  for (size_t l = 0; l < g->level_count; l++)
    for (size_t p = 0; p < 2; p++) bbc__dual_grid_free(&g->levels[l].g[p]);
  free(g->levels);
  for (size_t p = 0; p < 2; p++) {
    free(g->part[p].tris);
    free(g->part[p].faces);
    free(g->part[p].points);
    free(g->part[p].all);
  }
  free(g->face_part);
  free(g);
}

/* Progress names the part and the run when steps repeat. */
static void part_callbacks(const bbc_planes_options *o, const bbc_grid *g, const grid_part *gp,
                           double scale, int attempt, bbc_label *lab, bbc_callbacks *cb) {
  *cb = o->callbacks;
  if (g->part_count > 1 && attempt > 1)
    bbc_callbacks_label(&o->callbacks, lab, cb, "%s, run %d at epsilon %.3g %%", gp->name, attempt,
                        scale * gp->params->epsilon_pct);
  else if (g->part_count > 1)
    bbc_callbacks_label(&o->callbacks, lab, cb, "%s", gp->name);
  else if (attempt > 1)
    bbc_callbacks_label(&o->callbacks, lab, cb, "run %d at epsilon %.3g %%", attempt,
                        scale * gp->params->epsilon_pct);
}

/* The level at `scale`, built (step 1 proper: each part's dual grid and its
 * density) unless the grid has it already. */
static bbc_result level_at(bbc_grid *g, const bbc_planes_options *o, double scale, int attempt,
                           size_t *index, bbc_error *err) {
  for (size_t l = 0; l < g->level_count; l++)
    if (g->levels[l].scale == scale) {
      *index = l;
      return BBC_OK;
    }
  grid_level *levels = realloc(g->levels, (g->level_count + 1) * sizeof *levels);
  if (!levels) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 1: out of memory");
  g->levels = levels;
  grid_level *L = &levels[g->level_count];
  memset(L, 0, sizeof *L);
  L->scale = scale;
  for (size_t pi = 0; pi < g->part_count; pi++) {
    grid_part *gp = &g->part[pi];
    if (!gp->n) continue;
    const bbc_params *p = gp->params;
    /* epsilon is relative to the whole model's radius for every part. */
    L->eps_abs[pi] = scale * p->epsilon_pct / 100.0 * g->mesh_radius;
    bbc_label lab;
    bbc_callbacks cb;
    part_callbacks(o, g, gp, scale, attempt, &lab, &cb);
    double t0 = bbc__now_s();
    if (bbc__dual_grid_init(&L->g[pi], p->res_deg, L->eps_abs[pi], gp->radius, p->up_axis,
                            gp->total_area, p->threads) != BBC_OK) {
      for (size_t q = 0; q < 2; q++) bbc__dual_grid_free(&L->g[q]);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 1: out of memory for the grid");
    }
    if (bbc__dual_grid_accumulate(&L->g[pi], gp->faces, NULL, gp->nf, +1, &cb) != BBC_OK) {
      for (size_t q = 0; q < 2; q++) bbc__dual_grid_free(&L->g[q]);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 1: out of memory for the grid");
    }
    bbc__progress(&cb, "grid", 1.0);
    L->step1_s[pi] = bbc__now_s() - t0;
    if (bbc__cancelled(&cb)) {
      for (size_t q = 0; q < 2; q++) bbc__dual_grid_free(&L->g[q]);
      return bbc__fail(err, BBC_ERROR_CANCELLED, "plane selection: cancelled");
    }
  }
  *index = g->level_count++;
  return BBC_OK;
}

static bbc_result grid_build(const bbc_mesh *mesh, const bbc_planes_options *o, int density,
                             bbc_grid **out, bbc_error *err);

/* grid_build with the options' thread count. */
static bbc_result grid_build_threads(const bbc_mesh *mesh, const bbc_planes_options *o, int density,
                                     bbc_grid **out, bbc_error *err) {
  assert(mesh && out);
  int saved = bbc__threads_use(o->params.threads);
  bbc_result r = grid_build(mesh, o, density, out, err);
  bbc__threads_restore(saved);
  return r;
}

bbc_result bbc_grid_build(const bbc_mesh *mesh, const bbc_planes_options *o, bbc_grid **out,
                          bbc_error *err) {
  return grid_build_threads(mesh, o, 1, out, err);
}

bbc_result bbc_grid_build_for_select(const bbc_mesh *mesh, const bbc_planes_options *o,
                                     bbc_grid **out, bbc_error *err) {
  return grid_build_threads(mesh, o, 0, out, err);
}

/* Splits the model into parts (a point cloud is one) into g->face_part,
 * their names into names; warns of part parameters for parts the model
 * does not have. */
static bbc_result grid_split(const bbc_mesh *mesh, const bbc_planes_options *o, bbc_grid *g,
                             char names[2][32], bbc_error *err) {
  int points = mesh->kind == BBC_MESH_POINTS;
  size_t nf = g->face_count;
  bbc_split_options split = o->split;
  split.up = bbc_up_from_axis(o->params.up_axis);
  split.all_trunk_by_geometry = o->params.limbs > 0; /* a leafless tree: limbs and twigs */
  split.limbs = o->params.limbs;
  bbc_result r = BBC_OK;
  if (points) { /* one part: a scan has no trunk or foliage groups */
    memset(g->face_part, 0, nf * sizeof *g->face_part);
    g->part_count = 1;
    snprintf(names[0], sizeof names[0], "all");
    snprintf(g->split_why, sizeof g->split_why, "a point cloud: one part");
  } else {
    r = bbc_split_parts(mesh, &split, g->face_part, &g->part_count, names, g->split_why,
                        sizeof g->split_why, err);
  }
  /* A part's parameters for a part the model does not have: said. */
  for (size_t i = 0; r == BBC_OK && i < o->part_override_count; i++) {
    int used = 0;
    for (size_t pi = 0; pi < g->part_count; pi++)
      used |= !strcasecmp(o->part_overrides[i].part, names[pi]);
    if (!used)
      bbc__log(&o->callbacks, BBC_LOG_WARNING,
               "parameters for part '%s' are not used: the model's parts are %s%s%s",
               o->part_overrides[i].part, names[0], g->part_count > 1 ? " and " : "",
               g->part_count > 1 ? names[1] : "");
  }
  return r;
}

/* Part pi of the grid (name `name`): its parameters, triangles, frame and
 * faces in dual form (a point cloud's points, with pointnormals the
 * file's normals, else estimated ones). */
static bbc_result grid_part_faces(const bbc_mesh *mesh, bbc_grid *g, size_t pi, const char *name,
                                  bbc_error *err) {
  int points = mesh->kind == BBC_MESH_POINTS;
  size_t nf = g->face_count;
  grid_part *gp = &g->part[pi];
  snprintf(gp->name, sizeof gp->name, "%s", name);
  gp->params = bbc__part_params(&g->options, gp->name);
  for (size_t t = 0; t < nf; t++) gp->n += g->face_part[t] == pi;
  if (!points && gp->params->limbs > 0 && g->part_count > 1 && !strcmp(gp->name, "trunk")) {
    gp->meshed = gp->n; /* limbs: no planes; step 3 keeps these faces as a mesh */
    gp->n = 0;
  }
  if (!gp->n) return BBC_OK;
  gp->tris = malloc(gp->n * sizeof *gp->tris);
  if (!gp->tris) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  size_t n = 0;
  for (size_t t = 0; t < nf; t++)
    if (g->face_part[t] == pi) gp->tris[n++] = (uint32_t)t;
  if (points)
    points_frame(mesh, gp->center, &gp->radius, &gp->total_area);
  else
    part_frame(mesh, gp->tris, n, gp->center, &gp->radius, &gp->total_area);
  gp->nf = n;
  gp->stride = 1;
  if (!points) {
    if (bbc__dual_faces_build_merged(mesh, gp->tris, n, gp->center, FLAT_TOL * gp->radius,
                                     &gp->faces, &gp->nf) != BBC_OK)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory for the grid");
    return bbc__sample_faces(gp, err);
  }
  /* A point cloud: steps 1 and 2 on a sample of it when it is larger than
   * 4 x `pointsample` (the density of 16k points stands for that of
   * millions; sparser scans keep every point: a scan of 17,709 points on one
   * tree sampled to half lost 0.03 of IoU): select_part then gives every
   * point its plane. */
  const uint32_t *idx = gp->tris;
  uint32_t *sample = NULL;
  size_t ps = gp->params->point_sample > 0 ? (size_t)gp->params->point_sample : 0;
  if (ps && n / 4 > ps) {
    size_t st = (n + ps - 1) / ps, ns = (n - st / 2 + st - 1) / st;
    sample = malloc(ns * sizeof *sample);
    if (!sample) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
    for (size_t i = 0; i < ns; i++) sample[i] = gp->tris[st / 2 + i * st];
    idx = sample;
    gp->stride = st;
    gp->nf = ns;
    gp->total_area = (double)ns;
    /* every point, for select_part to give it a plane: floats about the
     * centre (their error, 1e-7 of the radius, far below epsilon) */
    gp->points = malloc(3 * n * sizeof *gp->points);
    if (!gp->points) {
      free(sample);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
    }
    for (size_t i = 0; i < n; i++)
      for (int k = 0; k < 3; k++)
        gp->points[3 * i + k] =
            (float)(mesh->positions[3 * (size_t)gp->tris[i] + k] - gp->center[k]);
  }
  float *normals = NULL; /* pointnormals: the file's, else estimated (the sample's) */
  int local = 0;
  bbc_result r = BBC_OK;
  if (gp->params->point_normals) {
    if (mesh->normals) {
      normals = mesh->normals;
    } else {
      normals = malloc(gp->nf * 3 * sizeof *normals);
      local = 1;
      r = normals ? bbc__points_estimate_normals_at(mesh, sample, gp->nf, gp->params->threads,
                                                    normals, err)
                  : bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
    }
  }
  if (r == BBC_OK &&
      bbc__dual_points_build(mesh, idx, gp->nf, gp->center, normals, local, &gp->faces) != BBC_OK)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory for the grid");
  if (local) free(normals);
  free(sample);
  return r;
}

/* Step 1: the parts' faces in dual form and, with `density`, the level at
 * the asked epsilon (without, bbc_planes_select builds the levels it
 * runs on). */
static bbc_result grid_build(const bbc_mesh *mesh, const bbc_planes_options *o, int density,
                             bbc_grid **out, bbc_error *err) {
  *out = NULL;
  int points = mesh->kind == BBC_MESH_POINTS;
  if ((!points && mesh->kind != BBC_MESH_TRIANGLES) ||
      (points ? mesh->vertex_count : mesh->triangle_count) == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "plane selection: the model has no %s",
                     points ? "points" : "triangles");
  if (points && mesh->vertex_count > UINT32_MAX)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "plane selection: more than 2^32 points");
  bbc_grid *g = calloc(1, sizeof *g);
  /* "faces": a point cloud's points (thesis 2.4) */
  size_t nf = points ? mesh->vertex_count : mesh->triangle_count;
  if (g) g->face_part = malloc(nf * sizeof *g->face_part);
  if (!g || !g->face_part) {
    bbc_grid_free(g);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  }
  bbc_planes_options_copy(&g->options, g->text, o);
  g->face_count = nf;
  g->mesh_radius = mesh->radius;
  char names[2][32];
  bbc_result r = grid_split(mesh, o, g, names, err);
  for (size_t pi = 0; r == BBC_OK && pi < g->part_count; pi++)
    r = grid_part_faces(mesh, g, pi, names[pi], err);
  size_t first;
  if (r == BBC_OK && density) r = level_at(g, o, 1.0, 1, &first, err);
  g->current = 0;
  if (r != BBC_OK) {
    bbc_grid_free(g);
    return r;
  }
  *out = g;
  return BBC_OK;
}

/* The views show the level of the planes step 2 returned. */
void bbc__show_level(bbc_grid *g, double scale) {
  for (size_t l = 0; l < g->level_count; l++)
    if (g->levels[l].scale == scale) g->current = l;
}

/* ---- step 2 on the grid ------------------------------------------------------- */

/* A planeset for the grid's faces, no plane yet: every face
 * BBC_NO_PLANE (limbs), the grid's parts and the split's explanation. */
static bbc_result planeset_start(const bbc_grid *g, bbc_planeset *set, bbc_error *err) {
  size_t nf = g->face_count;
  set->face_count = nf;
  set->radius = g->mesh_radius;
  set->face_plane = malloc(nf * sizeof *set->face_plane);
  set->face_part = malloc(nf * sizeof *set->face_part);
  set->parts = calloc(g->part_count ? g->part_count : 1, sizeof *set->parts);
  if (!set->face_plane || !set->face_part || !set->parts) {
    bbc_planeset_free(set);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  }
  memcpy(set->face_part, g->face_part, nf * sizeof *set->face_part);
  for (size_t f = 0; f < nf; f++) set->face_plane[f] = BBC_NO_PLANE; /* limbs */
  snprintf(set->split_why, sizeof set->split_why, "%s", g->split_why);
  return BBC_OK;
}

bbc_plane bbc__plane_to_model(const bbc_plane *in, const grid_part *gp, size_t pi, size_t base) {
  bbc_plane pl = *in;
  pl.d +=
      pl.normal[0] * gp->center[0] + pl.normal[1] * gp->center[1] + pl.normal[2] * gp->center[2];
  pl.part = (uint32_t)pi;
  if (pl.mother >= 0) pl.mother += (int32_t)base;
  return pl;
}

/* Part pi's planes (sr) into the set: the model's frame and global plane
 * indices; faces to mesh triangles (a face of four vertices is two), a
 * plane's face count its triangles'. */
static bbc_result add_part_planes(bbc_planeset *set, const grid_part *gp, size_t pi,
                                  const select_result *sr, double eps, bbc_error *err) {
  bbc_plane *planes = realloc(set->planes, (set->plane_count + sr->plane_count) * sizeof *planes);
  if (!planes) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  set->planes = planes;
  size_t base = set->plane_count;
  for (size_t k = 0; k < sr->plane_count; k++)
    planes[base + k] = bbc__plane_to_model(&sr->planes[k], gp, pi, base);
  for (size_t k = 0; k < sr->plane_count; k++)
    if (planes[base + k].kind != BBC_PLANE_CARDBOARD) planes[base + k].face_count = 0;
  if (gp->stride > 1) {
    set->plane_count += sr->plane_count;
    set->parts[pi].plane_count = sr->plane_count;
    return bbc__assign_sampled(set, gp, pi, sr, base, eps, err);
  }
  for (size_t i = 0; i < gp->nf; i++) {
    const dual_face *f = &gp->faces[i];
    uint32_t pl = (uint32_t)(base + sr->face_plane[i]);
    set->face_plane[f->mesh_index] = pl;
    planes[pl].face_count++;
    if (f->mesh_index2 != UINT32_MAX) {
      set->face_plane[f->mesh_index2] = pl;
      planes[pl].face_count++;
    }
  }
  set->plane_count += sr->plane_count;
  set->parts[pi].plane_count = sr->plane_count;
  return BBC_OK;
}

#ifndef NDEBUG
/* Whether face f's vertices (the part's frame) lie within tol of plane pl
 * (the model's frame; the part's centre at `center`). */
static int face_within(const dual_face *f, const bbc_plane *pl, const double center[3],
                       double tol) {
  double d =
      pl->d - (pl->normal[0] * center[0] + pl->normal[1] * center[1] + pl->normal[2] * center[2]);
  int nv = f->point ? 1 : f->nv;
  for (int k = 0; k < nv; k++) {
    double v = 0;
    for (int j = 0; j < 3; j++) v += pl->normal[j] * (f->c[j] + (f->point ? 0 : f->d[k][j]));
    if (fabs(v - d) > tol) return 0;
  }
  return 1;
}

/* Whether mesh face (or point) `index` of part pi has a plane of its part,
 * not a cardboard one. */
static int face_has_plane(const bbc_planeset *set, uint32_t index, size_t pi) {
  uint32_t p = set->face_plane[index];
  return p < set->plane_count && set->planes[p].part == pi &&
         set->planes[p].kind != BBC_PLANE_CARDBOARD;
}

/* The promise of steps 1 and 2 (bbc_planes_find), an invariant of every
 * part's selection: each of its faces or points, sampled or not, is
 * simplified by a plane of the part, not a cardboard one, and each of its
 * vertices lies within eps of that plane. Debug builds only: a pass over
 * the part's faces. */
static int part_bound_holds(const bbc_planeset *set, const grid_part *gp, size_t pi, double eps) {
  double tol = eps * (1 + 1e-6) + 1e-9 * (gp->radius + 1);
  const dual_face *faces = gp->stride > 1 && gp->all ? gp->all : gp->faces;
  size_t nf = gp->stride > 1 && gp->all ? gp->all_nf : gp->nf;
  if (gp->stride > 1 && !gp->all) { /* a sampled point cloud: every point */
    for (size_t i = 0; i < gp->n; i++) {
      dual_face f = {.point = 1, .nv = 3};
      for (int k = 0; k < 3; k++) f.c[k] = gp->points[3 * i + k];
      if (!face_has_plane(set, gp->tris[i], pi)) return 0;
      if (!face_within(&f, &set->planes[set->face_plane[gp->tris[i]]], gp->center, tol)) return 0;
    }
    return 1;
  }
  for (size_t i = 0; i < nf; i++) {
    const dual_face *f = &faces[i];
    if (!face_has_plane(set, f->mesh_index, pi)) return 0;
    if (f->mesh_index2 != UINT32_MAX &&
        set->face_plane[f->mesh_index2] != set->face_plane[f->mesh_index])
      return 0;
    if (!face_within(f, &set->planes[set->face_plane[f->mesh_index]], gp->center, tol)) return 0;
  }
  return 1;
}
#endif

/* `breaknum` (faces of the whole) for a run on one face in `stride` of
 * part gp's faces (a sampled mesh's: of its sample), at least 10. */
int bbc__sampled_break_num(const grid_part *gp, int break_num, int stride) {
  size_t st = (size_t)stride * (gp->all ? gp->stride : 1);
  if (st <= 1) return break_num;
  return (size_t)break_num / st > 10 ? (int)((size_t)break_num / st) : 10;
}

/* Step 2 for part pi at level L into the set. */
static bbc_result select_part(bbc_grid *g, const bbc_planes_options *o, const grid_level *L,
                              size_t pi, double scale, int attempt, bbc_planeset *set,
                              bbc_error *err) {
  grid_part *gp = &g->part[pi];
  bbc_part_result *pr = &set->parts[pi];
  snprintf(pr->name, sizeof pr->name, "%s", gp->name);
  pr->face_count = gp->n + gp->meshed;
  pr->limbs = gp->meshed ? gp->params->limbs : 0;
  set->part_count = pi + 1;
  if (!gp->n) return BBC_OK;
  /* select asks for the parameters of step 2 as they are now; `breaknum`
   * counts faces: a sampled mesh's, its sample's */
  bbc_params sp = *bbc__part_params(o, gp->name);
  sp.break_num = bbc__sampled_break_num(gp, sp.break_num, 1);
  const bbc_params *p = &sp;
  pr->epsilon_abs = L->eps_abs[pi];
  if (pr->epsilon_abs > set->epsilon_abs) set->epsilon_abs = pr->epsilon_abs;
  memcpy(pr->center, gp->center, sizeof pr->center);
  pr->radius = gp->radius;
  const dual_grid *kept = &L->g[pi];
  pr->grid_cells = (size_t)kept->n_theta * kept->n_phi * kept->n_rho;
  pr->step1_s = L->reported ? 0 : L->step1_s[pi];

  bbc_label lab;
  bbc_callbacks cb;
  part_callbacks(o, g, gp, scale, attempt, &lab, &cb);
  /* the greedy select consumes the density: a copy of the kept grid */
  dual_grid work;
  if (bbc__dual_grid_copy(&work, kept) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory for the grid");
  double t1 = bbc__now_s();
  select_result sr;
  bbc_result r =
      bbc__select_planes(gp->faces, gp->nf, &work, p, pr->epsilon_abs, gp->radius, &cb, &sr);
  pr->step2_s = bbc__now_s() - t1;
  bbc__dual_grid_free(&work);
  if (r == BBC_ERROR_CANCELLED) return bbc__fail(err, r, "plane selection: cancelled");
  if (r != BBC_OK) return bbc__fail(err, r, "plane selection failed: %s", bbc_result_string(r));
  r = add_part_planes(set, gp, pi, &sr, pr->epsilon_abs, err);
  bbc__select_result_free(&sr);
  if (r != BBC_OK) return r;
  assert(part_bound_holds(set, gp, pi, pr->epsilon_abs));
  bbc__progress(&cb, "select", 1.0);
  return BBC_OK;
}

bbc_result bbc__select_once(bbc_grid *g, const bbc_planes_options *o, double scale, int attempt,
                            bbc_planeset *set, bbc_error *err) {
  memset(set, 0, sizeof *set);
  size_t li;
  bbc_result r = level_at(g, o, scale, attempt, &li, err);
  if (r != BBC_OK) return r;
  grid_level *L = &g->levels[li];
  g->current = li;
  r = planeset_start(g, set, err);
  if (r != BBC_OK) return r;
  for (size_t pi = 0; r == BBC_OK && pi < g->part_count; pi++)
    r = select_part(g, o, L, pi, scale, attempt, set, err);
  if (r != BBC_OK) {
    bbc_planeset_free(set);
    return r;
  }
  L->reported = 1;
  return BBC_OK;
}

bbc_result bbc_planes_find(const bbc_mesh *mesh, const bbc_planes_options *o, bbc_planeset *set,
                           bbc_error *err) {
  assert(mesh && set);
  memset(set, 0, sizeof *set);
  bbc_grid *grid;
  bbc_result r = bbc_grid_build_for_select(mesh, o, &grid, err);
  if (r != BBC_OK) return r;
  r = bbc_planes_select(grid, o, set, err);
  bbc_grid_free(grid);
  return r;
}
