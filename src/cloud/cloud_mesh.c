/* cloud_mesh.c — step 3's last stages: the billboards' images packed into
 * one atlas (and the normal maps, 2.3.1, into a second of the same layout),
 * and the cloud's mesh: each billboard's outline as a fan (twice with back
 * images), then the limbs' mesh (`limbs`) on the swatch of their colour. */
#include "cloud.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The mesh's arrays for the billboards' fans (`sides` each) and the limbs'
 * mesh; tangents with a normal atlas. */
static bbc_result mesh_alloc(const bbc_planeset *set, const bbc_cloud *cl, int sides, int tangents,
                             const bbc_mesh *limbs, bbc_mesh *me, bbc_error *err) {
  size_t nv = limbs->vertex_count, nt = limbs->triangle_count;
  for (size_t k = 0; k < cl->billboard_count; k++) {
    nv += (size_t)sides * cl->billboards[k].corner_count;
    nt += (size_t)sides * (cl->billboards[k].corner_count - 2);
  }
  me->kind = BBC_MESH_TRIANGLES;
  me->vertex_count = nv;
  me->triangle_count = nt;
  me->positions = malloc(3 * nv * sizeof *me->positions);
  me->normals = malloc(3 * nv * sizeof *me->normals);
  me->uvs = malloc(2 * nv * sizeof *me->uvs);
  if (tangents) me->tangents = malloc(4 * nv * sizeof *me->tangents);
  me->indices = malloc(3 * nt * sizeof *me->indices);
  me->face_material = calloc(nt, sizeof *me->face_material);
  me->face_group = malloc(nt * sizeof *me->face_group);
  me->materials = calloc(2, sizeof *me->materials);
  me->textures = calloc(3, sizeof *me->textures);
  me->group_names = calloc(set->part_count, sizeof *me->group_names);
  if (!me->positions || !me->normals || !me->uvs || (tangents && !me->tangents) || !me->indices ||
      !me->face_material || !me->face_group || !me->materials || !me->textures || !me->group_names)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  return BBC_OK;
}

/* The materials ("billboards", and "limbs" when there are limbs), the
 * atlases as the textures (moved into the mesh) and a group per part. */
