/* pipeline.h — steps 1 to 3 on one model for one or more epsilons (levels of
 * detail), and what the tool makes of the result: cloud files, the report,
 * the preview. Shared by `bbcgen MODEL -o OUT` and the batch commands. */
#ifndef BBCGEN_PIPELINE_H
#define BBCGEN_PIPELINE_H

#include "cli.h"

#define JOB_MAX_LODS 8

typedef struct job_lod {
  double epsilon_pct;
  bbc_params params; /* as used */
  bbc_planeset set;
  bbc_cloud cloud;
  double step1_s, step2_s; /* summed over parts */
} job_lod;

typedef struct job {
  char model_path[4096];
  bbc_mesh mesh;
  double load_s, write_s;
  size_t lod_count;
  job_lod lods[JOB_MAX_LODS];
  int atlas_shared; /* glTF LOD chain: the levels share one atlas */
} job;

/* Loads the model and runs steps 1 to 3 for each epsilon (percent; NULL /
 * 0 = the parameters' epsilon). Prints info lines; returns an exit code. On
 * failure the job is freed. */
int job_run(const cli *c, const char *model, const double *epsilons, size_t count, job *j);
/* The info line of steps 1 and 2 (cloud NULL) or of a cloud made with
 * `params` (step3_only: "steps 1+2 kept"; without a cloud: step 1 kept). */
void job_info(const cli *c, const bbc_planeset *set, const bbc_cloud *cloud,
              const bbc_params *params, int step3_only);
/* Loads the model only (no steps). */
int job_load(const cli *c, const char *model, job *j);

void job_free(job *j);

/* Writes the clouds: .glb/.gltf (every LOD a node, MSFT_lod chain), or
 * .obj/.wrl (LOD 0 at OUT, LOD k at OUT with _lodk before the extension). */
int job_write(const cli *c, job *j, const char *out);
/* Parameters, per-stage times, planes, texels, atlas fill, as JSON. */
int job_report(const cli *c, const job *j, const char *out, const char *cloud_path);
/* Original, cloud (LOD 0) and plane outlines from four directions. */
int job_preview(const cli *c, const job *j, const char *out, int cell);

/* Thesis Appendix A `save [dir]`: the folder
 * vrml97models/<dir>/<model>/<model>_eX.XX_texN[_nm][_pl]/<model>.wrl
 * (created as needed) under the current folder. */
int job_save_vrml(const cli *c, job *j, const char *user_dir);

/* `show model` and `show bbc` (cmd_view.c): a window with the viewer over
 * the session's model, grid, planes and `cloud` (may be NULL; bbcload's or
 * the session's); `keys` (may be NULL) script it: key names and
 * shot:FILE.png, the window closing after them. */
int show_window(const cli *c, const bbc_session *session, const bbc_cloud *cloud, int bbc,
                const char *keys);
/* The debug levels (parameter debug >= 1): from begin to end, step 2 shows
 * its picks (1), greedy steps (2) and clusters (3) in a window over `model`
 * (sets o->callbacks.debug). */
void debug_views_begin(const cli *c, const bbc_mesh *model, bbc_planes_options *o);
void debug_views_end(void);

#endif
