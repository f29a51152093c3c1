/* session.c — BBCgen's workflow (thesis Appendix A): a model, its planes
 * and its cloud kept between steps, with the parameter classes deciding
 * what a change needs. Every step builds into new state and replaces the
 * old only when it is whole, so a failed or cancelled step leaves the
 * session as it was. */
#include "session.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void remember(bbc_session *s, const bbc_planes_options *options) {
  bbc_planes_options_copy(&s->planned, s->text, options);
}

bbc_session *bbc_session_new(void) {
  return calloc(1, sizeof(bbc_session));
}

static void drop_extra(bbc_session *s) {
  for (size_t k = 0; k < s->extra_count; k++) {
    bbc_planeset_free(&s->extra[k].planes);
    bbc_cloud_free(&s->extra[k].cloud);
  }
  s->extra_count = 0;
  s->atlas_shared = 0;
}

static void drop_cloud(bbc_session *s) {
  drop_extra(s);
  if (s->have_cloud) bbc_cloud_free(&s->level0.cloud);
  s->have_cloud = 0;
}

double app_now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

app_level *app_session_level(bbc_session *s, size_t k) {
  if (!s->have_cloud) return NULL;
  if (k == 0) return &s->level0;
  return k - 1 < s->extra_count ? &s->extra[k - 1] : NULL;
}

/* Level 0's cloud made with `params`. */
static void set_cloud(bbc_session *s, const bbc_cloud *c, const bbc_params *params) {
  s->level0.cloud = *c;
  s->level0.params = *params;
  s->level0.epsilon_pct = params->epsilon_pct;
  s->level0.screen_px = 0;
  s->have_cloud = 1;
}

static void drop_planes(bbc_session *s) {
  drop_cloud(s);
  if (s->have_planes) bbc_planeset_free(&s->level0.planes);
  s->have_planes = 0;
}

static void drop_grid(bbc_session *s) {
  drop_planes(s);
  bbc_grid_free(s->grid);
  s->grid = NULL;
}

void bbc_session_free(bbc_session *s) {
  if (!s) return;
  drop_grid(s);
  if (s->have_model) bbc_mesh_free(&s->model);
  free(s);
}

bbc_result bbc_session_load(bbc_session *s, const char *path, const bbc_load_options *options,
                            bbc_error *err) {
  bbc_mesh m;
  double t0 = app_now_s();
  bbc_result r = bbc_mesh_load(path, options, &m, err);
  if (r != BBC_OK) return r;
  drop_grid(s);
  if (s->have_model) bbc_mesh_free(&s->model);
  s->model = m;
  s->have_model = 1;
  snprintf(s->model_path, sizeof s->model_path, "%s", path);
  s->load_s = app_now_s() - t0;
  return BBC_OK;
}

int bbc_session_stale_step(const bbc_session *s, const bbc_planes_options *options,
                           const char **which) {
  if (which) *which = NULL;
  if (!s->have_planes) return -1;
  return bbc_planes_options_stale_step(&s->planned, options, which);
}

int bbc_session_grid_stale_step(const bbc_session *s, const bbc_planes_options *options,
                                const char **which) {
  if (which) *which = NULL;
  if (!s->grid) return -1;
  return bbc_planes_options_stale_step(bbc_grid_get_options(s->grid), options, which) == 1;
}

bbc_result bbc_session_build_grid(bbc_session *s, const bbc_planes_options *options,
                                  bbc_error *err) {
  if (!s->have_model)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "step 1 needs a model: load one");
  bbc_grid *g;
  bbc_result r = bbc_grid_build(&s->model, options, &g, err);
  if (r != BBC_OK) return r;
  drop_grid(s);
  s->grid = g;
  return BBC_OK;
}

bbc_result bbc_session_select_planes(bbc_session *s, const bbc_planes_options *options,
                                     bbc_error *err) {
  if (!s->have_model)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "step 2 needs a model: load one");
  const char *which = NULL;
  int stale = bbc_session_grid_stale_step(s, options, &which);
  if (stale < 0)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "step 2 needs the grid of step 1 first");
  if (stale)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "%s changed since step 1, and it needs step 1 again", which);
  bbc_planeset set;
  bbc_result r = bbc_planes_select(s->grid, options, &set, err);
  if (r != BBC_OK) return r;
  drop_planes(s);
  s->level0.planes = set;
  s->have_planes = 1;
  remember(s, options);
  return BBC_OK;
}

