/*
 * load_ply.c — the PLY reader: point clouds (thesis section 2.4) and polygon
 * meshes.
 *
 * Every .ply file comes here, never to Assimp. A PLY whose header declares
 * `face` or `tristrips` records loads as a triangle mesh; one with vertices
 * only loads as a point cloud. Why not Assimp? Assimp stores coordinates as
 * float, which ruins UTM-sized scans (6e5 / 5e6 m); it does not check a
 * binary body against the header, so a damaged file loads as garbage; it
 * reads face indices past the vertex array (uninitialised memory) instead of
 * refusing them; and on some damaged headers (no end_header) it never
 * returns. Our own reader keeps doubles, reads per-point colours, normals and
 * texture coordinates, and treats every byte as untrusted: sizes are checked
 * against the header before any record is read, every index is checked
 * against the vertex count, and every refusal names the file and the place
 * (line number in text, record index and byte offset in binary).
 *
 * The reader loads the whole file into memory with one fread (files are at
 * most a few hundred MB) and parses from the buffer; the buffer is NUL
 * terminated so strtod can never run past its end. This file holds the
 * entry, the vertices and the binary and ASCII bodies; ply_header.c reads
 * the header, ply_mesh.c makes faces and strips triangles (ply.h).
 */
#include "ply.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* Triangles reserved before reading a mesh's faces; the array grows past
 * this as needed. */
#define PLY_FIRST_TRIANGLES (1u << 22)

/* 1 when the file is a mesh: some `face` or `tristrips` element has records.
 * A header that declares "element face 0" (some scanners write one) is a
 * point cloud. */
static int ply_has_faces(const ply_header *h) {
  for (size_t i = 0; i < h->element_count; i++)
    if ((strcmp(h->elements[i].name, "face") == 0 ||
         strcmp(h->elements[i].name, "tristrips") == 0) &&
        h->elements[i].count > 0)
      return 1;
  return 0;
}

/* ------------------------------------------------------------------------ */
/* PLY element mapping and storage                                           */
/* ------------------------------------------------------------------------ */

/* Finds the vertex properties we read; refuses a vertex element without
 * scalar x, y, z. Normals, colours and texture coordinates are used only
 * when complete. */
