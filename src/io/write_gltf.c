/* write_gltf.c — glTF 2.0 output (.glb, or .gltf + .bin + .png files), every
 * file atomic, the JSON written by hand (cJSON, which the readers use, builds
 * a tree first; this writes in one pass). Layout of the binary buffer, per mesh in node order,
 * every bufferView 4-byte aligned: POSITION (float VEC3), NORMAL (float VEC3, when present),
 * TEXCOORD_0 (float VEC2, when present), TANGENT (float VEC4, when present), then the indices of
 * each primitive (one per material used, in material order), then (.glb only) the mesh's PNG
 * images. Accessors follow the non-image bufferViews one to one. The same mesh and options give
 * byte-identical files. */
#include "io.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the JSON and the binary chunk: io's text buffer ----------------------- */

/* Pads with `byte` to a multiple of 4. */
static void gbuf_pad4(bbc__text *b, unsigned char byte) {
  while (b->size % 4 && !b->oom) bbc__text_append(b, &byte, 1);
}

/* A JSON string: quotes, backslashes and control characters escaped, bytes
 * that are not valid UTF-8 replaced by U+FFFD (JSON must be UTF-8). */
static void gbuf_string(bbc__text *b, const char *s) {
  const unsigned char *p = (const unsigned char *)s;
  bbc__text_puts(b, "\"");
  while (*p) {
    unsigned char c = *p;
    if (c == '"' || c == '\\') {
      char e[2] = {'\\', (char)c};
      bbc__text_append(b, e, 2);
      p++;
    } else if (c < 0x20) {
      bbc__text_printf(b, "\\u%04x", c);
      p++;
    } else if (c < 0x80) {
      bbc__text_append(b, p, 1);
      p++;
    } else {
      /* Length of a well-formed UTF-8 sequence starting here, or 0. */
      size_t n = 0;
      if (c >= 0xC2 && c <= 0xDF)
        n = 2;
      else if (c >= 0xE0 && c <= 0xEF)
        n = 3;
      else if (c >= 0xF0 && c <= 0xF4)
        n = 4;
      for (size_t k = 1; k < n; k++)
        if ((p[k] & 0xC0) != 0x80) n = 0;
      /* Overlong forms, surrogates and code points above U+10FFFF. */
      if (n == 3 && ((c == 0xE0 && p[1] < 0xA0) || (c == 0xED && p[1] >= 0xA0))) n = 0;
      if (n == 4 && ((c == 0xF0 && p[1] < 0x90) || (c == 0xF4 && p[1] >= 0x90))) n = 0;
      if (n) {
        bbc__text_append(b, p, n);
        p += n;
      } else {
        bbc__text_puts(b, "\\ufffd");
        p++;
      }
    }
  }
  bbc__text_puts(b, "\"");
}

static void put_u32le(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)v;
  p[1] = (unsigned char)(v >> 8);
  p[2] = (unsigned char)(v >> 16);
  p[3] = (unsigned char)(v >> 24);
}

static void gbuf_u32(bbc__text *b, uint32_t v) {
  unsigned char q[4];
  put_u32le(q, v);
  bbc__text_append(b, q, 4);
}

static void gbuf_f32(bbc__text *b, float v) {
  uint32_t u;
  memcpy(&u, &v, 4);
  gbuf_u32(b, u); /* little-endian whatever the host */
}

/* ---- a minimal JSON syntax check for extras_json ------------------------- */

typedef struct jscan {
  const char *p;
  int depth;
} jscan;

