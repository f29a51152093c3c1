/* load_obj.c — Wavefront OBJ (and its MTL) read by us into the scene Assimp's
 * OBJ importer would hand over, then converted as every Assimp scene is
 * (load_assimp.c): the same mesh, bit for bit, at a fraction of the time
 * and memory (issue 34: Assimp took 3.8 s and 600 MB over the 227 MB file
 * of a 1.13M-triangle oak).
 *
 * The scene follows Assimp 5's importer (its behaviour, observed and read
 * in its documentation and sources): an object (`o`, and a new one at every
 * change of `g`) is a node named after it; a mesh per run of one material
 * in it (`usemtl` opens a new mesh once the current one has faces); every
 * face corner its own vertex; quads cut as its Triangulate step cuts them
 * (from a concave corner, else from the first); numbers rounded as its
 * fast_atof rounds them (the integer part as a float, the first 15
 * decimals through a double, added in float). The MTL gives each material
 * what the conversion reads: name, Kd, Ka, d, Ns, illum and map_Kd, on
 * Assimp's defaults (diffuse 0.6, opacity 1, illum 1).
 *
 * Only a plain subset is read here: triangles and quads with v, vt, vn
 * indices, o, g, s, usemtl, mtllib, comments, numbers of the form
 * [-]digits[.digits][e[-]digits]. Anything else (polygons of more corners,
 * lines, points, vertex colours, names with spaces, texture options,
 * indentation, ...) is deferred (*deferred = 1) and the caller hands the
 * file to Assimp, as before. test_load_obj checks both readers give the same mesh
 * on every OBJ of the data set and on made ones. */
#include "io.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

enum { NO_MATERIAL = -1, NAME_MAX_LEN = 1000 };

typedef struct obj_material {
  char *name;
  float ambient[3], diffuse[3], alpha, shininess;
  int illum;
  char *texture; /* map_Kd */
} obj_material;

typedef struct obj_mesh {
  int material; /* NO_MATERIAL until a usemtl or the object's creation sets it */
  int has_normals;
  size_t uv_refs, faces;
} obj_mesh;

typedef struct obj_object {
  char *name;
  uint32_t *meshes;
  size_t n, cap;
} obj_object;

/* A growing array of `elem`-byte items. */
typedef struct vec {
  void *p;
  size_t n, cap, elem;
} vec;

typedef struct obj_reader {
  const char *path;
  const bbc_load_options *opt;
  vec v, vt, vn;    /* floats: 3 a position, 3 a texture coordinate (z 0 when 2D), 3 a normal */
  vec corners;      /* int32: v, vt, vn (-1: none) a corner, indices 0-based */
  vec face_mesh;    /* uint32 a face: its mesh */
  vec face_corners; /* uint8 a face: 3 or 4 */
  vec meshes;       /* obj_mesh */
  vec objects;      /* obj_object */
  vec materials;    /* obj_material; [0] Assimp's DefaultMaterial */
  int current_object, current_mesh, current_material; /* -1: none */
  char *active_group;
  int defer; /* beyond the subset: Assimp reads the file */
  int oom;
} obj_reader;

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
  if (memchr(buf, 0, size) || memchr(buf, '\r', size))
    R->defer = 1;
  else
    parse_mtl(R, buf);
  free(buf);
}

/* ---- OBJ lines ---------------------------------------------------------------- */

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
  uint32_t *fm = vec_push(&R->face_mesh);
  uint8_t *fc = vec_push(&R->face_corners);
  if (!fm || !fc) {
    R->oom = 1;
    return;
  }
  *fm = (uint32_t)R->current_mesh;
  *fc = (uint8_t)nc;
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
  case 'o':
    if (!(n = one_name(p + 1, &s))) {
      R->defer = 1;
      return;
    }
    R->current_object = -1;
    for (size_t i = 0; i < R->objects.n; i++) {
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
    R->defer = 1; /* lines, points, curves, indented lines, ...: Assimp */
  }
}

/* ---- the scene ------------------------------------------------------------------- */

static void add_prop(struct aiMaterial *m, const char *key, unsigned semantic,
                     enum aiPropertyTypeInfo type, const void *data, unsigned length, int *oom) {
  struct aiMaterialProperty *p = calloc(1, sizeof *p);
  if (p) p->mData = malloc(length);
  if (!p || !p->mData || m->mNumProperties == m->mNumAllocated) {
    if (p) free(p->mData);
    free(p);
    *oom = 1;
    return;
  }
  p->mKey.length = (ai_uint32)strlen(key);
  memcpy(p->mKey.data, key, p->mKey.length + 1);
  p->mSemantic = semantic;
  p->mType = type;
  p->mDataLength = length;
  memcpy(p->mData, data, length);
  m->mProperties[m->mNumProperties++] = p;
}