static bbc_result ply_map_vertex(ply_reader *pp, bbc_error *err) {
  static const char *const names[V_U] = {"x",  "y",   "z",     "nx",   "ny",
                                         "nz", "red", "green", "blue", "alpha"};
  static const char *const alt[V_U] = {
      NULL,           NULL,           NULL, NULL, NULL, NULL, "diffuse_red", "diffuse_green",
      "diffuse_blue", "diffuse_alpha"};
  /* Texture coordinate names in use, most common first. */
  static const char *const uv_names[][2] = {
      {"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
  const ply_element *e = pp->vertex;
  for (int v = 0; v < V_U; v++) {
    size_t k = ply_find_property(e, names[v]);
    if (k == SIZE_MAX && alt[v]) k = ply_find_property(e, alt[v]);
    if (k != SIZE_MAX && e->props[k].count_type != PLY_NONE) {
      if (v <= V_Z)
        return bbc__fail(err, BBC_ERROR_CORRUPT,
                         "%s: PLY vertex property '%s' is a list, not a coordinate", pp->path,
                         e->props[k].name);
      k = SIZE_MAX; /* a list where a scalar belongs: ignore it */
    }
    pp->prop[v] = k;
  }
  for (int v = V_X; v <= V_Z; v++)
    if (pp->prop[v] == SIZE_MAX)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: PLY vertex element has no '%s' property; cannot read %s", pp->path,
                       names[v], pp->is_mesh ? "the mesh" : "points");
  pp->has_normals =
      pp->prop[V_NX] != SIZE_MAX && pp->prop[V_NY] != SIZE_MAX && pp->prop[V_NZ] != SIZE_MAX;
  /* Per-vertex colours are a point-cloud feature; meshes carry materials. */
  pp->has_colors = !pp->is_mesh && pp->prop[V_R] != SIZE_MAX && pp->prop[V_G] != SIZE_MAX &&
                   pp->prop[V_B] != SIZE_MAX;
  if (pp->has_colors)
    for (int v = V_R; v <= V_A; v++)
      if (pp->prop[v] != SIZE_MAX && !ply_type_is_integer(e->props[pp->prop[v]].type))
        pp->float_colors = 1;
  pp->prop[V_U] = pp->prop[V_V] = SIZE_MAX;
  for (size_t i = 0; pp->is_mesh && i < sizeof uv_names / sizeof uv_names[0]; i++) {
    size_t ku = ply_find_property(e, uv_names[i][0]);
    size_t kv = ply_find_property(e, uv_names[i][1]);
    if (ku != SIZE_MAX && kv != SIZE_MAX && e->props[ku].count_type == PLY_NONE &&
        e->props[kv].count_type == PLY_NONE) {
      pp->prop[V_U] = ku;
      pp->prop[V_V] = kv;
      pp->has_uvs = 1;
      break;
    }
  }
  return BBC_OK;
}

/* Allocates the vertex arrays and, for a mesh, room for one triangle per
 * face (more are added as polygons need them). Called after the body size
 * check, so the counts are bounded by the file size; the first triangle
 * reservation is capped all the same, since a face may take a single byte
 * on the way to being refused. */
static bbc_result ply_alloc(ply_reader *pp, bbc_error *err) {
  bbc_mesh *m = pp->mesh;
  uint64_t n = pp->vertex->count;
  if (n > SIZE_MAX / (3 * sizeof(double)))
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: too many vertices (%llu) for this machine",
                     pp->path, (unsigned long long)n);
  m->kind = pp->is_mesh ? BBC_MESH_TRIANGLES : BBC_MESH_POINTS;
  m->positions = malloc((size_t)n * 3 * sizeof(double));
  if (!m->positions) goto oom;
  if (pp->has_normals) {
    m->normals = malloc((size_t)n * 3 * sizeof(float));
    if (!m->normals) goto oom;
  }
  if (pp->has_uvs) {
    m->uvs = malloc((size_t)n * 2 * sizeof(float));
    if (!m->uvs) goto oom;
  }
  if (pp->has_colors) {
    m->colors = malloc((size_t)n * 4);
    if (!m->colors) goto oom;
    if (pp->float_colors) {
      pp->raw_colors = malloc((size_t)n * 4 * sizeof(float));
      if (!pp->raw_colors) goto oom;
    }
  }
  m->vertex_count = (size_t)n;
  if (pp->is_mesh) {
    uint64_t cap = (pp->face ? pp->face->count : 0) + (pp->strips ? pp->strips->count : 0);
    if (cap > PLY_FIRST_TRIANGLES) cap = PLY_FIRST_TRIANGLES;
    m->indices = malloc((size_t)cap * 3 * sizeof(uint32_t));
    if (!m->indices) goto oom;
    pp->triangle_cap = (size_t)cap;
  }
  return BBC_OK;
oom:
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu vertices", pp->path,
                   (unsigned long long)n);
}

/* Makes room for at least n list items. */
static int ply_list_reserve(ply_list *l, size_t n) {
  if (n <= l->cap) return 1;
  size_t cap = l->cap ? 2 * l->cap : 16;
  if (cap < n) cap = n;
  if (cap > SIZE_MAX / sizeof(double)) return 0;
  double *items = realloc(l->items, cap * sizeof *items);
  if (!items) return 0;
  l->items = items;
  l->cap = cap;
  return 1;
}

/* One record of an element read into the mesh: reports progress now and
 * then (never for small files). */
static void ply_progress(ply_reader *pp) {
  pp->records_done++;
  if (pp->progress_step && pp->records_done % pp->progress_step == 0)
    bbc__progress(pp->cb, "load", 0.9 * (double)pp->records_done / (double)pp->records_total);
}

/* An integer colour channel as 8 bits. */
static uint8_t color_from_integer(double v, ply_type t) {
  if (t == PLY_UINT16) v = v / 257.0; /* 16-bit colour: scale, do not clamp */
  if (!(v > 0)) return 0;
  if (v >= 255) return 255;
  return (uint8_t)(v + 0.5);
}

/* Checks and stores vertex i from its property values. Messages locate it by
 * `line` (ASCII, 1-based) or, when line is 0, by the byte `offset` (binary). */