static void js_ws(jscan *s) {
  while (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r') s->p++;
}

static int js_value(jscan *s);

static int js_string(jscan *s) {
  if (*s->p != '"') return 0;
  s->p++;
  for (;;) {
    unsigned char c = (unsigned char)*s->p;
    if (c == 0 || c < 0x20) return 0;
    s->p++;
    if (c == '"') return 1;
    if (c == '\\') {
      char e = *s->p++;
      if (e == 'u') {
        for (int k = 0; k < 4; k++, s->p++)
          if (!isxdigit((unsigned char)*s->p)) return 0;
      } else if (!strchr("\"\\/bfnrt", e) || e == 0) {
        return 0;
      }
    }
  }
}

static int js_number(jscan *s) {
  const char *p = s->p;
  if (*p == '-') p++;
  if (*p == '0')
    p++;
  else if (*p >= '1' && *p <= '9')
    while (isdigit((unsigned char)*p)) p++;
  else
    return 0;
  if (*p == '.') {
    p++;
    if (!isdigit((unsigned char)*p)) return 0;
    while (isdigit((unsigned char)*p)) p++;
  }
  if (*p == 'e' || *p == 'E') {
    p++;
    if (*p == '+' || *p == '-') p++;
    if (!isdigit((unsigned char)*p)) return 0;
    while (isdigit((unsigned char)*p)) p++;
  }
  s->p = p;
  return 1;
}

static int js_container(jscan *s, char open, char close) {
  if (*s->p != open || ++s->depth > 64) return 0;
  s->p++;
  js_ws(s);
  if (*s->p == close) {
    s->p++;
    s->depth--;
    return 1;
  }
  for (;;) {
    if (open == '{') {
      if (!js_string(s)) return 0;
      js_ws(s);
      if (*s->p++ != ':') return 0;
      js_ws(s);
    }
    if (!js_value(s)) return 0;
    js_ws(s);
    if (*s->p == close) {
      s->p++;
      s->depth--;
      return 1;
    }
    if (*s->p++ != ',') return 0;
    js_ws(s);
  }
}

static int js_value(jscan *s) {
  switch (*s->p) {
  case '{':
    return js_container(s, '{', '}');
  case '[':
    return js_container(s, '[', ']');
  case '"':
    return js_string(s);
  case 't':
    return strncmp(s->p, "true", 4) ? 0 : (s->p += 4, 1);
  case 'f':
    return strncmp(s->p, "false", 5) ? 0 : (s->p += 5, 1);
  case 'n':
    return strncmp(s->p, "null", 4) ? 0 : (s->p += 4, 1);
  default:
    return js_number(s);
  }
}

/* 1 when `text` is one JSON object (surrounding white space allowed). A
 * syntax check only, not a parse: the text is embedded verbatim. */
static int is_json_object(const char *text) {
  jscan s = {text, 0};
  js_ws(&s);
  if (*s.p != '{' || !js_value(&s)) return 0;
  js_ws(&s);
  return *s.p == 0;
}

/* ---- file names ------------------------------------------------------------ */

/* Stem of `path` (no folder, no extension) with every byte outside
 * [A-Za-z0-9_.-] replaced by '_', so that it is a valid relative URI as is. */
static void safe_stem(const char *path, char *out, size_t n) {
  const char *s = strrchr(path, '/');
  s = s ? s + 1 : path;
  const char *dot = strrchr(s, '.');
  char base[1024];
  snprintf(base, sizeof base, "%.*s", (int)(dot ? (size_t)(dot - s) : strlen(s)), s);
  bbc__safe_name(base, out, n);
}

/* ---- the writer -------------------------------------------------------------- */

typedef struct view {
  size_t offset, length;
  int target; /* 34962 vertex data, 34963 indices, 0 none (images) */
} view;

/* Per mesh: where its data went. */
typedef struct mesh_out {
  size_t first_accessor; /* POSITION; then NORMAL, TEXCOORD_0, TANGENT when present */
  int has_normal, has_uv, has_tangent;
  size_t first_index_accessor;
  size_t first_material; /* glTF material of its material 0 */
  size_t first_image;    /* glTF image of its first used texture */
  size_t *mat_tris;      /* triangles per material */
  int *tex_gltf;         /* mesh texture -> glTF texture, -1 unused */
  float pmin[3], pmax[3];
  size_t nv;
  int small;
  size_t images_written; /* images this mesh added (not shared with an earlier one) */
} mesh_out;

/* One scene being written: the nodes and options, the binary buffer and its
 * bufferViews, the images, the JSON, and the side files written so far. */
typedef struct gltf_writer {
  const char *path;
  const bbc_gltf_node *nodes;
  size_t node_count;
  const bbc_gltf_options *options;
  const char *extras; /* the asset's extras_json, or NULL */
  int binary, lod, unlit;
  const char *stem, *dir; /* file names' stem; the output's folder */
  const char *tex_stem;   /* the images' stem (bbc__side_file_stem) */
  bbc__text bin, json;
  mesh_out *mo; /* per node */
  view *views;
  size_t n_views;
  size_t *image_view;       /* .glb: the bufferView of each image */
  char (*image_names)[200]; /* each image's file name without ".png" */
  const bbc_image **image_src;
  size_t n_images;
  size_t pngs_written; /* .gltf side files written, removed again on failure */
  int bin_written;
  bbc_error *err;
} gltf_writer;

static bbc_result check_mesh(const char *path, const bbc_mesh *m, bbc_error *err) {
  if (m->kind != BBC_MESH_TRIANGLES || m->triangle_count == 0 || m->vertex_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: nothing to write (no triangles)", path);
  if (m->vertex_count > UINT32_MAX || m->triangle_count > UINT32_MAX / 3)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "%s: mesh too large for glTF", path);
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (m->face_material[t] >= m->material_count)
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY, "%s: triangle %zu names material %u of %zu",
                       path, t, (unsigned)m->face_material[t], m->material_count);
    for (int k = 0; k < 3; k++)
      if (m->indices[3 * t + k] >= m->vertex_count)
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY, "%s: triangle %zu: index out of range",
                         path, t);
  }
  for (size_t i = 0; i < m->material_count; i++) {
    if (m->materials[i].normal_map < 0 || (size_t)m->materials[i].normal_map > m->texture_count)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: material %zu: bad normal map", path,
                       i);
    if (m->materials[i].occlusion_map < 0 ||
        (size_t)m->materials[i].occlusion_map > m->texture_count)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: material %zu: bad occlusion map", path,
                       i);
  }
  return BBC_OK;
}

