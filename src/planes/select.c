/*
 * select.c — step 2 of the Billboard Cloud algorithm for one part: the
 * greedy select with recursive refinement (thesis 2.1.8) and the extensions
 * that act on it: fail-safe "parachute" (2.3.4), supergreedy (2.3.6),
 * cardboard planes (2.3.7), view-dependent penalty (2.3.8), simple and
 * pre-clustering (2.3.10, in cluster.c), coplanar optimisation and
 * post-plane tweaking (2.3.2, 2.3.3, in tweak.c); then merging redundant
 * planes (merge.c).
 *
 * Per plane: pick the densest grid cell; take the unassigned faces simply
 * valid for it (the largest cluster of them when clustering); refine: while
 * the centre plane of the current box does not simplify every face of the
 * set, split the box and its 26 neighbours into 8 subcells each (216), keep
 * the densest subcell (densities from the current set only, subpenalty as
 * penalty factor) and the faces simply valid for it. Refinement evaluates a
 * face once per sub-direction (6 x 6) and bins the result into the 6 rho
 * slices, rather than once per subcell.
 */
#include "select.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct ctx {
  const dual_face *faces;
  size_t nf;
  dual_grid *g;
  const bbc_params *p;
  double eps;
  double gap;        /* clustering gap (2 % of the part radius) */
  uint8_t *assigned; /* per face */
  size_t remaining;
  int threads;
  const bbc_callbacks *cb;
  select_result *out;
  uint8_t *flag;                /* scratch per face */
  uint32_t *scratch;            /* scratch per face */
  uint32_t *label;              /* scratch per face */
  uint32_t *ev_faces, *ev_done; /* debug events: mesh triangles (NULL: no debug) */
  double part_radius;
  /* per face, for the select loop: the plane's faces (set), the faces a
   * candidate cell's plane came from and those it simplifies (cand0,
   * cand), the unassigned faces for the parachute (set0), and a work
   * buffer */
  uint32_t *set, *set0, *cand0, *cand, *work;
} ctx;

/* An Appendix A debug event (parameter `debug`): `set` as mesh triangles,
 * and the faces earlier planes simplified. */
static void debug_event(ctx *c, int level, int step, const uint32_t *set, size_t n) {
  if (!c->ev_faces || c->p->debug < level) return;
  size_t ns = 0, nd = 0; /* mesh triangles: a quad's two */
  for (size_t i = 0; i < n; i++) {
    const dual_face *f = &c->faces[set[i]];
    c->ev_faces[ns++] = f->mesh_index;
    if (f->mesh_index2 != UINT32_MAX) c->ev_faces[ns++] = f->mesh_index2;
  }
  for (size_t k = 0; k < c->nf; k++)
    if (c->assigned[k] == 1) {
      c->ev_done[nd++] = c->faces[k].mesh_index;
      if (c->faces[k].mesh_index2 != UINT32_MAX) c->ev_done[nd++] = c->faces[k].mesh_index2;
    }
  bbc_debug_event e = {level, "", c->out->plane_count, step, c->ev_faces, ns, c->ev_done, nd};
  c->cb->debug(c->cb->user, &e);
}

static int thread_count(const ctx *c) {
  return bbc__thread_count(c->threads);
}

/* View-dependent penalty (2.3.8): density factor for a normal elevation phi,
 * 1 - punishval at the poles (horizontal planes), 1 below the cutoff angle,
 * linear in between. */
static double view_factor(const bbc_params *p, double phi) {
  if (p->punish_value <= 0) return 1;
  double a = fabs(phi) * 180.0 / M_PI, cut = p->punish_cutoff_deg;
  if (a <= cut) return 1;
  double t = cut >= 90 ? 1 : (a - cut) / (90 - cut);
  if (t > 1) t = 1;
  return 1 - p->punish_value * t;
}

static double read_density(const ctx *c, int64_t contrib, int64_t penalty, double factor,
                           double phi) {
  double d = (double)contrib - factor * (double)penalty;
  return d > 0 ? d * view_factor(c->p, phi) : d;
}

/* A face's range of valid rho over a direction box (simple validity); a
 * point's exact range (2.4.2). 0 when no plane of the box can be valid. */
static int range_over_box(const ctx *c, const dual_face *f, const dual_dir *dir,
                          const dual_box_trig *bt, double *lo, double *hi) {
  if (!f->point) return dual_face_range(f, dir, c->eps, lo, hi);
  double a, b, cc;
  dual_point_frame(&c->g->frame, f->c, &a, &b, &cc);
  dual_point_extremes(a, b, cc, bt, lo, hi);
  *lo -= c->eps;
  *hi += c->eps;
  return 1;
}

/* Faces of `in` (or all unassigned faces when in == NULL) simply valid for
 * box b, written to out in ascending order; returns their number. */
static size_t simply_valid(ctx *c, const dual_box *b, const uint32_t *in, size_t n_in,
                           uint32_t *out) {
  dual_dir dir;
  bbc__dual_dir_of_box(&c->g->frame, b, &dir);
  dual_box_trig bt;
  dual_box_trig_of(b, &bt);
  size_t n = in ? n_in : c->nf;
  int nt = thread_count(c);
  (void)nt;
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 256) num_threads(nt) if (n > 256)
#endif
  for (size_t i = 0; i < n; i++) {
    size_t f = in ? in[i] : i;
    double lo, hi;
    c->flag[i] = (in || !c->assigned[f]) && range_over_box(c, &c->faces[f], &dir, &bt, &lo, &hi) &&
                 hi >= b->r0 && lo <= b->r1;
  }
  size_t k = 0;
  for (size_t i = 0; i < n; i++)
    if (c->flag[i]) out[k++] = (uint32_t)(in ? in[i] : i);
  return k;
}

