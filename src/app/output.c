/* output.c — a session's cloud on disk, exactly as bbcgen writes it: glTF
 * with its LOD chain, OBJ or VRML files, and Appendix A's save folder. The
 * JSON report is report.c's, the preview sheet preview.c's. */
#include "session.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <dirent.h>
#include <stdatomic.h>
#include <sys/stat.h>
#include <unistd.h>

typedef app_level job_lod;

static const char *extension_of(const char *path) {
  const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
  return dot && (!slash || dot > slash) ? dot : path + strlen(path);
}

/* OUT with "_lod<k>" before its extension (k > 0). */
static void lod_path(const char *out, size_t k, char *buf, size_t n) {
  if (k == 0) {
    snprintf(buf, n, "%s", out);
    return;
  }
  const char *ext = extension_of(out);
  snprintf(buf, n, "%.*s_lod%zu%s", (int)(ext - out), out, k, ext);
}

/* The model's file name without folder and extension, safe for names. */
static void model_name(const char *path, char *out, size_t n) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  const char *ext = extension_of(base);
  size_t i = 0;
  for (const char *p = base; p < ext && i + 1 < n; p++, i++) {
    unsigned char ch = (unsigned char)*p;
    out[i] = (char)(isalnum(ch) || ch == '_' || ch == '-' || ch == '.' ? ch : '_');
  }
  out[i] = 0;
  if (!i) snprintf(out, n, "model");
}

void bbc_session_get_level_file_path(const char *out, size_t k, char *buf, size_t n) {
  const char *ext = extension_of(out);
  snprintf(buf, n, "%.*s_LOD%zu%s", (int)(ext - out), out, k, ext);
}

/* OUT and, for OBJ and VRML chains, OUT_lod<k>.EXT: the files a write makes. */
void bbc_session_get_output_path(const char *out, size_t level, char *buf, size_t n) {
  lod_path(out, level, buf, n);
}

void bbc_session_set_output(bbc_session *s, const bbc_params *p) {
  for (size_t k = 0; k < bbc_session_get_level_count(s); k++) {
    app_level *l = app_session_level(s, k);
    l->params.format = p->format;
    l->params.dds = p->dds;
  }
}

/* Names engines understand: <model>_LOD<k> for the levels of a chain, <model>
 * for a single cloud and for the chain's group node; the material
 * "billboards" (a chain's "billboards_LOD<k>"), so texture files are
 * <stem>_billboards.png (bbc_texture_file_name). Here the materials of a
 * chain's levels (and of their limbs) get their level's suffix. */
static void name_chain_materials(job_lod *const *lods, size_t count) {
  for (size_t k = 0; k < count && count > 1; k++) {
    char name[64];
    snprintf(name, sizeof name, "billboards_LOD%zu", k);
    bbc_material *mat = &lods[k]->cloud.mesh.materials[0];
    char *dup = strdup(name);
    if (dup) {
      free(mat->name);
      mat->name = dup;
    }
    if (lods[k]->cloud.mesh.material_count > 1) { /* the limbs' */
      snprintf(name, sizeof name, "limbs_LOD%zu", k);
      mat = &lods[k]->cloud.mesh.materials[1];
      dup = strdup(name);
      if (dup) {
        free(mat->name);
        mat->name = dup;
      }
    }
  }
}

/* One atlas for every level of a glTF chain when they fit the budget
 * (atlasmax, else the largest level's atlas): one texture bind for the
 * whole chain. */
static bbc_result share_chain_atlas(bbc_session *s, job_lod *const *lods, size_t count,
                                    const bbc_callbacks *cb, bbc_error *err) {
  int budget = lods[0]->params.atlas_max;
  for (size_t k = 0; k < count; k++) {
    const bbc_image *a = &lods[k]->cloud.mesh.textures[0].image;
    if (a->width > budget) budget = a->width;
  }
  bbc_cloud clouds[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) clouds[k] = lods[k]->cloud;
  bbc_result r =
      bbc_clouds_share_atlas(clouds, count, budget < 64 ? 64 : budget, &s->atlas_shared, err);
  for (size_t k = 0; k < count; k++) lods[k]->cloud = clouds[k];
  if (r != BBC_OK) return r;
  const bbc_image *a = &lods[0]->cloud.mesh.textures[0].image;
  if (s->atlas_shared)
    bbc_callbacks_log(cb, BBC_LOG_INFO, "the %zu levels share one %dx%d atlas", count, a->width,
                      a->height);
  else
    bbc_callbacks_log(cb, BBC_LOG_INFO,
                      "the levels do not fit one %dx%d atlas together: one atlas each", budget,
                      budget);
  return BBC_OK;
}

