/* occlude.c — cells of trees hidden behind the terrain,
 * GL-free and conservative: a cell is hidden only when the terrain *as
 * drawn this frame* stands above every ray from the eye to its box.
 *
 * The drawn terrain (src/forest/terrain.c, CDLOD) samples the heightmap at
 * its vertices: at a distance whose level is l, its grid has a vertex every
 * 2^l squares, morphing towards 2^(l+1), aligned to multiples of that
 * spacing, and a triangle's heights lie between its corners'. So the drawn
 * surface anywhere inside an aligned block of 2^k squares, k >= l + 1, is at
 * least the smallest heightmap value of that block: a pyramid of block
 * minima is a height below the drawn terrain. For a box seen from the eye
 * over azimuths [a0, a1], every ray to it crosses, at each horizontal
 * distance r short of the box, the arc of radius r between a0 and a1, and
 * is there no higher than the box's top seen along the steepest of them;
 * where the blocks under that whole arc all stand higher, every ray has
 * gone below the drawn terrain, which is opaque: the box is hidden.
 *
 * Per frame (bbc_forest_occluder_begin) that test is tabled, for each
 * azimuth bin around the eye that a box asks about (once a frame), at
 * every distance step: H[b][k], the steepest
 * rise (height over distance from the eye) that the terrain under bin b
 * blocks at one of the first k steps. A box is hidden when, in every bin
 * it spans, H at the last step short of it exceeds the rise of its
 * steepest ray. */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void bbc_forest_occluder_free(bbc_forest_occluder *o) {
  if (!o) return;
  for (int k = 0; o->min && k < o->levels; k++) free(o->min[k]);
  free(o->min);
  free(o->step);
  free(o->step_lod);
  free(o->horizon);
  free(o->bin_dir);
  free(o->bin_done);
  memset(o, 0, sizeof *o);
}

/* The distance step after r: 12 % farther, plus a heightmap spacing. */
static double next_step(double r, double spacing) {
  return r * 1.12 + spacing;
}

bbc_result bbc_forest_occluder_init(bbc_forest_occluder *o, const bbc_forest_world *w,
                                    bbc_error *err) {
  assert(o && w);
  memset(o, 0, sizeof *o);
  int n = w->width - 1;
  if (!w->height || n < 1 || w->depth != w->width || (n & (n - 1)))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "occlusion: %d x %d vertices is not (2^n + 1)^2", w->width, w->depth);
  o->squares = n;
  o->spacing = w->spacing;
  o->height = w->height;
  while ((n >> o->levels) >= 1) o->levels++;
  o->min = calloc((size_t)o->levels, sizeof *o->min);
  if (!o->min) goto oom;
  o->lowest = INFINITY;
  o->highest = -INFINITY;
  for (int k = 0; k < o->levels; k++) {
    int m = n >> k;
    float *b = o->min[k] = malloc((size_t)m * m * sizeof *b);
    if (!b) goto oom;
    for (int z = 0; z < m; z++)
      for (int x = 0; x < m; x++) {
        float lo;
        if (k == 0) { /* a square: its four corners */
          const float *h = w->height + (size_t)z * w->width + x;
          lo = fminf(fminf(h[0], h[1]), fminf(h[w->width], h[w->width + 1]));
          o->lowest = fmin(o->lowest, lo);
          o->highest =
              fmax(o->highest, fmaxf(fmaxf(h[0], h[1]), fmaxf(h[w->width], h[w->width + 1])));
        } else { /* four blocks of the level below */
          const float *c = o->min[k - 1];
          int cm = m * 2;
          lo = fminf(
              fminf(c[(size_t)2 * z * cm + 2 * x], c[(size_t)2 * z * cm + 2 * x + 1]),
              fminf(c[(size_t)(2 * z + 1) * cm + 2 * x], c[(size_t)(2 * z + 1) * cm + 2 * x + 1]));
        }
        b[(size_t)z * m + x] = lo;
      }
  }
  /* the distance steps, out to the map's diagonal */
  double far = 1.5 * n * w->spacing;
  int steps = 0;
  for (double r = 2 * w->spacing; r < far; r = next_step(r, w->spacing)) steps++;
  o->steps = steps;
  o->step = malloc((size_t)(steps ? steps : 1) * sizeof *o->step);
  o->step_lod = malloc((size_t)(steps ? steps : 1) * sizeof *o->step_lod);
  o->horizon = malloc((size_t)(steps ? steps : 1) * BBC_FOREST_OCCLUDER_BINS * sizeof *o->horizon);
  o->bin_dir = malloc((BBC_FOREST_OCCLUDER_BINS + 1) * 2 * sizeof *o->bin_dir);
  o->bin_done = calloc(BBC_FOREST_OCCLUDER_BINS, 1);
  if (!o->step || !o->step_lod || !o->horizon || !o->bin_dir || !o->bin_done) goto oom;
  steps = 0;
  for (double r = 2 * w->spacing; r < far; r = next_step(r, w->spacing)) o->step[steps++] = r;
  for (int b = 0; b <= BBC_FOREST_OCCLUDER_BINS; b++) {
    double a = -M_PI + 2 * M_PI * b / BBC_FOREST_OCCLUDER_BINS;
    o->bin_dir[2 * b] = cos(a);
    o->bin_dir[2 * b + 1] = sin(a);
  }
  return BBC_OK;