/* Keeps only the largest cluster of `set` projected onto normal n. */
static size_t largest_cluster(ctx *c, uint32_t *set, size_t n, const double normal[3],
                              double *fraction) {
  if (n < 2) {
    if (fraction) *fraction = 1;
    return n;
  }
  bbc__dual_cluster(c->faces, set, n, normal, c->gap, c->label);
  double all = 0, kept_area = 0;
  size_t k = 0;
  for (size_t i = 0; i < n; i++) {
    double a = dual_projected_area(&c->faces[set[i]], normal);
    all += a;
    if (c->label[i] == 0) {
      kept_area += a;
      set[k++] = set[i];
    }
  }
  if (fraction) *fraction = all > 0 ? kept_area / all : 1;
  return k;
}

/* Faces of set (all unassigned faces when set == NULL) valid for plane
 * (n, rho): count and fixed-point projected area. */
static size_t count_valid(ctx *c, const uint32_t *set, size_t n, const double normal[3], double rho,
                          int64_t *area_fixed) {
  size_t count = 0;
  int64_t area = 0;
  size_t total = set ? n : c->nf;
  int nt = thread_count(c);
  (void)nt;
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 256) reduction(+ : count, area) num_threads(nt) if (total > 256)
#endif
  for (size_t i = 0; i < total; i++) {
    if (!set && c->assigned[i]) continue;
    const dual_face *f = &c->faces[set ? set[i] : i];
    if (bbc__dual_face_valid(f, normal, rho, c->eps)) {
      count++;
      area += llround(dual_projected_area(f, normal) * c->g->scale);
    }
  }
  if (area_fixed) *area_fixed = area;
  return count;
}

/* A point's shares of the 36 x 6 subcells of a refinement step (2.4.3, Eq.
 * 2-11/2-12): subcells are finer than eps, so a point gives more the closer
 * it lies to a subcell's centre plane, and penalises a plane it lies in
 * front of by eps to 2 eps. */
static BBC__CLONES void point_subcells(const ctx *c, const dual_face *f, const dual_box *b,
                                       const double *nx, const double *ny, const double *nz,
                                       const int *valid_dir, int64_t (*contrib)[6],
                                       int64_t (*penalty)[6]) {
  double dr = 0.5 * (b->r1 - b->r0), base = b->r0 - 2 * dr, eps = c->eps, scale = c->g->scale;
  double e2 = 2 * eps / dr, e1 = eps / dr;
  int oriented = f->n[0] != 0 || f->n[1] != 0 || f->n[2] != 0; /* else it counts whole */
  /* Each sub-direction's rho, slice range and weight, all 36 at once (a
   * sub-direction beyond a pole has n = 0 and is skipped below). */
  double rho[36], lo[36], hi[36], w[36];
  const double c0 = f->c[0], c1 = f->c[1], c2 = f->c[2], area = f->area;
  const double n0 = f->n[0], n1 = f->n[1], n2 = f->n[2];
  for (int s = 0; s < 36; s++) {
    rho[s] = c0 * nx[s] + c1 * ny[s] + c2 * nz[s];
    /* only slices whose centre lies within [rho - 2 eps, rho + eps] */
    double x = (rho[s] - base) / dr - 0.5;
    lo[s] = ceil(x - e2);
    hi[s] = floor(x + e1);
    double pa = area * fabs(n0 * nx[s] + n1 * ny[s] + n2 * nz[s]);
    w[s] = (oriented ? pa : area) * scale;
  }
  for (int s = 0; s < 36; s++) {
    if (!valid_dir[s]) continue;
    int r0 = (int)lo[s], r1 = (int)hi[s];
    if (r0 < 0) r0 = 0;
    if (r1 > 5) r1 = 5;
    for (int r = r0; r <= r1; r++) {
      double mid = base + (r + 0.5) * dr, d = rho[s] - mid, ad = fabs(d);
      if (ad <= eps)
        contrib[s][r] += (int64_t)(w[s] * (1 - ad / eps) + 0.5);
      else if (d > 0 && d <= 2 * eps)
        penalty[s][r] += (int64_t)(w[s] * (2 * eps - d) / eps + 0.5);
    }
  }
}

/* A refinement step's subcells: ND x ND sub-directions, NR rho slices;
 * their kink arrays NR + 2 long (dual_column_add's). */
enum { ND = 6, NR = 6, NK = NR + 2 };

/* The 36 sub-directions of a refinement step as structure-of-arrays (0
 * where a sub-direction lies beyond a pole), for dual_face_ranges. */
typedef struct subdirs {
  double nx[36], ny[36], nz[36], rad[36];
} subdirs;

/* What holds for every valid sub-direction s of a refinement step: its
 * centre normal n_s lies within chord distance `d` of `nu`, its radius is
 * at least `rmin`; the six rho slices run from rbase to rtop. */
typedef struct subdir_bound {
  double nu[3], d, rmin, rbase, rtop;
} subdir_bound;

