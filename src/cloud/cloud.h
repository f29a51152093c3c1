/*
 * cloud.h — step 3's internal interface (src/cloud): the cloud built on
 * given rectangles (baselines), the stem's billboards, the limbs' mesh and
 * the alpha refinement. Not installed.
 */
#ifndef BBC_CLOUD_H
#define BBC_CLOUD_H

#include "base.h"
#include "planes.h" /* the stem (bbc__stem) */

/* ---- step 3 internals (src/cloud/cloud.c, texsize.c) ------------------------- */
/* bbc_cloud_build with the billboards' rectangles given (one per plane of
 * `set`, NULL = computed as usual): baselines use it. */
bbc_result bbc__cloud_build_rects(const bbc_mesh *mesh, const bbc_planeset *set,
                                  const bbc_billboard *rects, const bbc_params *params,
                                  const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
/* Texels of all images for rectangles rects[n] of set's planes (NULL: none
 * is a leftovers') at resolution texres. */
size_t bbc__cloud_texels(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int texres,
                         int sides);
/* A billboard's texels a model unit against the others': 1/2 for a plane of
 * a sampled part's leftovers (few faces scattered over a large rectangle),
 * which the longest side that sets `texres` leaves out; else 1. */
double bbc__rect_density(const bbc_planeset *set, const bbc_billboard *rect);

/* ---- supersamples down to texels (src/cloud/texels.c) ------------------------ */
/* Which texels of a k x k supersampled image end opaque (mask[texel] = 1)
 * and which some sample covered (cand). `dither` 0 (growing, thesis 2.3.9):
 * at least `min_opaque` of its k^2 samples are covered; 1: coverage-keeping
 * error diffusion (Floyd-Steinberg, serpentine rows) of each texel's covered
 * fraction (its samples' alphas; with taps, those drawn at their centres,
 * bbc__bake.taps), so that over any small area the fraction of opaque texels
 * is the fraction covered, and a texel no sample covers never turns opaque. */
bbc_result bbc__alpha_mask(const bbc_image *img, const uint8_t *taps, int k, int dither,
                           unsigned min_opaque, uint8_t *mask, uint8_t *cand);
/* `img` (k x k samples a texel) replaced by its texels: each the mean of its
 * covered samples (is_normal 1: normals, encoded 255 (n + 1) / 2,
 * renormalised; 2: their mean kept, at most unit length), alpha 255 where
 * mask says so, else 0 (the colour kept). */
bbc_result bbc__downsample_masked(bbc_image *img, int k, int is_normal, const uint8_t *mask);
/* Texels not opaque in `mask` become (0, 0, 0, 0); opaque ones alpha 255. */
void bbc__clear_masked(bbc_image *img, const uint8_t *mask);
/* Every transparent texel (alpha 0) takes the colour of its nearest opaque
 * ones (breadth first), alpha kept, so that a GPU's filtering and mip
 * levels mix no black (or no bogus normal) into edges. */
bbc_result bbc__fill_transparent(bbc_image *img);

/* ---- the trunk part as a mesh (src/cloud/limbs.c) ----------------------------- */
/* The faces no plane simplifies (set->face_plane BBC_NO_PLANE: the trunk
 * part with `limbs`), welded and simplified to at most `target` triangles,
 * with smooth normals, one material and one group; an empty mesh (all
 * zero) when there are none. Free with bbc_mesh_free. */
bbc_result bbc__limbs_build(const bbc_mesh *mesh, const bbc_planeset *set, int target,
                            bbc_mesh *out, bbc_error *err);

/* ---- alpha refinement (src/cloud/refine.c) ----------------------------------- */
/* One billboard's texels: alpha[side] nonzero = opaque (side 1 NULL: the
 * front image is seen from both sides), cand[side] nonzero = may turn
 * opaque (some sample of the original covered it; NULL = none may). */
typedef struct bbc__refine_image {
  uint8_t *alpha[2];
  const uint8_t *cand[2];
  int width, height;
} bbc__refine_image;

typedef struct bbc__refine_options {
  int views;             /* views over the sphere (0 = off) */
  int size;              /* pixels per side of each view */
  int rounds;            /* at most this many rounds (fewer when nothing changes) */
  int up_axis;           /* 0 = x, 1 = y, 2 = z */
  int threads;           /* 0 = all cores; never changes the result */
  const bbc_mesh *solid; /* opaque geometry drawn with the cloud (the limbs), or NULL */
  const struct bbc__alpha_bits *alpha_bits; /* per texture of the mesh: its alpha
                                             * test as bits, or NULL */
} bbc__refine_options;

/* Refines the alpha of the billboards cb[n] (images im[n]) of a cloud of
 * `mesh` against renders of the mesh. */
bbc_result bbc__refine_alpha(const bbc_mesh *mesh, const bbc_cloud_billboard *cb,
                             bbc__refine_image *im, size_t n, const bbc__refine_options *options,
                             bbc_error *err);

/* ==== step 3's stages, which src/cloud/cloud.c runs in order ================ */
/* Those returning a bbc_result return BBC_OK or an error, its message in
 * err. */

/* -- the planes that get a billboard (src/cloud/billboard.c) -- */
/* Whether plane i gets a billboard (2.3.5, 2.3.7). */
int bbc__plane_kept(const bbc_mesh *mesh, const bbc_planeset *set, size_t i,
                    const bbc_params *params);
/* The kept planes' indices into order[] (*kept_planes of them), then the
 * stem's billboards: returns the count of both; *longest: the longest side
 * of their rectangles (rects: one per plane). */
size_t bbc__billboards_keep(const bbc_mesh *mesh, const bbc_planeset *set, const bbc_params *params,
                            const bbc_billboard *rects, const bbc__stem *stem, size_t *order,
                            size_t *kept_planes, double *longest);

/* -- texture sizes (src/cloud/texsize.c; thesis 2.1.9) -- */
/* The largest power of two <= x (at least 1, at most 2^14). */
int bbc__floor_pow2(double x);
/* atlasmax: the largest texres (8192 down to 8, else 4) whose images of
 * rectangles rects[n] (`sides` each, `scale` times the texels a side) the
 * packer fits in one limit x limit atlas; -1 out of memory. */
int bbc__texres_fitting(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int sides,
                        int scale, int limit);
/* The cloud's billboards 0..kept_planes-1 from the kept planes (order[]),
 * then the stem's (count billboards in all, allocated): plane, rectangle
 * and texture size at `texres` for the longest side `longest`. */
void bbc__cloud_billboards_init(bbc_cloud *cloud, const bbc_planeset *set,
                                const bbc_billboard *rects, const size_t *order, size_t kept_planes,
                                const bbc__stem *stem, size_t count, double longest, int texres);

/* -- baking (src/cloud/bake.c; thesis 2.1.9, 2.2.5, 2.3.9) -- */
/* What every billboard's bake shares. */
typedef struct bbc__bake_inputs {
  const bbc_mesh *mesh;
  const bbc_planeset *set;
  const bbc_params *params;
  float *vshade;                      /* per vertex: voxel shadowing's light (2.3.11), or NULL;
                                       * with `occlusion` it goes to the occlusion images */
  struct bbc__mips *mips;             /* the mesh's textures' mipmaps, or NULL */
  struct bbc__alpha_bits *alpha_bits; /* the mesh's textures' alpha tests, or NULL */
  uint8_t *share;                     /* pure 2: per triangle, its alpha share, or NULL */
  double light[3];                    /* the prelight's direction */
  double light_gain;                  /* prelight: its brightness as a lit viewer's */
  double crown_center[3];             /* nmbend: what normals bend away from */
} bbc__bake_inputs;

/* The images of one billboard before packing. */
typedef struct bbc__baked {
  bbc_image front, back, front_nm, back_nm;
  bbc_image front_ao, back_ao; /* `occlusion`: the occlusion images (grey) */
  uint8_t *mask[2], *cand[2];  /* quality 2: per texel opaque / has covered samples */
  bbc_error err;
  bbc_result r;
} bbc__baked;

/* Voxel shadowing (2.3.11): in->vshade when the parameters ask for it;
 * the crown's centre. */
bbc_result bbc__bake_shading(bbc__bake_inputs *in, bbc_error *err);
/* The light, its gain, the mipmaps and (pure 2) the faces' alpha shares
 * among the kept planes order[0..kept_planes-1]. */
bbc_result bbc__bake_lighting(bbc__bake_inputs *in, const size_t *order, size_t kept_planes,
                              bbc_error *err);
/* Bakes every billboard of the cloud (those of the kept planes order[],
 * then the stem's) into bk[], in parallel, with progress and cancelling. */
bbc_result bbc__bake_all(const bbc__bake_inputs *in, const size_t *order, size_t kept_planes,
                         const bbc__stem *stem, const bbc_callbacks *callbacks, bbc_cloud *cloud,
                         bbc__baked *bk, bbc_error *err);
/* Samples per texel side the bake draws: quality 2 `samples`, quality 3 4,
 * else 1. */
int bbc__bake_samples(const bbc_params *prm);
/* quality 2: texels left transparent by the masks become (0, 0, 0, 0),
 * opaque ones alpha 255. */
void bbc__baked_clear_transparent(bbc__baked *b);
/* Every image's transparent texels take the colour of their nearest
 * opaque ones (alpha stays 0), so that filtering mixes in no black.
 * BBC_ERROR_OUT_OF_MEMORY leaves some images unfilled. */
bbc_result bbc__baked_fill_transparent(bbc__baked *b);
void bbc__baked_free(bbc__baked *b);
void bbc__bake_inputs_free(bbc__bake_inputs *in);

/* -- the limbs (src/cloud/limbs.c) -- */
/* The part whose faces `limbs` keeps as a mesh: its triangle budget (0 =
 * none) and, when part is not NULL, its index. */
int bbc__limbs_part(const bbc_planeset *set, uint32_t *part);
/* The limbs' mesh (at most `target` triangles, fewer for a cloud of few
 * billboards) and the 4 x 4 swatches of their colour, flat normal
 * (swatch[1] only with normal maps) and occlusion (swatch[2] only with
 * `occlusion`). */
bbc_result bbc__limbs_stage(const bbc__bake_inputs *in, const bbc_cloud *cloud, int target,
                            bbc_mesh *limbs, bbc_image swatch[3], bbc_error *err);

/* -- refinement (src/cloud/refine.c) -- */
/* quality 2: the baked masks refined against renders of the original (the
 * limbs drawn with the cloud; alpha_bits: the mesh's textures' alpha tests
 * as bits, or NULL), then the transparent texels cleared. */
bbc_result bbc__refine_baked(const bbc_mesh *mesh, const bbc_params *params, bbc_cloud *cloud,
                             bbc__baked *bk, const bbc_mesh *limbs,
                             const struct bbc__alpha_bits *alpha_bits,
                             const bbc_callbacks *callbacks, bbc_error *err);

/* -- tight outlines (src/cloud/outline.c) -- */
/* Each billboard's outline tightened around its images' opaque texels (at
 * most `most` corners, most >= 3), fewer where max_tris > 0 asks (the
 * cloud's other triangles other_tris, `sides` fans a billboard; without
 * `most` the outlines as they are, cut to what the budget leaves). */
bbc_result bbc__tight_outlines(bbc_cloud *cloud, const bbc__baked *bk, int most, int max_tris,
                               size_t other_tris, int sides);

/* -- the atlas and the mesh (src/cloud/cloud_mesh.c) -- */
/* The baked images packed into the atlas (and the normal atlas, 2.3.1, and
 * the occlusion atlas, in the same layout), the swatches last, and the
 * cloud's mesh: each billboard's outline, then the limbs' mesh (part
 * limbs_group) on the swatch. */
bbc_result bbc__cloud_atlas_mesh(const bbc_planeset *set, const bbc_params *params,
                                 bbc_cloud *cloud, const bbc__baked *bk, const bbc_image swatch[3],
                                 const bbc_mesh *limbs, uint32_t limbs_group, int atlas_limit,
                                 bbc_error *err);

#endif /* BBC_CLOUD_H */
