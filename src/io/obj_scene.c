/* obj_scene.c — the scene Assimp's OBJ importer and its Triangulate and
 * SortByPType steps would hand over, built from our reader's model
 * (obj_reader.h; load_obj.c says why and how it is checked). */
#include "obj_reader.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

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
  if (m->mFaces && m->mNumFaces) free(m->mFaces[0].mIndices); /* one block for all */
  free(m->mFaces);
  free(m);
}

/* Corner c's vertex data into vertex o of m: position, normal and texture
 * coordinates as createVertexArray copies them (an index past the end
 * drops the mesh's normals or texture coordinates, *n_ok / *t_ok). 0 for a
 * vertex index out of range (Assimp's error). */
static int put_corner(const obj_reader *R, const int32_t *c, struct aiMesh *m, size_t o, int *n_ok,
                      int *t_ok) {
  if (c[0] < 0 || (size_t)c[0] >= R->v.n) return 0;
  memcpy(&m->mVertices[o], (const float *)R->v.p + 3 * (size_t)c[0], 3 * sizeof(float));
  if (m->mNormals && *n_ok) {
    if (c[2] >= 0 && (size_t)c[2] < R->vn.n)
      memcpy(&m->mNormals[o], (const float *)R->vn.p + 3 * (size_t)c[2], 3 * sizeof(float));
    else if (c[2] != -1)
      *n_ok = 0;
  }
  if (m->mTextureCoords[0] && *t_ok) {
    if (c[1] >= 0 && (size_t)c[1] < R->vt.n)
      memcpy(&m->mTextureCoords[0][o], (const float *)R->vt.p + 3 * (size_t)c[1],
             3 * sizeof(float));
    else if (c[1] != -1)
      *t_ok = 0;
  }
  return 1;
}

/* The triangles of face f (corners c, 3 or 4): their corners' indices
 * into c, as Triangulate cuts a quad. Returns the triangle count. */
static int face_triangles(const obj_reader *R, const int32_t *c, int nc, int tri[2][3]) {
  tri[0][0] = 0, tri[0][1] = 1, tri[0][2] = 2;
  if (nc == 3) return 1;
  struct aiVector3D q[4];
  for (int k = 0; k < 4; k++)
    memcpy(&q[k], (const float *)R->v.p + 3 * (size_t)c[3 * k], 3 * sizeof(float));
  int s = quad_start(q);
  for (int h = 0; h < 2; h++) {
    tri[h][0] = s;
    tri[h][1] = (s + 1 + h) % 4;
    tri[h][2] = (s + 2 + h) % 4;
  }
  return 2;
}

/* Mesh mi's triangles as Assimp's createTopology, createVertexArray and
 * Triangulate make them: a vertex a corner; normals when the file has some
 * and a face of the mesh refers to them, texture coordinates likewise;
 * quads in two. A mesh with lines too is then split by SortByPType, which
 * copies a vertex per triangle corner (`split`). `faces` lists the mesh's
 * faces in file order (lines skipped here), `first` each face's first
 * corner. NULL with R->defer for indices out of range (Assimp's error),
 * or with nothing to deferred and no triangles (*none). */