/* A string property as Assimp lays it out: length (4 bytes), characters, NUL. */
static void add_string(struct aiMaterial *m, const char *key, unsigned semantic, const char *s,
                       int *oom) {
  char buf[4 + NAME_MAX_LEN + 1];
  uint32_t len = (uint32_t)strlen(s);
  memcpy(buf, &len, 4);
  memcpy(buf + 4, s, len + 1);
  add_prop(m, key, semantic, aiPTI_String, buf, 4 + len + 1, oom);
}

/* The properties of Assimp's createMaterials that the conversion reads. */
static struct aiMaterial *make_material(const obj_material *om, int *oom) {
  struct aiMaterial *m = calloc(1, sizeof *m);
  if (m) m->mProperties = calloc(8, sizeof *m->mProperties);
  if (!m || !m->mProperties) {
    free(m);
    *oom = 1;
    return NULL;
  }
  m->mNumAllocated = 8;
  int sm = om->illum == 0   ? aiShadingMode_NoShading
           : om->illum == 2 ? aiShadingMode_Phong
                            : aiShadingMode_Gouraud;
  add_string(m, "?mat.name", 0, om->name, oom);
  add_prop(m, "$mat.shadingm", 0, aiPTI_Integer, &sm, sizeof sm, oom);
  add_prop(m, "$clr.ambient", 0, aiPTI_Float, om->ambient, sizeof om->ambient, oom);
  add_prop(m, "$clr.diffuse", 0, aiPTI_Float, om->diffuse, sizeof om->diffuse, oom);
  add_prop(m, "$mat.shininess", 0, aiPTI_Float, &om->shininess, sizeof om->shininess, oom);
  add_prop(m, "$mat.opacity", 0, aiPTI_Float, &om->alpha, sizeof om->alpha, oom);
  if (om->texture) add_string(m, "$tex.file", aiTextureType_DIFFUSE, om->texture, oom);
  return m;
}

void bbc__scene_material_free(struct aiMaterial *m) {
  if (!m) return;
  for (unsigned i = 0; i < m->mNumProperties; i++) {
    free(m->mProperties[i]->mData);
    free(m->mProperties[i]);
  }
  free(m->mProperties);
  free(m);
}

/* Assimp's Triangulate on a quad's corners a (positions): the first corner
 * whose angles to the diagonal sum beyond pi (a concave one) starts the
 * two triangles, else the first. Single precision, as there. */
static int quad_start(const struct aiVector3D *a) {
  for (int i = 0; i < 4; i++) {
    const struct aiVector3D *v0 = &a[(i + 3) % 4], *v1 = &a[(i + 2) % 4], *v2 = &a[(i + 1) % 4],
                            *v = &a[i];
    float d[3][3] = {{v0->x - v->x, v0->y - v->y, v0->z - v->z},
                     {v1->x - v->x, v1->y - v->y, v1->z - v->z},
                     {v2->x - v->x, v2->y - v->y, v2->z - v->z}};
    for (int k = 0; k < 3; k++) {
      float len = sqrtf(d[k][0] * d[k][0] + d[k][1] * d[k][1] + d[k][2] * d[k][2]);
      if (len != 0.0f) {
        float inv = 1.0f / len;
        d[k][0] *= inv;
        d[k][1] *= inv;
        d[k][2] *= inv;
      }
    }
    float left = d[0][0] * d[1][0] + d[0][1] * d[1][1] + d[0][2] * d[1][2];
    float right = d[2][0] * d[1][0] + d[2][1] * d[1][1] + d[2][2] * d[1][2];
    float angle = acosf(left) + acosf(right);
    if (angle > (float)M_PI) return i;
  }
  return 0;
}

static void free_mesh(struct aiMesh *m) {
  if (!m) return;
  free(m->mVertices);
  free(m->mNormals);
  free(m->mTextureCoords[0]);
  if (m->mFaces) free(m->mFaces[0].mIndices); /* one block for all */
  free(m->mFaces);
  free(m);
}

/* Mesh mi as Assimp's createTopology, createVertexArray and Triangulate
 * make it: a vertex a corner; normals when the file has some and a face of
 * the mesh refers to them, texture coordinates likewise; quads in two.
 * `faces` lists the mesh's faces in file order, `first` each face's first
 * corner. NULL with R->defer for indices out of range (Assimp's error). */
