/*
 * planes.c — bbc_planes_find: steps 1 and 2 over the parts of a model.
 * Reads like the thesis's list of steps; the algorithms live in
 * dualgrid.c (step 1) and select.c (step 2).
 *
 *   1. split the faces into parts (trunk / foliage, thesis 2.2.4, 3.1.1);
 *   2. per part: its own parameters, epsilon in percent of the WHOLE model's
 *      radius, its own centre of gravity as the grid centre (2.1.4);
 *      step 1: dual grid and density; step 2: greedy select;
 *   3. merge: planes back to the model's frame, one face -> plane table.
 */
#include "select.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const k_kind_names[BBC_PLANE_KIND_COUNT] = {
    "standard", "coplanar", "posttweaked", "cardboard", "parachute", "stem"};

const char *bbc_plane_kind_name(bbc_plane_kind kind) {
  return (unsigned)kind < BBC_PLANE_KIND_COUNT ? k_kind_names[kind] : "unknown";
}

void bbc_planes_options_default(bbc_planes_options *o) {
  memset(o, 0, sizeof *o);
  bbc_params_default(&o->params);
  o->split.mode = BBC_SPLIT_AUTO;
  o->split.stem_only = 1;
}

static int same_text(const char *a, const char *b) {
  return (!a && !b) || (a && b && !strcmp(a, b));
}

/* The parameters part `name` is found with. */
static const bbc_params *part_params(const bbc_planes_options *o, const char *name);

int bbc_planes_options_first_step(const bbc_planes_options *a, const bbc_planes_options *b,
                                  const char **which) {
  static _Thread_local char name[64];
  const bbc_split_options *sa = &a->split, *sb = &b->split;
  if (which) *which = NULL;
  if (sa->mode != sb->mode || sa->stem_only != sb->stem_only || sa->up_axis != sb->up_axis ||
      !same_text(sa->trunk_patterns, sb->trunk_patterns) ||
      !same_text(sa->foliage_patterns, sb->foliage_patterns) || !same_text(sa->rest, sb->rest)) {
    if (which) *which = "split";
    return 1;
  }
  const char *w = NULL;
  int first = bbc_params_first_step(&a->params, &b->params, &w);
  if (which) *which = w;
  /* each part as it will be found: its override, else the common parameters */
  static const char *const parts[3] = {"trunk", "foliage", "all"};
  for (int k = 0; k < 3; k++) {
    const bbc_params *pa = part_params(a, parts[k]), *pb = part_params(b, parts[k]);
    if (pa == &a->params && pb == &b->params) continue; /* no override: compared above */
    const char *pw = NULL;
    int step = bbc_params_first_step(pa, pb, &pw);
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
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0]};
    double ar = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
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

static const bbc_params *part_params(const bbc_planes_options *o, const char *name) {
  for (size_t i = 0; i < o->part_override_count; i++)
    if (!strcasecmp(o->part_overrides[i].part, name)) return &o->part_overrides[i].params;
  return &o->params;
}