bbc_result bbc_session_build_cloud(bbc_session *s, const bbc_planes_options *options,
                                   bbc_error *err) {
  if (!s->have_planes)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "step 3 needs the planes of steps 1 and 2 first");
  const char *which = NULL;
  int step = bbc_session_stale_step(s, options, &which);
  if (step == 1 || step == 2)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "%s changed since the planes were found, and it needs step %d again",
                         which, step);
  bbc_cloud c;
  bbc_result r =
      bbc_cloud_build(&s->model, &s->level0.planes, &options->params, &options->callbacks, &c, err);
  if (r != BBC_OK) return r;
  drop_cloud(s);
  set_cloud(s, &c, &options->params);
  return BBC_OK;
}

bbc_result bbc_session_run(bbc_session *s, const bbc_planes_options *options, bbc_error *err) {
  if (!s->have_model)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "steps 1 to 3 need a model: load one");
  /* every step into new state first: a failure keeps the old grid, planes
   * and cloud */
  bbc_grid *g;
  bbc_result r = bbc_grid_build_for_select(&s->model, options, &g, err);
  if (r != BBC_OK) return r;
  bbc_planeset set;
  r = bbc_planes_select(g, options, &set, err);
  if (r != BBC_OK) {
    bbc_grid_free(g);
    return r;
  }
  bbc_cloud c;
  r = bbc_cloud_build(&s->model, &set, &options->params, &options->callbacks, &c, err);
  if (r != BBC_OK) {
    bbc_planeset_free(&set);
    bbc_grid_free(g);
    return r;
  }
  drop_grid(s);
  s->grid = g;
  s->level0.planes = set;
  s->have_planes = 1;
  set_cloud(s, &c, &options->params);
  remember(s, options);
  return BBC_OK;
}

bbc_result bbc_session_run_levels(bbc_session *s, const bbc_planes_options *options,
                                  const double *epsilons, size_t count, bbc_error *err) {
  if (!epsilons || !count) return bbc_session_run(s, options, err);
  if (count > BBC_SESSION_MAX_LEVELS)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "at most %d levels of detail",
                         BBC_SESSION_MAX_LEVELS);
  bbc_lod_level lv[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) lv[k] = (bbc_lod_level){epsilons[k], 0, 0};
  return bbc_session_run_chain(s, options, lv, count, err);
}

/* Triangles a level draws: its billboards' and its limbs'. */
static size_t level_triangles(const app_level *L) {
  return L->cloud.mesh.triangle_count;
}

/* Steps 1 to 3 of one level at epsilon `eps` (texres as `o` says); the grid
 * is kept in *g for level 0. */
static bbc_result run_one_level(bbc_session *s, bbc_planes_options *o, double eps, app_level *L,
                                bbc_grid **g, bbc_error *err) {
  double base = o->params.epsilon_pct;
  o->params.epsilon_pct = eps;
  for (size_t i = 0; i < o->part_override_count; i++) /* a part's own epsilon stays */
    if (o->part_overrides[i].params.epsilon_pct == base)
      o->part_overrides[i].params.epsilon_pct = eps;
  bbc_result r = bbc_grid_build_for_select(&s->model, o, g, err);
  if (r != BBC_OK) return r;
  r = bbc_planes_select(*g, o, &L->planes, err);
  if (r == BBC_OK) {
    r = bbc_cloud_build(&s->model, &L->planes, &o->params, &o->callbacks, &L->cloud, err);
    if (r != BBC_OK) bbc_planeset_free(&L->planes);
  }
  if (r != BBC_OK) {
    bbc_grid_free(*g);
    *g = NULL;
    return r;
  }
  L->params = o->params;
  L->epsilon_pct = eps;
  return BBC_OK;
}

static void free_level(app_level *L) {
  bbc_planeset_free(&L->planes);
  bbc_cloud_free(&L->cloud);
}

static int floor_pow2_int(double x) {
  int t = 4;
  while (t * 2 <= x && t < 8192) t *= 2;
  return t;
}

/* A level made for P pixels on screen: at most max(32, P^2/64) triangles
 * (maxtris, unless a smaller one is asked). The limbs' mesh gets half of
 * them, none under 32 (then the stem on two crossed billboards at most);
 * the planes at most what is left in quads. */
static void level_budget(double px, bbc_params *p) {
  /* outline auto: tight outlines where they save fragments (a tree of
   * 520 pixels: 7 % fewer; of 130: 4 % more, counted on llvmpipe) */
  if (p->outline < 0) p->outline = px >= 384 ? 8 : 0;
  int budget = (int)fmax(32, floor(px * px / 64));
  if (p->max_tris <= 0 || p->max_tris > budget) p->max_tris = budget;
  budget = p->max_tris;
  if (p->limbs > 0) {
    int limbs = budget / 2 >= 32 ? budget / 2 : 0;
    if (limbs < p->limbs) p->limbs = limbs;
    if (!p->limbs && p->stem > 2) p->stem = 2; /* the trunk on two crossed billboards */
  }
  /* fewer than 16 quads a side: each billboard one double-sided quad
   * (twice the planes; at such sizes a side's own image shows nothing
   * the other's does not) */
  if (p->back_images && (budget - p->limbs) / 4 < 16) p->back_images = 0;
  int cap = (budget - p->limbs) / (p->back_images ? 4 : 2) - (p->limbs ? 0 : p->stem);
  if (cap < 1) cap = 1;
  if (p->max_planes <= 0 || p->max_planes > cap) p->max_planes = cap;
  if (p->min_planes > p->max_planes) p->min_planes = p->max_planes;
}