/* 1 when a face's shares are certainly whole in every slice of every valid
 * sub-direction, without penalty: dual_face_range's range (the same
 * formula, bounded over the sub-directions through nu, d and rmin, with a
 * margin far above its rounding) holds the six slices, and the face's
 * normal keeps its sign against every n_s. Then its share in each slice of
 * s is its projected area, sign x area x (n_f . n_s): linear in n_s, so the
 * faces of a set sum to one vector. Most faces are so in the later steps,
 * whose boxes are small against epsilon. */
static inline int whole_in_subcells(const dual_face *f, const subdir_bound *u, double eps) {
  const double *n = u->nu;
  double cu = f->c[0] * n[0] + f->c[1] * n[1] + f->c[2] * n[2];
  double amax = -HUGE_VAL, amin = HUGE_VAL;
  for (int i = 0; i < 4; i++) {
    double a = f->d[i][0] * n[0] + f->d[i][1] * n[1] + f->d[i][2] * n[2];
    amax = a > amax ? a : amax;
    amin = a < amin ? a : amin;
  }
  double pu = f->n[0] * n[0] + f->n[1] * n[1] + f->n[2] * n[2];
  double scale = f->c_len + f->d_max + eps, slack = 1e-12 * scale, m = 1e-9 * scale;
  double wl = f->c_len + f->d_max, spread = u->d - u->rmin;
  return amax - amin + 2 * f->d_max * spread <= 2 * eps + slack - m &&
         cu + amax + wl * spread - eps - slack <= u->rbase - m &&
         cu + amin - wl * spread + eps + slack >= u->rtop + m && fabs(pu) > u->d + 1e-9;
}

/* The shares of n faces of a set in the 36 x 6 subcells: for each face
 * the arithmetic of dual_face_range (over all 36 at once, vectorised) and
 * dual_projected_area, then dual_column_add over the six rho slices, into
 * kink arrays (diff[s]: dual_column_add's three), or, where its range holds
 * all six slices of sub-direction s, its share into whole[s] (what the
 * kinks would give: the share in each slice, no penalty); a face whole in
 * every subcell (whole_in_subcells) only into agg, the sum of its signed
 * area vectors in fixed point. */
static BBC__CLONES void faces_subcells(const ctx *c, const uint32_t *set, size_t n,
                                       const dual_box *b, const subdirs *sd, const int *valid_dir,
                                       const subdir_bound *u, int64_t (*diff)[3 * NK],
                                       int64_t *whole, int64_t agg[3]) {
  const double eps = c->eps, scale = c->g->scale, dr = 0.5 * (b->r1 - b->r0);
  const double rbase = b->r0 - 2 * dr, inv = 1.0 / dr, e = eps * inv;
  double lo[36], hi[36], proj[36], ok[36];
  for (size_t i = 0; i < n; i++) {
    const dual_face *f = &c->faces[set[i]];
    if (f->area > 0 && whole_in_subcells(f, u, eps)) {
      double sg = f->n[0] * u->nu[0] + f->n[1] * u->nu[1] + f->n[2] * u->nu[2] > 0 ? 1 : -1;
      for (int k = 0; k < 3; k++) agg[k] += (int64_t)floor(sg * f->area * scale * f->n[k] + 0.5);
      continue;
    }
    dual_face_ranges(f, sd->nx, sd->ny, sd->nz, sd->rad, 36, eps, lo, hi, ok);
    for (int s = 0; s < 36; s++) {
      double pn = f->n[0] * sd->nx[s] + f->n[1] * sd->ny[s] + f->n[2] * sd->nz[s];
      proj[s] = f->area * (pn < 0 ? -pn : pn) * scale;
    }
    for (int s = 0; s < 36; s++) {
      if (!valid_dir[s] || ok[s] == 0 || !(proj[s] > 0)) continue;
      double x = (lo[s] - rbase) * inv, y = (hi[s] - rbase) * inv;
      if (x <= 0 && y >= NR) /* whole in this sub-direction's slices: no kinks */
        whole[s] += (int64_t)(proj[s] + 0.5);
      else
        dual_column_add(diff[s], NK, NR, x, y, e, (int64_t)(proj[s] + 0.5));
    }
  }
}

/* A refinement step's 36 sub-directions of box b (ND x ND, those beyond a
 * pole not valid), the same as structure-of-arrays, and their bound. */
typedef struct refine_dirs {
  int valid[ND * ND];
  dual_dir dirs[ND * ND];
  subdirs sd;
  subdir_bound u;
} refine_dirs;