/* The levels as one glTF file (.glb when `binary`): a node per level with
 * its JSON in the extras, the parameters (and the origin the coordinates
 * were moved from) in the scene's extras, MSFT_screencoverage between the
 * levels. */
static bbc_result write_gltf_chain(const bbc_session *s, job_lod *const *lods, size_t count,
                                   const char *out, const char *model, int binary, int unlit,
                                   bbc_error *err) {
  char *texts[BBC_SESSION_MAX_LEVELS] = {0}, names[BBC_SESSION_MAX_LEVELS][200];
  bbc_gltf_node nodes[BBC_SESSION_MAX_LEVELS];
  double coverage[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) {
    texts[k] = app_level_json_text(lods[k]);
    if (count > 1)
      snprintf(names[k], sizeof names[k], "%s_LOD%zu", model, k);
    else
      snprintf(names[k], sizeof names[k], "%s", model);
    nodes[k] = (bbc_gltf_node){&lods[k]->cloud.mesh, names[k], texts[k]};
    /* MSFT_screencoverage: with screen sizes (--lod-pixels) level k gives
     * way to level k + 1 where the tree's height on a 1080-line screen
     * falls to level k + 1's size; else where level k + 1's error
     * (epsilon, a share of the bounding radius) is at most 2 pixels. The
     * last level ends at 2 pixels. */
    if (k + 1 < count && lods[k + 1]->screen_px > 0) {
      coverage[k] = fmin(1.0, lods[k + 1]->screen_px / 1080.0);
    } else if (k + 1 < count) {
      double e = lods[k + 1]->epsilon_pct * lods[k + 1]->planes.epsilon_scale / 100;
      coverage[k] = fmin(1.0, 2.0 * 2.0 / (e * 1080.0));
    } else {
      coverage[k] = 2.0 / 1080.0;
    }
    if (k && coverage[k] > coverage[k - 1]) coverage[k] = coverage[k - 1];
  }
  char *params = app_params_json_text(&lods[0]->params);
  size_t n = params ? strlen(params) + 64 : 0;
  char *extras = params ? malloc(n + 128) : NULL;
  if (!extras) { /* the file would lose its parameters: an error, not a quiet loss */
    cJSON_free(params);
    for (size_t k = 0; k < count; k++) cJSON_free(texts[k]);
    return bbc_error_set(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", out);
  }
  const double *og = s->model.origin;
  if (og[0] != 0 || og[1] != 0 || og[2] != 0) /* where the coordinates were */
    snprintf(extras, n + 128,
             "{\"bbcgen_lighting\":\"%s\",\"bbcgen_parameters\":%s,"
             "\"bbcgen_origin\":[%.17g,%.17g,%.17g]}",
             bbc_params_lighting_name(&lods[0]->params), params, og[0], og[1], og[2]);
  else
    snprintf(extras, n + 128, "{\"bbcgen_lighting\":\"%s\",\"bbcgen_parameters\":%s}",
             bbc_params_lighting_name(&lods[0]->params), params);
  bbc_gltf_options go;
  memset(&go, 0, sizeof go);
  go.format = binary ? BBC_GLTF_BINARY : BBC_GLTF_SEPARATE;
  go.extras_json = extras;
  go.lod_chain = 1;
  go.lod_group_name = model;
  go.screen_coverage = coverage;
  go.unlit = unlit;
  bbc_result r = bbc_scene_write_gltf(out, nodes, count, &go, err);
  free(extras);
  cJSON_free(params);
  for (size_t k = 0; k < count; k++) cJSON_free(texts[k]);
  return r;
}

/* The levels as one FBX file: a Model per level named <model>_LOD<k> (the
 * model's name alone for one level), the names Unity and Unreal build LOD
 * groups from. */
static bbc_result write_fbx_chain(job_lod *const *lods, size_t count, const char *out,
                                  const char *model, bbc_error *err) {
  char names[BBC_SESSION_MAX_LEVELS][200];
  bbc_fbx_node nodes[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) {
    if (count > 1)
      snprintf(names[k], sizeof names[k], "%s_LOD%zu", model, k);
    else
      snprintf(names[k], sizeof names[k], "%s", model);
    nodes[k] = (bbc_fbx_node){&lods[k]->cloud.mesh, names[k]};
  }
  return bbc_scene_write_fbx(out, nodes, count, err);
}

/* The levels as OBJ (`obj`) or VRML files, OUT and OUT_lod<k>.EXT, each
 * with a comment naming the model, the epsilon and the origin. */
static bbc_result write_level_files(const bbc_session *s, job_lod *const *lods, size_t count,
                                    const char *out, int obj, int unlit, bbc_error *err) {
  bbc_result r = BBC_OK;
  for (size_t k = 0; k < count && r == BBC_OK; k++) {
    char path[4200];
    lod_path(out, k, path, sizeof path);
    char comment[4600], why[160];
    bbc_session_get_epsilon_note(s, k, why, sizeof why);
    const double *og = s->model.origin;
    char origin[160] = "";
    if (og[0] != 0 || og[1] != 0 || og[2] != 0)
      snprintf(origin, sizeof origin, "\norigin: %.17g %.17g %.17g (add to the coordinates)", og[0],
               og[1], og[2]);
    snprintf(comment, sizeof comment, "model: %s\nepsilon: %.4g %% (%.6g model units)%s%s",
             s->model_path, lods[k]->epsilon_pct * lods[k]->planes.epsilon_scale,
             lods[k]->planes.epsilon_abs, why, origin);
    if (obj) {
      bbc_obj_options oo = {.comment = comment, .unlit = unlit};
      r = bbc_mesh_write_obj(path, &lods[k]->cloud.mesh, &oo, err);
    } else {
      bbc_vrml_options vo = {.format = lods[k]->params.format,
                             .unlit = unlit,
                             .dds = lods[k]->params.dds,
                             .comment = comment};
      r = bbc_cloud_write_vrml(path, &lods[k]->cloud, &vo, err);
    }
  }
  return r;
}

static bbc_result write_levels(bbc_session *s, const char *out, const bbc_callbacks *cb,
                               bbc_error *err) {
  size_t count = bbc_session_get_level_count(s);
  if (!count)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "no Billboard Cloud to write: run step 3");
  job_lod *lods[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) lods[k] = app_session_level(s, k);
  const char *ext = extension_of(out);
  int glb = !strcasecmp(ext, ".glb"), gltf = !strcasecmp(ext, ".gltf"),
      obj = !strcasecmp(ext, ".obj"), wrl = !strcasecmp(ext, ".wrl"),
      fbx = !strcasecmp(ext, ".fbx");
  if (!glb && !gltf && !obj && !wrl && !fbx)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "the output must end in .glb, .gltf, .obj, .wrl or .fbx, not '%s'", out);
  if (fbx && lods[0]->params.occlusion > 0 && !lods[0]->params.prelight)
    bbc_callbacks_log(cb, BBC_LOG_WARNING, "FBX carries no occlusion map (use .glb or .gltf)");
  if (fbx && s->level_files && count > 1)
    bbc_callbacks_log(cb, BBC_LOG_WARNING,
                      "--lod-files makes glTF level files; the .fbx holds every level in one file");
  if (obj && (lods[0]->params.normal_maps || lods[0]->params.occlusion > 0))
    bbc_callbacks_log(cb, BBC_LOG_WARNING,
                      "OBJ output carries no normal or occlusion map (use .glb or .gltf, or "
                      "--lighting baked)");
  if (wrl && lods[0]->params.occlusion > 0 && !lods[0]->params.prelight)
    bbc_callbacks_log(cb, BBC_LOG_WARNING, "VRML carries no occlusion map (use .glb or .gltf)");
  if (wrl && lods[0]->params.normal_maps && lods[0]->params.format == BBC_VRML_97)
    bbc_callbacks_log(cb, BBC_LOG_WARNING,
                      "VRML97 (format 1) carries no normal map: none written (format 0 has them)");
  double t0 = app_now_s();
  bbc_result r = BBC_OK;
  char model[128];
  model_name(s->model_path, model, sizeof model);
  name_chain_materials(lods, count);
  int unlit = bbc_params_is_unlit(&lods[0]->params);
  /* --lod-files: each level a file of its own, with its own atlas */
  for (size_t k = 0; (glb || gltf) && count > 1 && s->level_files && k < count && r == BBC_OK;
       k++) {
    char path[4200], name[160];
    bbc_session_get_level_file_path(out, k, path, sizeof path);
    snprintf(name, sizeof name, "%s_LOD%zu", model, k);
    r = write_gltf_chain(s, &lods[k], 1, path, name, glb, unlit, err);
  }
  if (r != BBC_OK) return r;
  if ((glb || gltf || fbx) && count > 1 && !s->atlas_shared) {
    r = share_chain_atlas(s, lods, count, cb, err);
    if (r != BBC_OK) return r;
  }
  if (glb || gltf)
    r = write_gltf_chain(s, lods, count, out, model, glb, unlit, err);
  else if (fbx)
    r = write_fbx_chain(lods, count, out, model, err);
  else
    r = write_level_files(s, lods, count, out, obj, unlit, err);
  s->write_s = app_now_s() - t0;
  return r;
}

