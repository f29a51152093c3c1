/* refine.c — beyond the thesis: each billboard's binary alpha refined
 * against renders of the original. The original's coverage is
 * rendered once from views spread over the sphere; then, for a few rounds,
 * the cloud is drawn from the same views keeping per pixel the nearest
 * opaque texel and the nearest texel that could turn opaque (one that some
 * sample of the original covered). Each view is cut in 8 x 8 pixel blocks,
 * and a block is too dense or too sparse where the cloud covers more or
 * fewer of its pixels than the original. An opaque texel is cleared when it
 * is seen more often where the original is empty than where it is covered,
 * unless it lies more often in too sparse blocks than in too dense ones (so
 * thin outer parts are not thinned further); where it lies mostly in too
 * dense blocks, already when it is wrong 0.7 times as often as right. A
 * transparent one is set when it would fill more of the original's
 * uncovered pixels than it would add false ones, unless it lies mostly in
 * too dense blocks.
 * Texels no view's pixel centre lands on (smaller than a pixel as drawn,
 * or always hidden) are not judged: after the rounds they are thinned as
 * the judged ones of their image were (unseen_thin).
 * Counts are integers summed per thread in a fixed order, so the result
 * does not depend on the number of threads.
 * Step 3 runs it on quality 2's baked masks (bbc__refine_baked), then
 * clears the colour of the texels left transparent. */
#include "cloud.h"
#include "raster.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

/* Per texel counts of one round, over its pixels in every view: right
 * (an opaque texel seen where the original is covered, a transparent one
 * that would fill a pixel the original covers but the cloud does not),
 * wrong (the reverse), and how often it lies in a block that is too dense
 * minus how often in one that is too sparse. */
enum { RIGHT, WRONG, BALANCE, COUNTS }; /* BALANCE: too dense minus too sparse */
#define BLOCK 8                         /* pixels per block side: density is matched over blocks */

typedef struct buffers {
  float *z, *cz;      /* nearest opaque / candidate texel depth */
  uint32_t *id, *cid; /* its texel + 1, 0 = none */
} buffers;

/* Draws every billboard's visible side into the buffers. */
static void draw_cloud(const bbc_cloud_billboard *cb, const bbc__refine_image *im, size_t n,
                       const size_t *offset, const bbc__camera *cam, int size, buffers *b) {
  size_t np = (size_t)size * size;
  for (size_t i = 0; i < np; i++) {
    b->z[i] = b->cz[i] = FLT_MAX;
    b->id[i] = b->cid[i] = 0;
  }
  for (size_t k = 0; k < n; k++) {
    const bbc_billboard *rc = &cb[k].rect;
    const bbc__refine_image *m = &im[k];
    double dn =
        cam->f[0] * cb[k].normal[0] + cam->f[1] * cb[k].normal[1] + cam->f[2] * cb[k].normal[2];
    int side = dn > 0 && m->alpha[1] ? 1 : 0; /* the back seen, when it has its own image */
    const uint8_t *alpha = m->alpha[side], *cand = m->cand[side];
    size_t base = offset[2 * k + side];
    /* x(s, t) = o + s A + t B on the screen. */
    double o[3], pa[3], pb[3], A[3], B[3], q[3];
    bbc__camera_project(cam, rc->origin, o);
    for (int j = 0; j < 3; j++) q[j] = rc->origin[j] + rc->width * rc->u[j];
    bbc__camera_project(cam, q, pa);
    for (int j = 0; j < 3; j++) q[j] = rc->origin[j] + rc->height * rc->w[j];
    bbc__camera_project(cam, q, pb);
    for (int j = 0; j < 3; j++) {
      A[j] = pa[j] - o[j];
      B[j] = pb[j] - o[j];
    }
    double det = A[0] * B[1] - A[1] * B[0];
    if (fabs(det) < 1e-6) continue; /* edge-on */
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    int nc = cb[k].corner_count;
    for (int c = 0; c < nc; c++) {
      double s = cb[k].corners[c][0], t = cb[k].corners[c][1];
      double x = o[0] + s * A[0] + t * B[0], y = o[1] + s * A[1] + t * B[1];
      xmin = fmin(xmin, x);
      xmax = fmax(xmax, x);
      ymin = fmin(ymin, y);
      ymax = fmax(ymax, y);
    }
    int y0 = (int)fmax(0, floor(ymin)), y1 = (int)fmin(size - 1, ceil(ymax));
    if (xmax < 0 || xmin > size) continue;
    int w = m->width, h = m->height;
    /* s and t at pixel centre (X, Y) = (x + 0.5, y + 0.5): linear; so is
     * each outline edge's inside function (the outline is convex, counter-
     * clockwise in (s, t)), which gives each row's span. */
    double sx = B[1] / det, sy = -B[0] / det, s0 = (o[1] * B[0] - o[0] * B[1]) / det;
    double tx = -A[1] / det, ty = A[0] / det, t0 = (A[1] * o[0] - A[0] * o[1]) / det;
    double ex[10], ey[10], e0[10];
    for (int c = 0; c < nc; c++) {
      const double *P = cb[k].corners[c], *Q = cb[k].corners[(c + 1) % nc];
      double du = Q[0] - P[0], dv = Q[1] - P[1];
      ex[c] = du * tx - dv * sx;
      ey[c] = du * ty - dv * sy;
      e0[c] = du * (t0 - P[1]) - dv * (s0 - P[0]);
    }
    for (int y = y0; y <= y1; y++) {
      double Y = y + 0.5, lo = 0.5, hi = size - 0.5;
      for (int c = 0; c < nc && lo <= hi; c++) {
        double g = ey[c] * Y + e0[c] + 1e-12;
        if (ex[c] > 0)
          lo = fmax(lo, -g / ex[c]);
        else if (ex[c] < 0)
          hi = fmin(hi, -g / ex[c]);
        else if (g < 0)
          hi = -1;
      }
      if (lo > hi) continue;
      int xs = (int)ceil(lo - 0.5), xe = (int)floor(hi - 0.5);
      if (xs < 0) xs = 0;
      if (xe > size - 1) xe = size - 1;
      for (int x = xs; x <= xe; x++) {
        double X = x + 0.5;
        double s = sx * X + sy * Y + s0, t = tx * X + ty * Y + t0;
        if (s < 0 || s >= 1 || t < 0 || t >= 1) continue;
        int col = (int)(s * w), row = (int)((1.0 - t) * h);
        if (col >= w) col = w - 1;
        if (row >= h) row = h - 1;
        if (row < 0) row = 0;
        size_t tex = (size_t)row * w + col, pi = (size_t)y * size + x;
        float z = (float)(o[2] + s * A[2] + t * B[2]);
        if (alpha[tex]) {
          if (z < b->z[pi]) {
            b->z[pi] = z;
            b->id[pi] = (uint32_t)(base + tex + 1);
          }
        } else if (cand && cand[tex] && z < b->cz[pi]) {
          b->cz[pi] = z;
          b->cid[pi] = (uint32_t)(base + tex + 1);
        }
      }
    }
  }
}