static bbc_result mesh_materials(const bbc_planeset *set, const bbc_params *prm, bbc_mesh *me,
                                 bbc_image *atlas, bbc_image *nm_atlas, bbc_image *ao_atlas,
                                 const bbc_mesh *limbs, bbc_error *err) {
  me->material_count = 1;
  bbc_material *mat = &me->materials[0];
  mat->name = bbc__strdup("billboards");
  mat->texture = 0;
  mat->single_sided = prm->back_images;
  for (int c = 0; c < 4; c++) mat->base_color[c] = 1.0f;
  me->texture_count = 1;
  me->textures[0].image = *atlas;
  me->textures[0].has_alpha = bbc_image_has_transparency(atlas);
  memset(atlas, 0, sizeof *atlas);
  if (nm_atlas) {
    me->textures[me->texture_count++].image = *nm_atlas;
    memset(nm_atlas, 0, sizeof *nm_atlas);
    mat->normal_map = (int)me->texture_count;
  }
  if (ao_atlas) {
    me->textures[me->texture_count++].image = *ao_atlas;
    memset(ao_atlas, 0, sizeof *ao_atlas);
    mat->occlusion_map = (int)me->texture_count;
  }
  me->group_count = set->part_count;
  for (size_t g = 0; g < set->part_count; g++) {
    me->group_names[g] = bbc__strdup(set->parts[g].name);
    if (!me->group_names[g]) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  if (!mat->name) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  if (limbs->triangle_count) {
    /* The limbs: their own material "limbs" (the same atlas, both sides: a
     * simplified tube may open), so that readers tell them from billboards
     * (forest draws them in one call). */
    bbc_material *lm = &me->materials[1];
    *lm = *mat;
    lm->name = bbc__strdup("limbs");
    lm->single_sided = 0;
    me->material_count = 2;
    if (!lm->name) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  return BBC_OK;
}

/* Each billboard's outline as a fan per side (the back one reversed), its
 * texture coordinates in its image's place on the aw x ah atlas. *v, *t:
 * the next vertex and triangle. */
static void billboard_fans(const bbc_cloud *cl, int sides, double aw, double ah, bbc_mesh *me,
                           size_t *vp, size_t *tp) {
  size_t v = *vp, t = *tp;
  for (size_t k = 0; k < cl->billboard_count; k++) {
    const bbc_cloud_billboard *cb = &cl->billboards[k];
    const bbc_billboard *b = &cb->rect;
    int nc = cb->corner_count;
    for (int side = 0; side < sides; side++) {
      const bbc_atlas_rect *rc = side ? &cb->back : &cb->front;
      double sign = side ? -1.0 : 1.0;
      size_t base = v;
      for (int c = 0; c < nc; c++, v++) {
        double s = cb->corners[c][0], tt = cb->corners[c][1];
        for (int j = 0; j < 3; j++) {
          me->positions[3 * v + j] =
              b->origin[j] + s * b->width * b->u[j] + tt * b->height * b->w[j];
          me->normals[3 * v + j] = (float)(sign * cb->normal[j]);
          if (me->tangents) me->tangents[4 * v + j] = (float)b->u[j];
        }
        if (me->tangents) me->tangents[4 * v + 3] = (float)sign;
        /* Image rows run top first; v = 0 is the image's bottom row. */
        me->uvs[2 * v] = (float)((rc->x + s * rc->width) / aw);
        me->uvs[2 * v + 1] = (float)(1.0 - (rc->y + (1 - tt) * rc->height) / ah);
      }
      for (int c = 1; c + 1 < nc; c++, t++) {
        uint32_t a = (uint32_t)base, b1 = (uint32_t)(base + c), b2 = (uint32_t)(base + c + 1);
        me->indices[3 * t] = a;
        me->indices[3 * t + 1] = side ? b2 : b1;
        me->indices[3 * t + 2] = side ? b1 : b2;
        me->face_group[t] = cb->part;
      }
    }
  }
  *vp = v;
  *tp = t;
}

/* The limbs' mesh from vertex v and triangle t on: every vertex at the
 * swatch's centre texel, material 1, part limbs_group. */
static void limbs_mesh(const bbc_mesh *limbs, const bbc_atlas_rect *swatch, uint32_t limbs_group,
                       double aw, double ah, bbc_mesh *me, size_t v, size_t t) {
  float su = swatch ? (float)((swatch->x + 0.5 * swatch->width) / aw) : 0;
  float sv = swatch ? (float)(1.0 - (swatch->y + 0.5 * swatch->height) / ah) : 0;
  size_t v0 = v;
  for (size_t i = 0; i < limbs->vertex_count; i++, v++) {
    const float *n = limbs->normals + 3 * i;
    for (int j = 0; j < 3; j++) {
      me->positions[3 * v + j] = limbs->positions[3 * i + j];
      me->normals[3 * v + j] = n[j];
    }
    me->uvs[2 * v] = su;
    me->uvs[2 * v + 1] = sv;
    if (me->tangents) { /* any unit tangent across the normal (the swatch is flat) */
      int a = fabsf(n[0]) < 0.6f ? 0 : fabsf(n[1]) < 0.6f ? 1 : 2;
      float e[3] = {0, 0, 0}, tg[3];
      e[a] = 1;
      float d = n[0] * e[0] + n[1] * e[1] + n[2] * e[2];
      for (int j = 0; j < 3; j++) tg[j] = e[j] - d * n[j];
      float l = sqrtf(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
      for (int j = 0; j < 3; j++) me->tangents[4 * v + j] = l > 0 ? tg[j] / l : (float)e[j];
      me->tangents[4 * v + 3] = 1;
    }
  }
  for (size_t i = 0; i < limbs->triangle_count; i++, t++) {
    for (int c = 0; c < 3; c++) me->indices[3 * t + c] = (uint32_t)(v0 + limbs->indices[3 * i + c]);
    me->face_group[t] = limbs_group;
    me->face_material[t] = 1;
  }
}

#ifndef NDEBUG
/* Whether every index names a vertex, every face a material, and every
 * texture coordinate lies in the atlas (debug builds only). */
static int mesh_indices_valid(const bbc_mesh *me) {
  for (size_t i = 0; i < 3 * me->triangle_count; i++)
    if (me->indices[i] >= me->vertex_count) return 0;
  for (size_t t = 0; t < me->triangle_count; t++)
    if (me->face_material[t] >= me->material_count) return 0;
  for (size_t i = 0; i < 2 * me->vertex_count; i++)
    if (!(me->uvs[i] >= -1e-6f && me->uvs[i] <= 1 + 1e-6f)) return 0;
  return 1;
}
#endif

/* The cloud's mesh: each billboard's outline (twice with back images), then
 * the limbs' mesh (`limbs`, may be empty) textured by the swatch. */
static bbc_result build_mesh(const bbc_planeset *set, const bbc_params *prm, bbc_cloud *cl,
                             bbc_image *atlas, bbc_image *nm_atlas, bbc_image *ao_atlas,
                             const bbc_mesh *limbs, const bbc_atlas_rect *swatch,
                             uint32_t limbs_group, bbc_error *err) {
  bbc_mesh *me = &cl->mesh;
  int sides = prm->back_images ? 2 : 1;
  bbc_result r = mesh_alloc(set, cl, sides, nm_atlas != NULL, limbs, me, err);
  if (r == BBC_OK) r = mesh_materials(set, prm, me, atlas, nm_atlas, ao_atlas, limbs, err);
  if (r != BBC_OK) return r;
  double aw = me->textures[0].image.width, ah = me->textures[0].image.height;
  size_t v = 0, t = 0;
  billboard_fans(cl, sides, aw, ah, me, &v, &t);
  limbs_mesh(limbs, swatch, limbs_group, aw, ah, me, v, t);
  assert(v + limbs->vertex_count == me->vertex_count &&
         t + limbs->triangle_count == me->triangle_count); /* mesh_alloc's counts, filled */
  assert(mesh_indices_valid(me));
  cl->limb_triangles = limbs->triangle_count;
  if (swatch && limbs->triangle_count) cl->limb_swatch = *swatch;
  return BBC_OK;
}

/* softalpha: inside each of the n rectangles of the atlas, a texel whose
 * 8 neighbours (those inside the rectangle) hold k of the other state gets
 * its alpha moved towards the other side by 50 (8 - k) / 7 (0 for k = 0):
 * transparent texels next to an opaque one up to 50, opaque ones next to a
 * transparent one down to 205, so that a client's bilinear filter with an
 * alpha test at 0.5 keeps an isolated texel's area (it keeps 0.61 of it at
 * 0 and 255: the dithered, sparse parts of a crown thinned by 40 %) while
 * the test itself, and every nearest-sampling reader, sees the same mask.
 * Simulated over Floyd-Steinberg masks of 5-90 % coverage: 0.96-1.04 of
 * their coverage kept by bilinear alpha testing against 0.63-1.04 at 0/255
 * (test_soft_alpha measures isolated texels). */
static bbc_result soften_alpha(bbc_image *atlas, const bbc_atlas_rect *rects, size_t n) {
  for (size_t i = 0; i < n; i++) {
    const bbc_atlas_rect *rc = &rects[i];
    int w = rc->width, h = rc->height;
    if (w <= 0 || h <= 0) continue;
    uint8_t *on = malloc((size_t)w * h);
    if (!on) return BBC_ERROR_OUT_OF_MEMORY;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++)
        on[(size_t)y * w + x] =
            atlas->rgba[4 * ((size_t)(rc->y + y) * atlas->width + (size_t)(rc->x + x)) + 3] >= 128;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        int self = on[(size_t)y * w + x], k = 0;
        for (int dy = -1; dy <= 1; dy++)
          for (int dx = -1; dx <= 1; dx++) {
            int xx = x + dx, yy = y + dy;
            if ((dx || dy) && xx >= 0 && xx < w && yy >= 0 && yy < h)
              k += on[(size_t)yy * w + xx] != self;
          }
        if (!k) continue;
        int shift = (50 * (8 - k) + 3) / 7;
        uint8_t *a =
            &atlas->rgba[4 * ((size_t)(rc->y + y) * atlas->width + (size_t)(rc->x + x)) + 3];
        *a = (uint8_t)(self ? 255 - shift : shift);
      }
    free(on);
  }
  return BBC_OK;
}

/* The atlas: front images then back images, the swatch last (imgs and
 * rects: room for ni). Each billboard's places, the cloud's texels and how
 * full the atlas is. */
static bbc_result pack_atlas(const bbc_params *prm, bbc_cloud *cl, const bbc__baked *bk,
                             const bbc_image swatch[3], int atlas_limit, bbc_image *imgs, size_t ni,
                             bbc_image *atlas, bbc_atlas_rect *rects, bbc_error *err) {
  int sides = prm->back_images ? 2 : 1;
  size_t nk = cl->billboard_count;
  for (size_t k = 0; k < nk; k++) {
    imgs[k] = bk[k].front;
    if (sides == 2) imgs[nk + k] = bk[k].back;
  }
  if (swatch[0].rgba) imgs[ni - 1] = swatch[0];
  bbc_result r = bbc_atlas_pack(imgs, ni, 2, atlas_limit, atlas, rects, err);
  if (r == BBC_OK && prm->soft_alpha && soften_alpha(atlas, rects, (size_t)sides * nk) != BBC_OK)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK) {
    for (size_t k = 0; k < nk; k++) {
      cl->billboards[k].front = rects[k];
      if (sides == 2) cl->billboards[k].back = rects[nk + k];
      cl->texels += (size_t)sides * bk[k].front.width * bk[k].front.height;
    }
    if (swatch[0].rgba) cl->texels += (size_t)swatch[0].width * swatch[0].height;
    cl->atlas_fill = (double)cl->texels / ((double)atlas->width * atlas->height);
  }
  return r;
}

