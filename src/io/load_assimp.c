/* load_assimp.c — polygon models through Assimp's C API into bbc_mesh.
 *
 * Node transforms are applied while walking the node tree, so the result is in
 * the file's world frame; each node contributes its meshes under the node's
 * name as the group (OBJ `o`/`g`, 3DS and AC3D objects, glTF nodes), which is
 * what separates trunk from foliage later (thesis 2.2.4). */
#include "io.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

typedef struct loader {
  const char *path;
  const struct aiScene *scene;
  const bbc_load_options *opt;
  bbc_mesh *mesh;
  size_t vertex_cap, triangle_cap, group_cap;
  int has_normals, has_uvs, has_tangents;
  size_t skipped_primitives; /* points and lines: not surfaces */
  int lod_found;             /* lod_node: a node of that level was met */
  bbc_error *err;
} loader;

/* ---- small matrix helpers (Assimp: row-major, column vectors) ----------- */

static void mat_mul(const struct aiMatrix4x4 *a, const struct aiMatrix4x4 *b,
                    struct aiMatrix4x4 *r) {
  const ai_real *x = &a->a1, *y = &b->a1;
  ai_real o[16];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      ai_real s = 0;
      for (int k = 0; k < 4; k++) s += x[4 * i + k] * y[4 * k + j];
      o[4 * i + j] = s;
    }
  memcpy(&r->a1, o, sizeof o);
}

/* ---- growing arrays ------------------------------------------------------ */

static int grow(void **p, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t n = *cap ? *cap : 1024;
  while (n < need) n *= 2;
  void *q = realloc(*p, n * elem);
  if (!q) return 0;
  *p = q;
  *cap = n;
  return 1;
}

static int reserve_vertices(loader *L, size_t need) {
  bbc_mesh *m = L->mesh;
  size_t c1 = L->vertex_cap, c2 = L->vertex_cap, c3 = L->vertex_cap, c4 = L->vertex_cap;
  if (!grow((void **)&m->positions, &c1, need, 3 * sizeof(double))) return 0;
  if (!grow((void **)&m->normals, &c2, need, 3 * sizeof(float))) return 0;
  if (!grow((void **)&m->uvs, &c3, need, 2 * sizeof(float))) return 0;
  if (!grow((void **)&m->tangents, &c4, need, 4 * sizeof(float))) return 0;
  L->vertex_cap = c1;
  return 1;
}

static int reserve_triangles(loader *L, size_t need) {
  bbc_mesh *m = L->mesh;
  size_t c1 = L->triangle_cap, c2 = L->triangle_cap, c3 = L->triangle_cap;
  if (!grow((void **)&m->indices, &c1, need, 3 * sizeof(uint32_t))) return 0;
  if (!grow((void **)&m->face_material, &c2, need, sizeof(uint32_t))) return 0;
  if (!grow((void **)&m->face_group, &c3, need, sizeof(uint32_t))) return 0;
  L->triangle_cap = c1;
  return 1;
}

/* Group index for a name, adding it when new. Returns UINT32_MAX on OOM. */
static uint32_t group_index(loader *L, const char *name) {
  bbc_mesh *m = L->mesh;
  for (size_t i = 0; i < m->group_count; i++)
    if (!strcmp(m->group_names[i], name)) return (uint32_t)i;
  if (!grow((void **)&m->group_names, &L->group_cap, m->group_count + 1, sizeof(char *)))
    return UINT32_MAX;
  char *s = bbc__strdup(name);
  if (!s) return UINT32_MAX;
  m->group_names[m->group_count] = s;
  return (uint32_t)m->group_count++;
}

/* ---- geometry ------------------------------------------------------------ */

/* Vertices equal in position, normal and first UV set are one (what
 * Assimp's JoinIdenticalVertices did, at a fraction of its time and
 * memory, which on large models run to seconds and hundreds of MB).
 * remap[v] is vertex v's new index; first[u] the first vertex of new index
 * u; new indices follow first use, as Assimp numbers them. Returns the
 * number of distinct vertices, 0 when out of memory. */
