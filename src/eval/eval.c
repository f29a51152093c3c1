/* eval.c — how close a simplified model looks to its original: both
 * rendered by the software rasterizer, orthographic, in the original's
 * frame, from directions spread evenly over the sphere; coverage and colour
 * metrics per view and summarised. */
#include "raster.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#define PSNR_CAP 99.0 /* identical images */

void bbc_eval_options_default(bbc_eval_options *o) {
  assert(o);
  memset(o, 0, sizeof *o);
}

/* The options with their zeros made the defaults they stand for. */
static void resolve_defaults(bbc_eval_options *o) {
  if (o->views == 0) o->views = 64;
  if (o->size == 0) o->size = 256;
  if (o->side_elevation_deg == 0)
    o->side_elevation_deg = 30;
  else if (o->side_elevation_deg < 0)
    o->side_elevation_deg = 0; /* the horizon only */
  if (o->light[0] == 0 && o->light[1] == 0 && o->light[2] == 0) o->light[1] = 1;
  if (o->point_size == 0) o->point_size = 3.5;
  if (o->sun_ambient == 0) o->sun_ambient = 0.4;
}

void bbc_eval_result_free(bbc_eval_result *r) {
  if (!r) return;
  free(r->views);
  memset(r, 0, sizeof *r);
}

/* Direction k of n, camera towards the model: a Fibonacci lattice over the
 * sphere (area-uniform), in the frame (a, b, up). */
void bbc_eval_get_direction(int k, int n, bbc_axis up_axis, double dir[3]) {
  assert(n > 0 && k >= 0 && k < n && dir);
  int up = (int)up_axis >= 0 && up_axis <= 2 ? (int)up_axis : 1, a = (up + 1) % 3, b = (up + 2) % 3;
  double z = 1.0 - (2.0 * k + 1.0) / n, r = sqrt(fmax(0.0, 1.0 - z * z));
  double phi = k * 2.399963229728653; /* the golden angle */
  dir[up] = -z;
  dir[a] = -r * cos(phi);
  dir[b] = -r * sin(phi);
}

/* A view along `dir` framing the box lo..hi. */
static void frame_view(const double *dir, int up_axis, const double *lo, const double *hi,
                       const bbc_eval_options *o, double gain, bbc_view *v) {
  int up = up_axis >= 0 && up_axis <= 2 ? up_axis : 1;
  double upv[3] = {0, 0, 0};
  upv[fabs(dir[up]) > 0.999 ? (up + 2) % 3 : up] = 1; /* looking straight up or down */
  bbc__view_frame_box(lo, hi, dir, upv, 1.02, v);
  v->lighting = o->lighting;
  if (o->lighting) memcpy(v->light, o->light, sizeof v->light);
  v->light_gain = gain;
  v->ambient = o->lighting && !o->no_ambient && !o->sun;
  v->sun = o->lighting && o->sun;
  v->sun_ambient = o->sun_ambient;
  v->point_round = !o->point_square;
  /* background (0, 0, 0, 0): alpha tells coverage */
}