static bbc_result ply_store_vertex(ply_reader *pp, size_t i, const double *vals, size_t line,
                                   uint64_t offset, bbc_error *err) {
  bbc_mesh *m = pp->mesh;
  double *pos = m->positions + 3 * i;
  ply_place pl;
  for (int k = 0; k < 3; k++) {
    double v = vals[pp->prop[V_X + k]];
    if (!coordinate_ok(v)) {
      ply_place_set(&pl, line, offset);
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: %svertex %zu%s has a non-finite or absurd coordinate (%g)", pp->path,
                       pl.pre, i, pl.post, v);
    }
    pos[k] = v;
  }
  if (pp->has_normals) {
    double n[3], len = 0.0, big = 0.0;
    for (int k = 0; k < 3; k++) {
      n[k] = vals[pp->prop[V_NX + k]];
      if (!isfinite(n[k])) {
        ply_place_set(&pl, line, offset);
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: %svertex %zu%s has a non-finite normal (%g)", pp->path, pl.pre, i,
                         pl.post, n[k]);
      }
      if (fabs(n[k]) > big) big = fabs(n[k]);
    }
    float *out = m->normals + 3 * i;
    if (big > 0.0) {
      /* Scale first so that huge components cannot overflow the square. */
      for (int k = 0; k < 3; k++) {
        n[k] /= big;
        len += n[k] * n[k];
      }
      len = sqrt(len);
      for (int k = 0; k < 3; k++) out[k] = (float)(n[k] / len);
    } else {
      /* Kept as 0: bbc_mesh_finalize computes it for a mesh. */
      out[0] = out[1] = out[2] = 0.0f;
      pp->zero_normals++;
    }
  }
  if (pp->has_uvs) {
    for (int k = 0; k < 2; k++) {
      double v = vals[pp->prop[V_U + k]];
      if (!coordinate_ok(v)) {
        ply_place_set(&pl, line, offset);
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: %svertex %zu%s has a non-finite or absurd texture coordinate (%g)",
                         pp->path, pl.pre, i, pl.post, v);
      }
      m->uvs[2 * i + k] = (float)v;
    }
  }
  if (pp->has_colors) {
    for (int k = 0; k < 4; k++) {
      size_t prop = pp->prop[V_R + k];
      double v = prop == SIZE_MAX ? 255.0 : vals[prop];
      if (pp->float_colors) {
        if (isnan(v)) v = 0.0;
        if (prop != SIZE_MAX && !ply_type_is_integer(pp->vertex->props[prop].type) &&
            v > pp->raw_color_max)
          pp->raw_color_max = v;
        pp->raw_colors[4 * i + k] = (float)v;
      } else {
        m->colors[4 * i + k] =
            color_from_integer(v, prop == SIZE_MAX ? PLY_UINT8 : pp->vertex->props[prop].type);
      }
    }
  }
  return BBC_OK;
}

/* Float colour channels are usually in [0, 1], but some writers store 0..255
 * in floats; the largest value tells which. Integer channels keep their
 * usual meaning. */
static void ply_finish_colors(ply_reader *pp) {
  if (!pp->has_colors || !pp->float_colors) return;
  double scale = pp->raw_color_max > 1.0 ? 1.0 : 255.0;
  for (size_t i = 0; i < pp->mesh->vertex_count; i++)
    for (int k = 0; k < 4; k++) {
      size_t prop = pp->prop[V_R + k];
      double v = pp->raw_colors[4 * i + k];
      if (prop != SIZE_MAX && !ply_type_is_integer(pp->vertex->props[prop].type)) {
        v *= scale;
        pp->mesh->colors[4 * i + k] = !(v > 0) ? 0 : v >= 255 ? 255 : (uint8_t)(v + 0.5);
      } else {
        pp->mesh->colors[4 * i + k] =
            color_from_integer(v, prop == SIZE_MAX ? PLY_UINT8 : pp->vertex->props[prop].type);
      }
    }
}

