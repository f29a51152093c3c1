/* fuzz_scene.c — libFuzzer harness for our code after Assimp, without
 * Assimp's parsers: the bytes describe a scene as Assimp hands it over
 * (pointers and array sizes as Assimp guarantees them; every value — counts,
 * indices, coordinates, names, material properties, embedded textures, node
 * tree, transforms — taken from the input), and bbc__load_assimp_scene turns
 * it into our mesh as bbc_mesh_load does after Assimp: materials, texture
 * lookup (embedded images decoded from memory), groups, LOD nodes,
 * triangles, finishing. Crashes inside Assimp's importers are Assimp's
 * business (fuzz_obj, fuzz_3ds, fuzz_glb feed real files through it); this
 * one finds ours. */
#include <assimp/material.h>
#include <assimp/scene.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#include "io.h"

typedef struct reader {
  const uint8_t *p;
  size_t n, i;
} reader;

static uint8_t u8(reader *r) {
  return r->i < r->n ? r->p[r->i++] : 0;
}
static uint32_t u16(reader *r) {
  uint32_t a = u8(r);
  return a | (uint32_t)u8(r) << 8;
}
static uint32_t u32(reader *r) {
  uint32_t a = u16(r);
  return a | u16(r) << 16;
}
/* Small integers as often as raw floats (NaN, Inf, huge) */
static float f32(reader *r) {
  uint8_t k = u8(r);
  if (k < 160) return (float)((int)u8(r) - 128) / 8.0f;
  uint32_t b = u32(r);
  float f;
  memcpy(&f, &b, sizeof f);
  return f;
}
static void str(reader *r, struct aiString *s) {
  size_t len = u8(r);
  if (len > r->n - r->i) len = r->n - r->i;
  memcpy(s->data, r->p + r->i, len);
  s->data[len] = 0;
  s->length = (ai_uint32)len;
  r->i += len;
}

/* ---- materials: properties laid out as Assimp stores them -------------- */

static void add_prop(struct aiMaterial *m, const char *key, unsigned semantic,
                     enum aiPropertyTypeInfo type, const void *data, unsigned length) {
  if (m->mNumProperties == m->mNumAllocated) return;
  struct aiMaterialProperty *p = calloc(1, sizeof *p);
  if (!p) return;
  p->mKey.length = (ai_uint32)strlen(key);
  memcpy(p->mKey.data, key, p->mKey.length + 1);
  p->mSemantic = semantic;
  p->mType = type;
  p->mDataLength = length;
  p->mData = malloc(length ? length : 1);
  if (!p->mData) {
    free(p);
    return;
  }
  memcpy(p->mData, data, length);
  m->mProperties[m->mNumProperties++] = p;
}
/* A string property: its length (4 bytes), the characters, a NUL. */
static void add_string(struct aiMaterial *m, const char *key, unsigned semantic,
                       const struct aiString *s) {
  char buf[4 + MAXLEN];
  uint32_t len = s->length;
  memcpy(buf, &len, 4);
  memcpy(buf + 4, s->data, len + 1);
  add_prop(m, key, semantic, aiPTI_String, buf, 4 + len + 1);
}
static void add_floats(struct aiMaterial *m, const char *key, reader *r, unsigned count) {
  float v[4];
  for (unsigned k = 0; k < count; k++) v[k] = f32(r);
  add_prop(m, key, 0, aiPTI_Float, v, count * sizeof(float));
}
static void add_int(struct aiMaterial *m, const char *key, int v) {
  add_prop(m, key, 0, aiPTI_Integer, &v, sizeof v);
}

static struct aiMaterial *make_material(reader *r, unsigned textures) {
  struct aiMaterial *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->mNumAllocated = 16;
  m->mProperties = calloc(m->mNumAllocated, sizeof *m->mProperties);
  if (!m->mProperties) {
    free(m);
    return NULL;
  }
  uint8_t has = u8(r);
  struct aiString s;
  if (has & 1) {
    str(r, &s);
    add_string(m, "?mat.name", 0, &s);
  }
  if (has & 2) add_floats(m, "$clr.diffuse", r, 3 + (u8(r) & 1));
  if (has & 4) add_floats(m, "$clr.base", r, 4);
  if (has & 8) add_floats(m, "$clr.ambient", r, 3);
  if (has & 16) add_floats(m, "$mat.opacity", r, 1);
  if (has & 32) add_int(m, "$mat.twosided", (int)u8(r) - 1);
  if (has & 64) add_int(m, "$mat.shadingm", u8(r) % 12);
  if (has & 128) { /* a texture: embedded ("*N", N maybe past the last) or a file name */
    uint8_t k = u8(r);
    if (k & 1) {
      s.length =
          (ai_uint32)snprintf(s.data, sizeof s.data, "*%u", (unsigned)u8(r) % (textures + 2));
    } else {
      str(r, &s);
    }
    add_string(m, "$tex.file", (k & 2) ? aiTextureType_BASE_COLOR : aiTextureType_DIFFUSE, &s);
  }
  return m;
}

