/* output.c — what a session's cloud becomes on disk, exactly as bbcgen
 * writes it: cloud files (glTF with its LOD chain, OBJ, VRML), the JSON
 * report, the preview sheet, Appendix A's save folder. */
#include "session.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

typedef bbc__level job_lod;

/* Which budget moved epsilon (maxplanes raises it, minplanes lowers it), or
 * NULL when the asked epsilon was used. */
static const char *epsilon_adjusted_by(const job_lod *L) {
  double f = L->planes.epsilon_scale;
  return f > 1 ? "maxplanes" : f < 1 ? "minplanes" : NULL;
}

void bbc_session_epsilon_note(const bbc_session *s, size_t level, char *buf, size_t n) {
  const job_lod *L = bbc__session_level((bbc_session *)s, level);
  const char *by = L ? epsilon_adjusted_by(L) : NULL;
  if (!by) {
    if (n) buf[0] = 0;
    return;
  }
  int raised = by[1] == 'a';
  snprintf(buf, n, " (%s from %.3g %% by %s %d)", raised ? "raised" : "lowered", L->epsilon_pct, by,
           raised ? L->params.max_planes : L->params.min_planes);
}

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

static char *params_json_text(const bbc_params *p) {
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
  cJSON *kinds = cJSON_AddArrayToObject(o, "kinds");
  for (size_t b = 0; b < L->cloud.billboard_count; b++)
    cJSON_AddItemToArray(kinds,
                         cJSON_CreateString(bbc_plane_kind_name(L->cloud.billboards[b].kind)));
  if (!detailed) return o;
  const bbc_mesh *m = &L->cloud.mesh;
  cJSON_AddNumberToObject(o, "triangles", (double)m->triangle_count);
  cJSON_AddNumberToObject(o, "limb_triangles", (double)L->cloud.limb_triangles);
  cJSON_AddNumberToObject(o, "texels", (double)L->cloud.texels);
  cJSON_AddNumberToObject(o, "texres_used", L->cloud.texres);
  cJSON_AddNumberToObject(o, "plane_runs", L->planes.attempts);
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

/* OUT and, for OBJ and VRML chains, OUT_lod<k>.EXT: the files a write makes. */
void bbc_session_output_path(const char *out, size_t level, char *buf, size_t n) {
  lod_path(out, level, buf, n);
}

void bbc_session_set_output(bbc_session *s, const bbc_params *p) {
  for (size_t k = 0; k < bbc_session_level_count(s); k++) {
    bbc__level *l = bbc__session_level(s, k);
    l->params.format = p->format;
    l->params.dds = p->dds;
  }
}

bbc_result bbc_session_write(bbc_session *s, const char *out, const bbc_callbacks *cb,
                             bbc_error *err) {
  size_t count = bbc_session_level_count(s);
  if (!count)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "no Billboard Cloud to write: run step 3");
  job_lod *lods[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) lods[k] = bbc__session_level(s, k);
  const char *ext = extension_of(out);
  int glb = !strcasecmp(ext, ".glb"), gltf = !strcasecmp(ext, ".gltf"),
      obj = !strcasecmp(ext, ".obj"), wrl = !strcasecmp(ext, ".wrl");
  if (!glb && !gltf && !obj && !wrl)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "the output must end in .glb, .gltf, .obj or .wrl, not '%s'", out);
  if (obj && lods[0]->params.normal_maps)
    bbc__log(cb, BBC_LOG_WARNING, "OBJ output carries no normal map (use .glb, .gltf or .wrl)");
  if (wrl && lods[0]->params.normal_maps && lods[0]->params.format == 1)
    bbc__log(cb, BBC_LOG_WARNING,
             "VRML97 (format 1) carries no normal map: none written (format 0 has them)");
  double t0 = bbc__now_s();
  bbc_result r = BBC_OK;
  /* Names engines understand: <model>_LOD<k> for the levels of a chain, <model>
   * for a single cloud and for the chain's group node; the material
   * "billboards" (a chain's "billboards_LOD<k>"), so texture files are
   * <stem>_billboards.png (bbc_texture_file_name). */
  char model[128];
  model_name(s->model_path, model, sizeof model);
  for (size_t k = 0; k < count && count > 1; k++) {
    char name[64];
    snprintf(name, sizeof name, "billboards_LOD%zu", k);
    bbc_material *mat = &lods[k]->cloud.mesh.materials[0];
    char *dup = bbc__strdup(name);
    if (dup) {
      free(mat->name);
      mat->name = dup;
    }
    if (lods[k]->cloud.mesh.material_count > 1) { /* the limbs' */
      snprintf(name, sizeof name, "limbs_LOD%zu", k);
      mat = &lods[k]->cloud.mesh.materials[1];
      dup = bbc__strdup(name);
      if (dup) {
        free(mat->name);
        mat->name = dup;
      }
    }
  }
  int unlit = bbc_params_unlit(&lods[0]->params);
  if ((glb || gltf) && count > 1 && !s->atlas_shared) {
    /* One atlas for every level when they fit the budget (atlasmax, else
     * the largest level's atlas): one texture bind for the whole chain. */
    int budget = lods[0]->params.atlas_max;
    for (size_t k = 0; k < count; k++) {
      const bbc_image *a = &lods[k]->cloud.mesh.textures[0].image;
      if (a->width > budget) budget = a->width;
    }
    bbc_cloud clouds[BBC_SESSION_MAX_LEVELS];
    for (size_t k = 0; k < count; k++) clouds[k] = lods[k]->cloud;
    r = bbc_clouds_share_atlas(clouds, count, budget < 64 ? 64 : budget, &s->atlas_shared, err);
    for (size_t k = 0; k < count; k++) lods[k]->cloud = clouds[k];
    if (r != BBC_OK) return r;
    const bbc_image *a = &lods[0]->cloud.mesh.textures[0].image;
    if (s->atlas_shared)
      bbc__log(cb, BBC_LOG_INFO, "the %zu levels share one %dx%d atlas", count, a->width,
               a->height);
    else
      bbc__log(cb, BBC_LOG_INFO, "the levels do not fit one %dx%d atlas together: one atlas each",
               budget, budget);
  }
  if (glb || gltf) {
    char *texts[BBC_SESSION_MAX_LEVELS] = {0}, names[BBC_SESSION_MAX_LEVELS][160];
    bbc_gltf_node nodes[BBC_SESSION_MAX_LEVELS];
    double coverage[BBC_SESSION_MAX_LEVELS];
    for (size_t k = 0; k < count; k++) {
      cJSON *o = lod_json(lods[k], 0);
      texts[k] = cJSON_PrintUnformatted(o);
      cJSON_Delete(o);
      if (count > 1)
        snprintf(names[k], sizeof names[k], "%s_LOD%zu", model, k);
      else
        snprintf(names[k], sizeof names[k], "%s", model);
      nodes[k] = (bbc_gltf_node){&lods[k]->cloud.mesh, names[k], texts[k]};
      /* MSFT_screencoverage: level k gives way to level k + 1 once level
       * k + 1's error (epsilon, a share of the bounding radius) is at most
       * 2 pixels of a 1080-line screen; the last level ends at 2 pixels. */
      if (k + 1 < count) {
        double e = lods[k + 1]->epsilon_pct * lods[k + 1]->planes.epsilon_scale / 100;
        coverage[k] = fmin(1.0, 2.0 * 2.0 / (e * 1080.0));
      } else {
        coverage[k] = 2.0 / 1080.0;
      }
      if (k && coverage[k] > coverage[k - 1]) coverage[k] = coverage[k - 1];
    }
    char *params = params_json_text(&lods[0]->params);
    size_t n = strlen(params) + 64;
    char *extras = malloc(n + 128);
    const double *og = s->model.origin;
    if (extras && (og[0] != 0 || og[1] != 0 || og[2] != 0)) /* where the coordinates were */
      snprintf(extras, n + 128, "{\"bbcgen_parameters\":%s,\"bbcgen_origin\":[%.17g,%.17g,%.17g]}",
               params, og[0], og[1], og[2]);
    else if (extras)
      snprintf(extras, n, "{\"bbcgen_parameters\":%s}", params);
    bbc_gltf_options go;
    memset(&go, 0, sizeof go);
    go.binary = glb;
    go.extras_json = extras;
    go.lod_chain = 1;
    go.lod_group_name = model;
    go.screen_coverage = coverage;
    go.unlit = unlit;
    r = bbc_scene_write_gltf(out, nodes, count, &go, err);
    free(extras);
    cJSON_free(params);
    for (size_t k = 0; k < count; k++) cJSON_free(texts[k]);
  } else {
    for (size_t k = 0; k < count && r == BBC_OK; k++) {
      char path[4200];
      lod_path(out, k, path, sizeof path);
      char comment[4600], why[160];
      bbc_session_epsilon_note(s, k, why, sizeof why);
      const double *og = s->model.origin;
      char origin[160] = "";
      if (og[0] != 0 || og[1] != 0 || og[2] != 0)
        snprintf(origin, sizeof origin, "\norigin: %.17g %.17g %.17g (add to the coordinates)",
                 og[0], og[1], og[2]);
      snprintf(comment, sizeof comment, "model: %s\nepsilon: %.4g %% (%.6g model units)%s%s",
               s->model_path, lods[k]->epsilon_pct * lods[k]->planes.epsilon_scale,
               lods[k]->planes.epsilon_abs, why, origin);
      if (obj)
        r = bbc_mesh_write_obj_ex(path, &lods[k]->cloud.mesh, comment, unlit, err);
      else
        r = bbc_cloud_write_vrml(path, &lods[k]->cloud,
                                 lods[k]->params.format | (unlit ? BBC_VRML_UNLIT : 0) |
                                     (lods[k]->params.dds ? BBC_VRML_DDS : 0),
                                 comment, err);
    }
  }
  s->write_s = bbc__now_s() - t0;
  return r;
}

