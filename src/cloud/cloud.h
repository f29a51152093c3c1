/*
 * cloud.h — step 3's internal interface (src/cloud): the cloud built on
 * given rectangles (baselines), the stem's billboards, the limbs' mesh and
 * the alpha refinement. Not installed.
 */
#ifndef BBC_CLOUD_H
#define BBC_CLOUD_H

#include "base.h"

/* ---- step 3 internals (src/core/cloud.c) ----------------------------------- */
/* bbc_cloud_build with the billboards' rectangles given (one per plane of
 * `set`, NULL = computed as usual): baselines use it. */
bbc_result bbc__cloud_build_rects(const bbc_mesh *mesh, const bbc_planeset *set,
                                  const bbc_billboard *rects, const bbc_params *params,
                                  const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
/* Texels of all images for rectangles rects[n] at resolution texres. */
size_t bbc__cloud_texels(const bbc_billboard *rects, size_t n, int texres, int sides);

/* ---- the trunk part as a mesh (src/core/limbs.c) ------------------------------ */
/* The faces no plane simplifies (set->face_plane BBC_NO_PLANE: the trunk
 * part with `limbs`), welded and simplified to at most `target` triangles,
 * with smooth normals, one material and one group; an empty mesh (all
 * zero) when there are none. Free with bbc_mesh_free. */
bbc_result bbc__limbs_build(const bbc_mesh *mesh, const bbc_planeset *set, int target,
                            bbc_mesh *out, bbc_error *err);

/* ---- alpha refinement (src/core/refine.c) ------------------------------------ */
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
} bbc__refine_options;

/* Refines the alpha of the billboards cb[n] (images im[n]) of a cloud of
 * `mesh` against renders of the mesh (src/core/refine.c). */
bbc_result bbc__refine_alpha(const bbc_mesh *mesh, const bbc_cloud_billboard *cb,
                             bbc__refine_image *im, size_t n, const bbc__refine_options *options,
                             bbc_error *err);

#endif /* BBC_CLOUD_H */
