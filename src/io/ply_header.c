/* ply_header.c — the PLY header: the format line, the elements with their
 * properties, and the texture a "comment TextureFile" line names. Every
 * line is checked, and a refusal names the file and the line. */
#include "ply.h"

#include <stdlib.h>
#include <string.h>

/* A real PLY header is a few hundred bytes; this bounds the header scan of a
 * file that only starts with "ply". */
#define PLY_MAX_HEADER (1u << 20)

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

void bbc__ply_header_free(ply_header *h) {
  for (size_t i = 0; i < h->element_count; i++) {
    for (size_t k = 0; k < h->elements[i].prop_count; k++) free(h->elements[i].props[k].name);
    free(h->elements[i].props);
    free(h->elements[i].name);
  }
  free(h->elements);
  free(h->texture_file);
  memset(h, 0, sizeof *h);
}

static int tok_is(token t, const char *word) {
  size_t n = strlen(word);
  return t.n == n && memcmp(t.s, word, n) == 0;
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

ply_element *bbc__ply_find_element(const ply_header *h, const char *name) {
  for (size_t i = 0; i < h->element_count; i++)
    if (strcmp(h->elements[i].name, name) == 0) return &h->elements[i];
  return NULL;
}

#define HEADER_MAX_TOKENS 6

/* One header line split at blanks, and where it is for messages. */
typedef struct header_line {
  const char *path;
  size_t line;    /* its number, 1-based */
  const char *le; /* its end */
  token t[HEADER_MAX_TOKENS];
  size_t nt, extra; /* tokens kept; tokens past HEADER_MAX_TOKENS */
} header_line;

/* Splits line [ls, l->le) at blanks into l->t. Control bytes in the header
 * mean binary data, not a header line. */
static bbc_result split_line(header_line *l, const char *ls, bbc_error *err) {
  const char *le = l->le;
  l->nt = l->extra = 0;
  for (const char *p = ls; p < le;) {
    while (p < le && is_blank(*p)) p++;
    if (p >= le) break;
    const char *s = p;
    while (p < le && !is_blank(*p)) {
      if ((unsigned char)*p < 0x20 || *p == 0x7f)
        return bbc__fail(err, BBC_ERROR_CORRUPT,
                         "%s: PLY header line %zu contains binary data; the header is damaged "
                         "or has no end_header line",
                         l->path, l->line);
      p++;
    }
    if (l->nt < HEADER_MAX_TOKENS)
      l->t[l->nt++] = (token){s, (size_t)(p - s)};
    else
      l->extra++;
  }
  return BBC_OK;
}

/* "comment TextureFile NAME": the first one names the texture. The name is
 * the rest of the line: file names may contain blanks. */
static bbc_result read_texture_file(const header_line *l, ply_header *h, bbc_error *err) {
  const token *t = l->t;
  const char *e = l->le;
  while (e > t[2].s && is_blank(e[-1])) e--;
  h->texture_file = tok_dup((token){t[2].s, (size_t)(e - t[2].s)});
  if (!h->texture_file)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the PLY header",
                     l->path);
  return BBC_OK;
}

/* "format ascii|binary_little_endian|binary_big_endian 1.0", once. */
static bbc_result read_format(const header_line *l, ply_header *h, int *have_format,
                              bbc_error *err) {
  const token *t = l->t;
  char q[40];
  if (*have_format || l->nt != 3)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY header line %zu: malformed format line (expected \"format "
                     "ascii|binary_little_endian|binary_big_endian 1.0\" once)",
                     l->path, l->line);
  if (tok_is(t[1], "ascii"))
    h->format = PLY_ASCII;
  else if (tok_is(t[1], "binary_little_endian"))
    h->format = PLY_BINARY_LE;
  else if (tok_is(t[1], "binary_big_endian"))
    h->format = PLY_BINARY_BE;
  else
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown format '%s'",
                     l->path, l->line, bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
  if (!tok_is(t[2], "1.0") && !tok_is(t[2], "1"))
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: PLY header line %zu: version '%s' is not supported (only 1.0)", l->path,
                     l->line, bbc__quote_token(q, sizeof q, t[2].s, t[2].s + t[2].n));
  *have_format = 1;
  return BBC_OK;
}

/* "element <name> <count>": a new element, declared once. */
static bbc_result read_element(const header_line *l, ply_header *h, bbc_error *err) {
  const token *t = l->t;
  char q[40];
  uint64_t count;
  if (l->nt != 3 || !parse_count(t[2], &count))
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY header line %zu: malformed element line (expected \"element "
                     "<name> <count>\" with a whole non-negative count)",
                     l->path, l->line);
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
  if (bbc__ply_find_element(h, e->name) != e)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY header line %zu: element '%s' is declared twice", l->path, l->line,
                     bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
  e->count = count;
  e->fixed = 1;
  return BBC_OK;
oom:
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the PLY header",
                   l->path);
}