/* An 8 x 8 ordered-dither threshold map (Bayer), 0..63. */
static const uint8_t k_bayer[8][8] = {
    {0, 32, 8, 40, 2, 34, 10, 42},  {48, 16, 56, 24, 50, 18, 58, 26},
    {12, 44, 4, 36, 14, 46, 6, 38}, {60, 28, 52, 20, 62, 30, 54, 22},
    {3, 35, 11, 43, 1, 33, 9, 41},  {51, 19, 59, 27, 49, 17, 57, 25},
    {15, 47, 7, 39, 13, 45, 5, 37}, {63, 31, 55, 23, 61, 29, 53, 21}};

/* Opaque texels that no round judged keep of their number the share the
 * judged ones of the same image kept (of those opaque before the rounds;
 * the whole cloud's share for an image with fewer than 64 judged), in an
 * ordered-dither pattern. Without it they keep the bake's density, which
 * refinement found too high where it could judge: that matters where
 * texels are smaller than the views' pixels and most opaque ones go
 * unjudged. */
/* `kept`: 2 n zeroed pairs, per image side the judged texels opaque
 * before the rounds and how many of them still are. */
static void unseen_thin(bbc__refine_image *im, size_t n, const size_t *offset, const uint8_t *seen,
                        const uint8_t *before, size_t (*kept)[2]) {
  size_t all[2] = {0, 0};
  for (size_t k = 0; k < n; k++)
    for (int s = 0; s < 2; s++) {
      if (!im[k].alpha[s]) continue;
      size_t nx = (size_t)im[k].width * im[k].height, base = offset[2 * k + s];
      size_t *c = kept[2 * k + s];
      for (size_t i = 0; i < nx; i++)
        if (seen[base + i] && before[base + i]) {
          c[0]++;
          c[1] += im[k].alpha[s][i] != 0;
        }
      all[0] += c[0];
      all[1] += c[1];
    }
  for (size_t k = 0; k < n; k++)
    for (int s = 0; s < 2; s++) {
      if (!im[k].alpha[s]) continue;
      size_t w = (size_t)im[k].width, nx = w * im[k].height, base = offset[2 * k + s];
      const size_t *c = kept[2 * k + s][0] < 64 ? all : kept[2 * k + s];
      size_t k0 = c[0], k1 = c[1];
      if (k0 == 0 || k1 >= k0) continue;
      /* Kept where 64 k1 > (threshold + 0.5) k0, in integers. */
      for (size_t i = 0; i < nx; i++)
        if (!seen[base + i] && im[k].alpha[s][i] &&
            128 * (uint64_t)k1 <= (2 * (uint64_t)k_bayer[(i / w) & 7][(i % w) & 7] + 1) * k0)
          im[k].alpha[s][i] = 0;
    }
}

