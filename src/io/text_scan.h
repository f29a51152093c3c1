/* text_scan.h — what the point and mesh readers we write ourselves share
 * (the PLY reader through ply.h, load_xyz.c): whole-file reading, a line cursor that accepts
 * every line end, number fields with full double precision, one-line
 * quoting of bad input, the finishing of a loaded mesh. Internal. */
#ifndef BBC_TEXT_SCAN_H
#define BBC_TEXT_SCAN_H

#include "io.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>

/* Coordinates beyond this are not measurements but damage (a shifted binary
 * record read as float gives values like 1e38). */
#define ABSURD_COORDINATE 1e30
/* Below this many records (vertices, faces) progress is not worth reporting. */
#define PROGRESS_MIN_RECORDS 65536u

static inline int is_blank(char c) {
  return c == ' ' || c == '\t';
}

/* Line iterator over a text buffer. Accepts "\n", "\r\n" and a lone "\r"
 * (old Mac files) as line ends. */
typedef struct text_cursor {
  const char *p;
  const char *end;
  size_t line; /* number of the line last returned, 1-based */
} text_cursor;

static inline int next_line(text_cursor *c, const char **ls, const char **le) {
  if (c->p >= c->end) return 0;
  const char *q = c->p;
  while (q < c->end && *q != '\n' && *q != '\r') q++;
  *ls = c->p;
  *le = q;
  if (q < c->end) q += (*q == '\r' && q + 1 < c->end && q[1] == '\n') ? 2 : 1;
  c->p = q;
  c->line++;
  return 1;
}

/* Parses a number that starts exactly at p and must end at a blank, at the
 * line end `le`, or (comma_ok) at a comma. Returns the position after it, or
 * NULL when the field is not a number. strtod gets full double precision;
 * it could skip leading white space across a line break, which the first test
 * rules out. "nan" and "inf" parse as numbers and are refused later with a
 * clearer message than "not a number". */
static inline const char *scan_number(const char *p, const char *le, int comma_ok, double *out) {
  if (p >= le || isspace((unsigned char)*p)) return NULL;
  char *q;
  double v = strtod(p, &q);
  if (q == p || q > le) return NULL;
  if (q < le && !is_blank(*q) && !(comma_ok && *q == ',')) return NULL;
  *out = v;
  return q;
}

/* End of the field starting at p (for quoting it in messages). */
static inline const char *field_end(const char *p, const char *le, int comma_ok) {
  while (p < le && !is_blank(*p) && !(comma_ok && *p == ',')) p++;
  return p;
}

static inline int coordinate_ok(double v) {
  return isfinite(v) && fabs(v) <= ABSURD_COORDINATE;
}
/* Copies at most 24 characters of [s, e) into out for a message, control
 * bytes replaced, so that binary junk never ends up in a one-line message. */
const char *bbc__quote_token(char *out, size_t out_size, const char *s, const char *e);
/* Runs bbc_mesh_finalize, reports dropped triangles and the end of the
 * stage; frees on error. */
bbc_result bbc__finish_loaded(bbc_mesh *mesh, const bbc_load_options *options, const char *path,
                              bbc_error *err);

#endif
