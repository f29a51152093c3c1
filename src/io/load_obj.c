/* load_obj.c — Wavefront OBJ (and its MTL) read by us into the scene Assimp's
 * OBJ importer would hand over (built by obj_scene.c), then converted as
 * every Assimp scene is (load_assimp.c): the same mesh, bit for bit, at a
 * fraction of Assimp's time and memory on large files (docs/design.md,
 * "Speed").
 *
 * The scene follows Assimp 5's importer (its behaviour, observed and read
 * in its documentation and sources): an object (`o`, and a new one at every
 * change of `g`) is a node named after it; a mesh per run of one material
 * in it (`usemtl` opens a new mesh once the current one has faces); every
 * face corner its own vertex; quads cut as its Triangulate step cuts them
 * (from a concave corner, else from the first); lines (`l`) moved to a mesh
 * of their own as its SortByPType step moves them (the triangles then get
 * a vertex a corner); numbers rounded as its fast_atof rounds them (the
 * integer part as a float, the first 15 decimals through a double, added
 * in float). The MTL gives each material what the conversion reads: name,
 * Kd, Ka, d, Ns, illum and map_Kd, on Assimp's defaults (diffuse 0.6,
 * opacity 1, illum 1).
 *
 * Only a plain subset is read here: triangles and quads with v, vt, vn
 * indices, lines of vertex indices, o, g, s, usemtl, mtllib, comments,
 * numbers of the form [-]digits[.digits][e[-]digits]. Anything else
 * (polygons of more corners, points, vertex colours, names with spaces,
 * texture options, indentation, ...) is deferred (*deferred = 1) and the
 * caller hands the file to Assimp, as before. test_load_obj checks both
 * readers give the same mesh on every OBJ of the data set and on made
 * ones. */
#include "io.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include "obj_reader.h"

static void *vec_push(vec *a) {
  if (a->n == a->cap) {
    size_t cap = a->cap ? 2 * a->cap : 256;
    void *q = realloc(a->p, cap * a->elem);
    if (!q) return NULL;
    a->p = q;
    a->cap = cap;
  }
  return (char *)a->p + a->elem * a->n++;
}

static char *dup_span(const char *s, size_t n) {
  char *d = malloc(n + 1);
  if (d) {
    memcpy(d, s, n);
    d[n] = 0;
  }
  return d;
}

/* ---- numbers as Assimp's fast_atof reads them ------------------------------ */

static int is_digit(char c) {
  return c >= '0' && c <= '9';
}
static int is_blank(char c) {
  return c == ' ' || c == '\t';
}
static int at_end(char c) {
  return c == 0 || c == '\n' || c == '\r';
}

/* 10^-k for k decimals, as the constants of fast_atof's table */
static const double k_tenths[16] = {0.0,  0.1,  0.01,  0.001, 1e-4,  1e-5,  1e-6,  1e-7,
                                    1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};

/* One number at *p: [+-]digits[.digits][(e|E)[+-]digits], ending at a
 * blank or the line's end. The value as fast_atof computes it in single
 * precision: the integer part converted to float, at most 15 decimals as an
 * integer times 10^-k in double, rounded to float and added, an exponent
 * applied by powf. 0 (defer) for anything else, for more than 18 digits
 * before the point or in the exponent, and for values that are not finite
 * or beyond 1e29 (Assimp's path refuses them with a message). */
static int read_number(const char **pp, float *out) {
  const char *c = *pp;
  int neg = *c == '-';
  if (neg || *c == '+') c++;
  if (!is_digit(*c)) return 0;
  uint64_t ip = 0;
  int nd = 0;
  while (is_digit(*c)) {
    if (++nd > 18) return 0;
    ip = ip * 10 + (uint64_t)(*c++ - '0');
  }
  float f = (float)ip;
  if (*c == '.') {
    c++;
    if (!is_digit(*c)) return 0;
    uint64_t fr = 0;
    unsigned k = 0;
    while (is_digit(*c)) {
      if (k < 15) {
        fr = fr * 10 + (uint64_t)(*c - '0');
        k++;
      }
      c++;
    }
    double pl = (double)fr * k_tenths[k];
    f += (float)pl;
  }
  if (*c == 'e' || *c == 'E') {
    c++;
    int eneg = *c == '-';
    if (eneg || *c == '+') c++;
    if (!is_digit(*c)) return 0;
    uint64_t e = 0;
    int ne = 0;
    while (is_digit(*c)) {
      if (++ne > 18) return 0;
      e = e * 10 + (uint64_t)(*c++ - '0');
    }
    float ex = (float)e;
    if (eneg) ex = -ex;
    f *= powf(10.0f, ex);
  }
  if (neg) f = -f;
  if (!is_blank(*c) && !at_end(*c)) return 0;
  if (!isfinite(f) || fabsf(f) > 1e29f) return 0;
  *out = f;
  *pp = c;
  return 1;
}