static float weld_key(float x) {
  return x + 0.0f; /* -0 as +0: equal values, equal bits */
}
static int weld_equal(const struct aiMesh *am, unsigned a, unsigned b) {
  const struct aiVector3D *p = am->mVertices;
  if (p[a].x != p[b].x || p[a].y != p[b].y || p[a].z != p[b].z) return 0;
  const struct aiVector3D *n = am->mNormals;
  if (n && (n[a].x != n[b].x || n[a].y != n[b].y || n[a].z != n[b].z)) return 0;
  const struct aiVector3D *t = am->mTextureCoords[0];
  if (t && (t[a].x != t[b].x || t[a].y != t[b].y)) return 0;
  return 1;
}
static uint64_t weld_hash(const struct aiMesh *am, unsigned v) {
  float f[8] = {weld_key(am->mVertices[v].x),
                weld_key(am->mVertices[v].y),
                weld_key(am->mVertices[v].z),
                0,
                0,
                0,
                0,
                0};
  if (am->mNormals) {
    f[3] = weld_key(am->mNormals[v].x);
    f[4] = weld_key(am->mNormals[v].y);
    f[5] = weld_key(am->mNormals[v].z);
  }
  if (am->mTextureCoords[0]) {
    f[6] = weld_key(am->mTextureCoords[0][v].x);
    f[7] = weld_key(am->mTextureCoords[0][v].y);
  }
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (int k = 0; k < 8; k++) {
    uint32_t b;
    memcpy(&b, &f[k], sizeof b);
    h = (h ^ b) * 0xff51afd7ed558ccdull;
    h ^= h >> 32;
  }
  return h;
}
static unsigned weld(const struct aiMesh *am, uint32_t *remap, uint32_t *first) {
  unsigned nv = am->mNumVertices;
  size_t cap = 16;
  while (cap < 2 * (size_t)nv) cap *= 2;
  uint32_t *slot = calloc(cap, sizeof *slot); /* vertex + 1; 0 = empty */
  if (!slot) return 0;
  unsigned unique = 0;
  for (unsigned v = 0; v < nv; v++) {
    size_t h = (size_t)weld_hash(am, v) & (cap - 1);
    for (;;) {
      uint32_t s = slot[h];
      if (!s) {
        slot[h] = v + 1;
        first[unique] = v;
        remap[v] = unique++;
        break;
      }
      if (weld_equal(am, s - 1, v)) {
        remap[v] = remap[s - 1];
        break;
      }
      h = (h + 1) & (cap - 1);
    }
  }
  free(slot);
  return unique;
}

/* Vertex v's tangent (glTF TANGENT, as Assimp reads it: the tangent and
 * the bitangent) moved by the linear part a[9] of the node's transform,
 * unit, its handedness from the bitangent against normal x tangent (n: the
 * moved normal); zero when the mesh has none. */
static void put_tangent(const struct aiMesh *am, unsigned v, const double a[9], int mirrored,
                        const float n[3], float out[4]) {
  memset(out, 0, 4 * sizeof *out);
  if (!am->mTangents || !am->mBitangents || !am->mNormals) return;
  const struct aiVector3D *t = &am->mTangents[v], *b = &am->mBitangents[v], *sn = &am->mNormals[v];
  double tt[3], l = 0;
  for (int k = 0; k < 3; k++) {
    tt[k] = a[3 * k] * t->x + a[3 * k + 1] * t->y + a[3 * k + 2] * t->z;
    l += tt[k] * tt[k];
  }
  if (!(l > 0) || !isfinite(l)) return;
  l = sqrt(l);
  for (int k = 0; k < 3; k++) out[k] = (float)(tt[k] / l);
  double c[3] = {sn->y * t->z - sn->z * t->y, sn->z * t->x - sn->x * t->z,
                 sn->x * t->y - sn->y * t->x};
  double hand = c[0] * b->x + c[1] * b->y + c[2] * b->z < 0 ? -1.0 : 1.0;
  out[3] = (float)(mirrored ? -hand : hand);
  (void)n;
}

