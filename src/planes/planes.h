/*
 * planes.h — what steps 1 and 2 give the layers above them besides the
 * public API (src/planes): normals at some points, and
 * the stem model (stem.c) that the split and step 3's stem billboards
 * share. Not installed.
 */
#ifndef BBC_PLANES_H
#define BBC_PLANES_H

#include "base.h"

/* bbc_points_estimate_normals for the points idx[count] only (NULL: every
 * point, count = the mesh's), each from all the cloud's points around it
 * (the same bits as for the whole cloud) into normals[3 * count]. */
bbc_result bbc__points_estimate_normals_at(const bbc_mesh *mesh, const uint32_t *idx, size_t count,
                                           int threads, float *normals, bbc_error *err);

/* ---- the stem model (stem.c) ------------------------------------------------ */
/* The split's view, the stem's path: keeps in part `trunk` only the faces
 * near the path of its stem up the up axis (0 = x, 1 = y, 2 = z; else y);
 * the others (branches) go to part `rest`. Returns the number of faces
 * moved, or SIZE_MAX when out of memory. */
size_t bbc__stem_keep(const bbc_mesh *mesh, uint32_t *face_part, uint32_t trunk, uint32_t rest,
                      int up_axis);

/* The stem billboards' view, the stem's axis and planes through it. */
#define BBC__STEM_MAX 8
typedef struct bbc__stem {
  size_t count;                       /* planes; 0 = no stem (no trunk part, or none found) */
  bbc_plane planes[BBC__STEM_MAX];    /* kind BBC_PLANE_STEM, part = the trunk part */
  bbc_billboard rects[BBC__STEM_MAX]; /* the stem faces' bounds on each (plane UINT32_MAX) */
  double slab[BBC__STEM_MAX];         /* half the thickness of each one's slab: all the
                                       * stem faces lie inside */
  uint8_t *face_mask;                 /* per triangle: 1 = a stem face */
  size_t face_count;
  double axis[3], base[3], base_radius; /* the axis (unit, up), base centre, radius */
} bbc__stem;

/* The trunk part's stem (the part named "trunk"): base = its faces in the
 * lowest 5 % of its height, axis = principal direction of its faces within
 * 2.5 base radii of the axis (refined twice from the up axis), and
 * `planes` planes through the axis. out->count = 0 when there is no trunk
 * part, or it has no height, no base or no face near the axis. A principal
 * direction leaning more than 60 degrees ends the refinement (the axis
 * found before it stays). Free with bbc__stem_free. */
bbc_result bbc__stem_find(const bbc_mesh *mesh, const bbc_planeset *set, int planes, int up_axis,
                          bbc__stem *out, bbc_error *err);
void bbc__stem_free(bbc__stem *stem);

#endif /* BBC_PLANES_H */