/* "the 70051 vertices" / "the 12 'face' records, ..." for size messages. */
static void ply_describe_counts(const ply_header *h, char *out, size_t size) {
  size_t used = 0, listed = 0, nonzero = 0;
  for (size_t i = 0; i < h->element_count; i++) nonzero += h->elements[i].count > 0;
  out[0] = '\0';
  for (size_t i = 0; i < h->element_count && used + 1 < size; i++) {
    const ply_element *e = &h->elements[i];
    if (e->count == 0) continue;
    const char *sep = listed == 0 ? "the " : listed + 1 == nonzero ? " and " : ", ";
    int w;
    if (listed == 3) {
      w = snprintf(out + used, size - used, " and more");
      used += w > 0 ? (size_t)w : 0;
      break;
    }
    if (strcmp(e->name, "vertex") == 0)
      w = snprintf(out + used, size - used, "%s%llu %s", sep, (unsigned long long)e->count,
                   e->count == 1 ? "vertex" : "vertices");
    else
      w = snprintf(out + used, size - used, "%s%llu '%.40s' record%s", sep,
                   (unsigned long long)e->count, e->name, e->count == 1 ? "" : "s");
    if (w < 0) break;
    used += (size_t)w;
    if (used >= size) used = size - 1;
    listed++;
  }
  if (listed == 0) snprintf(out, size, "the elements");
}

/* ------------------------------------------------------------------------ */
/* PLY binary body                                                           */
/* ------------------------------------------------------------------------ */

static int host_is_big_endian(void) {
  const uint16_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 0;
}

static double ply_binary_value(const unsigned char *p, ply_type t, int swap) {
  unsigned char b[8];
  size_t n = ply_type_size(t);
  if (swap)
    for (size_t i = 0; i < n; i++) b[i] = p[n - 1 - i];
  else
    memcpy(b, p, n);
  switch (t) {
  case PLY_INT8: {
    int8_t v;
    memcpy(&v, b, 1);
    return v;
  }
  case PLY_UINT8:
    return b[0];
  case PLY_INT16: {
    int16_t v;
    memcpy(&v, b, 2);
    return v;
  }
  case PLY_UINT16: {
    uint16_t v;
    memcpy(&v, b, 2);
    return v;
  }
  case PLY_INT32: {
    int32_t v;
    memcpy(&v, b, 4);
    return v;
  }
  case PLY_UINT32: {
    uint32_t v;
    memcpy(&v, b, 4);
    return v;
  }
  case PLY_FLOAT32: {
    float v;
    memcpy(&v, b, 4);
    return v;
  }
  case PLY_FLOAT64: {
    double v;
    memcpy(&v, b, 8);
    return v;
  }
  case PLY_NONE:
    break;
  }
  return 0.0;
}

typedef enum record_status {
  RECORD_OK,
  RECORD_SHORT,
  RECORD_NEGATIVE_LIST,
  RECORD_NO_MEMORY
} record_status;

/* Reads one binary record at *pp; scalar values go to vals (when not NULL),
 * the items of list property list->prop to list (when not NULL). On a
 * negative list length *bad_prop names the property. */
static record_status ply_binary_record(const ply_element *e, const unsigned char **pp,
                                       const unsigned char *end, int swap, double *vals,
                                       ply_list *list, size_t *bad_prop) {
  const unsigned char *p = *pp;
  if (list) list->count = 0;
  for (size_t k = 0; k < e->prop_count; k++) {
    const ply_property *pr = &e->props[k];
    if (pr->count_type == PLY_NONE) {
      size_t sz = ply_type_size(pr->type);
      if ((size_t)(end - p) < sz) return RECORD_SHORT;
      if (vals) vals[k] = ply_binary_value(p, pr->type, swap);
      p += sz;
    } else {
      size_t csz = ply_type_size(pr->count_type);
      if ((size_t)(end - p) < csz) return RECORD_SHORT;
      double n = ply_binary_value(p, pr->count_type, swap);
      p += csz;
      if (n < 0) {
        *bad_prop = k;
        return RECORD_NEGATIVE_LIST;
      }
      /* n < 2^32 and item size <= 8: the product fits in 64 bits. */
      size_t item_size = ply_type_size(pr->type);
      uint64_t bytes = (uint64_t)n * item_size;
      if ((uint64_t)(end - p) < bytes) return RECORD_SHORT;
      if (list && k == list->prop) {
        /* Bounded by the bytes just checked: at most 8 doubles per byte. */
        size_t items = (size_t)n;
        if (!ply_list_reserve(list, items)) return RECORD_NO_MEMORY;
        for (size_t j = 0; j < items; j++)
          list->items[j] = ply_binary_value(p + j * item_size, pr->type, swap);
        list->count = items;
      }
      p += bytes;
    }
  }
  *pp = p;
  return RECORD_OK;
}