static struct aiMesh *make_mesh(obj_reader *R, int mi, const uint32_t *faces, size_t nf,
                                const size_t *first) {
  const obj_mesh *om = (const obj_mesh *)R->meshes.p + mi;
  const uint8_t *fcn = R->face_corners.p;
  const int32_t *cr = R->corners.p;
  const float *V = R->v.p, *T = R->vt.p, *N = R->vn.p;
  size_t nv = 0, nt = 0;
  for (size_t i = 0; i < nf; i++) {
    nv += fcn[faces[i]];
    nt += fcn[faces[i]] == 4 ? 2 : 1;
  }
  if (nv > UINT32_MAX / 2) {
    R->defer = 1;
    return NULL;
  }
  struct aiMesh *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = (unsigned)nv;
  m->mNumFaces = (unsigned)nt;
  m->mMaterialIndex = om->material == NO_MATERIAL ? 0 : (unsigned)om->material;
  m->mVertices = malloc(nv * sizeof *m->mVertices);
  int normals = R->vn.n && om->has_normals, uvs = R->vt.n && om->uv_refs;
  if (normals) m->mNormals = calloc(nv, sizeof *m->mNormals);
  if (uvs) {
    m->mTextureCoords[0] = calloc(nv, sizeof *m->mTextureCoords[0]);
    m->mNumUVComponents[0] = 2;
  }
  m->mFaces = calloc(nt ? nt : 1, sizeof *m->mFaces);
  unsigned *ix = malloc((nt ? 3 * nt : 1) * sizeof *ix);
  if (!m->mVertices || (normals && !m->mNormals) || (uvs && !m->mTextureCoords[0]) || !m->mFaces ||
      !ix) {
    free(ix);
    free_mesh(m);
    return NULL;
  }
  m->mFaces[0].mIndices = ix;
  int normals_ok = 1, uvs_ok = 1;
  size_t o = 0, t = 0;
  for (size_t i = 0; i < nf; i++) {
    size_t f = faces[i], c0 = first[f];
    int nc = fcn[f];
    for (int k = 0; k < nc; k++) {
      const int32_t *c = cr + 3 * (c0 + (size_t)k);
      if (c[0] < 0 || (size_t)c[0] >= R->v.n) {
        R->defer = 1;
        free_mesh(m);
        return NULL;
      }
      memcpy(&m->mVertices[o + (size_t)k], V + 3 * (size_t)c[0], 3 * sizeof(float));
      if (normals && normals_ok && c[2] >= -1) {
        if (c[2] >= 0 && (size_t)c[2] < R->vn.n)
          memcpy(&m->mNormals[o + (size_t)k], N + 3 * (size_t)c[2], 3 * sizeof(float));
        else if (c[2] != -1)
          normals_ok = 0;
      }
      if (uvs && uvs_ok && c[1] >= -1) {
        if (c[1] >= 0 && (size_t)c[1] < R->vt.n)
          memcpy(&m->mTextureCoords[0][o + (size_t)k], T + 3 * (size_t)c[1], 3 * sizeof(float));
        else if (c[1] != -1)
          uvs_ok = 0;
      }
    }
    unsigned b = (unsigned)o;
    if (nc == 3) {
      m->mFaces[t].mNumIndices = 3;
      m->mFaces[t].mIndices = ix + 3 * t;
      ix[3 * t] = b, ix[3 * t + 1] = b + 1, ix[3 * t + 2] = b + 2;
      t++;
    } else {
      unsigned s = (unsigned)quad_start(&m->mVertices[o]);
      unsigned q[4] = {b, b + 1, b + 2, b + 3};
      for (int h = 0; h < 2; h++) {
        m->mFaces[t].mNumIndices = 3;
        m->mFaces[t].mIndices = ix + 3 * t;
        ix[3 * t] = q[s];
        ix[3 * t + 1] = q[(s + 1 + (unsigned)h) % 4];
        ix[3 * t + 2] = q[(s + 2 + (unsigned)h) % 4];
        t++;
      }
    }
    o += (size_t)nc;
  }
  if (!normals_ok) {
    free(m->mNormals);
    m->mNormals = NULL;
  }
  if (!uvs_ok) {
    free(m->mTextureCoords[0]);
    m->mTextureCoords[0] = NULL;
  }
  return m;
}

static void free_scene(struct aiScene *sc) {
  if (!sc) return;
  for (unsigned i = 0; i < sc->mNumMeshes; i++) free_mesh(sc->mMeshes[i]);
  free(sc->mMeshes);
  for (unsigned i = 0; i < sc->mNumMaterials; i++) bbc__scene_material_free(sc->mMaterials[i]);
  free(sc->mMaterials);
  if (sc->mRootNode) {
    for (unsigned i = 0; i < sc->mRootNode->mNumChildren; i++) {
      free(sc->mRootNode->mChildren[i]->mMeshes);
      free(sc->mRootNode->mChildren[i]);
    }
    free(sc->mRootNode->mChildren);
    free(sc->mRootNode);
  }
  free(sc);
}

