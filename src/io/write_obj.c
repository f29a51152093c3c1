/* write_obj.c — Wavefront OBJ + MTL + PNG textures, every file atomic. */
#include "io.h"

#include <assert.h>
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Base name of a path without folder and extension, into out. */
/* "TAG x y ..." (count numbers of `digits` significant digits, spelt as in
 * the C locale) and a line end. */
static void put_numbers(FILE *f, const char *tag, int digits, const double *v, int count) {
  fputs(tag, f);
  for (int k = 0; k < count; k++) {
    char s[BBC__NUMBER_TEXT];
    bbc__number_text(s, sizeof s, digits, v[k]);
    fputc(' ', f);
    fputs(s, f);
  }
  fputc('\n', f);
}

static void path_stem(const char *path, char *out, size_t n) {
  const char *s = strrchr(path, '/');
  s = s ? s + 1 : path;
  snprintf(out, n, "%s", s);
  char *dot = strrchr(out, '.');
  if (dot) *dot = 0;
}

/* Comment lines "# ..." for each line of `text` (may be NULL). */
static void put_comment(FILE *f, const char *text) {
  for (const char *p = text; p && *p;) {
    size_t n = strcspn(p, "\r\n");
    fprintf(f, "# %.*s\n", (int)n, p);
    p += n;
    while (*p == '\r' || *p == '\n') p++;
  }
}

/* The decoded textures the materials use, as <stem>_<name>.png beside the
 * OBJ (bbc_texture_file_name's rule): tex_names gets each file's name,
 * written (n_written) each file's path. */
static bbc_result write_textures(const bbc_mesh *m, const char *stem, const char *dir,
                                 char (*tex_names)[520], char (*written)[2600], size_t *n_written,
                                 bbc_error *err) {
  bbc_result r = BBC_OK;
  for (size_t i = 0; i < m->material_count && r == BBC_OK; i++) {
    int t = m->materials[i].texture;
    if (t < 0 || tex_names[t][0] || !m->textures[t].image.rgba) continue;
    char safe[160];
    bbc_texture_file_name(m, (size_t)t, safe, sizeof safe);
    snprintf(tex_names[t], sizeof tex_names[t], "%s_%s.png", stem, safe);
    char full[2600];
    snprintf(full, sizeof full, "%s%s", dir, tex_names[t]);
    r = bbc_image_write_png(full, &m->textures[t].image, err);
    if (r == BBC_OK) memcpy(written[(*n_written)++], full, sizeof full);
  }
  return r;
}

/* The MTL: each material's colour, opacity and textures (map_d too when the
 * texture has alpha); illum 0 when unlit. */
static bbc_result write_mtl(const char *mtl_path, const bbc_mesh *m, char (*tex_names)[520],
                            int unlit, bbc_error *err) {
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, mtl_path, err);
  if (r != BBC_OK) return r;
  fprintf(af.fp, "# written by bbcgen %s\n", BBC_VERSION_STRING);
  for (size_t i = 0; i < m->material_count; i++) {
    const bbc_material *mat = &m->materials[i];
    char safe[128];
    bbc__safe_name(mat->name, safe, sizeof safe);
    fprintf(af.fp, "\nnewmtl %s\n", safe);
    const double kd[4] = {mat->base_color[0], mat->base_color[1], mat->base_color[2],
                          mat->base_color[3]};
    put_numbers(af.fp, "Kd", 6, kd, 3);
    if (mat->base_color[3] < 1.0f) put_numbers(af.fp, "d", 6, kd + 3, 1);
    if (unlit) fprintf(af.fp, "illum 0\n"); /* colour only, no lighting */
    if (mat->texture >= 0 && tex_names[mat->texture][0]) {
      fprintf(af.fp, "map_Kd %s\n", tex_names[mat->texture]);
      if (m->textures[mat->texture].has_alpha)
        fprintf(af.fp, "map_d %s\n", tex_names[mat->texture]);
    }
  }
  return bbc__atomic_commit(&af, err);
}

/* The faces in mesh order: a group line whenever the group changes, a
 * usemtl line whenever the material does (restated inside each group);
 * corners name their vt and vn when the mesh has them. */