/* a * b + c, saturating at UINT64_MAX. */
static uint64_t mul_add_sat(uint64_t a, uint64_t b, uint64_t c) {
  if (a != 0 && b > UINT64_MAX / a) return UINT64_MAX;
  uint64_t m = a * b;
  return m > UINT64_MAX - c ? UINT64_MAX : m + c;
}

/* A binary body being read: its records, the byte order, the vertex's
 * values. */
typedef struct binary_body {
  const ply_header *h;
  const unsigned char *body, *end; /* the first record; one past the file */
  int swap;                        /* the file's byte order is not the host's */
  double *vals;                    /* the scalar values of the vertex record */
} binary_body;

/* Before reading a single record, checks that the body can hold what the
 * header declares: this refuses absurd counts without allocating, and it
 * names truncation (the usual damage) as the reason instead of whatever
 * garbage a shifted record would produce. */
static bbc_result check_binary_size(const char *path, const ply_header *h, uint64_t have,
                                    bbc_error *err) {
  int all_fixed = 1;
  char what[200];
  uint64_t need = 0;
  for (size_t i = 0; i < h->element_count; i++) {
    need = mul_add_sat(h->elements[i].count, h->elements[i].record_size, need);
    if (!h->elements[i].fixed && h->elements[i].count > 0) all_fixed = 0;
  }
  if (need > have) {
    ply_describe_counts(h, what, sizeof what);
    if (need == UINT64_MAX)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: binary body has %llu bytes, far fewer than %s declared in the "
                       "header need; the header is damaged",
                       path, (unsigned long long)have, what);
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: binary body is %llu byte%s shorter than %s declared in the header "
                     "need%s (%llu of %llu bytes); the file is truncated or damaged (a binary "
                     "file passed through a text-mode line-ending conversion looks like this)",
                     path, (unsigned long long)(need - have), need - have == 1 ? "" : "s", what,
                     all_fixed ? "" : " at least", (unsigned long long)have,
                     (unsigned long long)need);
  }
  return BBC_OK;
}

/* Passes over the records of an element we do not read, whose records all
 * have the same size. The size check bounds the product, but lists before
 * this element may have used more than their minimum: checks what is
 * left. */
static bbc_result skip_binary_element(const char *path, const binary_body *bb, const ply_element *e,
                                      const unsigned char **pos, bbc_error *err) {
  const unsigned char *p = *pos;
  uint64_t bytes = e->count * e->record_size;
  if ((uint64_t)(bb->end - p) < bytes) {
    uint64_t i = (uint64_t)(bb->end - p) / e->record_size;
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: binary body ends inside %s %llu (byte offset %llu) of the %llu the "
                     "header declares; the file is truncated or damaged",
                     path, e->name, (unsigned long long)i,
                     (unsigned long long)(p - bb->body) + bb->h->body_offset + i * e->record_size,
                     (unsigned long long)e->count);
  }
  *pos = p + bytes;
  return BBC_OK;
}

/* Reads the records of element e from *pos on, storing the vertices, faces
 * and strips (other elements' records are read past). */
static bbc_result read_binary_element(ply_reader *pp, const binary_body *bb, const ply_element *e,
                                      const unsigned char **pos, bbc_error *err) {
  const char *path = pp->path;
  const unsigned char *body = bb->body, *end = bb->end;
  const unsigned char *p = *pos;
  int is_vertex = e == pp->vertex;
  int is_polygon = e == pp->face || e == pp->strips;
  bbc_result r = BBC_OK;
  ply_list *list = NULL;
  if (is_polygon) {
    pp->list.prop = e == pp->face ? pp->face_list : pp->strip_list;
    list = &pp->list;
  }
  for (uint64_t i = 0; i < e->count; i++) {
    const unsigned char *start = p;
    uint64_t offset = (uint64_t)(start - body) + bb->h->body_offset;
    size_t bad = 0;
    record_status st =
        ply_binary_record(e, &p, end, bb->swap, is_vertex ? bb->vals : NULL, list, &bad);
    if (st == RECORD_NO_MEMORY)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %s %llu", path,
                       e->name, (unsigned long long)i);
    if (st == RECORD_SHORT)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: binary body ends inside %s %llu (byte offset %llu) of the %llu the "
                       "header declares; the file is truncated or damaged",
                       path, e->name, (unsigned long long)i, (unsigned long long)offset,
                       (unsigned long long)e->count);
    if (st == RECORD_NEGATIVE_LIST)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: %s %llu (byte offset %llu) has a negative length for list '%s'; the "
                       "file is damaged",
                       path, e->name, (unsigned long long)i, (unsigned long long)offset,
                       e->props[bad].name);
    if (is_vertex)
      r = ply_store_vertex(pp, (size_t)i, bb->vals, 0, offset, err);
    else if (is_polygon)
      r = bbc__ply_store_polygon(pp, e, e == pp->strips, i, 0, offset, err);
    if (r != BBC_OK) return r;
    if (is_vertex || is_polygon) ply_progress(pp);
  }
  *pos = p;
  return BBC_OK;
}