static bbc_result add_mesh(loader *L, const struct aiMesh *am, const struct aiMatrix4x4 *M,
                           uint32_t group) {
  bbc_mesh *m = L->mesh;
  if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || am->mNumVertices == 0) {
    L->skipped_primitives += am->mNumFaces;
    return BBC_OK;
  }
  size_t base = m->vertex_count;
  uint32_t *remap = malloc(2 * (size_t)am->mNumVertices * sizeof *remap);
  unsigned nu = remap ? weld(am, remap, remap + am->mNumVertices) : 0;
  const uint32_t *first = remap ? remap + am->mNumVertices : NULL;
  if (!nu) {
    free(remap);
    return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
  }
  if (base + nu > UINT32_MAX) {
    free(remap);
    return bbc__fail(L->err, BBC_ERROR_INVALID_GEOMETRY, "%s: more than 4 billion vertices",
                     L->path);
  }
  if (!reserve_vertices(L, base + nu)) {
    free(remap);
    return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
  }

  /* Normals transform with the cofactor matrix (inverse transpose up to a
   * positive scale times the sign of the determinant). */
  double a[9] = {M->a1, M->a2, M->a3, M->b1, M->b2, M->b3, M->c1, M->c2, M->c3};
  double cof[9] = {a[4] * a[8] - a[5] * a[7], a[5] * a[6] - a[3] * a[8], a[3] * a[7] - a[4] * a[6],
                   a[2] * a[7] - a[1] * a[8], a[0] * a[8] - a[2] * a[6], a[1] * a[6] - a[0] * a[7],
                   a[1] * a[5] - a[2] * a[4], a[2] * a[3] - a[0] * a[5], a[0] * a[4] - a[1] * a[3]};
  double det = a[0] * cof[0] + a[1] * cof[1] + a[2] * cof[2];
  int mirrored = det < 0;

  for (unsigned u = 0; u < nu; u++) {
    unsigned v = first[u];
    const struct aiVector3D *p = &am->mVertices[v];
    double *q = m->positions + 3 * (base + u);
    q[0] = (double)M->a1 * p->x + (double)M->a2 * p->y + (double)M->a3 * p->z + M->a4;
    q[1] = (double)M->b1 * p->x + (double)M->b2 * p->y + (double)M->b3 * p->z + M->b4;
    q[2] = (double)M->c1 * p->x + (double)M->c2 * p->y + (double)M->c3 * p->z + M->c4;
    float *n = m->normals + 3 * (base + u);
    if (am->mNormals) {
      const struct aiVector3D *s = &am->mNormals[v];
      double sg = mirrored ? -1.0 : 1.0;
      for (int k = 0; k < 3; k++)
        n[k] = (float)(sg * (cof[3 * k] * s->x + cof[3 * k + 1] * s->y + cof[3 * k + 2] * s->z));
    } else {
      n[0] = n[1] = n[2] = 0.0f; /* filled by bbc_mesh_finalize */
    }
    put_tangent(am, v, a, mirrored, n, m->tangents + 4 * (base + u));
    float *uv = m->uvs + 2 * (base + u);
    if (am->mTextureCoords[0]) {
      uv[0] = am->mTextureCoords[0][v].x;
      uv[1] = am->mTextureCoords[0][v].y;
    } else {
      uv[0] = uv[1] = 0.0f;
    }
  }
  if (am->mNormals) L->has_normals = 1;
  if (am->mTextureCoords[0]) L->has_uvs = 1;
  if (am->mTangents && am->mBitangents && am->mNormals) L->has_tangents = 1;
  m->vertex_count = base + nu;

  if (!reserve_triangles(L, m->triangle_count + am->mNumFaces)) {
    free(remap);
    return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
  }
  for (unsigned f = 0; f < am->mNumFaces; f++) {
    const struct aiFace *face = &am->mFaces[f];
    if (face->mNumIndices != 3) {
      L->skipped_primitives++;
      continue;
    }
    uint32_t *ix = m->indices + 3 * m->triangle_count;
    for (int k = 0; k < 3; k++) {
      unsigned i = face->mIndices[k];
      if (i >= am->mNumVertices) {
        free(remap);
        return bbc__fail(L->err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: mesh '%s' face %u refers to vertex %u, but the mesh has %u", L->path,
                         am->mName.data, f, i, am->mNumVertices);
      }
      ix[k] = (uint32_t)(base + remap[i]);
    }
    if (mirrored) {
      uint32_t t = ix[1];
      ix[1] = ix[2];
      ix[2] = t;
    }
    m->face_material[m->triangle_count] = am->mMaterialIndex;
    m->face_group[m->triangle_count] = group;
    m->triangle_count++;
  }
  free(remap);
  return BBC_OK;
}

/* Whether a node's name ends with "_LOD<k>" (k = level). */
static int is_lod_node(const struct aiNode *node, int level) {
  char suffix[32];
  snprintf(suffix, sizeof suffix, "_LOD%d", level);
  size_t n = node->mName.length, m = strlen(suffix);
  return n >= m && !strcmp(node->mName.data + n - m, suffix);
}

