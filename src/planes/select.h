/* select.h — step 2 for one part (select.c, merge.c); internal. */
#ifndef BBC_SELECT_H
#define BBC_SELECT_H

#include "dual.h"

typedef struct select_result {
  bbc_plane *planes; /* grid frame: normal . x = d relative to the part centre */
  size_t plane_count, plane_cap;
  uint32_t *face_plane; /* per part face: index into planes */
} select_result;

/* Runs the greedy select on a grid whose density holds all `faces`. The
 * grid's density is consumed (it ends at zero). */
bbc_result bbc__select_planes(const dual_face *faces, size_t nf, dual_grid *g, const bbc_params *p,
                              double eps, double part_radius, const bbc_callbacks *cb,
                              select_result *out);
void bbc__select_result_free(select_result *r);

/* Merges redundant planes of a select's result over its nf faces
 * (merge.c; parameter `merge`): planes dissolved into others or merged
 * with a larger one, then renumbered. */
bbc_result bbc__merge_planes(const dual_face *faces, size_t nf, double eps, select_result *out);

#endif