static double luminance(const uint8_t *p) {
  return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

static void compare(const bbc_image *a, const bbc_image *b, bbc_eval_view *ev) {
  size_t n = (size_t)a->width * a->height, na = 0, nb = 0, both = 0;
  double sq = 0, ab = 0, sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};
  for (size_t i = 0; i < n; i++) {
    const uint8_t *p = a->rgba + 4 * i, *q = b->rgba + 4 * i;
    int ca = p[3] >= 128, cb = q[3] >= 128;
    na += (size_t)ca;
    nb += (size_t)cb;
    both += (size_t)(ca && cb);
    if (!ca && !cb) continue;
    for (int c = 0; c < 3; c++) {
      if (ca) sa[c] += p[c];
      if (cb) sb[c] += q[c];
      double x = ca ? p[c] : 0, y = cb ? q[c] : 0;
      sq += (x - y) * (x - y);
      if (ca && cb) ab += fabs(x - y);
    }
  }
  size_t uni = na + nb - both;
  ev->original_px = na;
  ev->other_px = nb;
  ev->both_px = both;
  ev->iou = uni ? (double)both / (double)uni : 1.0;
  ev->recall = na ? (double)both / (double)na : 1.0;
  ev->false_coverage = nb ? (double)(nb - both) / (double)nb : 0.0;
  double mse = uni ? sq / (3.0 * (double)uni) : 0.0;
  ev->psnr = mse > 0 ? fmin(PSNR_CAP, 10.0 * log10(255.0 * 255.0 / mse)) : PSNR_CAP;
  ev->mae = both ? ab / (3.0 * (double)both) : 0.0;
  for (int c = 0; c < 3; c++) {
    ev->original_rgb[c] = na ? sa[c] / (double)na : 0.0;
    ev->other_rgb[c] = nb ? sb[c] / (double)nb : 0.0;
  }
  ev->coverage_ratio = na ? (double)nb / (double)na : 0.0;
  /* Seen 8x farther: 32 x 32 blocks (8 x 8 pixels at 256). Block IoU: per
   * block the covered fractions; block luminance error: per block the
   * covered pixels' summed luminance over the block's area, sum |other -
   * original| / sum original. */
  enum { NB = 32 };
  int w = a->width, h = a->height;
  double smin = 0, smax = 0, ldiff = 0, ltotal = 0;
  for (int by = 0; by < NB; by++)
    for (int bx = 0; bx < NB; bx++) {
      int x0 = bx * w / NB, x1 = (bx + 1) * w / NB, y0 = by * h / NB, y1 = (by + 1) * h / NB;
      if (x1 <= x0 || y1 <= y0) continue;
      size_t fa = 0, fb = 0;
      double la = 0, lb = 0;
      for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
          const uint8_t *p = a->rgba + 4 * ((size_t)y * w + x),
                        *q = b->rgba + 4 * ((size_t)y * w + x);
          fa += p[3] >= 128;
          fb += q[3] >= 128;
          if (p[3] >= 128) la += luminance(p);
          if (q[3] >= 128) lb += luminance(q);
        }
      double area = (double)(x1 - x0) * (y1 - y0);
      smin += fmin((double)fa, (double)fb) / area;
      smax += fmax((double)fa, (double)fb) / area;
      ldiff += fabs(la - lb) / area;
      ltotal += la / area;
    }
  ev->block_iou = smax > 0 ? smin / smax : 1.0;
  ev->block_luminance_error = ltotal > 0 ? ldiff / ltotal : 0.0;
}

/* Digits 0-9 and '.' in a 3 x 5 pixel font, one row per byte (bit 2 =
 * left column). */
static const uint8_t k_digits[11][5] = {{7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7},
                                        {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7},
                                        {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7},
                                        {7, 5, 7, 1, 7}, {0, 0, 0, 0, 2}};

/* Writes `text` (digits and '.') in black at (x, y) of the sheet, each
 * font pixel `scale` x `scale`, on a white box one font pixel wider. */
static void put_text(bbc_image *sheet, int x, int y, const char *text, int scale) {
  int n = (int)strlen(text), w = (4 * n + 1) * scale, h = 7 * scale;
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      int px = x + i, py = y + j;
      if (px < 0 || py < 0 || px >= sheet->width || py >= sheet->height) continue;
      int gx = i / scale - 1, gy = j / scale - 1, ci = gx >= 0 ? gx / 4 : -1, col = gx % 4;
      int ink = 0;
      if (ci >= 0 && ci < n && col < 3 && gy >= 0 && gy < 5) {
        char c = text[ci];
        int g = c == '.' ? 10 : c >= '0' && c <= '9' ? c - '0' : -1;
        ink = g >= 0 && (k_digits[g][gy] >> (2 - col) & 1);
      }
      uint8_t *o = sheet->rgba + 4 * ((size_t)py * sheet->width + px);
      o[0] = o[1] = o[2] = ink ? 0 : 255;
      o[3] = 255;
    }
}

/* Sheet row: original | other | coverage difference (grey both, red only
 * the original, blue only the other), the difference cell labelled with the
 * view's coverage ratio (top) and block IoU (below). */
static void put_row(bbc_image *sheet, int row, const bbc_image *a, const bbc_image *b) {
  int s = a->width;
  for (int y = 0; y < s; y++)
    for (int x = 0; x < s; x++) {
      size_t i = (size_t)y * s + x;
      const uint8_t *p = a->rgba + 4 * i, *q = b->rgba + 4 * i;
      uint8_t *o = sheet->rgba + 4 * ((size_t)(row * s + y) * sheet->width + x);
      const uint8_t white[4] = {255, 255, 255, 255};
      memcpy(o, p[3] >= 128 ? p : white, 4);
      memcpy(o + 4 * s, q[3] >= 128 ? q : white, 4);
      uint8_t *d = o + 8 * s;
      int ca = p[3] >= 128, cb = q[3] >= 128;
      d[0] = ca && !cb ? 230 : ca && cb ? 150 : !ca && cb ? 40 : 255;
      d[1] = ca && cb ? 150 : (ca || cb) ? 40 : 255;
      d[2] = !ca && cb ? 230 : ca && cb ? 150 : ca ? 40 : 255;
      o[3] = o[4 * s + 3] = d[3] = 255;
      o[4 * s + 3] = 255;
    }
}

