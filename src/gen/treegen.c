/*
 * treegen.c — the built-in procedural tree generator (bbc_tree_generate).
 *
 * The thesis tests BBCgen on trees; this generator gives the toolkit test
 * trees of any size without shipping model files. A tree is made in three
 * steps:
 *   1. plan: from the species and the requested leaf count decide how many
 *      branches each level gets and how finely the tubes are tessellated, so
 *      the wood stays a modest fraction of the triangles at every size;
 *   2. skeleton: the trunk (or the stems of a bush) first, then each level's
 *      branches are spread over the level above by stratified sampling along
 *      the parents' lengths (linear time, even spacing with jitter). Every
 *      branch is grown as a polyline bent by gravity, phototropism and a
 *      smooth random wobble, and kept only at the rings that will be drawn,
 *      so children sit exactly on the drawn axis of their parent;
 *   3. geometry: every branch becomes a tapered tube of rings with shared
 *      vertices and a pointed tip; leaves are textured quads spread over the
 *      finest branches (the twigs), denser toward the twig tips.
 * Two textures are generated: the leaf (texture 0, alpha exactly 0 or 255;
 * a needle spray for the pine) and a small tileable bark pattern (texture
 * 1, repeated along the branches, multiplied by the bark's base colour).
 *
 * Levels: 0 trunk (or bush stems), 1 limbs, 2 branches, 3 twigs. The finest
 * level in use carries the leaves (the pine's limbs too). All randomness
 * comes from bbc__rng streams derived from the seed and the species, in a
 * fixed order, so the same options always give byte-identical arrays.
 */
#include "base.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TG_PI          3.14159265358979323846
#define TG_DEG         (TG_PI / 180.0)
#define TG_LEVELS      4
#define TG_MAX_LEAVES  5000000u
#define TG_MIN_TEXTURE 8
#define TG_MAX_TEXTURE 4096
#define TG_MAX_SIDES   24
/* Fine polyline segments per level: the resolution at which a branch is
 * grown; the drawn rings are a subset, so a branch keeps its shape whatever
 * the tessellation. */
#define TG_MAX_FINE 32
static const int tg_fine_segments[TG_LEVELS] = {TG_MAX_FINE, 16, 8, 4};

/* ------------------------------------------------------------------------ */
/* Small vector helpers                                                      */
/* ------------------------------------------------------------------------ */

typedef struct vec3 {
  double x, y, z;
} vec3;

