/*
 * treegen_grow.c — the tree generator's skeleton (step 2 of treegen.c): the
 * trunk (or a bush's stems), the pine's whorls, and each finer level's
 * branches spread over the level above; every branch grown as a polyline
 * bent by gravity, phototropism and a smooth random wobble, and kept only at
 * the rings that will be drawn.
 */
#include "treegen.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

/* Fine polyline segments per level: the resolution at which a branch is
 * grown; the drawn rings are a subset, so a branch keeps its shape whatever
 * the tessellation. */
#define TG_MAX_FINE 32
static const int tg_fine_segments[TG_LEVELS] = {TG_MAX_FINE, 16, 8, 4};

typedef struct tg_child {
  vec3 dir;
  double length, radius, vigor;
  tg_growth growth;
} tg_child;

/* Point, tangent and drawn radius of branch b at t in [0, 1]. */
void bbc__tree_branch_at(const tg_ctx *c, const tg_branch *b, double t, tg_attach *a) {
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

/* A child's proportions as its species and level give them, before its
 * parent and the crown limit them: the angle it leaves its parent at, its
 * length, its radius as a share of the parent's (clamped to rmin..rmax),
 * whether the crown envelope clips it, and how it bends. */
typedef struct tg_shape {
  double angle, len, rratio, rmin, rmax;
  int clip;
  tg_growth g;
} tg_shape;

static void oak_child(int level, const tg_attach *a, double h, bbc__rng *rng, tg_shape *s,
                      tg_child *ch) {
  if (level == 1) {
    double u = clampd((a->t - 0.32) / 0.65, 0, 1);
    s->angle = lerp(78, 35, u) * TG_DEG + rnd(rng, -10, 10) * TG_DEG;
    s->len = 0.62 * h * (1.05 - 0.4 * u) * rnd(rng, 0.85, 1.15);
    s->rratio = 0.65;
    s->rmin = 0.05;
    ch->vigor = rnd(rng, 0.8, 1.12);
    s->g = (tg_growth){0.05, 0.05, 0.42, 0.12, 0};
    s->clip = 1;
  } else if (level == 2) {
    s->angle = rnd(rng, 40, 75) * TG_DEG;
    s->len = (0.32 * a->parent->length * (1 - 0.55 * a->t) + 0.6) * rnd(rng, 0.7, 1.25);
    s->rratio = 0.55;
    s->rmin = 0.012;
    s->g = (tg_growth){0.12, 0.16, 0.5, 0.25, 0};
    s->clip = 1;
  } else {
    s->angle = rnd(rng, 35, 60) * TG_DEG;
    s->len = rnd(rng, 0.25, 0.6);
    s->rratio = 0.6;
    s->rmin = 0.004;
    s->rmax = 0.02;
    s->g = (tg_growth){0.15, 0.4, 1.0, 0.4, 0};
  }
}

static void pine_child(const tg_attach *a, bbc__rng *rng, tg_shape *s) {
  /* Level 2, the side shoots that carry the needle clusters; level 1 is
   * placed in whorls by tg_place_whorls. */
  s->angle = rnd(rng, 50, 70) * TG_DEG;
  s->len = (0.42 * a->parent->length * (1 - 0.65 * a->t) + 0.15) * rnd(rng, 0.8, 1.2);
  s->rratio = 0.5;
  s->rmin = 0.006;
  s->g = (tg_growth){0.35, 0.0, 0.3, 0.3, 0};
}

static void birch_child(int level, const tg_attach *a, double h, bbc__rng *rng, tg_shape *s,
                        tg_child *ch) {
  if (level == 1) {
    double u = clampd((a->t - 0.27) / 0.70, 0, 1);
    s->angle = (lerp(55, 25, u) + rnd(rng, -8, 8)) * TG_DEG;
    s->len = 0.27 * h * pow(sin(TG_PI * (0.12 + 0.88 * u)), 0.8) * rnd(rng, 0.8, 1.15) + 0.4;
    s->rratio = 0.45;
    s->rmin = 0.02;
    ch->vigor = rnd(rng, 0.85, 1.1);
    s->g = (tg_growth){0.22, 0.0, 0.25, 0.12, 0};
    s->clip = 1;
  } else if (level == 2) {
    s->angle = rnd(rng, 40, 75) * TG_DEG;
    s->len = rnd(rng, 0.8, 2.0) * (1 - 0.4 * a->t);
    s->rratio = 0.5;
    s->rmin = 0.006;
    s->g = (tg_growth){2.5, 0.0, 0.4, 0.3, 0};
  } else {
    s->angle = rnd(rng, 20, 40) * TG_DEG;
    s->len = rnd(rng, 0.25, 0.6);
    s->rratio = 0.6;
    s->rmax = 0.008;
    s->g = (tg_growth){4.0, 0.0, 0.6, 0.5, 0};
  }
}

static void palm_child(double h, bbc__rng *rng, tg_shape *s) {
  /* Fronds from the crown: the young ones upright, the old ones spread
   * and arching down under their weight. */
  s->angle = rnd(rng, 35, 100) * TG_DEG;
  s->len = 0.38 * h * rnd(rng, 0.85, 1.12);
  s->rratio = 0.25;
  s->rmin = 0.02;
  s->rmax = 0.05;
  s->g = (tg_growth){0.5, 0.0, 0.12, 0.25, 0};
}

static void bush_child(int level, const tg_attach *a, double h, bbc__rng *rng, tg_shape *s) {
  if (level == 1) {
    s->angle = rnd(rng, 45, 80) * TG_DEG;
    s->len = (0.45 + rnd(rng, 0, 0.5)) * (1 - 0.45 * a->t) * h / 2.5;
    s->rratio = 0.55;
    s->rmin = 0.006;
    s->g = (tg_growth){0.3, 0.25, 0.8, 0.25, 0};
    s->clip = 1;
  } else {
    s->angle = rnd(rng, 30, 60) * TG_DEG;
    s->len = rnd(rng, 0.15, 0.35);
    s->rratio = 0.6;
    s->rmin = 0.0025;
    s->rmax = 0.008;
    s->g = (tg_growth){0.2, 0.4, 1.2, 0.5, 0};
  }
}

/* Shape of a child branch: species- and level-specific proportions.
 * `radial` is the (unit, perpendicular to the parent) direction the child
 * leaves in. */
static void tg_child_shape(tg_ctx *c, int level, const tg_attach *a, vec3 radial, bbc__rng *rng,
                           tg_child *ch) {
  double h = c->height;
  tg_shape s = {45 * TG_DEG, 1, 0.5, 0.003, 1, 0, {0.1, 0.1, 0.4, 0.3, 0}};
  vec3 t = a->tangent;
  ch->vigor = a->parent->vigor;
  switch (c->shape) {
  case BBC_TREE_OAK:
    oak_child(level, a, h, rng, &s, ch);
    break;
  case BBC_TREE_PINE:
    pine_child(a, rng, &s);
    break;
  case BBC_TREE_BIRCH:
    birch_child(level, a, h, rng, &s, ch);
    break;
  case BBC_TREE_PALM:
    palm_child(h, rng, &s);
    break;
  case BBC_TREE_BUSH:
  default:
    bush_child(level, a, h, rng, &s);
    break;
  }
  double angle = s.angle, len = s.len;
  tg_growth g = s.g;
  ch->dir = vnorm(vadd(vscale(t, cos(angle)), vscale(radial, sin(angle))));
  if (s.clip) len = tg_clip_length(c, a->pos, ch->dir, len, ch->vigor * rnd(rng, 0.92, 1.08));
  ch->length = len;
  double r = a->radius * s.rratio;
  ch->radius = clampd(r, s.rmin, s.rmax);
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

/* Stratified spreading (tg_spread in treegen.h): point k at (k + jitter) /
 * count of the total weight. */
int bbc__tree_spread_next(tg_spread *s, bbc__rng *rng, size_t *branch, double *u) {
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
  while (bbc__tree_spread_next(&sp, rng, &bi, &u)) {
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
    bbc__tree_branch_at(c, parent, r ? lerp(r->t0, r->t1, u) : u, &a);
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
    bbc__tree_branch_at(c, trunk, y / trunk->length, &a);
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

bbc_result bbc__tree_skeleton(tg_ctx *c) {
  c->first[0] = 0;
  tg_place_trunks(c, &c->rng_shape);
  c->first[1] = c->branch_count;
  for (int l = 1; l < c->levels; l++) {
    bbc__rng *rng = l == 1 ? &c->rng_shape : &c->rng_fine;
    if (l == 1 && c->shape == BBC_TREE_PINE)
      tg_place_whorls(c, rng);
    else if (tg_place_level(c, l, rng) != BBC_OK)
      return BBC_ERROR_OUT_OF_MEMORY;
    c->first[l + 1] = c->branch_count;
  }
  for (int l = c->levels; l < TG_LEVELS; l++) c->first[l + 1] = c->branch_count;
  return BBC_OK;
}
