/*
 * treegen_mesh.c — the tree generator's geometry and textures (step 3 of
 * treegen.c): every branch as a tapered tube, the leaves as textured quads
 * spread over the twigs, the leaf texture (a broad blade or a needle spray)
 * and the tileable bark texture.
 */
#include "treegen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
void bbc__tree_leaf_texture(tg_ctx *c, bbc_image *img) {
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
void bbc__tree_bark_texture(tg_ctx *c, bbc_image *img) {
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
void bbc__tree_emit_tube(const tg_ctx *c, const tg_branch *b, tg_out *o) {
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
bbc_result bbc__tree_emit_leaves(const tg_ctx *c, tg_out *o, const bbc_callbacks *cb) {
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
  while (bbc__tree_spread_next(&sp, &rng, &bi, &u)) {
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
    bbc__tree_branch_at(c, b, t0 + (t1 - t0) * pow(u, c->info->leaf_exponent), &a);
    vec3 n0 = vperp(a.tangent), b0 = vcross(a.tangent, n0);
    vec3 radial = vadd(vscale(n0, cos(roll)), vscale(b0, sin(roll)));
    tg_emit_leaf(c, &a, radial, &rng, o);
    if (++done % report == 0) bbc__progress(cb, "tree", 0.3 + 0.6 * (double)done / c->leaves);
  }
  free(cum);
  return BBC_OK;
}
