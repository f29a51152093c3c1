/* scene.c — loading a map for `forest`: the map file, its world, each
 * placed model (a model description file with its LOD blocks, or a 3D file
 * placed directly: one level, or one per level of a glTF LOD chain), every
 * 3D file read once however often it is used (thesis 3.2.2-3.2.3), the
 * terrain's colour with the objects' soft shadows (the sun lights it in the
 * shaders), the culling grid and the terrain quadtree. */
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

void scene_load_warning(void *user, bbc_log_level level, const char *message) {
  scene_load_note *n = user;
  if (level != BBC_LOG_WARNING) return;
  n->warnings++;
  fprintf(stderr, "forest: %s:%d: warning: %s\n", n->where, n->line, message);
  if (n->log) fprintf(n->log, "%s:%d: warning: %s\n", n->where, n->line, message);
}

void scene_join(const char *folder, const char *name, char *out, size_t n) {
  size_t lf = name[0] == '/' || !folder[0] ? 0 : strlen(folder), ln = strlen(name);
  if (lf + 1 + ln + 1 > n) { /* too long: an empty name, which then is not found */
    out[0] = '\0';
    return;
  }
  if (lf) {
    memcpy(out, folder, lf);
    out[lf++] = '/';
  }
  memcpy(out + lf, name, ln + 1);
}

