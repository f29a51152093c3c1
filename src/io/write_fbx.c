/* write_fbx.c — binary FBX 7.4 for engines' LOD groups: one Model per mesh
 * (named as the caller says, "<model>_LOD0" ... for a chain), each with its
 * Geometry (triangles, normals and texture coordinates per corner, a
 * material index per triangle) and Phong materials whose DiffuseColor and
 * NormalMap are PNG files beside the FBX. Every file atomic.
 *
 * The format, as its public descriptions give it (Blender's
 * io_scene_fbx/encode_bin.py and parse_fbx.py, Assimp's
 * FBXBinaryTokenizer.cpp): the 23-byte magic "Kaydara FBX Binary  \0\x1a\0"
 * and a uint32 version, then records. A record (version < 7500) is uint32
 * end offset (absolute), uint32 property count, uint32 property bytes,
 * uint8 name length, the name, the properties, then its children followed
 * by 13 zero bytes when it has any; 13 zero bytes end the top level. A
 * property is a type code and its value: 'I' int32, 'L' int64, 'D' double,
 * 'C' bool (one byte), 'S' string (uint32 length + bytes), and arrays 'i',
 * 'd' (uint32 count, uint32 encoding 0 raw / 1 zlib, uint32 byte length,
 * the data). Objects are linked by Connections ("OO" child parent, "OP"
 * child parent property); a Material's order of connection to its Model is
 * the index the Geometry's LayerElementMaterial uses. Names are "name\0\1Class". */
#include "io.h"

#include <assert.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

/* The file in memory: io's buffer (bytes appended with bbc__text_append). */
typedef bbc__text fbuf;

static void put(fbuf *b, const void *d, size_t n) {
  bbc__text_append(b, d, n);
}