static bbc_result walk(loader *L, const struct aiNode *node, const struct aiMatrix4x4 *parent,
                       int depth, int inside) {
  if (depth > 1000)
    return bbc__fail(L->err, BBC_ERROR_CORRUPT, "%s: node tree deeper than 1000 levels", L->path);
  struct aiMatrix4x4 M;
  mat_mul(parent, &node->mTransformation, &M);
  if (!inside && is_lod_node(node, L->opt->lod_node - 1)) {
    inside = 1;
    L->lod_found = 1;
  }
  for (unsigned i = 0; inside && i < node->mNumMeshes; i++) {
    unsigned mi = node->mMeshes[i];
    if (mi >= L->scene->mNumMeshes)
      return bbc__fail(L->err, BBC_ERROR_CORRUPT, "%s: node '%s' refers to missing mesh %u",
                       L->path, node->mName.data, mi);
    const struct aiMesh *am = L->scene->mMeshes[mi];
    if (am->mMaterialIndex >= L->scene->mNumMaterials)
      return bbc__fail(L->err, BBC_ERROR_CORRUPT, "%s: mesh '%s' refers to missing material %u",
                       L->path, am->mName.data, am->mMaterialIndex);
    /* The node's name is the object's name in OBJ, 3DS, AC3D and glTF; an
     * unnamed node falls back to its mesh's name. */
    const char *name = node->mName.length ? node->mName.data : am->mName.data;
    uint32_t g = group_index(L, name);
    if (g == UINT32_MAX)
      return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
    bbc_result r = add_mesh(L, am, &M, g);
    if (r != BBC_OK) return r;
  }
  for (unsigned c = 0; c < node->mNumChildren; c++) {
    bbc_result r = walk(L, node->mChildren[c], &M, depth + 1, inside);
    if (r != BBC_OK) return r;
  }
  return BBC_OK;
}

/* ---- materials and textures --------------------------------------------- */

/* Index of the texture with this key (resolved path or "*N"), adding it. */
static int find_texture(const bbc_mesh *m, const char *key) {
  for (size_t i = 0; i < m->texture_count; i++)
    if (m->textures[i].path && !strcmp(m->textures[i].path, key)) return (int)i;
  return -1;
}

static bbc_result add_texture(loader *L, const char *key, bbc_image *img, int *index) {
  bbc_mesh *m = L->mesh;
  bbc_texture *t = realloc(m->textures, (m->texture_count + 1) * sizeof *t);
  if (!t) return BBC_ERROR_OUT_OF_MEMORY;
  m->textures = t;
  t = &m->textures[m->texture_count];
  memset(t, 0, sizeof *t);
  t->path = bbc__strdup(key);
  if (!t->path) return BBC_ERROR_OUT_OF_MEMORY;
  t->image = *img;
  t->has_alpha = bbc_image_has_transparency(img);
  *index = (int)m->texture_count++;
  return BBC_OK;
}

/* Decodes an embedded texture: compressed (PNG/JPEG bytes, mHeight == 0) or
 * raw BGRA texels. */
static bbc_result decode_embedded(const struct aiTexture *tex, bbc_image *img) {
  if (tex->mHeight == 0) return bbc_image_load_memory(tex->pcData, tex->mWidth, img, NULL);
  if (tex->mWidth > INT_MAX || tex->mHeight > INT_MAX) return BBC_ERROR_CORRUPT;
  bbc_result r = bbc_image_alloc(img, (int)tex->mWidth, (int)tex->mHeight);
  if (r != BBC_OK) return r;
  size_t n = (size_t)tex->mWidth * tex->mHeight;
  for (size_t i = 0; i < n; i++) {
    img->rgba[4 * i + 0] = tex->pcData[i].r;
    img->rgba[4 * i + 1] = tex->pcData[i].g;
    img->rgba[4 * i + 2] = tex->pcData[i].b;
    img->rgba[4 * i + 3] = tex->pcData[i].a;
  }
  return BBC_OK;
}