static void put_faces(FILE *f, const bbc_mesh *m) {
  uint32_t cur_group = UINT32_MAX, cur_mat = UINT32_MAX;
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (m->face_group[t] != cur_group) {
      cur_group = m->face_group[t];
      char safe[256];
      bbc__safe_name(m->group_names[cur_group], safe, sizeof safe);
      fprintf(f, "g %s\n", safe);
      cur_mat = UINT32_MAX; /* restate the material inside each group */
    }
    if (m->face_material[t] != cur_mat) {
      cur_mat = m->face_material[t];
      char safe[128];
      bbc__safe_name(m->materials[cur_mat].name, safe, sizeof safe);
      fprintf(f, "usemtl %s\n", safe);
    }
    const uint32_t *ix = m->indices + 3 * t;
    fputc('f', f);
    for (int k = 0; k < 3; k++) {
      unsigned long i = (unsigned long)ix[k] + 1;
      if (m->uvs && m->normals)
        fprintf(f, " %lu/%lu/%lu", i, i, i);
      else if (m->uvs)
        fprintf(f, " %lu/%lu", i, i);
      else if (m->normals)
        fprintf(f, " %lu//%lu", i, i);
      else
        fprintf(f, " %lu", i);
    }
    fputc('\n', f);
  }
}

/* The OBJ: a header naming the MTL, the caller's comment, the vertices,
 * texture coordinates and normals, then the faces. */
static bbc_result write_obj_file(const char *obj_path, const bbc_mesh *m, const char *stem,
                                 const char *comment, bbc_error *err) {
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, obj_path, err);
  if (r != BBC_OK) return r;
  FILE *f = af.fp;
  fprintf(f, "# written by bbcgen %s: %zu vertices, %zu triangles\nmtllib %s.mtl\n",
          BBC_VERSION_STRING, m->vertex_count, m->triangle_count, stem);
  put_comment(f, comment);
  for (size_t v = 0; v < m->vertex_count; v++) put_numbers(f, "v", 9, m->positions + 3 * v, 3);
  if (m->uvs)
    for (size_t v = 0; v < m->vertex_count; v++) {
      const double uv[2] = {m->uvs[2 * v], m->uvs[2 * v + 1]};
      put_numbers(f, "vt", 7, uv, 2);
    }
  if (m->normals)
    for (size_t v = 0; v < m->vertex_count; v++) {
      const double nv[3] = {m->normals[3 * v], m->normals[3 * v + 1], m->normals[3 * v + 2]};
      put_numbers(f, "vn", 6, nv, 3);
    }
  put_faces(f, m);
  return bbc__atomic_commit(&af, err);
}

bbc_result bbc_mesh_write_obj(const char *obj_path, const bbc_mesh *m,
                              const bbc_obj_options *options, bbc_error *err) {
  assert(obj_path && m);
  const char *comment = options ? options->comment : NULL;
  int unlit = options ? options->unlit : 0;
  size_t len = strlen(obj_path);
  if (len < 5 || strcasecmp(obj_path + len - 4, ".obj"))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: OBJ output must end in .obj", obj_path);
  if (m->kind != BBC_MESH_TRIANGLES || m->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: nothing to write (no triangles)", obj_path);

  char stem[256], dir[2048];
  /* The MTL and PNG names: the OBJ's stem with bytes outside
   * [A-Za-z0-9_.-] as '_', since `mtllib` and `map_Kd` split at spaces
   * (an OBJ named "my tree.obj" gets my_tree.mtl, my_tree_obj_billboards.png). */
  char raw_stem[256];
  path_stem(obj_path, raw_stem, sizeof raw_stem);
  bbc__safe_name(raw_stem, stem, sizeof stem);
  bbc__path_folder(obj_path, dir, sizeof dir);

  /* Texture file names: bbc_texture_file_name's rule. */
  char(*tex_names)[520] = calloc(m->texture_count ? m->texture_count : 1, sizeof *tex_names);
  /* Files written so far: removed again when a later one fails. */
  char(*written)[2600] = calloc(m->texture_count + 1, sizeof *written);
  size_t n_written = 0;
  if (!tex_names || !written) {
    free(tex_names);
    free(written);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", obj_path);
  }
  char tex_stem[270];
  bbc__side_file_stem(obj_path, 1, tex_stem, sizeof tex_stem);
  bbc_result r = write_textures(m, tex_stem, dir, tex_names, written, &n_written, err);
  char mtl_path[2400];
  snprintf(mtl_path, sizeof mtl_path, "%s%s.mtl", dir, stem);
  if (r == BBC_OK) r = write_mtl(mtl_path, m, tex_names, unlit, err);
  free(tex_names);
  if (r == BBC_OK) {
    snprintf(written[n_written++], sizeof written[0], "%s", mtl_path);
    r = write_obj_file(obj_path, m, stem, comment, err);
  }
  if (r != BBC_OK)
    for (size_t i = 0; i < n_written; i++) remove(written[i]);
  free(written);
  return r;
}