void scene_folder_of(const char *path, char *out, size_t n) {
  snprintf(out, n, "%s", path);
  char *slash = strrchr(out, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(out, n, ".");
}

int scene_file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int scene_is_model_file(const char *name) {
  const char *dot = strrchr(name, '.');
  static const char *const ext[] = {".wrl", ".vrml", ".glb", ".gltf", ".obj",
                                    ".3ds", ".ply",  ".dae", ".fbx",  ".ac"};
  for (size_t i = 0; dot && i < sizeof ext / sizeof ext[0]; i++)
    if (!strcasecmp(dot, ext[i])) return 1;
  return 0;
}

/* Distinct planes of a mesh's triangles when it looks like a Billboard
 * Cloud (few triangles per plane: a fan of at most 10 corners a side,
 * bbc_cloud_billboard), else 0. */
static size_t count_billboards(const bbc_mesh *m) {
  enum { MAX = 1024 };
  double pl[MAX][4];
  size_t n = 0;
  size_t limbs = 0; /* bbcgen's limbs: a mesh inside the cloud, no billboards */
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (bbc_material_is_limbs(&m->materials[m->face_material[t]])) {
      limbs++;
      continue;
    }
    const double *a = m->positions + 3 * m->indices[3 * t],
                 *b = m->positions + 3 * m->indices[3 * t + 1],
                 *e = m->positions + 3 * m->indices[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (l <= 0) continue;
    for (int k = 0; k < 3; k++) c[k] /= l;
    double d = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    size_t i = 0;
    for (; i < n; i++) {
      double dot = c[0] * pl[i][0] + c[1] * pl[i][1] + c[2] * pl[i][2];
      if (fabs(fabs(dot) - 1) < 1e-4 &&
          fabs(d - (dot > 0 ? 1 : -1) * pl[i][3]) < 1e-4 * (1 + m->radius))
        break;
    }
    if (i < n) continue;
    if (n == MAX) return 0;
    memcpy(pl[n], c, sizeof c);
    pl[n++][3] = d;
  }
  return m->triangle_count - limbs <= 16 * n ? n : 0;
}

/* An impostor's quad: corners (+-1, +-1, 0), one white material; the
 * drawing layer places it facing the eye and reads the atlases. 0 when out
 * of memory. */
static int impostor_quad(bbc_mesh *q) {
  static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  memset(q, 0, sizeof *q);
  q->kind = BBC_MESH_TRIANGLES;
  q->positions = calloc(12, sizeof *q->positions);
  q->normals = calloc(12, sizeof *q->normals);
  q->uvs = calloc(8, sizeof *q->uvs);
  q->indices = malloc(sizeof idx);
  q->face_material = calloc(2, sizeof *q->face_material);
  q->face_group = calloc(2, sizeof *q->face_group);
  q->materials = calloc(1, sizeof *q->materials);
  q->group_names = calloc(1, sizeof *q->group_names);
  if (!q->positions || !q->normals || !q->uvs || !q->indices || !q->face_material ||
      !q->face_group || !q->materials || !q->group_names ||
      !(q->materials[0].name = strdup("impostor")) || !(q->group_names[0] = strdup("impostor"))) {
    bbc_mesh_free(q);
    return 0;
  }
  for (int k = 0; k < 4; k++) {
    q->positions[3 * k] = corner[k][0];
    q->positions[3 * k + 1] = corner[k][1];
    q->normals[3 * k + 2] = 1;
    q->uvs[2 * k] = (float)(0.5 * corner[k][0] + 0.5);
    q->uvs[2 * k + 1] = (float)(0.5 * corner[k][1] + 0.5);
  }
  memcpy(q->indices, idx, sizeof idx);
  q->vertex_count = 4;
  q->triangle_count = 2;
  q->material_count = 1;
  q->group_count = 1;
  q->materials[0].texture = -1;
  for (int k = 0; k < 4; k++) q->materials[0].base_color[k] = 1;
  return 1;
}

/* An impostor's descriptor at `path` into m (its quad and atlases); 0 with
 * the message said. */
static int load_impostor(scene_mesh *m, const char *path, const char *where, int line) {
  bbc_error err;
  m->impostor = calloc(1, sizeof *m->impostor);
  if (!m->impostor || bbc_impostor_read(path, m->impostor, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: %s\n", where, line, m->impostor ? err.message : "out of memory");
    free(m->impostor);
    m->impostor = NULL;
    return 0;
  }
  const bbc_impostor *im = m->impostor;
  if (im->up != BBC_AXIS_Y || !impostor_quad(&m->mesh)) {
    fprintf(stderr, "%s:%d: %s: %s\n", where, line, path,
            im->up != BBC_AXIS_Y ? "forest draws impostors of y-up models (bbcgen impostor "
                                   "--up y, the default)"
                                 : "out of memory");
    bbc_impostor_free(m->impostor);
    free(m->impostor);
    m->impostor = NULL;
    return 0;
  }
  double c = sqrt(im->center[0] * im->center[0] + im->center[1] * im->center[1] +
                  im->center[2] * im->center[2]);
  m->radius = c + im->radius;
  m->height = im->center[1] + im->radius;
  m->billboards = 1;
  m->relightable = 1; /* its normal atlas: lit by the sun wherever placed */
  return 1;
}

static long find_mesh(scene *s, const char *path, int lod_node, FILE *log, int progress,
                      const char *where, int line) {
  for (size_t i = 0; i < s->mesh_count; i++)
    if (s->meshes[i].lod_node == lod_node && !strcmp(s->meshes[i].path, path)) return (long)i;
  scene_mesh *m2 = realloc(s->meshes, (s->mesh_count + 1) * sizeof *m2);
  if (!m2) return -1;
  s->meshes = m2;
  scene_mesh *m = &s->meshes[s->mesh_count];
  memset(m, 0, sizeof *m);
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.lod_node = lod_node;
  scene_load_note note = {where, line, log, 0};
  lo.callbacks.log = scene_load_warning;
  lo.callbacks.user = &note;
  bbc_error err;
  if (progress) fprintf(stderr, "forest: loading %s\n", path);
  size_t pl = strlen(path);
  if (pl >= 5 && !strcasecmp(path + pl - 5, ".json")) { /* an impostor */
    if (!load_impostor(m, path, where, line) || !(m->path = strdup(path))) return -1;
    if (log)
      fprintf(log, "model %s: an impostor, %d x %d %s frames of %d texels\n", path,
              m->impostor->frames, m->impostor->frames,
              m->impostor->hemi ? "hemi-octahedral" : "octahedral", m->impostor->frame_size);
    return (long)s->mesh_count++;
  }
  bbc_result r = bbc_mesh_load(path, &lo, &m->mesh, &err);
  if (r != BBC_OK) {
    if (lod_node > 0 && r == BBC_ERROR_NOT_FOUND && scene_file_exists(path))
      return -2; /* no such level */
    fprintf(stderr, "%s:%d: %s\n", where, line, err.message);
    return -1;
  }
  if (m->mesh.kind != BBC_MESH_TRIANGLES) {
    fprintf(stderr, "%s:%d: %s is a point cloud; forest draws polygon models and clouds\n", where,
            line, path);
    bbc_mesh_free(&m->mesh);
    return -1;
  }
  m->path = strdup(path);
  m->lod_node = lod_node;
  m->billboards = count_billboards(&m->mesh);
  for (size_t v = 0; v < m->mesh.vertex_count; v++) {
    const double *p = m->mesh.positions + 3 * v;
    double d = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (d > m->radius) m->radius = d;
  }
  for (size_t v = 0; v < m->mesh.vertex_count; v++)
    if (m->mesh.positions[3 * v + 1] > m->height) m->height = m->mesh.positions[3 * v + 1];
  s->triangles_loaded += m->mesh.triangle_count;
  int unlit = 0;
  for (size_t i = 0; i < m->mesh.material_count; i++) {
    const bbc_material *ma = &m->mesh.materials[i];
    m->relightable |= !ma->unlit && (ma->normal_map > 0 || ma->occlusion_map > 0);
    unlit |= ma->unlit;
  }
  if (!m->relightable && !unlit && !m->billboards) { /* a polygon model */
    bbc_params prm;
    bbc_params_default(&prm);
    m->occlusion = malloc((m->mesh.vertex_count + 1) * sizeof *m->occlusion);
    if (m->occlusion && bbc_shade_vertices(&m->mesh, prm.occlusion, prm.occlusion_min, BBC_AXIS_Y,
                                           m->occlusion, &err) != BBC_OK) {
      free(m->occlusion);
      m->occlusion = NULL;
    }
  }
  if (log)
    fprintf(log, "model %s%s: %zu triangles, %zu materials, %zu billboards, %s\n", path,
            lod_node ? " (one level)" : "", m->mesh.triangle_count, m->mesh.material_count,
            m->billboards,
            m->relightable ? "lit by the sun (normal and occlusion maps)"
            : unlit        ? "its light baked in (drawn as it is)"
                           : "lit by the sun where marked lighting");
  return (long)s->mesh_count++;
}

/* Where a placement's model comes from: the file the map names, its mipmap
 * flag and line, and what loading says where. */
typedef struct model_source {
  const char *file;
  double scale; /* the placement's: distances from a radius are the placed size's */
  int mipmap, line;
  const char *map_path;
  FILE *log;
  int progress;
} model_source;

/* A 3D file placed directly: one level, or each level of a glTF chain,
 * switching at 40, 120, 360... times the model's radius as placed (times
 * the placement's scale: a tree modelled in centimetres and placed at 0.01
 * switches where one modelled in metres does). 0 on failure. */
static int model_from_mesh_file(scene *s, scene_model *m, const model_source *src,
                                const char *path) {
  size_t cap = 8;
  m->ranges = malloc(cap * 2 * sizeof *m->ranges);
  m->parts = calloc(cap, sizeof *m->parts);
  m->part_count = calloc(cap, sizeof *m->part_count);
  if (!m->ranges || !m->parts || !m->part_count) return 0;
  int chain = 0;
  const char *dot = strrchr(src->file, '.');
  if (dot && (!strcasecmp(dot, ".glb") || !strcasecmp(dot, ".gltf"))) chain = 1;
  for (int level = 0; level < (chain ? 8 : 1); level++) {
    long mesh = find_mesh(s, path, chain ? level + 1 : 0, src->log, src->progress, src->map_path,
                          src->line);
    if (mesh == -2 && level == 0)
      mesh = find_mesh(s, path, 0, src->log, src->progress, src->map_path, src->line);
    if (mesh == -2) break;
    if (mesh < 0) return 0;
    m->parts[level][0].mesh = (size_t)mesh;
    m->parts[level][0].lit = 1;
    if (level == 0) m->height = s->meshes[mesh].height;
    m->parts[level][0].mipmap = src->mipmap;
    m->part_count[level] = 1;
    m->lod_count++;
    if (s->meshes[mesh].lod_node == 0) break;
  }
  double r = s->meshes[m->parts[0][0].mesh].radius * src->scale;
  for (size_t l = 0; l < m->lod_count; l++) {
    m->ranges[2 * l] = l ? 40 * r * pow(3, (double)l - 1) : 0;
    m->ranges[2 * l + 1] = l + 1 < m->lod_count ? 40 * r * pow(3, (double)l) : 1e30;
  }
  m->fade = m->lod_count > 1 ? 4 * r : 0;
  return 1;
}

/* A model description file (Appendix B): its LOD blocks, each part's 3D
 * file relative to the description's folder. 0 on failure. */
static int model_from_description(scene *s, scene_model *m, const model_source *src,
                                  const char *path) {
  bbc_forest_model d;
  bbc_error err;
  if (bbc_forest_model_load(path, &d, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: model description %s: %s\n", src->map_path, src->line, src->file,
            err.message);
    return 0;
  }
  char mfolder[4096];
  scene_folder_of(path, mfolder, sizeof mfolder);
  m->lod_count = d.lod_count;
  m->fade = d.fade;
  m->shadow_radius = d.shadow_radius;
  m->shadow_cutoff = d.shadow_cutoff;
  m->ranges = malloc(d.lod_count * 2 * sizeof *m->ranges);
  m->parts = calloc(d.lod_count, sizeof *m->parts);
  m->part_count = calloc(d.lod_count, sizeof *m->part_count);
  if (!m->ranges || !m->parts || !m->part_count) {
    bbc_forest_model_free(&d);
    return 0;
  }
  for (size_t l = 0; l < d.lod_count; l++) {
    m->ranges[2 * l] = d.lods[l].min_dist;
    m->ranges[2 * l + 1] = d.lods[l].max_dist;
    m->part_count[l] = d.lods[l].part_count;
    for (int k = 0; k < d.lods[l].part_count; k++) {
      char p2[8300];
      scene_join(mfolder, d.lods[l].part[k].file, p2, sizeof p2);
      long mesh = find_mesh(s, p2, 0, src->log, src->progress, path, d.lods[l].line);
      if (mesh < 0) {
        bbc_forest_model_free(&d);
        return 0;
      }
      m->parts[l][k].mesh = (size_t)mesh;
      m->parts[l][k].lit = d.lods[l].part[k].lighting || s->meshes[mesh].relightable;
      if (l == 0 && k == 0) m->height = s->meshes[mesh].height;
      m->parts[l][k].mipmap = src->mipmap || d.lods[l].part[k].mipmap;
    }
  }
  bbc_forest_model_free(&d);
  return 1;
}

/* The model of a placement file (loaded once per file and mipmap flag). */
static long find_model(scene *s, const char *file, int mipmap, double scale, int line,
                       const char *map_path, FILE *log, int progress) {
  char key[4200];
  /* a 3D file's switch distances depend on the scale it is placed at: a
   * model per scale; a description file's are its own, in world units */
  int mesh_file = scene_is_model_file(file);
  if (mesh_file)
    snprintf(key, sizeof key, "%s|%d|%.17g", file, mipmap, scale);
  else
    snprintf(key, sizeof key, "%s|%d", file, mipmap);
  for (size_t i = 0; i < s->model_count; i++)
    if (!strcmp(s->models[i].key, key)) return (long)i;
  scene_model *m2 = realloc(s->models, (s->model_count + 1) * sizeof *m2);
  if (!m2) return -1;
  s->models = m2;
  scene_model *m = &s->models[s->model_count];
  memset(m, 0, sizeof *m);
  char path[4096];
  scene_join(s->folder, file, path, sizeof path);
  model_source src = {file, scale, mipmap, line, map_path, log, progress};
  int ok =
      mesh_file ? model_from_mesh_file(s, m, &src, path) : model_from_description(s, m, &src, path);
  if (!ok) { /* nothing of a model that did not load stays allocated */
    free(m->ranges);
    free(m->parts);
    free(m->part_count);
    memset(m, 0, sizeof *m);
    return -1;
  }
  for (size_t l = 0; l < m->lod_count; l++)
    for (int k = 0; k < m->part_count[l]; k++)
      if (s->meshes[m->parts[l][k].mesh].radius > m->radius)
        m->radius = s->meshes[m->parts[l][k].mesh].radius;
  m->key = strdup(key);
  m->name = strdup(file);
  if (log) {
    fprintf(log, "object %s: %zu level%s", file, m->lod_count, m->lod_count == 1 ? "" : "s");
    for (size_t l = 0; l < m->lod_count; l++)
      fprintf(log, " [%g, %g)", m->ranges[2 * l], m->ranges[2 * l + 1]);
    fprintf(log, ", fade %g, shadow %g/%g, radius %g\n", m->fade, m->shadow_radius,
            m->shadow_cutoff, m->radius);
  }
  return (long)s->model_count++;
}

void scene_free(scene *s) {
  for (size_t i = 0; i < s->mesh_count; i++) {
    free(s->meshes[i].path);
    bbc_mesh_free(&s->meshes[i].mesh);
    bbc_impostor_free(s->meshes[i].impostor);
    free(s->meshes[i].impostor);
    free(s->meshes[i].occlusion);
  }
  free(s->meshes);
  for (size_t i = 0; i < s->model_count; i++) {
    free(s->models[i].key);
    free(s->models[i].name);
    free(s->models[i].ranges);
    free(s->models[i].parts);
    free(s->models[i].part_count);
  }
  free(s->models);
  free(s->placement_models);
  bbc_image_free(&s->terrain_colour);
  for (int i = 0; i < 6; i++) bbc_image_free(&s->sky[i]);
  bbc_forest_cull_free(s->cull);
  s->cull = NULL;
  bbc_forest_terrain_free(&s->terrain);
  bbc_forest_occluder_free(&s->occluder);
  bbc_forest_world_free(&s->world);
  bbc_forest_map_free(&s->map);
  memset(s, 0, sizeof *s);
}

int scene_load(scene *s, const char *map_path, FILE *log, int progress) {
  memset(s, 0, sizeof *s);
  scene_folder_of(map_path, s->folder, sizeof s->folder);
  const char *base = strrchr(map_path, '/');
  snprintf(s->map_name, sizeof s->map_name, "%s", base ? base + 1 : map_path);
  char *dot = strrchr(s->map_name, '.');
  if (dot && dot != s->map_name) *dot = '\0';
  bbc_error err;
  if (bbc_forest_map_load(map_path, &s->map, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 0;
  }
  if (progress) fprintf(stderr, "forest: building the terrain and placing objects\n");
  if (bbc_forest_world_build(&s->map, s->folder, &s->world, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message); /* "MAP:LINE: ..." */
    return 0;
  }
  if (log && s->world.note[0]) fprintf(log, "note: %s\n", s->world.note);
  s->extent = (s->world.width - 1) * s->world.spacing;
  s->far_clip = s->map.farclip > 0 ? s->map.farclip * s->world.spacing : s->extent * 1.5;
  s->placement_models = calloc(s->map.placement_count + 1, sizeof *s->placement_models);
  if (!s->placement_models) return 0;
  for (size_t p = 0; p < s->map.placement_count; p++) {
    const bbc_forest_placement *pl = &s->map.placements[p];
    s->placement_models[p][0] = s->placement_models[p][1] = UINT32_MAX;
    long a = find_model(s, pl->file, pl->mipmap, pl->scale, pl->line, map_path, log, progress);
    if (a < 0) return 0;
    s->placement_models[p][0] = (uint32_t)a;
    if (pl->file2) {
      long b = find_model(s, pl->file2, pl->mipmap, pl->scale, pl->line, map_path, log, progress);
      if (b < 0) return 0;
      s->placement_models[p][1] = (uint32_t)b;
    }
  }
  /* shadows per placement: the first component's model decides */
  double(*shadow)[2] = calloc(s->map.placement_count + 1, sizeof *shadow);
  if (!shadow) return 0;
  for (size_t p = 0; p < s->map.placement_count; p++) {
    const scene_model *m = &s->models[s->placement_models[p][0]];
    shadow[p][0] = m->shadow_radius;
    shadow[p][1] = m->shadow_cutoff;
  }
  /* the colours and the shadows; the sun lights them per pixel */
  bbc_result r = bbc_forest_terrain_bake_colour(&s->world, NULL, (const double(*)[2])shadow,
                                                &s->terrain_colour, &err);
  free(shadow);
  if (r != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 0;
  }
  bbc_forest_lod_model *lm = calloc(s->model_count + 1, sizeof *lm);
  if (!lm) return 0;
  for (size_t i = 0; i < s->model_count; i++) {
    lm[i].lod_count = s->models[i].lod_count;
    lm[i].ranges = s->models[i].ranges;
    lm[i].fade = s->models[i].fade;
    lm[i].radius = s->models[i].radius;
  }
  r = bbc_forest_cull_build(&s->world, lm, s->model_count,
                            (const uint32_t(*)[2])s->placement_models, s->map.placement_count,
                            &s->cull, &err);
  free(lm);
  if (r != BBC_OK || bbc_forest_terrain_init(&s->terrain, &s->world, &err) != BBC_OK ||
      bbc_forest_occluder_init(&s->occluder, &s->world, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 0;
  }
  if (s->map.skymap) {
    static const char *const side[6] = {"FR", "BK", "LF", "RT", "UP", "DN"};
    for (int i = 0; i < 6; i++) {
      char name[4200], path[8400];
      snprintf(name, sizeof name, "%s_%s.tga", s->map.skymap, side[i]);
      scene_join(s->folder, name, path, sizeof path);
      if (bbc_image_load(path, &s->sky[i], &err) != BBC_OK) {
        fprintf(stderr, "forest: %s:%d: skymap: %s\n", map_path, s->map.skymap_line, err.message);
        return 0;
      }
      if (s->sky[i].width != s->sky[i].height || s->sky[i].width != s->sky[0].width) {
        fprintf(stderr,
                "forest: %s:%d: skymap: %s is %d x %d; the six images must be square and alike\n",
                map_path, s->map.skymap_line, name, s->sky[i].width, s->sky[i].height);
        return 0;
      }
    }
    s->has_sky = 1;
  }
  return 1;
}
