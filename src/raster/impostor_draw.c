/* impostor_draw.c — an octahedral impostor drawn as a GPU draws its quad
 * (docs/impostors.md): per pixel the three frames nearest the view, each
 * looked up where the view's ray meets its frame's surface (depth
 * parallax), blended by their weights, alpha tested, lit from the normal
 * atlas. Orthographic views, as bbc_render_ortho's. */
#include "raster.h"
#include "vec3.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef bbc__camera camera;

/* A 4 x 4 ordered dither's thresholds, (v + 0.5) / 16. */
static const uint8_t bayer[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};

/* The atlases of the level drawn: its frames' side and rows of texels. */
typedef struct level_atlas {
  const bbc_image *albedo, *normal;
  int size;
} level_atlas;

/* One of the three frames: its basis, its cell of the atlases and how the
 * view's ray crosses it. */
typedef struct frame_look {
  const level_atlas *lv;
  double w; /* blend weight */
  double dir[3], r[3], u[3];
  double denom; /* the view's forward . the frame's forward (> 0) */
  int x0, y0;   /* the frame's corner in the level's atlases */
} frame_look;

typedef struct texel_mix {
  double a, col[3], n[3]; /* alpha (0..1), alpha-weighted colour (0..1) and normal */
} texel_mix;

/* The frame's texel coordinates (x right, y down, texel units, centres at
 * +0.5) of the model point q, relative to the impostor's centre. */
static void frame_coords(const bbc_impostor *imp, const frame_look *fl, const double *q, double *s,
                         double *t) {
  int n = fl->lv->size;
  double k = 0.5 * n / imp->half_extent;
  *s = 0.5 * n + k * (q[0] * fl->r[0] + q[1] * fl->r[1] + q[2] * fl->r[2]);
  *t = 0.5 * n - k * (q[0] * fl->u[0] + q[1] * fl->u[1] + q[2] * fl->u[2]);
}

/* The nearest texel's depth (model units along the frame's forward from
 * the centre plane); *covered 0 where it is transparent or outside the
 * frame. */
static double depth_at(const bbc_impostor *imp, const frame_look *fl, double s, double t,
                       int *covered) {
  const level_atlas *lv = fl->lv;
  int x = (int)floor(s), y = (int)floor(t), n = lv->size;
  *covered = 0;
  if (x < 0 || y < 0 || x >= n || y >= n) return 0;
  size_t o = (size_t)(fl->y0 + y) * lv->albedo->width + (size_t)(fl->x0 + x);
  if (!lv->albedo->rgba[4 * o + 3]) return 0;
  *covered = 1;
  return (lv->normal->rgba[4 * o + 3] / 127.5 - 1.0) * imp->radius;
}

/* The nearest texel's colour, alpha (0 or 1 at every level) and normal at
 * (s, t) (as the rasterizer samples a mesh's textures); outside the frame
 * transparent (its border texels are never covered). */
static void sample_texel(const frame_look *fl, double s, double t, texel_mix *m) {
  memset(m, 0, sizeof *m);
  const level_atlas *lv = fl->lv;
  int x = (int)floor(s), y = (int)floor(t), n = lv->size;
  if (x < 0 || y < 0 || x >= n || y >= n) return;
  size_t o = (size_t)(fl->y0 + y) * lv->albedo->width + (size_t)(fl->x0 + x);
  const uint8_t *c = lv->albedo->rgba + 4 * o, *e = lv->normal->rgba + 4 * o;
  if (!c[3]) return;
  m->a = 1;
  for (int k = 0; k < 3; k++) {
    m->col[k] = c[k] / 255.0;
    m->n[k] = e[k] / 127.5 - 1.0;
  }
}

/* Frame fl's texel where the view's ray through p0 (on the centre plane
 * across the view, relative to the centre) meets the surface the frame
 * saw: marched from the near end of the model's sphere to the far end one
 * texel of the frame at a time, the first covered texel whose depth the
 * ray has reached and not passed by more than a thin shell (relief
 * mapping, the frame's depths as surfaces without volume). */