static void refine_dirs_of(const ctx *c, const dual_box *b, refine_dirs *rd) {
  double dt = 0.5 * (b->t1 - b->t0), dp = 0.5 * (b->p1 - b->p0), dr = 0.5 * (b->r1 - b->r0);
  int *valid_dir = rd->valid;
  dual_dir *dirs = rd->dirs;
  for (int j = 0; j < ND; j++)
    for (int i = 0; i < ND; i++) {
      int s = j * ND + i;
      dual_box sb = {b->t0 - 2 * dt + i * dt,
                     b->t0 - dt + i * dt,
                     b->p0 - 2 * dp + j * dp,
                     b->p0 - dp + j * dp,
                     0,
                     0};
      /* Beyond a pole the directions repeat those on the other side. */
      valid_dir[s] = sb.p0 >= -M_PI / 2 - 1e-12 && sb.p1 <= M_PI / 2 + 1e-12;
      if (valid_dir[s]) bbc__dual_dir_of_box(&c->g->frame, &sb, &dirs[s]);
    }
  subdirs *sd = &rd->sd;
  for (int s = 0; s < ND * ND; s++) {
    sd->nx[s] = valid_dir[s] ? dirs[s].n[0] : 0;
    sd->ny[s] = valid_dir[s] ? dirs[s].n[1] : 0;
    sd->nz[s] = valid_dir[s] ? dirs[s].n[2] : 0;
    sd->rad[s] = valid_dir[s] ? dirs[s].radius : 0;
  }
  /* The bound of every valid sub-direction, for whole_in_subcells. */
  subdir_bound u = {{0, 0, 0}, 0, HUGE_VAL, b->r0 - 2 * dr, b->r0 + 4 * dr};
  for (int s = 0; s < ND * ND; s++)
    if (valid_dir[s])
      for (int k = 0; k < 3; k++) u.nu[k] += dirs[s].n[k];
  double ul = sqrt(u.nu[0] * u.nu[0] + u.nu[1] * u.nu[1] + u.nu[2] * u.nu[2]);
  for (int k = 0; k < 3; k++) u.nu[k] = ul > 0 ? u.nu[k] / ul : 0;
  for (int s = 0; s < ND * ND; s++) {
    if (!valid_dir[s]) continue;
    double dx = dirs[s].n[0] - u.nu[0], dy = dirs[s].n[1] - u.nu[1], dz = dirs[s].n[2] - u.nu[2];
    u.d = fmax(u.d, sqrt(dx * dx + dy * dy + dz * dz));
    u.rmin = fmin(u.rmin, dirs[s].radius);
  }
  u.d = u.d * (1 + 1e-9) + 1e-12;
  rd->u = u;
}

/* The faces' (or points') shares in the 36 x 6 subcells, added to contrib
 * and penalty. Each face read once for the 36 sub-directions, chunks of the
 * set per thread, integer sums (the same whatever the split). A
 * sub-direction per thread streaming the set 36 times made memory the
 * bottleneck on large sets. A part is all points or all triangles. */
static void refine_sums(const ctx *c, const dual_box *b, const uint32_t *set, size_t n,
                        const refine_dirs *rd, int64_t (*contrib)[NR], int64_t (*penalty)[NR]) {
  int points = n && c->faces[set[0]].point;
  int64_t agg[3] = {0, 0, 0};
  int nt = thread_count(c);
  (void)nt;
#ifdef _OPENMP
#pragma omp parallel num_threads(nt) if (n > (points ? 256u : 512u))
#endif
  {
    int64_t lc[ND * ND][NR], lp[ND * ND][NR], diff[ND * ND][3 * NK], la[3] = {0, 0, 0};
    int64_t lw[ND * ND] = {0};
    memset(lc, 0, sizeof lc);
    memset(lp, 0, sizeof lp);
    memset(diff, 0, sizeof diff);
    int tid = 0, tn = 1;
#ifdef _OPENMP
    tid = omp_get_thread_num();
    tn = omp_get_num_threads();
#endif
    /* Chunks dealt in turn: faces near one another cost alike (whole in
     * every subcell or not), so halves of the set would not. */
    enum { CHUNK = 64 };
    for (size_t i0 = (size_t)tid * CHUNK; i0 < n; i0 += (size_t)tn * CHUNK) {
      size_t i1 = n - i0 > CHUNK ? i0 + CHUNK : n;
      if (points)
        for (size_t i = i0; i < i1; i++)
          point_subcells(c, &c->faces[set[i]], b, rd->sd.nx, rd->sd.ny, rd->sd.nz, rd->valid, lc,
                         lp);
      else
        faces_subcells(c, set + i0, i1 - i0, b, &rd->sd, rd->valid, &rd->u, diff, lw, la);
    }
    if (!points)
      for (int s = 0; s < ND * ND; s++) {
        dual_kinks_fold(diff[s], NK, NR, 1, lc[s], lp[s]);
        for (int r = 0; r < NR; r++) lc[s][r] += lw[s];
      }
#ifdef _OPENMP
#pragma omp critical(bbc_refine_sum)
#endif
    {
      for (int s = 0; s < ND * ND; s++)
        for (int r = 0; r < NR; r++) {
          contrib[s][r] += lc[s][r];
          penalty[s][r] += lp[s][r];
        }
      for (int k = 0; k < 3; k++) agg[k] += la[k];
    }
  }
  /* The faces whole in every subcell: their summed area vector, the same
   * share in each slice of a sub-direction. */
  for (int s = 0; s < ND * ND; s++) {
    if (!rd->valid[s]) continue;
    const dual_dir *ds = &rd->dirs[s];
    double w = (double)agg[0] * ds->n[0] + (double)agg[1] * ds->n[1] + (double)agg[2] * ds->n[2];
    int64_t wi = w > 0 ? (int64_t)(w + 0.5) : 0;
    for (int r = 0; r < NR; r++) contrib[s][r] += wi;
  }
}

/* The densest subcell (sub-penalty as penalty factor) into best; 0 when
 * none has density > 0. */
static int refine_best(const ctx *c, const dual_box *b, const refine_dirs *rd,
                       int64_t (*contrib)[NR], int64_t (*penalty)[NR], dual_box *best) {
  double dt = 0.5 * (b->t1 - b->t0), dp = 0.5 * (b->p1 - b->p0), dr = 0.5 * (b->r1 - b->r0);
  double best_d = 0;
  int found = 0;
  for (int s = 0; s < ND * ND; s++) {
    if (!rd->valid[s]) continue;
    for (int r = 0; r < NR; r++) {
      double d = read_density(c, contrib[s][r], penalty[s][r], c->p->sub_penalty, rd->dirs[s].phi);
      if (d > best_d) {
        best_d = d;
        found = 1;
        int i = s % ND, j = s / ND;
        best->t0 = b->t0 - 2 * dt + i * dt;
        best->t1 = best->t0 + dt;
        best->p0 = b->p0 - 2 * dp + j * dp;
        best->p1 = best->p0 + dp;
        best->r0 = b->r0 - 2 * dr + r * dr;
        best->r1 = best->r0 + dr;
      }
    }
  }
  return found;
}