/* The types of a property line: "property list <count type> <item type>
 * <name>" or "property <type> <name>"; *name is the name's token. */
static bbc_result property_types(const header_line *l, ply_property *p, token *name,
                                 bbc_error *err) {
  const token *t = l->t;
  size_t nt = l->nt;
  char q[40];
  if (nt >= 2 && tok_is(t[1], "list")) {
    if (nt != 5)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: PLY header line %zu: malformed list property (expected \"property "
                       "list <count type> <item type> <name>\")",
                       l->path, l->line);
    p->count_type = ply_type_from_token(t[2]);
    p->type = ply_type_from_token(t[3]);
    token bad = p->count_type == PLY_NONE ? t[2] : t[3];
    if (p->count_type == PLY_NONE || p->type == PLY_NONE)
      return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown type '%s'",
                       l->path, l->line, bbc__quote_token(q, sizeof q, bad.s, bad.s + bad.n));
    if (!ply_type_is_integer(p->count_type))
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: PLY header line %zu: list count type must be an integer type", l->path,
                       l->line);
    *name = t[4];
  } else {
    if (nt != 3)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: PLY header line %zu: malformed property (expected \"property "
                       "<type> <name>\")",
                       l->path, l->line);
    p->type = ply_type_from_token(t[1]);
    if (p->type == PLY_NONE)
      return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown type '%s'",
                       l->path, l->line, bbc__quote_token(q, sizeof q, t[1].s, t[1].s + t[1].n));
    *name = t[2];
  }
  return BBC_OK;
}

/* A property line: one more property of the last element, whose binary
 * record size grows by the property's (a list's count only: its items vary). */
static bbc_result read_property(const header_line *l, ply_header *h, bbc_error *err) {
  if (h->element_count == 0)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: property before any element",
                     l->path, l->line);
  ply_element *e = &h->elements[h->element_count - 1];
  ply_property p = {NULL, PLY_NONE, PLY_NONE};
  token name = {NULL, 0};
  bbc_result r = property_types(l, &p, &name, err);
  if (r != BBC_OK) return r;
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
  return BBC_OK;
oom:
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the PLY header",
                   l->path);
}

/* One header line [ls, l->le): blank lines and comments are passed over,
 * keywords read; *done once end_header is read. */
static bbc_result read_line(header_line *l, const char *ls, ply_header *h, int *have_format,
                            int *done, bbc_error *err) {
  bbc_result r = split_line(l, ls, err);
  if (r != BBC_OK) return r;
  const token *t = l->t;
  char q[40];
  if (l->nt == 0) return BBC_OK; /* tolerate blank lines */
  if (tok_is(t[0], "comment") && l->nt >= 3 && tok_is(t[1], "TextureFile") && !h->texture_file)
    return read_texture_file(l, h, err);
  if (tok_is(t[0], "comment") || tok_is(t[0], "obj_info")) return BBC_OK;
  if (l->extra) l->nt = HEADER_MAX_TOKENS + 1; /* too many tokens for any keyword */

  if (tok_is(t[0], "format")) return read_format(l, h, have_format, err);
  if (tok_is(t[0], "element")) return read_element(l, h, err);
  if (tok_is(t[0], "property")) return read_property(l, h, err);
  if (tok_is(t[0], "end_header")) {
    if (l->nt != 1)
      return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: malformed end_header",
                       l->path, l->line);
    *done = 1;
    return BBC_OK;
  }
  if (isdigit((unsigned char)t[0].s[0]) || strchr("+-.", t[0].s[0]))
    /* Numbers where keywords belong: the data begins without end_header. */
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: PLY header line %zu starts with a number ('%s'): the header has no "
                     "end_header line before the data",
                     l->path, l->line, bbc__quote_token(q, sizeof q, t[0].s, t[0].s + t[0].n));
  return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: PLY header line %zu: unknown keyword '%s'", l->path,
                   l->line, bbc__quote_token(q, sizeof q, t[0].s, t[0].s + t[0].n));
}

/* Parses the header at the start of buf[0, size), the whole file. The scan
 * stops after PLY_MAX_HEADER bytes, so a file without end_header is refused
 * quickly whatever its size. */
bbc_result bbc__ply_parse_header(const char *path, const char *buf, size_t size, ply_header *h,
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
  header_line l;
  l.path = path;
  next_line(&c, &ls, &le); /* "ply" */
  while (!done && next_line(&c, &ls, &le)) {
    l.line = c.line;
    l.le = le;
    r = read_line(&l, ls, h, &have_format, &done, err);
    if (r != BBC_OK) goto fail;
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

fail:
  bbc__ply_header_free(h);
  return r;
}
