/* cloud.c — step 3 (thesis 2.1.9, 2.2.5, 2.3.1, 2.3.5, 2.3.9, 2.3.11): the
 * pipeline that builds a Billboard Cloud on the planes of steps 1-2,
 * calling its stages in order: the stem's billboards (bbc__stem_find), or
 * the limbs' part; the billboards' rectangles (billboard.c); voxel
 * shadowing (bake.c, shade.c); the planes that get a billboard
 * (billboard.c) and their texture sizes (texsize.c); the light, and every
 * billboard baked in parallel (bake.c); the limbs' mesh and colour
 * (limbs.c); quality 2's alpha refinement (refine.c); the atlas and the
 * cloud's mesh (cloud_mesh.c). With `atlasmax` the texture resolution is
 * chosen first, so that the images fit one atlas (texsize.c). */
#include "cloud.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

void bbc_cloud_free(bbc_cloud *cloud) {
  if (!cloud) return;
  bbc_mesh_free(&cloud->mesh);
  free(cloud->billboards);
  memset(cloud, 0, sizeof *cloud);
}

bbc_result bbc_cloud_build(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                           const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  assert(m && set && prm && cl);
  return bbc__cloud_build_rects(m, set, NULL, prm, cbk, cl, err);
}

static bbc_result build_inner(const bbc_mesh *m, const bbc_planeset *set,
                              const bbc_billboard *given, const bbc__stem *stem,
                              const bbc_params *prm, const bbc_callbacks *cbk, bbc_cloud *cl,
                              bbc_error *err, int atlas_limit);

static bbc_result cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                    const bbc_billboard *given, const bbc_params *prm,
                                    const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err);

bbc_result bbc__cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                  const bbc_billboard *given, const bbc_params *prm,
                                  const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  int saved = bbc__threads_use(prm->threads);
  bbc_result r = cloud_build_rects(m, set, given, prm, cbk, cl, err);
  bbc__threads_restore(saved);
  return r;
}

/* The cloud's materials' roughness: the mean of the source's over the
 * faces they show (the billboards': faces on a plane; the limbs': the
 * others), area-weighted, of the materials that give one (0 = none did);
 * the billboards' at least `floor` (roughmin: one flat plane reflects a sun
 * as one mirror where its many leaves scattered it, docs/lighting.md). */
static void set_roughness(const bbc_mesh *m, const bbc_planeset *set, double floor,
                          bbc_mesh *cloud) {
  double sum[2] = {0, 0}, weight[2] = {0, 0};
  for (size_t t = 0; t < m->triangle_count && m->kind == BBC_MESH_TRIANGLES; t++) {
    float r = m->materials[m->face_material[t]].roughness;
    if (!(r > 0)) continue;
    double a = bbc__triangle_area(m, t);
    int limb = set->face_plane[t] == BBC_NO_PLANE;
    sum[limb] += a * r;
    weight[limb] += a;
  }
  for (size_t i = 0; i < cloud->material_count; i++) {
    int limb = bbc_material_is_limbs(&cloud->materials[i]);
    if (!(weight[limb] > 0)) limb = !limb;
    float r = weight[limb] > 0 ? (float)(sum[limb] / weight[limb]) : 0.0f;
    if (!bbc_material_is_limbs(&cloud->materials[i]) && r > 0 && r < floor) r = (float)floor;
    cloud->materials[i].roughness = r;
  }
}

static bbc_result cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                    const bbc_billboard *given, const bbc_params *prm,
                                    const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  memset(cl, 0, sizeof *cl);
  bbc_params pts;
  if (m->kind == BBC_MESH_POINTS) { /* 2.4.4: no normal maps, no stem for points */
    pts = *prm;
    pts.normal_maps = 0;
    pts.occlusion = 0;
    pts.stem = 0;
    prm = &pts;
  }
  bbc__stem stem;
  bbc_result r = BBC_OK;
  /* with limbs the trunk part is a mesh: no stem billboards */
  if (m->kind == BBC_MESH_TRIANGLES && !bbc__limbs_part(set, NULL))
    r = bbc__stem_find(m, set, prm->stem, prm->up_axis, &stem, err);
  else
    memset(&stem, 0, sizeof stem);
  if (r != BBC_OK) return r;
  if (prm->atlas_max <= 0) {
    r = build_inner(m, set, given, &stem, prm, cbk, cl, err, 16384);
    bbc__stem_free(&stem);
    return r;
  }
  /* atlasmax: the largest texres whose images the packer fits in one
   * limit x limit atlas (tried on blank images of their sizes before any
   * baking), then halved while the baked ones do not fit (they do). */
  int limit = bbc__floor_pow2(prm->atlas_max < 64 ? 64 : prm->atlas_max); /* below 64: 64 */
  size_t np = set->plane_count, nk = 0;
  bbc_billboard *bb = calloc(np ? np : 1, sizeof *bb);
  bbc_billboard *kept = calloc(np + stem.count + 1, sizeof *kept);
  if (!bb || !kept) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK && given)
    memcpy(bb, given, np * sizeof *bb);
  else if (r == BBC_OK)
    r = bbc_billboards_compute(m, set, bb, err);
  for (size_t i = 0; r == BBC_OK && i < np; i++)
    if (bbc__plane_kept(m, set, i, prm)) kept[nk++] = bb[i];
  for (size_t i = 0; r == BBC_OK && i < stem.count; i++) kept[nk++] = stem.rects[i];
  int texres = 4, sides = prm->back_images ? 2 : 1,
      scale = prm->quality == BBC_QUALITY_SUPERSAMPLED ? 4 : 1;
  if (r == BBC_OK) texres = bbc__texres_fitting(set, kept, nk, sides, scale, limit);
  if (r == BBC_OK && texres < 0)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  bbc_params p2 = *prm;
  while (r == BBC_OK) {
    p2.texres = texres;
    r = build_inner(m, set, bb, &stem, &p2, cbk, cl, err, limit); /* billboards computed once */
    if (r != BBC_ERROR_OUT_OF_RANGE || texres <= 4) break;
    r = BBC_OK; /* did not fit: half the resolution */
    texres /= 2;
  }
  free(bb);
  free(kept);
  bbc__stem_free(&stem);
  return r;
}

