/* ply_mesh.c — a PLY file as a triangle mesh: polygons as fans and
 * triangle strips as triangles, then what the format lacks: one material
 * ("default", textured when a TextureFile comment names a file) and one
 * group. */
#include "ply.h"

#include <stdlib.h>
#include <string.h>

/* Finds the index list of a face or tristrips element with records:
 * "vertex_indices" (the standard name) or "vertex_index" (Assimp and some
 * scanners write that). Other face properties (flags, per-face texture
 * coordinates) are read past and ignored. */
static bbc_result ply_map_index_list(const ply_reader *pp, const ply_element *e, size_t *out,
                                     bbc_error *err) {
  size_t k = ply_find_property(e, "vertex_indices");
  if (k == SIZE_MAX) k = ply_find_property(e, "vertex_index");
  if (k == SIZE_MAX)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY element '%s' has no 'vertex_indices' list property; cannot read "
                     "its %llu records",
                     pp->path, e->name, (unsigned long long)e->count);
  if (e->props[k].count_type == PLY_NONE)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY %s property '%s' is a single value, not a list of vertex indices",
                     pp->path, e->name, e->props[k].name);
  *out = k;
  return BBC_OK;
}

/* Looks up the elements a mesh is made of. */
bbc_result bbc__ply_map_faces(ply_reader *pp, const ply_header *h, bbc_error *err) {
  const ply_element *face = bbc__ply_find_element(h, "face");
  const ply_element *strips = bbc__ply_find_element(h, "tristrips");
  pp->face = face && face->count > 0 ? face : NULL;
  pp->strips = strips && strips->count > 0 ? strips : NULL;
  bbc_result r = BBC_OK;
  if (pp->face) r = ply_map_index_list(pp, pp->face, &pp->face_list, err);
  if (r == BBC_OK && pp->strips) r = ply_map_index_list(pp, pp->strips, &pp->strip_list, err);
  if (r == BBC_OK && pp->vertex->count > UINT32_MAX)
    r = bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                  "%s: PLY mesh has %llu vertices; at most %lu are supported (32-bit indices)",
                  pp->path, (unsigned long long)pp->vertex->count, (unsigned long)UINT32_MAX);
  return r;
}

static bbc_result ply_add_triangle(ply_reader *pp, uint32_t a, uint32_t b, uint32_t c,
                                   bbc_error *err) {
  bbc_mesh *m = pp->mesh;
  if (m->triangle_count == pp->triangle_cap) {
    size_t cap = pp->triangle_cap ? 2 * pp->triangle_cap : 64;
    uint32_t *ni = NULL;
    if (cap <= SIZE_MAX / (3 * sizeof *ni)) ni = realloc(m->indices, cap * 3 * sizeof *ni);
    if (!ni)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu triangles",
                       pp->path, cap);
    m->indices = ni;
    pp->triangle_cap = cap;
  }
  uint32_t *t = m->indices + 3 * m->triangle_count++;
  t[0] = a;
  t[1] = b;
  t[2] = c;
  return BBC_OK;
}

/* Checks the vertex indices of record `index` of a face element (strip 0)
 * or a tristrips element (strip 1), held in pp->list, and adds its
 * triangles. A face with n >= 3 corners becomes the fan (0, i, i+1). In a
 * strip, -1 restarts the strip and every other index makes a triangle with
 * the two before it, the winding alternating so that all face the same way;
 * strip triangles that repeat an index are the usual joints between strips,
 * not surface, and are skipped. Messages locate the record as in
 * ply_store_vertex. */
bbc_result bbc__ply_store_polygon(ply_reader *pp, const ply_element *e, int strip, uint64_t index,
                                  size_t line, uint64_t offset, bbc_error *err) {
  const double *v = pp->list.items;
  size_t n = pp->list.count;
  uint64_t nv = pp->vertex->count;
  ply_place pl;
  if (!strip && n < 3) {
    ply_place_set(&pl, line, offset);
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: %sface %llu%s has %zu vertex ind%s; a face needs at least 3", pp->path,
                     pl.pre, (unsigned long long)index, pl.post, n, n == 1 ? "ex" : "ices");
  }
  for (size_t j = 0; j < n; j++) {
    double x = v[j];
    if (strip && x == -1.0) continue;
    if (!isfinite(x) || x != floor(x)) {
      ply_place_set(&pl, line, offset);
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: %s%s %llu%s: vertex index %g is not a whole number", pp->path, pl.pre,
                       e->name, (unsigned long long)index, pl.post, x);
    }
    if (x < 0 || x >= (double)nv) {
      ply_place_set(&pl, line, offset);
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: %s%s %llu%s refers to vertex %.0f, but the file has %llu vert%s",
                       pp->path, pl.pre, e->name, (unsigned long long)index, pl.post, x,
                       (unsigned long long)nv, nv == 1 ? "ex" : "ices");
    }
  }
  bbc_result r = BBC_OK;
  if (!strip) {
    for (size_t j = 1; r == BBC_OK && j + 1 < n; j++)
      r = ply_add_triangle(pp, (uint32_t)v[0], (uint32_t)v[j], (uint32_t)v[j + 1], err);
    return r;
  }
  size_t run = 0; /* indices so far in the current strip */
  uint32_t a = 0, b = 0;
  for (size_t j = 0; r == BBC_OK && j < n; j++) {
    if (v[j] == -1.0) {
      run = 0;
      continue;
    }
    uint32_t c = (uint32_t)v[j];
    if (run >= 2 && a != b && b != c && a != c)
      r = run % 2 == 0 ? ply_add_triangle(pp, a, b, c, err) : ply_add_triangle(pp, b, a, c, err);
    a = b;
    b = c;
    run++;
  }
  return r;
}

