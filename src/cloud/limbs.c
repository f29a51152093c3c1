/* limbs.c — beyond the thesis: the trunk part kept as a small mesh inside
 * the cloud (`limbs`). A stem and its limbs are thin cylinders: on
 * billboards they are lines from the sides those planes are seen edge-on
 * (a conifer's whorls lie on near-horizontal planes, so from the side its
 * limbs vanish) and up to epsilon off their place. As a mesh they hold from
 * every side at their place. The trunk part's faces (those no plane
 * simplifies, BBC_NO_PLANE) are welded by position and simplified with
 * meshoptimizer (edge collapses keeping the topology; where that stops
 * above the budget, clustering on the result) to at most `target`
 * triangles, with smooth normals. Their colour: a swatch in the atlas. */
#include "cloud.h"
#include "raster.h"

#include <math.h>
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

bbc_result bbc__limbs_build(const bbc_mesh *m, const bbc_planeset *set, int target, bbc_mesh *out,
                            bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (m->kind != BBC_MESH_TRIANGLES || target <= 0 || set->face_count != m->triangle_count)
    return BBC_OK;
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; t++) n += set->face_plane[t] == BBC_NO_PLANE;
  if (!n) return BBC_OK;
  /* The part's triangles on their own vertices (float, as meshoptimizer
   * takes them), then one vertex per position. */
  size_t ni = 3 * n;
  unsigned *idx = malloc(ni * sizeof *idx), *welded = malloc(ni * sizeof *welded);
  unsigned *remap = malloc(ni * sizeof *remap), *res = malloc(ni * sizeof *res);
  float *pos = malloc(3 * ni * sizeof *pos), *upos = malloc(3 * ni * sizeof *upos);
  bbc_result r = BBC_OK;
  if (!idx || !welded || !remap || !res || !pos || !upos)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "limbs: out of memory");
  size_t nu = 0, got = 0;
  if (r == BBC_OK) {
    size_t k = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
      if (set->face_plane[t] != BBC_NO_PLANE) continue;
      for (int c = 0; c < 3; c++, k++) {
        const double *p = m->positions + 3 * (size_t)m->indices[3 * t + c];
        for (int j = 0; j < 3; j++) pos[3 * k + j] = (float)p[j];
        idx[k] = (unsigned)k;
      }
    }
    nu = meshopt_generateVertexRemap(remap, idx, ni, pos, ni, 3 * sizeof *pos);
    meshopt_remapIndexBuffer(welded, idx, ni, remap);
    meshopt_remapVertexBuffer(upos, pos, ni, 3 * sizeof *pos, remap);
    size_t want = 3 * (size_t)target;
    if (ni <= want) {
      memcpy(res, welded, ni * sizeof *res);
      got = ni;
    } else {
      got = meshopt_simplify(res, welded, ni, upos, nu, 3 * sizeof *upos, want, 1.0f, 0, NULL);
      if (got > want) { /* the topology held it back: cluster what is left */
        memcpy(idx, res, got * sizeof *idx);
        got = meshopt_simplifySloppy(res, idx, got, upos, nu, 3 * sizeof *upos, want, 1.0f, NULL);
      }
    }
  }
  /* Only the vertices still used, in first-use order. */
  size_t nv = 0;
  if (r == BBC_OK) {
    for (size_t v = 0; v < nu; v++) remap[v] = UINT32_MAX;
    for (size_t i = 0; i < got; i++)
      if (remap[res[i]] == UINT32_MAX) remap[res[i]] = (unsigned)nv++;
    out->kind = BBC_MESH_TRIANGLES;
    out->vertex_count = nv;
    out->triangle_count = got / 3;
    out->positions = malloc((nv ? nv : 1) * 3 * sizeof *out->positions);
    out->indices = malloc((got ? got : 1) * sizeof *out->indices);
    out->face_material = calloc(got / 3 + 1, sizeof *out->face_material);
    out->face_group = malloc((got / 3 + 1) * sizeof *out->face_group);
    out->materials = calloc(1, sizeof *out->materials);
    out->group_names = calloc(1, sizeof *out->group_names);
    /* counted at once, so that bbc_mesh_free frees the names on failure */
    if (out->materials) {
      out->material_count = 1;
      out->materials[0].name = bbc__strdup("limbs");
    }
    if (out->group_names) {
      out->group_count = 1;
      out->group_names[0] = bbc__strdup("trunk");
    }
    if (!out->positions || !out->indices || !out->face_material || !out->face_group ||
        !out->materials || !out->group_names || !out->materials[0].name || !out->group_names[0])
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "limbs: out of memory");
  }
  if (r == BBC_OK) {
    out->materials[0].texture = -1;
    for (int c = 0; c < 4; c++) out->materials[0].base_color[c] = 1.0f;
    for (size_t v = 0; v < nu; v++)
      if (remap[v] != UINT32_MAX)
        for (int j = 0; j < 3; j++) out->positions[3 * (size_t)remap[v] + j] = upos[3 * v + j];
    for (size_t i = 0; i < got; i++) out->indices[i] = remap[res[i]];
    for (size_t t = 0; t < got / 3; t++) out->face_group[t] = 0;
    if (got) r = bbc_mesh_finalize(out, 1, "limbs", err);
  }
  free(idx);
  free(welded);
  free(remap);
  free(res);
  free(pos);
  free(upos);
  if (r != BBC_OK || !out->triangle_count) bbc_mesh_free(out);
  if (r != BBC_OK) memset(out, 0, sizeof *out);
  return r;
}

int bbc__limbs_part(const bbc_planeset *set, uint32_t *part) {
  for (size_t pi = 0; pi < set->part_count; pi++)
    if (set->parts[pi].limbs > 0) {
      if (part) *part = (uint32_t)pi;
      return set->parts[pi].limbs;
    }
  return 0;
}

