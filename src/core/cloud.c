/* cloud.c — step 3, first version: billboards baked with the software
 * rasterizer, packed into one atlas, assembled as a mesh of quads
 * (thesis 2.1.9, 2.2.5, 2.3.5, 2.3.9). */
#include "dual.h"

#include <stdlib.h>
#include <string.h>

static int floor_pow2(double x) {
  int p = 1;
  while (p * 2 <= x && p < (1 << 14)) p *= 2;
  return p;
}

/* Renders the faces within +-eps of the billboard's plane, seen from the
 * front (from the side the normal points to), into img (w x h texels). */
static bbc_result bake_front(const bbc_mesh *m, const bbc_billboard *b, const bbc_plane *p,
                             double eps, const uint8_t *mask, int lighting, int w, int h,
                             bbc_image *img, bbc_error *err) {
  bbc_result r = bbc_image_alloc(img, w, h);
  if (r != BBC_OK) return bbc__fail(err, r, "baking: out of memory for a %dx%d texture", w, h);
  bbc_view v;
  memset(&v, 0, sizeof v);
  for (int k = 0; k < 3; k++) {
    v.direction[k] = -p->normal[k];
    v.up[k] = b->w[k];
    v.center[k] = b->origin[k] + 0.5 * b->width * b->u[k] + 0.5 * b->height * b->w[k];
  }
  /* Degenerate (single-point or single-line) rectangles still get a texel. */
  v.half_extent = 0.5 * (b->width > 0 ? b->width : eps);
  v.half_extent_y = 0.5 * (b->height > 0 ? b->height : eps);
  v.depth_min = -eps;
  v.depth_max = eps;
  v.face_mask = mask;
  v.lighting = lighting;
  r = bbc_render_ortho(m, &v, img, err);
  if (r != BBC_OK) bbc_image_free(img);
  return r;
}

/* quality 2 (2.3.9): a texel is opaque when any of its k x k samples is, with
 * the mean colour of the opaque samples, so small leaves do not vanish and
 * alpha stays 0 or 255. */
static bbc_result downsample_grow(const bbc_image *src, int k, bbc_image *dst) {
  bbc_result r = bbc_image_alloc(dst, src->width / k, src->height / k);
  if (r != BBC_OK) return r;
  for (int y = 0; y < dst->height; y++)
    for (int x = 0; x < dst->width; x++) {
      unsigned sum[3] = {0, 0, 0}, n = 0;
      for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
          const uint8_t *s = src->rgba + 4 * ((size_t)(y * k + j) * src->width + (x * k + i));
          if (s[3] < 128) continue;
          for (int c = 0; c < 3; c++) sum[c] += s[c];
          n++;
        }
      uint8_t *d = dst->rgba + 4 * ((size_t)y * dst->width + x);
      if (n) {
        for (int c = 0; c < 3; c++) d[c] = (uint8_t)((sum[c] + n / 2) / n);
        d[3] = 255;
      }
    }
  return BBC_OK;
}