/* Gives the material the texture a "comment TextureFile" line names. A
 * texture that cannot be found or decoded is a warning, not an error: the
 * material keeps its base colour and texture_ref. */
static bbc_result ply_load_texture(ply_reader *pp, const char *ref, const bbc_load_options *opt,
                                   bbc_error *err) {
  bbc_mesh *m = pp->mesh;
  bbc_material *mat = &m->materials[0];
  mat->texture_ref = bbc__strdup(ref);
  if (!mat->texture_ref) goto oom;
  char resolved[4096];
  if (!bbc__texture_resolve(pp->path, ref, BBC__TEXTURE_FILE, resolved, sizeof resolved)) {
    bbc__log(&opt->callbacks, BBC_LOG_WARNING,
             "%s: texture '%s' (named by the header's TextureFile comment) not found beside the "
             "model; using the base colour",
             pp->path, ref);
    return BBC_OK;
  }
  bbc_image img;
  memset(&img, 0, sizeof img);
  if (!opt->skip_textures) {
    bbc_error ierr;
    memset(&ierr, 0, sizeof ierr);
    if (bbc_image_load(resolved, &img, &ierr) != BBC_OK) {
      bbc__log(&opt->callbacks, BBC_LOG_WARNING, "%s: texture: %s; using the base colour", pp->path,
               ierr.message);
      return BBC_OK;
    }
  }
  m->textures = calloc(1, sizeof *m->textures);
  if (!m->textures) {
    bbc_image_free(&img);
    goto oom;
  }
  m->textures[0].image = img; /* owned by the mesh from here on */
  m->textures[0].has_alpha = bbc_image_has_transparency(&img);
  m->texture_count = 1;
  m->textures[0].path = bbc__strdup(resolved);
  if (!m->textures[0].path) goto oom;
  mat->texture = 0;
  return BBC_OK;
oom:
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", pp->path);
}

/* Completes a mesh read from PLY: PLY has no materials or groups, so every
 * triangle gets material 0, "default" (grey 0.8, opaque, textured when the
 * header names a TextureFile), and group 0, named after the file's stem
 * ("bunny" for "scans/bunny.ply") so that the group says where the geometry
 * came from, as OBJ groups do. */
bbc_result bbc__ply_finish_mesh(ply_reader *pp, const ply_header *h, const bbc_load_options *opt,
                                bbc_error *err) {
  bbc_mesh *m = pp->mesh;
  size_t n = m->triangle_count ? m->triangle_count : 1;
  if (m->triangle_count && m->triangle_count < pp->triangle_cap) {
    uint32_t *shrunk = realloc(m->indices, m->triangle_count * 3 * sizeof *shrunk);
    if (shrunk) m->indices = shrunk;
  }
  m->face_material = calloc(n, sizeof *m->face_material);
  m->face_group = calloc(n, sizeof *m->face_group);
  m->materials = calloc(1, sizeof *m->materials);
  m->group_names = calloc(1, sizeof *m->group_names);
  if (!m->face_material || !m->face_group || !m->materials || !m->group_names) goto oom;
  m->material_count = 1;
  bbc_material *mat = &m->materials[0];
  mat->name = bbc__strdup("default");
  if (!mat->name) goto oom;
  mat->base_color[0] = mat->base_color[1] = mat->base_color[2] = 0.8f;
  mat->base_color[3] = 1.0f;
  mat->texture = -1;
  mat->texture_ref = NULL;
  const char *base = strrchr(pp->path, '/') ? strrchr(pp->path, '/') + 1 : pp->path;
  const char *dot = strrchr(base, '.');
  size_t stem = dot && dot != base ? (size_t)(dot - base) : strlen(base);
  m->group_names[0] = tok_dup((token){base, stem});
  if (!m->group_names[0]) goto oom;
  m->group_count = 1;
  if (h->texture_file) return ply_load_texture(pp, h->texture_file, opt, err);
  return BBC_OK;
oom:
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", pp->path);
}