static bbc_result load_material_texture(loader *L, bbc_material *mat, const char *ref) {
  bbc_mesh *m = L->mesh;
  const struct aiScene *sc = L->scene;
  mat->texture = -1;
  /* Embedded: "*N", or a file name that matches an embedded texture. */
  const struct aiTexture *emb = NULL;
  if (ref[0] == '*') {
    char *end;
    long i = strtol(ref + 1, &end, 10);
    if (*end == 0 && i >= 0 && (unsigned long)i < sc->mNumTextures) emb = sc->mTextures[i];
  } else {
    for (unsigned i = 0; i < sc->mNumTextures && !emb; i++)
      if (!strcmp(sc->mTextures[i]->mFilename.data, ref)) emb = sc->mTextures[i];
  }
  if (emb) {
    char key[64];
    snprintf(key, sizeof key, "*%ld", (long)(emb - sc->mTextures[0]));
    for (unsigned i = 0; i < sc->mNumTextures; i++)
      if (sc->mTextures[i] == emb) snprintf(key, sizeof key, "*%u", i);
    int found = find_texture(m, key);
    if (found >= 0) {
      mat->texture = found;
      return BBC_OK;
    }
    if (L->opt->skip_textures) return BBC_OK;
    bbc_image img;
    if (decode_embedded(emb, &img) != BBC_OK) {
      bbc__log(&L->opt->callbacks, BBC_LOG_WARNING,
               "%s: material '%s': embedded texture %s cannot be decoded; using the base colour",
               L->path, mat->name, key);
      return BBC_OK;
    }
    bbc_result r = add_texture(L, key, &img, &mat->texture);
    if (r != BBC_OK) bbc_image_free(&img);
    return r;
  }
  char resolved[2048];
  if (!bbc__texture_resolve(L->path, ref, BBC__TEXTURE_ASSIMP, resolved, sizeof resolved)) {
    bbc__log(&L->opt->callbacks, BBC_LOG_WARNING,
             "%s: material '%s': texture '%s' not found beside the model; using the base colour",
             L->path, mat->name, ref);
    return BBC_OK;
  }
  int found = find_texture(m, resolved);
  if (found >= 0) {
    mat->texture = found;
    return BBC_OK;
  }
  bbc_image img;
  memset(&img, 0, sizeof img);
  if (!L->opt->skip_textures) {
    bbc_error ierr;
    if (bbc_image_load(resolved, &img, &ierr) != BBC_OK) {
      bbc__log(&L->opt->callbacks, BBC_LOG_WARNING, "%s: material '%s': %s; using the base colour",
               L->path, mat->name, ierr.message);
      return BBC_OK;
    }
  }
  bbc_result r = add_texture(L, resolved, &img, &mat->texture);
  if (r != BBC_OK) bbc_image_free(&img);
  return r;
}

/* A material's normal map (glTF normalTexture) and occlusion map (glTF
 * occlusionTexture, which Assimp files as a light map), when the file
 * gives them: what a relightable cloud carries. */
static bbc_result load_lighting_maps(loader *L, const struct aiMaterial *am, bbc_material *mat) {
  static const enum aiTextureType kinds[2] = {aiTextureType_NORMALS, aiTextureType_LIGHTMAP};
  for (int i = 0; i < 2; i++) {
    struct aiString tex;
    if (aiGetMaterialTexture(am, kinds[i], 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) !=
            AI_SUCCESS ||
        !tex.length)
      continue;
    bbc_material tmp = *mat;
    bbc_result r = load_material_texture(L, &tmp, tex.data);
    if (r != BBC_OK) return r;
    if (tmp.texture < 0) continue;
    if (i == 0)
      mat->normal_map = tmp.texture + 1;
    else
      mat->occlusion_map = tmp.texture + 1;
  }
  return BBC_OK;
}

