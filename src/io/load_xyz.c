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

bbc_result bbc__parse_xyz(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err) {
  const bbc_callbacks *cb = options ? &options->callbacks : NULL;
  memset(mesh, 0, sizeof *mesh);
  bbc_result r = BBC_OK;
  /* A NUL byte near the start means a binary file with the wrong extension;
   * say so instead of complaining about its first "line". */
  const char *nul = memchr(buf, '\0', size < 65536 ? size : 65536);
  if (nul) {
    size_t offset = (size_t)(nul - buf);
    free(buf);
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: contains binary data (a zero byte at offset %zu); an XYZ file is text",
                     path, offset);
  }

  /* Every point has a line of its own, so the line count bounds the number
   * of points (one quick pass); the array shrinks to fit at the end. */
  size_t cap = 1;
  for (size_t i = 0; i < size; i++) cap += buf[i] == '\n' || buf[i] == '\r';
  if (cap > SIZE_MAX / (3 * sizeof(double))) {
    free(buf);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: file is too large", path);
  }
  mesh->kind = BBC_MESH_POINTS;
  mesh->positions = malloc(cap * 3 * sizeof(double));
  if (!mesh->positions) {
    free(buf);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory for up to %zu points", path,
                     cap);
  }

  text_cursor c = {buf, buf + size, 0};
  if (size >= 3 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0) c.p += 3; /* UTF-8 byte order mark */
  const char *ls, *le;
  size_t n = 0, header_line = 0;
  double pts_count = -1; /* Leica PTS: the count its first line gives */
  size_t next_report = size / 8, report = size >= 4u * 1024 * 1024;
  char q[40];
  while (next_line(&c, &ls, &le)) {
    const char *p = ls;
    while (p < le && is_blank(*p)) p++;
    if (p == le || *p == '#' || (*p == '/' && p + 1 < le && p[1] == '/')) continue;
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
        if (k == 0 && n == 0 && header_line == 0) {
          header_line = c.line;
          break;
        }
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: line %zu: field %d ('%s') is not a number; expected \"x y z\"", path,
                      c.line, k + 1, bbc__quote_token(q, sizeof q, p, field_end(p, le, 1)));
        goto fail;
      }
      p = next;
    }
    if (header_line == c.line) continue;
    /* Leica PTS (routed here too) starts with a line holding the point count. */
    if (k == 1 && n == 0 && header_line == 0 && v[0] >= 0 && v[0] == floor(v[0])) {
      header_line = c.line;
      pts_count = v[0];
      continue;
    }
    if (k < 3) {
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: line %zu has %d number%s; a point needs three (x y z)", path, c.line, k,
                    k == 1 ? "" : "s");
      goto fail;
    }
    for (int j = 0; j < 3; j++)
      if (!coordinate_ok(v[j])) {
        r = bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                      "%s: line %zu: point %zu has a non-finite or absurd coordinate (%g)", path,
                      c.line, n, v[j]);
        goto fail;
      }
    if (n == cap) { /* cannot happen given the bound; kept as a guard */
      r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: line %zu: more points than expected", path,
                    c.line);
      goto fail;
    }
    memcpy(mesh->positions + 3 * n, v, sizeof v);
    n++;
    if (report && (size_t)(c.p - buf) >= next_report) {
      bbc__progress(cb, "load", 0.9 * (double)(c.p - buf) / (double)size);
      next_report += size / 8;
    }
  }
  free(buf);
  buf = NULL;
  if (n == 0) {
    r = bbc__fail(err, BBC_ERROR_EMPTY,
                  "%s: no points: the file has only comments, blank lines or a header", path);
    goto fail;
  }
  if (pts_count >= 0 && pts_count != (double)n) { /* truncated, or not a count */
    r = bbc__fail(err, BBC_ERROR_CORRUPT,
                  "%s: line %zu gives %.0f points, the file holds %zu: truncated or damaged", path,
                  header_line, pts_count, n);
    goto fail;
  }
  double *shrunk = realloc(mesh->positions, n * 3 * sizeof(double));
  if (shrunk) mesh->positions = shrunk;
  mesh->vertex_count = n;
  return bbc__finish_loaded(mesh, options, path, err);

fail:
  free(buf);
  bbc_mesh_free(mesh);
  return r;
}