/* ---- embedded textures: compressed bytes (our image decoders) or texels */

static struct aiTexture *make_texture(reader *r) {
  struct aiTexture *t = calloc(1, sizeof *t);
  if (!t) return NULL;
  str(r, &t->mFilename);
  if (u8(r) & 1) {
    size_t len = u16(r) % 4096;
    if (len > r->n - r->i) len = r->n - r->i;
    t->mWidth = (unsigned)len;
    t->mHeight = 0;
    t->pcData = malloc(len ? len : 1);
    if (t->pcData) memcpy(t->pcData, r->p + r->i, len);
    r->i += len;
  } else {
    t->mWidth = 1 + u8(r) % 16;
    t->mHeight = 1 + u8(r) % 16;
    t->pcData = calloc((size_t)t->mWidth * t->mHeight, sizeof *t->pcData);
    for (size_t k = 0; t->pcData && k < (size_t)t->mWidth * t->mHeight; k++) {
      t->pcData[k].b = u8(r);
      t->pcData[k].g = u8(r);
      t->pcData[k].r = u8(r);
      t->pcData[k].a = u8(r);
    }
  }
  if (!t->pcData) {
    free(t);
    return NULL;
  }
  return t;
}

/* ---- meshes --------------------------------------------------------------- */

static struct aiMesh *make_mesh(reader *r, unsigned materials) {
  struct aiMesh *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->mPrimitiveTypes = u8(r) & 0xF;
  m->mNumVertices = u16(r) % 200;
  m->mNumFaces = u16(r) % 200;
  m->mMaterialIndex = u8(r) % (materials + 2);
  str(r, &m->mName);
  uint8_t has = u8(r);
  m->mVertices = calloc(m->mNumVertices + 1, sizeof *m->mVertices);
  if (has & 1) m->mNormals = calloc(m->mNumVertices + 1, sizeof *m->mNormals);
  if (has & 2) {
    m->mTextureCoords[0] = calloc(m->mNumVertices + 1, sizeof *m->mTextureCoords[0]);
    m->mNumUVComponents[0] = 2;
  }
  m->mFaces = calloc(m->mNumFaces + 1, sizeof *m->mFaces);
  if (!m->mVertices || !m->mFaces) return m; /* freed by the caller */
  for (unsigned v = 0; v < m->mNumVertices; v++) {
    m->mVertices[v].x = f32(r);
    m->mVertices[v].y = f32(r);
    m->mVertices[v].z = f32(r);
    if (m->mNormals) {
      m->mNormals[v].x = f32(r);
      m->mNormals[v].y = f32(r);
      m->mNormals[v].z = f32(r);
    }
    if (m->mTextureCoords[0]) {
      m->mTextureCoords[0][v].x = f32(r);
      m->mTextureCoords[0][v].y = f32(r);
    }
  }
  for (unsigned f = 0; f < m->mNumFaces; f++) {
    struct aiFace *face = &m->mFaces[f];
    face->mNumIndices = 1 + u8(r) % 4;
    face->mIndices = calloc(face->mNumIndices, sizeof *face->mIndices);
    if (!face->mIndices) {
      face->mNumIndices = 0;
      continue;
    }
    for (unsigned k = 0; k < face->mNumIndices; k++)
      face->mIndices[k] = u8(r) % 8 == 7 ? u32(r) : u16(r) % (m->mNumVertices + 1);
  }
  return m;
}

static void free_mesh(struct aiMesh *m) {
  if (!m) return;
  for (unsigned f = 0; m->mFaces && f < m->mNumFaces; f++) free(m->mFaces[f].mIndices);
  free(m->mFaces);
  free(m->mVertices);
  free(m->mNormals);
  free(m->mTextureCoords[0]);
  free(m);
}

/* ---- the node tree ---------------------------------------------------------- */