/* Refinement's state over its rounds. */
typedef struct refine {
  const bbc_mesh *m;
  const bbc_cloud_billboard *cb;
  bbc__refine_image *im;
  size_t n;
  const bbc__refine_options *opt;
  int nv, size, nt;  /* views, pixels per side, threads */
  size_t np, total;  /* pixels a view, texels of all images */
  size_t *offset;    /* per image side: its first texel among all */
  uint8_t *orig;     /* per view: the original's coverage */
  uint8_t *solid;    /* per view: the solid geometry's, or NULL */
  bbc__camera *cams; /* per view */
  int32_t *counts;   /* per thread, per texel: COUNTS counts */
  uint8_t *seen;     /* per texel: judged in some round */
  uint8_t *before;   /* per texel: opaque before the rounds */
  size_t (*kept)[2]; /* unseen_thin's counts */
  int failed;        /* a view or a buffer failed: first says why */
  bbc_error first;
} refine;

static void refine_free(refine *rf) {
  free(rf->seen);
  free(rf->before);
  free(rf->kept);
  free(rf->offset);
  free(rf->orig);
  free(rf->solid);
  free(rf->cams);
  free(rf->counts);
}

/* Each image side's first texel among all, and the buffers; out of memory:
 * an error, nothing allocated. */
static bbc_result refine_alloc(refine *rf, bbc_error *err) {
  const bbc__refine_options *opt = rf->opt;
  bbc__refine_image *im = rf->im;
  size_t n = rf->n;
  int nv = rf->nv, size = rf->size;
  size_t *offset = malloc(2 * n * sizeof *offset), total = 0;
  if (!offset) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "refine: out of memory");
  for (size_t k = 0; k < n; k++)
    for (int s = 0; s < 2; s++) {
      offset[2 * k + s] = total;
      if (im[k].alpha[s]) total += (size_t)im[k].width * im[k].height;
    }
  rf->offset = offset;
  rf->total = total;
  size_t np = (size_t)size * size;
  rf->np = np;
  rf->orig = malloc((size_t)nv * np);
  /* The opaque geometry drawn with the cloud (the limbs' mesh): no texel
   * is judged at its pixels, and they stay out of a block's count of what
   * the cloud covers (not of the original's), so that the foliage's
   * density is matched as if they were not drawn (closer to the original
   * than counting them as covered, or leaving them out of both counts). */
  rf->solid = opt->solid ? malloc((size_t)nv * np) : NULL;
  rf->cams = malloc((size_t)nv * sizeof *rf->cams);
  int nt = bbc__thread_count(opt->threads);
  rf->nt = nt;
  rf->counts = calloc((size_t)nt * COUNTS * (total ? total : 1), sizeof *rf->counts);
  rf->seen = calloc(total ? total : 1, 1);
  rf->before = malloc(total ? total : 1);
  rf->kept = calloc(2 * n, sizeof *rf->kept);
  if (!rf->orig || !rf->cams || !rf->counts || !rf->seen || !rf->before || !rf->kept ||
      (opt->solid && !rf->solid)) {
    refine_free(rf);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "refine: out of memory");
  }
  for (size_t k = 0; k < n; k++)
    for (int s = 0; s < 2; s++)
      if (im[k].alpha[s]) {
        size_t nx = (size_t)im[k].width * im[k].height;
        for (size_t i = 0; i < nx; i++) rf->before[offset[2 * k + s] + i] = im[k].alpha[s][i] != 0;
      }
  return BBC_OK;
}

