/*
 * dual.h — internal interface of plane selection (thesis 2.1.3-2.1.8, 2.3):
 * the dual grid and its density (dualgrid.c), face clustering (cluster.c),
 * the greedy select with its refinement (select.c) and the plane tweaks
 * (tweak.c). Not installed.
 *
 * Conventions, stated once:
 *   - Everything here works in a part's grid frame: model coordinates minus
 *     the part's centre of gravity (thesis 2.1.4), so |rho| <= radius + eps.
 *   - A direction (theta, phi) maps to the unit normal
 *       n = cos(theta) cos(phi) a + sin(theta) cos(phi) b + sin(phi) up
 *     where `up` is the model's up axis and (a, b, up) is right-handed: the
 *     grid's poles (phi = +-90 deg) are horizontal planes, which is where the
 *     view-dependent penalty of 2.3.8 acts. theta in [-pi, pi), phi in
 *     [-pi/2, pi/2].
 *   - A plane is (n, rho): n . x = rho, rho >= 0 in the grid (the plane
 *     (n, -rho) is (-n, rho), thesis Eq. 2-2).
 *   - Density is accumulated in 64-bit integers (fixed point), so adding
 *     and later removing a face's share is exact, and the sum does not
 *     depend on the order of faces or on the number of threads.
 */
#ifndef BBC_DUAL_H
#define BBC_DUAL_H

#include "base.h"

#include <math.h>
#include <string.h>

#ifndef M_SQRT1_2
#define M_SQRT1_2 0.70710678118654752440
#endif

/* One triangle of a part, in the grid frame. */
typedef struct dual_face {
  double c[3];          /* centroid (of the vertices) */
  double d[4][3];       /* vertex offsets from the centroid; a triangle's d[3] is d[0] */
  double n[3];          /* unit normal */
  double area;          /* model units squared */
  double c_len;         /* |c| */
  double d_max;         /* max |d_i| */
  uint32_t mesh_index;  /* triangle index in the mesh (a point cloud: the point's) */
  uint32_t mesh_index2; /* a quad's second triangle, else UINT32_MAX */
  int nv;               /* vertices: 3, or 4 for two coplanar triangles sharing an edge */
  int point;            /* a point of a point cloud (thesis 2.4): c the point, d and n
                         * zero, area its weight (1): it counts, it has no area */
} dual_face;

/* A box of plane space: theta x phi x rho ranges (radians, model units). */
typedef struct dual_box {
  double t0, t1, p0, p1, r0, r1;
} dual_box;

/* Geometry of a (sub)cell's direction range, for conservative bounds. */
typedef struct dual_dir {
  double n[3];   /* unit normal at the centre direction */
  double radius; /* chord radius: every direction of the range is within this
                  * distance of n (an upper bound) */
  double phi;    /* centre phi, radians */
} dual_dir;

typedef struct dual_frame {
  double axis_a[3], axis_b[3], axis_up[3];
} dual_frame;

/* The dual grid of one part (thesis 2.1.4-2.1.7). */
typedef struct dual_grid {
  dual_frame frame;
  int n_theta, n_phi, n_rho;
  double res_rad;        /* theta/phi cell size, radians */
  double rho_res;        /* rho cell size, model units (2 eps, Eq. 2-6) */
  double rho_min;        /* lower rho of cell 0: -rho_res / 2 */
  double eps;            /* error threshold, model units */
  double scale;          /* fixed point: density units per model area unit */
  dual_dir *dirs;        /* n_theta * n_phi, index phi_row * n_theta + theta_col */
  int64_t *contrib;      /* per cell (dir * n_rho + k) */
  int64_t *penalty;      /* per cell, already multiplied by the penalty factor */
  double penalty_factor; /* 10 for the grid (2.1.7) */
  int threads;
} dual_grid;

/* Unit normal of direction (theta, phi) in the frame. */
void bbc__dual_normal(const dual_frame *f, double theta, double phi, double n[3]);
/* Centre normal, chord radius and centre phi of a direction range. */
void bbc__dual_dir_of_box(const dual_frame *f, const dual_box *b, dual_dir *out);
/* Builds the frame for up axis 0/1/2 (x/y/z). */
void bbc__dual_frame_init(dual_frame *f, int up_axis);

static inline double dual_max(double a, double b) {
  return a > b ? a : b;
}
static inline double dual_min(double a, double b) {
  return a < b ? a : b;
}