bbc_result bbc_cloud_build(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                           bbc_mesh *cloud, bbc_error *err) {
  memset(cloud, 0, sizeof *cloud);
  size_t np = set->plane_count, nf = set->face_count;
  bbc_billboard *bb = calloc(np ? np : 1, sizeof *bb);
  uint8_t *keep = calloc(np ? np : 1, 1), *mask = malloc(nf ? nf : 1);
  bbc_image *imgs = calloc(np ? np : 1, sizeof *imgs);
  bbc_atlas_rect *rects = calloc(np ? np : 1, sizeof *rects);
  size_t *order = malloc((np ? np : 1) * sizeof *order);
  bbc_image atlas;
  memset(&atlas, 0, sizeof atlas);
  bbc_result r = BBC_OK;
  if (!bb || !keep || !mask || !imgs || !rects || !order)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK) r = bbc_billboards_compute(m, set, bb, err);
  /* Which planes get a billboard (2.3.5, 2.3.7). */
  size_t nk = 0;
  double longest = 0;
  if (r == BBC_OK) {
    for (size_t i = 0; i < np; i++) {
      const bbc_plane *p = &set->planes[i];
      double largest = 0;
      for (size_t j = 0; j < np; j++)
        if (set->planes[j].part == p->part && set->planes[j].kind != BBC_PLANE_CARDBOARD &&
            set->planes[j].area > largest)
          largest = set->planes[j].area;
      if (p->kind == BBC_PLANE_CARDBOARD)
        keep[i] = p->coverage_pct >= prm->cb_coverage_pct;
      else
        keep[i] = p->area >= prm->poly_skip_pct / 100.0 * largest;
      if (keep[i]) {
        order[nk++] = i;
        if (bb[i].width > longest) longest = bb[i].width;
      }
    }
    if (nk == 0) r = bbc__fail(err, BBC_ERROR_EMPTY, "step 3: every plane was skipped");
  }
  /* Bake (2.1.9): the longest side gets texres texels. */
  int ss = prm->quality >= 2 ? 4 : 1;
  for (size_t k = 0; r == BBC_OK && k < nk; k++) {
    size_t i = order[k];
    const bbc_plane *p = &set->planes[i];
    double texel = longest / prm->texres;
    int w = floor_pow2(bb[i].width / texel), h = floor_pow2(bb[i].height / texel);
    if (w < 4) w = 4;
    if (h < 4) h = 4;
    uint32_t owner = p->kind == BBC_PLANE_CARDBOARD ? (uint32_t)p->mother : (uint32_t)i;
    for (size_t t = 0; t < nf; t++) mask[t] = !prm->pure || set->face_plane[t] == owner;
    double eps = set->parts[p->part].epsilon_abs;
    bbc_image big;
    r = bake_front(m, &bb[i], p, eps, mask, prm->prelight, w * ss, h * ss, &big, err);
    if (r != BBC_OK) break;
    if (prm->quality == 2) {
      r = downsample_grow(&big, ss, &imgs[k]);
      bbc_image_free(&big);
      if (r != BBC_OK) r = bbc__fail(err, r, "step 3: out of memory");
    } else {
      imgs[k] = big;
    }
  }
  if (r == BBC_OK) r = bbc_atlas_pack(imgs, nk, 2, 16384, &atlas, rects, err);
  /* The cloud: one quad per billboard. */
  if (r == BBC_OK) {
    cloud->kind = BBC_MESH_TRIANGLES;
    cloud->vertex_count = 4 * nk;
    cloud->triangle_count = 2 * nk;
    cloud->positions = malloc(12 * nk * sizeof *cloud->positions);
    cloud->normals = malloc(12 * nk * sizeof *cloud->normals);
    cloud->uvs = malloc(8 * nk * sizeof *cloud->uvs);
    cloud->indices = malloc(6 * nk * sizeof *cloud->indices);
    cloud->face_material = calloc(2 * nk, sizeof *cloud->face_material);
    cloud->face_group = malloc(2 * nk * sizeof *cloud->face_group);
    cloud->materials = calloc(1, sizeof *cloud->materials);
    cloud->textures = calloc(1, sizeof *cloud->textures);
    cloud->group_names = calloc(set->part_count, sizeof *cloud->group_names);
    if (!cloud->positions || !cloud->normals || !cloud->uvs || !cloud->indices ||
        !cloud->face_material || !cloud->face_group || !cloud->materials || !cloud->textures ||
        !cloud->group_names)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  }
  if (r == BBC_OK) {
    cloud->material_count = 1;
    cloud->materials[0].name = bbc__strdup("billboards");
    cloud->materials[0].texture = 0;
    for (int c = 0; c < 4; c++) cloud->materials[0].base_color[c] = 1.0f;
    cloud->texture_count = 1;
    cloud->textures[0].image = atlas;
    cloud->textures[0].has_alpha = bbc_image_has_transparency(&atlas);
    memset(&atlas, 0, sizeof atlas);
    cloud->group_count = set->part_count;
    for (size_t g = 0; g < set->part_count; g++)
      cloud->group_names[g] = bbc__strdup(set->parts[g].name);
    double aw = cloud->textures[0].image.width, ah = cloud->textures[0].image.height;
    for (size_t k = 0; k < nk; k++) {
      const bbc_billboard *b = &bb[order[k]];
      const bbc_plane *p = &set->planes[order[k]];
      static const double st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int c = 0; c < 4; c++) {
        size_t v = 4 * k + (size_t)c;
        for (int j = 0; j < 3; j++) {
          cloud->positions[3 * v + j] =
              b->origin[j] + st[c][0] * b->width * b->u[j] + st[c][1] * b->height * b->w[j];
          cloud->normals[3 * v + j] = (float)p->normal[j];
        }
        /* Image rows run top first; v = 0 is the image's bottom row. */
        const bbc_atlas_rect *rc = &rects[k];
        cloud->uvs[2 * v] = (float)((rc->x + st[c][0] * rc->width) / aw);
        cloud->uvs[2 * v + 1] = (float)(1.0 - (rc->y + (1 - st[c][1]) * rc->height) / ah);
      }
      uint32_t base = (uint32_t)(4 * k);
      const uint32_t q[6] = {base, base + 1, base + 2, base, base + 2, base + 3};
      memcpy(cloud->indices + 6 * k, q, sizeof q);
      cloud->face_group[2 * k] = cloud->face_group[2 * k + 1] = p->part;
    }
    if (!cloud->materials[0].name) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
    if (r == BBC_OK) r = bbc_mesh_finalize(cloud, 0, "billboard cloud", err);
  }
  for (size_t k = 0; k < nk; k++) bbc_image_free(&imgs[k]);
  bbc_image_free(&atlas);
  free(bb);
  free(keep);
  free(mask);
  free(imgs);
  free(rects);
  free(order);
  if (r != BBC_OK) bbc_mesh_free(cloud);
  return r;
}