static void look_up(const bbc_impostor *imp, const frame_look *fl, const double *p0,
                    const double *f, texel_mix *m) {
  double a0 = -vdot(vload(p0), vload(fl->dir)); /* p0's depth in the frame */
  double R = imp->radius, q[3], s0, t0, s1, t1;
  for (int k = 0; k < 3; k++) q[k] = p0[k] + (-R - a0) / fl->denom * f[k];
  frame_coords(imp, fl, q, &s0, &t0);
  for (int k = 0; k < 3; k++) q[k] = p0[k] + (R - a0) / fl->denom * f[k];
  frame_coords(imp, fl, q, &s1, &t1);
  double len = fmax(fabs(s1 - s0), fabs(t1 - t0));
  int steps = len < 1 ? 1 : len > 4096 ? 4096 : (int)ceil(len);
  /* a surface is a shell: the ray meets it within a step, a texel and
   * the depths' rounding of it (a leaf has no volume behind it) */
  double texel = 2 * imp->half_extent / fl->lv->size;
  double shell = 2 * R / steps + texel + 2 * R / 255.0;
  /* The ray passing from in front of one covered texel to behind the next
   * crosses the surface between them, where their depths differ by less
   * than `bridge`, a quarter of the frame's width (one canopy's surface,
   * not two leaves far apart: measured on the Scopia pine and a generated
   * oak, docs/impostors.md). */
  int was_in_front = 0;
  double front_d = 0, bridge = 0.5 * imp->half_extent;
  for (int i = 0; i < steps; i++) {
    double mid = (i + 0.5) / steps, end = -R + 2 * R * (i + 1.0) / steps;
    double s = s0 + mid * (s1 - s0), t = t0 + mid * (t1 - t0);
    int covered;
    double d = depth_at(imp, fl, s, t, &covered);
    int hit = covered && d <= end && (d >= end - shell || (was_in_front && front_d - d <= bridge));
    was_in_front = covered && d > end;
    front_d = d;
    if (hit) {
      sample_texel(fl, s, t, m);
      return;
    }
  }
  memset(m, 0, sizeof *m);
}

static uint8_t round_byte(double v) {
  return (uint8_t)(v <= 0 ? 0 : v >= 254.5 ? 255 : v + 0.5);
}

/* The three frames a view along cam->f blends (weight 0: unused). */
static void setup_frames(const bbc_impostor *imp, const level_atlas *lv, const camera *cam,
                         frame_look fl[3]) {
  double towards[3] = {-cam->f[0], -cam->f[1], -cam->f[2]}, c[3], w[3];
  int fr[3][2];
  bbc__impostor_to_mapping((int)imp->up, towards, c);
  bbc_octahedral_blend(c, imp->frames, imp->hemi, fr, w);
  for (int k = 0; k < 3; k++) {
    frame_look *l = &fl[k];
    l->lv = lv;
    bbc_impostor_frame_basis(imp, fr[k][0], fr[k][1], l->dir, l->r, l->u);
    l->denom = -vdot(vload(cam->f), vload(l->dir));
    l->w = l->denom > 0.02 ? w[k] : 0; /* a frame seen edge-on gives nothing */
    l->x0 = fr[k][0] * lv->size;
    l->y0 = fr[k][1] * lv->size;
  }
  double sum = fl[0].w + fl[1].w + fl[2].w;
  for (int k = 0; k < 3; k++) fl[k].w = sum > 0 ? fl[k].w / sum : 0;
}

/* The light as bbc_render_ortho sets it up. */
static void light_dir(const camera *cam, const bbc_view *view, double *l) {
  if (view->headlight)
    for (int k = 0; k < 3; k++) l[k] = -cam->f[k];
  else if (view->light[0] != 0 || view->light[1] != 0 || view->light[2] != 0)
    memcpy(l, view->light, 3 * sizeof *l);
  else
    for (int k = 0; k < 3; k++) l[k] = -0.6 * cam->f[k] + 0.6 * cam->u[k] - 0.45 * cam->r[k];
  vstore(l, vnormalize(vload(l)));
}

/* The shade of colour col with normal n, as the rasterizer lights a mesh. */
static void shade(const bbc_view *v, const double *l, const double *n, const double *col,
                  uint8_t *out) {
  double s = 1, amb = 0;
  if (v->lighting) {
    double len = sqrt(vdot(vload(n), vload(n))), ndl = vdot(vload(n), vload(l));
    double inv = len > 1e-9 ? 1 / len : 0;
    double gain = v->light_gain > 0 ? v->light_gain : 1;
    if (v->sun) /* n.l of the mean normal, plus its missing length's share lit as a
                 * sphere of normals is (a quarter) */
      s = (v->sun_ambient + (ndl > 0 ? ndl : 0) + 0.25 * (1 - len)) / (v->sun_ambient + 1.0);
    else
      s = gain * (v->headlight ? fabs(ndl * inv) : 0.35 + 0.65 * fabs(ndl * inv));
    if (v->ambient && !v->sun) amb = 0.2;
  }
  for (int k = 0; k < 3; k++) out[k] = round_byte(255.0 * col[k] * (s + amb));
  out[3] = 255;
}