/* A second atlas of the same layout: the normal maps (layer 1) or the
 * occlusion images (layer 2) packed as pack_atlas packed the colour
 * images, which have the same sizes in the same order (checked). */
static bbc_result pack_layer_atlas(const bbc_params *prm, const bbc_cloud *cl, const bbc__baked *bk,
                                   int layer, const bbc_image swatch[3], int atlas_limit,
                                   bbc_image *imgs, size_t ni, const bbc_image *atlas,
                                   const bbc_atlas_rect *rects, bbc_image *out, bbc_error *err) {
  int sides = prm->back_images ? 2 : 1;
  size_t nk = cl->billboard_count;
  bbc_result r = BBC_OK;
  for (size_t k = 0; k < nk; k++) {
    imgs[k] = layer == 1 ? bk[k].front_nm : bk[k].front_ao;
    if (sides == 2) imgs[nk + k] = layer == 1 ? bk[k].back_nm : bk[k].back_ao;
  }
  if (swatch[0].rgba) imgs[ni - 1] = swatch[layer];
  bbc_atlas_rect *r2 = calloc(ni, sizeof *r2);
  if (!r2) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK) r = bbc_atlas_pack(imgs, ni, 2, atlas_limit, out, r2, err);
  if (r == BBC_OK && (out->width != atlas->width || out->height != atlas->height ||
                      memcmp(r2, rects, ni * sizeof *r2)))
    r = bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "step 3: the %s atlas's layout differs",
                  layer == 1 ? "normal" : "occlusion");
  free(r2);
  return r;
}

