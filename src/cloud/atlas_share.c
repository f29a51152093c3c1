/* atlas_share.c — bbc_clouds_share_atlas: the levels of detail of one model
 * in one atlas, when they fit, so an engine binds one texture for them all. */
#include "cloud.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

/* A copy of the w x h texels at (x, y) of `src`. */
static bbc_result crop(const bbc_image *src, const bbc_atlas_rect *r, bbc_image *out) {
  bbc_result res = bbc_image_alloc(out, r->width, r->height);
  if (res != BBC_OK) return res;
  for (int y = 0; y < r->height; y++)
    memcpy(out->rgba + 4 * (size_t)y * r->width,
           src->rgba + 4 * ((size_t)(r->y + y) * src->width + (size_t)r->x), 4 * (size_t)r->width);
  return BBC_OK;
}

/* A texture coordinate on an ow x oh atlas, in image rectangle `from`,
 * moved to the same place in rectangle `to` of `atlas`. */
static void move_uv(float *uv, double ow, double oh, const bbc_atlas_rect *from,
                    const bbc_atlas_rect *to, const bbc_image *atlas) {
  double x = uv[0] * ow - from->x + to->x;
  double y = (1.0 - uv[1]) * oh - from->y + to->y;
  uv[0] = (float)(x / atlas->width);
  uv[1] = (float)(1.0 - y / atlas->height);
}

/* The image rectangles of a cloud, front images then back images, as its
 * mesh lays them out (per billboard: the front fan, then the back fan). */
static size_t rect_count(const bbc_cloud *c) {
  size_t n = 0;
  for (size_t b = 0; b < c->billboard_count; b++) n += 1 + (c->billboards[b].back.width > 0);
  return n + (c->limb_triangles > 0); /* the limbs' swatch last */
}

/* Copies of every cloud's images, of each of its ntex atlases (colour,
 * normal, occlusion: layer l in imgs[l]), in the order of rect_count, and
 * their old places. */
static bbc_result crop_all(const bbc_cloud *clouds, size_t count, size_t ntex, bbc_image **imgs,
                           bbc_atlas_rect *old) {
  bbc_result r = BBC_OK;
  size_t i = 0;
  for (size_t k = 0; k < count && r == BBC_OK; k++) {
    const bbc_cloud *c = &clouds[k];
    for (size_t b = 0; b < c->billboard_count && r == BBC_OK; b++)
      for (int side = 0; side < 2 && r == BBC_OK; side++) {
        const bbc_atlas_rect *q = side ? &c->billboards[b].back : &c->billboards[b].front;
        if (side && q->width == 0) continue;
        old[i] = *q;
        for (size_t l = 0; l < ntex && r == BBC_OK; l++)
          r = crop(&c->mesh.textures[l].image, q, &imgs[l][i]);
        i++;
      }
    if (r == BBC_OK && c->limb_triangles) {
      old[i] = c->limb_swatch;
      for (size_t l = 0; l < ntex && r == BBC_OK; l++)
        r = crop(&c->mesh.textures[l].image, &c->limb_swatch, &imgs[l][i]);
      i++;
    }
  }
  return r;
}

/* Moves every vertex's texture coordinates to its image's new place; the
 * mesh holds per billboard the front fan, then the back fan. */
static void move_all_uvs(bbc_cloud *clouds, size_t count, const bbc_atlas_rect *old,
                         const bbc_atlas_rect *rects, const bbc_image *atlas) {
  size_t i = 0;
  for (size_t k = 0; k < count; k++) {
    bbc_cloud *c = &clouds[k];
    bbc_mesh *m = &c->mesh;
    double ow = m->textures[0].image.width, oh = m->textures[0].image.height;
    size_t v = 0;
    for (size_t b = 0; b < c->billboard_count; b++)
      for (int side = 0; side < 2; side++) {
        bbc_atlas_rect *q = side ? &c->billboards[b].back : &c->billboards[b].front;
        if (side && q->width == 0) continue;
        for (int corner = 0; corner < c->billboards[b].corner_count; corner++, v++) {
          if (v >= m->vertex_count) break;
          move_uv(m->uvs + 2 * v, ow, oh, &old[i], &rects[i], atlas);
        }
        *q = rects[i];
        i++;
      }
    if (c->limb_triangles) { /* the limbs: the remaining vertices, on the swatch */
      for (; v < m->vertex_count; v++) move_uv(m->uvs + 2 * v, ow, oh, &old[i], &rects[i], atlas);
      c->limb_swatch = rects[i];
      i++;
    }
  }
}