static bbc_result build_inner(const bbc_mesh *m, const bbc_planeset *set,
                              const bbc_billboard *given, const bbc__stem *stem,
                              const bbc_params *prm, const bbc_callbacks *cbk, bbc_cloud *cl,
                              bbc_error *err, int atlas_limit) {
  memset(cl, 0, sizeof *cl);
  int points = m->kind == BBC_MESH_POINTS;
  size_t nf = points ? m->vertex_count : m->triangle_count;
  if (set->face_count != nf)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "step 3: the planes were found for another model (%zu %s, it has %zu)",
                     set->face_count, points ? "points" : "faces", nf);
  double t0 = bbc__now_s();
  size_t np = set->plane_count;
  bbc_billboard *bb = calloc(np ? np : 1, sizeof *bb);
  size_t *order = malloc((np ? np : 1) * sizeof *order);
  bbc__bake_inputs in;
  memset(&in, 0, sizeof in);
  in.mesh = m;
  in.set = set;
  in.params = prm;
  bbc_mesh limbs; /* `limbs`: the trunk part as a mesh, and its colour's swatch */
  memset(&limbs, 0, sizeof limbs);
  bbc_image swatch[3] = {{0, 0, NULL}, {0, 0, NULL}, {0, 0, NULL}};
  uint32_t limbs_group = 0;
  int limbs_target = points ? 0 : bbc__limbs_part(set, &limbs_group);
  bbc_result r = BBC_OK;
  if (!bb || !order) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  /* The billboards' rectangles (2.1.9). */
  if (r == BBC_OK && given)
    memcpy(bb, given, np * sizeof *bb);
  else if (r == BBC_OK)
    r = bbc_billboards_compute(m, set, bb, err);
  if (r == BBC_OK) r = bbc__bake_shading(&in, err); /* voxel shadowing (2.3.11) */
  /* Which planes get a billboard (2.3.5, 2.3.7): billboards
   * 0..np_kept-1 are the kept planes', then the stem's. */
  size_t nk = 0, np_kept = 0;
  double longest = 0;
  if (r == BBC_OK) nk = bbc__billboards_keep(m, set, prm, bb, stem, order, &np_kept, &longest);
  if (r == BBC_OK && np_kept == 0)
    r = bbc__fail(err, BBC_ERROR_EMPTY, "step 3: every plane was skipped");
  bbc__baked *bk = NULL;
  if (r == BBC_OK) {
    cl->billboards = calloc(nk, sizeof *cl->billboards);
    bk = calloc(nk, sizeof *bk);
    if (!cl->billboards || !bk)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  }
  if (r == BBC_OK) { /* texture sizes, the light, the bake */
    bbc__cloud_billboards_init(cl, set, bb, order, np_kept, stem, nk, longest, prm->texres);
    r = bbc__bake_lighting(&in, order, np_kept, err);
    if (r == BBC_OK) r = bbc__bake_all(&in, order, np_kept, stem, cbk, cl, bk, err);
  }
  /* The limbs' mesh and the swatch of their colour (its normal flat). */
  if (r == BBC_OK && limbs_target > 0)
    r = bbc__limbs_stage(&in, cl, limbs_target, &limbs, swatch, err);
  /* quality 2: alpha refined against renders of the original, then the
   * colour of texels left transparent cleared. */
  if (r == BBC_OK && prm->quality == BBC_QUALITY_SQUASHED)
    r = bbc__refine_baked(m, prm, cl, bk, &limbs, in.alpha_bits, cbk, err);
  if (r == BBC_OK && (prm->outline >= 3 || prm->max_tris > 0) &&
      bbc__tight_outlines(cl, bk, prm->outline, prm->max_tris, limbs.triangle_count,
                          prm->back_images ? 2 : 1) != BBC_OK)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  double t1 = bbc__now_s();
  cl->bake_s = t1 - t0;
  for (size_t k = 0; r == BBC_OK && k < nk; k++)
    if (bbc__baked_fill_transparent(&bk[k]) != BBC_OK)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK)
    r = bbc__cloud_atlas_mesh(set, prm, cl, bk, swatch, &limbs, limbs_group, atlas_limit, err);
  if (r == BBC_OK) set_roughness(m, set, prm->rough_min, &cl->mesh);
  cl->atlas_s = bbc__now_s() - t1;
  for (size_t k = 0; bk && k < nk; k++) bbc__baked_free(&bk[k]);
  free(bk);
  free(bb);
  free(order);
  bbc__bake_inputs_free(&in);
  bbc_mesh_free(&limbs);
  bbc_image_free(&swatch[0]);
  bbc_image_free(&swatch[1]);
  bbc_image_free(&swatch[2]);
  if (r != BBC_OK) bbc_cloud_free(cl);
  return r;
}