/* What every view of bbc_eval shares. */
typedef struct eval_ctx {
  const bbc_mesh *orig, *other;
  const bbc_eval_options *o;
  int n, up, rows;     /* views, the up axis, the sheet's rows */
  double lo[3], hi[3]; /* both models' bounds */
  double gain;         /* the light's gain */
  bbc_eval_result *res;
} eval_ctx;

/* View k: both models rendered (into a and b) and compared into
 * res->views[k], and the sheet's rows that show it. 0 when a render failed
 * (e says why). */
static int eval_view(const eval_ctx *c, int k, bbc_image *a, bbc_image *b, bbc_error *e) {
  const bbc_eval_options *o = c->o;
  int n = c->n, up = c->up;
  bbc_eval_view *ev = &c->res->views[k];
  double dir[3];
  if (o->direction_count) {
    memcpy(dir, o->directions + 3 * k, sizeof dir);
    double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int i = 0; i < 3; i++) dir[i] = l > 0 ? dir[i] / l : (i == up ? -1 : 0);
  } else if (o->upper) { /* the first half of a lattice of 2n: z >= 0 */
    bbc_eval_get_direction(k, 2 * n, up, dir);
  } else {
    bbc_eval_get_direction(k, n, up, dir);
  }
  memcpy(ev->direction, dir, sizeof dir);
  ev->elevation_deg = asin(fmax(-1.0, fmin(1.0, -dir[up]))) * 180.0 / 3.14159265358979323846;
  ev->side = fabs(ev->elevation_deg) <= o->side_elevation_deg + 1e-9; /* "within" */
  bbc_view v;
  frame_view(dir, up, c->lo, c->hi, o, c->gain, &v);
  /* a point cloud splatted as step 3 splats it: pointsize pixels of a
   * 256-pixel picture of the whole model (its bounding sphere) */
  v.point_size_px =
      (float)(o->point_size * (2 * c->orig->radius / 256.0) * (o->size / (2 * v.half_extent)));
  if (bbc_render_ortho(c->orig, &v, a, e) != BBC_OK ||
      (o->impostor ? bbc_impostor_render(o->impostor, &v, b, e)
                   : bbc_render_ortho(c->other, &v, b, e)) != BBC_OK)
    return 0;
  compare(a, b, ev);
  /* Sheet rows: views spread over the whole list. */
  for (int r = 0; r < c->rows; r++)
    if ((int)((long long)r * n / c->rows) == k) {
      put_row(o->sheet, r, a, b);
      char t1[16], t2[16];
      snprintf(t1, sizeof t1, "%.2f", ev->coverage_ratio);
      snprintf(t2, sizeof t2, "%.2f", ev->block_iou);
      int sc = o->size >= 256 ? 2 : 1;
      put_text(o->sheet, 2 * o->size + 2, r * o->size + 2, t1, sc);
      put_text(o->sheet, 2 * o->size + 2, r * o->size + 2 + 8 * sc, t2, sc);
    }
  return 1;
}

/* Every view, in parallel (each thread with its own pair of images).
 * Returns 1 when one failed: first_err says why, if a render said. */
static int eval_views(const eval_ctx *c, bbc_error *first_err) {
  const bbc_eval_options *o = c->o;
  int n = c->n;
  int nt = bbc__thread_count(o->threads);
  int failed = 0;
#pragma omp parallel num_threads(nt)
  {
    bbc_image a = {0}, b = {0}; /* both freed below, whichever allocation failed */
    int ok = bbc_image_alloc(&a, o->size, o->size) == BBC_OK &&
             bbc_image_alloc(&b, o->size, o->size) == BBC_OK;
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < n; k++) {
      if (!ok) {
#pragma omp critical(bbc_eval_fail)
        failed = 1;
        continue;
      }
      bbc_error e;
      if (!eval_view(c, k, &a, &b, &e)) {
#pragma omp critical(bbc_eval_fail)
        {
          if (!failed) *first_err = e;
          failed = 1;
        }
        continue;
      }
    }
    bbc_image_free(&a);
    bbc_image_free(&b);
  }
  return failed;
}