static int texture_used(const bbc_mesh *m, size_t t) {
  if (!m->textures[t].image.rgba) return 0;
  for (size_t i = 0; i < m->material_count; i++)
    if (m->materials[i].texture == (int)t || m->materials[i].normal_map == (int)t + 1 ||
        m->materials[i].occlusion_map == (int)t + 1)
      return 1;
  return 0;
}

/* POSITION, with the bounds its accessor needs; a coordinate that does not
 * fit in a float is refused. */
static bbc_result put_positions(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  size_t nv = m->vertex_count;
  bbc__text *bin = &w->bin;
  w->views[w->n_views++] = (view){bin->size, nv * 12, 34962};
  for (size_t v = 0; v < nv; v++)
    for (int k = 0; k < 3; k++) {
      float f = (float)m->positions[3 * v + k];
      if (!isfinite(f))
        return bbc__fail(w->err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: vertex %zu does not fit in a float (%g)", w->path, v,
                         m->positions[3 * v + k]);
      if (v == 0 || f < mo->pmin[k]) mo->pmin[k] = f;
      if (v == 0 || f > mo->pmax[k]) mo->pmax[k] = f;
      gbuf_f32(bin, f);
    }
  return BBC_OK;
}

/* NORMAL, when the mesh has normals. */
static void put_normals(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  size_t nv = m->vertex_count;
  bbc__text *bin = &w->bin;
  if (!m->normals) return;
  mo->has_normal = 1;
  w->views[w->n_views++] = (view){bin->size, nv * 12, 34962};
  for (size_t v = 0; v < nv; v++) {
    /* glTF requires unit normals: renormalise float rounding away; a zero
     * or non-finite normal (never from bbc_mesh_finalize) becomes +Z. */
    const float *n = m->normals + 3 * v;
    double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
    for (int k = 0; k < 3; k++)
      gbuf_f32(bin, isfinite(len) && len > 1e-20 ? (float)(n[k] / len) : (k == 2 ? 1.0f : 0.0f));
  }
}

/* TEXCOORD_0, when the mesh has texture coordinates. */
static bbc_result put_uvs(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  size_t nv = m->vertex_count;
  bbc__text *bin = &w->bin;
  if (!m->uvs) return BBC_OK;
  mo->has_uv = 1;
  w->views[w->n_views++] = (view){bin->size, nv * 8, 34962};
  for (size_t v = 0; v < nv; v++) {
    float u = m->uvs[2 * v], t = m->uvs[2 * v + 1];
    if (!isfinite(u) || !isfinite(t))
      return bbc__fail(w->err, BBC_ERROR_INVALID_GEOMETRY, "%s: vertex %zu has a non-finite uv",
                       w->path, v);
    gbuf_f32(bin, u);
    gbuf_f32(bin, 1.0f - t); /* OpenGL's bottom-left origin -> glTF's top-left */
  }
  return BBC_OK;
}

/* TANGENT, when the mesh has tangents and normals. glTF: unit xyz, w = +-1;
 * the bitangent is cross(normal, tangent) * w and points up the image (our
 * v, glTF's -v). */
static void put_tangents(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  size_t nv = m->vertex_count;
  bbc__text *bin = &w->bin;
  if (!m->tangents || !m->normals) return;
  mo->has_tangent = 1;
  w->views[w->n_views++] = (view){bin->size, nv * 16, 34962};
  for (size_t v = 0; v < nv; v++) {
    const float *t = m->tangents + 4 * v;
    double len = sqrt((double)t[0] * t[0] + (double)t[1] * t[1] + (double)t[2] * t[2]);
    for (int k = 0; k < 3; k++)
      gbuf_f32(bin, isfinite(len) && len > 1e-20 ? (float)(t[k] / len) : (k == 0 ? 1.0f : 0.0f));
    gbuf_f32(bin, t[3] < 0 ? -1.0f : 1.0f);
  }
}

/* The indices, one bufferView per material used, keeping the face order
 * within each: 16 bits when every index fits below 65535 (itself the
 * primitive restart value), else 32. */