static bbc_result load_materials(loader *L) {
  const struct aiScene *sc = L->scene;
  bbc_mesh *m = L->mesh;
  unsigned n = sc->mNumMaterials ? sc->mNumMaterials : 1;
  m->materials = calloc(n, sizeof *m->materials);
  if (!m->materials)
    return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
  m->material_count = n;
  for (unsigned i = 0; i < n; i++) {
    bbc_material *mat = &m->materials[i];
    mat->texture = -1;
    mat->base_color[0] = mat->base_color[1] = mat->base_color[2] = 0.8f;
    mat->base_color[3] = 1.0f;
    if (i >= sc->mNumMaterials) {
      mat->name = bbc__strdup("");
      if (!mat->name)
        return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
      continue;
    }
    const struct aiMaterial *am = sc->mMaterials[i];
    struct aiString s;
    mat->name =
        bbc__strdup(aiGetMaterialString(am, AI_MATKEY_NAME, &s) == AI_SUCCESS ? s.data : "");
    if (!mat->name) return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
    struct aiColor4D c;
    char ext[16];
    bbc__path_extension(L->path, ext, sizeof ext);
    int gltf = !strcmp(ext, "glb") || !strcmp(ext, "gltf");
    if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
        aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS) {
      /* glTF's baseColorFactor is linear; base_color multiplies the
       * texture's stored (sRGB) values, as other formats' colours do. */
      mat->base_color[0] = gltf ? (float)bbc__linear_to_srgb(c.r) : c.r;
      mat->base_color[1] = gltf ? (float)bbc__linear_to_srgb(c.g) : c.g;
      mat->base_color[2] = gltf ? (float)bbc__linear_to_srgb(c.b) : c.b;
      mat->base_color[3] = c.a;
    }
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_AMBIENT, &c) == AI_SUCCESS) {
      mat->ambient[0] = c.r;
      mat->ambient[1] = c.g;
      mat->ambient[2] = c.b;
    }
    ai_real opacity;
    unsigned one = 1;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_OPACITY, &opacity, &one) == AI_SUCCESS &&
        opacity >= 0 && opacity < 1)
      mat->base_color[3] = opacity;
    /* glTF says whether a material is double-sided (a cloud's front and
     * back copies are not); other formats' flags mean other things. */
    int two = 1;
    unsigned one_int = 1;
    if (gltf && aiGetMaterialIntegerArray(am, AI_MATKEY_TWOSIDED, &two, &one_int) == AI_SUCCESS)
      mat->single_sided = !two;
    /* Roughness: glTF's own, else from a Phong shininess (MTL Ns): the
     * Blinn-Phong match alpha = sqrt(2 / (Ns + 2)) is GGX's alpha, and glTF's
     * roughness is its square root (alpha = roughness^2). */
    ai_real rough, shin;
    one = 1;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_ROUGHNESS_FACTOR, &rough, &one) == AI_SUCCESS &&
        rough >= 0 && rough <= 1) {
      mat->roughness = rough > 0.001f ? (float)rough : 0.001f;
    } else if ((one = 1, aiGetMaterialFloatArray(am, AI_MATKEY_SHININESS, &shin, &one)) ==
                   AI_SUCCESS &&
               shin > 0 && shin < 1e6) {
      mat->roughness = (float)sqrt(sqrt(2.0 / (shin + 2.0)));
    }
    int shading = 0;
    one_int = 1;
    if (aiGetMaterialIntegerArray(am, AI_MATKEY_SHADING_MODEL, &shading, &one_int) == AI_SUCCESS &&
        shading == aiShadingMode_NoShading)
      mat->unlit = 1;
    struct aiString tex;
    if (aiGetMaterialTexture(am, aiTextureType_DIFFUSE, 0, &tex, NULL, NULL, NULL, NULL, NULL,
                             NULL) == AI_SUCCESS ||
        aiGetMaterialTexture(am, aiTextureType_BASE_COLOR, 0, &tex, NULL, NULL, NULL, NULL, NULL,
                             NULL) == AI_SUCCESS) {
      if (tex.length) {
        mat->texture_ref = bbc__strdup(tex.data);
        if (!mat->texture_ref)
          return bbc__fail(L->err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->path);
        bbc_result r = load_material_texture(L, mat, tex.data);
        if (r != BBC_OK) return bbc__fail(L->err, r, "%s: out of memory loading textures", L->path);
      }
    }
    bbc_result r = load_lighting_maps(L, am, mat);
    if (r != BBC_OK) return bbc__fail(L->err, r, "%s: out of memory loading textures", L->path);
  }
  return BBC_OK;
}

/* Assimp adds a "DefaultMaterial" to OBJ files and keeps materials no face
 * uses: keep only the used ones, in their original order. */
static bbc_result drop_unused_materials(bbc_mesh *m) {
  uint32_t *remap = malloc(m->material_count * sizeof *remap);
  if (!remap) return BBC_ERROR_OUT_OF_MEMORY;
  for (size_t i = 0; i < m->material_count; i++) remap[i] = UINT32_MAX;
  for (size_t t = 0; t < m->triangle_count; t++) remap[m->face_material[t]] = 0;
  size_t kept = 0;
  for (size_t i = 0; i < m->material_count; i++) {
    if (remap[i] == UINT32_MAX) {
      free(m->materials[i].name);
      free(m->materials[i].texture_ref);
      continue;
    }
    remap[i] = (uint32_t)kept;
    m->materials[kept++] = m->materials[i];
  }
  m->material_count = kept;
  for (size_t t = 0; t < m->triangle_count; t++) m->face_material[t] = remap[m->face_material[t]];
  free(remap);
  return BBC_OK;
}

/* Assimp's messages are terse; classify them for the exit code. A file
 * whose extension Assimp knows but that no reader accepts is damaged, not
 * of an unknown format. */
static bbc_result classify_assimp_error(const char *path, const char *msg) {
  char ext[16], dotted[20];
  bbc__path_extension(path, ext, sizeof ext);
  snprintf(dotted, sizeof dotted, ".%s", ext);
  int known = ext[0] && aiIsExtensionSupported(dotted);
  if (!known && (strstr(msg, "No suitable reader") || strstr(msg, "nsupported")))
    return BBC_ERROR_UNSUPPORTED_FORMAT;
  return BBC_ERROR_CORRUPT;
}

