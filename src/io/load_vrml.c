/* load_vrml.c — VRML 2.0 / VRML97 (ISO/IEC 14772-1) meshes: the files
 * bbcgen writes (both formats) and the common subset other tools write:
 * Shape with Appearance (Material, ImageTexture) and IndexedFaceSet
 * (Coordinate, TextureCoordinate, coordIndex, texCoordIndex, ccw), inside
 * Group, Transform (translation, rotation, scale), Anchor, Billboard,
 * Collision, Switch (its chosen child) and LOD (its finest level), with
 * DEF/USE. Other geometry and unknown nodes are skipped (their count is
 * logged). Debian's Assimp has no VRML importer; this is the project's. */
#include "io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64

typedef enum { T_END, T_WORD, T_STRING, T_LBRACE, T_RBRACE, T_LBRACK, T_RBRACK } tkind;

typedef struct vnode vnode;

/* A field's value: numbers, strings and nodes in the order written. */
typedef struct vfield {
  char name[48];
  double *num;
  size_t num_count, num_cap;
  char *str; /* the first string (url) */
  vnode **node;
  size_t node_count, node_cap;
  int line;
} vfield;

struct vnode {
  char type[48];
  vfield *field;
  size_t field_count, field_cap;
  int line;
};

typedef struct parser {
  const char *s, *end, *path;
  int line;
  tkind kind;
  char tok[256];
  int tok_line;
  /* Every node, for freeing; DEF names. */
  vnode **all;
  size_t all_count, all_cap;
  struct def {
    char name[64];
    vnode *node;
  } * defs;
  size_t def_count, def_cap;
  bbc_error *err;
  int failed;
} parser;

static int fail(parser *p, bbc_result code, const char *what) {
  if (!p->failed) bbc__fail(p->err, code, "%s:%d: %s", p->path, p->tok_line, what);
  p->failed = 1;
  return 0;
}

static void next(parser *p) {
  for (;;) {
    while (p->s < p->end && (isspace((unsigned char)*p->s) || *p->s == ',')) {
      if (*p->s == '\n') p->line++;
      p->s++;
    }
    if (p->s < p->end && *p->s == '#') {
      while (p->s < p->end && *p->s != '\n') p->s++;
      continue;
    }
    break;
  }
  p->tok_line = p->line;
  p->tok[0] = 0;
  if (p->s >= p->end) {
    p->kind = T_END;
    return;
  }
  char c = *p->s;
  if (c == '{' || c == '}' || c == '[' || c == ']') {
    p->kind = c == '{' ? T_LBRACE : c == '}' ? T_RBRACE : c == '[' ? T_LBRACK : T_RBRACK;
    p->s++;
    return;
  }
  size_t n = 0;
  if (c == '"') {
    p->kind = T_STRING;
    p->s++;
    while (p->s < p->end && *p->s != '"') {
      if (*p->s == '\\' && p->s + 1 < p->end) p->s++;
      if (*p->s == '\n') p->line++;
      if (n + 1 < sizeof p->tok) p->tok[n++] = *p->s;
      p->s++;
    }
    if (p->s >= p->end) {
      fail(p, BBC_ERROR_CORRUPT, "a string is not closed");
      p->kind = T_END;
      return;
    }
    p->s++;
  } else {
    p->kind = T_WORD;
    while (p->s < p->end && !isspace((unsigned char)*p->s) && *p->s != ',' && *p->s != '{' &&
           *p->s != '}' && *p->s != '[' && *p->s != ']' && *p->s != '"' && *p->s != '#') {
      if (n + 1 < sizeof p->tok) p->tok[n++] = *p->s;
      p->s++;
    }
  }
  p->tok[n] = 0;
}

static int hex_digit(char c) {
  return c >= '0' && c <= '9'   ? c - '0'
         : c >= 'a' && c <= 'f' ? c - 'a' + 10
         : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                : -1;
}