oom:
  bbc_forest_occluder_free(o);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "occlusion: out of memory");
}

/* The lowest the drawn terrain can be over the square [x0, x1] x [z0, z1]
 * (world units) at terrain level `lod` or finer: the blocks' minima at a
 * level coarse enough for both; the map's lowest outside the map. */
static double lowest_under(const bbc_forest_occluder *o, double x0, double x1, double z0, double z1,
                           int lod) {
  double s = o->spacing;
  x0 /= s, x1 /= s, z0 /= s, z1 /= s;
  if (x0 < 0 || z0 < 0 || x1 > o->squares || z1 > o->squares) return o->lowest;
  int k = lod < 0 ? 0 : lod;
  double wide = fmax(x1 - x0, z1 - z0);
  while (k < o->levels && (double)(1 << k) < wide) k++; /* narrower blocks span 3 or more */
  for (; k < o->levels; k++) {                          /* at most 2 x 2 blocks */
    double b = (double)(1 << k);
    if (floor(x1 / b) - floor(x0 / b) <= 1 && floor(z1 / b) - floor(z0 / b) <= 1) break;
  }
  if (k >= o->levels) return o->lowest;
  int m = o->squares >> k, bx0 = (int)floor(x0 / (1 << k)), bx1 = (int)floor(x1 / (1 << k));
  int bz0 = (int)floor(z0 / (1 << k)), bz1 = (int)floor(z1 / (1 << k));
  if (bx1 >= m) bx1 = m - 1;
  if (bz1 >= m) bz1 = m - 1;
  double lo = INFINITY;
  for (int z = bz0; z <= bz1; z++)
    for (int x = bx0; x <= bx1; x++) lo = fmin(lo, o->min[k][(size_t)z * m + x]);
  return lo;
}

/* The highest the drawn terrain can be at (x, z): the heights of the
 * aligned block of 2 x 2 squares around it (level 0 near the eye, morphing
 * towards level 1); the map's highest outside the map. */
static double ground_under(const bbc_forest_occluder *o, double x, double z) {
  int gx = (int)floor(x / o->spacing / 2) * 2, gz = (int)floor(z / o->spacing / 2) * 2;
  if (gx < 0 || gz < 0 || gx + 2 > o->squares || gz + 2 > o->squares) return o->highest;
  double hi = -INFINITY;
  for (int j = 0; j <= 2; j++)
    for (int i = 0; i <= 2; i++)
      hi = fmax(hi, o->height[(size_t)(gz + j) * (o->squares + 1) + gx + i]);
  return hi;
}

/* The coarsest grid level the terrain can draw at 3D distance d or less
 * (its level by `range`, plus one for the morph towards the next). */
static int lod_at(const bbc_forest_terrain *t, double d) {
  int l = 0;
  while (l + 1 < t->levels && t->range[l] < d) l++;
  return l + 1;
}

void bbc_forest_occluder_begin(bbc_forest_occluder *o, const bbc_forest_terrain *t,
                               const double eye[3]) {
  assert(o && t && eye);
  o->ready = 0;
  if (!o->min || !o->horizon) return;
  double ex = eye[0], ey = eye[1], ez = eye[2];
  /* the eye above the terrain drawn around it */
  if (!(ey > ground_under(o, ex, ez))) return;
  memcpy(o->eye, eye, sizeof o->eye);
  double drop = ey - o->lowest, bulge = 1 - cos(M_PI / BBC_FOREST_OCCLUDER_BINS) + 1e-6;
  /* per step: the terrain's coarsest level there (for the widest arc a bin
   * has: its chord plus the bulge each way) */
  double chord = 2 * sin(M_PI / BBC_FOREST_OCCLUDER_BINS) + 2 * bulge;
  for (int k = 0; k < o->steps; k++) {
    double r = o->step[k], w = chord * r;
    o->step_lod[k] = lod_at(t, sqrt((r + w) * (r + w) + drop * drop) + w);
  }
  memset(o->bin_done, 0, BBC_FOREST_OCCLUDER_BINS);
  o->ready = 1;
}