/* The scene of the model read: a root node, a child node an object (its
 * meshes with faces), the materials in the library's order. NULL with
 * R->defer or R->oom. */
static struct aiScene *make_scene(obj_reader *R) {
  size_t nf = R->face_mesh.n, nm = R->meshes.n;
  const uint32_t *fm = R->face_mesh.p;
  const uint8_t *fcn = R->face_corners.p;
  struct aiScene *sc = calloc(1, sizeof *sc);
  size_t *first = malloc((nf ? nf : 1) * sizeof *first);
  size_t *start = calloc(nm + 1, sizeof *start);
  uint32_t *order = malloc((nf ? nf : 1) * sizeof *order);
  if (sc) {
    sc->mRootNode = calloc(1, sizeof *sc->mRootNode);
    sc->mMeshes = calloc(nm ? nm : 1, sizeof *sc->mMeshes);
    sc->mMaterials = calloc(R->materials.n, sizeof *sc->mMaterials);
  }
  if (!sc || !first || !start || !order || !sc->mRootNode || !sc->mMeshes || !sc->mMaterials)
    goto oom;
  /* faces by mesh, each mesh's in file order */
  size_t c = 0;
  for (size_t f = 0; f < nf; f++) {
    first[f] = c;
    c += fcn[f];
    start[fm[f] + 1]++;
  }
  for (size_t i = 0; i < nm; i++) start[i + 1] += start[i];
  for (size_t f = 0; f < nf; f++) order[start[fm[f]]++] = (uint32_t)f;
  for (size_t i = nm; i > 0; i--) start[i] = start[i - 1];
  start[0] = 0;
  struct aiNode *root = sc->mRootNode;
  root->mTransformation.a1 = root->mTransformation.b2 = root->mTransformation.c3 =
      root->mTransformation.d4 = 1;
  root->mChildren = calloc(R->objects.n ? R->objects.n : 1, sizeof *root->mChildren);
  if (!root->mChildren) goto oom;
  for (size_t oi = 0; oi < R->objects.n; oi++) {
    const obj_object *ob = (const obj_object *)R->objects.p + oi;
    struct aiNode *node = calloc(1, sizeof *node);
    if (!node) goto oom;
    root->mChildren[root->mNumChildren++] = node;
    node->mParent = root;
    node->mTransformation = root->mTransformation;
    node->mName.length = (ai_uint32)strlen(ob->name);
    memcpy(node->mName.data, ob->name, node->mName.length + 1);
    node->mMeshes = malloc((ob->n ? ob->n : 1) * sizeof *node->mMeshes);
    if (!node->mMeshes) goto oom;
    for (size_t k = 0; k < ob->n; k++) {
      int mi = (int)ob->meshes[k];
      size_t count = start[mi + 1] - start[mi];
      if (!count) continue; /* Assimp leaves meshes without faces out */
      struct aiMesh *m = make_mesh(R, mi, order + start[mi], count, first);
      if (!m) {
        if (R->defer) goto fail;
        goto oom;
      }
      node->mMeshes[node->mNumMeshes++] = sc->mNumMeshes;
      sc->mMeshes[sc->mNumMeshes++] = m;
    }
  }
  for (size_t i = 0; i < R->materials.n; i++) {
    int oom = 0;
    sc->mMaterials[sc->mNumMaterials] = make_material((obj_material *)R->materials.p + i, &oom);
    if (sc->mMaterials[sc->mNumMaterials]) sc->mNumMaterials++;
    if (oom) goto oom;
  }
  free(first);
  free(start);
  free(order);
  return sc;
oom:
  R->oom = 1;
fail:
  free(first);
  free(start);
  free(order);
  free_scene(sc);
  return NULL;
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
  vec *all[] = {&R->v,      &R->vt,      &R->vn,       &R->corners, &R->face_mesh, &R->face_corners,
                &R->meshes, &R->objects, &R->materials};
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
  R.opt = options;
  R.v.elem = R.vt.elem = R.vn.elem = 3 * sizeof(float);
  R.corners.elem = 3 * sizeof(int32_t);
  R.face_mesh.elem = sizeof(uint32_t);
  R.face_corners.elem = 1;
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
  struct aiScene *sc = R.defer || R.oom ? NULL : make_scene(&R);
  int defer = R.defer, oom = R.oom;
  reader_free(&R);
  if (defer) return BBC_OK;
  *deferred = 0;
  if (oom || !sc) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  bbc_result r = bbc__assimp_convert(path, sc, options, mesh, err);
  free_scene(sc);
  return r;
}