static bbc_result find_once(const bbc_mesh *mesh, const bbc_planes_options *o, double scale,
                            int attempt, bbc_planeset *set, bbc_error *err) {
  memset(set, 0, sizeof *set);
  if (mesh->kind != BBC_MESH_TRIANGLES || mesh->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "plane selection needs a triangle mesh (point clouds are not supported yet)");
  size_t nf = mesh->triangle_count;
  set->face_count = nf;
  set->radius = mesh->radius;
  set->face_plane = malloc(nf * sizeof *set->face_plane);
  set->face_part = malloc(nf * sizeof *set->face_part);
  uint32_t *tris = malloc(nf * sizeof *tris);
  if (!set->face_plane || !set->face_part || !tris) {
    free(tris);
    bbc_planeset_free(set);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  }
  char names[2][32];
  size_t part_count = 0;
  bbc_split_options split = o->split;
  split.up_axis = o->params.up_axis;
  bbc_result r = bbc_split_parts(mesh, &split, set->face_part, &part_count, names, set->split_why,
                                 sizeof set->split_why, err);
  if (r == BBC_OK) {
    set->parts = calloc(part_count, sizeof *set->parts);
    if (!set->parts) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
  }
  for (size_t pi = 0; r == BBC_OK && pi < part_count; pi++) {
    bbc_part_result *pr = &set->parts[pi];
    snprintf(pr->name, sizeof pr->name, "%s", names[pi]);
    const bbc_params *p = part_params(o, pr->name);
    size_t n = 0;
    for (size_t t = 0; t < nf; t++)
      if (set->face_part[t] == pi) tris[n++] = (uint32_t)t;
    pr->face_count = n;
    set->part_count = pi + 1;
    if (n == 0) continue;
    /* epsilon is relative to the whole model's radius for every part. */
    pr->epsilon_abs = scale * p->epsilon_pct / 100.0 * mesh->radius;
    if (pr->epsilon_abs > set->epsilon_abs) set->epsilon_abs = pr->epsilon_abs;
    double total_area;
    part_frame(mesh, tris, n, pr->center, &pr->radius, &total_area);

    /* Progress names the part and the run when steps repeat. */
    bbc__label lab;
    bbc_callbacks cb = o->callbacks;
    if (part_count > 1 && attempt > 1)
      bbc__label_callbacks(&o->callbacks, &lab, &cb, "%s, run %d at epsilon %.3g %%", pr->name,
                           attempt, scale * p->epsilon_pct);
    else if (part_count > 1)
      bbc__label_callbacks(&o->callbacks, &lab, &cb, "%s", pr->name);
    else if (attempt > 1)
      bbc__label_callbacks(&o->callbacks, &lab, &cb, "run %d at epsilon %.3g %%", attempt,
                           scale * p->epsilon_pct);
    double t0 = bbc__now_s();
    dual_face *faces = NULL;
    dual_grid g;
    memset(&g, 0, sizeof g);
    if (dual_faces_build(mesh, tris, n, pr->center, &faces) != BBC_OK ||
        dual_grid_init(&g, p->res_deg, pr->epsilon_abs, pr->radius, p->up_axis, total_area,
                       p->threads) != BBC_OK) {
      free(faces);
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory for the grid");
      break;
    }
    pr->grid_cells = (size_t)g.n_theta * g.n_phi * g.n_rho;
    dual_grid_accumulate(&g, faces, NULL, n, +1, &cb);
    bbc__progress(&cb, "grid", 1.0);
    if (bbc__cancelled(&cb)) {
      dual_grid_free(&g);
      free(faces);
      r = bbc__fail(err, BBC_ERROR_CANCELLED, "plane selection: cancelled");
      break;
    }
    double t1 = bbc__now_s();
    select_result sr;
    r = select_planes(faces, n, &g, p, pr->epsilon_abs, pr->radius, &cb, &sr);
    double t2 = bbc__now_s();
    pr->step1_s = t1 - t0;
    pr->step2_s = t2 - t1;
    dual_grid_free(&g);
    free(faces);
    if (r == BBC_ERROR_CANCELLED) {
      bbc__fail(err, r, "plane selection: cancelled");
      break;
    }
    if (r != BBC_OK) {
      bbc__fail(err, r, "plane selection failed: %s", bbc_result_string(r));
      break;
    }
    /* Merge: the model's frame and global plane indices. */
    bbc_plane *planes = realloc(set->planes, (set->plane_count + sr.plane_count) * sizeof *planes);
    if (!planes) {
      select_result_free(&sr);
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "plane selection: out of memory");
      break;
    }
    set->planes = planes;
    size_t base = set->plane_count;
    for (size_t k = 0; k < sr.plane_count; k++) {
      bbc_plane pl = sr.planes[k];
      pl.d += pl.normal[0] * pr->center[0] + pl.normal[1] * pr->center[1] +
              pl.normal[2] * pr->center[2];
      pl.part = (uint32_t)pi;
      if (pl.mother >= 0) pl.mother += (int32_t)base;
      planes[base + k] = pl;
    }
    for (size_t i = 0; i < n; i++) set->face_plane[tris[i]] = (uint32_t)(base + sr.face_plane[i]);
    set->plane_count += sr.plane_count;
    pr->plane_count = sr.plane_count;
    select_result_free(&sr);
    bbc__progress(&cb, "select", 1.0);
  }
  free(tris);
  if (r != BBC_OK) bbc_planeset_free(set);
  return r;
}