static struct aiNode *make_node(reader *r, struct aiNode *parent, unsigned meshes, int depth,
                                int *budget) {
  struct aiNode *n = calloc(1, sizeof *n);
  if (!n) return NULL;
  n->mParent = parent;
  --*budget;
  uint8_t k = u8(r);
  str(r, &n->mName);
  if ((k & 3) == 1 && n->mName.length + 5 < MAXLEN) { /* the engine convention */
    n->mName.length += (ai_uint32)snprintf(n->mName.data + n->mName.length, 8, "_LOD%u", u8(r) % 3);
  }
  float *t = &n->mTransformation.a1;
  for (int i = 0; i < 16; i++) t[i] = i % 5 == 0 ? 1.0f : 0.0f;
  if (k & 4)
    for (int i = 0; i < 12; i++) t[i] = f32(r); /* the rows that move points */
  n->mNumMeshes = u8(r) % 4;
  n->mMeshes = calloc(n->mNumMeshes + 1, sizeof *n->mMeshes);
  if (!n->mMeshes) n->mNumMeshes = 0;
  for (unsigned i = 0; i < n->mNumMeshes; i++)
    n->mMeshes[i] = u8(r) % 16 == 15 ? u32(r) : u8(r) % (meshes + 1);
  unsigned children = depth < 6 && *budget > 0 ? u8(r) % 4 : 0;
  n->mChildren = calloc(children + 1, sizeof *n->mChildren);
  for (unsigned c = 0; n->mChildren && c<children && * budget> 0; c++) {
    struct aiNode *ch = make_node(r, n, meshes, depth + 1, budget);
    if (ch) n->mChildren[n->mNumChildren++] = ch;
  }
  return n;
}

static void free_node(struct aiNode *n) {
  if (!n) return;
  for (unsigned c = 0; c < n->mNumChildren; c++) free_node(n->mChildren[c]);
  free(n->mChildren);
  free(n->mMeshes);
  free(n);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  reader r = {data, size, 0};
  uint8_t head = u8(&r);
  struct aiScene sc;
  memset(&sc, 0, sizeof sc);
  unsigned nmat = u8(&r) % 5, ntex = u8(&r) % 3, nmesh = u8(&r) % 5;
  sc.mMaterials = calloc(nmat + 1, sizeof *sc.mMaterials);
  sc.mTextures = calloc(ntex + 1, sizeof *sc.mTextures);
  sc.mMeshes = calloc(nmesh + 1, sizeof *sc.mMeshes);
  int ok = sc.mMaterials && sc.mTextures && sc.mMeshes;
  for (unsigned i = 0; ok && i < ntex; i++)
    if ((sc.mTextures[sc.mNumTextures] = make_texture(&r))) sc.mNumTextures++;
  for (unsigned i = 0; ok && i < nmat; i++)
    if ((sc.mMaterials[sc.mNumMaterials] = make_material(&r, sc.mNumTextures))) sc.mNumMaterials++;
  for (unsigned i = 0; ok && i < nmesh; i++) {
    struct aiMesh *m = make_mesh(&r, sc.mNumMaterials);
    if (m && m->mVertices && m->mFaces)
      sc.mMeshes[sc.mNumMeshes++] = m;
    else
      free_mesh(m);
  }
  int budget = 40;
  if (ok && !(head & 1)) sc.mRootNode = make_node(&r, NULL, sc.mNumMeshes, 0, &budget);

  bbc_load_options o;
  bbc_load_options_default(&o);
  o.lod_node = (head >> 1) % 3;        /* 0: all; k: the nodes *_LOD<k-1> */
  o.flat_normals = !((head >> 3) & 1); /* as --normals */
  o.skip_textures = 0;                 /* embedded ones: from memory */
  const char *name = (head & 16) ? "/nonexistent-fuzz/scene.glb" : "/nonexistent-fuzz/scene.obj";
  bbc_mesh mesh;
  bbc_error err;
  if (ok && bbc__load_assimp_scene(name, &sc, &o, &mesh, &err) == BBC_OK) {
    /* what the steps rely on */
    if (!mesh.triangle_count || !(mesh.radius >= 0) || !isfinite(mesh.radius)) __builtin_trap();
    for (size_t t = 0; t < 3 * mesh.triangle_count; t++)
      if (mesh.indices[t] >= mesh.vertex_count) __builtin_trap();
    for (size_t t = 0; t < mesh.triangle_count; t++)
      if (mesh.face_material[t] >= mesh.material_count) __builtin_trap();
    for (size_t i = 0; i < mesh.material_count; i++)
      if (mesh.materials[i].texture >= (int)mesh.texture_count) __builtin_trap();
    bbc_mesh_free(&mesh);
  }
  free_node(sc.mRootNode);
  for (unsigned i = 0; i < sc.mNumMeshes; i++) free_mesh(sc.mMeshes[i]);
  for (unsigned i = 0; i < sc.mNumMaterials; i++) bbc__scene_material_free(sc.mMaterials[i]);
  for (unsigned i = 0; i < sc.mNumTextures; i++) {
    free(sc.mTextures[i]->pcData);
    free(sc.mTextures[i]);
  }
  free(sc.mMeshes);
  free(sc.mMaterials);
  free(sc.mTextures);
  return 0;
}