/* One refinement step: the densest of the 216 subcells of box b and its 26
 * neighbours, from the faces of set. Returns 0 when none has density > 0. */
static int refine_step(ctx *c, const dual_box *b, const uint32_t *set, size_t n, dual_box *best) {
  int64_t contrib[ND * ND][NR], penalty[ND * ND][NR];
  refine_dirs rd;
  refine_dirs_of(c, b, &rd);
  memset(contrib, 0, sizeof contrib);
  memset(penalty, 0, sizeof penalty);
  refine_sums(c, b, set, n, &rd, contrib, penalty);
  return refine_best(c, b, &rd, contrib, penalty, best);
}

typedef struct found_plane {
  double n[3];
  double rho;
  bbc_plane_kind kind;
} found_plane;

typedef struct area_index {
  double area;
  uint32_t index;
} area_index;

static int area_index_cmp(const void *a, const void *b) {
  const area_index *x = a, *y = b;
  if (x->area != y->area) return x->area > y->area ? -1 : 1;
  return (x->index > y->index) - (x->index < y->index);
}

/* Fail-safe (2.3.4): the supporting plane of one of the set's faces that is
 * valid for the most faces of the set (candidates: the 64 largest faces),
 * or their area-weighted average plane if that is valid for more. */
static found_plane parachute(ctx *c, const uint32_t *set, size_t n) {
  found_plane fp = {{0, 0, 1}, 0, BBC_PLANE_PARACHUTE};
  area_index *cand = malloc(n * sizeof *cand);
  if (!cand) return fp; /* out of memory: the first face's plane below */
  for (size_t i = 0; i < n; i++) {
    cand[i].area = c->faces[set[i]].area;
    cand[i].index = set[i];
  }
  qsort(cand, n, sizeof *cand, area_index_cmp);
  size_t nc = n < 64 ? n : 64, best_count = 0;
  int64_t best_area = -1;
  for (size_t i = 0; i < nc + 1; i++) {
    double nn[3], rho;
    if (i < nc) {
      const dual_face *f = &c->faces[cand[i].index];
      memcpy(nn, f->n, sizeof nn);
      if (f->point && nn[0] == 0 && nn[1] == 0 && nn[2] == 0) {
        /* no normal: the plane through it facing away from the centre */
        nn[2] = 1;
        if (f->c_len > 0)
          for (int k = 0; k < 3; k++) nn[k] = f->c[k] / f->c_len;
      }
      rho = nn[0] * f->c[0] + nn[1] * f->c[1] + nn[2] * f->c[2];
    } else if (c->faces[set[0]].point) {
      continue; /* the weighted average plane needs face normals */
    } else {
      /* Weighted average plane (Eq. 2-7/2-8, origin as reference). */
      memcpy(nn, fp.n, sizeof nn);
      rho = fp.rho;
      if (!bbc__dual_posttweak(c->faces, set, n, INFINITY, nn, &rho)) continue;
    }
    int64_t area;
    size_t cnt = count_valid(c, set, n, nn, rho, &area);
    if (cnt > best_count || (cnt == best_count && area > best_area)) {
      best_count = cnt;
      best_area = area;
      memcpy(fp.n, nn, sizeof nn);
      fp.rho = rho;
    }
  }
  free(cand);
  return fp;
}

/* The densest grid cells, best first (at most `want`), with pre-clustering
 * weights for the top cells (Eq. 2-9) when clustering = 2. Returns how many
 * cells have density > 0 (up to want). */
static int densest_cells(ctx *c, size_t *cells, int want) {
  dual_grid *g = c->g;
  size_t nd = (size_t)g->n_theta * g->n_phi, ncell = nd * g->n_rho;
  enum { TOP = 20, LIST = 24 };
  size_t top[LIST];
  double topd[LIST];
  int ntop = 0;
  int list = c->p->clustering == BBC_CLUSTERING_PRE ? TOP + want : want;
  if (list > LIST) list = LIST;
  for (size_t cell = 0; cell < ncell; cell++) {
    double d = read_density(c, g->contrib[cell], g->penalty[cell], g->penalty_factor,
                            g->dirs[cell / g->n_rho].phi);
    if (!(d > 0)) continue;
    /* Sorted descending; ties keep the lower cell index first. */
    int pos = ntop;
    while (pos > 0 && topd[pos - 1] < d) pos--;
    if (pos >= list) continue;
    int last = ntop < list ? ntop : list - 1;
    for (int k = last; k > pos; k--) {
      top[k] = top[k - 1];
      topd[k] = topd[k - 1];
    }
    top[pos] = cell;
    topd[pos] = d;
    if (ntop < list) ntop++;
  }
  if (c->p->clustering == BBC_CLUSTERING_PRE) {
    /* Pre-clustering (Eq. 2-9): the top cells' densities weighted by their
     * largest cluster's share of their faces' coverage; the cells after
     * them keep their plain density. Then re-sort (stable). */
    for (int k = 0; k < ntop && k < TOP; k++) {
      dual_box b;
      bbc__dual_grid_cell_box(g, top[k] / g->n_rho, (int)(top[k] % g->n_rho), &b);
      size_t n = simply_valid(c, &b, NULL, 0, c->scratch);
      double frac = 1;
      if (n > 1) largest_cluster(c, c->scratch, n, g->dirs[top[k] / g->n_rho].n, &frac);
      topd[k] *= frac;
    }
    for (int i = 1; i < ntop; i++) {
      size_t x = top[i];
      double xd = topd[i];
      int j = i;
      while (j > 0 && topd[j - 1] < xd) {
        top[j] = top[j - 1];
        topd[j] = topd[j - 1];
        j--;
      }
      top[j] = x;
      topd[j] = xd;
    }
  }
  int n = ntop < want ? ntop : want;
  for (int k = 0; k < n; k++) cells[k] = top[k];
  return n;
}

