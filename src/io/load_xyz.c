/* load_xyz.c — the XYZ text reader: one point a line (`x y z ...`, blanks
 * or commas), comments and a header line allowed, Leica PTS counts skipped;
 * doubles kept; a bad line is refused with its number. */
#include "text_scan.h"

#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* XYZ text                                                                  */
/* ------------------------------------------------------------------------ */

/* Skips the separator between two fields: blanks with at most one comma. */
static const char *skip_separator(const char *p, const char *le) {
  while (p < le && is_blank(*p)) p++;
  if (p < le && *p == ',') {
    p++;
    while (p < le && is_blank(*p)) p++;
  }
  return p;
}

/* The points read so far and what the lines before them said. */
typedef struct xyz_reader {
  const char *path;
  text_cursor c;
  bbc_mesh *mesh;
  size_t n, cap;      /* points read; room in mesh->positions */
  size_t header_line; /* the line of the column header or PTS count, 0 when none */
  double pts_count;   /* Leica PTS: the count its first line gives */
} xyz_reader;

/* A NUL byte near the start means a binary file with the wrong extension;
 * say so instead of complaining about its first "line". */
static bbc_result check_text(const char *path, const char *buf, size_t size, bbc_error *err) {
  const char *nul = memchr(buf, '\0', size < 65536 ? size : 65536);
  if (nul) {
    size_t offset = (size_t)(nul - buf);
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: contains binary data (a zero byte at offset %zu); an XYZ file is text",
                     path, offset);
  }
  return BBC_OK;
}

/* Every point has a line of its own, so the line count bounds the number
 * of points (one quick pass); the array shrinks to fit at the end. */
static bbc_result alloc_points(const char *path, const char *buf, size_t size, bbc_mesh *mesh,
                               size_t *cap_out, bbc_error *err) {
  size_t cap = 1;
  for (size_t i = 0; i < size; i++) cap += buf[i] == '\n' || buf[i] == '\r';
  if (cap > SIZE_MAX / (3 * sizeof(double)))
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: file is too large", path);
  mesh->kind = BBC_MESH_POINTS;
  mesh->positions = malloc(cap * 3 * sizeof(double));
  if (!mesh->positions)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory for up to %zu points", path,
                     cap);
  *cap_out = cap;
  return BBC_OK;
}

/* Line [ls, le), the cursor's current line: a point (*added = 1), or a
 * blank line, a comment, the column header or a PTS count passed over. */
static bbc_result read_line(xyz_reader *x, const char *ls, const char *le, int *added,
                            bbc_error *err) {
  const char *path = x->path;
  size_t line = x->c.line;
  char q[40];
  *added = 0;
  const char *p = ls;
  while (p < le && is_blank(*p)) p++;
  if (p == le || *p == '#' || (*p == '/' && p + 1 < le && p[1] == '/')) return BBC_OK;
  double v[3];
  int k = 0;
  for (; k < 3; k++) {
    if (k > 0) {
      p = skip_separator(p, le);
      if (p >= le) break;
    }
    const char *next = scan_number(p, le, 1, &v[k]);
    if (!next) {
      /* Words before the first point are a column header ("x y z i"). */
      if (k == 0 && x->n == 0 && x->header_line == 0) {
        x->header_line = line;
        break;
      }
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: line %zu: field %d ('%s') is not a number; expected \"x y z\"", path,
                       line, k + 1, bbc__quote_token(q, sizeof q, p, field_end(p, le, 1)));
    }
    p = next;
  }
  if (x->header_line == line) return BBC_OK;
  /* Leica PTS (routed here too) starts with a line holding the point count. */
  if (k == 1 && x->n == 0 && x->header_line == 0 && v[0] >= 0 && v[0] == floor(v[0])) {
    x->header_line = line;
    x->pts_count = v[0];
    return BBC_OK;
  }
  if (k < 3)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: line %zu has %d number%s; a point needs three (x y z)", path, line, k,
                     k == 1 ? "" : "s");
  for (int j = 0; j < 3; j++)
    if (!coordinate_ok(v[j]))
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: line %zu: point %zu has a non-finite or absurd coordinate (%g)", path,
                       line, x->n, v[j]);
  if (x->n == x->cap) /* cannot happen given the bound; kept as a guard */
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: line %zu: more points than expected", path, line);
  memcpy(x->mesh->positions + 3 * x->n, v, sizeof v);
  x->n++;
  *added = 1;
  return BBC_OK;
}

/* Every line of buf[0, size), reporting progress now and then on large
 * files. */
static bbc_result read_points(xyz_reader *x, const char *buf, size_t size, const bbc_callbacks *cb,
                              bbc_error *err) {
  text_cursor *c = &x->c;
  if (size >= 3 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0) c->p += 3; /* UTF-8 byte order mark */
  const char *ls, *le;
  size_t next_report = size / 8, report = size >= 4u * 1024 * 1024;
  while (next_line(c, &ls, &le)) {
    int added;
    bbc_result r = read_line(x, ls, le, &added, err);
    if (r != BBC_OK) return r;
    if (added && report && (size_t)(c->p - buf) >= next_report) {
      bbc__progress(cb, "load", 0.9 * (double)(c->p - buf) / (double)size);
      next_report += size / 8;
    }
  }
  return BBC_OK;
}

bbc_result bbc__parse_xyz(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err) {
  const bbc_callbacks *cb = options ? &options->callbacks : NULL;
  memset(mesh, 0, sizeof *mesh);
  xyz_reader x;
  memset(&x, 0, sizeof x);
  bbc_result r = check_text(path, buf, size, err);
  if (r == BBC_OK) r = alloc_points(path, buf, size, mesh, &x.cap, err);
  if (r != BBC_OK) {
    free(buf);
    return r;
  }
  x.path = path;
  x.c = (text_cursor){buf, buf + size, 0};
  x.mesh = mesh;
  x.pts_count = -1;
  r = read_points(&x, buf, size, cb, err);
  free(buf);
  buf = NULL;
  if (r == BBC_OK && x.n == 0)
    r = bbc__fail(err, BBC_ERROR_EMPTY,
                  "%s: no points: the file has only comments, blank lines or a header", path);
  if (r == BBC_OK && x.pts_count >= 0 && x.pts_count != (double)x.n) /* truncated, or not a count */
    r = bbc__fail(err, BBC_ERROR_CORRUPT,
                  "%s: line %zu gives %.0f points, the file holds %zu: truncated or damaged", path,
                  x.header_line, x.pts_count, x.n);
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  double *shrunk = realloc(mesh->positions, x.n * 3 * sizeof(double));
  if (shrunk) mesh->positions = shrunk;
  mesh->vertex_count = x.n;
  return bbc__finish_loaded(mesh, options, path, err);
}