static void put_indices(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  bbc__text *bin = &w->bin;
  mo->small = m->vertex_count <= 65535;
  for (size_t i = 0; i < m->material_count; i++) {
    if (!mo->mat_tris[i]) continue;
    size_t count = 3 * mo->mat_tris[i];
    w->views[w->n_views++] = (view){bin->size, count * (mo->small ? 2 : 4), 34963};
    for (size_t t = 0; t < m->triangle_count; t++) {
      if (m->face_material[t] != i) continue;
      for (int k = 0; k < 3; k++) {
        uint32_t ix = m->indices[3 * t + k];
        if (mo->small) {
          unsigned char q[2] = {(unsigned char)ix, (unsigned char)(ix >> 8)};
          bbc__text_append(bin, q, 2);
        } else {
          gbuf_u32(bin, ix);
        }
      }
    }
    gbuf_pad4(bin, 0);
  }
}

/* Texture t of the mesh as the next image: a PNG in the buffer (.glb) or a
 * file beside the .gltf named <stem>_gltf_<material>[_nm].png, made unique
 * within the file. */
static bbc_result put_image(gltf_writer *w, const bbc_mesh *m, mesh_out *mo, size_t t) {
  const bbc_image *im = &m->textures[t].image;
  size_t n = w->n_images;
  w->image_src[n] = im;
  mo->images_written++;
  bbc__text png = {0};
  bbc_result pr = bbc__png_encode(im, &png.data, &png.size);
  png.cap = png.size;
  if (pr != BBC_OK)
    return bbc__fail(w->err, pr, "%s: cannot encode texture %zu as PNG", w->path, t);
  mo->tex_gltf[t] = (int)n;
  char name[160];
  bbc_texture_file_name(m, t, name, sizeof name);
  snprintf(w->image_names[n], sizeof w->image_names[0], "%s_%s", w->tex_stem, name);
  for (size_t i = 0; i < n; i++)
    if (!strcmp(w->image_names[i], w->image_names[n])) {
      snprintf(w->image_names[n], sizeof w->image_names[0], "%s_%s_%zu", w->tex_stem, name, n);
      break;
    }
  bbc_result r = BBC_OK;
  if (w->binary) {
    w->image_view[n] = w->n_views;
    w->views[w->n_views++] = (view){w->bin.size, png.size, 0};
    bbc__text_append(&w->bin, png.data, png.size);
    gbuf_pad4(&w->bin, 0);
  } else {
    char full[2600];
    snprintf(full, sizeof full, "%s%s.png", w->dir, w->image_names[n]);
    r = bbc_write_file_atomic(full, png.data, png.size, w->err);
    if (r == BBC_OK) w->pngs_written = n + 1;
  }
  w->n_images++;
  free(png.data);
  return r;
}

/* The textures a material uses and that were decoded, in texture order. */
static bbc_result put_images(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  mo->first_image = w->n_images;
  for (size_t t = 0; t < m->texture_count; t++) {
    mo->tex_gltf[t] = -1;
    if (!texture_used(m, t)) continue;
    const bbc_image *im = &m->textures[t].image;
    /* The same texels as an image written before (levels of detail sharing
     * one atlas): that image again. */
    int same = -1;
    for (size_t i = 0; i < w->n_images && same < 0; i++)
      if (w->image_src[i]->width == im->width && w->image_src[i]->height == im->height &&
          !memcmp(w->image_src[i]->rgba, im->rgba, 4 * (size_t)im->width * im->height))
        same = (int)i;
    if (same >= 0) {
      mo->tex_gltf[t] = same;
      continue;
    }
    bbc_result r = put_image(w, m, mo, t);
    if (r != BBC_OK) return r;
  }
  return BBC_OK;
}

/* Writes one mesh's vertex data, indices and images into the buffer. */
static bbc_result put_mesh(gltf_writer *w, const bbc_mesh *m, mesh_out *mo) {
  mo->nv = m->vertex_count;
  for (size_t t = 0; t < m->triangle_count; t++) mo->mat_tris[m->face_material[t]]++;
  bbc_result r = put_positions(w, m, mo);
  if (r != BBC_OK) return r;
  put_normals(w, m, mo);
  r = put_uvs(w, m, mo);
  if (r != BBC_OK) return r;
  put_tangents(w, m, mo);
  put_indices(w, m, mo);
  r = put_images(w, m, mo);
  if (r != BBC_OK) return r;
  if (w->bin.oom) return bbc__fail(w->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", w->path);
  return BBC_OK;
}

static void put_floats(bbc__text *j, const float *v, int n) {
  for (int k = 0; k < n; k++) {
    if (k) bbc__text_puts(j, ",");
    bbc__text_number(j, 9, v[k]);
  }
}

/* Checks the path, the nodes and the extras before anything is written;
 * counts the bufferViews and textures the writer makes room for. */
static bbc_result check_scene(gltf_writer *w, const char *ext, size_t *total_views,
                              size_t *total_tex) {
  const char *path = w->path;
  bbc_error *err = w->err;
  if (strcmp(ext, w->binary ? "glb" : "gltf"))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: glTF output must end in %s", path,
                     w->binary ? ".glb" : ".gltf");
  if (w->node_count == 0 || !w->nodes)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: nothing to write (no meshes)", path);
  if (w->extras && !is_json_object(w->extras))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: extras_json is not one JSON object",
                     path);
  *total_views = *total_tex = 0;
  for (size_t n = 0; n < w->node_count; n++) {
    bbc_result r = check_mesh(path, w->nodes[n].mesh, err);
    if (r != BBC_OK) return r;
    if (w->nodes[n].extras_json && !is_json_object(w->nodes[n].extras_json))
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                       "%s: node %zu: extras_json is not one JSON object", path, n);
    *total_views += 4 + w->nodes[n].mesh->material_count + w->nodes[n].mesh->texture_count;
    *total_tex += w->nodes[n].mesh->texture_count;
  }
  return BBC_OK;
}

