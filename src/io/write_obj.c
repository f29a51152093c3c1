/* write_obj.c — Wavefront OBJ + MTL + PNG textures, every file atomic. */
#include "io.h"

#include <assert.h>
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* "TAG x y ..." (count numbers of `digits` significant digits, spelt as in
 * the C locale) and a line end. */
static void put_numbers(bbc__text *t, const char *tag, int digits, const double *v, int count) {
  bbc__text_puts(t, tag);
  for (int k = 0; k < count; k++) {
    bbc__text_puts(t, " ");
    bbc__text_number(t, digits, v[k]);
  }
  bbc__text_puts(t, "\n");
}

/* Writes the text out to f once it holds 1 MiB (an OBJ is written as it
 * goes); 0 when out of memory or the write failed. */
static int spill(bbc__text *t, FILE *f) {
  return t->size < (1u << 20) ? !t->oom : bbc__text_flush(t, f);
}

/* Base name of a path without folder and extension, into out. */
static void path_stem(const char *path, char *out, size_t n) {
  const char *s = strrchr(path, '/');
  s = s ? s + 1 : path;
  snprintf(out, n, "%s", s);
  char *dot = strrchr(out, '.');
  if (dot) *dot = 0;
}

/* Comment lines "# ..." for each line of `text` (may be NULL). */
static void put_comment(bbc__text *t, const char *text) {
  for (const char *p = text; p && *p;) {
    size_t n = strcspn(p, "\r\n");
    bbc__text_printf(t, "# %.*s\n", (int)n, p);
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

/* The rest of the text into the file, then the file committed (or
 * removed: out of memory). */
static bbc_result finish(bbc__atomic_file *af, bbc__text *t, const char *path, bbc_error *err) {
  int oom = t->oom;
  if (!oom) bbc__text_flush(t, af->fp); /* a failed write: the commit says so */
  bbc__text_free(t);
  if (oom) {
    bbc__atomic_abort(af);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  return bbc__atomic_commit(af, err);
}

/* The MTL: each material's colour, opacity and textures (map_d too when the
 * texture has alpha); illum 0 when unlit. */
static bbc_result write_mtl(const char *mtl_path, const bbc_mesh *m, char (*tex_names)[520],
                            int unlit, bbc_error *err) {
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, mtl_path, err);
  if (r != BBC_OK) return r;
  bbc__text t = {0};
  bbc__text_printf(&t, "# written by bbcgen %s\n", BBC_VERSION_STRING);
  for (size_t i = 0; i < m->material_count; i++) {
    const bbc_material *mat = &m->materials[i];
    char safe[128];
    bbc__safe_name(mat->name, safe, sizeof safe);
    bbc__text_printf(&t, "\nnewmtl %s\n", safe);
    const double kd[4] = {mat->base_color[0], mat->base_color[1], mat->base_color[2],
                          mat->base_color[3]};
    put_numbers(&t, "Kd", 6, kd, 3);
    if (mat->base_color[3] < 1.0f) put_numbers(&t, "d", 6, kd + 3, 1);
    if (unlit) bbc__text_puts(&t, "illum 0\n"); /* colour only, no lighting */
    if (mat->texture >= 0 && tex_names[mat->texture][0]) {
      bbc__text_printf(&t, "map_Kd %s\n", tex_names[mat->texture]);
      if (m->textures[mat->texture].has_alpha)
        bbc__text_printf(&t, "map_d %s\n", tex_names[mat->texture]);
    }
  }
  return finish(&af, &t, mtl_path, err);
}

/* The faces in mesh order: a group line whenever the group changes, a
 * usemtl line whenever the material does (restated inside each group);
 * corners name their vt and vn when the mesh has them. */
static void put_faces(bbc__text *t, FILE *f, const bbc_mesh *m) {
  uint32_t cur_group = UINT32_MAX, cur_mat = UINT32_MAX;
  for (size_t k = 0; k < m->triangle_count && spill(t, f); k++) {
    if (m->face_group[k] != cur_group) {
      cur_group = m->face_group[k];
      char safe[256];
      bbc__safe_name(m->group_names[cur_group], safe, sizeof safe);
      bbc__text_printf(t, "g %s\n", safe);
      cur_mat = UINT32_MAX; /* restate the material inside each group */
    }
    if (m->face_material[k] != cur_mat) {
      cur_mat = m->face_material[k];
      char safe[128];
      bbc__safe_name(m->materials[cur_mat].name, safe, sizeof safe);
      bbc__text_printf(t, "usemtl %s\n", safe);
    }
    const uint32_t *ix = m->indices + 3 * k;
    bbc__text_puts(t, "f");
    for (int c = 0; c < 3; c++) {
      unsigned long i = (unsigned long)ix[c] + 1;
      if (m->uvs && m->normals)
        bbc__text_printf(t, " %lu/%lu/%lu", i, i, i);
      else if (m->uvs)
        bbc__text_printf(t, " %lu/%lu", i, i);
      else if (m->normals)
        bbc__text_printf(t, " %lu//%lu", i, i);
      else
        bbc__text_printf(t, " %lu", i);
    }
    bbc__text_puts(t, "\n");
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
  bbc__text t = {0};
  bbc__text_printf(&t, "# written by bbcgen %s: %zu vertices, %zu triangles\nmtllib %s.mtl\n",
                   BBC_VERSION_STRING, m->vertex_count, m->triangle_count, stem);
  put_comment(&t, comment);
  for (size_t v = 0; v < m->vertex_count && spill(&t, f); v++)
    put_numbers(&t, "v", 9, m->positions + 3 * v, 3);
  if (m->uvs)
    for (size_t v = 0; v < m->vertex_count && spill(&t, f); v++) {
      const double uv[2] = {m->uvs[2 * v], m->uvs[2 * v + 1]};
      put_numbers(&t, "vt", 7, uv, 2);
    }
  if (m->normals)
    for (size_t v = 0; v < m->vertex_count && spill(&t, f); v++) {
      const double nv[3] = {m->normals[3 * v], m->normals[3 * v + 1], m->normals[3 * v + 2]};
      put_numbers(&t, "vn", 6, nv, 3);
    }
  put_faces(&t, f, m);
  return finish(&af, &t, obj_path, err);
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
