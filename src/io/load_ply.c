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
 * most a few hundred MB) and parse from the buffer; the buffer is NUL
 * terminated so strtod can never run past its end.
 */
#include "text_scan.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* A real PLY header is a few hundred bytes; this bounds the header scan of a
 * file that only starts with "ply". */
#define PLY_MAX_HEADER (1u << 20)
/* Triangles reserved before reading a mesh's faces; the array grows past
 * this as needed. */
#define PLY_FIRST_TRIANGLES (1u << 22)

/* ------------------------------------------------------------------------ */
/* PLY header                                                                */
/* ------------------------------------------------------------------------ */

typedef enum ply_type {
  PLY_NONE = 0,
  PLY_INT8,
  PLY_UINT8,
  PLY_INT16,
  PLY_UINT16,
  PLY_INT32,
  PLY_UINT32,
  PLY_FLOAT32,
  PLY_FLOAT64
} ply_type;

static const struct {
  const char *name;
  ply_type type;
} ply_type_names[] = {
    {"char", PLY_INT8},       {"int8", PLY_INT8},       {"uchar", PLY_UINT8},
    {"uint8", PLY_UINT8},     {"short", PLY_INT16},     {"int16", PLY_INT16},
    {"ushort", PLY_UINT16},   {"uint16", PLY_UINT16},   {"int", PLY_INT32},
    {"int32", PLY_INT32},     {"uint", PLY_UINT32},     {"uint32", PLY_UINT32},
    {"float", PLY_FLOAT32},   {"float32", PLY_FLOAT32}, {"double", PLY_FLOAT64},
    {"float64", PLY_FLOAT64},
};

static size_t ply_type_size(ply_type t) {
  switch (t) {
  case PLY_INT8:
  case PLY_UINT8:
    return 1;
  case PLY_INT16:
  case PLY_UINT16:
    return 2;
  case PLY_INT32:
  case PLY_UINT32:
  case PLY_FLOAT32:
    return 4;
  case PLY_FLOAT64:
    return 8;
  case PLY_NONE:
    break;
  }
  return 0;
}

static int ply_type_is_integer(ply_type t) {
  return t != PLY_NONE && t != PLY_FLOAT32 && t != PLY_FLOAT64;
}

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

typedef struct ply_property {
  char *name;
  ply_type type;       /* scalar type, or the item type of a list */
  ply_type count_type; /* PLY_NONE for a scalar property */
} ply_property;

typedef struct ply_element {
  char *name;
  uint64_t count;
  ply_property *props;
  size_t prop_count;
  size_t prop_cap;
  /* Binary size of one record: exact when `fixed`, else the minimum (every
   * list empty). */
  uint64_t record_size;
  int fixed;
} ply_element;

typedef enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE } ply_format;

typedef struct ply_header {
  ply_format format;
  ply_element *elements;
  size_t element_count;
  size_t element_cap;
  size_t body_offset;  /* first byte after the end_header line */
  size_t header_lines; /* lines up to and including end_header */
  char *texture_file;  /* first "comment TextureFile NAME" (some exporters), or NULL */
} ply_header;

static void ply_header_free(ply_header *h) {
  for (size_t i = 0; i < h->element_count; i++) {
    for (size_t k = 0; k < h->elements[i].prop_count; k++) free(h->elements[i].props[k].name);
    free(h->elements[i].props);
    free(h->elements[i].name);
  }
  free(h->elements);
  free(h->texture_file);
  memset(h, 0, sizeof *h);
}

typedef struct token {
  const char *s;
  size_t n;
} token;

static int tok_is(token t, const char *word) {
  size_t n = strlen(word);
  return t.n == n && memcmp(t.s, word, n) == 0;
}

static char *tok_dup(token t) {
  char *d = malloc(t.n + 1);
  if (d) {
    memcpy(d, t.s, t.n);
    d[t.n] = '\0';
  }
  return d;
}

static ply_type ply_type_from_token(token t) {
  for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; i++)
    if (tok_is(t, ply_type_names[i].name)) return ply_type_names[i].type;
  return PLY_NONE;
}

/* Parses a non-negative decimal count; 0 when it is not one. */
static int parse_count(token t, uint64_t *out) {
  uint64_t v = 0;
  if (t.n == 0) return 0;
  for (size_t i = 0; i < t.n; i++) {
    unsigned d = (unsigned)(unsigned char)t.s[i] - '0';
    if (d > 9 || v > (UINT64_MAX - d) / 10) return 0;
    v = v * 10 + d;
  }
  *out = v;
  return 1;
}