/* A location ending in .dds (any case). */
static int is_dds(const char *url) {
  size_t n = strlen(url);
  return n >= 4 && url[n - 4] == '.' && (url[n - 3] | 32) == 'd' && (url[n - 2] | 32) == 'd' &&
         (url[n - 1] | 32) == 's';
}

static int is_number(const char *t) {
  return (t[0] >= '0' && t[0] <= '9') || t[0] == '-' || t[0] == '+' || t[0] == '.';
}

static void *grow(void *ptr, size_t *cap, size_t need, size_t size) {
  if (need <= *cap) return ptr;
  size_t nc = *cap ? *cap * 2 : 8;
  while (nc < need) nc *= 2;
  void *q = realloc(ptr, nc * size);
  if (q) *cap = nc;
  return q;
}

static vnode *new_node(parser *p) {
  vnode **a = grow(p->all, &p->all_cap, p->all_count + 1, sizeof *a);
  vnode *n = calloc(1, sizeof *n);
  if (!a || !n) {
    if (a) p->all = a;
    free(n);
    fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
    return NULL;
  }
  p->all = a;
  p->all[p->all_count++] = n;
  return n;
}

static int add_num(parser *p, vfield *f, double v) {
  double *a = grow(f->num, &f->num_cap, f->num_count + 1, sizeof *a);
  if (!a) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  f->num = a;
  f->num[f->num_count++] = v;
  return 1;
}

static int add_child(parser *p, vfield *f, vnode *c) {
  vnode **a = grow(f->node, &f->node_cap, f->node_count + 1, sizeof *a);
  if (!a) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  f->node = a;
  f->node[f->node_count++] = c;
  return 1;
}

static vnode *parse_node(parser *p, int depth);

/* Skips a balanced [ ... ] or { ... } starting at the current token. */
static int skip_group(parser *p) {
  int depth = 0;
  do {
    if (p->kind == T_END) return fail(p, BBC_ERROR_CORRUPT, "a PROTO is not closed");
    if (p->kind == T_LBRACE || p->kind == T_LBRACK) depth++;
    if (p->kind == T_RBRACE || p->kind == T_RBRACK) depth--;
    next(p);
  } while (depth > 0 && !p->failed);
  return !p->failed;
}

/* PROTO name [ interface ] { body }, EXTERNPROTO name [ interface ] url,
 * ROUTE a.b TO c.d: declarations, skipped (their instances are unknown
 * nodes to us, skipped too). Returns 1 when one was skipped. */
static int skip_declaration(parser *p) {
  if (p->kind != T_WORD) return 0;
  if (!strcmp(p->tok, "PROTO") || !strcmp(p->tok, "EXTERNPROTO")) {
    int external = !strcmp(p->tok, "EXTERNPROTO");
    next(p); /* the name */
    next(p);
    if (p->kind != T_LBRACK) {
      fail(p, BBC_ERROR_CORRUPT, "expected '[' after the PROTO's name");
      return 1; /* consumed; p->failed tells the caller */
    }
    if (!skip_group(p)) return 1;
    if (external) {
      if (p->kind == T_LBRACK)
        skip_group(p);
      else
        next(p);
    } else {
      if (p->kind != T_LBRACE) {
        fail(p, BBC_ERROR_CORRUPT, "expected '{' for the PROTO's body");
        return 1;
      }
      skip_group(p);
    }
    return 1;
  }
  if (!strcmp(p->tok, "ROUTE")) {
    for (int i = 0; i < 4; i++) next(p);
    return 1;
  }
  return 0;
}

/* A scalar word (number, TRUE/FALSE) into the field. */
static int scalar(parser *p, vfield *f) {
  if (!strcmp(p->tok, "TRUE")) return add_num(p, f, 1);
  if (!strcmp(p->tok, "FALSE")) return add_num(p, f, 0);
  char *e;
  errno = 0;
  double v = strtod(p->tok, &e);
  if (*e || e == p->tok || !isfinite(v)) {
    char m[320];
    snprintf(m, sizeof m, "field '%s': '%.64s' is not a number", f->name, p->tok);
    return fail(p, BBC_ERROR_CORRUPT, m);
  }
  return add_num(p, f, v);
}