int bbc_impostor_level_count(const bbc_impostor *imp) {
  int n = 1;
  for (int s = imp && imp->frame_size > 0 ? imp->frame_size : 1; s > 1; s >>= 1) n++;
  return n;
}

int bbc_impostor_level_size(const bbc_impostor *imp, int level) {
  int s = imp ? imp->frame_size : 0;
  if (level < 0) level = 0;
  s = level >= 30 ? 0 : s >> level;
  return s > 1 ? s : 1;
}

/* Texel (x, y) of frame (i, j) at level size s: the mean over the level-0
 * texels it stands for (bbc_impostor_level), their covered share in
 * *share (the caller makes alpha binary from the shares). */
static void level_texel(const bbc_impostor *imp, int i, int j, int x, int y, int s, uint8_t *a,
                        uint8_t *e, float *share) {
  int S = imp->frame_size, W = imp->albedo.width;
  int x0 = x * S / s, x1 = (x + 1) * S / s, y0 = y * S / s, y1 = (y + 1) * S / s;
  double col[3] = {0, 0, 0}, all[3] = {0, 0, 0}, nrm[3] = {0, 0, 0}, depth = 0;
  long covered = 0, total = 0;
  for (int v = y0; v < y1; v++)
    for (int u = x0; u < x1; u++) {
      size_t o = 4 * ((size_t)(j * S + v) * W + (size_t)(i * S + u));
      const uint8_t *c = imp->albedo.rgba + o, *m = imp->normal.rgba + o;
      total++;
      for (int k = 0; k < 3; k++) all[k] += c[k];
      if (!c[3]) continue;
      covered++;
      for (int k = 0; k < 3; k++) {
        col[k] += c[k];
        nrm[k] += m[k] / 127.5 - 1.0;
      }
      depth += m[3];
    }
  *share = (float)((double)covered / (double)total);
  if (!covered) {
    for (int k = 0; k < 3; k++) {
      a[k] = round_byte(all[k] / (double)total);
      e[k] = 128;
    }
    a[3] = 0;
    e[3] = 128;
    return;
  }
  for (int k = 0; k < 3; k++) {
    a[k] = round_byte(col[k] / (double)covered);
    e[k] = round_byte(127.5 * (nrm[k] / (double)covered + 1.0));
  }
  a[3] = 255;
  e[3] = round_byte(depth / (double)covered);
}

/* The impostor's own atlases as their sizes say. */
static int is_impostor(const bbc_impostor *imp) {
  int n = imp->frame_size;
  return imp->frames >= 2 && n >= 1 && imp->albedo.rgba && imp->normal.rgba &&
         imp->albedo.width == imp->frames * n && imp->albedo.height == imp->frames * n &&
         imp->normal.width == imp->albedo.width && imp->normal.height == imp->albedo.height &&
         imp->half_extent > 0 && imp->radius > 0;
}

bbc_result bbc_impostor_level(const bbc_impostor *imp, int level, bbc_image *albedo,
                              bbc_image *normal, bbc_error *err) {
  assert(imp && albedo && normal);
  memset(albedo, 0, sizeof *albedo);
  memset(normal, 0, sizeof *normal);
  if (!is_impostor(imp))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor level: not an impostor's atlases");
  if (level < 0 || level >= bbc_impostor_level_count(imp))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor level %d: it has levels 0 to %d",
                     level, bbc_impostor_level_count(imp) - 1);
  int s = bbc_impostor_level_size(imp, level), n = imp->frames, W = n * s;
  if (bbc_image_alloc(albedo, W, W) != BBC_OK || bbc_image_alloc(normal, W, W) != BBC_OK) {
    bbc_image_free(albedo);
    bbc_image_free(normal);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "impostor level: out of memory");
  }
  if (level == 0) { /* the atlases themselves */
    memcpy(albedo->rgba, imp->albedo.rgba, 4 * (size_t)W * W);
    memcpy(normal->rgba, imp->normal.rgba, 4 * (size_t)W * W);
    return BBC_OK;
  }
  float *frac = malloc((size_t)s * s * sizeof *frac);
  uint8_t *on = malloc((size_t)s * s);
  if (!frac || !on) {
    free(frac);
    free(on);
    bbc_image_free(albedo);
    bbc_image_free(normal);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "impostor level: out of memory");
  }
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      for (int y = 0; y < s; y++)
        for (int x = 0; x < s; x++) {
          size_t o = 4 * ((size_t)(j * s + y) * W + (size_t)(i * s + x));
          level_texel(imp, i, j, x, y, s, albedo->rgba + o, normal->rgba + o, &frac[y * s + x]);
        }
      /* binary alpha keeping the frame's coverage whole (bbc__coverage_tree:
       * error diffusion made the far levels thinner) */
      bbc__coverage_tree(frac, s, s, s, on);
      for (int y = 0; y < s; y++)
        for (int x = 0; x < s; x++)
          albedo->rgba[4 * ((size_t)(j * s + y) * W + (size_t)(i * s + x)) + 3] =
              on[y * s + x] ? 255 : 0;
    }
  free(frac);
  free(on);
  return BBC_OK;
}