/* Level k's options: its epsilon (given, else the level before's as used
 * times (its size / this size)^(1/8), the plane budgets off) and texres
 * (given; else for a screen size at most a texel a pixel there and, past
 * level 0, at most half the level before's; level 0 otherwise by the atlas
 * budget). */
static double level_options(const bbc_planes_options *options, const bbc_lod_level *levels,
                            size_t k, const app_level *prev, bbc_planes_options *o) {
  *o = *options;
  double eps = levels[k].epsilon_pct > 0 ? levels[k].epsilon_pct : o->params.epsilon_pct;
  if (k && levels[k].epsilon_pct <= 0) {
    double step = levels[k - 1].screen_px > 0 && levels[k].screen_px > 0
                      ? pow(levels[k - 1].screen_px / levels[k].screen_px, 0.125)
                      : 1.5;
    eps = fmin(99, prev->epsilon_pct * prev->planes.epsilon_scale * step);
    o->params.max_planes = o->params.min_planes = 0;
  }
  /* refine judges the alpha at the size the level is shown at (at most 256) */
  if (levels[k].screen_px > 0 && levels[k].screen_px < o->params.refine_size)
    o->params.refine_size = (int)fmax(16, levels[k].screen_px);
  if (levels[k].texres > 0) {
    o->params.texres = levels[k].texres;
    o->params.atlas_max = 0;
  } else if (k && levels[k].screen_px > 0) {
    int t = floor_pow2_int(levels[k].screen_px);
    if (t > prev->cloud.texres / 2) t = prev->cloud.texres / 2 < 4 ? 4 : prev->cloud.texres / 2;
    o->params.texres = t;
    o->params.atlas_max = 0;
  }
  if (levels[k].screen_px > 0) level_budget(levels[k].screen_px, &o->params);
  return eps;
}

/* Step 3 again at `texres` (the planes kept). */
static bbc_result rebake(bbc_session *s, app_level *L, int texres, const bbc_callbacks *cb,
                         bbc_error *err) {
  bbc_params p = L->params;
  p.texres = texres;
  p.atlas_max = 0;
  bbc_cloud c;
  bbc_result r = bbc_cloud_build(&s->model, &L->planes, &p, cb, &c, err);
  if (r != BBC_OK) return r;
  bbc_cloud_free(&L->cloud);
  L->cloud = c;
  L->params = p;
  return BBC_OK;
}