/* The limbs' colour: their original faces baked as the stem billboards
 * are (prelit by a headlight from the side, textures at the distance of a
 * 64-texel image), seen from two sides, averaged over what they cover. */
static bbc_result limb_colour(const bbc__bake_inputs *in, uint8_t rgba[4]) {
  const bbc_mesh *m = in->mesh;
  const bbc_planeset *set = in->set;
  const bbc_params *prm = in->params;
  enum { SIDE = 64 };
  uint32_t *faces = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *faces);
  uint8_t *img = malloc(4 * SIDE * SIDE);
  if (!faces || !img) {
    free(faces);
    free(img);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; t++) {
    if (set->face_plane[t] != BBC_NO_PLANE) continue;
    faces[n++] = (uint32_t)t;
    for (int c = 0; c < 3; c++)
      for (int k = 0; k < 3; k++) {
        double x = m->positions[3 * (size_t)m->indices[3 * t + c] + k];
        lo[k] = fmin(lo[k], x);
        hi[k] = fmax(hi[k], x);
      }
  }
  double sum[3] = {0, 0, 0}, weight = 0;
  int up = prm->up_axis >= 0 && prm->up_axis <= 2 ? prm->up_axis : 1;
  bbc_result r = BBC_OK;
  for (int side = 0; n && r == BBC_OK && side < 2; side++) {
    int ax = (up + 1 + side) % 3, across = (up + 2 - side) % 3;
    bbc_view v;
    memset(&v, 0, sizeof v);
    v.direction[ax] = -1;
    v.up[up] = 1;
    for (int k = 0; k < 3; k++) v.center[k] = 0.5 * (lo[k] + hi[k]);
    v.half_extent = fmax(0.5 * (hi[across] - lo[across]), 1e-9);
    v.half_extent_y = fmax(0.5 * (hi[up] - lo[up]), 1e-9);
    v.lighting = prm->prelight;
    v.headlight = 1;
    v.light_gain = 1;
    v.ambient = prm->viewer_ambient;
    v.vertex_shade = in->vshade;
    bbc__bake bk;
    memset(&bk, 0, sizeof bk);
    bk.width = bk.height = SIDE;
    bk.front = img;
    bk.mips = in->mips;
    bk.alpha_bits = in->alpha_bits;
    memset(img, 0, 4 * SIDE * SIDE);
    bbc_error quiet;
    r = bbc__render_bake(m, faces, n, &v, &bk, &quiet);
    if (r == BBC_ERROR_OUT_OF_MEMORY) break;
    if (r != BBC_OK) { /* a side it cannot see: the other's colour, else grey */
      r = BBC_OK;
      continue;
    }
    for (size_t i = 0; i < (size_t)SIDE * SIDE; i++) {
      double a = img[4 * i + 3] / 255.0;
      for (int c = 0; c < 3; c++) sum[c] += a * img[4 * i + c];
      weight += a;
    }
  }
  for (int c = 0; c < 3; c++) rgba[c] = (uint8_t)(weight > 0 ? sum[c] / weight + 0.5 : 128);
  rgba[3] = 255;
  free(faces);
  free(img);
  return r;
}

/* The mean voxel shadowing of the faces the limbs' mesh replaces. */
static uint8_t limb_occlusion(const bbc__bake_inputs *in) {
  const bbc_mesh *m = in->mesh;
  double sum = 0;
  size_t n = 0;
  for (size_t t = 0; in->vshade && t < m->triangle_count; t++) {
    if (in->set->face_plane[t] != BBC_NO_PLANE) continue;
    for (int c = 0; c < 3; c++) sum += in->vshade[m->indices[3 * t + c]];
    n += 3;
  }
  double a = n ? sum / (double)n : 1.0;
  return (uint8_t)(a >= 1 ? 255 : a <= 0 ? 0 : a * 255.0 + 0.5);
}

bbc_result bbc__limbs_stage(const bbc__bake_inputs *in, const bbc_cloud *cl, int limbs_target,
                            bbc_mesh *limbs, bbc_image swatch[3], bbc_error *err) {
  const bbc_params *prm = in->params;
  size_t nk = cl->billboard_count;
  /* At most `limbs` triangles, and at most 4 times the billboards' (at
   * least 16): a coarse level of a chain keeps its weight. */
  size_t bt = 0;
  for (size_t k = 0; k < nk; k++)
    bt += (size_t)(prm->back_images ? 2 : 1) * (size_t)(cl->billboards[k].corner_count - 2);
  if ((size_t)limbs_target > 4 * bt) limbs_target = (int)(4 * bt < 16 ? 16 : 4 * bt);
  bbc_result r = bbc__limbs_build(in->mesh, in->set, limbs_target, limbs, err);
  if (r == BBC_OK && limbs->triangle_count) {
    uint8_t texel[3][4] = {{0, 0, 0, 255}, {128, 128, 255, 255}, {255, 255, 255, 255}};
    r = limb_colour(in, texel[0]);
    if (r != BBC_OK) r = bbc__fail(err, r, "step 3: out of memory");
    texel[2][0] = texel[2][1] = texel[2][2] = limb_occlusion(in);
    int want[3] = {1, prm->normal_maps, prm->occlusion > 0};
    for (int i = 0; r == BBC_OK && i < 3; i++)
      if (want[i] && (r = bbc_image_alloc(&swatch[i], 4, 4)) != BBC_OK)
        r = bbc__fail(err, r, "step 3: out of memory");
    for (int i = 0; r == BBC_OK && i < 3; i++)
      for (size_t x = 0; swatch[i].rgba && x < 16; x++) memcpy(swatch[i].rgba + 4 * x, texel[i], 4);
  }
  return r;
}