static ply_element *ply_find_element(const ply_header *h, const char *name) {
  for (size_t i = 0; i < h->element_count; i++)
    if (strcmp(h->elements[i].name, name) == 0) return &h->elements[i];
  return NULL;
}

#define HEADER_MAX_TOKENS 6

/* Parses the header at the start of buf[0, size), the whole file. The scan
 * stops after PLY_MAX_HEADER bytes, so a file without end_header is refused
 * quickly whatever its size. */
static bbc_result ply_parse_header(const char *path, const char *buf, size_t size, ply_header *h,
                                   bbc_error *err) {
  memset(h, 0, sizeof *h);
  /* The magic first: anything else is not a PLY file at all. */
  if (size < 3 || memcmp(buf, "ply", 3) != 0 || (size > 3 && buf[3] != '\n' && buf[3] != '\r'))
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: not a PLY file (it does not start with the line \"ply\")", path);

  size_t scan = size < PLY_MAX_HEADER ? size : PLY_MAX_HEADER;
  text_cursor c = {buf, buf + scan, 0};
  const char *ls, *le;
  int have_format = 0, done = 0;
  bbc_result r = BBC_OK;
  char q[40];
  next_line(&c, &ls, &le); /* "ply" */
  while (!done && next_line(&c, &ls, &le)) {
    token t[HEADER_MAX_TOKENS];
    size_t nt = 0, extra = 0;
    for (const char *p = ls; p < le;) {
      while (p < le && is_blank(*p)) p++;
      if (p >= le) break;
      const char *s = p;
      while (p < le && !is_blank(*p)) {
        /* Control bytes in the header mean binary data, not a header line. */
        if ((unsigned char)*p < 0x20 || *p == 0x7f) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT,
                        "%s: PLY header line %zu contains binary data; the header is damaged "
                        "or has no end_header line",
                        path, c.line);
          goto fail;
        }
        p++;
      }
      if (nt < HEADER_MAX_TOKENS)
        t[nt++] = (token){s, (size_t)(p - s)};
      else
        extra++;
    }
    if (nt == 0) continue; /* tolerate blank lines */
    if (tok_is(t[0], "comment") && nt >= 3 && tok_is(t[1], "TextureFile") && !h->texture_file) {
      /* The name is the rest of the line: file names may contain blanks. */
      const char *e = le;
      while (e > t[2].s && is_blank(e[-1])) e--;
      h->texture_file = tok_dup((token){t[2].s, (size_t)(e - t[2].s)});
      if (!h->texture_file) goto oom;
      continue;
    }
    if (tok_is(t[0], "comment") || tok_is(t[0], "obj_info")) continue;
    if (extra) nt = HEADER_MAX_TOKENS + 1; /* too many tokens for any keyword */

    if (tok_is(t[0], "format")) {
      if (have_format || nt != 3) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: PLY header line %zu: malformed format line (expected \"format "
                      "ascii|binary_little_endian|binary_big_endian 1.0\" once)",
                      path, c.line);
        goto fail;
      }
      if (tok_is(t[1], "ascii"))
        h->format = PLY_ASCII;
      else if (tok_is(t[1], "binary_little_endian"))
        h->format = PLY_BINARY_LE;
      else if (tok_is(t[1], "binary_big_endian"))
        h->format = PLY_BINARY_BE;
      else {
        r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown format '%s'", path,
                      c.line, bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
        goto fail;
      }
      if (!tok_is(t[2], "1.0") && !tok_is(t[2], "1")) {
        r = bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                      "%s: PLY header line %zu: version '%s' is not supported (only 1.0)", path,
                      c.line, bbc__quote_token(q, sizeof q, t[2].s, t[2].s + t[2].n));
        goto fail;
      }
      have_format = 1;
    } else if (tok_is(t[0], "element")) {
      uint64_t count;
      if (nt != 3 || !parse_count(t[2], &count)) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: PLY header line %zu: malformed element line (expected \"element "
                      "<name> <count>\" with a whole non-negative count)",
                      path, c.line);
        goto fail;
      }
      if (h->element_count == h->element_cap) {
        size_t cap = h->element_cap ? 2 * h->element_cap : 4;
        ply_element *ne = realloc(h->elements, cap * sizeof *ne);
        if (!ne) goto oom;
        h->elements = ne;
        h->element_cap = cap;
      }
      ply_element *e = &h->elements[h->element_count];
      memset(e, 0, sizeof *e);
      e->name = tok_dup(t[1]);
      if (!e->name) goto oom;
      h->element_count++;
      if (ply_find_element(h, e->name) != e) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: PLY header line %zu: element '%s' is declared twice", path, c.line,
                      bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
        goto fail;
      }
      e->count = count;
      e->fixed = 1;
    } else if (tok_is(t[0], "property")) {
      if (h->element_count == 0) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: PLY header line %zu: property before any element", path, c.line);
        goto fail;
      }
      ply_element *e = &h->elements[h->element_count - 1];
      ply_property p = {NULL, PLY_NONE, PLY_NONE};
      token name;
      if (nt >= 2 && tok_is(t[1], "list")) {
        if (nt != 5) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT,
                        "%s: PLY header line %zu: malformed list property (expected \"property "
                        "list <count type> <item type> <name>\")",
                        path, c.line);
          goto fail;
        }
        p.count_type = ply_type_from_token(t[2]);
        p.type = ply_type_from_token(t[3]);
        token bad = p.count_type == PLY_NONE ? t[2] : t[3];
        if (p.count_type == PLY_NONE || p.type == PLY_NONE) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown type '%s'", path,
                        c.line, bbc__quote_token(q, sizeof q, bad.s, bad.s + bad.n));
          goto fail;
        }
        if (!ply_type_is_integer(p.count_type)) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT,
                        "%s: PLY header line %zu: list count type must be an integer type", path,
                        c.line);
          goto fail;
        }
        name = t[4];
      } else {
        if (nt != 3) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT,
                        "%s: PLY header line %zu: malformed property (expected \"property "
                        "<type> <name>\")",
                        path, c.line);
          goto fail;
        }
        p.type = ply_type_from_token(t[1]);
        if (p.type == PLY_NONE) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown type '%s'", path,
                        c.line, bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
          goto fail;
        }
        name = t[2];
      }
      if (e->prop_count == e->prop_cap) {
        size_t cap = e->prop_cap ? 2 * e->prop_cap : 8;
        ply_property *np = realloc(e->props, cap * sizeof *np);
        if (!np) goto oom;
        e->props = np;
        e->prop_cap = cap;
      }
      p.name = tok_dup(name);
      if (!p.name) goto oom;
      e->props[e->prop_count++] = p;
      if (p.count_type != PLY_NONE) {
        e->fixed = 0;
        e->record_size += ply_type_size(p.count_type);
      } else {
        e->record_size += ply_type_size(p.type);
      }
    } else if (tok_is(t[0], "end_header")) {
      if (nt != 1) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: malformed end_header", path,
                      c.line);
        goto fail;
      }
      done = 1;
    } else if (isdigit((unsigned char)t[0].s[0]) || strchr("+-.", t[0].s[0])) {
      /* Numbers where keywords belong: the data begins without end_header. */
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: PLY header line %zu starts with a number ('%s'): the header has no "
                    "end_header line before the data",
                    path, c.line, bbc__quote_token(q, sizeof q, t[0].s, t[0].s + t[0].n));
      goto fail;
    } else {
      r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown keyword '%s'", path,
                    c.line, bbc__quote_token(q, sizeof q, t[0].s, t[0].s + t[0].n));
      goto fail;
    }
  }
  if (!done) {
    if (scan < size)
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: PLY header has no end_header line in its first %u bytes; the header is "
                    "damaged",
                    path, PLY_MAX_HEADER);
    else
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: PLY header has no end_header line (the file ends inside the header, "
                    "after line %zu); the file is truncated or not a complete PLY file",
                    path, c.line);
    goto fail;
  }
  if (!have_format) {
    r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header has no format line", path);
    goto fail;
  }
  h->body_offset = (size_t)(c.p - buf);
  h->header_lines = c.line;
  return BBC_OK;