bbc_result bbc_planes_find(const bbc_mesh *mesh, const bbc_planes_options *o, bbc_planeset *set,
                           bbc_error *err) {
  double scale = 1, retry = 0;
  int maxp = o->params.max_planes, minp = o->params.min_planes, grown = 0;
  if (minp > 0 && maxp > 0 && minp > maxp)
    bbc__log(&o->callbacks, BBC_LOG_WARNING, "minplanes %d is above maxplanes %d: ignored", minp,
             maxp);
  bbc_planeset best; /* shrinking: the last result within maxplanes */
  int have_best = 0;
  memset(&best, 0, sizeof best);
  for (int attempt = 1;; attempt++) {
    double t0 = bbc__now_s();
    bbc_result r = find_once(mesh, o, scale, attempt, set, err);
    if (r != BBC_OK) {
      if (have_best) bbc_planeset_free(&best);
      return r;
    }
    set->epsilon_scale = scale;
    set->attempts = attempt;
    set->retry_s = retry;
    size_t n = set->plane_count;
    if (have_best && maxp > 0 && n > (size_t)maxp) {
      /* Shrinking went one step too far: the previous result it is. */
      retry += bbc__now_s() - t0;
      bbc_planeset_free(set);
      *set = best;
      set->attempts = attempt;
      set->retry_s = retry;
      return BBC_OK;
    }
    if (have_best) bbc_planeset_free(&best);
    have_best = 0;
    double f = 0;
    if (maxp > 0 && n > (size_t)maxp && attempt < 12 &&
        o->params.epsilon_pct * scale < 99) { /* epsilon's own range ends at 99 % */
      /* Too many planes: grow epsilon by a factor that follows the excess
       * (planes fall roughly with epsilon^1.5), between 1.25 and 2. */
      f = pow((double)n / maxp, 1.0 / 1.5);
      f = f < 1.25 ? 1.25 : f > 2 ? 2 : f;
      grown = 1;
    } else if (minp > 0 && n < (size_t)minp && !grown && scale > 0.2 &&
               (maxp <= 0 || minp <= maxp)) {
      /* Few planes: a smaller epsilon buys fidelity within the budget. */
      f = 1.0 / fmin(2.0, fmax(1.25, pow((double)minp / (double)(n ? n : 1), 1.0 / 1.5)));
      best = *set;
      have_best = 1;
    }
    if (f == 0) {
      if (maxp > 0 && n > (size_t)maxp)
        bbc__log(&o->callbacks, BBC_LOG_WARNING,
                 "%zu planes after %d tries (maxplanes %d): keeping them", n, attempt, maxp);
      return BBC_OK;
    }
    bbc__log(&o->callbacks, BBC_LOG_INFO, "%zu planes at epsilon %.3g %%, %s %d: trying %.3g %%", n,
             o->params.epsilon_pct * scale, f > 1 ? "more than maxplanes" : "fewer than minplanes",
             f > 1 ? maxp : minp, o->params.epsilon_pct * scale * f);
    scale *= f;
    if (!have_best) bbc_planeset_free(set);
    memset(set, 0, sizeof *set);
    retry += bbc__now_s() - t0;
  }
}
