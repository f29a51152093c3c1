/* write_gltf.c — glTF 2.0 output (.glb, or .gltf + .bin + .png files), every
 * file atomic, the JSON written by hand (the library does not link a JSON
 * library). Layout of the binary buffer, every bufferView 4-byte aligned:
 *   POSITION (float VEC3), NORMAL (float VEC3, when present), TEXCOORD_0
 *   (float VEC2, when present), then the indices of each primitive (one per
 *   material used, in material order), then (.glb only) the PNG images.
 * The same mesh and options give byte-identical files. */
#include "internal.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image_write.h>

/* ---- growable byte buffer ------------------------------------------------ */

typedef struct gbuf {
  unsigned char *data;
  size_t size, cap;
  int oom; /* a growth failed: every later append is ignored */
} gbuf;

static void gbuf_append(gbuf *b, const void *data, size_t n) {
  if (b->oom || n == 0) return;
  if (b->size + n < b->size) {
    b->oom = 1;
    return;
  }
  if (b->size + n > b->cap) {
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->size + n) {
      if (cap > SIZE_MAX / 2) {
        cap = b->size + n;
        break;
      }
      cap *= 2;
    }
    unsigned char *p = realloc(b->data, cap);
    if (!p) {
      b->oom = 1;
      return;
    }
    b->data = p;
    b->cap = cap;
  }
  memcpy(b->data + b->size, data, n);
  b->size += n;
}

/* Pads with `byte` to a multiple of 4. */
static void gbuf_pad4(gbuf *b, unsigned char byte) {
  while (b->size % 4 && !b->oom) gbuf_append(b, &byte, 1);
}

static void gbuf_puts(gbuf *b, const char *s) {
  gbuf_append(b, s, strlen(s));
}

static void gbuf_printf(gbuf *b, const char *fmt, ...) BBC__PRINTF(2, 3);
static void gbuf_printf(gbuf *b, const char *fmt, ...) {
  char small[256];
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < 0) {
    b->oom = 1;
    return;
  }
  if ((size_t)n < sizeof small) {
    gbuf_append(b, small, (size_t)n);
    return;
  }
  char *big = malloc((size_t)n + 1);
  if (!big) {
    b->oom = 1;
    return;
  }
  va_start(ap, fmt);
  vsnprintf(big, (size_t)n + 1, fmt, ap);
  va_end(ap);
  gbuf_append(b, big, (size_t)n);
  free(big);
}

/* A float as a JSON number that reads back as the same float ("%.9g"). A
 * locale with a decimal comma cannot leak into the JSON: ',' becomes '.'. */
static void gbuf_number(gbuf *b, double v) {
  char s[64];
  snprintf(s, sizeof s, "%.9g", v);
  for (char *p = s; *p; p++)
    if (*p == ',') *p = '.';
  gbuf_puts(b, s);
}

/* A JSON string: quotes, backslashes and control characters escaped, bytes
 * that are not valid UTF-8 replaced by U+FFFD (JSON must be UTF-8). */
static void gbuf_string(gbuf *b, const char *s) {
  const unsigned char *p = (const unsigned char *)s;
  gbuf_puts(b, "\"");
  while (*p) {
    unsigned char c = *p;
    if (c == '"' || c == '\\') {
      char e[2] = {'\\', (char)c};
      gbuf_append(b, e, 2);
      p++;
    } else if (c < 0x20) {
      gbuf_printf(b, "\\u%04x", c);
      p++;
    } else if (c < 0x80) {
      gbuf_append(b, p, 1);
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
        gbuf_append(b, p, n);
        p += n;
      } else {
        gbuf_puts(b, "\\ufffd");
        p++;
      }
    }
  }
  gbuf_puts(b, "\"");
}

static void put_u32le(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)v;
  p[1] = (unsigned char)(v >> 8);
  p[2] = (unsigned char)(v >> 16);
  p[3] = (unsigned char)(v >> 24);
}

static void gbuf_u32(gbuf *b, uint32_t v) {
  unsigned char q[4];
  put_u32le(q, v);
  gbuf_append(b, q, 4);
}

static void gbuf_f32(gbuf *b, float v) {
  uint32_t u;
  memcpy(&u, &v, 4);
  gbuf_u32(b, u); /* little-endian whatever the host */
}

static void png_to_gbuf(void *ctx, void *data, int size) {
  if (size > 0) gbuf_append(ctx, data, (size_t)size);
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
  size_t len = dot ? (size_t)(dot - s) : strlen(s), i = 0;
  for (; i < len && i + 1 < n; i++) {
    unsigned char c = (unsigned char)s[i];
    out[i] = (char)(isalnum(c) || c == '_' || c == '-' || c == '.' ? c : '_');
  }
  out[i] = 0;
  if (i == 0) snprintf(out, n, "unnamed");
}