static const char *skip_blanks(const char *p) {
  while (is_blank(*p)) p++;
  return p;
}

/* `count` numbers then the line's end (blanks allowed) into out; 0: defer. */
static int read_numbers(const char *p, int count, float *out) {
  for (int k = 0; k < count; k++) {
    p = skip_blanks(p);
    if (!read_number(&p, &out[k])) return 0;
  }
  return at_end(*skip_blanks(p));
}

/* How many blank-separated tokens stand before the line's end. */
static int count_tokens(const char *p) {
  int n = 0;
  for (;;) {
    p = skip_blanks(p);
    if (at_end(*p)) return n;
    n++;
    while (!is_blank(*p) && !at_end(*p)) p++;
  }
}

/* The one name after a keyword: a single token, nothing after it (not
 * even blanks: Assimp's versions differ on trimming), shorter than
 * NAME_MAX_LEN. Returns its length (*start its first character), 0: defer. */
static size_t one_name(const char *p, const char **start) {
  if (!is_blank(*p)) return 0;
  p = skip_blanks(p);
  const char *s = p;
  while (!is_blank(*p) && !at_end(*p)) p++;
  size_t n = (size_t)(p - s);
  if (!n || !at_end(*p) || n >= NAME_MAX_LEN) return 0;
  *start = s;
  return n;
}

/* ---- the model as Assimp's parser builds it ------------------------------- */

static int material_index(const obj_reader *R, const char *name, size_t n) {
  const obj_material *m = R->materials.p;
  for (size_t i = 0; i < R->materials.n; i++)
    if (strlen(m[i].name) == n && !memcmp(m[i].name, name, n)) return (int)i;
  return -1;
}

static int new_material(obj_reader *R, const char *name, size_t n) {
  obj_material *m = vec_push(&R->materials);
  if (!m) return -1;
  memset(m, 0, sizeof *m);
  m->name = dup_span(name, n);
  if (!m->name) {
    R->materials.n--;
    return -1;
  }
  m->diffuse[0] = m->diffuse[1] = m->diffuse[2] = 0.6f;
  m->alpha = 1.0f;
  m->illum = 1;
  return (int)R->materials.n - 1;
}

static void create_mesh(obj_reader *R) {
  obj_mesh *m = vec_push(&R->meshes);
  if (!m) {
    R->oom = 1;
    return;
  }
  memset(m, 0, sizeof *m);
  m->material = NO_MATERIAL;
  R->current_mesh = (int)R->meshes.n - 1;
  if (R->current_object < 0) return; /* Assimp: no object to attach it to */
  obj_object *o = (obj_object *)R->objects.p + R->current_object;
  if (o->n == o->cap) {
    size_t cap = o->cap ? 2 * o->cap : 4;
    uint32_t *q = realloc(o->meshes, cap * sizeof *q);
    if (!q) {
      R->oom = 1;
      return;
    }
    o->meshes = q;
    o->cap = cap;
  }
  o->meshes[o->n++] = (uint32_t)R->current_mesh;
}

static void create_object(obj_reader *R, const char *name, size_t n) {
  obj_object *o = vec_push(&R->objects);
  if (!o) {
    R->oom = 1;
    return;
  }
  memset(o, 0, sizeof *o);
  o->name = dup_span(name, n);
  if (!o->name) {
    R->objects.n--;
    R->oom = 1;
    return;
  }
  R->current_object = (int)R->objects.n - 1;
  create_mesh(R);
  if (!R->oom && R->current_material >= 0)
    ((obj_mesh *)R->meshes.p)[R->current_mesh].material = R->current_material;
}

/* ---- MTL --------------------------------------------------------------------- */

