/* grid.h — step 1's result kept for step 2 and for the views (planes.c,
 * src/cloud/views.c); internal. */
#ifndef BBC_GRID_H
#define BBC_GRID_H

#include "dual.h"

/* One part's share of step 1 that does not depend on epsilon: its faces in
 * dual form and its frame. */
typedef struct grid_part {
  char name[32];
  const bbc_params *params; /* into grid->options */
  uint32_t *tris;           /* mesh triangles of the part */
  size_t n;
  size_t meshed;    /* limbs: the part's triangles, kept as a mesh in step 3 (then n = 0) */
  dual_face *faces; /* its faces: a triangle, two coplanar ones, or a point */
  size_t nf;
  size_t stride;  /* a point cloud of more than 4 x `pointsample` points: faces holds 1 point
                   * in stride of tris (every stride-th from stride / 2), steps 1 and 2
                   * run on them; a mesh part of more than 4 x `facesample` faces: 1 face in
                   * stride of its dual faces (all); 1 = every face */
  float *points;  /* stride > 1, a cloud: the n points about the centre, to give each its plane */
  dual_face *all; /* stride > 1, a mesh: every face (faces holds 1 in stride of them) */
  size_t all_nf;
  double center[3], radius, total_area;
} grid_part;

/* Every part's dual grid at one epsilon scale, its density whole (step 2
 * works on copies). maxplanes/minplanes visit several scales. */
typedef struct grid_level {
  double scale;
  dual_grid g[2];
  double eps_abs[2], step1_s[2];
  int reported; /* step 1's time went into a planeset already */
} grid_level;

struct bbc_grid {
  bbc_planes_options options; /* what step 1 was run with (texts copied below) */
  char text[3][4096];
  size_t face_count; /* the mesh's triangles */
  uint32_t *face_part;
  size_t part_count;
  grid_part part[2];
  char split_why[320];
  double mesh_radius;
  grid_level *levels;
  size_t level_count;
  size_t current; /* the level step 2 used last (0 before) */
};

/* sampled.c: a mesh part of more than 4 x `facesample` faces to its sample
 * (nothing for a smaller one); a sampled part's faces or points to the
 * sample's planes sr (the first in the set at index base). */
bbc_result bbc__sample_faces(grid_part *gp, bbc_error *err);
struct select_result;
/* A sampled part's faces or points (gp->stride > 1, part pi) to planes:
 * the sample's (sr, the grid's frame, at `base` in the set, which counts
 * them already), else planes of the leftovers' own, appended. */
bbc_result bbc__assign_sampled(bbc_planeset *set, const grid_part *gp, size_t pi,
                               const struct select_result *sr, size_t base, double eps,
                               bbc_error *err);
/* planes.c: plane `pl` of part pi's select (the grid's frame, its mother
 * an index among the select's) as plane of the set, whose first of that
 * select is at `base`. */
bbc_plane bbc__plane_to_model(const bbc_plane *pl, const grid_part *gp, size_t pi, size_t base);

/* planes.c, for search.c: a part's parameters, `breaknum` for a run on
 * one face in `stride` of a part's faces, one whole run of step 2 at an
 * epsilon scale (its grid built or found), and the views' level. */
const bbc_params *bbc__part_params(const bbc_planes_options *o, const char *name);
int bbc__sampled_break_num(const grid_part *gp, int break_num, int stride);
bbc_result bbc__select_once(bbc_grid *g, const bbc_planes_options *o, double scale, int attempt,
                            bbc_planeset *set, bbc_error *err);
void bbc__show_level(bbc_grid *g, double scale);

#endif