/* Bin b's column of the frame's table (made when first asked: the view
 * spans a fraction of the bins). */
static const float *column(bbc_forest_occluder *o, int b) {
  float *h = o->horizon + (size_t)b * o->steps;
  if (o->bin_done[b]) return h;
  double ex = o->eye[0], ey = o->eye[1], ez = o->eye[2];
  double bulge = 1 - cos(M_PI / BBC_FOREST_OCCLUDER_BINS) + 1e-6;
  const double *d0 = o->bin_dir + 2 * b, *d1 = d0 + 2;
  double lx = fmin(d0[0], d1[0]) - bulge, hx = fmax(d0[0], d1[0]) + bulge;
  double lz = fmin(d0[1], d1[1]) - bulge, hz = fmax(d0[1], d1[1]) + bulge;
  double best = -INFINITY;
  for (int k = 0; k < o->steps; k++) {
    double r = o->step[k];
    /* the bin's arc at r: its two ends and the bulge beyond the chord */
    double rise =
        (lowest_under(o, ex + r * lx, ex + r * hx, ez + r * lz, ez + r * hz, o->step_lod[k]) - ey) /
        r;
    if (rise > best) best = rise;
    h[k] = (float)best;
  }
  o->bin_done[b] = 1;
  return h;
}

/* The bin of azimuth a (radians, any turn). */
static int bin_of(double a) {
  double f = (a + M_PI) / (2 * M_PI);
  f -= floor(f);
  int b = (int)(f * BBC_FOREST_OCCLUDER_BINS);
  return b >= BBC_FOREST_OCCLUDER_BINS ? BBC_FOREST_OCCLUDER_BINS - 1 : b;
}

int bbc_forest_occluder_hides(bbc_forest_occluder *o, const float box[6]) {
  assert(o && box);
  if (!o->ready || box[0] > box[3]) return 0;
  double ex = o->eye[0], ey = o->eye[1], ez = o->eye[2];
  /* the box, grown for the wind's sway */
  double grow = 0.1 * (box[4] - box[1]);
  double x0 = box[0] - grow, x1 = box[3] + grow, z0 = box[2] - grow, z1 = box[5] + grow;
  double top = box[4] + grow;
  if (fmin(ey, top) >= o->highest) return 0; /* above everything */
  /* its nearest and farthest horizontal distance, its azimuths about the centre's */
  double nx = ex < x0 ? x0 - ex : ex > x1 ? ex - x1 : 0;
  double nz = ez < z0 ? z0 - ez : ez > z1 ? ez - z1 : 0;
  double dmin = sqrt(nx * nx + nz * nz);
  if (dmin < 4 * o->spacing) return 0; /* at or near the eye */
  double cx = 0.5 * (x0 + x1) - ex, cz = 0.5 * (z0 + z1) - ez, cl = sqrt(cx * cx + cz * cz);
  cx /= cl, cz /= cl;
  double a0 = INFINITY, a1 = -INFINITY, dmax = 0;
  for (int k = 0; k < 4; k++) {
    double px = (k & 1 ? x1 : x0) - ex, pz = (k & 2 ? z1 : z0) - ez;
    double a = atan2(cx * pz - cz * px, cx * px + cz * pz); /* about the centre's direction */
    a0 = fmin(a0, a);
    a1 = fmax(a1, a);
    dmax = fmax(dmax, sqrt(px * px + pz * pz));
  }
  double rise = (top - ey) / (top >= ey ? dmin : dmax); /* its steepest ray's */
  /* the last step short of it */
  int lo = 0, hi = o->steps; /* the first step at dmin - spacing or beyond */
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (o->step[mid] < dmin - o->spacing)
      lo = mid + 1;
    else
      hi = mid;
  }
  int k = lo - 1;
  if (k < 0) return 0;
  double base = atan2(cz, cx);
  int b0 = bin_of(base + a0), n = bin_of(base + a1) - b0;
  if (n < 0) n += BBC_FOREST_OCCLUDER_BINS;
  for (int i = 0; i <= n; i++)
    if (!(column(o, (b0 + i) % BBC_FOREST_OCCLUDER_BINS)[k] > rise)) return 0;
  return 1;
}