static int mtl_key(const char *p, const char *key) {
  size_t n = strlen(key);
  return !strncmp(p, key, n) && is_blank(p[n]);
}

/* The MTL's materials appended to the model; its last newmtl is then the
 * current material, as in Assimp. Lines it keys on but we do not read
 * (Ks, Ke, Ni, Tf and maps other than map_Kd) are skipped; others that
 * would change what the conversion reads (Tr, norm, Pr, texture options,
 * a second newmtl of a name) defer. */
static void parse_mtl(obj_reader *R, const char *buf) {
  const char *p = buf;
  if (is_blank(*p) || (unsigned char)*p == 0xEF) {
    R->defer = 1;
    return;
  }
  int cur = -1;
  while (*p && !R->defer && !R->oom) {
    p = skip_blanks(p);
    const char *eol = p;
    while (*eol && *eol != '\n') eol++;
    obj_material *m = cur >= 0 ? (obj_material *)R->materials.p + cur : NULL;
    const char *s;
    size_t n;
    if (at_end(*p) || *p == '#') {
      /* blank or comment */
    } else if (mtl_key(p, "newmtl")) {
      if (!(n = one_name(p + 6, &s)) || material_index(R, s, n) >= 0) {
        R->defer = 1;
      } else {
        cur = new_material(R, s, n);
        if (cur < 0) R->oom = 1;
        R->current_material = cur;
      }
    } else if (mtl_key(p, "Kd") || mtl_key(p, "Ka")) {
      float c[3];
      if (!m || !read_numbers(p + 2, 3, c))
        R->defer = 1;
      else
        memcpy(p[1] == 'd' ? m->diffuse : m->ambient, c, sizeof c);
    } else if (mtl_key(p, "d") || mtl_key(p, "Ns")) {
      float v;
      if (!m || !read_numbers(p + (p[0] == 'd' ? 1 : 2), 1, &v))
        R->defer = 1;
      else if (p[0] == 'd')
        m->alpha = v;
      else
        m->shininess = v;
    } else if (mtl_key(p, "illum")) {
      const char *q = skip_blanks(p + 5);
      int v = 0, digits = 0;
      while (is_digit(*q) && digits < 6) v = 10 * v + (*q++ - '0'), digits++;
      if (!m || !digits || !at_end(*skip_blanks(q)))
        R->defer = 1;
      else
        m->illum = v;
    } else if (mtl_key(p, "map_Kd")) {
      if (!m || m->texture || !(n = one_name(p + 6, &s)) || *s == '-' || *s == '*')
        R->defer = 1;
      else if (!(m->texture = dup_span(s, n)))
        R->oom = 1;
    } else if (mtl_key(p, "Ks") || mtl_key(p, "Ke") || mtl_key(p, "Ni") || mtl_key(p, "Tf") ||
               mtl_key(p, "map_d") || mtl_key(p, "map_Ka") || mtl_key(p, "map_Ks") ||
               mtl_key(p, "map_Ns") || mtl_key(p, "map_bump") || mtl_key(p, "map_Bump") ||
               mtl_key(p, "bump")) {
      /* read by Assimp into what the conversion does not look at */
    } else if (strchr("KkTdNnPmbriasc", *p)) {
      R->defer = 1; /* a key Assimp acts on that we do not follow */
    }
    p = *eol ? eol + 1 : eol;
  }
}

/* mtllib: the library beside the model (Assimp: the model's folder and
 * the name as written), else the model's path with "mtl" for its last
 * three characters; neither: nothing (usemtl then makes plain materials). */
static void load_mtllib(obj_reader *R, const char *name, size_t n) {
  char folder[4096], full[8192];
  /* a library in another folder (Assimp's versions differ on its maps'
   * paths), or one read while a mesh is open (newer ones give that mesh
   * each new material): Assimp */
  if (memchr(name, '/', n) || memchr(name, '\\', n) || R->current_mesh >= 0) {
    R->defer = 1;
    return;
  }
  bbc__path_folder(R->path, folder, sizeof folder);
  snprintf(full, sizeof full, "%s%.*s", folder, (int)n, name);
  if (!bbc__file_exists(full)) {
    size_t len = strlen(R->path);
    if (len < 3) return;
    snprintf(full, sizeof full, "%.*smtl", (int)(len - 3), R->path);
    if (!bbc__file_exists(full)) return;
  }
  char *buf = NULL;
  size_t size;
  bbc_error e;
  if (bbc__read_whole_file(full, &buf, &size, &e) != BBC_OK) {
    R->defer = 1; /* unreadable: Assimp says what it says */
    return;
  }
  /* CRLF line ends read as Assimp reads them; a lone CR (old Mac files) or
   * a NUL are Assimp's */
  int lone_cr = 0;
  for (const char *q = memchr(buf, '\r', size); q && !lone_cr;
       q = memchr(q + 1, '\r', size - (size_t)(q + 1 - buf)))
    lone_cr = q[1] != '\n';
  if (memchr(buf, 0, size) || lone_cr)
    R->defer = 1;
  else
    parse_mtl(R, buf);
  free(buf);
}