static void put_u32(fbuf *b, uint32_t v) {
  uint8_t d[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
  put(b, d, 4);
}

static void put_u64(fbuf *b, uint64_t v) {
  put_u32(b, (uint32_t)v);
  put_u32(b, (uint32_t)(v >> 32));
}

static void set_u32(fbuf *b, size_t at, uint32_t v) {
  if (b->oom) return;
  uint8_t d[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
  memcpy(b->data + at, d, 4);
}

/* A record being written: where its header is, how many properties it has
 * and whether children followed. */
typedef struct rec {
  size_t at, props_at;
  uint32_t props;
  int children;
} rec;

#define MAX_DEPTH 8
typedef struct writer {
  fbuf b;
  rec stack[MAX_DEPTH];
  int depth;
  int bad; /* nesting misuse (a bug) or a value too large */
} writer;

static void begin(writer *w, const char *name) {
  if (w->depth >= MAX_DEPTH) {
    w->bad = 1;
    return;
  }
  if (w->depth > 0) w->stack[w->depth - 1].children = 1;
  rec *r = &w->stack[w->depth++];
  r->at = w->b.size;
  r->props = 0;
  r->children = 0;
  put_u32(&w->b, 0); /* end offset */
  put_u32(&w->b, 0); /* property count */
  put_u32(&w->b, 0); /* property bytes */
  size_t len = strlen(name);
  uint8_t l = (uint8_t)len;
  put(&w->b, &l, 1);
  put(&w->b, name, len);
  r->props_at = w->b.size;
}

static void end(writer *w) {
  if (w->depth <= 0) {
    w->bad = 1;
    return;
  }
  rec *r = &w->stack[--w->depth];
  static const uint8_t zero[13] = {0};
  if (r->children) put(&w->b, zero, sizeof zero);
  if (w->b.size > UINT32_MAX) w->bad = 1; /* 32-bit offsets before version 7500 */
  set_u32(&w->b, r->at, (uint32_t)w->b.size);
  set_u32(&w->b, r->at + 4, r->props);
}

/* Properties: each adds to the current record's count and byte length. */
static void prop_begin(writer *w, char type) {
  if (w->depth <= 0 || w->stack[w->depth - 1].children) {
    w->bad = 1; /* properties come before children */
    return;
  }
  w->stack[w->depth - 1].props++;
  put(&w->b, &type, 1);
}

static void prop_end(writer *w) {
  if (w->depth <= 0 || w->b.oom) return;
  rec *r = &w->stack[w->depth - 1];
  set_u32(&w->b, r->at + 8, (uint32_t)(w->b.size - r->props_at));
}

static void p_int(writer *w, int32_t v) {
  prop_begin(w, 'I');
  put_u32(&w->b, (uint32_t)v);
  prop_end(w);
}

static void p_long(writer *w, int64_t v) {
  prop_begin(w, 'L');
  put_u64(&w->b, (uint64_t)v);
  prop_end(w);
}

static void p_double(writer *w, double v) {
  prop_begin(w, 'D');
  uint64_t u;
  memcpy(&u, &v, sizeof u);
  put_u64(&w->b, u);
  prop_end(w);
}

static void p_bool(writer *w, int v) {
  prop_begin(w, 'C');
  uint8_t c = v ? 1 : 0;
  put(&w->b, &c, 1);
  prop_end(w);
}

/* A string of n bytes (may hold the "\0\1" of object names). */
static void p_bytes(writer *w, const char *s, size_t n) {
  prop_begin(w, 'S');
  put_u32(&w->b, (uint32_t)n);
  put(&w->b, s, n);
  prop_end(w);
}

static void p_str(writer *w, const char *s) {
  p_bytes(w, s, strlen(s));
}

/* "name\0\1Class", the way FBX names objects. */
static void p_name(writer *w, const char *name, const char *cls) {
  char buf[600];
  size_t a = strlen(name), c = strlen(cls);
  if (a > 400) a = 400;
  memcpy(buf, name, a);
  buf[a] = 0;
  buf[a + 1] = 1;
  memcpy(buf + a + 2, cls, c);
  p_bytes(w, buf, a + 2 + c);
}

/* An array of `count` elements of `size` bytes (little-endian already),
 * zlib-compressed when that is smaller (deterministic: zlib's level 6). */
static void p_array(writer *w, char type, const void *data, size_t count, size_t size) {
  size_t raw = count * size;
  if (count > UINT32_MAX || raw > UINT32_MAX) {
    w->bad = 1;
    return;
  }
  prop_begin(w, type);
  put_u32(&w->b, (uint32_t)count);
  uLongf zn = compressBound((uLong)raw);
  uint8_t *z = raw >= 64 ? malloc(zn) : NULL;
  int zr = z ? compress2(z, &zn, data, (uLong)raw, 6) : Z_OK;
  if ((raw >= 64 && !z) || zr == Z_MEM_ERROR) { /* out of memory, not a raw array */
    free(z);
    w->b.oom = 1;
    return;
  }
  if (z && zr == Z_OK && zn < raw) {
    put_u32(&w->b, 1);
    put_u32(&w->b, (uint32_t)zn);
    put(&w->b, z, zn);
  } else {
    put_u32(&w->b, 0);
    put_u32(&w->b, (uint32_t)raw);
    put(&w->b, data, raw);
  }
  free(z);
  prop_end(w);
}

/* Little-endian bytes of doubles and int32s (the format's byte order). */
static void *le_doubles(const double *v, size_t n) {
  uint8_t *o = malloc(n ? n * 8 : 1);
  if (!o) return NULL;
  for (size_t i = 0; i < n; i++) {
    uint64_t u;
    memcpy(&u, &v[i], 8);
    for (int k = 0; k < 8; k++) o[8 * i + k] = (uint8_t)(u >> (8 * k));
  }
  return o;
}

static void *le_ints(const int32_t *v, size_t n) {
  uint8_t *o = malloc(n ? n * 4 : 1);
  if (!o) return NULL;
  for (size_t i = 0; i < n; i++)
    for (int k = 0; k < 4; k++) o[4 * i + k] = (uint8_t)((uint32_t)v[i] >> (8 * k));
  return o;
}

/* An array property from bytes made by le_doubles or le_ints (NULL: out
 * of memory). */
static void a_bytes(writer *w, char type, void *d, size_t n, size_t size) {
  if (!d) {
    w->b.oom = 1;
    return;
  }
  p_array(w, type, d, n, size);
  free(d);
}

static void a_doubles(writer *w, const double *v, size_t n) {
  a_bytes(w, 'd', le_doubles(v, n), n, 8);
}

static void a_ints(writer *w, const int32_t *v, size_t n) {
  a_bytes(w, 'i', le_ints(v, n), n, 4);
}

/* A child record holding one array. */
static void kv_doubles(writer *w, const char *k, const double *v, size_t n) {
  begin(w, k);
  a_doubles(w, v, n);
  end(w);
}

static void kv_ints(writer *w, const char *k, const int32_t *v, size_t n) {
  begin(w, k);
  a_ints(w, v, n);
  end(w);
}

/* A child record holding one value. */
static void kv_int(writer *w, const char *k, int32_t v) {
  begin(w, k);
  p_int(w, v);
  end(w);
}

static void kv_str(writer *w, const char *k, const char *v) {
  begin(w, k);
  p_str(w, v);
  end(w);
}

/* Properties70 entries: P "name" "type" "label" "flags" values... */
static void P_head(writer *w, const char *name, const char *type, const char *label,
                   const char *flags) {
  begin(w, "P");
  p_str(w, name);
  p_str(w, type);
  p_str(w, label);
  p_str(w, flags);
}

static void P_int(writer *w, const char *name, int v) {
  P_head(w, name, "int", "Integer", "");
  p_int(w, v);
  end(w);
}

static void P_double(writer *w, const char *name, double v) {
  P_head(w, name, "double", "Number", "");
  p_double(w, v);
  end(w);
}

static void P_number(writer *w, const char *name, double v) {
  P_head(w, name, "Number", "", "A");
  p_double(w, v);
  end(w);
}

static void P_color(writer *w, const char *name, double r, double g, double b) {
  P_head(w, name, "Color", "", "A");
  p_double(w, r);
  p_double(w, g);
  p_double(w, b);
  end(w);
}

static void P_vec(writer *w, const char *name, const char *type, double x, double y, double z) {
  P_head(w, name, type, "", "A");
  p_double(w, x);
  p_double(w, y);
  p_double(w, z);
  end(w);
}

static void P_kstring(writer *w, const char *name, const char *label, const char *v) {
  P_head(w, name, "KString", label, "");
  p_str(w, v);
  end(w);
}

/* ---- the document ------------------------------------------------------- */

static void header_extension(writer *w) {
  begin(w, "FBXHeaderExtension");
  kv_int(w, "FBXHeaderVersion", 1003);
  kv_int(w, "FBXVersion", 7400);
  kv_str(w, "Creator", "bbcgen " BBC_VERSION_STRING);
  end(w);
  kv_str(w, "Creator", "bbcgen " BBC_VERSION_STRING);
}

/* Y up, Z front, X right (glTF's frame, the cloud's), one unit a metre
 * (UnitScaleFactor is centimetres per unit), as bbcgen's glTF is read. */
static void global_settings(writer *w) {
  begin(w, "GlobalSettings");
  kv_int(w, "Version", 1000);
  begin(w, "Properties70");
  P_int(w, "UpAxis", 1);
  P_int(w, "UpAxisSign", 1);
  P_int(w, "FrontAxis", 2);
  P_int(w, "FrontAxisSign", 1);
  P_int(w, "CoordAxis", 0);
  P_int(w, "CoordAxisSign", 1);
  P_int(w, "OriginalUpAxis", 1);
  P_int(w, "OriginalUpAxisSign", 1);
  P_double(w, "UnitScaleFactor", 100.0);
  P_double(w, "OriginalUnitScaleFactor", 100.0);
  end(w);
  end(w);
}

/* Object ids: fixed, in writing order, so the file is the same every time. */
enum { ID_BASE = 1000000 };

typedef struct tex_file {
  const bbc_image *image;
  char name[600]; /* file name beside the FBX */
  int64_t tex_id, video_id;
  int dup; /* the same pixels as an earlier entry: its file and objects */
} tex_file;

typedef struct doc {
  const bbc_fbx_node *nodes;
  size_t count;
  tex_file *tex; /* the distinct images, one file each */
  size_t tex_count;
  int64_t next_id;
} doc;

static int same_image(const bbc_image *a, const bbc_image *b) {
  return a->width == b->width && a->height == b->height &&
         !memcmp(a->rgba, b->rgba, 4 * (size_t)a->width * (size_t)a->height);
}

/* The file index of mesh m's texture t (1 + index into mesh->textures as
 * materials name maps), or -1. */
static int tex_index(const doc *d, const bbc_mesh *m, int t) {
  if (t < 0 || (size_t)t >= m->texture_count || !m->textures[t].image.rgba) return -1;
  for (size_t i = 0; i < d->tex_count; i++)
    if (d->tex[i].image == &m->textures[t].image) return (int)i;
  return -1;
}

/* A Geometry's layer element, its header written; the caller writes its
 * arrays and ends it. */
static void layer_element(writer *w, const char *type, const char *name, const char *mapping,
                          const char *reference) {
  begin(w, type);
  p_int(w, 0);
  kv_int(w, "Version", 101);
  kv_str(w, "Name", name);
  kv_str(w, "MappingInformationType", mapping);
  kv_str(w, "ReferenceInformationType", reference);
}

static void geometry(writer *w, const bbc_mesh *m, const char *name, int64_t id) {
  size_t nt = m->triangle_count, nc = 3 * nt;
  begin(w, "Geometry");
  p_long(w, id);
  p_name(w, name, "Geometry");
  p_str(w, "Mesh");
  kv_doubles(w, "Vertices", m->positions, 3 * m->vertex_count);
  int32_t *pvi = malloc((nc ? nc : 1) * sizeof *pvi);
  double *nrm = malloc((nc ? nc : 1) * 3 * sizeof *nrm);
  double *uv = m->uvs ? malloc((m->vertex_count ? m->vertex_count : 1) * 2 * sizeof *uv) : NULL;
  int32_t *mat = malloc((nt ? nt : 1) * sizeof *mat);
  if (!pvi || !nrm || (m->uvs && !uv) || !mat) {
    w->b.oom = 1;
  } else {
    for (size_t c = 0; c < nc; c++) {
      int32_t v = (int32_t)m->indices[c];
      pvi[c] = c % 3 == 2 ? ~v : v; /* the last corner of a polygon: -(index + 1) */
      for (int k = 0; k < 3; k++)
        nrm[3 * c + k] = m->normals ? m->normals[3 * (size_t)m->indices[c] + k] : (k == 2);
    }
    for (size_t v = 0; uv && v < 2 * m->vertex_count; v++) uv[v] = m->uvs[v];
    for (size_t t = 0; t < nt; t++) mat[t] = (int32_t)m->face_material[t];
    kv_ints(w, "PolygonVertexIndex", pvi, nc);
    kv_int(w, "GeometryVersion", 124);
    layer_element(w, "LayerElementNormal", "", "ByPolygonVertex", "Direct");
    kv_doubles(w, "Normals", nrm, 3 * nc);
    end(w);
    if (uv) {
      layer_element(w, "LayerElementUV", "UVMap", "ByPolygonVertex", "IndexToDirect");
      kv_doubles(w, "UV", uv, 2 * m->vertex_count);
      for (size_t c = 0; c < nc; c++) pvi[c] = (int32_t)m->indices[c];
      kv_ints(w, "UVIndex", pvi, nc);
      end(w);
    }
    layer_element(w, "LayerElementMaterial", "", "ByPolygon", "IndexToDirect");
    kv_ints(w, "Materials", mat, nt);
    end(w);
    begin(w, "Layer");
    p_int(w, 0);
    kv_int(w, "Version", 100);
    const char *types[3] = {"LayerElementNormal", "LayerElementMaterial", "LayerElementUV"};
    for (int k = 0; k < (uv ? 3 : 2); k++) {
      begin(w, "LayerElement");
      kv_str(w, "Type", types[k]);
      kv_int(w, "TypedIndex", 0);
      end(w);
    }
    end(w);
  }
  free(pvi);
  free(nrm);
  free(uv);
  free(mat);
  end(w);
}

static void model(writer *w, const char *name, int64_t id) {
  begin(w, "Model");
  p_long(w, id);
  p_name(w, name, "Model");
  p_str(w, "Mesh");
  kv_int(w, "Version", 232);
  begin(w, "Properties70");
  P_vec(w, "Lcl Translation", "Lcl Translation", 0, 0, 0);
  P_vec(w, "Lcl Rotation", "Lcl Rotation", 0, 0, 0);
  P_vec(w, "Lcl Scaling", "Lcl Scaling", 1, 1, 1);
  P_int(w, "DefaultAttributeIndex", 0);
  end(w);
  begin(w, "Shading");
  p_bool(w, 1);
  end(w);
  kv_str(w, "Culling", "CullingOff");
  end(w);
}

/* Phong, as FBX materials are: the diffuse colour, no specular colour
 * beyond a dielectric's (SpecularFactor 0.25: Blender's importer makes it
 * Principled's 0.5, F0 = 0.04) and a shininess whose match in Blender's
 * importer, roughness = 1 - sqrt(Shininess) / 10, is the material's. */
static void material(writer *w, const bbc_material *mat, const char *name, int64_t id) {
  begin(w, "Material");
  p_long(w, id);
  p_name(w, name, "Material");
  p_str(w, "");
  kv_int(w, "Version", 102);
  kv_str(w, "ShadingModel", mat->unlit ? "lambert" : "phong");
  kv_int(w, "MultiLayer", 0);
  begin(w, "Properties70");
  const float *c = mat->base_color;
  P_color(w, "DiffuseColor", c[0], c[1], c[2]);
  P_number(w, "DiffuseFactor", 1.0);
  P_color(w, "AmbientColor", 0, 0, 0);
  P_color(w, "EmissiveColor", 0, 0, 0);
  P_color(w, "SpecularColor", 1, 1, 1);
  P_number(w, "SpecularFactor", mat->unlit ? 0.0 : 0.25);
  double r = mat->roughness > 0 && mat->roughness <= 1 ? mat->roughness : 1.0;
  double sh = 100.0 * (1.0 - r) * (1.0 - r);
  P_number(w, "Shininess", sh);
  P_number(w, "ShininessExponent", sh);
  P_number(w, "Opacity", c[3]);
  P_number(w, "TransparencyFactor", 1.0 - c[3]);
  end(w);
  end(w);
}

static void texture(writer *w, const tex_file *tf) {
  char stem[600];
  snprintf(stem, sizeof stem, "%s", tf->name);
  char *dot = strrchr(stem, '.');
  if (dot) *dot = 0;
  begin(w, "Video");
  p_long(w, tf->video_id);
  p_name(w, stem, "Video");
  p_str(w, "Clip");
  kv_str(w, "Type", "Clip");
  begin(w, "Properties70");
  P_kstring(w, "Path", "XRefUrl", tf->name);
  end(w);
  kv_int(w, "UseMipMap", 0);
  kv_str(w, "Filename", tf->name);
  kv_str(w, "RelativeFilename", tf->name);
  end(w);
  begin(w, "Texture");
  p_long(w, tf->tex_id);
  p_name(w, stem, "Texture");
  p_str(w, "");
  kv_str(w, "Type", "TextureVideoClip");
  kv_int(w, "Version", 202);
  begin(w, "TextureName");
  p_name(w, stem, "Texture");
  end(w);
  begin(w, "Media");
  p_name(w, stem, "Video");
  end(w);
  kv_str(w, "FileName", tf->name);
  kv_str(w, "RelativeFilename", tf->name);
  kv_str(w, "Texture_Alpha_Source", "None");
  end(w);
}

static void connect(writer *w, const char *kind, int64_t child, int64_t parent, const char *prop) {
  begin(w, "C");
  p_str(w, kind);
  p_long(w, child);
  p_long(w, parent);
  if (prop) p_str(w, prop);
  end(w);
}

/* Ids: node k's model ID_BASE + 100000 k, its geometry + 1, its material j
 * + 2 + j; texture files ID_BASE + 90000000 + 2 i (video + 1). */
static int64_t model_id(size_t k) {
  return ID_BASE + 100000 * (int64_t)k;
}

static void objects(writer *w, const doc *d) {
  begin(w, "Objects");
  for (size_t k = 0; k < d->count; k++) {
    const bbc_mesh *m = d->nodes[k].mesh;
    const char *name = d->nodes[k].name ? d->nodes[k].name : "";
    geometry(w, m, name, model_id(k) + 1);
    model(w, name, model_id(k));
    for (size_t j = 0; j < m->material_count; j++)
      material(w, &m->materials[j], m->materials[j].name, model_id(k) + 2 + (int64_t)j);
  }
  for (size_t i = 0; i < d->tex_count; i++)
    if (!d->tex[i].dup) texture(w, &d->tex[i]);
  end(w);
}

static void connections(writer *w, const doc *d) {
  begin(w, "Connections");
  for (size_t k = 0; k < d->count; k++) {
    const bbc_mesh *m = d->nodes[k].mesh;
    connect(w, "OO", model_id(k), 0, NULL);
    connect(w, "OO", model_id(k) + 1, model_id(k), NULL);
    for (size_t j = 0; j < m->material_count; j++) {
      int64_t mid = model_id(k) + 2 + (int64_t)j;
      connect(w, "OO", mid, model_id(k), NULL);
      int ti = tex_index(d, m, m->materials[j].texture);
      if (ti >= 0) connect(w, "OP", d->tex[ti].tex_id, mid, "DiffuseColor");
      int ni = m->materials[j].normal_map > 0 && m->tangents
                   ? tex_index(d, m, m->materials[j].normal_map - 1)
                   : -1;
      if (ni >= 0) connect(w, "OP", d->tex[ni].tex_id, mid, "NormalMap");
    }
  }
  for (size_t i = 0; i < d->tex_count; i++)
    if (!d->tex[i].dup) connect(w, "OO", d->tex[i].video_id, d->tex[i].tex_id, NULL);
  end(w);
}

/* The textures the materials use (colour and normal maps; FBX's Phong has
 * no occlusion slot), identical images once, named by
 * bbc_texture_file_name's rule: <stem>_<name>.png. */
static bbc_result collect_textures(doc *d, const char *stem, bbc_error *err) {
  size_t max = 0;
  for (size_t k = 0; k < d->count; k++) max += d->nodes[k].mesh->texture_count;
  d->tex = calloc(max ? max : 1, sizeof *d->tex);
  if (!d->tex) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "FBX: out of memory");
  for (size_t k = 0; k < d->count; k++) {
    const bbc_mesh *m = d->nodes[k].mesh;
    for (size_t j = 0; j < m->material_count; j++) {
      int ts[2] = {m->materials[j].texture,
                   m->materials[j].normal_map > 0 ? m->materials[j].normal_map - 1 : -1};
      for (int q = 0; q < 2; q++) {
        int t = ts[q];
        if (t < 0 || (size_t)t >= m->texture_count || !m->textures[t].image.rgba) continue;
        const bbc_image *img = &m->textures[t].image;
        int seen = 0;
        for (size_t i = 0; i < d->tex_count && !seen; i++)
          if (d->tex[i].image == img) seen = 1;
        if (seen) continue;
        tex_file *tf = &d->tex[d->tex_count];
        tf->image = img;
        /* the same pixels as an earlier file: that file */
        for (size_t i = 0; i < d->tex_count; i++)
          if (same_image(d->tex[i].image, img)) {
            memcpy(tf->name, d->tex[i].name, sizeof tf->name);
            tf->tex_id = d->tex[i].tex_id;
            tf->video_id = d->tex[i].video_id;
            tf->dup = 1;
            break;
          }
        if (!tf->name[0]) {
          char safe[160];
          bbc_texture_file_name(m, (size_t)t, safe, sizeof safe);
          snprintf(tf->name, sizeof tf->name, "%s_%s.png", stem, safe);
          /* two levels' different images of one name: numbered */
          for (size_t i = 0; i < d->tex_count; i++)
            if (!strcmp(d->tex[i].name, tf->name)) {
              snprintf(tf->name, sizeof tf->name, "%s_%s_%zu.png", stem, safe, d->tex_count);
              break;
            }
          tf->tex_id = ID_BASE + 90000000 + 2 * (int64_t)d->tex_count;
          tf->video_id = tf->tex_id + 1;
        }
        d->tex_count++;
      }
    }
  }
  return BBC_OK;
}

/* The footer Blender's and the SDK's writers end a file with (readers skip
 * it): an id, padding to 16 bytes, the version, 120 zeros, a magic. */
static void footer(fbuf *b) {
  static const uint8_t id[16] = {0xfa, 0xbc, 0xab, 0x09, 0xd0, 0xc8, 0xd4, 0x66,
                                 0xb1, 0x76, 0xfb, 0x83, 0x1c, 0xf7, 0x26, 0x7e};
  static const uint8_t magic[16] = {0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5, 0xd9, 0x7e,
                                    0xec, 0xe9, 0x0c, 0xe3, 0x75, 0x8f, 0x29, 0x0b};
  static const uint8_t zero[128] = {0};
  put(b, id, sizeof id);
  put(b, zero, 4);
  size_t pad = ((b->size + 15) & ~(size_t)15) - b->size;
  put(b, zero, pad ? pad : 16);
  put_u32(b, 7400);
  put(b, zero, 120);
  put(b, magic, sizeof magic);
}

bbc_result bbc_scene_write_fbx(const char *path, const bbc_fbx_node *nodes, size_t node_count,
                               bbc_error *err) {
  assert(path && (nodes || !node_count));
  size_t len = strlen(path);
  if (len < 5 || strcasecmp(path + len - 4, ".fbx"))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: FBX output must end in .fbx", path);
  if (!node_count) return bbc__fail(err, BBC_ERROR_EMPTY, "%s: nothing to write", path);
  for (size_t k = 0; k < node_count; k++) {
    const bbc_mesh *m = nodes[k].mesh;
    if (!m || m->kind != BBC_MESH_TRIANGLES || !m->triangle_count)
      return bbc__fail(err, BBC_ERROR_EMPTY, "%s: mesh %zu has no triangles", path, k);
    if (m->vertex_count > INT32_MAX || 3 * m->triangle_count > INT32_MAX)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: mesh %zu too large for FBX", path, k);
  }
  char dir[2048], stem[300];
  bbc__path_folder(path, dir, sizeof dir);
  bbc__side_file_stem(path, 1, stem, sizeof stem);
  doc d = {nodes, node_count, NULL, 0, 0};
  bbc_result r = collect_textures(&d, stem, err);
  if (r != BBC_OK) return r;

  writer w;
  memset(&w, 0, sizeof w);
  static const char magic[23] = "Kaydara FBX Binary  \0\x1a";
  put(&w.b, magic, sizeof magic);
  put_u32(&w.b, 7400);
  header_extension(&w);
  global_settings(&w);
  objects(&w, &d);
  connections(&w, &d);
  static const uint8_t zero[13] = {0};
  put(&w.b, zero, sizeof zero);
  footer(&w.b);
  if (w.b.oom || w.bad || w.depth) {
    free(w.b.data);
    free(d.tex);
    return w.b.oom ? bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path)
                   : bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: too large for FBX 7.4", path);
  }
  /* The textures first, then the FBX; whatever was written goes again on a
   * failure. */
  size_t n_written = 0;
  char(*written)[2700] = calloc(d.tex_count + 1, sizeof *written);
  if (!written) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  for (size_t i = 0; r == BBC_OK && i < d.tex_count; i++) {
    if (d.tex[i].dup) continue;
    snprintf(written[n_written], sizeof written[0], "%s%s", dir, d.tex[i].name);
    r = bbc_image_write_png(written[n_written], d.tex[i].image, err);
    if (r == BBC_OK) n_written++;
  }
  if (r == BBC_OK) r = bbc_write_file_atomic(path, w.b.data, w.b.size, err);
  if (r != BBC_OK)
    for (size_t i = 0; i < n_written; i++) remove(written[i]);
  free(written);
  free(w.b.data);
  free(d.tex);
  return r;
}
