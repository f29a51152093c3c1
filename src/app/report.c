/* report.c — what bbcgen reports of a session's levels: the note on a
 * moved epsilon, each level's JSON (the short form in a glTF file's
 * extras, the detailed one in the --report file) and the JSON report. */
#include "session.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef app_level job_lod;

/* Which budget moved epsilon (maxplanes raises it, minplanes lowers it), or
 * NULL when the asked epsilon was used. */
static const char *epsilon_adjusted_by(const job_lod *L) {
  double f = L->planes.epsilon_scale;
  return f > 1 ? "maxplanes" : f < 1 ? "minplanes" : NULL;
}

void bbc_session_get_epsilon_note(const bbc_session *s, size_t level, char *buf, size_t n) {
  const job_lod *L = app_session_level((bbc_session *)s, level);
  const char *by = L ? epsilon_adjusted_by(L) : NULL;
  if (!by) {
    if (n) buf[0] = 0;
    return;
  }
  int raised = by[1] == 'a';
  snprintf(buf, n, " (%s from %.3g %% by %s %d)", raised ? "raised" : "lowered", L->epsilon_pct, by,
           raised ? L->params.max_planes : L->params.min_planes);
}

char *app_params_json_text(const bbc_params *p) {
  cJSON *o = cJSON_CreateObject();
  for (size_t i = 0; i < bbc_param_count(); i++) {
    const bbc_param_info *info = bbc_param_at(i);
    /* threads never changes a result: left out, so outputs are identical */
    if (!strcmp(info->name, "threads")) continue;
    cJSON_AddNumberToObject(o, info->name, bbc_params_get(p, info));
  }
  char *s = cJSON_PrintUnformatted(o);
  cJSON_Delete(o);
  return s;
}

/* Steps 1 and 2 summed over the parts. */
static void step_times(const bbc_planeset *set, double *step1_s, double *step2_s) {
  *step1_s = *step2_s = 0;
  for (size_t p = 0; p < set->part_count; p++) {
    *step1_s += set->parts[p].step1_s;
    *step2_s += set->parts[p].step2_s;
  }
}

static cJSON *lod_json(const job_lod *L, int detailed) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "epsilon_pct", L->epsilon_pct);
  /* maxplanes/minplanes may have scaled it: */
  cJSON_AddNumberToObject(o, "epsilon_pct_used", L->epsilon_pct * L->planes.epsilon_scale);
  /* Which budget moved epsilon; "none" rather than null, which some glTF
   * readers warn about in extras. */
  const char *by = epsilon_adjusted_by(L);
  cJSON_AddStringToObject(o, "epsilon_adjusted_by", by ? by : "none");
  cJSON_AddNumberToObject(o, "epsilon", L->planes.epsilon_abs);
  cJSON_AddNumberToObject(o, "planes", (double)L->planes.plane_count);
  cJSON_AddNumberToObject(o, "billboards", (double)L->cloud.billboard_count);
  /* the tree's height on screen where the level starts (a --lod-pixels chain) */
  if (L->screen_px > 0) cJSON_AddNumberToObject(o, "screen_px", L->screen_px);
  cJSON_AddNumberToObject(o, "triangles", (double)L->cloud.mesh.triangle_count);
  cJSON_AddNumberToObject(o, "texels", (double)L->cloud.texels);
  cJSON *kinds = cJSON_AddArrayToObject(o, "kinds");
  for (size_t b = 0; b < L->cloud.billboard_count; b++)
    cJSON_AddItemToArray(kinds,
                         cJSON_CreateString(bbc_plane_kind_name(L->cloud.billboards[b].kind)));
  if (!detailed) return o;
  const bbc_mesh *m = &L->cloud.mesh;
  cJSON_AddNumberToObject(o, "limb_triangles", (double)L->cloud.limb_triangles);
  cJSON_AddNumberToObject(o, "texres_used", L->cloud.texres);
  cJSON_AddNumberToObject(o, "plane_runs", L->planes.attempts);
  cJSON_AddNumberToObject(o, "plane_probe_runs", L->planes.probe_runs);
  cJSON_AddNumberToObject(o, "plane_probe_stride", L->planes.probe_stride);
  cJSON_AddNumberToObject(o, "plane_sample_stride",
                          (double)(L->planes.sample_stride ? L->planes.sample_stride : 1));
  cJSON_AddNumberToObject(o, "plane_beyond_epsilon", (double)L->planes.beyond_count);
  cJSON_AddNumberToObject(o, "plane_beyond_max_epsilons", L->planes.beyond_max);
  cJSON_AddNumberToObject(o, "plane_leftover_planes", (double)L->planes.leftover_planes);
  cJSON *atlas = cJSON_AddArrayToObject(o, "atlas");
  cJSON_AddItemToArray(atlas, cJSON_CreateNumber(m->textures[0].image.width));
  cJSON_AddItemToArray(atlas, cJSON_CreateNumber(m->textures[0].image.height));
  cJSON_AddNumberToObject(o, "atlas_fill", L->cloud.atlas_fill);
  cJSON *t = cJSON_AddObjectToObject(o, "times_s");
  double s1, s2;
  step_times(&L->planes, &s1, &s2);
  cJSON_AddNumberToObject(t, "step1", s1);
  cJSON_AddNumberToObject(t, "step2", s2);
  cJSON_AddNumberToObject(t, "steps12_discarded_runs", L->planes.retry_s);
  cJSON_AddNumberToObject(t, "steps12_probes", L->planes.probe_s);
  cJSON_AddNumberToObject(t, "step3_bake", L->cloud.bake_s);
  cJSON_AddNumberToObject(t, "step3_atlas", L->cloud.atlas_s);
  cJSON *parts = cJSON_AddArrayToObject(o, "parts");
  for (size_t p = 0; p < L->planes.part_count; p++) {
    const bbc_part_result *pr = &L->planes.parts[p];
    cJSON *q = cJSON_CreateObject();
    cJSON_AddStringToObject(q, "name", pr->name);
    cJSON_AddNumberToObject(q, "faces", (double)pr->face_count);
    cJSON_AddNumberToObject(q, "planes", (double)pr->plane_count);
    cJSON_AddNumberToObject(q, "epsilon", pr->epsilon_abs);
    if (pr->limbs > 0) cJSON_AddNumberToObject(q, "limbs", pr->limbs); /* kept as a mesh */
    cJSON_AddItemToArray(parts, q);
  }
  cJSON_AddStringToObject(o, "split", L->planes.split_why);
  cJSON *bbs = cJSON_AddArrayToObject(o, "billboard_list");
  for (size_t b = 0; b < L->cloud.billboard_count; b++) {
    const bbc_cloud_billboard *cb = &L->cloud.billboards[b];
    cJSON *q = cJSON_CreateObject();
    cJSON_AddStringToObject(q, "kind", bbc_plane_kind_name(cb->kind));
    cJSON_AddStringToObject(q, "part", L->planes.parts[cb->part].name);
    cJSON_AddItemToObject(q, "normal", cJSON_CreateDoubleArray(cb->normal, 3));
    cJSON_AddNumberToObject(q, "d", cb->d);
    cJSON_AddNumberToObject(q, "width", cb->rect.width);
    cJSON_AddNumberToObject(q, "height", cb->rect.height);
    int tex[2] = {cb->tex_width, cb->tex_height};
    cJSON_AddItemToObject(q, "texture", cJSON_CreateIntArray(tex, 2));
    cJSON_AddNumberToObject(q, "faces_drawn", (double)cb->face_count);
    cJSON_AddNumberToObject(q, "corners", cb->corner_count);
    cJSON_AddItemToArray(bbs, q);
  }
  return o;
}

