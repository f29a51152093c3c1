/* ply.h — what the files of the PLY reader share: load_ply.c (the entry,
 * the vertices, the binary and ASCII bodies), ply_header.c (the header) and
 * ply_mesh.c (faces and strips as triangles; the mesh's material, group and
 * texture). Internal. */
#ifndef BBC_PLY_H
#define BBC_PLY_H

#include "text_scan.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* ---- the header (ply_header.c) ------------------------------------------ */

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

static inline size_t ply_type_size(ply_type t) {
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

static inline int ply_type_is_integer(ply_type t) {
  return t != PLY_NONE && t != PLY_FLOAT32 && t != PLY_FLOAT64;
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

typedef struct token {
  const char *s;
  size_t n;
} token;

static inline char *tok_dup(token t) {
  char *d = malloc(t.n + 1);
  if (d) {
    memcpy(d, t.s, t.n);
    d[t.n] = '\0';
  }
  return d;
}

/* Parses the header at the start of buf[0, size), the whole file; frees
 * what it built when it fails. */
bbc_result bbc__ply_parse_header(const char *path, const char *buf, size_t size, ply_header *h,
                                 bbc_error *err);
void bbc__ply_header_free(ply_header *h);
/* The element named `name`; NULL when the header declares none. */
ply_element *bbc__ply_find_element(const ply_header *h, const char *name);

/* ---- the reader ------------------------------------------------------------ */

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

static inline void ply_place_set(ply_place *pl, size_t line, uint64_t offset) {
  pl->pre[0] = pl->post[0] = '\0';
  if (line)
    snprintf(pl->pre, sizeof pl->pre, "line %zu: ", line);
  else
    snprintf(pl->post, sizeof pl->post, " (byte offset %llu)", (unsigned long long)offset);
}

static inline size_t ply_find_property(const ply_element *e, const char *name) {
  for (size_t k = 0; k < e->prop_count; k++)
    if (strcmp(e->props[k].name, name) == 0) return k;
  return SIZE_MAX;
}

/* ---- meshes (ply_mesh.c) -------------------------------------------------- */

/* Looks up the face and tristrips elements and their index lists. */
bbc_result bbc__ply_map_faces(ply_reader *pp, const ply_header *h, bbc_error *err);
/* Checks face or strip `index` (its indices in pp->list) and adds its
 * triangles. */
bbc_result bbc__ply_store_polygon(ply_reader *pp, const ply_element *e, int strip, uint64_t index,
                                  size_t line, uint64_t offset, bbc_error *err);
/* Gives the mesh read its material, group and texture. */
bbc_result bbc__ply_finish_mesh(ply_reader *pp, const ply_header *h, const bbc_load_options *opt,
                                bbc_error *err);

#endif /* BBC_PLY_H */
