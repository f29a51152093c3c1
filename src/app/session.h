/* session.h — the session's state, shared by session.c (the steps) and
 * what is written of them: output.c (cloud files), report.c (the JSON
 * report) and preview.c (the preview sheet); internal. */
#ifndef BBC_SESSION_H
#define BBC_SESSION_H

#include "app.h"

#include <stddef.h>

/* One level of detail: its planes, its cloud, what it was made with. */
typedef struct app_level {
  bbc_planeset planes;
  bbc_cloud cloud;
  bbc_params params;  /* the cloud's parameters */
  double epsilon_pct; /* the epsilon asked (maxplanes/minplanes may scale it) */
  double screen_px;   /* the tree's height on screen where the level starts; 0 unknown */
} app_level;

struct bbc_session {
  int have_model;
  bbc_mesh model;
  char model_path[4096];
  double load_s, write_s;
  bbc_grid *grid;
  /* level 0: the planes (step 2) and the cloud (step 3) the steps work on */
  int have_planes, have_cloud;
  app_level level0;
  bbc_planes_options planned; /* the options the planes were found with ... */
  char text[3][4096];         /* ... and copies of its split patterns */
  /* levels 1 .. of a chain (bbc_session_run_levels); gone with level 0's cloud */
  size_t extra_count;
  app_level extra[BBC_SESSION_MAX_LEVELS - 1];
  int atlas_shared; /* the chain's levels share one atlas (after a glTF write) */
  int level_files;  /* bbc_session_set_level_files */
};

/* Level k (0 = level0), NULL past the last. */
app_level *app_session_level(bbc_session *s, size_t k);

/* report.c's JSON for output.c's glTF extras, as unformatted text (free it
 * with cJSON_free; NULL when out of memory): the parameters (all but
 * threads, which never changes a result), and a level's short summary. */
char *app_params_json_text(const bbc_params *p);
char *app_level_json_text(const app_level *L);

/* Seconds from a monotonic clock (the load and write timings). */
double app_now_s(void);

#endif