/* ---- OBJ lines ---------------------------------------------------------------- */

/* A face (or line) of nc corners already pushed: its mesh, size, kind. */
static int store_face(obj_reader *R, int nc, int line) {
  uint32_t *fm = vec_push(&R->face_mesh);
  uint8_t *fc = vec_push(&R->face_corners), *fl = vec_push(&R->face_line);
  if (!fm || !fc || !fl) {
    R->oom = 1;
    return 0;
  }
  *fm = (uint32_t)R->current_mesh;
  *fc = (uint8_t)nc;
  *fl = (uint8_t)line;
  return 1;
}

/* A line (`l`) of plain vertex indices, 2 to 255 of them: Assimp keeps it
 * in the mesh (its SortByPType step then moves lines to a mesh of their
 * own, which the conversion counts and skips). */
static void read_line_element(obj_reader *R, const char *p) {
  int nc = 0;
  const int nv = (int)R->v.n;
  size_t at = R->corners.n;
  for (;;) {
    p = skip_blanks(p);
    if (at_end(*p)) break;
    int neg = *p == '-';
    if (neg) p++;
    long v = 0;
    int digits = 0;
    if (*p < '1' || *p > '9') digits = 10;
    while (digits < 10 && is_digit(*p)) {
      v = 10 * v + (*p++ - '0');
      digits++;
    }
    int idx = neg ? (int)(nv - v) : (int)(v - 1);
    if (digits > 9 || idx < 0 || (!is_blank(*p) && !at_end(*p)) || nc == 255) {
      R->defer = 1;
      return;
    }
    int32_t *q = vec_push(&R->corners);
    if (!q) {
      R->oom = 1;
      return;
    }
    q[0] = idx, q[1] = -1, q[2] = -1;
    nc++;
  }
  if (nc < 2) {
    R->corners.n = at;
    R->defer = 1;
    return;
  }
  if (R->current_object < 0) create_object(R, "defaultobject", 13);
  if (R->current_mesh < 0) create_mesh(R);
  if (R->oom || !store_face(R, nc, 1)) return;
  obj_mesh *m = (obj_mesh *)R->meshes.p + R->current_mesh;
  m->faces++;
  m->segments += (size_t)nc - 1;
}

/* A face's corners: v, v/t, v//n or v/t/n, the same form at every corner,
 * 3 or 4 of them, indices [-]N (N >= 1; negative: from the end so far). */