/* The original's coverage from every view (and the solid geometry's). */
static void render_originals(refine *rf) {
  const bbc__refine_options *opt = rf->opt;
  const bbc_mesh *m = rf->m;
  int nv = rf->nv, size = rf->size, nt = rf->nt;
  size_t np = rf->np;
  uint8_t *orig = rf->orig, *solid = rf->solid;
  bbc__camera *cams = rf->cams;
  int up = opt->up_axis >= 0 && opt->up_axis <= 2 ? opt->up_axis : 1;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
  for (int v = 0; v < nv; v++) {
    double dir[3], upv[3] = {0, 0, 0};
    /* A lattice turned half a step from eval's, so that what is refined
     * is not what is measured. */
    int a = (up + 1) % 3, bx = (up + 2) % 3;
    double z = 1.0 - (2.0 * v + 1.0) / nv, r = sqrt(fmax(0.0, 1.0 - z * z));
    double phi = (v + 0.5) * 2.399963229728653;
    dir[up] = -z;
    dir[a] = -r * cos(phi);
    dir[bx] = -r * sin(phi);
    upv[fabs(dir[up]) > 0.999 ? (up + 2) % 3 : up] = 1;
    bbc_view view;
    bbc__view_frame_box(m->bbox_min, m->bbox_max, dir, upv, 1.02, &view);
    bbc__camera_setup(&cams[v], &view, size, size);
    bbc_error e;
    if (bbc__render_coverage(m, &view, size, orig + (size_t)v * np, opt->alpha_bits, &e) !=
            BBC_OK ||
        (solid && bbc__render_coverage(opt->solid, &view, size, solid + (size_t)v * np, NULL, &e) !=
                      BBC_OK)) {
#pragma omp critical(bbc_refine_fail)
      {
        if (!rf->failed) rf->first = e;
        rf->failed = 1;
      }
    }
  }
}

/* View v's counts: per block, the pixels the cloud covers and the
 * original's; each pixel's texel (the nearest opaque one, else the nearest
 * candidate) counted right or wrong and in a too dense or too sparse
 * block, into cnt. */
static void count_view(const refine *rf, int v, const buffers *b, int32_t *cnt) {
  int size = rf->size;
  size_t np = rf->np;
  const uint8_t *o = rf->orig + (size_t)v * np, *so = rf->solid ? rf->solid + (size_t)v * np : NULL;
  for (int by = 0; by < size; by += BLOCK)
    for (int bx = 0; bx < size; bx += BLOCK) {
      int ey = by + BLOCK < size ? by + BLOCK : size, ex = bx + BLOCK < size ? bx + BLOCK : size;
      int cov = 0, ob = 0, any = 0;
      for (int y = by; y < ey; y++)
        for (int x = bx; x < ex; x++) {
          size_t i = (size_t)y * size + x;
          ob += o[i];
          cov += b->id[i] != 0;
          any |= b->id[i] || b->cid[i];
        }
      if (!any) continue;
      int over = cov > ob, under = cov < ob;
      for (int y = by; y < ey; y++)
        for (int x = bx; x < ex; x++) {
          size_t i = (size_t)y * size + x;
          uint32_t t = b->id[i] ? b->id[i] : b->cid[i];
          if (!t || (so && so[i])) continue;
          t--;
          int32_t *ct = cnt + (size_t)t * COUNTS;
          ct[o[i] ? RIGHT : WRONG]++;
          ct[BALANCE] += over - under;
        }
    }
}

/* One round's counts: the cloud drawn from every view, each thread into
 * its own copy of the counts. */
static void count_round(refine *rf) {
  int nv = rf->nv, size = rf->size, nt = rf->nt;
  size_t np = rf->np, total = rf->total;
  int32_t *counts = rf->counts;
#pragma omp parallel num_threads(nt)
  {
    int tid = 0, tn = 1;
#ifdef _OPENMP
    tid = omp_get_thread_num();
    tn = omp_get_num_threads();
#endif
    int32_t *cnt = counts + (size_t)tid * COUNTS * total;
    /* Every copy cleared, also those of threads the team lacks. */
    for (int t = tid; t < nt; t += tn)
      memset(counts + (size_t)t * COUNTS * total, 0, COUNTS * total * sizeof *counts);
#pragma omp barrier
    buffers b;
    b.z = malloc(np * sizeof *b.z);
    b.cz = malloc(np * sizeof *b.cz);
    b.id = malloc(np * sizeof *b.id);
    b.cid = malloc(np * sizeof *b.cid);
    int ok = b.z && b.cz && b.id && b.cid;
    if (!ok) {
#pragma omp critical(bbc_refine_fail)
      rf->failed = 1;
    }
#pragma omp for schedule(dynamic, 1)
    for (int v = 0; v < nv; v++) {
      if (!ok) continue;
      draw_cloud(rf->cb, rf->im, rf->n, rf->offset, &rf->cams[v], size, &b);
      count_view(rf, v, &b, cnt);
    }
    free(b.z);
    free(b.cz);
    free(b.id);
    free(b.cid);
  }
}

/* Each texel's counts summed over the threads' copies, then its flip
 * decided. Returns the texels flipped. */