/* Assimp's OBJ reader turns "nan" into zeros in some positions and shifts
 * the following numbers, so damaged coordinates would slip through as
 * plausible geometry. Check every `v` line's numbers before importing. */
static bbc_result check_obj_stream(FILE *f, const char *path, bbc_error *err);

static bbc_result check_obj_vertices(const char *path, bbc_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f) return BBC_OK; /* Assimp reports the open error */
  return check_obj_stream(f, path, err);
}

/* 1 when p starts with a number strtod reads as [+-]digits[.digits] or
 * [+-].digits, under 1e30 (at most 30 digits before the point, leading
 * zeros aside) and not followed by an exponent or a hexadecimal or special
 * form: then it is finite and small, and *end is where strtod would stop.
 * 0 leaves the number to strtod: the usual numbers of a file skip it. */
static int plain_decimal(const char *p, char **end) {
  const char *q = p;
  if (*q == '+' || *q == '-') q++;
  while (*q == '0') q++;
  const char *d0 = q;
  while (*q >= '0' && *q <= '9') q++;
  int before = (int)(q - d0), digits = before || q > p + (*p == '+' || *p == '-');
  if (*q == '.') {
    const char *f = ++q;
    while (*q >= '0' && *q <= '9') q++;
    digits |= q > f;
  }
  if (!digits || before > 30 || *q == 'e' || *q == 'E' || *q == 'x' || *q == 'X' ||
      (*q >= 'a' && *q <= 'z') || (*q >= 'A' && *q <= 'Z') || *q == '_')
    return 0;
  *end = (char *)q;
  return 1;
}

/* The same over an open stream (closed here). */
static bbc_result check_obj_stream(FILE *f, const char *path, bbc_error *err) {
  char *line = NULL;
  size_t cap = 0;
  ssize_t n;
  size_t lineno = 0;
  bbc_result r = BBC_OK;
  while (r == BBC_OK && (n = getline(&line, &cap, f)) >= 0) {
    lineno++;
    if (line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    char *p = line + 2;
    for (int k = 0; k < 3; k++) {
      while (*p == ' ' || *p == '\t') p++;
      char *end;
      double v = 0;
      if (!plain_decimal(p, &end)) v = strtod(p, &end);
      if (end == p || !isfinite(v) || fabs(v) > 1e30) {
        char tok[32];
        size_t len = strcspn(p, " \t\r\n");
        snprintf(tok, sizeof tok, "%.*s", (int)(len < 24 ? len : 24), p);
        r = bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                      "%s: line %zu: vertex coordinate %d is '%s', not a finite number", path,
                      lineno, k + 1, tok);
        break;
      }
      p = end;
    }
  }
  free(line);
  fclose(f);
  return r;
}

/* Points and lines are no surfaces: Assimp sorts them into their own meshes,
 * which add_mesh skips and counts. */
/* Only what we use: polygons as triangles, points and lines apart. Equal
 * vertices are joined by add_mesh (weld), not by Assimp. */
static const unsigned k_flags = aiProcess_Triangulate | aiProcess_SortByPType;

/* Imported without post-processing, then given it only when some mesh
 * holds more than triangles: on a model of triangles alone both steps
 * change nothing but still cost a noticeable share of a large import. */
static const struct aiScene *post_process(const struct aiScene *sc) {
  if (!sc) return NULL;
  for (unsigned i = 0; i < sc->mNumMeshes; i++)
    if (sc->mMeshes[i]->mPrimitiveTypes != aiPrimitiveType_TRIANGLE)
      return aiApplyPostProcessing(sc, k_flags);
  return sc;
}

static bbc_result from_scene(const char *path, const struct aiScene *sc,
                             const bbc_load_options *opt, bbc_mesh *mesh, bbc_error *err);

bbc_result bbc__load_assimp(const char *path, const bbc_load_options *opt, bbc_mesh *mesh,
                            bbc_error *err) {
  bbc__progress(&opt->callbacks, "load", 0.0);
  char ext[16];
  bbc__path_extension(path, ext, sizeof ext);
  if (!strcmp(ext, "obj")) {
    bbc_result cr = check_obj_vertices(path, err);
    if (cr != BBC_OK) return cr;
  }
  struct aiPropertyStore *props = aiCreatePropertyStore();
  const struct aiScene *sc = post_process(aiImportFileExWithProperties(path, 0, NULL, props));
  aiReleasePropertyStore(props);
  return from_scene(path, sc, opt, mesh, err);
}

