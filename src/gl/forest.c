/* forest.c — the forest renderer (thesis 3.2 on OpenGL 4.5 core): sky,
 * terrain (CDLOD nodes from src/forest/terrain.c, heights read in the
 * vertex shader, odd vertices morphed to the coarser grid), water, and the
 * 3D objects the culling of src/forest/objects.c chose: per (model, level,
 * component, material) one instanced draw with one texture, whatever the
 * number of trees; levels blended by screen-door dithering (each level
 * discards the pixels its fade weight does not cover, so no sorting and
 * depth stays right). Textures with alpha keep it binary in every mip level
 * (bbc_image_mipmaps). No allocation per frame once buffers have grown. */
#include "bbcgl.h"
#include "shader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

/* ---- the renderer -------------------------------------------------------- */

typedef struct batch {
  GLuint tex; /* 0 = untextured */
  float base[4];
  int lit;
  float gain, amb[3];
  size_t first, count; /* indices */
  int limbs;           /* bbcgen's material "limbs": a mesh, not billboards */
  uint32_t *runs;      /* naive mode: 2 per run of consecutive triangles in one
                        * plane (a billboard): first index, index count; the
                        * limbs one run */
  size_t run_count;
} batch;

typedef struct part {
  size_t bucket;
  GLuint vao, vbo, ebo;
  batch *batches;
  size_t batch_count;
  size_t triangles, billboards;
} part;

typedef struct texture_entry {
  const uint8_t *key; /* the image's texels: one GL texture per image */
  int mipmap;
  GLuint tex;
} texture_entry;

struct bbcgl_forest {
  bbcgl_scene scene;
  const bbc_forest_world *world;
  float fog_colour[3];
  GLuint p_terrain, p_model, p_sky, p_water;
  GLint u_has, u_base, u_lit, u_gain, u_amb; /* the model program's per-material uniforms */
  /* terrain */
  GLuint t_vao, t_vbo, t_ebo, t_nodes, t_height, t_colour;
  size_t t_first[5], t_count[5], t_node_capacity;
  float *t_node_data; /* 4 floats per node, grouped by quarter */
  int leaf, squares;
  /* sky, water */
  GLuint sky_vao, cube, w_vao, w_vbo;
  /* objects */
  part *parts;
  size_t part_count;
  texture_entry *textures;
  size_t texture_count;
  GLuint instances;             /* the culling's static records, then this frame's */
  size_t instance_capacity;     /* records */
  const void *statics_uploaded; /* the static records in `instances` (NULL = none yet) */
  size_t statics_count;
  GLuint indirect; /* this frame's multi-draw commands */
  uint32_t (*cmds)[5];
  size_t cmd_capacity;
  /* GPU culling (bbcgl_frame.gpu_cull), built at its first use */
  int gpu_state; /* 0 not built, 1 ready, -1 failed */
  char gpu_err[BBCGL_ERR];
  GLuint p_cull, p_cmdfill;
  GLuint g_out, g_counters, g_first, g_cmds, g_cmd_bucket;
  size_t *g_base;    /* per bucket: the first record of its region in g_out */
  size_t g_ncmd;     /* one command per part and material */
  GLuint vao_source; /* the buffer the parts' VAOs take their instances from */
  /* text */
  bbcgl__text *text;
};

static void set_fog(GLuint p, const bbcgl_forest *f, const double eye[3]) {
  glProgramUniform3f(p, glGetUniformLocation(p, "u_eye"), (float)eye[0], (float)eye[1],
                     (float)eye[2]);
  glProgramUniform3fv(p, glGetUniformLocation(p, "u_fog_colour"), 1, f->fog_colour);
  glProgramUniform2f(p, glGetUniformLocation(p, "u_fog"), (float)f->scene.fog_start,
                     (float)f->scene.fog_end);
}