/* Each level gets its own copy of the shared atlas (writers keep one
 * image when several meshes carry the same texels). */
static bbc_result copy_atlases(bbc_cloud *clouds, size_t count, size_t ntex, const bbc_image *atlas,
                               bbc_error *err) {
  bbc_result r = BBC_OK;
  for (size_t k = 0; k < count && r == BBC_OK; k++) {
    bbc_mesh *m = &clouds[k].mesh;
    for (size_t t = 0; t < ntex && r == BBC_OK; t++) {
      const bbc_image *src = &atlas[t];
      bbc_image copy;
      r = bbc_image_alloc(&copy, src->width, src->height);
      if (r != BBC_OK) {
        r = bbc__fail(err, r, "shared atlas: out of memory");
        break;
      }
      memcpy(copy.rgba, src->rgba, 4 * (size_t)src->width * src->height);
      bbc_image_free(&m->textures[t].image);
      m->textures[t].image = copy;
    }
    bbc_cloud *c = &clouds[k];
    c->atlas_fill = (double)c->texels / ((double)atlas[0].width * atlas[0].height);
  }
  return r;
}

bbc_result bbc_clouds_share_atlas(bbc_cloud *clouds, size_t count, int max_size, int *shared,
                                  bbc_error *err) {
  assert((clouds || count == 0) && shared);
  *shared = 0;
  if (count < 2) return BBC_OK;
  size_t ntex = clouds[0].mesh.texture_count, total = 0;
  for (size_t k = 0; k < count; k++) {
    const bbc_mesh *m = &clouds[k].mesh;
    if (m->texture_count < 1 || m->texture_count > 3 || m->texture_count != ntex || !m->uvs)
      return BBC_OK; /* mixed normal or occlusion maps: not shared */
    for (size_t i = 0; i < m->material_count; i++)
      if (m->materials[i].normal_map != clouds[0].mesh.materials[0].normal_map ||
          m->materials[i].occlusion_map != clouds[0].mesh.materials[0].occlusion_map)
        return BBC_OK;
    total += rect_count(&clouds[k]);
  }
  bbc_image *imgs[3] = {NULL, NULL, NULL};
  bbc_image atlas[3] = {{0, 0, NULL}, {0, 0, NULL}, {0, 0, NULL}};
  bbc_atlas_rect *old = calloc(total, sizeof *old), *rects = calloc(total, sizeof *rects),
                 *rects2 = calloc(total, sizeof *rects2);
  bbc_result r = BBC_OK;
  int oom = !old || !rects || !rects2;
  for (size_t l = 0; l < ntex; l++) oom |= !(imgs[l] = calloc(total, sizeof *imgs[l]));
  if (oom) {
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "shared atlas: out of memory");
    goto done;
  }
  r = crop_all(clouds, count, ntex, imgs, old);
  if (r != BBC_OK) {
    r = bbc__fail(err, r, "shared atlas: out of memory");
    goto done;
  }
  /* Does it fit? Not fitting is no error: the levels keep their atlases
   * (out of memory is). */
  bbc_error quiet;
  bbc_result fit = bbc_atlas_pack(imgs[0], total, 2, max_size, &atlas[0], rects, &quiet);
  if (fit == BBC_ERROR_OUT_OF_MEMORY) r = bbc__fail(err, fit, "%s", quiet.message);
  if (fit != BBC_OK) goto done;
  for (size_t l = 1; l < ntex; l++) {
    r = bbc_atlas_pack(imgs[l], total, 2, max_size, &atlas[l], rects2, err);
    if (r == BBC_OK && memcmp(rects, rects2, total * sizeof *rects))
      r = bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "shared atlas: layouts differ");
    if (r != BBC_OK) goto done;
  }
  move_all_uvs(clouds, count, old, rects, &atlas[0]);
  r = copy_atlases(clouds, count, ntex, atlas, err);
  *shared = r == BBC_OK;
done:
  for (size_t l = 0; l < 3; l++) {
    for (size_t q = 0; q < total && imgs[l]; q++) bbc_image_free(&imgs[l][q]);
    free(imgs[l]);
    bbc_image_free(&atlas[l]);
  }
  free(old);
  free(rects);
  free(rects2);
  return r;
}
