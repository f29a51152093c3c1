/* session.c — BBCgen's workflow (thesis Appendix A): a model, its planes
 * and its cloud kept between steps, with the parameter classes deciding
 * what a change needs. Every step builds into new state and replaces the
 * old only when it is whole, so a failed or cancelled step leaves the
 * session as it was. */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct bbc_session {
  int have_model, have_planes, have_cloud;
  bbc_mesh model;
  bbc_grid *grid;
  bbc_planeset planes;
  bbc_cloud cloud;
  bbc_planes_options planned; /* the options the planes were found with ... */
  char text[3][4096];         /* ... and copies of its split patterns */
};

static void remember(bbc_session *s, const bbc_planes_options *options) {
  bbc__planes_options_copy(&s->planned, s->text, options);
}

bbc_session *bbc_session_new(void) {
  return calloc(1, sizeof(bbc_session));
}

static void drop_cloud(bbc_session *s) {
  if (s->have_cloud) bbc_cloud_free(&s->cloud);
  s->have_cloud = 0;
}

static void drop_planes(bbc_session *s) {
  drop_cloud(s);
  if (s->have_planes) bbc_planeset_free(&s->planes);
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
  bbc_result r = bbc_mesh_load(path, options, &m, err);
  if (r != BBC_OK) return r;
  drop_grid(s);
  if (s->have_model) bbc_mesh_free(&s->model);
  s->model = m;
  s->have_model = 1;
  return BBC_OK;
}

int bbc_session_stale(const bbc_session *s, const bbc_planes_options *options, const char **which) {
  if (which) *which = NULL;
  if (!s->have_planes) return -1;
  return bbc_planes_options_first_step(&s->planned, options, which);
}

int bbc_session_grid_stale(const bbc_session *s, const bbc_planes_options *options,
                           const char **which) {
  if (which) *which = NULL;
  if (!s->grid) return -1;
  return bbc_planes_options_first_step(bbc__grid_options(s->grid), options, which) == 1;
}

bbc_result bbc_session_grid(bbc_session *s, const bbc_planes_options *options, bbc_error *err) {
  if (!s->have_model)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "step 1 needs a model: load one");
  bbc_grid *g;
  bbc_result r = bbc_grid_build(&s->model, options, &g, err);
  if (r != BBC_OK) return r;
  drop_grid(s);
  s->grid = g;
  return BBC_OK;
}

bbc_result bbc_session_planes(bbc_session *s, const bbc_planes_options *options, bbc_error *err) {
  if (!s->have_model)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "step 2 needs a model: load one");
  const char *which = NULL;
  int stale = bbc_session_grid_stale(s, options, &which);
  if (stale < 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "step 2 needs the grid of step 1 first");
  if (stale)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "%s changed since step 1, and it needs step 1 again", which);
  bbc_planeset set;
  bbc_result r = bbc_planes_select(s->grid, options, &set, err);
  if (r != BBC_OK) return r;
  drop_planes(s);
  s->planes = set;
  s->have_planes = 1;
  remember(s, options);
  return BBC_OK;
}

bbc_result bbc_session_cloud(bbc_session *s, const bbc_planes_options *options, bbc_error *err) {
  if (!s->have_planes)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "step 3 needs the planes of steps 1 and 2 first");
  const char *which = NULL;
  int step = bbc_session_stale(s, options, &which);
  if (step == 1 || step == 2)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "%s changed since the planes were found, and it needs step %d again", which,
                     step);
  bbc_cloud c;
  bbc_result r =
      bbc_cloud_build(&s->model, &s->planes, &options->params, &options->callbacks, &c, err);
  if (r != BBC_OK) return r;
  drop_cloud(s);
  s->cloud = c;
  s->have_cloud = 1;
  return BBC_OK;
}

bbc_result bbc_session_run(bbc_session *s, const bbc_planes_options *options, bbc_error *err) {
  if (!s->have_model)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "steps 1 to 3 need a model: load one");
  /* every step into new state first: a failure keeps the old grid, planes
   * and cloud */
  bbc_grid *g;
  bbc_result r = bbc_grid_build(&s->model, options, &g, err);
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
  s->planes = set;
  s->have_planes = 1;
  s->cloud = c;
  s->have_cloud = 1;
  remember(s, options);
  return BBC_OK;
}

const bbc_mesh *bbc_session_model(const bbc_session *s) {
  return s->have_model ? &s->model : NULL;
}

const bbc_grid *bbc_session_grid_get(const bbc_session *s) {
  return s->grid;
}

const bbc_planeset *bbc_session_planeset(const bbc_session *s) {
  return s->have_planes ? &s->planes : NULL;
}

const bbc_cloud *bbc_session_result(const bbc_session *s) {
  return s->have_cloud ? &s->cloud : NULL;
}