bbc_result bbc_session_report(const bbc_session *s, const char *out, const char *cloud_path,
                              bbc_error *err) {
  size_t count = bbc_session_level_count(s);
  if (!count)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "no Billboard Cloud to report: run step 3");
  const job_lod *lods[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < count; k++) lods[k] = bbc__session_level((bbc_session *)s, k);
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "generator", "bbcgen " BBC_VERSION_STRING);
  cJSON_AddStringToObject(o, "model", s->model_path);
  if (cloud_path) cJSON_AddStringToObject(o, "output", cloud_path);
  cJSON_AddNumberToObject(o, "model_triangles", (double)s->model.triangle_count);
  if (s->model.kind == BBC_MESH_POINTS)
    cJSON_AddNumberToObject(o, "model_points", (double)s->model.vertex_count);
  cJSON_AddNumberToObject(o, "model_radius", s->model.radius);
  char *params = params_json_text(&lods[0]->params);
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
  if (!text) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", out);
  size_t n = strlen(text);
  char *withnl = malloc(n + 2);
  bbc_result r = BBC_ERROR_OUT_OF_MEMORY;
  if (withnl) {
    memcpy(withnl, text, n);
    withnl[n] = '\n';
    withnl[n + 1] = 0;
    r = bbc_write_file_atomic(out, withnl, n + 1, err);
  } else {
    bbc__fail(err, r, "%s: out of memory", out);
  }
  free(withnl);
  cJSON_free(text);
  return r;
}