static size_t flip_texels(refine *rf) {
  bbc__refine_image *im = rf->im;
  size_t n = rf->n, total = rf->total;
  const size_t *offset = rf->offset;
  const int32_t *counts = rf->counts;
  uint8_t *seen = rf->seen;
  int nt = rf->nt;
  size_t changed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : changed) num_threads(nt)
  for (size_t k = 0; k < n; k++)
    for (int s = 0; s < 2; s++) {
      if (!im[k].alpha[s]) continue;
      size_t nx = (size_t)im[k].width * im[k].height, base = offset[2 * k + s];
      for (size_t i = 0; i < nx; i++) {
        int32_t c[COUNTS] = {0, 0, 0};
        for (int t = 0; t < nt; t++)
          for (int j = 0; j < COUNTS; j++)
            c[j] += counts[((size_t)t * total + base + i) * COUNTS + (size_t)j];
        int32_t right = c[RIGHT], wrong = c[WRONG], bal = c[BALANCE];
        if (right || wrong) seen[base + i] = 1;
        /* Cleared when more often wrong than right (a tie too) and not
         * where the cloud is too sparse, or, where it is too dense, when
         * wrong at least 0.7 times as often as right; set when more often
         * right than wrong and not where it is too dense. */
        int flip = im[k].alpha[s][i]
                       ? (wrong > right && bal >= 0) ||
                             (wrong && 10 * (int64_t)wrong >= 7 * (int64_t)right && bal > 0)
                       : right > wrong && bal <= 0;
        if (flip) {
          im[k].alpha[s][i] = im[k].alpha[s][i] ? 0 : 255;
          changed++;
        }
      }
    }
  return changed;
}

bbc_result bbc__refine_alpha(const bbc_mesh *m, const bbc_cloud_billboard *cb,
                             bbc__refine_image *im, size_t n, const bbc__refine_options *opt,
                             bbc_error *err) {
  int nv = opt->views, size = opt->size;
  if (nv <= 0 || n == 0) return BBC_OK;
  refine rf;
  memset(&rf, 0, sizeof rf);
  rf.m = m;
  rf.cb = cb;
  rf.im = im;
  rf.n = n;
  rf.opt = opt;
  rf.nv = nv;
  rf.size = size;
  bbc_result r = refine_alloc(&rf, err);
  if (r != BBC_OK) return r;
  render_originals(&rf);
  for (int round = 0; !rf.failed && round < opt->rounds; round++) {
    count_round(&rf);
    if (rf.failed) break;
    if (!flip_texels(&rf)) break;
  }
  if (!rf.failed) unseen_thin(im, n, rf.offset, rf.seen, rf.before, rf.kept);
  refine_free(&rf);
  if (rf.failed) {
    if (rf.first.message[0]) {
      if (err) *err = rf.first;
      return rf.first.code;
    }
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "refine: out of memory");
  }
  return BBC_OK;
}

bbc_result bbc__refine_baked(const bbc_mesh *m, const bbc_params *prm, bbc_cloud *cl,
                             bbc__baked *bk, const bbc_mesh *limbs,
                             const struct bbc__alpha_bits *alpha_bits, const bbc_callbacks *cbk,
                             bbc_error *err) {
  size_t nk = cl->billboard_count;
  int points = m->kind == BBC_MESH_POINTS;
  bbc_result r = BBC_OK;
  bbc__refine_image *ri = calloc(nk, sizeof *ri);
  if (!ri) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  for (size_t k = 0; r == BBC_OK && k < nk; k++) {
    for (int i = 0; i < 2; i++) {
      ri[k].alpha[i] = bk[k].mask[i];
      ri[k].cand[i] = bk[k].cand[i];
    }
    ri[k].width = cl->billboards[k].tex_width;
    ri[k].height = cl->billboards[k].tex_height;
  }
  if (r == BBC_OK && prm->refine > 0 && !points) { /* renders of triangles */
    if (cbk) bbc__progress(cbk, "refining", 0.0);
    int size = prm->refine_size >= 16 ? prm->refine_size : 256;
    bbc__refine_options ro = {prm->refine, size, 3, prm->up_axis, prm->threads, NULL, NULL};
    ro.solid = limbs->triangle_count ? limbs : NULL;
    ro.alpha_bits = alpha_bits;
    r = bbc__refine_alpha(m, cl->billboards, ri, nk, &ro, err);
    if (cbk) bbc__progress(cbk, "refining", 1.0);
  }
  for (size_t k = 0; r == BBC_OK && k < nk; k++) bbc__baked_clear_transparent(&bk[k]);
  free(ri);
  return r;
}