bbc_result bbc_impostor_render(const bbc_impostor *imp, const bbc_view *view, bbc_image *img,
                               bbc_error *err) {
  return bbc_impostor_render_level(imp, view, 0, img, err);
}

bbc_result bbc_impostor_render_level(const bbc_impostor *imp, const bbc_view *view, int level,
                                     bbc_image *img, bbc_error *err) {
  assert(imp && view && img);
  if (!img->rgba) return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "render: image not allocated");
  if (!is_impostor(imp))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "render: not an impostor's atlases");
  camera cam;
  bbc_result r = bbc__check_view(view, img->width, img->height, &cam, err);
  if (r != BBC_OK) return r;
  int top = bbc_impostor_level_count(imp) - 1;
  if (level < 0) { /* the level whose texels are nearest a pixel's size, as
                    * forest's shader picks it: round(log2(frame texels a pixel)) */
    double tpp = imp->frame_size / (fmin(cam.scale, cam.scale_y) * 2 * imp->half_extent);
    level = tpp > 1 ? (int)floor(log2(tpp) + 0.5) : 0;
  }
  if (level > top) level = top;
  bbc_image la = {0}, ln = {0};
  level_atlas lv = {&imp->albedo, &imp->normal, imp->frame_size};
  if (level > 0) {
    r = bbc_impostor_level(imp, level, &la, &ln, err);
    if (r != BBC_OK) return r;
    lv.albedo = &la;
    lv.normal = &ln;
    lv.size = bbc_impostor_level_size(imp, level);
  }
  frame_look fl[3];
  setup_frames(imp, &lv, &cam, fl);
  double l[3];
  light_dir(&cam, view, l);
  for (int py = 0; py < img->height; py++)
    for (int px = 0; px < img->width; px++) {
      uint8_t *o = img->rgba + 4 * ((size_t)py * img->width + px);
      /* the pixel's ray, on the plane through the impostor's centre across
       * the view, relative to the centre */
      double x = (px + 0.5 - cam.w2) / cam.scale, y = (cam.h2 - (py + 0.5)) / cam.scale_y, p0[3];
      for (int k = 0; k < 3; k++) p0[k] = cam.c[k] + x * cam.r[k] + y * cam.u[k] - imp->center[k];
      double along = vdot(vload(p0), vload(cam.f));
      for (int k = 0; k < 3; k++) p0[k] -= along * cam.f[k];
      texel_mix sum = {0, {0, 0, 0}, {0, 0, 0}};
      for (int k = 0; k < 3; k++) {
        if (!(fl[k].w > 0)) continue;
        texel_mix m;
        look_up(imp, &fl[k], p0, cam.f, &m);
        sum.a += fl[k].w * m.a;
        for (int c = 0; c < 3; c++) {
          sum.col[c] += fl[k].w * m.col[c];
          sum.n[c] += fl[k].w * m.n[c];
        }
      }
      /* The alpha test against an ordered dither's threshold instead of
       * 0.5: where the frames disagree (a leaf the parallax does not
       * align) the pixels covered are the blend's share, as alpha to
       * coverage gives, not only those most frames cover. */
      if (sum.a < (bayer[py & 3][px & 3] + 0.5) / 16.0) {
        memcpy(o, view->background, 4);
        continue;
      }
      double col[3], nn[3];
      for (int c = 0; c < 3; c++) col[c] = sum.col[c] / sum.a;
      /* the covered frames' mean normal, its length kept (at most 1): the
       * mean of Lambert's n.l over a texel's samples, not the brighter n.l
       * of their renormalised mean */
      double nl = 0;
      for (int c = 0; c < 3; c++) {
        nn[c] = sum.n[c] / sum.a;
        nl += nn[c] * nn[c];
      }
      if (nl > 1) vstore(nn, vnormalize(vload(nn))); /* a mean of zero stays zero */
      shade(view, l, nn, col, o);
    }
  bbc_image_free(&la);
  bbc_image_free(&ln);
  return BBC_OK;
}