/* Bytes left over after the last record mean the counts and the data
 * disagree: refused rather than guessing which records are real. A final
 * newline some writers append is harmless. */
static bbc_result check_binary_tail(const char *path, const binary_body *bb, const unsigned char *p,
                                    bbc_error *err) {
  const unsigned char *end = bb->end;
  uint64_t have = (uint64_t)(end - bb->body);
  char what[200];
  uint64_t extra = (uint64_t)(end - p);
  if (extra > 0) {
    int harmless = extra <= 2;
    for (const unsigned char *q = p; harmless && q < end; q++)
      harmless = *q == '\n' || *q == '\r' || *q == ' ' || *q == '\0';
    if (!harmless) {
      ply_describe_counts(bb->h, what, sizeof what);
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: binary body is %llu byte%s longer than %s declared in the header "
                       "need (%llu of %llu bytes); the file is damaged or its header counts are "
                       "wrong",
                       path, (unsigned long long)extra, extra == 1 ? "" : "s", what,
                       (unsigned long long)have, (unsigned long long)(have - extra));
    }
  }
  return BBC_OK;
}

static bbc_result ply_read_binary(ply_reader *pp, const ply_header *h, const char *buf, size_t size,
                                  bbc_error *err) {
  const char *path = pp->path;
  binary_body bb;
  bb.h = h;
  bb.body = (const unsigned char *)buf + h->body_offset;
  bb.end = (const unsigned char *)buf + size;
  bb.swap = (h->format == PLY_BINARY_BE) != host_is_big_endian();
  bbc_result r = check_binary_size(path, h, (uint64_t)(bb.end - bb.body), err);
  if (r != BBC_OK) return r;

  r = ply_alloc(pp, err);
  if (r != BBC_OK) return r;
  bb.vals = malloc((pp->vertex->prop_count ? pp->vertex->prop_count : 1) * sizeof *bb.vals);
  if (!bb.vals) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);

  const unsigned char *p = bb.body;
  for (size_t ei = 0; ei < h->element_count && r == BBC_OK; ei++) {
    const ply_element *e = &h->elements[ei];
    if (e != pp->vertex && e != pp->face && e != pp->strips && e->fixed)
      r = skip_binary_element(path, &bb, e, &p, err);
    else
      r = read_binary_element(pp, &bb, e, &p, err);
  }
  if (r == BBC_OK) r = check_binary_tail(path, &bb, p, err);
  free(bb.vals);
  return r;
}

/* ------------------------------------------------------------------------ */
/* PLY ASCII body                                                            */
/* ------------------------------------------------------------------------ */

/* Largest value a list count of type t can hold (for ASCII validation). */
static double ply_type_max(ply_type t) {
  switch (t) {
  case PLY_INT8:
    return 127.0;
  case PLY_UINT8:
    return 255.0;
  case PLY_INT16:
    return 32767.0;
  case PLY_UINT16:
    return 65535.0;
  case PLY_INT32:
    return 2147483647.0;
  case PLY_UINT32:
    return 4294967295.0;
  default:
    break;
  }
  return 0.0;
}

/* Parses one ASCII record (one line) of element e: scalar values go to vals
 * (when not NULL), the items of list property list->prop to list (when not
 * NULL). */
