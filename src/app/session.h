/* session.h — the session's state, shared by session.c (the steps) and
 * what is written of them: output.c (cloud files), report.c (the JSON
 * report) and preview.c (the preview sheet); internal. */
#ifndef BBC_SESSION_H
#define BBC_SESSION_H

#include "app.h"
#include "planes.h"

/* One level of detail: its planes, its cloud, what it was made with. */
typedef struct bbc__level {
  bbc_planeset planes;
  bbc_cloud cloud;
  bbc_params params;  /* the cloud's parameters */
  double epsilon_pct; /* the epsilon asked (maxplanes/minplanes may scale it) */
  double screen_px;   /* the tree's height on screen where the level starts; 0 unknown */
} bbc__level;

struct bbc_session {
  int have_model;
  bbc_mesh model;
  char model_path[4096];
  double load_s, write_s;
  bbc_grid *grid;
  /* level 0: the planes (step 2) and the cloud (step 3) the steps work on */
  int have_planes, have_cloud;
  bbc__level level0;
  bbc_planes_options planned; /* the options the planes were found with ... */
  char text[3][4096];         /* ... and copies of its split patterns */
  /* levels 1 .. of a chain (bbc_session_run_levels); gone with level 0's cloud */
  size_t extra_count;
  bbc__level extra[BBC_SESSION_MAX_LEVELS - 1];
  int atlas_shared; /* the chain's levels share one atlas (after a glTF write) */
  int level_files;  /* bbc_session_set_level_files */
};

/* Level k (0 = level0), NULL past the last. */
bbc__level *bbc__session_level(bbc_session *s, size_t k);

/* report.c's JSON for output.c's glTF extras, as unformatted text (free it
 * with cJSON_free; NULL when out of memory): the parameters (all but
 * threads, which never changes a result), and a level's short summary. */
char *bbc__params_json_text(const bbc_params *p);
char *bbc__level_json_text(const bbc__level *L);

#endif
