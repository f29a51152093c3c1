/* forest_parts.c — the forest's models on the GPU: each component of each
 * level a part (its mesh, a batch per material, the naive mode's draw
 * calls), each image one GL texture whatever the number of models using it
 * (thesis 3.2.2). */
#include "forest_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

/* BC1 for an image and its levels when the driver samples S3TC and every
 * level's alpha is binary (cloud atlases, whose mip levels keep coverage
 * with a binary alpha) or opaque; dimensions multiples of 4 for level 0
 * (the GL wants whole blocks except at the smallest levels). */
static int use_bc1(const bbcgl_forest *f, const bbc_image *im, const bbc_image *mips, int nm) {
  static int s3tc = -1;
  if (s3tc < 0) s3tc = epoxy_has_gl_extension("GL_EXT_texture_compression_s3tc");
  if (f->scene.uncompressed || !s3tc || im->width % 4 || im->height % 4) return 0;
  /* (normal and occlusion maps come here opaque) */
  if (!bbc_image_alpha_is_binary(im)) return 0;
  for (int l = 0; l < nm; l++)
    if (!bbc_image_alpha_is_binary(&mips[l])) return 0;
  return 1;
}

/* The image as the shaders read it, into out: a normal or occlusion map
 * (`map`) its colour channels, opaque (the colour map's alpha decides what
 * is drawn), so that its mip levels are plain averages and BC1 holds it; an
 * atlas with softened alpha edges (softalpha, for clients' bilinear alpha
 * tests) the binary mask it is, which BC1 and the coverage-keeping levels
 * take whole. */
static int shader_copy(const bbc_image *im, int map, bbc_image *out, char *err) {
  if (bbc_image_alloc(out, im->width, im->height) != BBC_OK) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  size_t n = (size_t)im->width * im->height;
  memcpy(out->rgba, im->rgba, 4 * n);
  if (map)
    for (size_t i = 0; i < n; i++) out->rgba[4 * i + 3] = 255;
  else
    bbc_image_alpha_binarise(out);
  return 1;
}

/* One GL texture per image and use (thesis 3.2.2: models that share a
 * texture share it in memory): texture `ti` of m; `map` 1: a normal or
 * occlusion map. An opaque texture's mip levels are made from it with its
 * texels no triangle uses padded by those it does, average only the texels
 * the triangles show, and stop where they would mix its islands
 * (bbc_mesh_texture_padded, bbc_image_mipmaps_masked: a texture atlas's
 * background and bark between leaves would brighten a far tree; an
 * alpha-tested one's levels already weigh colour by coverage). */