static int build_terrain(bbcgl_forest *f, char *err) {
  const bbc_forest_world *w = f->world;
  f->squares = w->width - 1;
  f->leaf = f->squares < BBC_FOREST_TERRAIN_LEAF ? f->squares : BBC_FOREST_TERRAIN_LEAF;
  int n = f->leaf, verts = (n + 1) * (n + 1);
  float *grid = malloc((size_t)verts * 2 * sizeof *grid);
  uint32_t *idx = malloc((size_t)n * n * 6 * 2 * sizeof *idx);
  if (!grid || !idx) {
    free(grid);
    free(idx);
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  for (int z = 0; z <= n; z++)
    for (int x = 0; x <= n; x++) {
      grid[2 * (z * (n + 1) + x)] = (float)x;
      grid[2 * (z * (n + 1) + x) + 1] = (float)z;
    }
  /* index ranges: the whole grid, then its four quarters */
  size_t k = 0;
  for (int r = -1; r < 4; r++) {
    int x0 = 0, z0 = 0, len = n;
    if (r >= 0) {
      len = n / 2 ? n / 2 : 1;
      x0 = (r & 1) * len;
      z0 = (r >> 1) * len;
    }
    f->t_first[r + 1] = k;
    for (int z = z0; z < z0 + len && z < n; z++)
      for (int x = x0; x < x0 + len && x < n; x++) {
        uint32_t a = (uint32_t)(z * (n + 1) + x), b = a + 1, c = a + (uint32_t)(n + 1), d = c + 1;
        /* alternate diagonals so the mesh has no direction */
        if ((x + z) & 1) {
          uint32_t t[6] = {a, c, b, b, c, d};
          memcpy(idx + k, t, sizeof t);
        } else {
          uint32_t t[6] = {a, c, d, a, d, b};
          memcpy(idx + k, t, sizeof t);
        }
        k += 6;
      }
    f->t_count[r + 1] = k - f->t_first[r + 1];
  }
  glCreateVertexArrays(1, &f->t_vao);
  glCreateBuffers(1, &f->t_vbo);
  glCreateBuffers(1, &f->t_ebo);
  glCreateBuffers(1, &f->t_nodes);
  glNamedBufferStorage(f->t_vbo, (GLsizeiptr)verts * 2 * sizeof *grid, grid, 0);
  glNamedBufferStorage(f->t_ebo, (GLsizeiptr)k * sizeof *idx, idx, 0);
  free(grid);
  free(idx);
  glVertexArrayVertexBuffer(f->t_vao, 0, f->t_vbo, 0, 2 * sizeof(float));
  glVertexArrayElementBuffer(f->t_vao, f->t_ebo);
  glEnableVertexArrayAttrib(f->t_vao, 0);
  glVertexArrayAttribFormat(f->t_vao, 0, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->t_vao, 0, 0);
  glEnableVertexArrayAttrib(f->t_vao, 1);
  glVertexArrayAttribFormat(f->t_vao, 1, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->t_vao, 1, 1);
  glVertexArrayBindingDivisor(f->t_vao, 1, 1);
  /* heights, 32-bit float, filtered */
  glCreateTextures(GL_TEXTURE_2D, 1, &f->t_height);
  glTextureStorage2D(f->t_height, 1, GL_R32F, w->width, w->depth);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(f->t_height, 0, 0, 0, w->width, w->depth, GL_RED, GL_FLOAT, w->height);
  glTextureParameteri(f->t_height, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_height, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_height, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->t_height, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  /* colour, with the lighting baked in, mipmapped */
  const bbc_image *c = f->scene.terrain_colour;
  int levels = 1;
  while ((c->width >> levels) > 0 || (c->height >> levels) > 0) levels++;
  glCreateTextures(GL_TEXTURE_2D, 1, &f->t_colour);
  glTextureStorage2D(f->t_colour, levels, GL_RGBA8, c->width, c->height);
  glTextureSubImage2D(f->t_colour, 0, 0, 0, c->width, c->height, GL_RGBA, GL_UNSIGNED_BYTE,
                      c->rgba);
  glGenerateTextureMipmap(f->t_colour);
  glTextureParameteri(f->t_colour, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(f->t_colour, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_colour, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->t_colour, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  /* Anisotropic filtering keeps the ground sharp at grazing angles; not on
   * Mesa's llvmpipe, which stalled for minutes on it (the demo map at
   * 640 x 400 from its start position, 2026-11-24, Mesa 22.3.6). */
  const char *renderer = (const char *)glGetString(GL_RENDERER);
  if (!renderer || !strstr(renderer, "llvmpipe"))
    glTextureParameterf(f->t_colour, GL_TEXTURE_MAX_ANISOTROPY, 4.0f);
  return 1;
}

static void build_water(bbcgl_forest *f) {
  const bbc_forest_world *w = f->world;
  float e = (float)((w->width - 1) * w->spacing), h = (float)f->scene.water_height;
  float v[18] = {-e, h, -e, -e,    h, 2 * e, 2 * e, h, 2 * e,
                 -e, h, -e, 2 * e, h, 2 * e, 2 * e, h, -e};
  glCreateVertexArrays(1, &f->w_vao);
  glCreateBuffers(1, &f->w_vbo);
  glNamedBufferStorage(f->w_vbo, sizeof v, v, 0);
  glVertexArrayVertexBuffer(f->w_vao, 0, f->w_vbo, 0, 3 * sizeof(float));
  glEnableVertexArrayAttrib(f->w_vao, 0);
  glVertexArrayAttribFormat(f->w_vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->w_vao, 0, 0);
}

static void build_sky(bbcgl_forest *f) {
  glCreateVertexArrays(1, &f->sky_vao);
  if (!f->scene.sky[0]) return;
  /* FR, BK, LF, RT, UP, DN onto the cube's faces: front = -z (the
   * direction a GL camera looks by default), right = +x, up = +y. */
  static const int face_of[6] = {5, 4, 1, 0, 2, 3}; /* +X=0 -X=1 +Y=2 -Y=3 +Z=4 -Z=5 */
  int size = f->scene.sky[0]->width;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &f->cube);
  glTextureStorage2D(f->cube, 1, GL_RGBA8, size, size);
  for (int s = 0; s < 6; s++) {
    const bbc_image *im = f->scene.sky[s];
    if (!im || im->width != size || im->height != size) continue;
    glTextureSubImage3D(f->cube, 0, 0, 0, face_of[s], size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                        im->rgba);
  }
  glTextureParameteri(f->cube, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(f->cube, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

bbcgl_forest *bbcgl_forest_create(const bbcgl_scene *scene, char *err) {
  bbcgl_forest *f = calloc(1, sizeof *f);
  if (!f) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  f->scene = *scene;
  f->world = scene->world;
  f->fog_colour[0] = 0.74f;
  f->fog_colour[1] = 0.81f;
  f->fog_colour[2] = 0.88f;
  if (!(f->p_terrain = bbcgl__program(bbcgl__glsl_forest_terrain_vert,
                                      bbcgl__glsl_forest_terrain_frag, "terrain", err)) ||
      !(f->p_model = bbcgl__program(bbcgl__glsl_forest_model_vert, bbcgl__glsl_forest_model_frag,
                                    "model", err)) ||
      !(f->p_sky =
            bbcgl__program(bbcgl__glsl_forest_sky_vert, bbcgl__glsl_forest_sky_frag, "sky", err)) ||
      !(f->p_water = bbcgl__program(bbcgl__glsl_forest_water_vert, bbcgl__glsl_forest_water_frag,
                                    "water", err)) ||
      !(f->text = bbcgl__text_new(err)) || !build_terrain(f, err)) {
    bbcgl_forest_free(f);
    return NULL;
  }
  f->u_has = glGetUniformLocation(f->p_model, "u_has_tex");
  f->u_base = glGetUniformLocation(f->p_model, "u_base");
  f->u_lit = glGetUniformLocation(f->p_model, "u_lit");
  f->u_gain = glGetUniformLocation(f->p_model, "u_gain");
  f->u_amb = glGetUniformLocation(f->p_model, "u_amb");
  build_water(f);
  build_sky(f);
  glCreateBuffers(1, &f->instances);
  glCreateBuffers(1, &f->indirect);
  return f;
}

void bbcgl_forest_free(bbcgl_forest *f) {
  if (!f) return;
  for (size_t i = 0; i < f->part_count; i++) {
    glDeleteVertexArrays(1, &f->parts[i].vao);
    glDeleteBuffers(1, &f->parts[i].vbo);
    glDeleteBuffers(1, &f->parts[i].ebo);
    for (size_t b = 0; b < f->parts[i].batch_count; b++) free(f->parts[i].batches[b].runs);
    free(f->parts[i].batches);
  }
  free(f->parts);
  for (size_t i = 0; i < f->texture_count; i++) glDeleteTextures(1, &f->textures[i].tex);
  free(f->textures);
  GLuint progs[4] = {f->p_terrain, f->p_model, f->p_sky, f->p_water};
  for (int i = 0; i < 4; i++)
    if (progs[i]) glDeleteProgram(progs[i]);
  GLuint bufs[6] = {f->t_vbo, f->t_ebo, f->t_nodes, f->w_vbo, f->instances, f->indirect};
  glDeleteBuffers(6, bufs);
  GLuint vaos[3] = {f->t_vao, f->sky_vao, f->w_vao};
  glDeleteVertexArrays(3, vaos);
  GLuint texs[3] = {f->t_height, f->t_colour, f->cube};
  glDeleteTextures(3, texs);
  free(f->t_node_data);
  bbcgl__text_free(f->text);
  free(f->cmds);
  if (f->p_cull) glDeleteProgram(f->p_cull);
  if (f->p_cmdfill) glDeleteProgram(f->p_cmdfill);
  GLuint gbufs[5] = {f->g_out, f->g_counters, f->g_first, f->g_cmds, f->g_cmd_bucket};
  for (int i = 0; i < 5; i++)
    if (gbufs[i]) glDeleteBuffers(1, &gbufs[i]);
  free(f->g_base);
  free(f);
}

/* One GL texture per image (thesis 3.2.2: models that share a texture share
 * it in memory). */
static GLuint texture_for(bbcgl_forest *f, const bbc_image *im, int mipmap, char *err) {
  for (size_t i = 0; i < f->texture_count; i++)
    if (f->textures[i].key == im->rgba && f->textures[i].mipmap == mipmap)
      return f->textures[i].tex;
  texture_entry *t2 = realloc(f->textures, (f->texture_count + 1) * sizeof *t2);
  if (!t2) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  f->textures = t2;
  bbc_image *mips = NULL;
  int nm = 0;
  bbc_error e;
  if (mipmap && bbc_image_mipmaps(im, &mips, &nm, &e) != BBC_OK) {
    snprintf(err, BBCGL_ERR, "%s", e.message);
    return 0;
  }
  /* Alpha-tested textures stop at 8 x 8 texels: below, a level cannot keep
   * the opaque fraction (a 1 x 1 level of a 40 % leaf is nothing at all)
   * and small leaves would vanish; sampling 8 x 8 texels keeps it on
   * average. */
  int nm_all = nm;
  if (nm && bbc_image_has_transparency(im))
    while (nm > 0 && (mips[nm - 1].width < 8 || mips[nm - 1].height < 8)) nm--;
  GLuint tex;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  glTextureStorage2D(tex, 1 + nm, GL_RGBA8, im->width, im->height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(tex, 0, 0, 0, im->width, im->height, GL_RGBA, GL_UNSIGNED_BYTE, im->rgba);
  for (int l = 0; l < nm; l++) {
    glTextureSubImage2D(tex, l + 1, 0, 0, mips[l].width, mips[l].height, GL_RGBA, GL_UNSIGNED_BYTE,
                        mips[l].rgba);
  }
  for (int l = 0; l < nm_all; l++) bbc_image_free(&mips[l]);
  free(mips);
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, nm ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_REPEAT);
  f->textures[f->texture_count].key = im->rgba;
  f->textures[f->texture_count].mipmap = mipmap;
  f->textures[f->texture_count++].tex = tex;
  return tex;
}

int bbcgl_forest_add_part(bbcgl_forest *f, size_t bucket, const bbc_mesh *m, int lit,
                          float light_gain, int mipmap, size_t billboards, char *err) {
  if (m->kind != BBC_MESH_TRIANGLES || !m->triangle_count) {
    snprintf(err, BBCGL_ERR, "a model to draw needs triangles");
    return 0;
  }
  part *p2 = realloc(f->parts, (f->part_count + 1) * sizeof *p2);
  if (!p2) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  f->parts = p2;
  part *p = &f->parts[f->part_count];
  memset(p, 0, sizeof *p);
  p->bucket = bucket;
  p->triangles = m->triangle_count;
  p->billboards = billboards;
  size_t groups = m->material_count ? m->material_count : 1;
  size_t *first = malloc(groups * sizeof *first), *count = malloc(groups * sizeof *count);
  p->batches = calloc(groups, sizeof *p->batches);
  float *v = NULL;
  uint32_t *idx = NULL;
  if (!first || !count || !p->batches ||
      !bbcgl__mesh_upload(m, &p->vao, &p->vbo, &p->ebo, first, count, &v, &idx, err)) {
    if (!first || !count || !p->batches) snprintf(err, BBCGL_ERR, "out of memory");
    free(first);
    free(count);
    free(p->batches);
    return 0;
  }
  for (size_t mat = 0; mat < m->material_count; mat++) {
    if (!count[mat]) continue;
    const bbc_material *ma = &m->materials[mat];
    batch *b = &p->batches[p->batch_count++];
    b->first = first[mat];
    b->count = count[mat];
    memcpy(b->base, ma->base_color, sizeof b->base);
    b->limbs = bbc_material_is_limbs(ma);
    b->lit = lit && !ma->unlit;
    b->gain = light_gain > 0 ? light_gain : 1.0f;
    if (b->lit) { /* X3D viewers' ambient, as bbc_view.ambient bakes it */
      double ka = (ma->ambient[0] + ma->ambient[1] + ma->ambient[2]) / 3;
      double kd = (ma->base_color[0] + ma->base_color[1] + ma->base_color[2]) / 3;
      if (!(ka > 0)) ka = 0.2;
      for (int c = 0; c < 3 && kd > 0; c++) b->amb[c] = (float)(0.2 * ka / kd * ma->base_color[c]);
    }
    if (ma->texture >= 0 && (size_t)ma->texture < m->texture_count &&
        m->textures[ma->texture].image.rgba) {
      b->tex = texture_for(f, &m->textures[ma->texture].image, mipmap, err);
      if (!b->tex) {
        free(v);
        free(idx);
        free(first);
        free(count);
        free(p->batches);
        GLuint bufs[2] = {p->vbo, p->ebo};
        glDeleteBuffers(2, bufs);
        glDeleteVertexArrays(1, &p->vao);
        return 0;
      }
    }
  }
  free(first);
  free(count);
  /* the naive mode's draw calls: each billboard (consecutive triangles in
   * one plane) on its own */
  for (size_t bi = 0; bi < p->batch_count; bi++) {
    batch *b = &p->batches[bi];
    b->runs = malloc((b->count / 3 + 1) * 2 * sizeof *b->runs);
    if (!b->runs) continue;
    double prev[4] = {0, 0, 0, 0};
    if (b->limbs) { /* one call for the whole mesh */
      b->runs[0] = (uint32_t)b->first;
      b->runs[1] = (uint32_t)b->count;
      b->run_count = 1;
      continue;
    }
    for (size_t t = 0; t < b->count / 3; t++) {
      const uint32_t *ix = idx + b->first + 3 * t;
      const float *a = v + 8 * ix[0], *c1 = v + 8 * ix[1], *c2 = v + 8 * ix[2];
      double e1[3] = {c1[0] - a[0], c1[1] - a[1], c1[2] - a[2]};
      double e2[3] = {c2[0] - a[0], c2[1] - a[1], c2[2] - a[2]};
      double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
      double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (l > 0)
        for (int q = 0; q < 3; q++) n[q] /= l;
      double d = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
      int same = t > 0 && fabs(n[0] * prev[0] + n[1] * prev[1] + n[2] * prev[2]) > 0.9999 &&
                 fabs(fabs(d) - fabs(prev[3])) < 1e-3 * (1 + fabs(d));
      if (!same) {
        b->runs[2 * b->run_count] = (uint32_t)(b->first + 3 * t);
        b->runs[2 * b->run_count + 1] = 0;
        b->run_count++;
      }
      b->runs[2 * b->run_count - 1] += 3;
      memcpy(prev, n, sizeof n);
      prev[3] = d;
    }
  }
  free(v);
  free(idx);
  /* the instance records: attributes 3 (x, y, z, yaw) and 4 (scale, fade) */
  GLuint a = p->vao;
  glEnableVertexArrayAttrib(a, 3);
  glVertexArrayAttribFormat(a, 3, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(a, 3, 1);
  glEnableVertexArrayAttrib(a, 4);
  glVertexArrayAttribFormat(a, 4, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float));
  glVertexArrayAttribBinding(a, 4, 1);
  glVertexArrayBindingDivisor(a, 1, 1);
  if (f->instances && f->instance_capacity)
    glVertexArrayVertexBuffer(a, 1, f->instances, 0, sizeof(bbc_forest_draw));
  f->part_count++;
  return 1;
}

static void inverse4(const float m[16], float out[16]) {
  /* cofactor expansion, double precision */
  double inv[16], a[16];
  for (int i = 0; i < 16; i++) a[i] = m[i];
  inv[0] = a[5] * a[10] * a[15] - a[5] * a[11] * a[14] - a[9] * a[6] * a[15] + a[9] * a[7] * a[14] +
           a[13] * a[6] * a[11] - a[13] * a[7] * a[10];
  inv[4] = -a[4] * a[10] * a[15] + a[4] * a[11] * a[14] + a[8] * a[6] * a[15] -
           a[8] * a[7] * a[14] - a[12] * a[6] * a[11] + a[12] * a[7] * a[10];
  inv[8] = a[4] * a[9] * a[15] - a[4] * a[11] * a[13] - a[8] * a[5] * a[15] + a[8] * a[7] * a[13] +
           a[12] * a[5] * a[11] - a[12] * a[7] * a[9];
  inv[12] = -a[4] * a[9] * a[14] + a[4] * a[10] * a[13] + a[8] * a[5] * a[14] -
            a[8] * a[6] * a[13] - a[12] * a[5] * a[10] + a[12] * a[6] * a[9];
  inv[1] = -a[1] * a[10] * a[15] + a[1] * a[11] * a[14] + a[9] * a[2] * a[15] -
           a[9] * a[3] * a[14] - a[13] * a[2] * a[11] + a[13] * a[3] * a[10];
  inv[5] = a[0] * a[10] * a[15] - a[0] * a[11] * a[14] - a[8] * a[2] * a[15] + a[8] * a[3] * a[14] +
           a[12] * a[2] * a[11] - a[12] * a[3] * a[10];
  inv[9] = -a[0] * a[9] * a[15] + a[0] * a[11] * a[13] + a[8] * a[1] * a[15] - a[8] * a[3] * a[13] -
           a[12] * a[1] * a[11] + a[12] * a[3] * a[9];
  inv[13] = a[0] * a[9] * a[14] - a[0] * a[10] * a[13] - a[8] * a[1] * a[14] + a[8] * a[2] * a[13] +
            a[12] * a[1] * a[10] - a[12] * a[2] * a[9];
  inv[2] = a[1] * a[6] * a[15] - a[1] * a[7] * a[14] - a[5] * a[2] * a[15] + a[5] * a[3] * a[14] +
           a[13] * a[2] * a[7] - a[13] * a[3] * a[6];
  inv[6] = -a[0] * a[6] * a[15] + a[0] * a[7] * a[14] + a[4] * a[2] * a[15] - a[4] * a[3] * a[14] -
           a[12] * a[2] * a[7] + a[12] * a[3] * a[6];
  inv[10] = a[0] * a[5] * a[15] - a[0] * a[7] * a[13] - a[4] * a[1] * a[15] + a[4] * a[3] * a[13] +
            a[12] * a[1] * a[7] - a[12] * a[3] * a[5];
  inv[14] = -a[0] * a[5] * a[14] + a[0] * a[6] * a[13] + a[4] * a[1] * a[14] - a[4] * a[2] * a[13] -
            a[12] * a[1] * a[6] + a[12] * a[2] * a[5];
  inv[3] = -a[1] * a[6] * a[11] + a[1] * a[7] * a[10] + a[5] * a[2] * a[11] - a[5] * a[3] * a[10] -
           a[9] * a[2] * a[7] + a[9] * a[3] * a[6];
  inv[7] = a[0] * a[6] * a[11] - a[0] * a[7] * a[10] - a[4] * a[2] * a[11] + a[4] * a[3] * a[10] +
           a[8] * a[2] * a[7] - a[8] * a[3] * a[6];
  inv[11] = -a[0] * a[5] * a[11] + a[0] * a[7] * a[9] + a[4] * a[1] * a[11] - a[4] * a[3] * a[9] -
            a[8] * a[1] * a[7] + a[8] * a[3] * a[5];
  inv[15] = a[0] * a[5] * a[10] - a[0] * a[6] * a[9] - a[4] * a[1] * a[10] + a[4] * a[2] * a[9] +
            a[8] * a[1] * a[6] - a[8] * a[2] * a[5];
  double det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
  det = det != 0 ? 1.0 / det : 0;
  for (int i = 0; i < 16; i++) out[i] = (float)(inv[i] * det);
}

static void draw_terrain(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_terrain *t,
                         bbcgl_stats *st) {
  if (!t || !t->node_count) return;
  if (t->node_count > f->t_node_capacity) {
    size_t cap = t->node_count * 2;
    float *d = realloc(f->t_node_data, cap * 4 * sizeof *d);
    if (!d) return;
    f->t_node_data = d;
    f->t_node_capacity = cap;
    glNamedBufferData(f->t_nodes, (GLsizeiptr)(cap * 4 * sizeof(float)), NULL, GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(f->t_vao, 1, f->t_nodes, 0, 4 * sizeof(float));
  }
  /* grouped by index range: whole grids, then each quarter */
  size_t start[6] = {0}, fill[5];
  for (size_t i = 0; i < t->node_count; i++) start[t->nodes[i].quarter + 2]++;
  for (int r = 0; r < 5; r++) start[r + 1] += start[r];
  memcpy(fill, start, sizeof fill);
  for (size_t i = 0; i < t->node_count; i++) {
    const bbc_forest_terrain_node *n = &t->nodes[i];
    float *d = f->t_node_data + 4 * fill[n->quarter + 1]++;
    int full = n->quarter < 0 ? n->size : 2 * n->size;
    d[0] = (float)(n->x - (n->quarter < 0 ? 0 : (n->quarter & 1) * n->size));
    d[1] = (float)(n->z - (n->quarter < 0 ? 0 : (n->quarter >> 1) * n->size));
    d[2] = (float)full / (float)f->leaf;
    d[3] = (float)n->level;
  }
  glNamedBufferSubData(f->t_nodes, 0, (GLsizeiptr)(t->node_count * 4 * sizeof(float)),
                       f->t_node_data);
  GLuint p = f->p_terrain;
  glUseProgram(p);
  glUniformMatrix4fv(glGetUniformLocation(p, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
  set_fog(p, f, fr->eye);
  glUniform1f(glGetUniformLocation(p, "u_spacing"), (float)f->world->spacing);
  glUniform1f(glGetUniformLocation(p, "u_squares"), (float)f->squares);
  float morph[48];
  for (int l = 0; l < 24; l++) {
    morph[2 * l] = (float)(l < t->levels ? t->morph_start[l] : 1e30);
    morph[2 * l + 1] = (float)(l < t->levels ? t->range[l] : 2e30);
  }
  glUniform2fv(glGetUniformLocation(p, "u_morph"), 24, morph);
  glUniform1i(glGetUniformLocation(p, "u_height"), 0);
  glUniform1i(glGetUniformLocation(p, "u_colour"), 1);
  glUniform1i(glGetUniformLocation(p, "u_flat"), fr->wireframe);
  glBindTextureUnit(0, f->t_height);
  glBindTextureUnit(1, f->t_colour);
  st->texture_binds += 2;
  glBindVertexArray(f->t_vao);
  for (int r = 0; r < 5; r++) {
    size_t n = start[r + 1] - start[r];
    if (!n) continue;
    glDrawElementsInstancedBaseInstance(GL_TRIANGLES, (GLsizei)f->t_count[r], GL_UNSIGNED_INT,
                                        (const void *)(f->t_first[r] * sizeof(uint32_t)),
                                        (GLsizei)n, (GLuint)start[r]);
    st->draw_calls++;
    st->triangles += n * f->t_count[r] / 3;
  }
  st->terrain_nodes = t->node_count;
}

/* A material's uniforms of the model program. */
static void set_batch(const bbcgl_forest *f, const batch *ba) {
  glUniform1i(f->u_has, ba->tex != 0);
  glUniform4fv(f->u_base, 1, ba->base);
  glUniform1i(f->u_lit, ba->lit);
  glUniform1f(f->u_gain, ba->gain);
  glUniform3fv(f->u_amb, 1, ba->amb);
}

/* The thesis's way (3.3), for measuring against: per tree, level and
 * billboard its own draw call and texture bind (the culling's per-frame
 * records, after the static ones in the buffer). */
static void draw_objects_naive(bbcgl_forest *f, const bbc_forest_cull *c, bbcgl_stats *st) {
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t first = c->static_count + c->bucket_start[pt->bucket],
           count = c->bucket_start[pt->bucket + 1] - c->bucket_start[pt->bucket];
    for (size_t tree = 0; tree < count; tree++) {
      glBindVertexArray(pt->vao);
      for (size_t b = 0; b < pt->batch_count; b++) {
        const batch *ba = &pt->batches[b];
        glBindTextureUnit(0, ba->tex);
        st->texture_binds++;
        set_batch(f, ba);
        if (!pt->billboards) { /* a polygon model: one call (its display list) */
          glDrawElementsInstancedBaseInstance(GL_TRIANGLES, (GLsizei)ba->count, GL_UNSIGNED_INT,
                                              (const void *)(ba->first * sizeof(uint32_t)), 1,
                                              (GLuint)(first + tree));
          st->draw_calls++;
        }
        for (size_t r = 0; pt->billboards && r < ba->run_count; r++) {
          glDrawElementsInstancedBaseInstance(
              GL_TRIANGLES, (GLsizei)ba->runs[2 * r + 1], GL_UNSIGNED_INT,
              (const void *)(ba->runs[2 * r] * sizeof(uint32_t)), 1, (GLuint)(first + tree));
          st->draw_calls++;
        }
        st->triangles += ba->count / 3;
      }
      st->billboards += pt->billboards;
    }
  }
}

/* The instance buffer holds the static records (uploaded once) and this
 * frame's records after them. */
static int upload_instances(bbcgl_forest *f, const bbc_forest_cull *c) {
  size_t s = c->static_count, n = c->bucket_start[c->bucket_count];
  if (s + n > f->instance_capacity) {
    size_t cap = s + n + n / 2 + 1024;
    glNamedBufferData(f->instances, (GLsizeiptr)(cap * sizeof(bbc_forest_draw)), NULL,
                      GL_DYNAMIC_DRAW);
    f->instance_capacity = cap;
    f->statics_uploaded = NULL;
    for (size_t i = 0; i < f->part_count; i++)
      glVertexArrayVertexBuffer(f->parts[i].vao, 1, f->instances, 0, sizeof(bbc_forest_draw));
    f->vao_source = f->instances;
  }
  if (f->statics_uploaded != (const void *)c->statics || f->statics_count != s) {
    if (s)
      glNamedBufferSubData(f->instances, 0, (GLsizeiptr)(s * sizeof(bbc_forest_draw)), c->statics);
    f->statics_uploaded = c->statics;
    f->statics_count = s;
  }
  if (n) {
    glInvalidateBufferSubData(f->instances, (GLintptr)(s * sizeof(bbc_forest_draw)),
                              (GLsizeiptr)(n * sizeof(bbc_forest_draw)));
    glNamedBufferSubData(f->instances, (GLintptr)(s * sizeof(bbc_forest_draw)),
                         (GLsizeiptr)(n * sizeof(bbc_forest_draw)), c->draws);
  }
  return 1;
}

/* One material of a part: its texture (when not bound already), its
 * uniforms, and `n` commands of the bound indirect buffer from `first`. */
static void multi_draw(bbcgl_forest *f, const batch *ba, size_t first, size_t n, GLuint *bound,
                       bbcgl_stats *st) {
  if (ba->tex && ba->tex != *bound) {
    glBindTextureUnit(0, ba->tex);
    *bound = ba->tex;
    st->texture_binds++;
  }
  set_batch(f, ba);
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                              (const void *)(first * 5 * sizeof(uint32_t)), (GLsizei)n, 0);
  st->draw_calls++;
  st->draw_commands += n;
}

/* The parts' VAOs take their instance records from `buf`. */
static void vao_source(bbcgl_forest *f, GLuint buf) {
  if (f->vao_source == buf) return;
  for (size_t i = 0; i < f->part_count; i++)
    glVertexArrayVertexBuffer(f->parts[i].vao, 1, buf, 0, sizeof(bbc_forest_draw));
  f->vao_source = buf;
}

/* GPU culling's programs and buffers: per bucket a region of the output as
 * large as its model's records, the first-component bits, and one indirect
 * command per part and material (its instance count filled in each frame). */
static void gpu_build(bbcgl_forest *f, const bbc_forest_cull *c) {
  f->gpu_state = -1;
  snprintf(f->gpu_err, sizeof f->gpu_err, "GPU culling: out of memory");
  if (!(f->p_cull = bbcgl__compute_program(bbcgl__glsl_forest_cull_comp, "cull", f->gpu_err)) ||
      !(f->p_cmdfill =
            bbcgl__compute_program(bbcgl__glsl_forest_cmdfill_comp, "cmdfill", f->gpu_err)))
    return;
  size_t nb = c->bucket_count, ncell = c->cell_count, total = 0;
  f->g_base = calloc(nb + 1, sizeof *f->g_base);
  size_t words = (c->static_count + 31) / 32 + 1;
  uint32_t *bits = calloc(words, sizeof *bits);
  size_t ncmd = 0;
  for (size_t i = 0; i < f->part_count; i++)
    if (f->parts[i].bucket < nb) ncmd += f->parts[i].batch_count;
  uint32_t(*cmd)[5] = calloc(ncmd + 1, sizeof *cmd);
  uint32_t *cmd_bucket = calloc(ncmd + 1, sizeof *cmd_bucket);
  if (!f->g_base || !bits || !cmd || !cmd_bucket) {
    free(bits);
    free(cmd);
    free(cmd_bucket);
    return;
  }
  for (size_t m = 0; m < c->model_count; m++) {
    const uint32_t *st = c->model_cell_start + m * (ncell + 1);
    for (size_t l = 0; l < c->models[m].lod_count; l++) {
      f->g_base[c->bucket_base[m] + l] = total;
      total += st[ncell] - st[0];
    }
  }
  for (size_t i = 0; i < c->static_count; i++)
    if (c->static_first[i]) bits[i >> 5] |= 1u << (i & 31);
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= nb) continue;
    for (size_t b = 0; b < pt->batch_count; b++, k++) {
      cmd[k][0] = (uint32_t)pt->batches[b].count;
      cmd[k][2] = (uint32_t)pt->batches[b].first;
      cmd[k][4] = (uint32_t)f->g_base[pt->bucket];
      cmd_bucket[k] = (uint32_t)pt->bucket;
    }
  }
  f->g_ncmd = ncmd;
  glCreateBuffers(1, &f->g_out);
  glCreateBuffers(1, &f->g_counters);
  glCreateBuffers(1, &f->g_first);
  glCreateBuffers(1, &f->g_cmds);
  glCreateBuffers(1, &f->g_cmd_bucket);
  glNamedBufferStorage(f->g_out, (GLsizeiptr)((total ? total : 1) * sizeof(bbc_forest_draw)), NULL,
                       0);
  glNamedBufferStorage(f->g_counters, (GLsizeiptr)((nb + 1) * sizeof(uint32_t)), NULL,
                       GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(f->g_first, (GLsizeiptr)(words * sizeof *bits), bits, 0);
  glNamedBufferStorage(f->g_cmds, (GLsizeiptr)((ncmd + 1) * sizeof *cmd), cmd, 0);
  glNamedBufferStorage(f->g_cmd_bucket, (GLsizeiptr)((ncmd + 1) * sizeof *cmd_bucket), cmd_bucket,
                       0);
  free(bits);
  free(cmd);
  free(cmd_bucket);
  f->gpu_state = 1;
}

/* GPU culling, before the drawing: every static record of every model
 * through the cull shader, then the commands' instance counts. */
static int gpu_cull(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_cull *c) {
  if (!f->gpu_state) gpu_build(f, c);
  if (f->gpu_state < 0 || !c->static_count) return 0;
  upload_instances(f, c);
  glClearNamedBufferData(f->g_counters, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
  GLuint p = f->p_cull;
  glUseProgram(p);
  double pl[6][4];
  bbc_forest_frustum(fr->viewproj, pl);
  float plf[24];
  for (int i = 0; i < 24; i++) plf[i] = (float)pl[i / 4][i % 4];
  glUniform4fv(glGetUniformLocation(p, "u_planes"), 6, plf);
  glUniform3f(glGetUniformLocation(p, "u_eye"), (float)fr->eye[0], (float)fr->eye[1],
              (float)fr->eye[2]);
  glUniform1f(glGetUniformLocation(p, "u_zoom"), (float)(fr->zoom > 0 ? fr->zoom : 1));
  glUniform1ui(glGetUniformLocation(p, "u_trees"), (GLuint)c->bucket_count);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, f->instances, 0,
                    (GLsizeiptr)(c->static_count * sizeof(bbc_forest_draw)));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, f->g_out);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, f->g_counters);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, f->g_first);
  GLint u_first = glGetUniformLocation(p, "u_first"), u_count = glGetUniformLocation(p, "u_count"),
        u_bucket0 = glGetUniformLocation(p, "u_bucket0"),
        u_radius = glGetUniformLocation(p, "u_radius"), u_fade = glGetUniformLocation(p, "u_fade"),
        u_lods = glGetUniformLocation(p, "u_lods"), u_range = glGetUniformLocation(p, "u_range"),
        u_base = glGetUniformLocation(p, "u_base");
  size_t ncell = c->cell_count;
  for (size_t m = 0; m < c->model_count; m++) {
    const uint32_t *st = c->model_cell_start + m * (ncell + 1);
    uint32_t first = st[0], count = st[ncell] - st[0];
    const bbc_forest_lod_model *mod = &c->models[m];
    if (!count || !mod->lod_count) continue;
    int lods = mod->lod_count > 8 ? 8 : (int)mod->lod_count;
    float range[16];
    GLuint base[8];
    for (int l = 0; l < lods; l++) {
      range[2 * l] = (float)mod->ranges[2 * l];
      range[2 * l + 1] = (float)mod->ranges[2 * l + 1];
      base[l] = (GLuint)f->g_base[c->bucket_base[m] + (size_t)l];
    }
    glUniform1ui(u_first, first);
    glUniform1ui(u_count, count);
    glUniform1ui(u_bucket0, (GLuint)c->bucket_base[m]);
    glUniform1f(u_radius, (float)mod->radius);
    glUniform1f(u_fade, (float)(mod->fade > 0 ? mod->fade : 0));
    glUniform1i(u_lods, lods);
    glUniform2fv(u_range, lods, range);
    glUniform1uiv(u_base, lods, base);
    glDispatchCompute((count + 255) / 256, 1, 1);
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(f->p_cmdfill);
  glUniform1ui(glGetUniformLocation(f->p_cmdfill, "u_ncmd"), (GLuint)f->g_ncmd);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, f->g_cmds);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, f->g_cmd_bucket);
  glDispatchCompute((GLuint)((f->g_ncmd + 63) / 64), 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
  return 1;
}

static void draw_objects_gpu(bbcgl_forest *f, const bbc_forest_cull *c, bbcgl_stats *st) {
  vao_source(f, f->g_out);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f->g_cmds);
  GLuint bound = 0;
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    glBindVertexArray(pt->vao);
    for (size_t bi = 0; bi < pt->batch_count; bi++, k++)
      multi_draw(f, &pt->batches[bi], k, 1, &bound, st);
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  /* the statistics: the counters read back (waits for the culling) */
  uint32_t *n = calloc(c->bucket_count + 1, sizeof *n);
  if (!n) return;
  glGetNamedBufferSubData(f->g_counters, 0, (GLsizeiptr)((c->bucket_count + 1) * sizeof *n), n);
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    st->billboards += n[pt->bucket] * pt->billboards;
    for (size_t bi = 0; bi < pt->batch_count; bi++)
      st->triangles += n[pt->bucket] * pt->batches[bi].count / 3;
  }
  st->trees = n[c->bucket_count];
  free(n);
}

static void draw_objects(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_cull *c,
                         bbcgl_stats *st) {
  st->trees = c->trees_visible;
  int gpu = 0;
  if (fr->gpu_cull && !fr->naive && c->bucket_count) {
    if (!gpu_cull(f, fr, c)) return;
    gpu = 1;
  } else if (!c->bucket_count || !upload_instances(f, c)) {
    return;
  }
  GLuint p = f->p_model;
  glUseProgram(p);
  glUniformMatrix4fv(glGetUniformLocation(p, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
  set_fog(p, f, fr->eye);
  double L[3] = {f->scene.light[0], f->scene.light[1], f->scene.light[2]};
  double ln = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  if (ln <= 0) ln = L[1] = 1;
  glUniform3f(glGetUniformLocation(p, "u_light"), (float)(L[0] / ln), (float)(L[1] / ln),
              (float)(L[2] / ln));
  glUniform1i(glGetUniformLocation(p, "u_tex"), 0);
  glUniform1i(glGetUniformLocation(p, "u_fill"), fr->fill_colour);
  if (gpu) {
    draw_objects_gpu(f, c, st);
    return;
  }
  vao_source(f, f->instances);
  if (fr->naive) {
    draw_objects_naive(f, c, st);
    return;
  }
  /* One multi-draw per part and material: a command per static range and
   * one for the per-frame records. */
  size_t ncmd = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t b = pt->bucket;
    size_t per =
        c->range_start[b + 1] - c->range_start[b] + (c->bucket_start[b + 1] > c->bucket_start[b]);
    ncmd += per * pt->batch_count;
  }
  if (!ncmd) return;
  if (ncmd > f->cmd_capacity) {
    size_t cap = ncmd + ncmd / 2 + 64;
    uint32_t(*d)[5] = realloc(f->cmds, cap * sizeof *d);
    if (!d) return;
    f->cmds = d;
    f->cmd_capacity = cap;
    glNamedBufferData(f->indirect, (GLsizeiptr)(cap * sizeof *d), NULL, GL_DYNAMIC_DRAW);
  }
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t b = pt->bucket, dyn = c->bucket_start[b + 1] - c->bucket_start[b];
    for (size_t ba = 0; ba < pt->batch_count; ba++) {
      for (size_t r = c->range_start[b]; r < c->range_start[b + 1]; r++) {
        uint32_t *cmd = f->cmds[k++];
        cmd[0] = (uint32_t)pt->batches[ba].count;
        cmd[1] = c->ranges[r][1];
        cmd[2] = (uint32_t)pt->batches[ba].first;
        cmd[3] = 0;
        cmd[4] = c->ranges[r][0];
      }
      if (dyn) {
        uint32_t *cmd = f->cmds[k++];
        cmd[0] = (uint32_t)pt->batches[ba].count;
        cmd[1] = (uint32_t)dyn;
        cmd[2] = (uint32_t)pt->batches[ba].first;
        cmd[3] = 0;
        cmd[4] = (uint32_t)(c->static_count + c->bucket_start[b]);
      }
    }
  }
  glInvalidateBufferData(f->indirect);
  glNamedBufferSubData(f->indirect, 0, (GLsizeiptr)(ncmd * sizeof *f->cmds), f->cmds);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f->indirect);
  GLuint bound = 0;
  k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t b = pt->bucket, count = bbc_forest_cull_bucket_size(c, b);
    size_t per =
        c->range_start[b + 1] - c->range_start[b] + (c->bucket_start[b + 1] > c->bucket_start[b]);
    if (!per) continue;
    glBindVertexArray(pt->vao);
    for (size_t bi = 0; bi < pt->batch_count; bi++) {
      const batch *ba = &pt->batches[bi];
      multi_draw(f, ba, k, per, &bound, st);
      k += per;
      st->triangles += count * ba->count / 3;
    }
    st->billboards += count * pt->billboards;
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

const char *bbcgl_forest_gpu_cull_error(const bbcgl_forest *f) {
  return f->gpu_state < 0 ? f->gpu_err : NULL;
}

void bbcgl_forest_draw(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_terrain *t,
                       const bbc_forest_cull *c, bbcgl_stats *st) {
  memset(st, 0, sizeof *st);
  glViewport(0, 0, fr->width, fr->height);
  if (fr->fill_colour)
    glClearColor(0, 0, 0, 1);
  else
    glClearColor(f->fog_colour[0], f->fog_colour[1], f->fog_colour[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  /* sky at the far plane, behind everything */
  if (!fr->wireframe && !fr->fill_colour) {
    glDisable(GL_DEPTH_TEST);
    glUseProgram(f->p_sky);
    float inv[16];
    inverse4(fr->viewproj, inv);
    glUniformMatrix4fv(glGetUniformLocation(f->p_sky, "u_inverse"), 1, GL_FALSE, inv);
    glUniform3fv(glGetUniformLocation(f->p_sky, "u_fog_colour"), 1, f->fog_colour);
    glUniform1i(glGetUniformLocation(f->p_sky, "u_has_cube"), f->cube != 0);
    glUniform1i(glGetUniformLocation(f->p_sky, "u_cube"), 2);
    if (f->cube) glBindTextureUnit(2, f->cube);
    glBindVertexArray(f->sky_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    st->draw_calls++;
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glPolygonMode(GL_FRONT_AND_BACK, fr->wireframe ? GL_LINE : GL_FILL);
  if (!fr->no_terrain && !fr->fill_colour) draw_terrain(f, fr, t, st);
  if (!fr->no_objects && c) draw_objects(f, fr, c, st);
  if (f->scene.has_water && !fr->no_terrain && !fr->fill_colour) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(f->p_water);
    glUniformMatrix4fv(glGetUniformLocation(f->p_water, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
    set_fog(f->p_water, f, fr->eye);
    glBindVertexArray(f->w_vao);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    st->draw_calls++;
    glDisable(GL_BLEND);
  }
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

void bbcgl_forest_text(bbcgl_forest *f, int width, int height, const char *const *lines,
                       size_t line_count, int scale) {
  bbcgl__text_draw(f->text, width, height, lines, line_count, scale, 0);
}