/* Conservative simple validity (thesis 2.1.4, tightened and made safe; the
 * derivation is in dualgrid.c): writes [lo, hi] such that every plane of the
 * direction range whose rho lies outside it is invalid for the face; returns
 * 0 when no plane of the direction range can be valid at all (the face is
 * thicker than 2 eps along every direction of it). Never misses a valid
 * plane. Inline: it is the innermost operation of steps 1 and 2. */
static inline int dual_face_range(const dual_face *f, const dual_dir *dir, double eps, double *lo,
                                  double *hi) {
  const double *n = dir->n;
  double cc = f->c[0] * n[0] + f->c[1] * n[1] + f->c[2] * n[2];
  double a0 = f->d[0][0] * n[0] + f->d[0][1] * n[1] + f->d[0][2] * n[2];
  double a1 = f->d[1][0] * n[0] + f->d[1][1] * n[1] + f->d[1][2] * n[2];
  double a2 = f->d[2][0] * n[0] + f->d[2][1] * n[1] + f->d[2][2] * n[2];
  double a3 = f->d[3][0] * n[0] + f->d[3][1] * n[1] + f->d[3][2] * n[2];
  double amax = dual_max(dual_max(a0, a3), dual_max(a1, a2));
  double amin = dual_min(dual_min(a0, a3), dual_min(a1, a2));
  double slack = 1e-12 * (f->c_len + f->d_max + eps);
  if (amax - amin - 2 * f->d_max * dir->radius > 2 * eps + slack) return 0;
  double w = (f->c_len + f->d_max) * dir->radius + eps + slack;
  *lo = cc + amax - w;
  *hi = cc + amin + w;
  return 1;
}

/* One direction of dual_face_ranges, given the vertices' offsets along it
 * (a0..a3) and its centroid term cc. */
static inline void dual_range_at(double cc, double a0, double a1, double a2, double a3, double wlen,
                                 double r, double eps, double slack, double dm2, double lim,
                                 double *lo, double *hi, double *ok) {
  double amax = dual_max(dual_max(a0, a3), dual_max(a1, a2));
  double amin = dual_min(dual_min(a0, a3), dual_min(a1, a2));
  double w = wlen * r + eps + slack;
  *ok = amax - amin - dm2 * r <= lim;
  *lo = cc + amax - w;
  *hi = cc + amin + w;
}

/* dual_face_range for m directions at once, given as structure-of-arrays
 * (nx, ny, nz, radius) so that the loop vectorises: ok[q] is 1 where the
 * face can be valid, [lo[q], hi[q]] its range there. Same arithmetic. */
static inline void dual_face_ranges(const dual_face *f, const double *restrict nx,
                                    const double *restrict ny, const double *restrict nz,
                                    const double *restrict rad, size_t m, double eps,
                                    double *restrict lo, double *restrict hi, double *restrict ok) {
  const double cx = f->c[0], cy = f->c[1], cz = f->c[2];
  const double(*dd)[3] = f->d;
  const double slack = 1e-12 * (f->c_len + f->d_max + eps), wlen = f->c_len + f->d_max;
  const double dm2 = 2 * f->d_max, lim = 2 * eps + slack;
  /* Two loops, so that each vectorises: a triangle's d[3] repeats d[0]. */
  if (f->nv == 3) {
    for (size_t q = 0; q < m; q++) {
      double x = nx[q], y = ny[q], z = nz[q];
      double a0 = dd[0][0] * x + dd[0][1] * y + dd[0][2] * z;
      dual_range_at(cx * x + cy * y + cz * z, a0, dd[1][0] * x + dd[1][1] * y + dd[1][2] * z,
                    dd[2][0] * x + dd[2][1] * y + dd[2][2] * z, a0, wlen, rad[q], eps, slack, dm2,
                    lim, &lo[q], &hi[q], &ok[q]);
    }
    return;
  }
  for (size_t q = 0; q < m; q++) {
    double x = nx[q], y = ny[q], z = nz[q];
    dual_range_at(cx * x + cy * y + cz * z, dd[0][0] * x + dd[0][1] * y + dd[0][2] * z,
                  dd[1][0] * x + dd[1][1] * y + dd[1][2] * z,
                  dd[2][0] * x + dd[2][1] * y + dd[2][2] * z,
                  dd[3][0] * x + dd[3][1] * y + dd[3][2] * z, wlen, rad[q], eps, slack, dm2, lim,
                  &lo[q], &hi[q], &ok[q]);
  }
}