/* A node value: DEF name Type {...}, USE name, NULL, or Type {...}. */
static int node_value(parser *p, vfield *f, int depth) {
  if (!strcmp(p->tok, "NULL")) {
    next(p);
    return 1;
  }
  vnode *c = parse_node(p, depth + 1);
  return c ? add_child(p, f, c) : 0;
}

static int parse_field(parser *p, vnode *n, int depth) {
  vfield *fa = grow(n->field, &n->field_cap, n->field_count + 1, sizeof *fa);
  if (!fa) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  n->field = fa;
  vfield *f = &n->field[n->field_count++];
  memset(f, 0, sizeof *f);
  snprintf(f->name, sizeof f->name, "%.47s", p->tok);
  f->line = p->tok_line;
  next(p);
  if (p->kind == T_LBRACK) {
    next(p);
    while (!p->failed && p->kind != T_RBRACK) {
      if (p->kind == T_END) return fail(p, BBC_ERROR_CORRUPT, "a list is not closed with ']'");
      if (p->kind == T_STRING) {
        /* The first string, or the next after a DDS (which our image
         * decoders do not read: bbcgen names the PNG after it). */
        if (!f->str || is_dds(f->str)) {
          free(f->str);
          if (!(f->str = bbc__strdup(p->tok)))
            return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
        }
        next(p);
      } else if (p->kind == T_WORD && (is_number(p->tok) || !strcmp(p->tok, "TRUE") ||
                                       !strcmp(p->tok, "FALSE") || f->num_count > 0)) {
        /* (a word amid numbers is a bad number, not a node) */
        if (!scalar(p, f)) return 0;
        next(p);
      } else if (p->kind == T_WORD) {
        if (skip_declaration(p)) {
          if (p->failed) return 0;
          continue;
        }
        if (!node_value(p, f, depth)) return 0;
      } else {
        return fail(p, BBC_ERROR_CORRUPT, "unexpected brace in a list");
      }
    }
    next(p);
    return !p->failed;
  }
  if (p->kind == T_STRING) {
    if (!(f->str = bbc__strdup(p->tok))) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
    next(p);
    return 1;
  }
  if (p->kind != T_WORD) {
    char m[160];
    snprintf(m, sizeof m, "field '%s' has no value", f->name);
    return fail(p, BBC_ERROR_CORRUPT, m);
  }
  if (is_number(p->tok) || !strcmp(p->tok, "TRUE") || !strcmp(p->tok, "FALSE")) {
    while (p->kind == T_WORD &&
           (is_number(p->tok) || !strcmp(p->tok, "TRUE") || !strcmp(p->tok, "FALSE"))) {
      if (!scalar(p, f)) return 0;
      next(p);
    }
    return 1;
  }
  return node_value(p, f, depth);
}