/* The summaries over all n views and over the side views. */
static void summarise(bbc_eval_result *res, int n) {
  size_t ns = 0;
  double ob[3] = {0, 0, 0}, tb[3] = {0, 0, 0};
  res->iou_min = res->iou_side_min = res->psnr_min = 1e300;
  for (int k = 0; k < n; k++) {
    const bbc_eval_view *ev = &res->views[k];
    res->iou_mean += ev->iou;
    res->recall_mean += ev->recall;
    res->false_mean += ev->false_coverage;
    res->psnr_mean += ev->psnr;
    res->mae_mean += ev->mae;
    res->coverage_ratio_mean += ev->coverage_ratio;
    res->block_iou_mean += ev->block_iou;
    res->block_luminance_error_mean += ev->block_luminance_error;
    for (int c = 0; c < 3; c++) {
      ob[c] += ev->original_rgb[c];
      tb[c] += ev->other_rgb[c];
    }
    res->iou_min = fmin(res->iou_min, ev->iou);
    res->psnr_min = fmin(res->psnr_min, ev->psnr);
    if (ev->side) {
      ns++;
      res->iou_side_mean += ev->iou;
      res->recall_side_mean += ev->recall;
      res->psnr_side_mean += ev->psnr;
      res->coverage_ratio_side_mean += ev->coverage_ratio;
      res->block_iou_side_mean += ev->block_iou;
      res->iou_side_min = fmin(res->iou_side_min, ev->iou);
    }
  }
  res->iou_mean /= n;
  res->recall_mean /= n;
  res->false_mean /= n;
  res->psnr_mean /= n;
  res->mae_mean /= n;
  res->coverage_ratio_mean /= n;
  res->block_iou_mean /= n;
  res->block_luminance_error_mean /= n;
  for (int c = 0; c < 3; c++) res->brightness_ratio[c] = ob[c] > 0 ? tb[c] / ob[c] : 0.0;
  double ol = 0.2126 * ob[0] + 0.7152 * ob[1] + 0.0722 * ob[2];
  double tl = 0.2126 * tb[0] + 0.7152 * tb[1] + 0.0722 * tb[2];
  res->luminance_ratio = ol > 0 ? tl / ol : 0.0;
  res->side_count = ns;
  if (ns) {
    res->iou_side_mean /= (double)ns;
    res->recall_side_mean /= (double)ns;
    res->psnr_side_mean /= (double)ns;
    res->coverage_ratio_side_mean /= (double)ns;
    res->block_iou_side_mean /= (double)ns;
  } else {
    res->iou_side_min = 0;
  }
}

bbc_result bbc_eval(const bbc_mesh *orig, const bbc_mesh *other, const bbc_eval_options *opt,
                    bbc_eval_result *res, bbc_error *err) {
  assert(orig && res && (other || (opt && opt->impostor)));
  memset(res, 0, sizeof *res);
  bbc_eval_options o;
  if (opt)
    o = *opt;
  else
    bbc_eval_options_default(&o);
  resolve_defaults(&o);
  int n = o.direction_count ? (int)o.direction_count : o.views;
  if (n < 1 || n > 100000 || o.size < 8 || o.size > 8192)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "eval: views must be 1..100000 and size 8..8192 (got %d, %d)", n, o.size);
  if (o.impostor) other = orig; /* its bounds: the original's */
  if (orig->vertex_count == 0 || other->vertex_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "eval: a model is empty");
  eval_ctx c;
  memset(&c, 0, sizeof c);
  c.orig = orig;
  c.other = other;
  c.o = &o;
  c.n = n;
  c.res = res;
  /* Lit as prelight bakes: as bright as a lit viewer shows the original. */
  c.gain = 1.0;
  if (o.lighting && !o.sun) {
    bbc_result r = bbc_light_gain_measure(orig, o.light, bbc_up_axis(o.up), &c.gain, err);
    if (r != BBC_OK) return r;
  }
  for (int k = 0; k < 3; k++) {
    c.lo[k] = fmin(orig->bbox_min[k], other->bbox_min[k]);
    c.hi[k] = fmax(orig->bbox_max[k], other->bbox_max[k]);
  }
  res->views = calloc((size_t)n, sizeof *res->views);
  if (!res->views) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "eval: out of memory");
  res->view_count = (size_t)n;
  if (o.sheet) {
    c.rows = n < o.sheet_views ? n : o.sheet_views;
    if (c.rows < 1) c.rows = n < 8 ? n : 8;
    if (bbc_image_alloc(o.sheet, 3 * o.size, c.rows * o.size) != BBC_OK) {
      bbc_eval_result_free(res);
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "eval: out of memory for the sheet");
    }
  }
  c.up = (int)bbc_up_axis(o.up);
  bbc_error first_err;
  memset(&first_err, 0, sizeof first_err);
  if (eval_views(&c, &first_err)) {
    if (o.sheet) bbc_image_free(o.sheet);
    bbc_eval_result_free(res);
    if (first_err.message[0]) {
      if (err) *err = first_err;
      return first_err.code;
    }
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "eval: out of memory");
  }
  summarise(res, n);
  return BBC_OK;
}