/* Recursive refinement (2.1.8) from box over the faces set0[n0] (work
 * buffer `set`): stops when the centre plane simplifies every face of the
 * current set, and takes that plane. (Keeping instead the centre plane that
 * simplified the most on the way was tried: it takes more faces per plane
 * early but needs more planes in all, because
 * such planes cut through foliage layers instead of lying in them.) After
 * `break` steps with more than `breaknum` faces left, the best centre plane
 * seen is taken. Returns 0 when no plane was found (parachute). */
static int refine_plane(ctx *c, dual_box box, const uint32_t *set0, size_t n0, uint32_t *set,
                        found_plane *fp) {
  const bbc_params *p = c->p;
  memcpy(set, set0, n0 * sizeof *set);
  size_t n = n0;
  found_plane best = {{0, 0, 0}, 0, BBC_PLANE_STANDARD};
  int64_t best_area = 0;
  for (int step = 0;; step++) {
    dual_dir dd;
    bbc__dual_dir_of_box(&c->g->frame, &box, &dd);
    double rho = 0.5 * (box.r0 + box.r1);
    int64_t area;
    size_t cnt = count_valid(c, set, n, dd.n, rho, &area);
    if (area > best_area) {
      best_area = area;
      memcpy(best.n, dd.n, sizeof best.n);
      best.rho = rho;
    }
    if (cnt == n) {
      memcpy(fp->n, dd.n, sizeof fp->n);
      fp->rho = rho;
      fp->kind = BBC_PLANE_STANDARD;
      return 1;
    }
    int tiny = (box.t1 - box.t0) < 1e-9 && (box.r1 - box.r0) < 1e-9 * c->eps;
    if ((step >= p->break_steps && n > (size_t)p->break_num) || tiny || step > 200) {
      *fp = best;
      return best_area > 0;
    }
    dual_box sub;
    if (!refine_step(c, &box, set, n, &sub)) return 0;
    size_t m = simply_valid(c, &sub, set, n, c->scratch);
    if (m == 0) return 0;
    memcpy(set, c->scratch, m * sizeof *set);
    n = m;
    box = sub;
    debug_event(c, 2, step + 1, set, n);
  }
}

static bbc_result push_plane(ctx *c, const found_plane *fp, size_t face_count, double area,
                             int32_t mother, double coverage) {
  select_result *o = c->out;
  if (o->plane_count == o->plane_cap) {
    size_t cap = o->plane_cap ? 2 * o->plane_cap : 32;
    bbc_plane *p = realloc(o->planes, cap * sizeof *p);
    if (!p) return BBC_ERROR_OUT_OF_MEMORY;
    o->planes = p;
    o->plane_cap = cap;
  }
  bbc_plane *pl = &o->planes[o->plane_count++];
  memset(pl, 0, sizeof *pl);
  memcpy(pl->normal, fp->n, sizeof pl->normal);
  pl->d = fp->rho; /* grid frame; the caller moves it to the model frame */
  pl->kind = fp->kind;
  pl->face_count = face_count;
  pl->area = area;
  pl->mother = mother;
  pl->coverage_pct = coverage;
  return BBC_OK;
}

/* Cardboard plane (2.3.7) for mother (n, rho) and its faces. */
static bbc_result add_cardboard(ctx *c, const found_plane *mother, const uint32_t *set, size_t n,
                                double mother_area, int32_t mother_index) {
  double u[3], w[3], mn[2], mx[2];
  if (bbc__dual_min_rect(c->faces, set, n, mother->n, u, w, mn, mx) != BBC_OK)
    return BBC_ERROR_OUT_OF_MEMORY;
  /* Through the centre of gravity of the projected faces. */
  double cg[3] = {0, 0, 0}, a = 0;
  for (size_t i = 0; i < n; i++) {
    const dual_face *f = &c->faces[set[i]];
    double pa = dual_projected_area(f, mother->n);
    for (int k = 0; k < 3; k++) cg[k] += pa * f->c[k];
    a += pa;
  }
  if (!(a > 0)) return BBC_OK;
  for (int k = 0; k < 3; k++) cg[k] /= a;
  const double *axes[2] = {u, w};
  found_plane best = {{0, 0, 0}, 0, BBC_PLANE_CARDBOARD};
  size_t best_n = 0;
  double best_area = 0;
  for (int k = 0; k < 2; k++) {
    found_plane cand = {{axes[k][0], axes[k][1], axes[k][2]}, 0, BBC_PLANE_CARDBOARD};
    cand.rho = cand.n[0] * cg[0] + cand.n[1] * cg[1] + cand.n[2] * cg[2];
    size_t cnt = 0;
    double area = 0;
    for (size_t i = 0; i < n; i++) {
      const dual_face *f = &c->faces[set[i]];
      if (bbc__dual_face_valid(f, cand.n, cand.rho, c->eps)) {
        cnt += f->mesh_index2 != UINT32_MAX ? 2 : 1; /* mesh triangles */
        area += dual_projected_area(f, cand.n);
      }
    }
    if (area > best_area) {
      best = cand;
      best_n = cnt;
      best_area = area;
    }
  }
  if (best_n == 0) return BBC_OK;
  return push_plane(c, &best, best_n, best_area, mother_index, 100.0 * best_area / mother_area);
}

