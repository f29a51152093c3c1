/*
 * treegen.h — what the built-in tree generator's three files share (src/gen;
 * internal): treegen.c (the public entry, the species and the plan),
 * treegen_grow.c (the skeleton's growth) and treegen_mesh.c (tubes, leaves
 * and the two textures). The generator's steps are described in treegen.c.
 */
#ifndef BBC_TREEGEN_H
#define BBC_TREEGEN_H

#include "base.h"
#include "vec3.h"

#define TG_PI        3.14159265358979323846
#define TG_DEG       (TG_PI / 180.0)
#define TG_LEVELS    4
#define TG_MAX_SIDES 24

/* Some unit vector perpendicular to unit vector d; horizontal when d is not
 * vertical, so "sideways" means the same thing on every branch. */
static inline vec3 vperp(vec3 d) {
  vec3 ref = fabs(d.y) < 0.95 ? v3(0, 1, 0) : v3(1, 0, 0);
  return vnorm(vcross(d, ref));
}
static inline double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}
static inline double clampd(double v, double lo, double hi) {
  return v < lo ? lo : v > hi ? hi : v;
}
static inline double rnd(bbc__rng *r, double lo, double hi) {
  return bbc__rng_range(r, lo, hi);
}
/* Random vector in the unit cube [-1, 1]^3 (direction noise; need not be
 * isotropic). */
static inline vec3 rnd_vec(bbc__rng *r) {
  double x = rnd(r, -1, 1), y = rnd(r, -1, 1), z = rnd(r, -1, 1);
  return v3(x, y, z);
}

/* ------------------------------------------------------------------------ */
/* Species                                                                   */
/* ------------------------------------------------------------------------ */

/* Where a level's branches (or the leaves) grow: on branches of
 * `parent_level`, between t0 and t1 of the parent's length (0 base, 1 tip),
 * `weight` per metre. A zero weight (a zeroed entry) is no rule. */
typedef struct tg_rule {
  int parent_level;
  double t0, t1, weight;
} tg_rule;

typedef struct tg_species {
  const char *name;
  bbc_tree_species shape;  /* the species whose branching code it shares */
  size_t structure_leaves; /* leafless species (default_leaves 0): the leaf count
                            * its twigs and branches are planned for */
  double droop;            /* extra gravity on twigs (hanging twigs), 0 = none */
  double twig_thin;        /* twig radius factor (< 1: thinner), 0 = 1 */
  double height;           /* nominal total height, m */
  size_t default_leaves;   /* leaves when options->leaves is 0 */
  double leaf_size;        /* edge of a leaf quad, m (the texture holds the blade) */
  float bark[3];           /* bark base colour */
  float leaf[3];           /* mean leaf colour of the texture */
  int levels;              /* branch levels in use: 3 (bush, pine) or 4 */
  double twig_factor;      /* twigs (finest level) = twig_factor * leaves^0.8 */
  double branch_factor;    /* branches of level 2 when twigs are level 3 = factor * leaves^0.55 */
  double leaf_exponent;    /* < 1 crowds leaves toward the twig tips */
  tg_rule rules[TG_LEVELS][2];
  tg_rule leaf_rules[2]; /* which branches carry leaves */
} tg_species;

/* ------------------------------------------------------------------------ */
/* Skeleton (treegen_grow.c)                                                 */
/* ------------------------------------------------------------------------ */

typedef struct tg_node {
  vec3 pos;
  double radius; /* 0 at the apex: the tube ends in a point */
} tg_node;

typedef struct tg_branch {
  size_t node; /* first of rings[level] + 1 nodes */
  int level;
  double length; /* m, along the polyline */
  double vigor;  /* inherited size factor: makes limbs differ, the crown lumpy */
} tg_branch;

/* How a branch bends while it grows (rates in radians per metre). */
typedef struct tg_growth {
  double gravity; /* droop, stronger where the branch is horizontal and toward its tip */
  double photo;   /* turning upward, toward the light */
  double wobble;  /* smooth random bending */
  double tip;     /* radius at the last ring relative to the base radius */
  double flare;   /* extra radius at the very base (root flare of trunks) */
} tg_growth;

typedef struct tg_ctx {
  bbc_tree_species species;
  bbc_tree_species shape; /* whose branching code it uses (info->shape) */
  const tg_species *info;
  size_t leaves;
  double height;    /* this tree's nominal height, m */
  double leaf_size; /* this tree's leaf edge, m */
  int levels;
  size_t count[TG_LEVELS]; /* branches per level */
  int sides[TG_LEVELS];    /* vertices around a ring */
  int rings[TG_LEVELS];    /* full rings per branch; the apex adds one node */
  int whorls, per_whorl;   /* pine only */
  size_t first[TG_LEVELS + 1];
  tg_branch *branches;
  size_t branch_count;
  tg_node *nodes;
  size_t node_count;
  bbc__rng rng_shape, rng_fine, rng_leaf, rng_texture;
} tg_ctx;

/* Where and how a child leaves its parent. */
typedef struct tg_attach {
  vec3 pos;     /* on the parent's axis */
  vec3 tangent; /* parent's direction there */
  double radius;
  double t; /* 0 base .. 1 tip of the parent */
  const tg_branch *parent;
} tg_attach;

/* Stratified spreading of `count` points over a run of branches, in
 * proportion to per-branch weights: point k falls at (k + jitter) / count of
 * the total weight. Linear time, and points come out grouped by branch and
 * ordered along it. */
typedef struct tg_spread {
  const double *cum; /* cumulative weights, one per branch */
  size_t n, count, k, p;
} tg_spread;

/* The next point of the spread: its branch (an index into the run) and
 * where along it (0..1); 0 when all are out. */
int bbc__tree_spread_next(tg_spread *s, bbc__rng *rng, size_t *branch, double *u);

/* Point, tangent and drawn radius of branch b at t in [0, 1]. */
void bbc__tree_branch_at(const tg_ctx *c, const tg_branch *b, double t, tg_attach *a);

/* The skeleton, level by level, so each level's branches are contiguous
 * (c->first[]); fails only when out of memory. */
bbc_result bbc__tree_skeleton(tg_ctx *c);

/* ------------------------------------------------------------------------ */
/* Geometry and textures (treegen_mesh.c)                                    */
/* ------------------------------------------------------------------------ */

typedef struct tg_out {
  bbc_mesh *m;
  size_t v, t; /* next vertex, next triangle */
} tg_out;

/* The leaf texture (texture 0) and the bark texture (texture 1). */
void bbc__tree_leaf_texture(tg_ctx *c, bbc_image *img);
void bbc__tree_bark_texture(tg_ctx *c, bbc_image *img);
/* Branch b as a tapered tube with a pointed tip. */
void bbc__tree_emit_tube(const tg_ctx *c, const tg_branch *b, tg_out *o);
/* Exactly c->leaves leaf quads over the branches that carry leaves. */
bbc_result bbc__tree_emit_leaves(const tg_ctx *c, tg_out *o, const bbc_callbacks *cb);

#endif /* BBC_TREEGEN_H */