static void read_face(obj_reader *R, const char *p) {
  int32_t c[4][3];
  int nc = 0, form = -1;
  const int nv = (int)R->v.n, nt = (int)R->vt.n, nn = (int)R->vn.n;
  for (;;) {
    p = skip_blanks(p);
    if (at_end(*p)) break;
    if (nc == 4) {
      R->defer = 1;
      return;
    }
    int idx[3] = {0, 0, 0}, have[3] = {0, 0, 0};
    for (int slot = 0; slot < 3; slot++) {
      int neg = *p == '-';
      if (neg) p++;
      if (*p >= '1' && *p <= '9') {
        long v = 0;
        int digits = 0;
        while (is_digit(*p)) {
          if (++digits > 9) {
            R->defer = 1;
            return;
          }
          v = 10 * v + (*p++ - '0');
        }
        const int size = slot == 0 ? nv : slot == 1 ? nt : nn;
        idx[slot] = neg ? (int)(size - v) : (int)(v - 1);
        have[slot] = 1;
        if (idx[slot] < 0) { /* before the first: Assimp's out-of-range error */
          R->defer = 1;
          return;
        }
      } else if (neg) {
        R->defer = 1;
        return;
      }
      if (*p != '/') break;
      p++;
    }
    if (!is_blank(*p) && !at_end(*p)) {
      R->defer = 1;
      return;
    }
    int f = have[0] | have[1] << 1 | have[2] << 2;
    /* the vertex always; a texture index only when there are texture
     * coordinates (Assimp reads v/n as a normal without them), a normal
     * only when there are normals */
    if (!have[0] || (have[1] && !nt) || (have[2] && !nn) || (form >= 0 && f != form)) {
      R->defer = 1;
      return;
    }
    form = f;
    c[nc][0] = idx[0];
    c[nc][1] = have[1] ? idx[1] : -1;
    c[nc][2] = have[2] ? idx[2] : -1;
    nc++;
  }
  if (nc < 3) {
    R->defer = 1;
    return;
  }
  if (R->current_object < 0) create_object(R, "defaultobject", 13);
  if (R->current_mesh < 0) create_mesh(R);
  if (R->oom) return;
  obj_mesh *m = (obj_mesh *)R->meshes.p + R->current_mesh;
  for (int k = 0; k < nc; k++) {
    int32_t *q = vec_push(&R->corners);
    if (!q) {
      R->oom = 1;
      return;
    }
    memcpy(q, c[k], sizeof c[k]);
  }
  if (!store_face(R, nc, 0)) return;
  m->faces++;
  if (form & 4) m->has_normals = 1;
  if (form & 2) m->uv_refs += (size_t)nc;
}

static void use_material(obj_reader *R, const char *name, size_t n) {
  if (R->current_material >= 0) {
    const char *cur = ((obj_material *)R->materials.p)[R->current_material].name;
    if (strlen(cur) == n && !memcmp(cur, name, n)) return; /* the same: ignored */
  }
  int k = material_index(R, name, n);
  if (k < 0 && (k = new_material(R, name, n)) < 0) {
    R->oom = 1;
    return;
  }
  R->current_material = k;
  obj_mesh *m = R->current_mesh >= 0 ? (obj_mesh *)R->meshes.p + R->current_mesh : NULL;
  if (!m || (m->material != NO_MATERIAL && m->material != k && m->faces)) create_mesh(R);
  if (!R->oom) ((obj_mesh *)R->meshes.p)[R->current_mesh].material = k;
}

static void read_line(obj_reader *R, const char *p) {
  const char *s;
  size_t n;
  float x[3];
  if (is_blank(*p)) { /* Assimp skips a line that starts with a blank */
    if (!at_end(*skip_blanks(p))) R->defer = 1;
    return;
  }
  switch (*p) {
  case 0:
  case '\n':
  case '\r':
  case '#':
    return;
  case 'v':
    if (is_blank(p[1])) {
      float *q = read_numbers(p + 1, 3, x) ? vec_push(&R->v) : NULL;
      if (q)
        memcpy(q, x, sizeof x);
      else
        R->defer = 1; /* 4 or 6 numbers (weights, colours), damaged ones: Assimp */
    } else if (p[1] == 't' && is_blank(p[2])) {
      int k = count_tokens(p + 2);
      x[2] = 0;
      float *q = (k == 2 || k == 3) && read_numbers(p + 2, k, x) ? vec_push(&R->vt) : NULL;
      if (q)
        memcpy(q, x, sizeof x);
      else
        R->defer = 1;
    } else if (p[1] == 'n' && is_blank(p[2])) {
      float *q = read_numbers(p + 2, 3, x) ? vec_push(&R->vn) : NULL;
      if (q)
        memcpy(q, x, sizeof x);
      else
        R->defer = 1;
    } else {
      R->defer = 1;
    }
    return;
  case 'f':
    if (is_blank(p[1]))
      read_face(R, p + 1);
    else
      R->defer = 1;
    return;
  case 's':
    return; /* smoothing groups: Assimp skips them */
  case 'l':
    if (is_blank(p[1]))
      read_line_element(R, p + 1);
    else
      R->defer = 1;
    return;
  case 'o':
    if (!(n = one_name(p + 1, &s))) {
      R->defer = 1;
      return;
    }
    R->current_object = -1; /* the first object of that name, as Assimp looks */
    for (size_t i = 0; i < R->objects.n && R->current_object < 0; i++) {
      const char *on = ((obj_object *)R->objects.p)[i].name;
      if (strlen(on) == n && !memcmp(on, s, n)) R->current_object = (int)i;
    }
    if (R->current_object < 0) create_object(R, s, n);
    return;
  case 'g':
    if (!(n = one_name(p + 1, &s))) {
      R->defer = 1;
      return;
    }
    if (R->active_group && strlen(R->active_group) == n && !memcmp(R->active_group, s, n)) return;
    create_object(R, s, n);
    free(R->active_group);
    if (!(R->active_group = dup_span(s, n))) R->oom = 1;
    return;
  case 'u':
    if (!strncmp(p, "usemtl", 6) && (n = one_name(p + 6, &s)))
      use_material(R, s, n);
    else
      R->defer = 1;
    return;
  case 'm':
    if (!strncmp(p, "mtllib", 6) && (n = one_name(p + 6, &s)))
      load_mtllib(R, s, n);
    else
      R->defer = 1;
    return;
  default:
    R->defer = 1; /* points, curves, ...: Assimp */
  }
}