/* [DEF name] Type { fields } or USE name; the token is the first word. */
static vnode *parse_node(parser *p, int depth) {
  if (depth > MAX_DEPTH) {
    fail(p, BBC_ERROR_CORRUPT, "nodes nested too deeply");
    return NULL;
  }
  char def[64] = "";
  if (p->kind == T_WORD && !strcmp(p->tok, "USE")) {
    next(p);
    for (size_t i = 0; i < p->def_count; i++)
      if (!strcmp(p->defs[i].name, p->tok)) {
        next(p);
        return p->defs[i].node;
      }
    char m[160];
    snprintf(m, sizeof m, "USE of '%.64s', which no DEF names before", p->tok);
    fail(p, BBC_ERROR_CORRUPT, m);
    return NULL;
  }
  if (p->kind == T_WORD && !strcmp(p->tok, "DEF")) {
    next(p);
    snprintf(def, sizeof def, "%.63s", p->tok);
    next(p);
  }
  if (p->kind != T_WORD) {
    fail(p, BBC_ERROR_CORRUPT, "expected a node type");
    return NULL;
  }
  vnode *n = new_node(p);
  if (!n) return NULL;
  snprintf(n->type, sizeof n->type, "%.47s", p->tok);
  n->line = p->tok_line;
  if (def[0]) {
    struct def *d = grow(p->defs, &p->def_cap, p->def_count + 1, sizeof *d);
    if (!d) {
      fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
      return NULL;
    }
    p->defs = d;
    snprintf(p->defs[p->def_count].name, sizeof p->defs[0].name, "%s", def);
    p->defs[p->def_count++].node = n;
  }
  next(p);
  if (p->kind != T_LBRACE) {
    char m[160];
    snprintf(m, sizeof m, "expected '{' after %s", n->type);
    fail(p, BBC_ERROR_CORRUPT, m);
    return NULL;
  }
  next(p);
  while (!p->failed && p->kind != T_RBRACE) {
    if (p->kind == T_END) {
      char m[160];
      snprintf(m, sizeof m, "%s (line %d) is not closed with '}'", n->type, n->line);
      fail(p, BBC_ERROR_CORRUPT, m);
      return NULL;
    }
    if (p->kind != T_WORD) {
      fail(p, BBC_ERROR_CORRUPT, "expected a field name");
      return NULL;
    }
    if (!parse_field(p, n, depth)) return NULL;
  }
  next(p);
  return p->failed ? NULL : n;
}

static const vfield *field(const vnode *n, const char *name) {
  for (size_t i = 0; n && i < n->field_count; i++)
    if (!strcmp(n->field[i].name, name)) return &n->field[i];
  return NULL;
}

static const vnode *child(const vnode *n, const char *name) {
  const vfield *f = field(n, name);
  return f && f->node_count ? f->node[0] : NULL;
}

/* ---- building the mesh ------------------------------------------------------ */

typedef struct builder {
  parser *p;
  bbc_mesh *m;
  size_t vcap, tcap, mcap, tex_cap; /* vertices, triangles, materials, textures */
  int load_textures;
  const bbc_callbacks *cb; /* warnings: a texture that cannot be read */
  size_t skipped;          /* geometry nodes other than IndexedFaceSet and PointSet */
  size_t visits;           /* nodes walked: USE can repeat a subtree, even inside itself */
  /* PointSets (Appendix A: a point cloud is one node with point and color) */
  double *pts;
  uint8_t *cols;
  size_t np, pcap;
  int any_colour;
} builder;

/* One PointSet under transform xf: its points and their colours (Color
 * per point; light grey where it has none). */