static bbc_result ply_ascii_record(const char *path, const ply_element *e, uint64_t index,
                                   const char *p, const char *le, size_t line, double *vals,
                                   ply_list *list, bbc_error *err) {
  char q[40];
  if (list) list->count = 0;
  for (size_t k = 0; k < e->prop_count; k++) {
    const ply_property *pr = &e->props[k];
    double v;
    while (p < le && is_blank(*p)) p++;
    if (p >= le)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: line %zu: %s %llu has too few values: property '%s' (%zu of %zu) "
                       "is missing",
                       path, line, e->name, (unsigned long long)index, pr->name, k + 1,
                       e->prop_count);
    const char *next = scan_number(p, le, 0, &v);
    if (!next)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: line %zu: %s %llu: value '%s' of property '%s' is not a number", path,
                       line, e->name, (unsigned long long)index,
                       bbc__quote_token(q, sizeof q, p, field_end(p, le, 0)), pr->name);
    if (pr->count_type == PLY_NONE) {
      if (vals) vals[k] = v;
      p = next;
      continue;
    }
    if (!(v >= 0) || v != floor(v) || v > ply_type_max(pr->count_type))
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: line %zu: %s %llu: list length '%s' of '%s' is not a valid count", path,
                       line, e->name, (unsigned long long)index,
                       bbc__quote_token(q, sizeof q, p, field_end(p, le, 0)), pr->name);
    p = next;
    ply_list *out = list && k == list->prop ? list : NULL;
    /* Items are bounded by the line length, so a huge count cannot loop long
     * (nor make the list grow beyond the line). */
    for (double j = 0; j < v; j++) {
      double item;
      while (p < le && is_blank(*p)) p++;
      if (p >= le)
        return bbc__fail(err, BBC_ERROR_CORRUPT,
                         "%s: line %zu: %s %llu: list '%s' has %.0f of the %.0f items its length "
                         "promises",
                         path, line, e->name, (unsigned long long)index, pr->name, j, v);
      next = scan_number(p, le, 0, &item);
      if (!next)
        return bbc__fail(err, BBC_ERROR_CORRUPT,
                         "%s: line %zu: %s %llu: item '%s' of list '%s' is not a number", path,
                         line, e->name, (unsigned long long)index,
                         bbc__quote_token(q, sizeof q, p, field_end(p, le, 0)), pr->name);
      p = next;
      if (out) {
        if (!ply_list_reserve(out, out->count + 1))
          return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: line %zu: out of memory", path, line);
        out->items[out->count++] = item;
      }
    }
  }
  while (p < le && is_blank(*p)) p++;
  if (p < le)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: line %zu: %s %llu has more values than the %zu properties the header "
                     "declares ('%s' is extra)",
                     path, line, e->name, (unsigned long long)index, e->prop_count,
                     bbc__quote_token(q, sizeof q, p, field_end(p, le, 0)));
  return BBC_OK;
}

static bbc_result ply_read_ascii(ply_reader *pp, const ply_header *h, const char *buf, size_t size,
                                 bbc_error *err) {
  const char *path = pp->path;
  uint64_t have = size - h->body_offset;
  char what[200];

  /* Every value takes at least one character: a cheap bound that refuses
   * absurd counts before allocating (memory stays within a small multiple of
   * the file size). It is loose on purpose, so that an ordinary missing value
   * is reported by the parser with its line number. */
  uint64_t need = 0;
  for (size_t i = 0; i < h->element_count; i++)
    need = mul_add_sat(h->elements[i].count, h->elements[i].prop_count, need);
  if (need > have) {
    ply_describe_counts(h, what, sizeof what);
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: ASCII body has %llu bytes, but %s declared in the header need at least "
                     "%llu; the file is truncated or the header is damaged",
                     path, (unsigned long long)have, what, (unsigned long long)need);
  }

  bbc_result r = ply_alloc(pp, err);
  if (r != BBC_OK) return r;
  double *vals = malloc((pp->vertex->prop_count ? pp->vertex->prop_count : 1) * sizeof *vals);
  if (!vals) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);

  text_cursor c = {buf + h->body_offset, buf + size, h->header_lines};
  const char *ls = NULL, *le = NULL;
  for (size_t ei = 0; ei < h->element_count; ei++) {
    const ply_element *e = &h->elements[ei];
    int is_vertex = e == pp->vertex;
    int is_polygon = e == pp->face || e == pp->strips;
    if (e->prop_count == 0) continue; /* records without values take no text */
    ply_list *list = NULL;
    if (is_polygon) {
      pp->list.prop = e == pp->face ? pp->face_list : pp->strip_list;
      list = &pp->list;
    }
    for (uint64_t i = 0; i < e->count; i++) {
      int got;
      do { /* blank lines between records are tolerated */
        got = next_line(&c, &ls, &le);
        while (got && ls < le && is_blank(*ls)) ls++;
      } while (got && ls == le);
      if (!got) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: file ends after line %zu with %llu of the %llu %s records the header "
                      "declares; the file is truncated",
                      path, c.line, (unsigned long long)i, (unsigned long long)e->count, e->name);
        goto done;
      }
      r = ply_ascii_record(path, e, i, ls, le, c.line, is_vertex ? vals : NULL, list, err);
      if (r != BBC_OK) goto done;
      if (is_vertex)
        r = ply_store_vertex(pp, (size_t)i, vals, c.line, 0, err);
      else if (is_polygon)
        r = bbc__ply_store_polygon(pp, e, e == pp->strips, i, c.line, 0, err);
      if (r != BBC_OK) goto done;
      if (is_vertex || is_polygon) ply_progress(pp);
    }
  }
  while (next_line(&c, &ls, &le)) {
    while (ls < le && (is_blank(*ls) || *ls == '\0')) ls++;
    if (ls < le) {
      char q[40];
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: line %zu: unexpected data '%s' after the last element the header "
                    "declares; the header's counts are wrong or the file is damaged",
                    path, c.line, bbc__quote_token(q, sizeof q, ls, field_end(ls, le, 0)));
      goto done;
    }
  }
  r = BBC_OK;