/* Exact validity: every vertex within eps of the plane n . x = rho. */
int bbc__dual_face_valid(const dual_face *f, const double n[3], double rho, double eps);

/* Projected area of the face onto a plane with normal n (Eq. 2-5). */
static inline double dual_projected_area(const dual_face *f, const double n[3]) {
  if (f->point && f->n[0] == 0 && f->n[1] == 0 && f->n[2] == 0)
    return f->area; /* 2.4.3: a point counts, whatever the direction */
  return f->area * fabs(f->n[0] * n[0] + f->n[1] * n[1] + f->n[2] * n[2]);
}

/* A direction box's edges as cosines and sines, for exact point ranges. */
typedef struct dual_box_trig {
  double ct0, st0, ct1, st1, cp0, sp0, cp1, sp1;
} dual_box_trig;

static inline void dual_box_trig_of(const dual_box *b, dual_box_trig *t) {
  t->ct0 = cos(b->t0);
  t->st0 = sin(b->t0);
  t->ct1 = cos(b->t1);
  t->st1 = sin(b->t1);
  t->cp0 = cos(b->p0);
  t->sp0 = sin(b->p0);
  t->cp1 = cos(b->p1);
  t->sp1 = sin(b->p1);
}

/* The exact range of rho = p . n over the directions of a box (theta and phi
 * ranges under 180 degrees) for a point with frame coordinates (a, b, c):
 * p . n = cos(phi) (a cos(theta) + b sin(theta)) + c sin(phi). Its extremes
 * lie at the box's edges or where a partial derivative vanishes, found with
 * sign tests (no trigonometry per point). Thesis 2.4.2: a point's validity
 * domain is then [min - eps, max + eps], with no false positives. The box's
 * edges as cosines and sines; R = |(a, b)|, the same for every box. Each
 * choice is made by selection, not a branch, so that a loop over boxes
 * vectorises (add_faces). */
static inline void dual_point_extremes_at(double a, double b, double c, double R, double ct0,
                                          double st0, double ct1, double st1, double cp0,
                                          double sp0, double cp1, double sp1, double *lo,
                                          double *hi) {
  double u0 = a * ct0 + b * st0, u1 = a * ct1 + b * st1;
  double umax = dual_max(u0, u1), umin = dual_min(u0, u1);
  /* u = a cos + b sin peaks (R) towards (a, b), and dips (-R) opposite */
  int peak = (ct0 * b - st0 * a >= 0) & (a * st1 - b * ct1 >= 0);
  int dip = (st0 * a - ct0 * b >= 0) & (b * ct1 - a * st1 >= 0);
  umax = peak ? R : umax;
  umin = dip ? -R : umin;
  /* over phi (cos phi >= 0): max of umax cos + c sin, min of umin cos + c sin */
  double mx = dual_max(umax * cp0 + c * sp0, umax * cp1 + c * sp1);
  int top = (umax > 0) & (cp0 * c - sp0 * umax >= 0) & (umax * sp1 - c * cp1 >= 0);
  double top_v = sqrt(umax * umax + c * c);
  mx = top ? top_v : mx;
  double mn = dual_min(umin * cp0 + c * sp0, umin * cp1 + c * sp1);
  int bottom = (umin < 0) & (-cp0 * c + sp0 * umin >= 0) & (-umin * sp1 + c * cp1 >= 0);
  double bottom_v = -sqrt(umin * umin + c * c);
  mn = bottom ? bottom_v : mn;
  *lo = mn;
  *hi = mx;
}

/* The same for one box. */
static inline void dual_point_extremes(double a, double b, double c, const dual_box_trig *t,
                                       double *lo, double *hi) {
  dual_point_extremes_at(a, b, c, sqrt(a * a + b * b), t->ct0, t->st0, t->ct1, t->st1, t->cp0,
                         t->sp0, t->cp1, t->sp1, lo, hi);
}

/* A point's frame coordinates. */
static inline void dual_point_frame(const dual_frame *fr, const double p[3], double *a, double *b,
                                    double *c) {
  *a = p[0] * fr->axis_a[0] + p[1] * fr->axis_a[1] + p[2] * fr->axis_a[2];
  *b = p[0] * fr->axis_b[0] + p[1] * fr->axis_b[1] + p[2] * fr->axis_b[2];
  *c = p[0] * fr->axis_up[0] + p[1] * fr->axis_up[1] + p[2] * fr->axis_up[2];
}