/* The binary buffer: every mesh in node order (see the top of the file),
 * numbering the accessors and materials each mesh's JSON refers to. */
static bbc_result lay_out_buffer(gltf_writer *w) {
  bbc_result r = BBC_OK;
  size_t n_acc = 0, n_mat = 0;
  for (size_t n = 0; n < w->node_count && r == BBC_OK; n++) {
    const bbc_mesh *m = w->nodes[n].mesh;
    mesh_out *mo = &w->mo[n];
    mo->mat_tris = calloc(m->material_count + 1, sizeof *mo->mat_tris);
    mo->tex_gltf = calloc(m->texture_count + 1, sizeof *mo->tex_gltf);
    if (!mo->mat_tris || !mo->tex_gltf)
      return bbc__fail(w->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", w->path);
    r = put_mesh(w, m, mo);
    mo->first_accessor = n_acc;
    n_acc += 1 + (size_t)mo->has_normal + (size_t)mo->has_uv + (size_t)mo->has_tangent;
    mo->first_index_accessor = n_acc;
    for (size_t i = 0; i < m->material_count; i++) n_acc += mo->mat_tris[i] ? 1 : 0;
    mo->first_material = n_mat;
    n_mat += m->material_count;
  }
  return r;
}

/* "asset" (with the caller's extras), "extensionsUsed" and "scene(s)".
 * Without a LOD chain every node is in the scene. With one, the scene holds
 * a group node (after the levels) whose children are the levels, named as
 * engines import LOD groups (<model>_LOD0, _LOD1, ...), and the finest
 * names the coarser ones through MSFT_lod. */
static void put_json_scene(gltf_writer *w) {
  bbc__text *j = &w->json;
  size_t node_count = w->node_count;
  bbc__text_puts(j,
                 "{\"asset\":{\"generator\":\"bbcgen " BBC_VERSION_STRING "\",\"version\":\"2.0\"");
  if (w->extras) {
    bbc__text_puts(j, ",\"extras\":");
    bbc__text_puts(j, w->extras);
  }
  bbc__text_puts(j, "},\n");
  if (w->lod || w->unlit)
    bbc__text_printf(j, "\"extensionsUsed\":[%s%s%s],\n", w->lod ? "\"MSFT_lod\"" : "",
                     w->lod && w->unlit ? "," : "", w->unlit ? "\"KHR_materials_unlit\"" : "");
  bbc__text_puts(j, "\"scene\":0,\"scenes\":[{\"nodes\":[");
  if (w->lod)
    bbc__text_printf(j, "%zu", node_count);
  else
    for (size_t n = 0; n < node_count; n++) bbc__text_printf(j, "%s%zu", n ? "," : "", n);
  bbc__text_puts(j, "]}],\n");
}

/* The finest level's MSFT_lod (the coarser levels' nodes) and, with
 * screen coverages, its extras: MSFT_screencoverage, one value per level,
 * before whatever the caller's extras `ex` hold. Returns the extras still to
 * write (NULL once merged). */
static const char *put_json_lod(gltf_writer *w, const char *ex) {
  bbc__text *j = &w->json;
  const bbc_gltf_options *options = w->options;
  bbc__text_puts(j, ",\"extensions\":{\"MSFT_lod\":{\"ids\":[");
  for (size_t k = 1; k < w->node_count; k++) bbc__text_printf(j, "%s%zu", k > 1 ? "," : "", k);
  bbc__text_puts(j, "]}}");
  if (options->screen_coverage) {
    bbc__text_puts(j, ",\"extras\":{\"MSFT_screencoverage\":[");
    for (size_t k = 0; k < w->node_count; k++) {
      if (k) bbc__text_puts(j, ",");
      bbc__text_number(j, 9, (float)options->screen_coverage[k]);
    }
    bbc__text_puts(j, "]");
    if (ex) {
      const char *body = ex + strspn(ex, " \t\r\n") + 1; /* after '{' */
      if (*(body + strspn(body, " \t\r\n")) != '}') bbc__text_puts(j, ",");
      bbc__text_puts(j, body);
    } else {
      bbc__text_puts(j, "}");
    }
    ex = NULL;
  }
  return ex;
}

/* "nodes": one per mesh, then the LOD group node when there is a chain. */
static void put_json_nodes(gltf_writer *w) {
  bbc__text *j = &w->json;
  const bbc_gltf_node *nodes = w->nodes;
  size_t node_count = w->node_count;
  bbc__text_puts(j, "\"nodes\":[");
  for (size_t n = 0; n < node_count; n++) {
    bbc__text_printf(j, "%s\n{\"mesh\":%zu", n ? "," : "", n);
    if (nodes[n].name) {
      bbc__text_puts(j, ",\"name\":");
      gbuf_string(j, nodes[n].name);
    }
    const char *ex = nodes[n].extras_json;
    if (w->lod && n == 0) ex = put_json_lod(w, ex);
    if (ex) {
      bbc__text_puts(j, ",\"extras\":");
      bbc__text_puts(j, ex);
    }
    bbc__text_puts(j, "}");
  }
  if (w->lod) {
    bbc__text_puts(j, ",\n{\"name\":");
    gbuf_string(j, w->options->lod_group_name ? w->options->lod_group_name : "lod_group");
    bbc__text_puts(j, ",\"children\":[");
    for (size_t n = 0; n < node_count; n++) bbc__text_printf(j, "%s%zu", n ? "," : "", n);
    bbc__text_puts(j, "]}");
  }
  bbc__text_puts(j, "],\n");
}

/* "meshes": one primitive per material used. */
static void put_json_meshes(gltf_writer *w) {
  bbc__text *j = &w->json;
  bbc__text_puts(j, "\"meshes\":[");
  for (size_t n = 0; n < w->node_count; n++) {
    const bbc_mesh *m = w->nodes[n].mesh;
    const mesh_out *o = &w->mo[n];
    bbc__text_puts(j, n ? ",\n{" : "\n{");
    if (w->nodes[n].name) {
      bbc__text_puts(j, "\"name\":");
      gbuf_string(j, w->nodes[n].name);
      bbc__text_puts(j, ",");
    }
    bbc__text_puts(j, "\"primitives\":[");
    size_t prim = 0, a = o->first_accessor;
    for (size_t i = 0; i < m->material_count; i++) {
      if (!o->mat_tris[i]) continue;
      size_t next = a + 1;
      bbc__text_printf(j, "%s\n{\"attributes\":{\"POSITION\":%zu", prim ? "," : "", a);
      if (o->has_normal) bbc__text_printf(j, ",\"NORMAL\":%zu", next++);
      if (o->has_uv) bbc__text_printf(j, ",\"TEXCOORD_0\":%zu", next++);
      if (o->has_tangent) bbc__text_printf(j, ",\"TANGENT\":%zu", next++);
      bbc__text_printf(j, "},\"indices\":%zu,\"material\":%zu,\"mode\":4}",
                       o->first_index_accessor + prim, o->first_material + i);
      prim++;
    }
    bbc__text_puts(j, "]}");
  }
  bbc__text_puts(j, "],\n");
}

/* "materials": every material of every mesh, alpha-masked. */
static void put_json_materials(gltf_writer *w) {
  bbc__text *j = &w->json;
  bbc__text_puts(j, "\"materials\":[");
  for (size_t n = 0; n < w->node_count; n++) {
    const bbc_mesh *m = w->nodes[n].mesh;
    const mesh_out *mo = &w->mo[n];
    for (size_t i = 0; i < m->material_count; i++) {
      const bbc_material *mat = &m->materials[i];
      bbc__text_puts(j, n || i ? ",\n{\"name\":" : "\n{\"name\":");
      gbuf_string(j, mat->name ? mat->name : "");
      bbc__text_puts(j, ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[");
      for (int k = 0; k < 4; k++) {
        float c = mat->base_color[k];
        c = c >= 0.0f ? (c <= 1.0f ? c : 1.0f) : (c < 0.0f ? 0.0f : 1.0f); /* NaN -> 1 */
        if (k < 3) c = (float)bbc__srgb_to_linear(c); /* glTF's factor is linear */
        if (k) bbc__text_puts(j, ",");
        bbc__text_number(j, 9, c);
      }
      bbc__text_puts(j, "]");
      int t = mat->texture;
      if (t >= 0 && (size_t)t < m->texture_count && mo->tex_gltf[t] >= 0)
        bbc__text_printf(j, ",\"baseColorTexture\":{\"index\":%d}", mo->tex_gltf[t]);
      float rough = mat->roughness > 0 && mat->roughness <= 1 ? mat->roughness : 1.0f;
      bbc__text_puts(j, ",\"metallicFactor\":0,\"roughnessFactor\":");
      bbc__text_number(j, 9, rough);
      bbc__text_puts(j, "}");
      int nmt = mat->normal_map - 1, aot = mat->occlusion_map - 1;
      if (nmt >= 0 && mo->tex_gltf[nmt] >= 0 && mo->has_tangent)
        bbc__text_printf(j, ",\"normalTexture\":{\"index\":%d}", mo->tex_gltf[nmt]);
      if (aot >= 0 && mo->tex_gltf[aot] >= 0)
        bbc__text_printf(j, ",\"occlusionTexture\":{\"index\":%d}", mo->tex_gltf[aot]);
      if (w->unlit) bbc__text_puts(j, ",\"extensions\":{\"KHR_materials_unlit\":{}}");
      bbc__text_printf(j, ",\"alphaMode\":\"MASK\",\"alphaCutoff\":0.5,\"doubleSided\":%s}",
                       mat->single_sided ? "false" : "true");
    }
  }
  bbc__text_puts(j, "],\n");
}

/* "samplers", "textures" and "images", when there are images. */
static void put_json_images(gltf_writer *w) {
  bbc__text *j = &w->json;
  if (!w->n_images) return;
  bbc__text_puts(j, "\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":33071,"
                    "\"wrapT\":33071}],\n\"textures\":[");
  for (size_t i = 0; i < w->n_images; i++)
    bbc__text_printf(j, "%s{\"sampler\":0,\"source\":%zu}", i ? "," : "", i);
  bbc__text_puts(j, "],\n\"images\":[");
  for (size_t i = 0; i < w->n_images; i++) {
    if (w->binary)
      bbc__text_printf(j, "%s{\"bufferView\":%zu,\"mimeType\":\"image/png\"}", i ? "," : "",
                       w->image_view[i]);
    else
      bbc__text_printf(j, "%s{\"uri\":\"%s.png\"}", i ? "," : "", w->image_names[i]);
  }
  bbc__text_puts(j, "],\n");
}

/* "accessors": they follow the bufferViews one to one, except images. */
static void put_json_accessors(gltf_writer *w) {
  bbc__text *j = &w->json;
  bbc__text_puts(j, "\"accessors\":[");
  size_t vi = 0, acc = 0;
  for (size_t n = 0; n < w->node_count; n++) {
    const bbc_mesh *m = w->nodes[n].mesh;
    const mesh_out *o = &w->mo[n];
    bbc__text_printf(j,
                     "%s\n{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,"
                     "\"type\":\"VEC3\",\"min\":[",
                     acc++ ? "," : "", vi++, o->nv);
    put_floats(j, o->pmin, 3);
    bbc__text_puts(j, "],\"max\":[");
    put_floats(j, o->pmax, 3);
    bbc__text_puts(j, "]}");
    if (o->has_normal)
      bbc__text_printf(
          j, ",\n{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"}", vi++,
          o->nv);
    if (o->has_uv)
      bbc__text_printf(
          j, ",\n{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"}", vi++,
          o->nv);
    if (o->has_tangent)
      bbc__text_printf(
          j, ",\n{\"bufferView\":%zu,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC4\"}", vi++,
          o->nv);
    for (size_t i = 0; i < m->material_count; i++) {
      if (!o->mat_tris[i]) continue;
      bbc__text_printf(
          j, ",\n{\"bufferView\":%zu,\"componentType\":%d,\"count\":%zu,\"type\":\"SCALAR\"}", vi++,
          o->small ? 5123 : 5125, 3 * o->mat_tris[i]);
    }
    if (w->binary) vi += o->images_written;
  }
  bbc__text_puts(j, "],\n");
}

/* "bufferViews" and the one buffer (.gltf: the .bin beside it). */
static void put_json_buffer(gltf_writer *w) {
  bbc__text *j = &w->json;
  bbc__text_puts(j, "\"bufferViews\":[");
  for (size_t i = 0; i < w->n_views; i++) {
    bbc__text_printf(j, "%s\n{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu", i ? "," : "",
                     w->views[i].offset, w->views[i].length);
    if (w->views[i].target) bbc__text_printf(j, ",\"target\":%d", w->views[i].target);
    bbc__text_puts(j, "}");
  }
  bbc__text_puts(j, "],\n\"buffers\":[{");
  if (!w->binary) bbc__text_printf(j, "\"uri\":\"%s.bin\",", w->stem);
  bbc__text_printf(j, "\"byteLength\":%zu}]}\n", w->bin.size);
}

/* The .glb: header, the JSON chunk (padded with blanks), the BIN chunk. */
static bbc_result write_glb(gltf_writer *w) {
  bbc__text *json = &w->json, *bin = &w->bin;
  bbc__text out = {0};
  gbuf_pad4(json, ' ');
  size_t total = 12 + 8 + json->size + 8 + bin->size;
  if (total > UINT32_MAX)
    return bbc__fail(w->err, BBC_ERROR_OUT_OF_RANGE, "%s: %zu bytes: too large for GLB (4 GiB)",
                     w->path, total);
  bbc__text_append(&out, "glTF", 4);
  gbuf_u32(&out, 2);
  gbuf_u32(&out, (uint32_t)total);
  gbuf_u32(&out, (uint32_t)json->size);
  bbc__text_append(&out, "JSON", 4);
  bbc__text_append(&out, json->data, json->size);
  gbuf_u32(&out, (uint32_t)bin->size);
  bbc__text_append(&out, "BIN\0", 4);
  bbc__text_append(&out, bin->data, bin->size);
  bbc_result r;
  if (out.oom)
    r = bbc__fail(w->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", w->path);
  else
    r = bbc_write_file_atomic(w->path, out.data, out.size, w->err);
  free(out.data);
  return r;
}

/* The .gltf and its .bin: the .bin first, so the .gltf never names a
 * missing file. */
static bbc_result write_gltf_files(gltf_writer *w) {
  char full[2600];
  snprintf(full, sizeof full, "%s%s.bin", w->dir, w->stem);
  bbc_result r = bbc_write_file_atomic(full, w->bin.data, w->bin.size, w->err);
  w->bin_written = r == BBC_OK;
  if (r == BBC_OK) r = bbc_write_file_atomic(w->path, w->json.data, w->json.size, w->err);
  return r;
}

/* .gltf: a failed write leaves none of its side files behind. */
static void remove_side_files(const gltf_writer *w) {
  char full[2600];
  for (size_t i = 0; i < w->pngs_written; i++) {
    snprintf(full, sizeof full, "%s%s.png", w->dir, w->image_names[i]);
    remove(full);
  }
  if (w->bin_written) {
    snprintf(full, sizeof full, "%s%s.bin", w->dir, w->stem);
    remove(full);
  }
}

static void free_writer(gltf_writer *w) {
  free(w->bin.data);
  free(w->json.data);
  for (size_t n = 0; w->mo && n < w->node_count; n++) {
    free(w->mo[n].mat_tris);
    free(w->mo[n].tex_gltf);
  }
  free(w->mo);
  free(w->views);
  free(w->image_view);
  free(w->image_names);
  free(w->image_src);
}

bbc_result bbc_scene_write_gltf(const char *path, const bbc_gltf_node *nodes, size_t node_count,
                                const bbc_gltf_options *options, bbc_error *err) {
  assert(path && (nodes || node_count == 0));
  gltf_writer w;
  memset(&w, 0, sizeof w);
  w.path = path;
  w.nodes = nodes;
  w.node_count = node_count;
  w.options = options;
  w.err = err;
  char ext[16];
  bbc__path_extension(path, ext, sizeof ext);
  bbc_gltf_format format = options ? options->format : BBC_GLTF_BY_EXTENSION;
  w.binary = format == BBC_GLTF_BY_EXTENSION ? !strcmp(ext, "glb") : format == BBC_GLTF_BINARY;
  w.extras = options ? options->extras_json : NULL;
  w.lod = options && options->lod_chain && node_count > 1;
  w.unlit = options && options->unlit;
  size_t total_views = 0, total_tex = 0;
  bbc_result r = check_scene(&w, ext, &total_views, &total_tex);
  if (r != BBC_OK) return r;

  char stem[256], dir[2048], tex_stem[270];
  safe_stem(path, stem, sizeof stem);
  bbc__side_file_stem(path, 1, tex_stem, sizeof tex_stem);
  w.tex_stem = tex_stem;
  bbc__path_folder(path, dir, sizeof dir);
  w.stem = stem;
  w.dir = dir;
  w.mo = calloc(node_count, sizeof *w.mo);
  w.views = calloc(total_views, sizeof *w.views);
  w.image_view = calloc(total_tex + 1, sizeof *w.image_view);
  w.image_names = calloc(total_tex + 1, sizeof *w.image_names);
  w.image_src = calloc(total_tex + 1, sizeof *w.image_src);
  if (!w.mo || !w.views || !w.image_view || !w.image_names || !w.image_src)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  if (r == BBC_OK) r = lay_out_buffer(&w);
  if (r == BBC_OK) {
    put_json_scene(&w);
    put_json_nodes(&w);
    put_json_meshes(&w);
    put_json_materials(&w);
    put_json_images(&w);
    put_json_accessors(&w);
    put_json_buffer(&w);
    if (w.json.oom) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  if (r == BBC_OK) r = w.binary ? write_glb(&w) : write_gltf_files(&w);
  if (r != BBC_OK && !w.binary) remove_side_files(&w);
  free_writer(&w);
  return r;
}

bbc_result bbc_mesh_write_gltf(const char *path, const bbc_mesh *m, const bbc_gltf_options *options,
                               bbc_error *err) {
  assert(path && m);
  bbc_gltf_node node = {m, NULL, NULL};
  return bbc_scene_write_gltf(path, &node, 1, options, err);
}
