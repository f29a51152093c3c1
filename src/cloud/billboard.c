/* billboard.c — the rectangle of each plane (thesis 2.1.9): the faces it
 * simplifies projected onto it, their minimum-area bounding rectangle
 * (src/planes/tweak.c: convex hull and rotating calipers), back in model
 * coordinates; and which planes get a billboard (2.3.5, 2.3.7). */
#include "cloud.h"
#include "dual.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* bbc__dual_face_valid's arithmetic for a point (its dual face: c the
 * point, offsets zero). */
static int point_valid(const double *c, const double n[3], double rho, double eps) {
  double cc = c[0] * n[0] + c[1] * n[1] + c[2] * n[2] - rho;
  return !(fabs(cc) > eps * (1 + 1e-12));
}

bbc_result bbc_billboards_compute(const bbc_mesh *mesh, const bbc_planeset *set, bbc_billboard *out,
                                  bbc_error *err) {
  assert(mesh && set && out);
  size_t nf = set->face_count, np = set->plane_count;
  int points = mesh->kind == BBC_MESH_POINTS;
  size_t have = points ? mesh->vertex_count : mesh->triangle_count;
  if (nf != have)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "billboards: the plane set has %zu faces, the model %zu %s", nf, have,
                     points ? "points" : "triangles");
  /* Triangles in dual form; points are read from the mesh (a point's dual
   * face, 184 bytes, for ten million points would be 1.8 GB). */
  dual_face *faces = NULL;
  const double origin[3] = {0, 0, 0};
  if (!points) {
    uint32_t *all = malloc((nf ? nf : 1) * sizeof *all);
    for (size_t t = 0; all && t < nf; t++) all[t] = (uint32_t)t;
    bbc_result r =
        all ? bbc__dual_faces_build(mesh, all, nf, origin, &faces) : BBC_ERROR_OUT_OF_MEMORY;
    free(all);
    if (r != BBC_OK) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "billboards: out of memory");
  }
  int oom = 0;
  /* The planes are independent: one each, a face list per thread. */
#pragma omp parallel
  {
    uint32_t *which = malloc((nf ? nf : 1) * sizeof *which);
    if (!which) {
#pragma omp atomic write
      oom = 1;
    }
#pragma omp for schedule(dynamic, 1)
    for (size_t i = 0; i < np; i++) {
      if (!which) continue;
      const bbc_plane *p = &set->planes[i];
      /* Its faces: the assigned ones, or for a cardboard plane its mother's
       * faces valid for it. */
      uint32_t owner = p->kind == BBC_PLANE_CARDBOARD ? (uint32_t)p->mother : (uint32_t)i;
      double eps = set->parts[p->part].epsilon_abs;
      size_t n = 0;
      for (size_t t = 0; t < nf; t++) {
        if (set->face_plane[t] != owner) continue;
        if (p->kind == BBC_PLANE_CARDBOARD &&
            !(points ? point_valid(mesh->positions + 3 * t, p->normal, p->d, eps)
                     : bbc__dual_face_valid(&faces[t], p->normal, p->d, eps)))
          continue;
        which[n++] = (uint32_t)t;
      }
      bbc_billboard *b = &out[i];
      memset(b, 0, sizeof *b);
      b->plane = (uint32_t)i;
      double mn[2], mx[2];
      bbc_result rr = points ? bbc__points_min_rect(mesh, which, n, p->normal, b->u, b->w, mn, mx)
                             : bbc__dual_min_rect(faces, which, n, p->normal, b->u, b->w, mn, mx);
      if (rr != BBC_OK) {
#pragma omp atomic write
        oom = 1;
      }
      double width = mx[0] - mn[0], height = mx[1] - mn[1];
      if (height > width) { /* longer side along u; u x w stays the normal */
        double u[3], w[3];
        for (int k = 0; k < 3; k++) {
          u[k] = b->w[k];
          w[k] = -b->u[k];
        }
        double m0 = mn[1], m1 = -mx[0];
        memcpy(b->u, u, sizeof u);
        memcpy(b->w, w, sizeof w);
        mn[0] = m0;
        mn[1] = m1;
        double t = width;
        width = height;
        height = t;
      }
      b->width = width;
      b->height = height;
      for (int k = 0; k < 3; k++)
        b->origin[k] = p->d * p->normal[k] + mn[0] * b->u[k] + mn[1] * b->w[k];
    }
    free(which);
  }
  free(faces);
  if (oom) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "billboards: out of memory");
  return BBC_OK;
}

int bbc__plane_kept(const bbc_mesh *m, const bbc_planeset *set, size_t i, const bbc_params *prm) {
  const bbc_plane *p = &set->planes[i];
  if (p->kind == BBC_PLANE_CARDBOARD) return p->coverage_pct >= prm->cb_coverage_pct;
  /* 2.4.4: a point cloud's planes with fewer than pointskip points go */
  if (m->kind == BBC_MESH_POINTS) return p->face_count >= (size_t)prm->point_skip;
  double largest = 0;
  for (size_t j = 0; j < set->plane_count; j++)
    if (set->planes[j].part == p->part && set->planes[j].kind != BBC_PLANE_CARDBOARD &&
        set->planes[j].area > largest)
      largest = set->planes[j].area;
  return p->area >= prm->poly_skip_pct / 100.0 * largest;
}

size_t bbc__billboards_keep(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                            const bbc_billboard *bb, const bbc__stem *stem, size_t *order,
                            size_t *np_kept, double *longest) {
  size_t nk = 0;
  double lg = 0;
  for (size_t i = 0; i < set->plane_count; i++)
    if (bbc__plane_kept(m, set, i, prm)) {
      order[nk++] = i;
      if (bbc__rect_density(set, &bb[i]) == 1.0) lg = fmax(lg, fmax(bb[i].width, bb[i].height));
    }
  *np_kept = nk;
  for (size_t i = 0; i < stem->count; i++) {
    lg = fmax(lg, fmax(stem->rects[i].width, stem->rects[i].height));
    nk++;
  }
  *longest = lg;
  return nk;
}