/* The points of a point cloud as dual faces (`idx`: point indices;
 * `normals`, 3 a point, may be NULL: unoriented points; indexed as the
 * mesh's points, or with normals_local as idx). */
bbc_result bbc__dual_points_build(const bbc_mesh *mesh, const uint32_t *idx, size_t count,
                                  const double center[3], const float *normals, int normals_local,
                                  dual_face **out);
/* Prepares the faces of a part: `tris` lists mesh triangle indices; one
 * face a triangle. */
bbc_result bbc__dual_faces_build(const bbc_mesh *mesh, const uint32_t *tris, size_t count,
                                 const double center[3], dual_face **out);
/* The same with two triangles that share an edge and lie in one plane (a
 * quad split by the file or by Assimp: leaf cards, branch segments) as one
 * face of four vertices, valid for a plane when all four are: about half
 * the faces for steps 1 and 2 to handle. With flat_tol > 0 also a pair
 * that bends by less than 30 degrees and whose apexes lie within flat_tol
 * of the other's plane (a modelled needle or leaf is a slightly folded
 * quad): to planes eps apart (flat_tol far below eps) it is as flat.
 * Pairs are taken in the order of `tris`; *out_count gets the number of
 * faces. */
bbc_result bbc__dual_faces_build_merged(const bbc_mesh *mesh, const uint32_t *tris, size_t count,
                                        const double center[3], double flat_tol, dual_face **out,
                                        size_t *out_count);

bbc_result bbc__dual_grid_init(dual_grid *g, int res_deg, double eps, double radius, int up_axis,
                               double total_area, int threads);
void bbc__dual_grid_free(dual_grid *g);
/* A deep copy (the greedy select consumes a grid's density). */
bbc_result bbc__dual_grid_copy(dual_grid *dst, const dual_grid *src);

/* Adds (sign = +1) or removes (sign = -1) the density of faces (thesis 2.1.5
 * step 2, and the grid update of 2.1.8). BBC_ERROR_OUT_OF_MEMORY leaves
 * the grid with some faces' density missing. */
bbc_result bbc__dual_grid_accumulate(dual_grid *g, const dual_face *faces, const uint32_t *which,
                                     size_t count, int sign, const bbc_callbacks *cb);

/* Density along rho in fixed point (steps 1 and 2). A face's range
 * [lo, hi] over a column of n rho cells adds to each cell w x the fraction
 * of the cell that [lo, hi] covers (its contribution) and w x the fraction
 * that [lo - eps, lo] covers (its penalty: planes just below the valid
 * range barely miss the face that lies in front of them; thesis 2.1.7,
 * Fig. 2-14, 2-15). Positions are counted in cells, to 2^-DUAL_FX of a
 * cell, and a range is two kinks: w x max(0, min(1, k + 1 - X)) added to
 * every cell k for a range starting at X, the same subtracted where it
 * ends. Kinks are kept in difference form (d[k] = value[k] - value[k -
 * 1], n + 2 entries so that no write needs a test), two writes a kink
 * whatever the range's length; dual_kinks_fold adds them up, or subtracts
 * them. Integer sums: removing a face subtracts exactly what adding it
 * added, in any order. */
#define DUAL_FX 20

static inline double dual_clamp(double x, double top) {
  return x > 0 ? (x < top ? x : top) : 0;
}

/* The shares of a range over a column of n cells, as kinks in difference
 * form: d[0..n+1] the kinks where ranges start, d[stride..] where they end,
 * d[2 stride..] where their penalties start (a penalty ends where its
 * range starts); dual_kinks_fold makes contribution and penalty of them.
 * Three arrays so that no two writes of one range meet at one address (a
 * range's end cell is often the cell after its start's). x and y are the
 * range's ends and e is eps, in cells from the column's lower end; w > 0
 * the face's fixed-point projected area. A kink at X (in 2^-DUAL_FX of a
 * cell) adds its part w x (the fraction of X's cell above X) to that cell
 * and w less that part to the next: in difference form, w to every cell
 * above. */