oom:
  r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the PLY header", path);
fail:
  ply_header_free(h);
  return r;
}

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

/* Vertex values we read; V_U and V_V (texture coordinates) only for meshes,
 * colours only for point clouds. */
enum { V_X, V_Y, V_Z, V_NX, V_NY, V_NZ, V_R, V_G, V_B, V_A, V_U, V_V, V_COUNT };

/* The items of one list property of the record being read (the vertex
 * indices of a face or a strip). */
typedef struct ply_list {
  size_t prop; /* property index in its element; SIZE_MAX: capture none */
  double *items;
  size_t count;
  size_t cap;
} ply_list;

typedef struct ply_reader {
  const char *path;
  const bbc_callbacks *cb;
  const ply_element *vertex;
  size_t prop[V_COUNT]; /* property index of each value, SIZE_MAX when absent */
  int has_normals;
  int has_colors;       /* point clouds only */
  int has_uvs;          /* meshes only */
  int float_colors;     /* some colour channel is float: convert at the end */
  float *raw_colors;    /* 4 per point while float_colors */
  double raw_color_max; /* largest float colour value seen */
  size_t zero_normals;  /* normals of length 0 in the file */
  /* Meshes: the face and triangle-strip elements (NULL when absent or
   * empty) and the property index of their index lists. */
  int is_mesh;
  const ply_element *face;
  size_t face_list;
  const ply_element *strips;
  size_t strip_list;
  size_t triangle_cap;
  ply_list list; /* indices of the current face or strip */
  /* Progress over the records of the elements read into the mesh. */
  uint64_t records_done, records_total, progress_step;
  bbc_mesh *mesh;
} ply_reader;