static vec3 v3(double x, double y, double z) {
  vec3 r = {x, y, z};
  return r;
}
static vec3 vadd(vec3 a, vec3 b) {
  return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static vec3 vsub(vec3 a, vec3 b) {
  return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static vec3 vscale(vec3 a, double s) {
  return v3(a.x * s, a.y * s, a.z * s);
}
/* a + b * s */
static vec3 vmadd(vec3 a, vec3 b, double s) {
  return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static double vdot(vec3 a, vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static vec3 vcross(vec3 a, vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double vlen(vec3 a) {
  return sqrt(vdot(a, a));
}
/* Unit vector along a; `fallback` when a is (nearly) zero. */
static vec3 vnorm_or(vec3 a, vec3 fallback) {
  double l = vlen(a);
  return l > 1e-12 ? vscale(a, 1.0 / l) : fallback;
}
static vec3 vnorm(vec3 a) {
  return vnorm_or(a, v3(0, 1, 0));
}
/* Some unit vector perpendicular to unit vector d; horizontal when d is not
 * vertical, so "sideways" means the same thing on every branch. */
static vec3 vperp(vec3 d) {
  vec3 ref = fabs(d.y) < 0.95 ? v3(0, 1, 0) : v3(1, 0, 0);
  return vnorm(vcross(d, ref));
}
static double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}
static double clampd(double v, double lo, double hi) {
  return v < lo ? lo : v > hi ? hi : v;
}
static double rnd(bbc__rng *r, double lo, double hi) {
  return bbc__rng_range(r, lo, hi);
}
/* Random vector in the unit cube [-1, 1]^3 (direction noise; need not be
 * isotropic). */
static vec3 rnd_vec(bbc__rng *r) {
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

/* The oak's branching, shared by the winter oak. */
#define TG_OAK_BRANCHING                                                                           \
  .levels = 4, .twig_factor = 0.40, .branch_factor = 1.3, .leaf_exponent = 0.4,                    \
  .rules = {[1] = {{0, 0.32, 0.97, 1}},                                                            \
            [2] = {{1, 0.15, 1.0, 1}, {0, 0.80, 1.0, 1}},                                          \
            [3] = {{2, 0.10, 1.0, 1}, {1, 0.5, 1.0, 1}}},                                          \
  .leaf_rules = {{3, 0.40, 1.0, 1}}

static const tg_species tg_species_table[BBC_TREE_SPECIES_COUNT] = {
    {.name = "oak",
     .shape = BBC_TREE_OAK,
     .height = 13.0,
     .default_leaves = 20000,
     .leaf_size = 0.24,
     .bark = {0.46f, 0.37f, 0.29f},
     .leaf = {0.22f, 0.40f, 0.12f},
     TG_OAK_BRANCHING},
    {.name = "pine",
     .shape = BBC_TREE_PINE,
     .height = 20.0,
     .default_leaves = 8000,
     .leaf_size = 0.45,
     .bark = {0.50f, 0.36f, 0.27f},
     .leaf = {0.12f, 0.27f, 0.11f},
     .levels = 3,
     .twig_factor = 0.50,
     .leaf_exponent = 1.0,
     /* Level 1 (the whorls) is placed by its own code. */
     .rules = {[2] = {{1, 0.10, 0.95, 1}}},
     .leaf_rules = {{2, 0.0, 1.0, 1}, {1, 0.35, 1.0, 0.8}}},
    {.name = "birch",
     .shape = BBC_TREE_BIRCH,
     .height = 16.0,
     .default_leaves = 20000,
     .leaf_size = 0.13,
     .bark = {0.90f, 0.88f, 0.84f},
     .leaf = {0.33f, 0.52f, 0.14f},
     .levels = 4,
     .twig_factor = 0.40,
     .branch_factor = 0.9,
     .leaf_exponent = 0.8,
     .rules = {[1] = {{0, 0.27, 0.97, 1}}, [2] = {{1, 0.15, 1.0, 1}}, [3] = {{2, 0.10, 1.0, 1}}},
     .leaf_rules = {{3, 0.0, 1.0, 1}, {2, 0.4, 1.0, 0.5}}},
    {.name = "bush",
     .shape = BBC_TREE_BUSH,
     .height = 2.6,
     .default_leaves = 8000,
     .leaf_size = 0.12,
     .bark = {0.46f, 0.39f, 0.32f},
     .leaf = {0.17f, 0.36f, 0.11f},
     .levels = 3,
     .twig_factor = 0.40,
     .leaf_exponent = 0.6,
     .rules = {[1] = {{0, 0.12, 0.95, 1}}, [2] = {{1, 0.10, 1.0, 1}, {0, 0.50, 1.0, 0.6}}},
     .leaf_rules = {{2, 0.15, 1.0, 1}}},
    /* Airy species (sparse crowns, thin parts: what clouds find hardest). */
    {.name = "larch", /* a conifer: needle tufts on long thin twigs, see-through */
     .shape = BBC_TREE_PINE,
     .height = 18.0,
     .default_leaves = 2500,
     .leaf_size = 0.22,
     .bark = {0.45f, 0.33f, 0.26f},
     .leaf = {0.30f, 0.45f, 0.16f},
     .levels = 3,
     .twig_factor = 0.9,
     .leaf_exponent = 1.0,
     .twig_thin = 0.6,
     .rules = {[2] = {{1, 0.10, 0.95, 1}}},
     .leaf_rules = {{2, 0.2, 1.0, 1}}},
    {.name = "weeping", /* a weeping birch: thin twigs hanging in curtains */
     .shape = BBC_TREE_BIRCH,
     .height = 15.0,
     .default_leaves = 6000,
     .leaf_size = 0.10,
     .bark = {0.88f, 0.86f, 0.82f},
     .leaf = {0.36f, 0.55f, 0.16f},
     .levels = 4,
     .twig_factor = 0.9,
     .branch_factor = 0.9,
     .leaf_exponent = 1.0,
     .droop = 2.5,
     .twig_thin = 0.6,
     .rules = {[1] = {{0, 0.30, 0.97, 1}}, [2] = {{1, 0.15, 1.0, 1}}, [3] = {{2, 0.10, 1.0, 1}}},
     .leaf_rules = {{3, 0.0, 1.0, 1}}},
    {.name = "winter", /* a leafless oak: branches and twigs only */
     .shape = BBC_TREE_OAK,
     .height = 12.0,
     .default_leaves = 0,
     .structure_leaves = 20000,
     .leaf_size = 0.24,
     .bark = {0.42f, 0.36f, 0.30f},
     .leaf = {0.22f, 0.40f, 0.12f},
     TG_OAK_BRANCHING},
    {.name = "palm", /* a coconut-like palm: leaning stem, fronds of leaflet cards */
     .shape = BBC_TREE_PALM,
     .height = 11.0,
     .default_leaves = 1400,
     .leaf_size = 0.8,
     .bark = {0.55f, 0.47f, 0.38f},
     .leaf = {0.26f, 0.43f, 0.12f},
     .levels = 2,
     .leaf_exponent = 1.0,
     .rules = {[1] = {{0, 0.965, 1.0, 1}}},
     .leaf_rules = {{1, 0.1, 0.98, 1}}},
};

const char *bbc_tree_species_name(bbc_tree_species species) {
  if ((int)species < 0 || (int)species >= BBC_TREE_SPECIES_COUNT) return NULL;
  return tg_species_table[species].name;
}

int bbc_tree_species_from_name(const char *name) {
  if (!name) return -1;
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++) {
    const char *a = name, *b = tg_species_table[s].name;
    /* ASCII case folding: names come from command lines, "Oak" is meant. */
    while (*a && *b) {
      char ca = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
      if (ca != *b) break;
      a++;
      b++;
    }
    if (!*a && !*b) return s;
  }
  return -1;
}

void bbc_tree_options_default(bbc_tree_options *options) {
  assert(options);
  memset(options, 0, sizeof *options);
  options->seed = 1;
  options->leaves = 0;
  options->species = BBC_TREE_OAK;
  options->texture_size = 128;
}

/* ------------------------------------------------------------------------ */
/* Skeleton                                                                  */
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

typedef struct tg_child {
  vec3 dir;
  double length, radius, vigor;
  tg_growth growth;
} tg_child;

static size_t tg_round(double v) {
  return v <= 0 ? 0 : (size_t)(v + 0.5);
}

/* Point, tangent and drawn radius of branch b at t in [0, 1]. */
static void tg_branch_at(const tg_ctx *c, const tg_branch *b, double t, tg_attach *a) {
  int segs = c->rings[b->level];
  const tg_node *nd = c->nodes + b->node;
  double u = clampd(t, 0, 1) * segs;
  int k = (int)u;
  if (k > segs - 1) k = segs - 1;
  double f = u - k;
  a->pos = vadd(vscale(nd[k].pos, 1 - f), vscale(nd[k + 1].pos, f));
  a->radius = lerp(nd[k].radius, nd[k + 1].radius, f);
  a->tangent = vnorm(vsub(nd[k + 1].pos, nd[k].pos));
  a->t = t;
  a->parent = b;
}

/* Crown envelope, an ellipsoid around the trunk axis (scaled by `scale`):
 * limbs and branches are shortened to stay inside it, which gives each
 * broadleaf species its silhouette. (The pine's cone comes from its whorls'
 * lengths instead.) */
static int tg_inside_crown(const tg_ctx *c, vec3 p, double scale) {
  double h = c->height, cy, rx, ry;
  switch (c->shape) {
  case BBC_TREE_BIRCH:
    cy = 0.60 * h, rx = 0.24 * h, ry = 0.42 * h;
    break;
  case BBC_TREE_BUSH:
    cy = 0.45 * h, rx = 0.75 * h, ry = 0.52 * h;
    break;
  default:
    cy = 0.55 * h, rx = 0.66 * h, ry = 0.45 * h;
    break;
  }
  rx *= scale;
  ry *= scale;
  double dx = p.x / rx, dy = (p.y - cy) / ry, dz = p.z / rx;
  return dx * dx + dy * dy + dz * dz <= 1.0;
}

/* Length of a straight branch from `start` along `dir` clipped to the
 * crown envelope; never below a quarter of `len` so no branch vanishes. */
static double tg_clip_length(const tg_ctx *c, vec3 start, vec3 dir, double len, double scale) {
  if (!tg_inside_crown(c, start, scale)) return 0.35 * len;
  double prev = 0;
  for (int i = 1; i <= 12; i++) {
    double s = len * i / 12.0;
    if (!tg_inside_crown(c, vmadd(start, dir, s), scale)) {
      double lo = prev, hi = s;
      for (int k = 0; k < 8; k++) {
        double mid = 0.5 * (lo + hi);
        if (tg_inside_crown(c, vmadd(start, dir, mid), scale))
          lo = mid;
        else
          hi = mid;
      }
      return lo > 0.25 * len ? lo : 0.25 * len;
    }
    prev = s;
  }
  return len;
}

/* Grows a branch at `level` and stores its drawn nodes. */
static void tg_grow(tg_ctx *c, int level, vec3 start, vec3 dir, double len, double r0, double vigor,
                    const tg_growth *g, bbc__rng *rng) {
  int nf = tg_fine_segments[level];
  vec3 fine[TG_MAX_FINE + 1];
  double step = len / nf;
  /* Keep branches above the ground: bush stems and drooping twigs would
   * otherwise dip into it. */
  double ground = c->shape == BBC_TREE_BUSH ? 0.06 : 0.25;
  vec3 p = start, d = vnorm(dir), bend = v3(0, 0, 0);
  fine[0] = p;
  for (int i = 1; i <= nf; i++) {
    double s = (i - 0.5) / nf;
    /* Low-pass filtered noise: branches curve smoothly instead of zig-zag. */
    bend = vadd(vscale(bend, 0.6), vscale(rnd_vec(rng), 0.4));
    double horizontal = sqrt(d.x * d.x + d.z * d.z);
    d = vmadd(d, bend, g->wobble * step);
    d.y += (g->photo - g->gravity * horizontal * (0.4 + s)) * step;
    d = vnorm(d);
    vec3 next = vmadd(p, d, step);
    if (next.y < ground && d.y < 0) {
      d.y = -0.5 * d.y;
      d = vnorm(d);
      next = vmadd(p, d, step);
    }
    p = next;
    fine[i] = p;
  }

  tg_branch *b = &c->branches[c->branch_count++];
  b->node = c->node_count;
  b->level = level;
  b->length = len;
  b->vigor = vigor;
  int rings = c->rings[level];
  for (int i = 0; i <= rings; i++) {
    int k = (2 * i * nf + rings) / (2 * rings); /* nearest fine node */
    double s = (double)k / nf;
    double r = r0 * (1 - (1 - g->tip) * s);
    if (g->flare > 0 && s < 0.08) {
      double f = 1 - s / 0.08;
      r *= 1 + g->flare * f * f;
    }
    tg_node *n = &c->nodes[c->node_count++];
    n->pos = fine[k];
    n->radius = i == rings ? 0 : r;
  }
}

/* Shape of a child branch: species- and level-specific proportions.
 * `radial` is the (unit, perpendicular to the parent) direction the child
 * leaves in. */
static void tg_child_shape(tg_ctx *c, int level, const tg_attach *a, vec3 radial, bbc__rng *rng,
                           tg_child *ch) {
  double h = c->height;
  double angle = 45 * TG_DEG, len = 1, rratio = 0.5, rmin = 0.003, rmax = 1;
  int clip = 0;
  vec3 t = a->tangent;
  ch->vigor = a->parent->vigor;
  tg_growth g = {0.1, 0.1, 0.4, 0.3, 0};
  switch (c->shape) {
  case BBC_TREE_OAK:
    if (level == 1) {
      double u = clampd((a->t - 0.32) / 0.65, 0, 1);
      angle = lerp(78, 35, u) * TG_DEG + rnd(rng, -10, 10) * TG_DEG;
      len = 0.62 * h * (1.05 - 0.4 * u) * rnd(rng, 0.85, 1.15);
      rratio = 0.65;
      rmin = 0.05;
      ch->vigor = rnd(rng, 0.8, 1.12);
      g = (tg_growth){0.05, 0.05, 0.42, 0.12, 0};
      clip = 1;
    } else if (level == 2) {
      angle = rnd(rng, 40, 75) * TG_DEG;
      len = (0.32 * a->parent->length * (1 - 0.55 * a->t) + 0.6) * rnd(rng, 0.7, 1.25);
      rratio = 0.55;
      rmin = 0.012;
      g = (tg_growth){0.12, 0.16, 0.5, 0.25, 0};
      clip = 1;
    } else {
      angle = rnd(rng, 35, 60) * TG_DEG;
      len = rnd(rng, 0.25, 0.6);
      rratio = 0.6;
      rmin = 0.004;
      rmax = 0.02;
      g = (tg_growth){0.15, 0.4, 1.0, 0.4, 0};
    }
    break;
  case BBC_TREE_PINE:
    /* Level 2, the side shoots that carry the needle clusters; level 1 is
     * placed in whorls by tg_place_whorls. */
    angle = rnd(rng, 50, 70) * TG_DEG;
    len = (0.42 * a->parent->length * (1 - 0.65 * a->t) + 0.15) * rnd(rng, 0.8, 1.2);
    rratio = 0.5;
    rmin = 0.006;
    g = (tg_growth){0.35, 0.0, 0.3, 0.3, 0};
    break;
  case BBC_TREE_BIRCH:
    if (level == 1) {
      double u = clampd((a->t - 0.27) / 0.70, 0, 1);
      angle = (lerp(55, 25, u) + rnd(rng, -8, 8)) * TG_DEG;
      len = 0.27 * h * pow(sin(TG_PI * (0.12 + 0.88 * u)), 0.8) * rnd(rng, 0.8, 1.15) + 0.4;
      rratio = 0.45;
      rmin = 0.02;
      ch->vigor = rnd(rng, 0.85, 1.1);
      g = (tg_growth){0.22, 0.0, 0.25, 0.12, 0};
      clip = 1;
    } else if (level == 2) {
      angle = rnd(rng, 40, 75) * TG_DEG;
      len = rnd(rng, 0.8, 2.0) * (1 - 0.4 * a->t);
      rratio = 0.5;
      rmin = 0.006;
      g = (tg_growth){2.5, 0.0, 0.4, 0.3, 0};
    } else {
      angle = rnd(rng, 20, 40) * TG_DEG;
      len = rnd(rng, 0.25, 0.6);
      rratio = 0.6;
      rmax = 0.008;
      g = (tg_growth){4.0, 0.0, 0.6, 0.5, 0};
    }
    break;
  case BBC_TREE_PALM:
    /* Fronds from the crown: the young ones upright, the old ones spread
     * and arching down under their weight. */
    angle = rnd(rng, 35, 100) * TG_DEG;
    len = 0.38 * h * rnd(rng, 0.85, 1.12);
    rratio = 0.25;
    rmin = 0.02;
    rmax = 0.05;
    g = (tg_growth){0.5, 0.0, 0.12, 0.25, 0};
    break;
  case BBC_TREE_BUSH:
  default:
    if (level == 1) {
      angle = rnd(rng, 45, 80) * TG_DEG;
      len = (0.45 + rnd(rng, 0, 0.5)) * (1 - 0.45 * a->t) * h / 2.5;
      rratio = 0.55;
      rmin = 0.006;
      g = (tg_growth){0.3, 0.25, 0.8, 0.25, 0};
      clip = 1;
    } else {
      angle = rnd(rng, 30, 60) * TG_DEG;
      len = rnd(rng, 0.15, 0.35);
      rratio = 0.6;
      rmin = 0.0025;
      rmax = 0.008;
      g = (tg_growth){0.2, 0.4, 1.2, 0.5, 0};
    }
    break;
  }
  ch->dir = vnorm(vadd(vscale(t, cos(angle)), vscale(radial, sin(angle))));
  if (clip) len = tg_clip_length(c, a->pos, ch->dir, len, ch->vigor * rnd(rng, 0.92, 1.08));
  ch->length = len;
  double r = a->radius * rratio;
  ch->radius = clampd(r, rmin, rmax);
  /* A child never looks thicker than its parent where it leaves it. */
  if (ch->radius > 0.8 * a->radius && a->radius > 0) ch->radius = 0.8 * a->radius;
  /* Airy species: the finest level thinner, and hanging. */
  if (level == c->levels - 1) {
    if (c->info->twig_thin > 0) ch->radius *= c->info->twig_thin;
    g.gravity += c->info->droop;
  }
  if (ch->radius < 0.0015) ch->radius = 0.0015;
  ch->growth = g;
}

/* Stratified spreading of `count` points over a run of branches, in
 * proportion to per-branch weights: point k falls at (k + jitter) / count of
 * the total weight. Linear time, and points come out grouped by branch and
 * ordered along it. */
typedef struct tg_spread {
  const double *cum; /* cumulative weights, one per branch */
  size_t n, count, k, p;
} tg_spread;

static int tg_spread_next(tg_spread *s, bbc__rng *rng, size_t *branch, double *u) {
  if (s->k >= s->count || s->n == 0) return 0;
  double total = s->cum[s->n - 1];
  double x = (s->k + rnd(rng, 0.1, 0.9)) / s->count * total;
  s->k++;
  while (s->p + 1 < s->n && s->cum[s->p] <= x) s->p++;
  double start = s->p ? s->cum[s->p - 1] : 0, w = s->cum[s->p] - start;
  *branch = s->p;
  *u = w > 0 ? clampd((x - start) / w, 0, 1) : 0.5;
  return 1;
}

/* The rule of `level` that applies to a parent of `parent_level`, or NULL. */
static const tg_rule *tg_rule_for(const tg_ctx *c, int level, int parent_level) {
  for (int r = 0; r < 2; r++)
    if (c->info->rules[level][r].weight > 0 &&
        c->info->rules[level][r].parent_level == parent_level)
      return &c->info->rules[level][r];
  return NULL;
}

/* Places the branches of `level` (1..3) on the levels above it. */
static bbc_result tg_place_level(tg_ctx *c, int level, bbc__rng *rng) {
  size_t lo = c->first[0], hi = c->first[level];
  size_t n = hi - lo;
  double *cum = malloc((n ? n : 1) * sizeof *cum);
  if (!cum) return BBC_ERROR_OUT_OF_MEMORY;
  double acc = 0;
  for (size_t i = 0; i < n; i++) {
    const tg_branch *b = &c->branches[lo + i];
    const tg_rule *r = tg_rule_for(c, level, b->level);
    if (r) acc += b->length * (r->t1 - r->t0) * r->weight;
    cum[i] = acc;
  }
  tg_spread sp = {cum, n, c->count[level], 0, 0};
  size_t bi, last = (size_t)-1;
  double u, roll = 0, side = 1;
  while (tg_spread_next(&sp, rng, &bi, &u)) {
    const tg_branch *parent = &c->branches[lo + bi];
    const tg_rule *r = tg_rule_for(c, level, parent->level);
    /* Branches without a rule weigh nothing, so they are never chosen; the
     * planned vertex count relies on every child being placed. */
    assert(r);
    if (bi != last) {
      last = bi;
      roll = rnd(rng, 0, 2 * TG_PI);
      side = rnd(rng, 0, 1) < 0.5 ? -1 : 1;
    }
    /* Phyllotaxis: successive children turn by the golden angle. */
    roll += (137.5 + rnd(rng, -20, 20)) * TG_DEG;
    side = -side;
    tg_attach a;
    tg_branch_at(c, parent, r ? lerp(r->t0, r->t1, u) : u, &a);
    vec3 n0 = vperp(a.tangent), b0 = vcross(a.tangent, n0);
    vec3 radial;
    if (c->shape == BBC_TREE_PINE) {
      /* Conifer side shoots lie roughly in the plane of their parent. */
      radial = vnorm(vadd(vscale(n0, side), vscale(b0, rnd(rng, -0.25, 0.25))));
    } else {
      radial = vadd(vscale(n0, cos(roll)), vscale(b0, sin(roll)));
    }
    tg_child ch;
    tg_child_shape(c, level, &a, radial, rng, &ch);
    /* Start inside the parent so the joint is closed. */
    vec3 start = vmadd(a.pos, radial, 0.5 * a.radius);
    tg_grow(c, level, start, ch.dir, ch.length, ch.radius, ch.vigor, &ch.growth, rng);
  }
  free(cum);
  return BBC_OK;
}

/* Level 0: the trunk, or the stems of a bush. */
static void tg_place_trunks(tg_ctx *c, bbc__rng *rng) {
  double h = c->height;
  if (c->shape == BBC_TREE_BUSH) {
    size_t k = c->count[0];
    double az0 = rnd(rng, 0, 2 * TG_PI);
    for (size_t i = 0; i < k; i++) {
      double az = az0 + 2 * TG_PI * (i + rnd(rng, -0.3, 0.3)) / k;
      double tilt = (i == 0 ? rnd(rng, 0, 8) : rnd(rng, 15, 50)) * TG_DEG;
      double off = i == 0 ? 0 : rnd(rng, 0.05, 0.18);
      vec3 start = v3(off * cos(az), 0, off * sin(az));
      vec3 dir = v3(sin(tilt) * cos(az), cos(tilt), sin(tilt) * sin(az));
      double len = h * rnd(rng, 0.72, 0.9) / (0.45 + 0.55 * cos(tilt));
      tg_growth g = {0.05, 0.25, 0.35, 0.15, 0.0};
      tg_grow(c, 0, start, dir, len, rnd(rng, 0.022, 0.032), 1.0, &g, rng);
    }
    return;
  }
  double len = h, r0 = 0.012 * h, lean = 0.02;
  tg_growth g = {0, 0, 0.03, 0.04, 0.3};
  if (c->shape == BBC_TREE_OAK) {
    len = 0.55 * h, r0 = 0.026 * h, lean = 0.08;
    g = (tg_growth){0, 0, 0.08, 0.3, 0.5};
  } else if (c->shape == BBC_TREE_BIRCH) {
    len = 0.96 * h, r0 = 0.012 * h, lean = 0.05;
    g = (tg_growth){0, 0.02, 0.05, 0.06, 0.3};
  } else if (c->shape == BBC_TREE_PALM) {
    /* A slender stem leaning out and curving back up toward the light. */
    len = 1.02 * h, r0 = 0.02 * h, lean = rnd(rng, 0.15, 0.35);
    g = (tg_growth){0, 0.035, 0.04, 0.7, 0.7};
  }
  double az = rnd(rng, 0, 2 * TG_PI);
  vec3 dir = vnorm(v3(lean * cos(az), 1, lean * sin(az)));
  tg_grow(c, 0, v3(0, 0, 0), dir, len, r0, 1.0, &g, rng);
}

/* Pine level 1: whorls of downward-sloping limbs, longest at the bottom of
 * the crown, so the tree is a cone. */
static void tg_place_whorls(tg_ctx *c, bbc__rng *rng) {
  double h = c->height, y0 = 0.14 * h, y1 = 0.97 * h;
  const tg_branch *trunk = &c->branches[c->first[0]];
  for (int w = 0; w < c->whorls; w++) {
    double s = (w + rnd(rng, 0.2, 0.8)) / c->whorls;
    double y = lerp(y0, y1, s);
    tg_attach a;
    tg_branch_at(c, trunk, y / trunk->length, &a);
    double roll0 = rnd(rng, 0, 2 * TG_PI);
    for (int j = 0; j < c->per_whorl; j++) {
      double roll = roll0 + 2 * TG_PI * (j + rnd(rng, -0.2, 0.2)) / c->per_whorl;
      vec3 radial = v3(cos(roll), 0, sin(roll));
      double angle = (lerp(106, 62, pow(s, 1.6)) + rnd(rng, -6, 6)) * TG_DEG;
      vec3 dir = vnorm(vadd(vscale(a.tangent, cos(angle)), vscale(radial, sin(angle))));
      double len = 0.21 * h * pow(1 - s, 0.85) * rnd(rng, 0.85, 1.1) + 0.35;
      double r = clampd(0.35 * a.radius, 0.015, 0.12);
      tg_growth g = {0.10, 0.10, 0.12, 0.1, 0};
      vec3 start = vmadd(a.pos, radial, 0.5 * a.radius);
      tg_grow(c, 1, start, dir, len, r, 1.0, &g, rng);
    }
  }
}

/* ------------------------------------------------------------------------ */
/* Plan                                                                      */
/* ------------------------------------------------------------------------ */

static void tg_tessellation(tg_ctx *c, double q) {
  int bush = c->shape == BBC_TREE_BUSH;
  c->sides[0] = bush ? 4 + (int)lround(6 * q) : 6 + (int)lround(18 * q);
  c->rings[0] = 3 + (int)lround(13 * q);
  c->sides[1] = 3 + (int)lround(9 * q);
  c->rings[1] = 1 + (int)lround(9 * q);
  c->sides[2] = 3 + (int)lround(3 * q);
  c->rings[2] = 1 + (int)lround(3 * q);
  c->sides[3] = 3 + (int)lround(q);
  c->rings[3] = 1 + (int)lround(q);
}

static size_t tg_tube_triangles(int sides, int rings) {
  return (size_t)sides * (size_t)(2 * (rings - 1) + 1);
}
static size_t tg_tube_vertices(int sides, int rings) {
  return (size_t)rings * (size_t)(sides + 1) + 1;
}

static size_t tg_wood_triangles(const tg_ctx *c) {
  size_t n = 0;
  for (int l = 0; l < c->levels; l++)
    n += c->count[l] * tg_tube_triangles(c->sides[l], c->rings[l]);
  return n;
}

/* Branch counts per level and tessellation. The twig count follows the leaf
 * count (about leaves^0.8 twigs, so big trees get more leaves per twig, as
 * real ones do), and the tessellation is the finest that keeps the wood
 * within about 30% of the leaf triangles. */
static void tg_plan(tg_ctx *c) {
  const tg_species *sp = c->info;
  /* A leafless tree is planned as if it had structure_leaves. */
  double n = (double)(c->leaves ? c->leaves : sp->structure_leaves ? sp->structure_leaves : 1);
  bbc__rng *rng = &c->rng_shape;
  c->levels = sp->levels;
  memset(c->count, 0, sizeof c->count);
  /* Bushes vary less: a much smaller one would be a different plant. */
  double spread = c->shape == BBC_TREE_BUSH ? 0.08 : 0.12;
  c->height = sp->height * rnd(rng, 1 - spread, 1 + spread);
  /* Fewer leaves are drawn somewhat larger so a low-polygon tree still
   * reads as foliage; more leaves, somewhat smaller. */
  double dl = sp->default_leaves ? (double)sp->default_leaves : (double)sp->structure_leaves;
  double scale = clampd(pow(dl / n, 0.25), 0.75, 1.6);
  c->leaf_size = sp->leaf_size * scale;

  size_t twigs = tg_round(sp->twig_factor * pow(n, 0.8));
  if (twigs < 1) twigs = 1;
  if (c->leaves && twigs > c->leaves) twigs = c->leaves;
  size_t branches = tg_round(sp->branch_factor * pow(n, 0.55));
  if (branches < 4) branches = 4;
  c->count[0] = 1;
  switch (c->shape) {
  case BBC_TREE_OAK:
    c->count[1] = 8 + (size_t)(bbc__rng_next(rng) % 4);
    c->count[2] = branches;
    c->count[3] = twigs;
    break;
  case BBC_TREE_PINE: {
    double w = 2.6 * log2(n) - 6;
    c->whorls = (int)clampd(floor(w + 0.5), 10, 40);
    c->per_whorl = 4 + (int)(bbc__rng_next(rng) % 3);
    c->count[1] = (size_t)c->whorls * (size_t)c->per_whorl;
    c->count[2] = twigs;
    break;
  }
  case BBC_TREE_PALM:
    c->count[1] = 14 + (size_t)(bbc__rng_next(rng) % 5);
    break;
  case BBC_TREE_BIRCH:
    c->count[1] = (size_t)clampd(floor(10 + 0.9 * pow(n, 0.3) + 0.5), 12, 40);
    c->count[2] = branches;
    c->count[3] = twigs;
    break;
  case BBC_TREE_BUSH:
  default:
    c->count[0] = 6 + (size_t)(bbc__rng_next(rng) % 4);
    c->count[1] = (size_t)clampd(floor(0.5 * pow(n, 0.55) + 0.5), 6, 1e9);
    c->count[2] = twigs;
    break;
  }

  double budget = fmax(300.0, 0.3 * 2.0 * n);
  double lo = 0, hi = 1;
  tg_tessellation(c, 1);
  if ((double)tg_wood_triangles(c) > budget) {
    for (int it = 0; it < 24; it++) {
      double mid = 0.5 * (lo + hi);
      tg_tessellation(c, mid);
      if ((double)tg_wood_triangles(c) <= budget)
        lo = mid;
      else
        hi = mid;
    }
    tg_tessellation(c, lo);
  }
}

/* ------------------------------------------------------------------------ */
/* Leaf texture                                                              */
/* ------------------------------------------------------------------------ */

/* Random values on a 32 x 32 lattice for smooth value noise. */
typedef struct tg_lattice {
  double v[32][32];
} tg_lattice;

static void tg_lattice_fill(tg_lattice *nz, bbc__rng *rng) {
  for (int y = 0; y < 32; y++)
    for (int x = 0; x < 32; x++) nz->v[y][x] = rnd(rng, -1, 1);
}

/* Smooth value noise in [-1, 1] at texture position (x, y) in [0, 1), with
 * cx by cy cells across the texture (powers of two up to 32). Periodic over
 * the texture, so bark tiles seamlessly around and along a branch. */
static double tg_noise(const tg_lattice *nz, double x, double y, int cx, int cy) {
  double fx = x * cx, fy = y * cy;
  int ix = (int)floor(fx), iy = (int)floor(fy);
  double tx = fx - ix, ty = fy - iy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  int x0 = ix & (cx - 1), x1 = (ix + 1) & (cx - 1), y0 = iy & (cy - 1), y1 = (iy + 1) & (cy - 1);
  double a = lerp(nz->v[y0][x0], nz->v[y0][x1], tx);
  double b = lerp(nz->v[y1][x0], nz->v[y1][x1], tx);
  return lerp(a, b, ty);
}

static double tg_smoothstep(double e0, double e1, double x) {
  double t = clampd((x - e0) / (e1 - e0), 0, 1);
  return t * t * (3 - 2 * t);
}

static uint8_t tg_byte(double v) {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  return (uint8_t)(v * 255.0 + 0.5);
}

static void tg_put(bbc_image *img, int x, int y, double r, double g, double b) {
  uint8_t *p = img->rgba + 4 * ((size_t)y * (size_t)img->width + (size_t)x);
  p[0] = tg_byte(r);
  p[1] = tg_byte(g);
  p[2] = tg_byte(b);
  p[3] = 255;
}

/* Half-width of a blade at s (0 base .. 1 tip), in texture widths. */
static double tg_blade_half_width(bbc_tree_species sp, double s) {
  if (s <= 0 || s >= 1) return 0;
  switch (sp) {
  case BBC_TREE_OAK: {
    /* Obovate outline with rounded lobes and narrow sinuses. */
    double w = 0.33 * pow(sin(TG_PI * pow(s, 1.3)), 0.75);
    double lobe = fabs(cos(TG_PI * (s * 4.6 + 0.35)));
    return w * (0.5 + 0.5 * sqrt(lobe));
  }
  case BBC_TREE_BIRCH: {
    /* Triangular-ovate, widest near the base, pointed tip, toothed margin. */
    double w = 0.40 * sin(TG_PI * pow(s, 0.62));
    double tooth = s * 15 - floor(s * 15);
    return w * (1 - 0.07 * tooth);
  }
  case BBC_TREE_PALM:
    /* A palm leaflet: long, narrow, tapering to a point. */
    return 0.10 * pow(sin(TG_PI * pow(s, 0.7)), 0.6);
  default:
    /* Elliptic with a short point. */
    return 0.27 * pow(sin(TG_PI * pow(s, 0.85)), 0.8);
  }
}

/* A broad leaf: blade, petiole, darker midrib and veins, colour noise.
 * v = 0 (the bottom row) is the leaf's base, where the quad is attached. */
static void tg_texture_blade(tg_ctx *c, bbc_image *img, const tg_lattice *nz) {
  int n = img->width;
  const float *base = c->info->leaf;
  double yb = 0.11, yt = 0.985;
  int veins = c->shape == BBC_TREE_OAK ? 5 : c->shape == BBC_TREE_BIRCH ? 8 : 7;
  double px_w = 1.0 / n;
  for (int py = 0; py < n; py++) {
    double y = 1.0 - (py + 0.5) / n;
    for (int px = 0; px < n; px++) {
      double x = (px + 0.5) / n - 0.5, ax = fabs(x);
      double grain = rnd(&c->rng_texture, -1, 1);
      double low = tg_noise(nz, (px + 0.5) / n, y, 8, 8);
      double s = (y - yb) / (yt - yb);
      double w = tg_blade_half_width(c->shape, s);
      double petiole = fmax(0.012, 0.5 * px_w);
      double shade;
      if (ax < w) {
        shade = 1.0 + 0.12 * low + 0.05 * grain;
        double e = ax / w;
        shade *= 1.0 - 0.12 * e * e;
        if (x < 0) shade *= 0.93; /* the blade is folded a little along the midrib */
        double rib = fmax(0.010 + 0.008 * (1 - s), 0.5 * px_w);
        double phase = (s - 0.9 * ax) * veins;
        double dv = fabs(phase - floor(phase + 0.5)) / veins * (yt - yb);
        double vw = fmax(0.0055 * (1 - 0.6 * e), 0.35 * px_w);
        if (ax < rib)
          shade *= 0.62;
        else if (dv < vw && e < 0.93 && s > 0.04)
          shade *= 0.74;
        tg_put(img, px, py, base[0] * shade * 1.05, base[1] * shade, base[2] * shade);
      } else if (y <= yb + 0.03 && ax < petiole) {
        shade = 0.85 + 0.05 * grain;
        tg_put(img, px, py, base[0] * shade * 1.3, base[1] * shade * 0.95, base[2] * shade);
      }
    }
  }
}

/* A capsule (thick segment) of colour rgb * shade, shade varying from
 * shade0 at (x0, y0) to shade1 at (x1, y1); coordinates in texture units,
 * y up. */
static void tg_capsule(bbc_image *img, double x0, double y0, double x1, double y1, double hw,
                       const double rgb[3], double shade0, double shade1) {
  int n = img->width;
  double dx = x1 - x0, dy = y1 - y0, l2 = dx * dx + dy * dy;
  double minx = fmin(x0, x1) - hw, maxx = fmax(x0, x1) + hw;
  double miny = fmin(y0, y1) - hw, maxy = fmax(y0, y1) + hw;
  int px0 = (int)floor(minx * n), px1 = (int)ceil(maxx * n);
  int row0 = (int)floor((1 - maxy) * n), row1 = (int)ceil((1 - miny) * n);
  if (px0 < 0) px0 = 0;
  if (px1 > n - 1) px1 = n - 1;
  if (row0 < 0) row0 = 0;
  if (row1 > n - 1) row1 = n - 1;
  for (int py = row0; py <= row1; py++) {
    double y = 1.0 - (py + 0.5) / n;
    for (int px = px0; px <= px1; px++) {
      double x = (px + 0.5) / n;
      double t = l2 > 0 ? clampd(((x - x0) * dx + (y - y0) * dy) / l2, 0, 1) : 0;
      double ex = x - (x0 + t * dx), ey = y - (y0 + t * dy);
      if (ex * ex + ey * ey > hw * hw) continue;
      double s = lerp(shade0, shade1, t);
      tg_put(img, px, py, rgb[0] * s, rgb[1] * s, rgb[2] * s);
    }
  }
}

/* A conifer card: a twig with many thin needles. The twig runs from the
 * bottom centre (where the card is attached) toward the top. */
static void tg_texture_needles(tg_ctx *c, bbc_image *img) {
  bbc__rng *rng = &c->rng_texture;
  int n = img->width;
  double px_w = 1.0 / n;
  const float *base = c->info->leaf;
  double hw = fmax(0.0055, 0.55 * px_w);
  double bend = rnd(rng, -0.04, 0.04);
  int count = 120;
  for (int i = 0; i < count + 8; i++) {
    double ya, xa, a, len;
    int tuft = i >= count;
    if (!tuft) {
      ya = 0.03 + 0.84 * (i + rnd(rng, 0, 1)) / count;
      double side = (i & 1) ? 1 : -1;
      a = side * rnd(rng, 22, 62) * TG_DEG;
      len = rnd(rng, 0.17, 0.33) * (1 - 0.3 * ya) * rnd(rng, 0.55, 1.0);
    } else {
      /* A tuft continuing the twig beyond its tip. */
      ya = 0.86;
      a = rnd(rng, -28, 28) * TG_DEG;
      len = rnd(rng, 0.08, 0.13);
    }
    xa = 0.5 + bend * ya * ya;
    double xe = xa + sin(a) * len, ye = ya + cos(a) * len;
    /* Keep the needle on the card. */
    if (xe < 0.02) xe = 0.02;
    if (xe > 0.98) xe = 0.98;
    if (ye > 0.985) ye = 0.985;
    double tint = rnd(rng, 0.8, 1.2);
    double rgb[3] = {base[0] * tint, base[1] * tint, base[2] * tint * rnd(rng, 0.9, 1.2)};
    tg_capsule(img, xa, ya, xe, ye, hw, rgb, 0.75, 1.25);
  }
  /* The twig, drawn in short pieces so it can curve. */
  double twig_rgb[3] = {0.36, 0.25, 0.15};
  double prevx = 0.5, prevy = 0.0;
  for (int k = 1; k <= 8; k++) {
    double y = 0.88 * k / 8, x = 0.5 + bend * y * y;
    double w = fmax(lerp(0.02, 0.009, y), 0.6 * px_w);
    tg_capsule(img, prevx, prevy, x, y, w, twig_rgb, 0.9, 1.0);
    prevx = x;
    prevy = y;
  }
}

/* The leaf texture: RGBA, alpha exactly 0 or 255. Transparent texels carry
 * the mean leaf colour so filtering never bleeds a dark fringe. */
static void tg_leaf_texture(tg_ctx *c, bbc_image *img) {
  size_t texels = (size_t)img->width * (size_t)img->height;
  const float *base = c->info->leaf;
  for (size_t i = 0; i < texels; i++) {
    img->rgba[4 * i + 0] = tg_byte(base[0]);
    img->rgba[4 * i + 1] = tg_byte(base[1]);
    img->rgba[4 * i + 2] = tg_byte(base[2]);
    img->rgba[4 * i + 3] = 0;
  }
  tg_lattice nz;
  tg_lattice_fill(&nz, &c->rng_texture);
  if (c->shape == BBC_TREE_PINE)
    tg_texture_needles(c, img);
  else
    tg_texture_blade(c, img, &nz);
}

/* The bark texture: a tileable brightness pattern near white, multiplied
 * by the bark material's base colour (which alone is the bark's colour for
 * renderers without textures). u runs around a branch, v along it. */
static void tg_bark_texture(tg_ctx *c, bbc_image *img) {
  tg_lattice nz;
  tg_lattice_fill(&nz, &c->rng_texture);
  int n = img->width;
  for (int py = 0; py < n; py++) {
    double y = (py + 0.5) / n;
    for (int px = 0; px < n; px++) {
      double x = (px + 0.5) / n, v, warm = 0;
      double grain = rnd(&c->rng_texture, -1, 1);
      switch (c->shape) {
      case BBC_TREE_OAK: {
        /* Deep fissures (where the noise crosses zero), long along the
         * branch, between rough ridges. */
        double f = tg_noise(&nz, x, y, 16, 2) + 0.3 * tg_noise(&nz, x, y, 32, 8);
        v = 0.4 + 0.6 * tg_smoothstep(0.03, 0.3, fabs(f)) + 0.05 * grain;
        break;
      }
      case BBC_TREE_PINE: {
        /* Scaly plates separated by dark cracks, warmer inside the plates. */
        double f = tg_noise(&nz, x, y, 8, 8) + 0.4 * tg_noise(&nz, x, y, 32, 16);
        double crack = tg_smoothstep(0.03, 0.2, fabs(f));
        v = 0.5 + 0.45 * crack + 0.04 * grain;
        warm = 0.08 * crack;
        break;
      }
      case BBC_TREE_BIRCH: {
        /* White with short dark horizontal lenticels and a few black
         * patches. */
        double band = 12 * y + 0.4 * tg_noise(&nz, x, y, 8, 8);
        double dash = tg_noise(&nz, x, y, 32, 16);
        double patch = tg_noise(&nz, x, y, 4, 4) + 0.3 * tg_noise(&nz, x, y, 16, 16);
        v = 0.96 + 0.04 * grain;
        if (band - floor(band) < 0.07 && dash > 0.15) v = 0.25;
        if (patch > 0.62) v = 0.2 + 0.05 * grain;
        break;
      }
      default: {
        double f = tg_noise(&nz, x, y, 16, 8);
        v = 0.78 + 0.18 * f + 0.04 * grain;
        break;
      }
      }
      tg_put(img, px, py, v * (1 + warm), v, v * (1 - warm));
    }
  }
}

/* ------------------------------------------------------------------------ */
/* Geometry                                                                  */
/* ------------------------------------------------------------------------ */

typedef struct tg_out {
  bbc_mesh *m;
  size_t v, t; /* next vertex, next triangle */
} tg_out;

static void tg_vertex(tg_out *o, vec3 p, vec3 n, double u, double v) {
  bbc_mesh *m = o->m;
  double *pp = m->positions + 3 * o->v;
  float *nn = m->normals + 3 * o->v, *uv = m->uvs + 2 * o->v;
  pp[0] = p.x;
  pp[1] = p.y;
  pp[2] = p.z;
  nn[0] = (float)n.x;
  nn[1] = (float)n.y;
  nn[2] = (float)n.z;
  uv[0] = (float)u;
  uv[1] = (float)v;
  o->v++;
}

static void tg_triangle(tg_out *o, size_t a, size_t b, size_t c, uint32_t group) {
  uint32_t *ix = o->m->indices + 3 * o->t;
  ix[0] = (uint32_t)a;
  ix[1] = (uint32_t)b;
  ix[2] = (uint32_t)c;
  o->m->face_material[o->t] = group; /* material i belongs to group i */
  o->m->face_group[o->t] = group;
  o->t++;
}

/* A branch as a tube: rings of sides + 1 vertices (the seam is doubled so u
 * runs 0..1 around), frames carried along by parallel transport so the
 * tube does not twist, and an apex vertex closing the tip. Counter-clockwise
 * seen from outside. */
static void tg_emit_tube(const tg_ctx *c, const tg_branch *b, tg_out *o) {
  int sides = c->sides[b->level], rings = c->rings[b->level];
  const tg_node *nd = c->nodes + b->node;
  double cs[TG_MAX_SIDES + 1], sn[TG_MAX_SIDES + 1];
  for (int j = 0; j <= sides; j++) {
    double a = 2 * TG_PI * (j % sides) / sides;
    cs[j] = cos(a);
    sn[j] = sin(a);
  }
  size_t base = o->v;
  double circumference = 2 * TG_PI * (nd[0].radius > 0 ? nd[0].radius : 0.01);
  double v = 0;
  vec3 first = vnorm(vsub(nd[1].pos, nd[0].pos));
  /* Trunks stand on the ground with a horizontal base ring. */
  vec3 tangent = b->level == 0 ? v3(0, 1, 0) : first;
  vec3 normal = vperp(tangent);
  for (int i = 0; i < rings; i++) {
    if (i > 0) {
      vec3 in = vnorm(vsub(nd[i].pos, nd[i - 1].pos));
      vec3 out = vnorm(vsub(nd[i + 1].pos, nd[i].pos));
      tangent = vnorm_or(vadd(in, out), out);
      v += vlen(vsub(nd[i].pos, nd[i - 1].pos)) / circumference;
    }
    normal = vnorm_or(vsub(normal, vscale(tangent, vdot(tangent, normal))), vperp(tangent));
    vec3 binormal = vcross(tangent, normal);
    for (int j = 0; j <= sides; j++) {
      vec3 d = vadd(vscale(normal, cs[j]), vscale(binormal, sn[j]));
      tg_vertex(o, vmadd(nd[i].pos, d, nd[i].radius), d, (double)j / sides, v);
    }
  }
  vec3 last = vnorm(vsub(nd[rings].pos, nd[rings - 1].pos));
  v += vlen(vsub(nd[rings].pos, nd[rings - 1].pos)) / circumference;
  size_t apex = o->v;
  tg_vertex(o, nd[rings].pos, last, 0.5, v);
  size_t stride = (size_t)sides + 1;
  for (int i = 0; i + 1 < rings; i++)
    for (int j = 0; j < sides; j++) {
      size_t a = base + (size_t)i * stride + (size_t)j;
      tg_triangle(o, a, a + 1, a + stride + 1, 0);
      tg_triangle(o, a, a + stride + 1, a + stride, 0);
    }
  for (int j = 0; j < sides; j++) {
    size_t a = base + (size_t)(rings - 1) * stride + (size_t)j;
    tg_triangle(o, a, a + 1, apex, 0);
  }
}

/* One leaf quad at twig point a, leaving in direction `radial`. The quad's
 * bottom edge centre is the leaf's base; u runs across, v from base to tip,
 * and the front (counter-clockwise) side faces `normal`. */
static void tg_emit_leaf(const tg_ctx *c, const tg_attach *a, vec3 radial, bbc__rng *rng,
                         tg_out *o) {
  vec3 t = a->tangent, up = v3(0, 1, 0), axis, pref;
  double size = c->leaf_size * rnd(rng, 0.8, 1.2);
  switch (c->shape) {
  case BBC_TREE_PINE: {
    /* Needle cards lie along the twig, rolled at random around it so the
     * cluster looks full from every side. */
    double ang = rnd(rng, 8, 35) * TG_DEG;
    axis = vnorm(vadd(vscale(t, cos(ang)), vscale(radial, sin(ang))));
    pref = vadd(vscale(up, 0.5), rnd_vec(rng));
    break;
  }
  case BBC_TREE_BIRCH: {
    /* Birch leaves hang from thin stalks and flutter. */
    double ang = rnd(rng, 35, 70) * TG_DEG;
    axis = vnorm(vadd(vscale(t, cos(ang)), vscale(radial, sin(ang))));
    axis = vnorm(vadd(axis, v3(0, -0.7, 0)));
    pref = vadd(vadd(vscale(radial, 0.8), vscale(up, 0.4)), vscale(rnd_vec(rng), 0.6));
    break;
  }
  case BBC_TREE_PALM: {
    /* Leaflets in two rows, one each side of the frond's midrib, pointing
     * forward a little and drooping, faces to the sky. */
    vec3 sidev = vnorm_or(vcross(t, up), vperp(t));
    double sgn = vdot(radial, sidev) >= 0 ? 1 : -1, droop = rnd(rng, 5, 40) * TG_DEG;
    axis =
        vnorm(vadd(vadd(vscale(sidev, sgn * cos(droop)), vscale(t, 0.5)), v3(0, -sin(droop), 0)));
    pref = vadd(up, vscale(rnd_vec(rng), 0.3));
    break;
  }
  default: {
    /* Broad leaves spread out from the twig and turn their face to the sky. */
    double ang = rnd(rng, 40, 75) * TG_DEG;
    axis = vnorm(vadd(vscale(t, cos(ang)), vscale(radial, sin(ang))));
    axis = vnorm(vadd(axis, v3(0, 0.15, 0)));
    pref = vadd(vadd(vscale(up, 0.7), vscale(radial, 0.7)), vscale(rnd_vec(rng), 0.5));
    break;
  }
  }
  vec3 base = c->shape == BBC_TREE_PINE || c->shape == BBC_TREE_PALM
                  ? a->pos
                  : vmadd(a->pos, radial, a->radius);
  /* Leaves near the ground turn upward rather than into the soil. */
  if (base.y + axis.y * size < 0.02 && axis.y < 0) {
    axis.y = -axis.y;
    axis = vnorm(axis);
  }
  vec3 normal = vnorm_or(vsub(pref, vscale(axis, vdot(axis, pref))), vperp(axis));
  vec3 side = vcross(axis, normal); /* so that side x axis = normal: front faces `normal` */
  double hw = 0.5 * size * rnd(rng, 0.9, 1.1);
  vec3 tip = vmadd(base, axis, size);
  vec3 corner[4] = {vmadd(base, side, -hw), vmadd(base, side, hw), vmadd(tip, side, hw),
                    vmadd(tip, side, -hw)};
  double low = corner[0].y;
  for (int k = 1; k < 4; k++) low = fmin(low, corner[k].y);
  if (low < 0.01)
    for (int k = 0; k < 4; k++) corner[k].y += 0.01 - low;
  size_t first = o->v;
  tg_vertex(o, corner[0], normal, 0, 0);
  tg_vertex(o, corner[1], normal, 1, 0);
  tg_vertex(o, corner[2], normal, 1, 1);
  tg_vertex(o, corner[3], normal, 0, 1);
  tg_triangle(o, first, first + 1, first + 2, 1);
  tg_triangle(o, first, first + 2, first + 3, 1);
}

/* The leaf rule for a branch of `level`, or NULL when it carries none. */
static const tg_rule *tg_leaf_rule(const tg_ctx *c, int level) {
  for (int r = 0; r < 2; r++)
    if (c->info->leaf_rules[r].weight > 0 && c->info->leaf_rules[r].parent_level == level)
      return &c->info->leaf_rules[r];
  return NULL;
}

/* Spreads exactly c->leaves leaves over the twigs (and, for some species,
 * the outer part of the level above them). */
static bbc_result tg_emit_leaves(const tg_ctx *c, tg_out *o, const bbc_callbacks *cb) {
  size_t lo = c->first[c->levels - 2], n = c->first[c->levels] - lo;
  double *cum = malloc((n ? n : 1) * sizeof *cum);
  if (!cum) return BBC_ERROR_OUT_OF_MEMORY;
  double acc = 0;
  for (size_t i = 0; i < n; i++) {
    const tg_branch *b = &c->branches[lo + i];
    const tg_rule *r = tg_leaf_rule(c, b->level);
    if (r) acc += b->length * (r->t1 - r->t0) * r->weight;
    cum[i] = acc;
  }
  bbc__rng rng = c->rng_leaf;
  tg_spread sp = {cum, n, c->leaves, 0, 0};
  size_t bi, last = (size_t)-1, done = 0, report = c->leaves / 16 + 1;
  double u, roll = 0;
  while (tg_spread_next(&sp, &rng, &bi, &u)) {
    const tg_branch *b = &c->branches[lo + bi];
    const tg_rule *r = tg_leaf_rule(c, b->level);
    if (bi != last) {
      last = bi;
      roll = rnd(&rng, 0, 2 * TG_PI);
    }
    roll += (137.5 + rnd(&rng, -25, 25)) * TG_DEG;
    tg_attach a;
    /* An exponent below 1 crowds the leaves toward the twig tip, where the
     * light is. */
    double t0 = r ? r->t0 : 0, t1 = r ? r->t1 : 1;
    tg_branch_at(c, b, t0 + (t1 - t0) * pow(u, c->info->leaf_exponent), &a);
    vec3 n0 = vperp(a.tangent), b0 = vcross(a.tangent, n0);
    vec3 radial = vadd(vscale(n0, cos(roll)), vscale(b0, sin(roll)));
    tg_emit_leaf(c, &a, radial, &rng, o);
    if (++done % report == 0) bbc__progress(cb, "tree", 0.3 + 0.6 * (double)done / c->leaves);
  }
  free(cum);
  return BBC_OK;
}

/* ------------------------------------------------------------------------ */
/* Entry point                                                               */
/* ------------------------------------------------------------------------ */

static int tg_is_pow2(int v) {
  return v > 0 && (v & (v - 1)) == 0;
}

static bbc_result tg_oom(tg_ctx *c, bbc_mesh *mesh, bbc_error *err) {
  free(c->branches);
  free(c->nodes);
  bbc_mesh_free(mesh);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "tree generator: out of memory");
}

static void *tg_array(size_t count, size_t size) {
  return count > SIZE_MAX / size ? NULL : malloc(count * size);
}

bbc_result bbc_tree_generate(const bbc_tree_options *options, bbc_mesh *mesh, bbc_error *err) {
  assert(options && mesh);
  memset(mesh, 0, sizeof *mesh);
  if ((int)options->species < 0 || (int)options->species >= BBC_TREE_SPECIES_COUNT)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: species %d is not one of oak (0), pine (1), birch (2), "
                     "bush (3), larch (4), weeping (5), winter (6), palm (7)",
                     (int)options->species);
  if (!tg_is_pow2(options->texture_size) || options->texture_size < TG_MIN_TEXTURE ||
      options->texture_size > TG_MAX_TEXTURE)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: texture size %d must be a power of two from %d to %d",
                     options->texture_size, TG_MIN_TEXTURE, TG_MAX_TEXTURE);
  if (options->leaves > TG_MAX_LEAVES)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: %zu leaves asked for; at most %u are allowed",
                     options->leaves, TG_MAX_LEAVES);
  const bbc_callbacks *cb = &options->callbacks;
  bbc__progress(cb, "tree", 0.0);

  tg_ctx c;
  memset(&c, 0, sizeof c);
  c.species = options->species;
  c.info = &tg_species_table[c.species];
  c.shape = c.info->shape;
  c.leaves = options->leaves ? options->leaves : c.info->default_leaves;
  /* Independent streams: the textures never depend on the leaf count, and
   * the trunk and limbs of a seed mostly stay when only the leaf count
   * changes. */
  bbc__rng seeder = {options->seed ^ (0x5DEECE66Dull * (uint64_t)(c.species + 1))};
  c.rng_shape.state = bbc__rng_next(&seeder);
  c.rng_fine.state = bbc__rng_next(&seeder);
  c.rng_leaf.state = bbc__rng_next(&seeder);
  c.rng_texture.state = bbc__rng_next(&seeder);
  tg_plan(&c);

  size_t total_branches = 0, total_nodes = 0, nv = 4 * c.leaves, nt = 2 * c.leaves;
  for (int l = 0; l < c.levels; l++) {
    total_branches += c.count[l];
    total_nodes += c.count[l] * (size_t)(c.rings[l] + 1);
    nv += c.count[l] * tg_tube_vertices(c.sides[l], c.rings[l]);
  }
  nt += tg_wood_triangles(&c);
  if (nv > UINT32_MAX)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: %zu vertices do not fit 32-bit indices", nv);
  c.branches = tg_array(total_branches, sizeof *c.branches);
  c.nodes = tg_array(total_nodes, sizeof *c.nodes);
  if (!c.branches || !c.nodes) return tg_oom(&c, mesh, err);

  /* Skeleton, level by level, so each level's branches are contiguous. */
  c.first[0] = 0;
  tg_place_trunks(&c, &c.rng_shape);
  c.first[1] = c.branch_count;
  for (int l = 1; l < c.levels; l++) {
    bbc__rng *rng = l == 1 ? &c.rng_shape : &c.rng_fine;
    if (l == 1 && c.shape == BBC_TREE_PINE)
      tg_place_whorls(&c, rng);
    else if (tg_place_level(&c, l, rng) != BBC_OK)
      return tg_oom(&c, mesh, err);
    c.first[l + 1] = c.branch_count;
  }
  for (int l = c.levels; l < TG_LEVELS; l++) c.first[l + 1] = c.branch_count;
  /* Every planned branch was placed: the vertex count above depends on it. */
  assert(c.branch_count == total_branches && c.node_count == total_nodes);
  bbc__progress(cb, "tree", 0.15);

  mesh->kind = BBC_MESH_TRIANGLES;
  mesh->vertex_count = nv;
  mesh->triangle_count = nt;
  mesh->positions = tg_array(nv, 3 * sizeof *mesh->positions);
  mesh->normals = tg_array(nv, 3 * sizeof *mesh->normals);
  mesh->uvs = tg_array(nv, 2 * sizeof *mesh->uvs);
  mesh->indices = tg_array(nt, 3 * sizeof *mesh->indices);
  mesh->face_material = tg_array(nt, sizeof *mesh->face_material);
  mesh->face_group = tg_array(nt, sizeof *mesh->face_group);
  mesh->materials = calloc(2, sizeof *mesh->materials);
  mesh->textures = calloc(2, sizeof *mesh->textures);
  mesh->group_names = calloc(2, sizeof *mesh->group_names);
  if (!mesh->positions || !mesh->normals || !mesh->uvs || !mesh->indices || !mesh->face_material ||
      !mesh->face_group || !mesh->materials || !mesh->textures || !mesh->group_names)
    return tg_oom(&c, mesh, err);
  mesh->material_count = 2;
  mesh->texture_count = 2;
  mesh->group_count = 2;
  mesh->materials[0].name = bbc__strdup("bark");
  mesh->materials[1].name = bbc__strdup("leaf");
  mesh->group_names[0] = bbc__strdup("trunk");
  mesh->group_names[1] = bbc__strdup("leaves");
  if (!mesh->materials[0].name || !mesh->materials[1].name || !mesh->group_names[0] ||
      !mesh->group_names[1])
    return tg_oom(&c, mesh, err);
  for (int k = 0; k < 3; k++) mesh->materials[0].base_color[k] = c.info->bark[k];
  mesh->materials[0].base_color[3] = 1.0f;
  mesh->materials[0].texture = 1;
  /* White: renderers multiply the base colour with the texture. */
  for (int k = 0; k < 4; k++) mesh->materials[1].base_color[k] = 1.0f;
  mesh->materials[1].texture = 0;

  int ts = options->texture_size;
  /* Bark is seen small: half the leaf texture's edge is plenty. */
  int bs = ts / 2 < 8 ? 8 : ts / 2 > 128 ? 128 : ts / 2;
  if (bbc_image_alloc(&mesh->textures[0].image, ts, ts) != BBC_OK ||
      bbc_image_alloc(&mesh->textures[1].image, bs, bs) != BBC_OK)
    return tg_oom(&c, mesh, err);
  tg_leaf_texture(&c, &mesh->textures[0].image);
  mesh->textures[0].has_alpha = 1;
  tg_bark_texture(&c, &mesh->textures[1].image);
  mesh->textures[1].has_alpha = 0;

  tg_out o = {mesh, 0, 0};
  for (size_t i = 0; i < c.branch_count; i++) tg_emit_tube(&c, &c.branches[i], &o);
  bbc__progress(cb, "tree", 0.3);
  if (tg_emit_leaves(&c, &o, cb) != BBC_OK) return tg_oom(&c, mesh, err);
  assert(o.v == nv && o.t == nt);
  free(c.branches);
  free(c.nodes);

  /* Every vertex has its normal, so the smoothing flag changes nothing; 0
   * spares finalize the position sort that smoothing needs. */
  bbc_result r = bbc_mesh_finalize(mesh, 0, "built-in tree", err);
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  bbc__progress(cb, "tree", 1.0);
  return BBC_OK;
}