bbc_result bbc__load_assimp_memory(const char *name, const void *data, size_t size,
                                   const bbc_load_options *opt, bbc_mesh *mesh, bbc_error *err) {
  bbc__progress(&opt->callbacks, "load", 0.0);
  char ext[16];
  bbc__path_extension(name, ext, sizeof ext);
  if (!strcmp(ext, "obj") && size) {
    FILE *f = fmemopen((void *)data, size, "rb");
    if (f) {
      bbc_result cr = check_obj_stream(f, name, err);
      if (cr != BBC_OK) return cr;
    }
  }
  /* Assimp aborts on an empty buffer (an assertion) */
  if (size == 0) return bbc__fail(err, BBC_ERROR_EMPTY, "%s: empty (0 bytes)", name);
  if (size > UINT_MAX) return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "%s: too large", name);
  struct aiPropertyStore *props = aiCreatePropertyStore();
  const struct aiScene *sc = post_process(
      aiImportFileFromMemoryWithProperties((const char *)data, (unsigned)size, 0, ext, props));
  aiReleasePropertyStore(props);
  return from_scene(name, sc, opt, mesh, err);
}

static bbc_result convert(const char *path, const struct aiScene *sc, const bbc_load_options *opt,
                          bbc_mesh *mesh, bbc_error *err);

/* The scene Assimp read (NULL: its error) as our mesh; releases it. */
static bbc_result from_scene(const char *path, const struct aiScene *sc,
                             const bbc_load_options *opt, bbc_mesh *mesh, bbc_error *err) {
  if (!sc) {
    const char *msg = aiGetErrorString();
    if (!msg || !*msg) msg = "unknown reason";
    return bbc__fail(err, classify_assimp_error(path, msg), "%s: cannot read model: %s", path, msg);
  }
  bbc_result r = convert(path, sc, opt, mesh, err);
  aiReleaseImport(sc);
  return r;
}

bbc_result bbc__load_assimp_scene(const char *name, const struct aiScene *scene,
                                  const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  memset(mesh, 0, sizeof *mesh);
  bbc_result r = convert(name, scene, options, mesh, err);
  return bbc__load_finish(name, r, 1, options, mesh, err);
}

bbc_result bbc__assimp_convert(const char *path, const struct aiScene *scene,
                               const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  return convert(path, scene, options, mesh, err);
}

/* The scene as our mesh (the scene is left as it is). */
static bbc_result convert(const char *path, const struct aiScene *sc, const bbc_load_options *opt,
                          bbc_mesh *mesh, bbc_error *err) {
  bbc__progress(&opt->callbacks, "load", 0.6);
  loader L;
  memset(&L, 0, sizeof L);
  L.path = path;
  L.scene = sc;
  L.opt = opt;
  L.mesh = mesh;
  L.err = err;
  mesh->kind = BBC_MESH_TRIANGLES;
  bbc_result r = BBC_OK;
  if (!sc->mRootNode || sc->mNumMeshes == 0)
    r = bbc__fail(err, BBC_ERROR_EMPTY, "%s: the file contains no meshes", path);
  if (r == BBC_OK) r = load_materials(&L);
  if (r == BBC_OK) {
    struct aiMatrix4x4 I = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    r = walk(&L, sc->mRootNode, &I, 0, opt->lod_node <= 0);
    if (r == BBC_OK && opt->lod_node > 0 && !L.lod_found)
      r = bbc__fail(err, BBC_ERROR_NOT_FOUND, "%s: no node named *_LOD%d (no such level of detail)",
                    path, opt->lod_node - 1);
  }
  if (r != BBC_OK) return r;
  if (mesh->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: the file contains no triangles%s", path,
                     L.skipped_primitives ? " (only points or lines)" : "");
  if (drop_unused_materials(mesh) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  if (!L.has_normals) {
    free(mesh->normals);
    mesh->normals = NULL;
  }
  if (!L.has_uvs) {
    free(mesh->uvs);
    mesh->uvs = NULL;
  }
  if (!L.has_tangents || !mesh->normals) {
    free(mesh->tangents);
    mesh->tangents = NULL;
  }
  if (L.skipped_primitives)
    bbc__log(&opt->callbacks, BBC_LOG_INFO, "%s: ignored %zu points and lines", path,
             L.skipped_primitives);
  bbc__progress(&opt->callbacks, "load", 0.8);
  return BBC_OK;
}