static void reader_free(obj_reader *R) {
  for (size_t i = 0; i < R->objects.n; i++) {
    free(((obj_object *)R->objects.p)[i].name);
    free(((obj_object *)R->objects.p)[i].meshes);
  }
  for (size_t i = 0; i < R->materials.n; i++) {
    free(((obj_material *)R->materials.p)[i].name);
    free(((obj_material *)R->materials.p)[i].texture);
  }
  vec *all[] = {&R->v,         &R->vt,           &R->vn,        &R->corners,
                &R->face_mesh, &R->face_corners, &R->face_line, &R->meshes,
                &R->objects,   &R->materials};
  for (size_t i = 0; i < sizeof all / sizeof *all; i++) free(all[i]->p);
  free(R->active_group);
}

bbc_result bbc__parse_obj(const char *path, const char *buf, size_t size,
                          const bbc_load_options *options, bbc_mesh *mesh, int *deferred,
                          bbc_error *err) {
  /* Assimp refuses files under 16 bytes; a BOM, NULs, lone carriage
   * returns and line continuations are its to read */
  *deferred = 1;
  if (size < 16 || (unsigned char)buf[0] == 0xEF || memchr(buf, 0, size)) return BBC_OK;
  obj_reader R;
  memset(&R, 0, sizeof R);
  R.path = path;
  R.v.elem = R.vt.elem = R.vn.elem = 3 * sizeof(float);
  R.corners.elem = 3 * sizeof(int32_t);
  R.face_mesh.elem = sizeof(uint32_t);
  R.face_corners.elem = R.face_line.elem = 1;
  R.meshes.elem = sizeof(obj_mesh);
  R.objects.elem = sizeof(obj_object);
  R.materials.elem = sizeof(obj_material);
  R.current_object = R.current_mesh = R.current_material = -1;
  if (new_material(&R, "DefaultMaterial", 15) < 0) R.oom = 1;
  bbc__progress(&options->callbacks, "load", 0.0);
  const char *p = buf, *end = buf + size;
  size_t next_report = size / 8;
  while (p < end && !R.defer && !R.oom) {
    const char *eol = memchr(p, '\n', (size_t)(end - p));
    if (!eol) eol = end;
    const char *last = eol > p && eol[-1] == '\r' ? eol - 1 : eol;
    if ((last > p && last[-1] == '\\') || memchr(p, '\r', (size_t)(last - p))) {
      R.defer = 1;
      break;
    }
    read_line(&R, p);
    p = eol + 1;
    if ((size_t)(p - buf) > next_report) {
      bbc__progress(&options->callbacks, "load", 0.5 * (double)(p - buf) / (double)size);
      next_report += size / 8;
    }
  }
  if (!R.defer && !R.oom && R.face_mesh.n == 0) R.defer = 1; /* no faces: Assimp says so */
  struct aiScene *sc = R.defer || R.oom ? NULL : bbc__obj_make_scene(&R);
  int defer = R.defer, oom = R.oom;
  reader_free(&R);
  if (defer) return BBC_OK;
  *deferred = 0;
  if (oom || !sc) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  bbc_result r = bbc__assimp_convert(path, sc, options, mesh, err);
  bbc__obj_free_scene(sc);
  return r;
}