/* ---- one run's files together or not at all ---------------------------------
 * The writers write into a fresh folder beside OUT ("<folder>.bbcgen-<pid>-<k>.tmp/");
 * once every file is there, each is renamed into OUT's folder, the side files
 * (atlases, .bin, .mtl, DDS) first and the outputs last, so that no output
 * names a file that is not there yet; a failure or an interruption before
 * that leaves the folder as it was. */

static atomic_uint g_stage_counter;

/* stage/<name> -> folder/<name> for every file of the stage: `outputs` 0
 * moves the side files, 1 those with the output's extension. */
static int move_staged(const char *stage, const char *folder, const char *ext, int outputs,
                       int dry_run, char *bad, size_t bad_size) {
  DIR *d = opendir(stage);
  if (!d) {
    snprintf(bad, bad_size, "%s", stage);
    return -1;
  }
  int rc = 0;
  struct dirent *e;
  while (rc == 0 && (e = readdir(d))) {
    if (e->d_name[0] == '.' && (!e->d_name[1] || (e->d_name[1] == '.' && !e->d_name[2]))) continue;
    if ((strcasecmp(extension_of(e->d_name), ext) == 0) != outputs) continue;
    char from[4600], to[4600];
    snprintf(from, sizeof from, "%s/%s", stage, e->d_name);
    snprintf(to, sizeof to, "%s%s", folder, e->d_name);
    struct stat st;
    if (dry_run ? stat(to, &st) == 0 && S_ISDIR(st.st_mode) : rename(from, to) != 0) {
      snprintf(bad, bad_size, "%s", to);
      rc = -1;
    }
  }
  closedir(d);
  return rc;
}