static int add_points(builder *b, const vnode *ps, const double *xf) {
  const vfield *pt = field(child(ps, "coord"), "point");
  const vfield *cl = field(child(ps, "color"), "color");
  size_t n = pt ? pt->num_count / 3 : 0;
  if (pt && pt->num_count % 3)
    return fail(b->p, BBC_ERROR_CORRUPT, "PointSet: point needs x y z triples");
  if (cl && cl->num_count && cl->num_count != 3 * n)
    return fail(b->p, BBC_ERROR_CORRUPT, "PointSet: color needs one r g b per point");
  if (b->np + n > b->pcap) {
    size_t c = b->pcap ? 2 * b->pcap : 1024;
    while (c < b->np + n) c *= 2;
    double *p2 = realloc(b->pts, 3 * c * sizeof *p2);
    if (p2) b->pts = p2;
    uint8_t *c2 = realloc(b->cols, 4 * c);
    if (c2) b->cols = c2;
    if (!p2 || !c2) return fail(b->p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
    b->pcap = c;
  }
  for (size_t i = 0; i < n; i++) {
    const double *q = pt->num + 3 * i;
    double *o = b->pts + 3 * (b->np + i);
    for (int r = 0; r < 3; r++)
      o[r] = xf[4 * r] * q[0] + xf[4 * r + 1] * q[1] + xf[4 * r + 2] * q[2] + xf[4 * r + 3];
    uint8_t *c = b->cols + 4 * (b->np + i);
    for (int k = 0; k < 3; k++) {
      double v = cl && cl->num_count ? cl->num[3 * i + k] : 200.0 / 255;
      c[k] = (uint8_t)lrint(255 * (v < 0 ? 0 : v > 1 ? 1 : v));
    }
    c[3] = 255;
  }
  if (cl && cl->num_count) b->any_colour = 1;
  b->np += n;
  return 1;
}

/* A relative URL's path with its %XX escapes decoded (RFC 3986 2.1: VRML97
 * 4.5.2 takes URLs; bbcgen's writer escapes spaces and the like). */
static void url_decode(const char *url, char *out, size_t size) {
  size_t n = 0;
  for (const char *p = url; *p && n + 1 < size; p++) {
    int hi, lo;
    if (*p == '%' && (hi = hex_digit(p[1])) >= 0 && (lo = hex_digit(p[2])) >= 0) {
      out[n++] = (char)(hi * 16 + lo);
      p += 2;
    } else {
      out[n++] = *p;
    }
  }
  out[n] = 0;
}

static int texture_index(builder *b, const char *encoded) {
  bbc_mesh *m = b->m;
  char full[8192], url[4096];
  url_decode(encoded, url, sizeof url);
  /* Not found: the url as written, which the read below names. */
  bbc__texture_resolve(b->p->path, url, BBC__TEXTURE_URL, full, sizeof full);
  for (size_t i = 0; i < m->texture_count; i++)
    if (m->textures[i].path && !strcmp(m->textures[i].path, full))
      return b->load_textures && !m->textures[i].image.rgba ? -1 : (int)i;
  bbc_texture *t = grow(m->textures, &b->tex_cap, m->texture_count + 1, sizeof *t);
  if (!t) return -2;
  m->textures = t;
  bbc_texture *nt = &m->textures[m->texture_count];
  memset(nt, 0, sizeof *nt);
  nt->path = bbc__strdup(full);
  if (!nt->path) return -2;
  m->texture_count++;
  if (b->load_textures) {
    bbc_error e;
    if (bbc_image_load(full, &nt->image, &e) != BBC_OK) {
      /* As for a missing map_Kd: said once, and the shapes keep their
       * material colour instead of drawing nothing. */
      bbc__log(b->cb, BBC_LOG_WARNING,
               "%s: texture '%s' cannot be read (%s); using the base colour", b->p->path, url,
               e.message);
      return -1;
    }
    nt->has_alpha = bbc_image_has_transparency(&nt->image);
  }
  return (int)(m->texture_count - 1);
}

/* Room for `nv` more vertices and `nt` more triangles in every array. */
static int reserve(builder *b, size_t nv, size_t nt) {
  bbc_mesh *m = b->m;
  if (m->vertex_count + nv > b->vcap) {
    size_t c = b->vcap ? 2 * b->vcap : 1024;
    while (c < m->vertex_count + nv) c *= 2;
    double *pos = realloc(m->positions, 3 * c * sizeof *pos);
    if (pos) m->positions = pos;
    float *uv = realloc(m->uvs, 2 * c * sizeof *uv);
    if (uv) m->uvs = uv;
    if (!pos || !uv) return 0;
    b->vcap = c;
  }
  if (m->triangle_count + nt > b->tcap) {
    size_t c = b->tcap ? 2 * b->tcap : 1024;
    while (c < m->triangle_count + nt) c *= 2;
    uint32_t *ix = realloc(m->indices, 3 * c * sizeof *ix);
    if (ix) m->indices = ix;
    uint32_t *fm = realloc(m->face_material, c * sizeof *fm);
    if (fm) m->face_material = fm;
    uint32_t *fg = realloc(m->face_group, c * sizeof *fg);
    if (fg) m->face_group = fg;
    if (!ix || !fm || !fg) return 0;
    b->tcap = c;
  }
  return 1;
}

/* One IndexedFaceSet under transform xf (3 x 4, row-major). */
static int add_faces(builder *b, const vnode *shape, const vnode *ifs, const double *xf) {
  parser *p = b->p;
  bbc_mesh *m = b->m;
  const vnode *app = child(shape, "appearance");
  const vnode *mat = child(app, "material");
  const vnode *tex = child(app, "texture");
  const vfield *url = tex ? field(tex, "url") : NULL;
  const vfield *pts = field(child(ifs, "coord"), "point");
  const vfield *tcs = field(child(ifs, "texCoord"), "point");
  const vfield *ci = field(ifs, "coordIndex"), *ti = field(ifs, "texCoordIndex");
  const vfield *ccw = field(ifs, "ccw"), *solid = field(ifs, "solid");
  if (!pts || !ci || pts->num_count < 9 || ci->num_count == 0) return 1; /* nothing to draw */
  size_t np = pts->num_count / 3, nt = tcs ? tcs->num_count / 2 : 0;
  if (ti && ti->num_count != ci->num_count) {
    p->tok_line = ifs->line;
    return fail(p, BBC_ERROR_INVALID_GEOMETRY, "texCoordIndex and coordIndex differ in length");
  }
  /* The material of this Shape. */
  bbc_material *ma = grow(m->materials, &b->mcap, m->material_count + 1, sizeof *ma);
  if (!ma) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  m->materials = ma;
  bbc_material *mt = &m->materials[m->material_count];
  memset(mt, 0, sizeof *mt);
  mt->name = bbc__strdup("");
  if (!mt->name) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  m->material_count++;
  for (int k = 0; k < 4; k++) mt->base_color[k] = 1.0f;
  mt->texture = -1;
  mt->unlit = !mat; /* VRML97 6.4: no Material, no lighting */
  mt->single_sided = !solid || solid->num_count == 0 || solid->num[0] != 0;
  if (mat) {
    const vfield *dc = field(mat, "diffuseColor"), *tr = field(mat, "transparency");
    if (dc && dc->num_count >= 3)
      for (int k = 0; k < 3; k++) mt->base_color[k] = (float)dc->num[k];
    if (tr && tr->num_count >= 1) mt->base_color[3] = (float)(1.0 - tr->num[0]);
    for (int k = 0; k < 3; k++) mt->ambient[k] = 0.2f; /* VRML's ambientIntensity default */
  }
  if (url && url->str) {
    int t = texture_index(b, url->str);
    if (t == -2) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
    mt->texture = t;
    mt->texture_ref = bbc__strdup(url->str);
  }
  uint32_t mi = (uint32_t)(m->material_count - 1);
  for (size_t k = 0; k + 1 < m->material_count; k++) { /* the same as an earlier one */
    const bbc_material *o = &m->materials[k];
    if (o->texture == mt->texture && o->unlit == mt->unlit && o->single_sided == mt->single_sided &&
        !memcmp(o->base_color, mt->base_color, sizeof o->base_color)) {
      free(mt->name);
      free(mt->texture_ref);
      m->material_count--;
      mi = (uint32_t)k;
      break;
    }
  }
  int flip = ccw && ccw->num_count && ccw->num[0] == 0;
  /* Faces: polygons ended by -1 (or the list's end), fan-triangulated, one
   * vertex per corner. */
  size_t start = 0, n = ci->num_count;
  for (size_t i = 0; i <= n; i++) {
    if (i < n && ci->num[i] >= 0) continue;
    size_t corners = i - start;
    for (size_t c = 1; corners >= 3 && c + 1 < corners; c++) {
      size_t k3[3] = {start, start + c, start + c + 1};
      if (flip) {
        size_t t = k3[1];
        k3[1] = k3[2];
        k3[2] = t;
      }
      if (!reserve(b, 3, 1)) return fail(p, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
      for (int j = 0; j < 3; j++) {
        double vi = ci->num[k3[j]];
        if (vi < 0 || vi >= (double)np || vi != floor(vi)) {
          p->tok_line = ci->line;
          return fail(p, BBC_ERROR_INVALID_GEOMETRY, "a coordIndex is outside the point list");
        }
        const double *q = pts->num + 3 * (size_t)vi;
        size_t v = m->vertex_count++;
        for (int r = 0; r < 3; r++)
          m->positions[3 * v + r] =
              xf[4 * r] * q[0] + xf[4 * r + 1] * q[1] + xf[4 * r + 2] * q[2] + xf[4 * r + 3];
        double t = ti ? ti->num[k3[j]] : vi;
        if (nt && (t < 0 || t >= (double)nt || t != floor(t))) {
          p->tok_line = ti ? ti->line : ci->line;
          return fail(p, BBC_ERROR_INVALID_GEOMETRY,
                      "a texture coordinate index is outside the list");
        }
        m->uvs[2 * v] = nt ? (float)tcs->num[2 * (size_t)t] : 0.0f;
        m->uvs[2 * v + 1] = nt ? (float)tcs->num[2 * (size_t)t + 1] : 0.0f;
        m->indices[3 * m->triangle_count + j] = (uint32_t)v;
      }
      m->face_material[m->triangle_count] = mi;
      m->face_group[m->triangle_count] = 0;
      m->triangle_count++;
    }
    start = i + 1;
  }
  return 1;
}

static void mul(const double *a, const double *b, double *o) { /* 3 x 4 affine */
  double r[12];
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 4; j++)
      r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j];
    r[4 * i + 3] += a[4 * i + 3];
  }
  memcpy(o, r, sizeof r);
}