/* Where a record is, for messages: "line 12: " before the record's name in
 * text, " (byte offset 345)" after it in binary. */
typedef struct ply_place {
  char pre[32];
  char post[48];
} ply_place;

static void ply_place_set(ply_place *pl, size_t line, uint64_t offset) {
  pl->pre[0] = pl->post[0] = '\0';
  if (line)
    snprintf(pl->pre, sizeof pl->pre, "line %zu: ", line);
  else
    snprintf(pl->post, sizeof pl->post, " (byte offset %llu)", (unsigned long long)offset);
}

static size_t ply_find_property(const ply_element *e, const char *name) {
  for (size_t k = 0; k < e->prop_count; k++)
    if (strcmp(e->props[k].name, name) == 0) return k;
  return SIZE_MAX;
}

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
static bbc_result ply_map_faces(ply_reader *pp, const ply_header *h, bbc_error *err) {
  const ply_element *face = ply_find_element(h, "face");
  const ply_element *strips = ply_find_element(h, "tristrips");
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
static bbc_result ply_store_polygon(ply_reader *pp, const ply_element *e, int strip, uint64_t index,
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

static bbc_result ply_read_binary(ply_reader *pp, const ply_header *h, const char *buf, size_t size,
                                  bbc_error *err) {
  const char *path = pp->path;
  const unsigned char *body = (const unsigned char *)buf + h->body_offset;
  const unsigned char *end = (const unsigned char *)buf + size;
  uint64_t have = (uint64_t)(end - body);
  int swap = (h->format == PLY_BINARY_BE) != host_is_big_endian();
  int all_fixed = 1;
  char what[200];

  /* Before reading a single record, check that the body can hold what the
   * header declares: this refuses absurd counts without allocating, and it
   * names truncation (the usual damage) as the reason instead of whatever
   * garbage a shifted record would produce. */
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

  bbc_result r = ply_alloc(pp, err);
  if (r != BBC_OK) return r;
  double *vals = malloc((pp->vertex->prop_count ? pp->vertex->prop_count : 1) * sizeof *vals);
  if (!vals) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);

  const unsigned char *p = body;
  for (size_t ei = 0; ei < h->element_count; ei++) {
    const ply_element *e = &h->elements[ei];
    int is_vertex = e == pp->vertex;
    int is_polygon = e == pp->face || e == pp->strips;
    if (!is_vertex && !is_polygon && e->fixed) {
      /* The check above bounds the product, but lists before this element
       * may have used more than their minimum: check what is left. */
      uint64_t bytes = e->count * e->record_size;
      if ((uint64_t)(end - p) < bytes) {
        uint64_t i = (uint64_t)(end - p) / e->record_size;
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: binary body ends inside %s %llu (byte offset %llu) of the %llu the "
                      "header declares; the file is truncated or damaged",
                      path, e->name, (unsigned long long)i,
                      (unsigned long long)(p - body) + h->body_offset + i * e->record_size,
                      (unsigned long long)e->count);
        goto done;
      }
      p += bytes;
      continue;
    }
    ply_list *list = NULL;
    if (is_polygon) {
      pp->list.prop = e == pp->face ? pp->face_list : pp->strip_list;
      list = &pp->list;
    }
    for (uint64_t i = 0; i < e->count; i++) {
      const unsigned char *start = p;
      uint64_t offset = (uint64_t)(start - body) + h->body_offset;
      size_t bad = 0;
      record_status st = ply_binary_record(e, &p, end, swap, is_vertex ? vals : NULL, list, &bad);
      if (st == RECORD_NO_MEMORY) {
        r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %s %llu", path,
                      e->name, (unsigned long long)i);
        goto done;
      }
      if (st == RECORD_SHORT) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: binary body ends inside %s %llu (byte offset %llu) of the %llu the "
                      "header declares; the file is truncated or damaged",
                      path, e->name, (unsigned long long)i, (unsigned long long)offset,
                      (unsigned long long)e->count);
        goto done;
      }
      if (st == RECORD_NEGATIVE_LIST) {
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: %s %llu (byte offset %llu) has a negative length for list '%s'; the "
                      "file is damaged",
                      path, e->name, (unsigned long long)i, (unsigned long long)offset,
                      e->props[bad].name);
        goto done;
      }
      if (is_vertex)
        r = ply_store_vertex(pp, (size_t)i, vals, 0, offset, err);
      else if (is_polygon)
        r = ply_store_polygon(pp, e, e == pp->strips, i, 0, offset, err);
      if (r != BBC_OK) goto done;
      if (is_vertex || is_polygon) ply_progress(pp);
    }
  }

  /* Bytes left over mean the counts and the data disagree: refuse rather
   * than guess which records are real. A final newline some writers append
   * is harmless. */
  uint64_t extra = (uint64_t)(end - p);
  if (extra > 0) {
    int harmless = extra <= 2;
    for (const unsigned char *q = p; harmless && q < end; q++)
      harmless = *q == '\n' || *q == '\r' || *q == ' ' || *q == '\0';
    if (!harmless) {
      ply_describe_counts(h, what, sizeof what);
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: binary body is %llu byte%s longer than %s declared in the header need "
                    "(%llu of %llu bytes); the file is damaged or its header counts are wrong",
                    path, (unsigned long long)extra, extra == 1 ? "" : "s", what,
                    (unsigned long long)have, (unsigned long long)(have - extra));
      goto done;
    }
  }
  r = BBC_OK;