/* The select's buffers, and out->face_plane; BBC_ERROR_OUT_OF_MEMORY when
 * one could not be had (ctx_free frees what was). */
static bbc_result ctx_alloc(ctx *c) {
  size_t nf = c->nf;
  select_result *out = c->out;
  c->assigned = calloc(nf ? nf : 1, 1);
  c->flag = malloc(nf ? nf : 1);
  c->scratch = malloc((nf ? nf : 1) * sizeof *c->scratch);
  c->label = malloc((nf ? nf : 1) * sizeof *c->label);
  c->set = malloc((nf ? nf : 1) * sizeof *c->set);
  c->set0 = malloc((nf ? nf : 1) * sizeof *c->set0);
  c->cand0 = malloc((nf ? nf : 1) * sizeof *c->cand0);
  c->cand = malloc((nf ? nf : 1) * sizeof *c->cand);
  c->work = malloc((nf ? nf : 1) * sizeof *c->work);
  out->face_plane = malloc((nf ? nf : 1) * sizeof *out->face_plane);
  bbc_result r = BBC_OK;
  if (c->p->debug > 0 && c->cb && c->cb->debug) {
    c->ev_faces = malloc((nf ? 2 * nf : 1) * sizeof *c->ev_faces);
    c->ev_done = malloc((nf ? 2 * nf : 1) * sizeof *c->ev_done);
    if (!c->ev_faces || !c->ev_done) r = BBC_ERROR_OUT_OF_MEMORY;
  }
  if (!c->assigned || !c->flag || !c->scratch || !c->label || !c->set || !c->set0 || !c->cand0 ||
      !c->cand || !c->work || !out->face_plane)
    r = BBC_ERROR_OUT_OF_MEMORY;
  return r;
}

static void ctx_free(ctx *c) {
  free(c->ev_faces);
  free(c->ev_done);
  free(c->assigned);
  free(c->flag);
  free(c->scratch);
  free(c->label);
  free(c->set);
  free(c->set0);
  free(c->cand0);
  free(c->cand);
  free(c->work);
}

/* Candidates: the densest cells (one in the thesis; more with the
 * `candidates` extension), each refined to a plane; the plane that
 * simplifies the largest projected area wins. Its faces (those of its
 * cell's set valid for it) go to c->set; returns their number (0: none). */
static size_t best_candidate(ctx *c, int want, found_plane *fp) {
  const dual_face *faces = c->faces;
  dual_grid *g = c->g;
  uint32_t *cand0 = c->cand0, *cand = c->cand;
  size_t cells[4];
  int ncand = densest_cells(c, cells, want);
  size_t n = 0;
  double best_area = -1;
  for (int k = 0; k < ncand; k++) {
    dual_box box;
    bbc__dual_grid_cell_box(g, cells[k] / g->n_rho, (int)(cells[k] % g->n_rho), &box);
    size_t m0 = simply_valid(c, &box, NULL, 0, cand0);
    if (m0 == 0) continue;
    if (c->p->clustering != BBC_CLUSTERING_OFF) {
      m0 = largest_cluster(c, cand0, m0, g->dirs[cells[k] / g->n_rho].n, NULL);
      debug_event(c, 3, 0, cand0, m0);
    }
    found_plane cp;
    if (!refine_plane(c, box, cand0, m0, c->work, &cp)) cp = parachute(c, cand0, m0);
    /* The faces it simplifies: those of the cell's set valid for it. */
    size_t m = 0;
    double area = 0;
    for (size_t i = 0; i < m0; i++)
      if (bbc__dual_face_valid(&faces[cand0[i]], cp.n, cp.rho, c->eps)) {
        cand[m++] = cand0[i];
        area += dual_projected_area(&faces[cand0[i]], cp.n);
      }
    if (area > best_area) {
      best_area = area;
      *fp = cp;
      memcpy(c->set, cand, m * sizeof *c->set);
      n = m;
    }
  }
  return n;
}

/* No positive density left (penalties dominate) or rounding: the parachute
 * over every unassigned face always progresses. Its faces go to c->set;
 * returns their number. */
static size_t parachute_all(ctx *c, found_plane *fp) {
  size_t n0 = 0, n = 0;
  for (size_t f = 0; f < c->nf; f++)
    if (!c->assigned[f]) c->set0[n0++] = (uint32_t)f;
  *fp = parachute(c, c->set0, n0);
  for (size_t i = 0; i < n0; i++)
    if (bbc__dual_face_valid(&c->faces[c->set0[i]], fp->n, fp->rho, c->eps))
      c->set[n++] = c->set0[i];
  return n;
}