static GLuint texture_for(bbcgl_forest *f, const bbc_mesh *m, int ti, int mipmap, int map,
                          int *premultiplied, int *alpha_tested, char *err) {
  const bbc_image *src = &m->textures[ti].image;
  for (size_t i = 0; i < f->texture_count; i++)
    if (f->textures[i].key == src->rgba && f->textures[i].mipmap == mipmap &&
        f->textures[i].map == map) {
      *premultiplied = f->textures[i].premultiplied;
      *alpha_tested = f->textures[i].alpha_tested;
      return f->textures[i].tex;
    }
  int transparent = bbc_image_has_transparency(src);
  texture_entry *t2 = realloc(f->textures, (f->texture_count + 1) * sizeof *t2);
  if (!t2) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  f->textures = t2;
  bbc_image opaque = {0}, padded = {0};
  bbc_error e;
  int apart = -1;       /* mip levels that keep an opaque atlas's islands apart */
  uint8_t *used = NULL; /* its texels the triangles show: what its levels average */
  if (mipmap && !transparent) {
    if (bbc_mesh_texture_padded(m, ti, &padded, &apart, &used, &e) != BBC_OK) {
      snprintf(err, BBCGL_ERR, "%s", e.message);
      return 0;
    }
    src = &padded;
  }
  int copy = map || bbc_image_alpha_is_soft_mask(src);
  if (copy && !shader_copy(src, map, &opaque, err)) {
    bbc_image_free(&padded);
    free(used);
    return 0;
  }
  const bbc_image *im = copy ? &opaque : src;
  bbc_image *all = NULL;
  int nm = 0;
  /* Normal and occlusion maps of 512 texels or more (and 128 a side) at
   * half their resolution (light varies slowly across a leaf; a quarter of
   * the memory): level 1 and the levels after it. Smaller atlases (far
   * levels') would lose the leaves' orientation: the test oak's 8-billboard
   * level, 256 x 128, fell to 0.898 of its polygon tree's brightness. */
  int big = im->width > im->height ? im->width : im->height;
  int half = map && big >= 512 && im->width >= 128 && im->height >= 128;
  bbc_result mr = BBC_OK;
  if (mipmap || half)
    mr = used ? bbc_image_mipmaps_masked(im, used, &all, &nm, &e)
              : bbc_image_mipmaps(im, &all, &nm, &e);
  free(used);
  if (mr != BBC_OK) {
    snprintf(err, BBCGL_ERR, "%s", e.message);
    bbc_image_free(&opaque);
    bbc_image_free(&padded);
    return 0;
  }
  int nm_all = nm;
  bbc_image *mips = all;
  if (half) {
    im = &all[0];
    mips = all + 1;
    nm = mipmap ? nm - 1 : 0;
  }
  /* Alpha-tested textures stop at 8 x 8 texels: below, a level cannot keep
   * the opaque fraction (a 1 x 1 level of a 40 % leaf is nothing at all)
   * and small leaves would vanish; sampling 8 x 8 texels keeps it on
   * average. */
  if (nm && bbc_image_has_transparency(im))
    while (nm > 0 && (mips[nm - 1].width < 8 || mips[nm - 1].height < 8)) nm--;
  if (apart >= 0 && nm > apart) nm = apart;
  GLuint tex;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  size_t bytes = 0;
  int bc1 = use_bc1(f, im, mips, nm);
  if (bc1) { /* level 0 and its coverage-keeping levels, each as BC1 */
    glTextureStorage2D(tex, 1 + nm, GL_COMPRESSED_RGBA_S3TC_DXT1_EXT, im->width, im->height);
    for (int l = 0; l <= nm && tex; l++) {
      const bbc_image *lv = l ? &mips[l - 1] : im;
      size_t n = bbc_bc1_size(lv->width, lv->height);
      uint8_t *blocks = malloc(n);
      if (!blocks || bbc_image_encode_bc1(lv, blocks, &e) != BBC_OK) {
        snprintf(err, BBCGL_ERR, "out of memory for a BC1 texture");
        glDeleteTextures(1, &tex);
        tex = 0;
      } else {
        glCompressedTextureSubImage2D(tex, l, 0, 0, lv->width, lv->height,
                                      GL_COMPRESSED_RGBA_S3TC_DXT1_EXT, (GLsizei)n, blocks);
        bytes += n;
      }
      free(blocks);
    }
  } else {
    glTextureStorage2D(tex, 1 + nm, GL_RGBA8, im->width, im->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex, 0, 0, 0, im->width, im->height, GL_RGBA, GL_UNSIGNED_BYTE, im->rgba);
    bytes = (size_t)im->width * im->height * 4;
    for (int l = 0; l < nm; l++) {
      glTextureSubImage2D(tex, l + 1, 0, 0, mips[l].width, mips[l].height, GL_RGBA,
                          GL_UNSIGNED_BYTE, mips[l].rgba);
      bytes += (size_t)mips[l].width * mips[l].height * 4;
    }
  }
  for (int l = 0; l < nm_all; l++) bbc_image_free(&all[l]);
  free(all);
  bbc_image_free(&opaque);
  bbc_image_free(&padded);
  if (!tex) return 0;
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, nm ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_REPEAT);
  f->textures[f->texture_count].key = m->textures[ti].image.rgba;
  f->textures[f->texture_count].mipmap = mipmap;
  f->textures[f->texture_count].map = map;
  f->textures[f->texture_count].bytes = bytes;
  f->textures[f->texture_count].premultiplied = bc1;
  f->textures[f->texture_count].alpha_tested = transparent;
  *premultiplied = bc1 && !map;
  *alpha_tested = transparent;
  f->textures[f->texture_count++].tex = tex;
  return tex;
}

/* An impostor's two atlases with their mip levels (bbc_impostor_level)
 * packed one below another in one RGBA8 texture each (level l's frames from
 * row bbcgl__impostor_level_row(l)), nearest texels: the shader fetches
 * texels of its frames at the level it picks; a normal atlas's alpha is
 * depth. tex[0] albedo, tex[1] normal; 0 when it fails. */
int bbcgl__impostor_level_row(const bbc_impostor *imp, int level) {
  int row = 0;
  for (int l = 0; l < level; l++) row += imp->frames * bbc_impostor_level_size(imp, l);
  return row;
}