static inline void dual_column_add(int64_t *d, size_t stride, int n, double x, double y, double e,
                                   int64_t w) {
  const double top = n, one = (double)((int64_t)1 << DUAL_FX);
  if (!(y > 0) || !(x < top)) return; /* the range misses the column */
  int64_t L = (int64_t)(dual_clamp(x, top) * one), H = (int64_t)(dual_clamp(y, top) * one);
  int64_t P = (int64_t)(dual_clamp(x - e, top) * one);
  int64_t kl = L >> DUAL_FX, kh = H >> DUAL_FX, kp = P >> DUAL_FX;
  int64_t pl = (w * (((kl + 1) << DUAL_FX) - L)) >> DUAL_FX;
  int64_t ph = (w * (((kh + 1) << DUAL_FX) - H)) >> DUAL_FX;
  int64_t pp = (w * (((kp + 1) << DUAL_FX) - P)) >> DUAL_FX;
  int64_t *ks = d, *ke = d + stride, *kq = d + 2 * stride;
  ks[kl] += pl;
  ks[kl + 1] += w - pl;
  ke[kh] += ph;
  ke[kh + 1] += w - ph;
  kq[kp] += pp;
  kq[kp + 1] += w - pp;
}

/* Adds sign x the contribution (starts less ends) and the penalty
 * (penalty starts less starts) of a column's kinks (n cells, three arrays
 * `stride` apart) to contrib and penalty, and clears the kinks. */
static inline void dual_kinks_fold(int64_t *d, size_t stride, int n, int sign, int64_t *contrib,
                                   int64_t *penalty) {
  int64_t s = 0, e = 0, q = 0;
  for (int k = 0; k < n; k++) {
    s += d[k];
    e += d[stride + k];
    q += d[2 * stride + k];
    contrib[k] += sign * (s - e);
    penalty[k] += sign * (q - s);
  }
  memset(d, 0, (size_t)(n + 2) * sizeof *d);
  memset(d + stride, 0, (size_t)(n + 2) * sizeof *d);
  memset(d + 2 * stride, 0, (size_t)(n + 2) * sizeof *d);
}

/* Box of grid cell (dir index, k). */
void bbc__dual_grid_cell_box(const dual_grid *g, size_t dir, int k, dual_box *b);

/* ---- clustering (2.3.10) ------------------------------------------------- */

/* Isolation-step clustering of faces projected onto the plane with normal n:
 * splits along the plane's two axes and both diagonals, allowing gaps up to
 * `gap`, until stable. Writes a cluster label per face (0 = the cluster with
 * the largest projected area) and returns the number of clusters. */
size_t bbc__dual_cluster(const dual_face *faces, const uint32_t *which, size_t count,
                         const double n[3], double gap, uint32_t *label);

/* ---- plane tweaks (2.3.2, 2.3.3, 2.3.7) ---------------------------------- */

/* 1 when every face lies in one plane (within a small tolerance); writes it. */
int bbc__dual_coplanar(const dual_face *faces, const uint32_t *which, size_t count, double tol,
                       double n[3], double *rho);
/* Post-plane tweaking (Eq. 2-7, 2-8) with both reference points; returns 1
 * and replaces (n, rho) when a refined plane keeps every face valid and its
 * projected area does not shrink. */
int bbc__dual_posttweak(const dual_face *faces, const uint32_t *which, size_t count, double eps,
                        double n[3], double *rho);
/* Least-squares plane of the faces' vertices (area-weighted); returns 1
 * and replaces (n, rho) when it keeps every face valid. Orientation kept. */
int bbc__dual_fit_plane(const dual_face *faces, const uint32_t *which, size_t count, double eps,
                        double n[3], double *rho);
/* Minimum-area bounding rectangle of the faces projected onto the plane:
 * writes its in-plane axes u, w (unit) and the rectangle's extents
 * (BBC_ERROR_OUT_OF_MEMORY: an empty one). */
bbc_result bbc__dual_min_rect(const dual_face *faces, const uint32_t *which, size_t count,
                              const double n[3], double u[3], double w[3], double min_uv[2],
                              double max_uv[2]);
/* The same for points of a point cloud (mesh positions, which[count]):
 * each point projected once, the same rectangle as their dual faces'. */
bbc_result bbc__points_min_rect(const bbc_mesh *mesh, const uint32_t *which, size_t count,
                                const double n[3], double u[3], double w[3], double min_uv[2],
                                double max_uv[2]);

#endif /* BBC_DUAL_H */