/* Tweaks (2.3.2, 2.3.3) of a standard plane and its n faces (c->set). */
static void tweak_plane(const ctx *c, found_plane *fp, size_t n) {
  const dual_face *faces = c->faces;
  const uint32_t *set = c->set;
  if (fp->kind == BBC_PLANE_STANDARD && n > 0 && !faces[set[0]].point) { /* 2.4.4: not for points */
    if (bbc__dual_coplanar(faces, set, n, 1e-9 * (c->part_radius + c->eps), fp->n, &fp->rho))
      fp->kind = BBC_PLANE_COPLANAR;
    else if (c->p->post_tweak && bbc__dual_posttweak(faces, set, n, c->eps, fp->n, &fp->rho))
      fp->kind = BBC_PLANE_POSTTWEAKED;
  }
}

/* Supergreedy (2.3.6) after the tweaks: a tweaked plane lies closer to its
 * faces' own plane, and so takes more of the faces around it. Adds to the
 * n faces of c->set every unassigned face valid for fp; returns their
 * number. */
static size_t super_greedy(ctx *c, const found_plane *fp, size_t n) {
  uint32_t *set = c->set;
  for (size_t i = 0; i < n; i++) c->assigned[set[i]] = 2; /* in the set already */
  size_t k = n;
  for (size_t f = 0; f < c->nf; f++)
    if (!c->assigned[f] && bbc__dual_face_valid(&c->faces[f], fp->n, fp->rho, c->eps))
      set[k++] = (uint32_t)f;
  for (size_t i = 0; i < n; i++) c->assigned[set[i]] = 0;
  return k;
}

/* Plane fp with its n faces (c->set): pushed, its faces assigned to it,
 * and its cardboard plane (2.3.7) after it. */
static bbc_result take_plane(ctx *c, const found_plane *fp, size_t n) {
  const uint32_t *set = c->set;
  select_result *out = c->out;
  assert(n > 0); /* a face is valid for its own plane */
  double area = 0;
  for (size_t i = 0; i < n; i++) area += dual_projected_area(&c->faces[set[i]], fp->n);
  int32_t index = (int32_t)out->plane_count;
  bbc_result r = push_plane(c, fp, n, area, -1, 100.0);
  if (r != BBC_OK) return r;
  debug_event(c, 1, 0, set, n);
  for (size_t i = 0; i < n; i++) {
    c->assigned[set[i]] = 1;
    out->face_plane[set[i]] = (uint32_t)index;
  }
  c->remaining -= n;
  if (c->p->cardboard && (r = add_cardboard(c, fp, set, n, area, index)) != BBC_OK) return r;
  return BBC_OK;
}

/* Grid update: exactly reverse the n simplified faces' density (2.1.8); or,
 * when fewer faces remain than were simplified, the grid anew from those
 * that remain (the same integer sums, less work). */
static bbc_result update_grid(ctx *c, size_t n) {
  dual_grid *g = c->g;
  if (c->remaining >= n) return bbc__dual_grid_accumulate(g, c->faces, c->set, n, -1, NULL);
  if (c->remaining > 0) {
    size_t k = 0, ncell = (size_t)g->n_theta * g->n_phi * g->n_rho;
    for (size_t f = 0; f < c->nf; f++)
      if (!c->assigned[f]) c->work[k++] = (uint32_t)f;
    memset(g->contrib, 0, ncell * sizeof *g->contrib);
    memset(g->penalty, 0, ncell * sizeof *g->penalty);
    return bbc__dual_grid_accumulate(g, c->faces, c->work, k, +1, NULL);
  }
  return BBC_OK;
}

/* One plane of the greedy select (2.1.8): found, tweaked, taken. */
static bbc_result select_plane(ctx *c, int want) {
  found_plane fp = {{0, 0, 0}, 0, BBC_PLANE_STANDARD};
  size_t n = best_candidate(c, want, &fp);
  if (n == 0) n = parachute_all(c, &fp);
  tweak_plane(c, &fp, n);
  if (c->p->super_greedy) n = super_greedy(c, &fp, n);
  bbc_result r = take_plane(c, &fp, n);
  if (r != BBC_OK) return r;
  return update_grid(c, n);
}

bbc_result bbc__select_planes(const dual_face *faces, size_t nf, dual_grid *g, const bbc_params *p,
                              double eps, double part_radius, const bbc_callbacks *cb,
                              select_result *out) {
  memset(out, 0, sizeof *out);
  ctx c;
  memset(&c, 0, sizeof c);
  c.faces = faces;
  c.nf = nf;
  c.g = g;
  c.p = p;
  c.eps = eps;
  c.gap = 0.02 * part_radius;
  c.part_radius = part_radius;
  c.threads = p->threads;
  c.cb = cb;
  c.out = out;
  c.remaining = nf;
  bbc_result r = ctx_alloc(&c);
  int want = p->candidates < 1 ? 1 : (p->candidates > 4 ? 4 : p->candidates);
  while (r == BBC_OK && c.remaining > 0) {
    r = select_plane(&c, want);
    if (r != BBC_OK) break;
    bbc__progress(cb, "select", 1.0 - (double)c.remaining / (double)nf);
    if (bbc__cancelled(cb)) {
      r = BBC_ERROR_CANCELLED;
      break;
    }
  }
  if (r == BBC_OK && p->merge) r = bbc__merge_planes(faces, nf, eps, out);
  ctx_free(&c);
  if (r != BBC_OK) bbc__select_result_free(out);
  return r;
}

void bbc__select_result_free(select_result *r) {
  free(r->planes);
  free(r->face_plane);
  memset(r, 0, sizeof *r);
}