static void put_px(bbc_image *im, int x, int y, const uint8_t *rgb) {
  if (x < 0 || y < 0 || x >= im->width || y >= im->height) return;
  uint8_t *p = im->rgba + 4 * ((size_t)y * im->width + x);
  memcpy(p, rgb, 3);
  p[3] = 255;
}

static void draw_line(bbc_image *im, double x0, double y0, double x1, double y1,
                      const uint8_t *rgb) {
  double dx = x1 - x0, dy = y1 - y0;
  int steps = (int)ceil(fmax(fabs(dx), fabs(dy)));
  if (steps > 100000) steps = 100000;
  for (int i = 0; i <= steps; i++) {
    double t = steps ? (double)i / steps : 0;
    int x = (int)floor(x0 + t * dx), y = (int)floor(y0 + t * dy);
    put_px(im, x, y, rgb);
    put_px(im, x + 1, y, rgb);
    put_px(im, x, y + 1, rgb);
  }
}

/* The thesis's colour code (Fig. 2-33 ff.). */
static const uint8_t k_kind_rgb[BBC_PLANE_KIND_COUNT][3] = {
    {120, 190, 255}, /* standard: light blue */
    {255, 150, 20},  /* coplanar: orange */
    {255, 120, 200}, /* post-tweaked: pink */
    {40, 220, 60},   /* cardboard: green */
    {0, 255, 255},   /* parachute: cyan */
    {255, 230, 40},  /* stem: yellow */
};