/* Nodes walked at most: a scene that USEs a group inside itself or nests
 * many instances would otherwise take exponential time. */
#define MAX_VISITS 500000u

static int walk(builder *b, const vnode *n, const double *xf, int depth) {
  if (!n || depth > MAX_DEPTH) return 1;
  if (++b->visits > MAX_VISITS)
    return fail(b->p, BBC_ERROR_CORRUPT,
                "more than 500,000 node instances (USE inside itself, or nested too often)");
  const char *t = n->type;
  if (!strcmp(t, "Shape")) {
    const vnode *g = child(n, "geometry");
    if (g && !strcmp(g->type, "IndexedFaceSet")) return add_faces(b, n, g, xf);
    if (g && !strcmp(g->type, "PointSet")) return add_points(b, g, xf);
    if (g) b->skipped++;
    return 1;
  }
  double x[12];
  memcpy(x, xf, sizeof x);
  if (!strcmp(t, "Transform")) {
    const vfield *tr = field(n, "translation"), *ro = field(n, "rotation"), *sc = field(n, "scale");
    double m2[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (sc && sc->num_count >= 3)
      for (int i = 0; i < 3; i++) m2[5 * i] = sc->num[i];
    if (ro && ro->num_count >= 4) { /* axis-angle (Rodrigues) */
      double ax = ro->num[0], ay = ro->num[1], az = ro->num[2],
             l = sqrt(ax * ax + ay * ay + az * az);
      if (l > 0) {
        ax /= l, ay /= l, az /= l;
        double c = cos(ro->num[3]), s = sin(ro->num[3]), C = 1 - c;
        double R[12] = {c + ax * ax * C,      ax * ay * C - az * s, ax * az * C + ay * s, 0,
                        ay * ax * C + az * s, c + ay * ay * C,      ay * az * C - ax * s, 0,
                        az * ax * C - ay * s, az * ay * C + ax * s, c + az * az * C,      0};
        mul(R, m2, m2);
      }
    }
    if (tr && tr->num_count >= 3)
      for (int i = 0; i < 3; i++) m2[4 * i + 3] += tr->num[i];
    mul(xf, m2, x);
  }
  if (!strcmp(t, "LOD")) return walk(b, child(n, "level"), x, depth + 1); /* the finest */
  if (!strcmp(t, "Switch")) {
    const vfield *w = field(n, "whichChoice"), *ch = field(n, "choice");
    int k = w && w->num_count ? (int)w->num[0] : -1;
    return k >= 0 && ch && (size_t)k < ch->node_count ? walk(b, ch->node[k], x, depth + 1) : 1;
  }
  const vfield *ch = field(n, "children");
  for (size_t i = 0; ch && i < ch->node_count; i++)
    if (!walk(b, ch->node[i], x, depth + 1)) return 0;
  return 1;
}

bbc_result bbc__parse_vrml(const char *path, char *text, size_t n, const bbc_load_options *options,
                           bbc_mesh *mesh, bbc_error *err) {
  if (n < 15 || strncmp(text, "#VRML V2.0", 10)) {
    free(text);
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: not a VRML 2.0 / VRML97 file (no '#VRML V2.0' header)", path);
  }
  parser p;
  memset(&p, 0, sizeof p);
  p.s = text;
  p.end = text + n;
  p.path = path;
  p.line = 1;
  p.err = err;
  builder b;
  memset(&b, 0, sizeof b);
  b.p = &p;
  b.m = mesh;
  b.load_textures = !options->skip_textures;
  b.cb = &options->callbacks;
  mesh->kind = BBC_MESH_TRIANGLES;
  const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  next(&p);
  while (!p.failed && p.kind != T_END) {
    if (skip_declaration(&p)) continue;
    vnode *top = parse_node(&p, 0);
    if (!top) break;
    if (!walk(&b, top, id, 0)) break;
  }
  for (size_t i = 0; i < p.all_count; i++) {
    for (size_t j = 0; j < p.all[i]->field_count; j++) {
      free(p.all[i]->field[j].num);
      free(p.all[i]->field[j].str);
      free(p.all[i]->field[j].node);
    }
    free(p.all[i]->field);
    free(p.all[i]);
  }
  free(p.all);
  free(p.defs);
  free(text);
  if (p.failed) {
    free(b.pts);
    free(b.cols);
    return err ? err->code : BBC_ERROR_CORRUPT;
  }
  if (mesh->triangle_count == 0 && b.np) { /* a point cloud */
    free(mesh->uvs);
    mesh->uvs = NULL;
    free(mesh->positions);
    mesh->kind = BBC_MESH_POINTS;
    mesh->positions = b.pts;
    mesh->vertex_count = b.np;
    mesh->colors = b.cols;
    if (!b.any_colour) { /* no Color anywhere: no colours */
      free(mesh->colors);
      mesh->colors = NULL;
    }
    if (b.skipped)
      bbc__log(&options->callbacks, BBC_LOG_WARNING, "%s: %zu shapes other than PointSet skipped",
               path, b.skipped);
    return BBC_OK;
  }
  if (b.np)
    bbc__log(&options->callbacks, BBC_LOG_WARNING,
             "%s: %zu points of PointSets skipped (the file has faces)", path, b.np);
  free(b.pts);
  free(b.cols);
  if (b.skipped)
    bbc__log(&options->callbacks, BBC_LOG_WARNING,
             "%s: %zu shapes other than IndexedFaceSet skipped", path, b.skipped);
  if (mesh->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: no IndexedFaceSet with faces and no PointSet",
                     path);
  mesh->group_count = 1;
  mesh->group_names = calloc(1, sizeof *mesh->group_names);
  if (!mesh->group_names || !(mesh->group_names[0] = bbc__strdup("")))
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  return BBC_OK;
}