bbc_result bbc__cloud_atlas_mesh(const bbc_planeset *set, const bbc_params *prm, bbc_cloud *cl,
                                 const bbc__baked *bk, const bbc_image swatch[3],
                                 const bbc_mesh *limbs, uint32_t limbs_group, int atlas_limit,
                                 bbc_error *err) {
  int sides = prm->back_images ? 2 : 1;
  size_t ni = (size_t)sides * cl->billboard_count + (swatch[0].rgba ? 1 : 0); /* the swatch last */
  bbc_image atlas = {0, 0, NULL}, nm_atlas = {0, 0, NULL}, ao_atlas = {0, 0, NULL};
  int ao = bk && cl->billboard_count && bk[0].front_ao.rgba;
  bbc_result r = BBC_OK;
  bbc_image *imgs = calloc(ni, sizeof *imgs);
  bbc_atlas_rect *rects = calloc(ni, sizeof *rects);
  if (!imgs || !rects) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK) r = pack_atlas(prm, cl, bk, swatch, atlas_limit, imgs, ni, &atlas, rects, err);
  if (r == BBC_OK && prm->normal_maps)
    r = pack_layer_atlas(prm, cl, bk, 1, swatch, atlas_limit, imgs, ni, &atlas, rects, &nm_atlas,
                         err);
  if (r == BBC_OK && ao)
    r = pack_layer_atlas(prm, cl, bk, 2, swatch, atlas_limit, imgs, ni, &atlas, rects, &ao_atlas,
                         err);
  if (r == BBC_OK)
    r = build_mesh(set, prm, cl, &atlas, prm->normal_maps ? &nm_atlas : NULL, ao ? &ao_atlas : NULL,
                   limbs, swatch[0].rgba ? &rects[ni - 1] : NULL, limbs_group, err);
  if (r == BBC_OK) r = bbc_mesh_finalize(&cl->mesh, 0, "billboard cloud", err);
  bbc_image_free(&atlas);
  bbc_image_free(&nm_atlas);
  bbc_image_free(&ao_atlas);
  free(imgs);
  free(rects);
  return r;
}