static void remove_stage(const char *stage) {
  DIR *d = opendir(stage);
  if (d) {
    struct dirent *e;
    while ((e = readdir(d))) {
      char f[4600];
      snprintf(f, sizeof f, "%s/%s", stage, e->d_name);
      if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) unlink(f);
    }
    closedir(d);
  }
  rmdir(stage);
}

/* err's message names the stage's files by their final names. */
static void unstage_message(bbc_error *err, const char *stage, const char *folder) {
  char *at = strstr(err->message, stage);
  if (!at) return;
  char msg[sizeof err->message + 4300];
  size_t sl = strlen(stage);
  int n = snprintf(msg, sizeof msg, "%.*s%s%s", (int)(at - err->message), err->message, folder,
                   at[sl] == '/' ? at + sl + 1 : at + sl);
  size_t len = n < 0 ? 0 : (size_t)n < sizeof err->message ? (size_t)n : sizeof err->message - 1;
  memcpy(err->message, msg, len);
  err->message[len] = 0;
}

bbc_result bbc_session_write(bbc_session *s, const char *out, const bbc_callbacks *cb,
                             bbc_error *err) {
  const char *slash = strrchr(out, '/');
  const char *base = slash ? slash + 1 : out;
  char folder[4200], stage[4300], staged_out[4600];
  snprintf(folder, sizeof folder, "%.*s", slash ? (int)(slash - out) + 1 : 0, out);
  int made = -1, e = 0;
  for (int attempt = 0; attempt < 100 && made != 0; attempt++) {
    snprintf(stage, sizeof stage, "%s.bbcgen-%ld-%u.tmp", folder, (long)getpid(),
             atomic_fetch_add(&g_stage_counter, 1u));
    made = mkdir(stage, 0777);
    e = errno;
    if (made != 0 && e != EEXIST) break;
  }
  if (made != 0)
    return bbc_error_set(err, BBC_ERROR_IO, "%s: cannot write in the folder %s: %s", out,
                         *folder ? folder : "./", strerror(e));
  snprintf(staged_out, sizeof staged_out, "%s/%s", stage, base);
  bbc_result r = write_levels(s, staged_out, cb, err);
  if (r != BBC_OK) unstage_message(err, stage, folder);
  const char *ext = extension_of(base);
  char bad[4600];
  if (r == BBC_OK && (move_staged(stage, folder, ext, 0, 1, bad, sizeof bad) != 0 ||
                      move_staged(stage, folder, ext, 1, 1, bad, sizeof bad) != 0))
    r = bbc_error_set(err, BBC_ERROR_IO, "%s: a folder is in the way; nothing written", bad);
  if (r == BBC_OK && (move_staged(stage, folder, ext, 0, 0, bad, sizeof bad) != 0 ||
                      move_staged(stage, folder, ext, 1, 0, bad, sizeof bad) != 0))
    r = bbc_error_set(err, BBC_ERROR_IO, "%s: cannot move it into place: %s", bad, strerror(errno));
  remove_stage(stage);
  return r;
}