static struct aiMesh *make_mesh(obj_reader *R, int mi, const uint32_t *faces, size_t nf,
                                const size_t *first, int *none) {
  const obj_mesh *om = (const obj_mesh *)R->meshes.p + mi;
  const uint8_t *fcn = R->face_corners.p, *fl = R->face_line.p;
  const int32_t *cr = R->corners.p;
  int split = om->segments > 0;
  size_t nv = 0, nt = 0;
  for (size_t i = 0; i < nf; i++) {
    if (fl[faces[i]]) {
      for (int k = 0; k < fcn[faces[i]]; k++) { /* Assimp checks lines' vertices too */
        int32_t v = cr[3 * (first[faces[i]] + (size_t)k)];
        if (v < 0 || (size_t)v >= R->v.n) {
          R->defer = 1;
          return NULL;
        }
      }
      continue;
    }
    size_t t = fcn[faces[i]] == 4 ? 2 : 1;
    nt += t;
    nv += split ? 3 * t : fcn[faces[i]];
  }
  *none = nt == 0;
  if (!nt) return NULL;
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
  m->mFaces = calloc(nt, sizeof *m->mFaces);
  unsigned *ix = malloc(3 * nt * sizeof *ix);
  if (!m->mVertices || (normals && !m->mNormals) || (uvs && !m->mTextureCoords[0]) || !m->mFaces ||
      !ix) {
    free(ix);
    free_mesh(m);
    return NULL;
  }
  m->mFaces[0].mIndices = ix;
  int n_ok = 1, t_ok = 1;
  size_t o = 0, t = 0;
  for (size_t i = 0; i < nf; i++) {
    size_t f = faces[i];
    if (fl[f]) continue;
    const int32_t *c = cr + 3 * first[f];
    int nc = fcn[f], tri[2][3];
    int ok = 1;
    if (!split)
      for (int k = 0; k < nc; k++) ok &= put_corner(R, c + 3 * k, m, o + (size_t)k, &n_ok, &t_ok);
    else
      for (int k = 0; k < nc; k++) /* the quad's cut reads the positions */
        ok &= c[3 * k] >= 0 && (size_t)c[3 * k] < R->v.n;
    if (!ok) {
      R->defer = 1;
      free_mesh(m);
      return NULL;
    }
    int ntri = face_triangles(R, c, nc, tri);
    for (int h = 0; h < ntri; h++, t++) {
      m->mFaces[t].mNumIndices = 3;
      m->mFaces[t].mIndices = ix + 3 * t;
      for (int k = 0; k < 3; k++) {
        if (split) { /* SortByPType: a vertex a triangle corner, in order */
          put_corner(R, c + 3 * tri[h][k], m, o, &n_ok, &t_ok);
          ix[3 * t + (size_t)k] = (unsigned)o++;
        } else {
          ix[3 * t + (size_t)k] = (unsigned)(o + (size_t)tri[h][k]);
        }
      }
    }
    if (!split) o += (size_t)nc;
  }
  if (!n_ok) {
    free(m->mNormals);
    m->mNormals = NULL;
  }
  if (!t_ok) {
    free(m->mTextureCoords[0]);
    m->mTextureCoords[0] = NULL;
  }
  return m;
}

/* A mesh's lines as SortByPType leaves them: a mesh of `segments` line
 * faces, which the conversion counts and skips (its vertices unread). */
static struct aiMesh *make_lines(const obj_mesh *om, size_t segments) {
  struct aiMesh *m = calloc(1, sizeof *m);
  if (!m) return NULL;
  m->mPrimitiveTypes = aiPrimitiveType_LINE;
  m->mNumVertices = (unsigned)(2 * segments);
  m->mNumFaces = (unsigned)segments;
  m->mMaterialIndex = om->material == NO_MATERIAL ? 0 : (unsigned)om->material;
  return m;
}

void bbc__obj_free_scene(struct aiScene *sc) {
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
struct aiScene *bbc__obj_make_scene(obj_reader *R) {
  size_t nf = R->face_mesh.n, nm = R->meshes.n;
  const uint32_t *fm = R->face_mesh.p;
  const uint8_t *fcn = R->face_corners.p;
  struct aiScene *sc = calloc(1, sizeof *sc);
  size_t *first = malloc((nf ? nf : 1) * sizeof *first);
  size_t *start = calloc(nm + 1, sizeof *start);
  uint32_t *order = malloc((nf ? nf : 1) * sizeof *order);
  if (sc) {
    sc->mRootNode = calloc(1, sizeof *sc->mRootNode);
    sc->mMeshes = calloc(nm ? 2 * nm : 1, sizeof *sc->mMeshes);
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
    node->mMeshes = malloc((ob->n ? 2 * ob->n : 1) * sizeof *node->mMeshes);
    if (!node->mMeshes) goto oom;
    for (size_t k = 0; k < ob->n; k++) {
      int mi = (int)ob->meshes[k];
      size_t count = start[mi + 1] - start[mi];
      if (!count) continue; /* Assimp leaves meshes without faces out */
      const obj_mesh *om = (const obj_mesh *)R->meshes.p + mi;
      if (om->segments) { /* SortByPType: the lines' mesh before the triangles' */
        struct aiMesh *l = make_lines(om, om->segments);
        if (!l) goto oom;
        node->mMeshes[node->mNumMeshes++] = sc->mNumMeshes;
        sc->mMeshes[sc->mNumMeshes++] = l;
      }
      int none = 0;
      struct aiMesh *m = make_mesh(R, mi, order + start[mi], count, first, &none);
      if (!m && none && !R->defer) continue; /* lines only */
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
  bbc__obj_free_scene(sc);
  return NULL;
}