bbc_result bbc_session_preview(const bbc_session *s, const char *out, int cell, bbc_error *err) {
  if (!s->have_cloud)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "no Billboard Cloud to preview: run step 3");
  if (cell < 16 || cell > 4096)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "preview cells of 16 to 4096 pixels, not %d",
                     cell);
  const bbc_mesh *m = &s->model;
  const job_lod *L = &s->level0;
  int up = L->params.up_axis;
  /* Front, side, above, and from 35 degrees up between front and side. */
  double dirs[4][3], ups[4][3];
  int a = (up + 1) % 3, b = (up + 2) % 3; /* (a, b, up) right-handed */
  for (int v = 0; v < 4; v++)
    for (int k = 0; k < 3; k++) dirs[v][k] = ups[v][k] = 0;
  dirs[0][b] = -1;
  dirs[1][a] = -1;
  dirs[2][up] = -1;
  double e = 35 * 3.14159265358979323846 / 180;
  dirs[3][a] = -cos(e) * sqrt(0.5);
  dirs[3][b] = -cos(e) * sqrt(0.5);
  dirs[3][up] = -sin(e);
  ups[0][up] = ups[1][up] = ups[3][up] = 1;
  ups[2][b] = -1;
  bbc_image sheet, img;
  if (bbc_image_alloc(&sheet, 4 * cell, 3 * cell) != BBC_OK ||
      bbc_image_alloc(&img, cell, cell) != BBC_OK) {
    bbc_image_free(&sheet);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "preview: out of memory");
  }
  float *shade = NULL;
  if (L->params.shade_voxels > 0) {
    shade = malloc(m->vertex_count * sizeof *shade);
    bbc_error ignored;
    if (shade && bbc_shade_vertices(m, L->params.shade_voxels, L->params.shade_ambient, up, shade,
                                    &ignored) != BBC_OK) {
      free(shade);
      shade = NULL;
    }
  }
  double light[3], gain = 1.0;
  bbc_params_light_direction(&L->params, light);
  bbc_result rc = BBC_OK;
  if (L->params.prelight) rc = bbc_light_gain(m, light, L->params.up_axis, &gain, err);
  for (int v = 0; v < 4 && rc == BBC_OK; v++) {
    for (int row = 0; row < 3 && rc == BBC_OK; row++) {
      bbc_view view;
      bbc_view_frame_mesh(m, dirs[v], ups[v], &view);
      /* The original lit as the textures were baked; the cloud unlit (its
       * textures carry the light). */
      view.lighting = row == 1 ? 0 : L->params.prelight;
      view.light_gain = gain;
      view.ambient = L->params.viewer_ambient;
      memcpy(view.light, light, sizeof light);
      view.vertex_shade = row == 1 ? NULL : shade;
      if (row == 2) view.background[0] = view.background[1] = view.background[2] = 40;
      const bbc_mesh *what = row == 1 ? &L->cloud.mesh : m;
      if ((rc = bbc_render_ortho(what, &view, &img, err)) != BBC_OK) break;
      if (row == 2) {
        /* The original faded into the background, the billboards' outlines
         * on top, coloured by kind. */
        for (size_t i = 0; i < (size_t)cell * cell; i++)
          for (int k = 0; k < 3; k++)
            img.rgba[4 * i + k] = (uint8_t)(40 + (img.rgba[4 * i + k] - 40) * 45 / 100);
        for (size_t q = 0; q < L->cloud.billboard_count; q++) {
          const bbc_cloud_billboard *cb = &L->cloud.billboards[q];
          const uint8_t *rgb = k_kind_rgb[cb->kind < BBC_PLANE_KIND_COUNT ? cb->kind : 0];
          double prev[2] = {0, 0}, first[2] = {0, 0};
          for (int cc = 0; cc <= cb->corner_count; cc++) {
            const double *st = cb->corners[cc % cb->corner_count];
            double p[3], sc[2];
            for (int k = 0; k < 3; k++)
              p[k] = cb->rect.origin[k] + st[0] * cb->rect.width * cb->rect.u[k] +
                     st[1] * cb->rect.height * cb->rect.w[k];
            bbc_view_project(&view, cell, cell, p, sc);
            if (cc == 0)
              memcpy(first, sc, sizeof sc);
            else
              draw_line(&img, prev[0], prev[1], sc[0], sc[1], rgb);
            memcpy(prev, sc, sizeof sc);
          }
          (void)first;
        }
      }
      for (int y = 0; y < cell; y++)
        memcpy(sheet.rgba + 4 * ((size_t)(row * cell + y) * sheet.width + (size_t)v * cell),
               img.rgba + 4 * (size_t)y * cell, 4 * (size_t)cell);
    }
  }
  free(shade);
  bbc_image_free(&img);
  if (rc == BBC_OK) rc = bbc_image_write_png(out, &sheet, err);
  bbc_image_free(&sheet);
  return rc;
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
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "save needs a Billboard Cloud: run bbc or bbc3 first");
  /* Appendix A: always below vrml97models/ of the current folder. */
  if (user_dir && (user_dir[0] == '/' || !strcmp(user_dir, "..") || !strncmp(user_dir, "../", 3) ||
                   strstr(user_dir, "/../") ||
                   (strlen(user_dir) >= 3 && !strcmp(user_dir + strlen(user_dir) - 3, "/..")))) {
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "save %s: the folder must stay below vrml97models/ (no '/' start, no '..')",
                     user_dir);
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
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot create the folder: %s", dir, strerror(errno));
  snprintf(path, sizeof path, "%s/%s.wrl", dir, stem);
  if (written) snprintf(written, written_size, "%s", path);
  return bbc_session_write(s, path, cb, err);
}