static int make_dirs(const char *path) {
  char buf[4096];
  snprintf(buf, sizeof buf, "%s", path);
  for (char *p = buf + 1; *p; p++) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
    *p = '/';
  }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
  return 0;
}

bbc_result bbc_session_save(bbc_session *s, const char *user_dir, const bbc_callbacks *cb,
                            char *written, size_t written_size, bbc_error *err) {
  if (!s->have_cloud)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "save needs a Billboard Cloud: run bbc or bbc3 first");
  /* Appendix A: always below vrml97models/ of the current folder. */
  if (user_dir && (user_dir[0] == '/' || !strcmp(user_dir, "..") || !strncmp(user_dir, "../", 3) ||
                   strstr(user_dir, "/../") ||
                   (strlen(user_dir) >= 3 && !strcmp(user_dir + strlen(user_dir) - 3, "/..")))) {
    return bbc_error_set(
        err, BBC_ERROR_INVALID_ARGUMENT,
        "save %s: the folder must stay below vrml97models/ (no '/' start, no '..')", user_dir);
  }
  const char *base = strrchr(s->model_path, '/');
  base = base ? base + 1 : s->model_path;
  const char *ext = extension_of(base);
  char stem[256];
  snprintf(stem, sizeof stem, "%.*s", (int)(ext - base), base);
  const bbc_params *p = &s->level0.params;
  char dir[4096], leaf[512], path[4600];
  /* Appendix A's appendices in order: eX.XX, texX, nm, pl, and for point
   * clouds szX.X (point size), skipX (point skip), smooth */
  char pts[64] = "";
  if (s->model.kind == BBC_MESH_POINTS)
    snprintf(pts, sizeof pts, "_sz%.1f_skip%d%s", p->point_size, p->point_skip,
             p->point_smooth ? "_smooth" : "");
  snprintf(leaf, sizeof leaf, "%s_e%.2f_tex%d%s%s%s", stem, s->level0.epsilon_pct, p->texres,
           p->normal_maps && s->model.kind != BBC_MESH_POINTS ? "_nm" : "",
           p->prelight ? "_pl" : "", pts);
  if (user_dir && *user_dir)
    snprintf(dir, sizeof dir, "vrml97models/%s/%s/%s", user_dir, stem, leaf);
  else
    snprintf(dir, sizeof dir, "vrml97models/%s/%s", stem, leaf);
  if (make_dirs(dir) != 0)
    return bbc_error_set(err, BBC_ERROR_IO, "%s: cannot create the folder: %s", dir,
                         strerror(errno));
  snprintf(path, sizeof path, "%s/%s.wrl", dir, stem);
  if (written) snprintf(written, written_size, "%s", path);
  return bbc_session_write(s, path, cb, err);
}