bbc_result bbc_session_run_chain(bbc_session *s, const bbc_planes_options *options,
                                 const bbc_lod_level *levels, size_t count, bbc_error *err) {
  if (!levels || !count) return bbc_session_run(s, options, err);
  if (count > BBC_SESSION_MAX_LEVELS)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "at most %d levels of detail",
                         BBC_SESSION_MAX_LEVELS);
  for (size_t k = 1; k < count; k++)
    if ((levels[k].epsilon_pct > 0 && levels[k].epsilon_pct <= levels[k - 1].epsilon_pct) ||
        (levels[k].screen_px > 0 && levels[k].screen_px >= levels[k - 1].screen_px) ||
        levels[k].epsilon_pct < 0)
      return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                           "the levels' epsilons must increase and their screen sizes fall "
                           "(finest first)");
  if (!s->have_model)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "steps 1 to 3 need a model: load one");
  /* every level into new state first: a failure keeps the session as it was */
  app_level lv[BBC_SESSION_MAX_LEVELS];
  memset(lv, 0, sizeof lv);
  bbc_grid *g0 = NULL;
  bbc_result r = BBC_OK;
  size_t made = 0;
  bbc_planes_options o0;
  for (size_t k = 0; k < count && r == BBC_OK; k++) {
    bbc_planes_options o;
    double eps = level_options(options, levels, k, k ? &lv[k - 1] : NULL, &o);
    bbc_label lab;
    if (count > 1)
      bbc_callbacks_label(&options->callbacks, &lab, &o.callbacks, "level %zu of %zu", k + 1,
                          count);
    bbc_grid *g = NULL;
    const bbc_planes_options level = o; /* run_one_level writes the epsilon into o */
    r = run_one_level(s, &o, eps, &lv[k], &g, err);
    /* triangles fall: a coarser epsilon until they do */
    while (r == BBC_OK && k && level_triangles(&lv[k]) >= level_triangles(&lv[k - 1]) && eps < 99) {
      free_level(&lv[k]);
      bbc_grid_free(g);
      g = NULL;
      eps = fmin(99, eps * 1.5);
      o = level;
      o.params.max_planes = o.params.min_planes = 0;
      r = run_one_level(s, &o, eps, &lv[k], &g, err);
    }
    /* within its triangle budget: a sampled part's leftovers' planes come
     * on top of maxplanes, so fewer planes until it is */
    for (bbc_planes_options fewer = level;
         r == BBC_OK && fewer.params.max_tris > 0 && fewer.params.max_planes > 1 &&
         level_triangles(&lv[k]) > (size_t)fewer.params.max_tris;) {
      size_t quad = fewer.params.back_images ? 4 : 2;
      size_t cut = (level_triangles(&lv[k]) - (size_t)fewer.params.max_tris + quad - 1) / quad;
      fewer.params.max_planes =
          (size_t)fewer.params.max_planes > cut + 1 ? fewer.params.max_planes - (int)cut : 1;
      if (fewer.params.min_planes > fewer.params.max_planes)
        fewer.params.min_planes = fewer.params.max_planes;
      free_level(&lv[k]);
      bbc_grid_free(g);
      g = NULL;
      o = fewer;
      r = run_one_level(s, &o, eps, &lv[k], &g, err);
    }
    /* level 0 at most a texel a pixel where it starts */
    if (r == BBC_OK && !k && levels[0].texres <= 0 && levels[0].screen_px > 0 &&
        lv[0].cloud.texres > floor_pow2_int(levels[0].screen_px))
      r = rebake(s, &lv[0], floor_pow2_int(levels[0].screen_px), &o.callbacks, err);
    /* texels fall: half the texres until they do */
    while (r == BBC_OK && k && lv[k].cloud.texels >= lv[k - 1].cloud.texels &&
           lv[k].cloud.texres > 4)
      r = rebake(s, &lv[k], lv[k].cloud.texres / 2, &o.callbacks, err);
    if (k == 0 && r == BBC_OK) {
      o0 = o;
      g0 = g;
    } else {
      bbc_grid_free(g);
    }
    if (r != BBC_OK) { /* both free on failure; zeroed, lv[k] frees as nothing */
      free_level(&lv[k]);
      break;
    }
    lv[k].screen_px = levels[k].screen_px;
    made = k + 1;
  }
  if (r != BBC_OK) {
    for (size_t k = 0; k < made; k++) free_level(&lv[k]);
    bbc_grid_free(g0);
    return r;
  }
  drop_grid(s);
  s->grid = g0;
  s->level0 = lv[0];
  s->have_planes = s->have_cloud = 1;
  remember(s, &o0);
  for (size_t k = 1; k < count; k++) s->extra[k - 1] = lv[k];
  s->extra_count = count - 1;
  return BBC_OK;
}

double bbc_session_get_level_screen_px(const bbc_session *s, size_t k) {
  const app_level *L = app_session_level((bbc_session *)s, k);
  return L ? L->screen_px : 0;
}

void bbc_session_set_level_files(bbc_session *s, int on) {
  s->level_files = on != 0;
}

size_t bbc_session_get_level_count(const bbc_session *s) {
  return s->have_cloud ? 1 + s->extra_count : 0;
}

const bbc_cloud *bbc_session_get_level(const bbc_session *s, size_t k, const bbc_planeset **planes,
                                       const bbc_params **params, double *epsilon_pct) {
  const app_level *L = app_session_level((bbc_session *)s, k);
  if (planes) *planes = L ? &L->planes : NULL;
  if (params) *params = L ? &L->params : NULL;
  if (epsilon_pct) *epsilon_pct = L ? L->epsilon_pct : 0;
  return L ? &L->cloud : NULL;
}

const char *bbc_session_get_model_path(const bbc_session *s) {
  return s->have_model ? s->model_path : NULL;
}

void bbc_session_get_times(const bbc_session *s, double *load_s, double *write_s) {
  if (load_s) *load_s = s->load_s;
  if (write_s) *write_s = s->write_s;
}

const bbc_mesh *bbc_session_get_model(const bbc_session *s) {
  return s->have_model ? &s->model : NULL;
}

const bbc_grid *bbc_session_get_grid(const bbc_session *s) {
  return s->grid;
}

const bbc_planeset *bbc_session_get_planes(const bbc_session *s) {
  return s->have_planes ? &s->level0.planes : NULL;
}

const bbc_cloud *bbc_session_get_cloud(const bbc_session *s) {
  return s->have_cloud ? &s->level0.cloud : NULL;
}
