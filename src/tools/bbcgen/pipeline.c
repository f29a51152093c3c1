/* pipeline.c — what bbcgen says and checks around the application layer's
 * session: the info line of each level, output folders checked before work,
 * the files written. The steps and the writers are the application layer's
 * (bbc_session_*, src/app/session.c and output.c), so the tests drive the
 * same workflow bbcgen does. */
#include "pipeline.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

void session_info(const cli *c, const bbc_session *s, size_t k, int kept) {
  const bbc_planeset *set = NULL;
  const bbc_params *params = NULL;
  double eps = 0;
  const bbc_cloud *cloud = bbc_session_get_level(s, k, &set, &params, &eps);
  if (!cloud) {
    set = bbc_session_get_planes(s);
    if (!set) return;
    eps = c->params.epsilon_pct;
  }
  double s1 = 0, s2 = 0;
  for (size_t p = 0; p < set->part_count; p++) {
    s1 += set->parts[p].step1_s;
    s2 += set->parts[p].step2_s;
  }
  char why[160] = "";
  if (cloud)
    bbc_session_get_epsilon_note(s, k, why, sizeof why);
  else if (set->epsilon_scale != 1)
    snprintf(why, sizeof why, " (%s from %.3g %% by %s %d)",
             set->epsilon_scale > 1 ? "raised" : "lowered", eps,
             set->epsilon_scale > 1 ? "maxplanes" : "minplanes",
             set->epsilon_scale > 1 ? c->params.max_planes : c->params.min_planes);
  const char *runs = set->attempts > 1 ? " in several runs" : "";
  if (!cloud) {
    cli_info(c, "epsilon %.3g %%%s: %zu planes; %s %.2f s%s", eps * set->epsilon_scale, why,
             set->plane_count, kept ? "step 2 on the kept grid" : "steps 1+2",
             (kept ? 0 : s1) + s2 + set->retry_s, runs);
    return;
  }
  const bbc_image *a = &cloud->mesh.textures[0].image;
  char steps[96];
  if (kept)
    snprintf(steps, sizeof steps, "steps 1+2 kept");
  else
    snprintf(steps, sizeof steps, "steps 1+2 %.2f s%s", s1 + s2 + set->retry_s, runs);
  cli_info(c,
           "epsilon %.3g %%%s: %zu planes, %zu billboards, texres %d, atlas %dx%d (%.0f %% "
           "filled); %s, step 3 %.2f s",
           eps * set->epsilon_scale, why, set->plane_count, cloud->billboard_count, cloud->texres,
           a->width, a->height, 100 * cloud->atlas_fill, steps, cloud->bake_s + cloud->atlas_s);
}

int session_run(const cli *c, bbc_session *s, const char *model, const bbc_lod_level *levels,
                size_t count) {
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  bbc_error err;
  if (bbc_session_load(s, model, &lo, &err) != BBC_OK) return cli_fail(&err, 0);
  if (bbc_session_run_chain(s, &po, levels, levels ? count : 0, &err) != BBC_OK)
    return cli_fail_in(model, &err, 0); /* the message names the model */
  for (size_t k = 0; k < bbc_session_get_level_count(s); k++) session_info(c, s, k, 0);
  return EXIT_OK;
}

/* "wrote ..." for each level's file. */
static void wrote(const cli *c, const bbc_session *s, const char *out) {
  const char *ext = strrchr(out, '.');
  int one_file =
      ext && (!strcasecmp(ext, ".glb") || !strcasecmp(ext, ".gltf") || !strcasecmp(ext, ".fbx"));
  for (size_t k = 0; k < bbc_session_get_level_count(s); k++) {
    const bbc_planeset *set;
    double eps;
    const bbc_cloud *cl = bbc_session_get_level(s, k, &set, NULL, &eps);
    char path[4200];
    bbc_session_get_output_path(out, one_file ? 0 : k, path, sizeof path);
    double px = bbc_session_get_level_screen_px(s, k);
    char at[64] = "";
    if (px > 0) snprintf(at, sizeof at, ", from %.0f px", px);
    if (one_file && bbc_session_get_level_count(s) > 1)
      snprintf(path + strlen(path), sizeof path - strlen(path), " level %zu", k);
    cli_info(c, "wrote %s: %zu billboards, %zu triangles, %zu texels (epsilon %.3g %%%s)", path,
             cl->billboard_count, cl->mesh.triangle_count, cl->texels, eps * set->epsilon_scale,
             at);
    if (one_file && c->level_files && bbc_session_get_level_count(s) > 1 &&
        strcasecmp(ext, ".fbx")) {
      bbc_session_get_level_file_path(out, k, path, sizeof path);
      cli_info(c, "wrote %s", path);
    }
  }
}

int session_write(const cli *c, bbc_session *s, const char *out) {
  const char *ext = strrchr(out, '.');
  int one_file =
      ext && (!strcasecmp(ext, ".glb") || !strcasecmp(ext, ".gltf") || !strcasecmp(ext, ".fbx"));
  for (size_t k = 1; k < bbc_session_get_level_count(s) && !one_file; k++) {
    char path[4200];
    bbc_session_get_output_path(out, k, path, sizeof path);
    if (!cli_output_ok("-o", path)) return EXIT_OUTPUT;
  }
  bbc_error err;
  bbc_session_set_output(s, &c->params);
  bbc_session_set_level_files(s, c->level_files);
  bbc_result r = bbc_session_write(s, out, &c->callbacks, &err);
  if (r != BBC_OK) return cli_fail(&err, r != BBC_ERROR_INVALID_ARGUMENT);
  wrote(c, s, out);
  return EXIT_OK;
}

int session_save(const cli *c, bbc_session *s, const char *user_dir) {
  char path[4600];
  bbc_error err;
  bbc_session_set_output(s, &c->params);
  bbc_result r = bbc_session_save(s, user_dir, &c->callbacks, path, sizeof path, &err);
  if (r != BBC_OK) return cli_fail(&err, r != BBC_ERROR_INVALID_ARGUMENT);
  wrote(c, s, path);
  return EXIT_OK;
}