char *app_level_json_text(const app_level *L) {
  cJSON *o = lod_json(L, 0);
  char *text = cJSON_PrintUnformatted(o);
  cJSON_Delete(o);
  return text;
}

bbc_result bbc_session_write_report(const bbc_session *s, const char *out, const char *cloud_path,
                                    bbc_error *err) {
  size_t count = bbc_session_get_level_count(s);
  if (!count)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "no Billboard Cloud to report: run step 3");
  const job_lod *lods[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) lods[k] = app_session_level((bbc_session *)s, k);
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "generator", "bbcgen " BBC_VERSION_STRING);
  cJSON_AddStringToObject(o, "model", s->model_path);
  if (cloud_path) cJSON_AddStringToObject(o, "output", cloud_path);
  cJSON_AddNumberToObject(o, "model_triangles", (double)s->model.triangle_count);
  if (s->model.kind == BBC_MESH_POINTS)
    cJSON_AddNumberToObject(o, "model_points", (double)s->model.vertex_count);
  cJSON_AddNumberToObject(o, "model_radius", s->model.radius);
  /* What the cloud's colours carry (docs/lighting.md). */
  cJSON_AddStringToObject(o, "lighting", bbc_params_lighting_name(&lods[0]->params));
  char *params = app_params_json_text(&lods[0]->params);
  cJSON_AddItemToObject(o, "parameters", cJSON_Parse(params));
  cJSON_free(params);
  cJSON *t = cJSON_AddObjectToObject(o, "times_s");
  double total = s->load_s + s->write_s;
  for (size_t k = 0; k < count; k++) {
    double s1, s2;
    step_times(&lods[k]->planes, &s1, &s2);
    total += s1 + s2 + lods[k]->planes.retry_s + lods[k]->cloud.bake_s + lods[k]->cloud.atlas_s;
  }
  cJSON_AddNumberToObject(t, "load", s->load_s);
  cJSON_AddNumberToObject(t, "write", s->write_s);
  cJSON_AddNumberToObject(t, "total", total);
  cJSON_AddBoolToObject(o, "atlas_shared", s->atlas_shared);
  cJSON *lj = cJSON_AddArrayToObject(o, "lods");
  for (size_t k = 0; k < count; k++) cJSON_AddItemToArray(lj, lod_json(lods[k], 1));
  char *text = cJSON_Print(o);
  cJSON_Delete(o);
  if (!text) return bbc_error_set(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", out);
  size_t n = strlen(text);
  char *withnl = malloc(n + 2);
  bbc_result r = BBC_ERROR_OUT_OF_MEMORY;
  if (withnl) {
    memcpy(withnl, text, n);
    withnl[n] = '\n';
    withnl[n + 1] = 0;
    r = bbc_write_file_atomic(out, withnl, n + 1, err);
  } else {
    bbc_error_set(err, r, "%s: out of memory", out);
  }
  free(withnl);
  cJSON_free(text);
  return r;
}