/* ---- the writer -------------------------------------------------------------- */

typedef struct view {
  size_t offset, length;
  int target; /* 34962 vertex data, 34963 indices, 0 none (images) */
} view;

bbc_result bbc_mesh_write_gltf(const char *path, const bbc_mesh *m, const bbc_gltf_options *options,
                               bbc_error *err) {
  char ext[16];
  bbc__path_extension(path, ext, sizeof ext);
  int binary = options ? options->binary : !strcmp(ext, "glb");
  const char *extras = options ? options->extras_json : NULL;
  if (strcmp(ext, binary ? "glb" : "gltf"))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: glTF output must end in %s", path,
                     binary ? ".glb" : ".gltf");
  if (m->kind != BBC_MESH_TRIANGLES || m->triangle_count == 0 || m->vertex_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: nothing to write (no triangles)", path);
  if (extras && !is_json_object(extras))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: extras_json is not one JSON object",
                     path);
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

  char stem[256], dir[2048];
  safe_stem(path, stem, sizeof stem);
  bbc__path_folder(path, dir, sizeof dir);

  gbuf bin = {0}, json = {0}, out = {0};
  size_t n_mat = m->material_count, n_tex = m->texture_count;
  size_t *mat_tris = calloc(n_mat + 1, sizeof *mat_tris); /* triangles per material */
  size_t *mat_first = calloc(n_mat + 1, sizeof *mat_first);
  uint32_t *sorted = malloc(3 * m->triangle_count * sizeof *sorted);
  int *tex_gltf = malloc((n_tex + 1) * sizeof *tex_gltf); /* mesh texture -> glTF texture */
  view *views = calloc(3 + n_mat + n_tex, sizeof *views);
  bbc_result r = BBC_OK;
  if (!mat_tris || !mat_first || !sorted || !tex_gltf || !views) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    goto done;
  }

  /* Indices grouped by material, keeping the face order within each. */
  for (size_t t = 0; t < m->triangle_count; t++) mat_tris[m->face_material[t]]++;
  for (size_t i = 1; i <= n_mat; i++) mat_first[i] = mat_first[i - 1] + mat_tris[i - 1];
  {
    size_t *fill = calloc(n_mat + 1, sizeof *fill);
    if (!fill) {
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
      goto done;
    }
    for (size_t t = 0; t < m->triangle_count; t++) {
      uint32_t mi = m->face_material[t];
      memcpy(sorted + 3 * (mat_first[mi] + fill[mi]++), m->indices + 3 * t, 3 * sizeof *sorted);
    }
    free(fill);
  }

  /* Textures used by a material and decoded, in texture order. */
  size_t n_images = 0;
  for (size_t t = 0; t < n_tex; t++) tex_gltf[t] = -1;
  for (size_t i = 0; i < n_mat; i++) {
    int t = m->materials[i].texture;
    if (t >= 0 && (size_t)t < n_tex && m->textures[t].image.rgba) tex_gltf[t] = 0;
  }
  for (size_t t = 0; t < n_tex; t++)
    if (tex_gltf[t] == 0) tex_gltf[t] = (int)n_images++;

  /* ---- binary buffer ---- */
  size_t nv = m->vertex_count, n_views = 0;
  float pmin[3] = {0}, pmax[3] = {0};
  views[n_views++] = (view){bin.size, nv * 12, 34962};
  for (size_t v = 0; v < nv; v++)
    for (int k = 0; k < 3; k++) {
      float f = (float)m->positions[3 * v + k];
      if (!isfinite(f)) {
        r = bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                      "%s: vertex %zu does not fit in a float (%g)", path, v,
                      m->positions[3 * v + k]);
        goto done;
      }
      if (v == 0 || f < pmin[k]) pmin[k] = f;
      if (v == 0 || f > pmax[k]) pmax[k] = f;
      gbuf_f32(&bin, f);
    }
  int normal_view = -1, uv_view = -1;
  if (m->normals) {
    normal_view = (int)n_views;
    views[n_views++] = (view){bin.size, nv * 12, 34962};
    for (size_t v = 0; v < nv; v++) {
      /* glTF requires unit normals: renormalise float rounding away; a zero
       * or non-finite normal (never from bbc_mesh_finalize) becomes +Z. */
      const float *n = m->normals + 3 * v;
      double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
      for (int k = 0; k < 3; k++)
        gbuf_f32(&bin, isfinite(len) && len > 1e-20 ? (float)(n[k] / len) : (k == 2 ? 1.0f : 0.0f));
    }
  }
  if (m->uvs) {
    uv_view = (int)n_views;
    views[n_views++] = (view){bin.size, nv * 8, 34962};
    for (size_t v = 0; v < nv; v++) {
      float u = m->uvs[2 * v], w = m->uvs[2 * v + 1];
      if (!isfinite(u) || !isfinite(w)) {
        r = bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY, "%s: vertex %zu has a non-finite uv", path,
                      v);
        goto done;
      }
      gbuf_f32(&bin, u);
      gbuf_f32(&bin, 1.0f - w); /* OpenGL's bottom-left origin -> glTF's top-left */
    }
  }
  int small = nv <= 65535; /* 65535 itself is the primitive restart value */
  size_t first_index_view = n_views;
  for (size_t i = 0; i < n_mat; i++) {
    if (!mat_tris[i]) continue;
    size_t count = 3 * mat_tris[i];
    views[n_views++] = (view){bin.size, count * (small ? 2 : 4), 34963};
    const uint32_t *ix = sorted + 3 * mat_first[i];
    for (size_t k = 0; k < count; k++) {
      if (small) {
        unsigned char q[2] = {(unsigned char)ix[k], (unsigned char)(ix[k] >> 8)};
        gbuf_append(&bin, q, 2);
      } else {
        gbuf_u32(&bin, ix[k]);
      }
    }
    gbuf_pad4(&bin, 0);
  }
  size_t first_image_view = n_views;
  size_t *png_size = NULL;
  if (n_images) {
    png_size = calloc(n_images, sizeof *png_size);
    if (!png_size) bin.oom = 1;
  }
  for (size_t t = 0; t < n_tex && !bin.oom; t++) {
    if (tex_gltf[t] < 0) continue;
    const bbc_image *im = &m->textures[t].image;
    gbuf png = {0};
    if (!stbi_write_png_to_func(png_to_gbuf, &png, im->width, im->height, 4, im->rgba,
                                im->width * 4) ||
        png.oom) {
      free(png.data);
      free(png_size);
      r = bbc__fail(err, png.oom ? BBC_ERROR_OUT_OF_MEMORY : BBC_ERROR_IO,
                    "%s: cannot encode texture %zu as PNG", path, t);
      goto done;
    }
    if (binary) {
      views[n_views++] = (view){bin.size, png.size, 0};
      gbuf_append(&bin, png.data, png.size);
      gbuf_pad4(&bin, 0);
    } else {
      char full[2600];
      snprintf(full, sizeof full, "%s%s_%d.png", dir, stem, tex_gltf[t]);
      r = bbc_write_file_atomic(full, png.data, png.size, err);
    }
    png_size[tex_gltf[t]] = png.size;
    free(png.data);
    if (r != BBC_OK) {
      free(png_size);
      goto done;
    }
  }
  free(png_size);
  if (bin.oom) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    goto done;
  }

  /* ---- JSON ---- */
  gbuf *j = &json;
  gbuf_puts(j, "{\"asset\":{\"generator\":\"bbcgen " BBC_VERSION_STRING "\",\"version\":\"2.0\"");
  if (extras) {
    gbuf_puts(j, ",\"extras\":");
    gbuf_puts(j, extras);
  }
  gbuf_puts(j, "},\n\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\n");

  /* One primitive per material used; attributes shared. */
  gbuf_puts(j, "\"meshes\":[{\"primitives\":[");
  size_t acc = (size_t)(1 + (normal_view >= 0) + (uv_view >= 0)), prim = 0;
  for (size_t i = 0; i < n_mat; i++) {
    if (!mat_tris[i]) continue;
    gbuf_printf(j, "%s\n{\"attributes\":{\"POSITION\":0", prim ? "," : "");
    if (normal_view >= 0) gbuf_puts(j, ",\"NORMAL\":1");
    if (uv_view >= 0) gbuf_printf(j, ",\"TEXCOORD_0\":%d", normal_view >= 0 ? 2 : 1);
    gbuf_printf(j, "},\"indices\":%zu,\"material\":%zu,\"mode\":4}", acc + prim, i);
    prim++;
  }
  gbuf_puts(j, "]}],\n");

  gbuf_puts(j, "\"materials\":[");
  for (size_t i = 0; i < n_mat; i++) {
    const bbc_material *mat = &m->materials[i];
    gbuf_puts(j, i ? ",\n{\"name\":" : "\n{\"name\":");
    gbuf_string(j, mat->name ? mat->name : "");
    gbuf_puts(j, ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[");
    for (int k = 0; k < 4; k++) {
      float c = mat->base_color[k];
      c = c >= 0.0f ? (c <= 1.0f ? c : 1.0f) : (c < 0.0f ? 0.0f : 1.0f); /* NaN -> 1 */
      if (k) gbuf_puts(j, ",");
      gbuf_number(j, c);
    }
    gbuf_puts(j, "]");
    int t = mat->texture;
    if (t >= 0 && (size_t)t < n_tex && tex_gltf[t] >= 0)
      gbuf_printf(j, ",\"baseColorTexture\":{\"index\":%d}", tex_gltf[t]);
    gbuf_puts(j, ",\"metallicFactor\":0,\"roughnessFactor\":1},"
                 "\"alphaMode\":\"MASK\",\"alphaCutoff\":0.5,\"doubleSided\":true}");
  }
  gbuf_puts(j, "],\n");

  if (n_images) {
    gbuf_puts(j, "\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":10497,"
                 "\"wrapT\":10497}],\n\"textures\":[");
    for (size_t i = 0; i < n_images; i++)
      gbuf_printf(j, "%s{\"sampler\":0,\"source\":%zu}", i ? "," : "", i);
    gbuf_puts(j, "],\n\"images\":[");
    for (size_t i = 0; i < n_images; i++) {
      if (binary)
        gbuf_printf(j, "%s{\"bufferView\":%zu,\"mimeType\":\"image/png\"}", i ? "," : "",
                    first_image_view + i);
      else
        gbuf_printf(j, "%s{\"uri\":\"%s_%zu.png\"}", i ? "," : "", stem, i);
    }
    gbuf_puts(j, "],\n");
  }

  gbuf_printf(j,
              "\"accessors\":[\n{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,"
              "\"type\":\"VEC3\",\"min\":[",
              nv);
  for (int k = 0; k < 3; k++) {
    if (k) gbuf_puts(j, ",");
    gbuf_number(j, pmin[k]);
  }
  gbuf_puts(j, "],\"max\":[");
  for (int k = 0; k < 3; k++) {
    if (k) gbuf_puts(j, ",");
    gbuf_number(j, pmax[k]);
  }
  gbuf_puts(j, "]}");
  if (normal_view >= 0)
    gbuf_printf(j, ",\n{\"bufferView\":%d,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"}",
                normal_view, nv);
  if (uv_view >= 0)
    gbuf_printf(j, ",\n{\"bufferView\":%d,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"}",
                uv_view, nv);
  prim = 0;
  for (size_t i = 0; i < n_mat; i++) {
    if (!mat_tris[i]) continue;
    gbuf_printf(j, ",\n{\"bufferView\":%zu,\"componentType\":%d,\"count\":%zu,\"type\":\"SCALAR\"}",
                first_index_view + prim, small ? 5123 : 5125, 3 * mat_tris[i]);
    prim++;
  }
  gbuf_puts(j, "],\n\"bufferViews\":[");
  for (size_t i = 0; i < n_views; i++) {
    gbuf_printf(j, "%s\n{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu", i ? "," : "",
                views[i].offset, views[i].length);
    if (views[i].target) gbuf_printf(j, ",\"target\":%d", views[i].target);
    gbuf_puts(j, "}");
  }
  gbuf_puts(j, "],\n\"buffers\":[{");
  if (!binary) gbuf_printf(j, "\"uri\":\"%s.bin\",", stem);
  gbuf_printf(j, "\"byteLength\":%zu}]}\n", bin.size);
  if (json.oom) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    goto done;
  }

  if (binary) {
    gbuf_pad4(&json, ' ');
    size_t total = 12 + 8 + json.size + 8 + bin.size;
    if (total > UINT32_MAX) {
      r = bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "%s: %zu bytes: too large for GLB (4 GiB)", path,
                    total);
      goto done;
    }
    gbuf_append(&out, "glTF", 4);
    gbuf_u32(&out, 2);
    gbuf_u32(&out, (uint32_t)total);
    gbuf_u32(&out, (uint32_t)json.size);
    gbuf_append(&out, "JSON", 4);
    gbuf_append(&out, json.data, json.size);
    gbuf_u32(&out, (uint32_t)bin.size);
    gbuf_append(&out, "BIN\0", 4);
    gbuf_append(&out, bin.data, bin.size);
    if (out.oom) {
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
      goto done;
    }
    r = bbc_write_file_atomic(path, out.data, out.size, err);
  } else {
    /* The .bin before the .gltf, so the .gltf never names a missing file. */
    char full[2600];
    snprintf(full, sizeof full, "%s%s.bin", dir, stem);
    r = bbc_write_file_atomic(full, bin.data, bin.size, err);
    if (r == BBC_OK) r = bbc_write_file_atomic(path, json.data, json.size, err);
  }

done:
  free(bin.data);
  free(json.data);
  free(out.data);
  free(mat_tris);
  free(mat_first);
  free(sorted);
  free(tex_gltf);
  free(views);
  return r;
}