done:
  free(vals);
  return r;
}

/* ------------------------------------------------------------------------ */
/* PLY ASCII body                                                            */
/* ------------------------------------------------------------------------ */

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
        r = ply_store_polygon(pp, e, e == pp->strips, i, c.line, 0, err);
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

/* ------------------------------------------------------------------------ */
/* PLY meshes: material, group, texture                                      */
/* ------------------------------------------------------------------------ */

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
  if (opt->load_textures) {
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
static bbc_result ply_finish_mesh(ply_reader *pp, const ply_header *h, const bbc_load_options *opt,
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
  r = ply_parse_header(path, buf, size, &h, err);
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
  pp.vertex = ply_find_element(&h, "vertex");
  if (!pp.vertex) {
    r = bbc__fail(err, BBC_ERROR_EMPTY, "%s: PLY header declares no vertex element", path);
    goto fail;
  }
  pp.is_mesh = ply_has_faces(&h);
  if (pp.is_mesh) {
    r = ply_map_faces(&pp, &h, err);
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
    r = ply_finish_mesh(&pp, &h, options, err);
    if (r != BBC_OK) goto fail;
  } else {
    ply_finish_colors(&pp);
    if (pp.zero_normals)
      bbc__log(cb, BBC_LOG_WARNING, "%s: %zu of %zu points have a zero-length normal (kept as 0)",
               path, pp.zero_normals, mesh->vertex_count);
  }
  free(pp.raw_colors);
  free(pp.list.items);
  ply_header_free(&h);
  return bbc__finish_loaded(mesh, options, path, err);

fail:
  free(pp.raw_colors);
  free(pp.list.items);
  ply_header_free(&h);
  free(buf);
  bbc_mesh_free(mesh);
  return r;
}