static int atlas_textures(bbcgl_forest *f, const bbc_impostor *imp, GLuint tex[2], char *err) {
  for (size_t i = 0; i + 1 < f->texture_count; i++)
    if (f->textures[i].key == imp->albedo.rgba && f->textures[i].map == 2) {
      tex[0] = f->textures[i].tex;
      tex[1] = f->textures[i + 1].tex;
      return 1;
    }
  texture_entry *t2 = realloc(f->textures, (f->texture_count + 2) * sizeof *t2);
  if (!t2) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  f->textures = t2;
  int levels = bbc_impostor_level_count(imp), W = imp->albedo.width;
  int H = bbcgl__impostor_level_row(imp, levels);
  glCreateTextures(GL_TEXTURE_2D, 2, tex);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (int k = 0; k < 2; k++) {
    glTextureStorage2D(tex[k], 1, GL_RGBA8, W, H);
    glTextureSubImage2D(tex[k], 0, 0, 0, W, W, GL_RGBA, GL_UNSIGNED_BYTE,
                        k ? imp->normal.rgba : imp->albedo.rgba);
    glTextureParameteri(tex[k], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(tex[k], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  for (int l = 1; l < levels; l++) {
    bbc_image a, n;
    bbc_error e;
    if (bbc_impostor_level(imp, l, &a, &n, &e) != BBC_OK) {
      snprintf(err, BBCGL_ERR, "%s", e.message);
      glDeleteTextures(2, tex);
      tex[0] = tex[1] = 0;
      return 0;
    }
    int row = bbcgl__impostor_level_row(imp, l);
    glTextureSubImage2D(tex[0], 0, 0, row, a.width, a.height, GL_RGBA, GL_UNSIGNED_BYTE, a.rgba);
    glTextureSubImage2D(tex[1], 0, 0, row, n.width, n.height, GL_RGBA, GL_UNSIGNED_BYTE, n.rgba);
    bbc_image_free(&a);
    bbc_image_free(&n);
  }
  for (int k = 0; k < 2; k++) {
    texture_entry *t = &f->textures[f->texture_count++];
    memset(t, 0, sizeof *t);
    t->key = k ? imp->normal.rgba : imp->albedo.rgba;
    t->map = 2 + k;
    t->tex = tex[k];
    t->bytes = (size_t)W * H * 4;
  }
  return 1;
}

size_t bbcgl_forest_texture_bytes(const bbcgl_forest *f, const bbc_image *im, int mipmap) {
  size_t n = 0; /* as a colour map and as a normal or occlusion map */
  for (size_t i = 0; i < f->texture_count; i++)
    if (f->textures[i].key == im->rgba && f->textures[i].mipmap == mipmap)
      n += f->textures[i].bytes;
  return n;
}

/* A new part of bucket `bucket` at the end of f->parts (counted once it is
 * complete). */
static part *new_part(bbcgl_forest *f, size_t bucket, const bbc_mesh *m, size_t billboards,
                      char *err) {
  part *p2 = realloc(f->parts, (f->part_count + 1) * sizeof *p2);
  if (!p2) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  f->parts = p2;
  part *p = &f->parts[f->part_count];
  memset(p, 0, sizeof *p);
  p->bucket = bucket;
  p->triangles = m->triangle_count;
  p->billboards = billboards;
  return p;
}

/* The image of texture `index` of `m` (-1 or out of range: none). */
static const bbc_image *mesh_image(const bbc_mesh *m, int index) {
  return index >= 0 && (size_t)index < m->texture_count && m->textures[index].image.rgba
             ? &m->textures[index].image
             : NULL;
}

/* A batch per material with triangles (first[], count[]: its indices), lit
 * as bbcgl_forest_add_part says, its maps uploaded once; 0 when a texture
 * fails. */
static int add_batches(bbcgl_forest *f, part *p, const bbc_mesh *m, const size_t *first,
                       const size_t *count, const bbcgl_part_options *o, char *err) {
  if (o->impostor) { /* its quad, one batch reading the atlases */
    batch *b = &p->batches[p->batch_count++];
    b->first = first[0];
    b->count = count[0];
    for (int k = 0; k < 4; k++) b->base[k] = 1;
    b->lit = o->lit;
    b->sway = o->sway_height;
    b->imp = o->impostor;
    return atlas_textures(f, o->impostor, b->tex, err);
  }
  for (size_t mat = 0; mat < m->material_count; mat++) {
    if (!count[mat]) continue;
    const bbc_material *ma = &m->materials[mat];
    batch *b = &p->batches[p->batch_count++];
    b->first = first[mat];
    b->count = count[mat];
    memcpy(b->base, ma->base_color, sizeof b->base);
    b->limbs = bbc_material_is_limbs(ma);
    b->lit = o->lit && !ma->unlit;
    b->single_sided = ma->single_sided;
    b->sway = o->sway_height;
    int ti[3] = {ma->texture, -1, -1};
    if (b->lit && m->tangents) ti[1] = ma->normal_map - 1;
    if (b->lit) ti[2] = ma->occlusion_map - 1;
    int alpha_tested = 0;
    for (int k = 0; k < 3; k++) {
      int pm = 0, at = 0;
      const bbc_image *im = mesh_image(m, ti[k]);
      if (im && !(b->tex[k] = texture_for(f, m, ti[k], o->mipmap, k > 0, &pm, &at, err))) return 0;
      if (k == 0) {
        b->premultiplied = pm;
        alpha_tested = at;
      }
    }
    /* A cloud's atlas holds each texel's coverage as the share of opaque
     * texels around it (dithered): a bilinear alpha test would shrink an
     * isolated opaque texel to 0.61 of its area and thin sparse leaves
     * (the Scopia palm's fronds), so its alpha is read at the nearest
     * texel of the nearest level (1), whose levels keep each block's
     * coverage (bbc_image_mipmaps); its colour stays filtered. A polygon
     * model's alpha-tested texture likewise from its first mip level on
     * (2), level 0 filtered (its leaves' edges smooth up close). */
    if (alpha_tested) b->texel_alpha = p->billboards > 0 && !b->limbs ? 1 : 2;
  }
  return 1;
}

/* The naive mode's draw calls (thesis 3.3): each billboard (consecutive
 * triangles in one plane) on its own; v, idx: the part's vertices
 * (BBCGL_VERTEX_FLOATS floats each) and indices. Without memory for them the batch has none. */
static void naive_runs(batch *b, const float *v, const uint32_t *idx) {
  b->runs = malloc((b->count / 3 + 1) * 2 * sizeof *b->runs);
  if (!b->runs) return;
  double prev[4] = {0, 0, 0, 0};
  if (b->limbs) { /* one call for the whole mesh */
    b->runs[0] = (uint32_t)b->first;
    b->runs[1] = (uint32_t)b->count;
    b->run_count = 1;
    return;
  }
  for (size_t t = 0; t < b->count / 3; t++) {
    const uint32_t *ix = idx + b->first + 3 * t;
    const float *a = v + BBCGL_VERTEX_FLOATS * ix[0], *c1 = v + BBCGL_VERTEX_FLOATS * ix[1],
                *c2 = v + BBCGL_VERTEX_FLOATS * ix[2];
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

/* The instance records: attributes 3 (x, y, z, yaw) and 4 (scale, fade) of
 * binding 1, from the instance buffer once it exists. */
static void instance_attributes(const bbcgl_forest *f, GLuint a) {
  glEnableVertexArrayAttrib(a, 3);
  glVertexArrayAttribFormat(a, 3, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(a, 3, 1);
  glEnableVertexArrayAttrib(a, 4);
  glVertexArrayAttribFormat(a, 4, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float));
  glVertexArrayAttribBinding(a, 4, 1);
  glVertexArrayBindingDivisor(a, 1, 1);
  if (f->instances && f->instance_capacity)
    glVertexArrayVertexBuffer(a, 1, f->instances, 0, sizeof(bbc_forest_draw));
}

int bbcgl_forest_add_part(bbcgl_forest *f, size_t bucket, const bbc_mesh *m,
                          const bbcgl_part_options *o, char *err) {
  size_t billboards = o->billboards;
  if (m->kind != BBC_MESH_TRIANGLES || !m->triangle_count) {
    snprintf(err, BBCGL_ERR, "a model to draw needs triangles");
    return 0;
  }
  part *p = new_part(f, bucket, m, billboards, err);
  if (!p) return 0;
  size_t groups = m->material_count ? m->material_count : 1;
  size_t *first = malloc(groups * sizeof *first), *count = malloc(groups * sizeof *count);
  p->batches = calloc(groups, sizeof *p->batches);
  float *v = NULL;
  uint32_t *idx = NULL;
  if (!first || !count || !p->batches ||
      !bbcgl__mesh_upload(m, o->occlusion, &p->vao, &p->vbo, &p->ebo, first, count, &v, &idx,
                          err)) {
    if (!first || !count || !p->batches) snprintf(err, BBCGL_ERR, "out of memory");
    free(first);
    free(count);
    free(p->batches);
    return 0;
  }
  int ok = add_batches(f, p, m, first, count, o, err);
  free(first);
  free(count);
  if (!ok) {
    free(v);
    free(idx);
    free(p->batches);
    GLuint bufs[2] = {p->vbo, p->ebo};
    glDeleteBuffers(2, bufs);
    glDeleteVertexArrays(1, &p->vao);
    return 0;
  }
  for (size_t bi = 0; bi < p->batch_count; bi++) naive_runs(&p->batches[bi], v, idx);
  free(v);
  free(idx);
  instance_attributes(f, p->vao);
  f->part_count++;
  return 1;
}