done:
  free(vals);
  return r;
}

bbc_result bbc__parse_ply(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err) {
  bbc_load_options defaults;
  if (!options) {
    bbc_load_options_default(&defaults);
    options = &defaults;
  }
  const bbc_callbacks *cb = &options->callbacks;
  memset(mesh, 0, sizeof *mesh);
  bbc_result r;
  ply_header h;
  r = bbc__ply_parse_header(path, buf, size, &h, err);
  if (r != BBC_OK) {
    free(buf);
    return r;
  }
  ply_reader pp;
  memset(&pp, 0, sizeof pp);
  pp.path = path;
  pp.cb = cb;
  pp.mesh = mesh;
  pp.list.prop = SIZE_MAX;
  pp.vertex = bbc__ply_find_element(&h, "vertex");
  if (!pp.vertex) {
    r = bbc__fail(err, BBC_ERROR_EMPTY, "%s: PLY header declares no vertex element", path);
    goto fail;
  }
  pp.is_mesh = ply_has_faces(&h);
  if (pp.is_mesh) {
    r = bbc__ply_map_faces(&pp, &h, err);
    if (r != BBC_OK) goto fail;
  }
  r = ply_map_vertex(&pp, err);
  if (r != BBC_OK) goto fail;
  if (pp.vertex->count == 0) {
    r = bbc__fail(err, BBC_ERROR_EMPTY, "%s: PLY header declares 0 vertices; no %s to load", path,
                  pp.is_mesh ? "mesh" : "points");
    goto fail;
  }
  pp.records_total =
      pp.vertex->count + (pp.face ? pp.face->count : 0) + (pp.strips ? pp.strips->count : 0);
  if (pp.records_total >= PROGRESS_MIN_RECORDS) pp.progress_step = pp.records_total / 8;

  if (h.format == PLY_ASCII)
    r = ply_read_ascii(&pp, &h, buf, size, err);
  else
    r = ply_read_binary(&pp, &h, buf, size, err);
  if (r != BBC_OK) goto fail;
  free(buf);
  buf = NULL;
  if (pp.is_mesh) {
    r = bbc__ply_finish_mesh(&pp, &h, options, err);
    if (r != BBC_OK) goto fail;
  } else {
    ply_finish_colors(&pp);
    if (pp.zero_normals)
      bbc__log(cb, BBC_LOG_WARNING, "%s: %zu of %zu points have a zero-length normal (kept as 0)",
               path, pp.zero_normals, mesh->vertex_count);
  }
  free(pp.raw_colors);
  free(pp.list.items);
  bbc__ply_header_free(&h);
  return bbc__finish_loaded(mesh, options, path, err);

fail:
  free(pp.raw_colors);
  free(pp.list.items);
  bbc__ply_header_free(&h);
  free(buf);
  bbc_mesh_free(mesh);
  return r;
}
