/* impostor.c — an octahedral impostor's frames (docs/impostors.md): the
 * model rendered orthographically from each frame direction of the grid
 * with the bake's rasterizer (unlit colour, normals, depth; k x k samples a
 * texel), brought down to texels with coverage-keeping binary alpha as a
 * billboard's images are (texels.c), and laid into two atlases. */
#include "cloud.h"
#include "raster.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One frame's supersampled images and what brings them to texels. */
typedef struct frame_work {
  bbc_image col, nm, depth; /* w x w samples, then s x s texels (depth: grey) */
  float *z;                 /* w x w sample depths */
  uint8_t *taps, *mask, *cand;
} frame_work;

static void work_free(frame_work *f) {
  bbc_image_free(&f->col);
  bbc_image_free(&f->nm);
  bbc_image_free(&f->depth);
  free(f->z);
  free(f->taps);
  free(f->mask);
  free(f->cand);
  memset(f, 0, sizeof *f);
}

static bbc_result work_alloc(frame_work *f, int w, int s) {
  memset(f, 0, sizeof *f);
  size_t n = (size_t)w * w, t = (size_t)s * s;
  if (bbc_image_alloc(&f->col, w, w) != BBC_OK || bbc_image_alloc(&f->nm, w, w) != BBC_OK ||
      bbc_image_alloc(&f->depth, s, s) != BBC_OK || !(f->z = malloc(n * sizeof *f->z)) ||
      !(f->taps = malloc(n)) || !(f->mask = malloc(t)) || !(f->cand = malloc(t))) {
    work_free(f);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  return BBC_OK;
}

/* Each texel's depth: the mean of its covered samples' (k x k), as
 * 255 (d / radius + 1) / 2, opaque where `mask` is. */
static void depth_texels(frame_work *f, int k, double radius) {
  int s = f->depth.width, w = s * k;
  for (int y = 0; y < s; y++)
    for (int x = 0; x < s; x++) {
      double sum = 0;
      int n = 0;
      for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
          size_t si = (size_t)(y * k + j) * w + (x * k + i);
          if (f->col.rgba[4 * si + 3] && f->z[si] < FLT_MAX) {
            sum += f->z[si];
            n++;
          }
        }
      uint8_t *d = f->depth.rgba + 4 * ((size_t)y * s + x);
      double v = n ? 127.5 * (sum / n / radius + 1.0) : 127.5;
      uint8_t b = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v + 0.5 > 255 ? 255 : v + 0.5);
      d[0] = d[1] = d[2] = b;
      d[3] = f->mask[(size_t)y * s + x] ? 255 : 0;
    }
}

typedef struct build_ctx {
  const bbc_mesh *mesh;
  bbc_impostor *imp;
  int samples;
} build_ctx;

/* Renders frame (i, j) into the atlases. */
static bbc_result build_frame(const build_ctx *c, int i, int j, frame_work *f, bbc_error *err) {
  bbc_impostor *imp = c->imp;
  int s = imp->frame_size, k = c->samples, w = s * k;
  size_t n = (size_t)w * w;
  memset(f->col.rgba, 0, 4 * n);
  memset(f->nm.rgba, 0, 4 * n);
  memset(f->taps, 0, n);
  double dir[3], right[3], up[3];
  bbc_impostor_frame_basis(imp, i, j, dir, right, up);
  bbc_view v;
  bbc_impostor_frame_view(imp, i, j, &v);
  bbc__bake bk;
  memset(&bk, 0, sizeof bk);
  bk.width = bk.height = w;
  bk.front = f->col.rgba;
  bk.front_nm = f->nm.rgba;
  bk.front_depth = f->z;
  bk.up[(int)imp->up] = 1;
  bk.colour_taps = k < 4;
  bk.taps[0] = bk.colour_taps ? f->taps : NULL;
  bbc_result r;
  if (c->mesh->kind == BBC_MESH_POINTS) {
    /* splats as step 3's: 3.5 pixels of a 256-pixel picture of the model */
    double px = 3.5 * (2 * imp->radius / 256.0) * (w / (2 * imp->half_extent));
    r = bbc__render_splats(c->mesh, NULL, c->mesh->vertex_count, &v, &bk, px < 1 ? 1 : px, 1, err);
    /* splats carry no normal: each covered sample faces the frame's viewer */
    for (size_t q = 0; r == BBC_OK && q < n; q++)
      if (f->col.rgba[4 * q + 3]) {
        uint8_t *e = f->nm.rgba + 4 * q;
        e[0] = e[1] = 128;
        e[2] = e[3] = 255;
      }
  } else {
    r = bbc__render_bake(c->mesh, NULL, 0, &v, &bk, err);
  }
  if (r != BBC_OK) return r;
  r = bbc__alpha_mask(&f->col, bk.taps[0], k, 1, 1, f->mask, f->cand);
  if (r == BBC_OK) depth_texels(f, k, imp->radius);
  /* the texels' own images (downsample replaces them by s x s ones) */
  bbc_image col = f->col, nm = f->nm;
  memset(&f->col, 0, sizeof f->col);
  memset(&f->nm, 0, sizeof f->nm);
  if (r == BBC_OK) r = bbc__downsample_masked(&nm, k, 2, f->mask);
  if (r == BBC_OK) r = bbc__downsample_masked(&col, k, 0, f->mask);
  if (r == BBC_OK) r = bbc__fill_transparent(&col);
  if (r == BBC_OK) r = bbc__fill_transparent(&nm);
  if (r == BBC_OK) r = bbc__fill_transparent(&f->depth);
  if (r == BBC_OK) {
    int W = imp->albedo.width;
    for (int y = 0; y < s; y++)
      for (int x = 0; x < s; x++) {
        size_t t = (size_t)y * s + x, o = (size_t)(j * s + y) * W + (size_t)(i * s + x);
        memcpy(imp->albedo.rgba + 4 * o, col.rgba + 4 * t, 4);
        /* the image's frame (x right, y up, z towards the viewer) to the model's */
        const uint8_t *e = nm.rgba + 4 * t;
        double a = e[0] / 127.5 - 1, b = e[1] / 127.5 - 1, z = e[2] / 127.5 - 1, m[3], len = 0;
        for (int q = 0; q < 3; q++) {
          m[q] = a * right[q] + b * up[q] + z * dir[q];
          len += m[q] * m[q];
        }
        len = sqrt(len);
        uint8_t *d = imp->normal.rgba + 4 * o;
        double keep = len > 1 ? len : 1; /* the mean normal's length kept (at most 1) */
        for (int q = 0; q < 3; q++) {
          double u = 127.5 * ((len > 1e-9 ? m[q] / keep : dir[q]) + 1.0);
          d[q] = (uint8_t)(u < 0 ? 0 : u + 0.5 > 255 ? 255 : u + 0.5);
        }
        d[3] = f->depth.rgba[4 * t];
      }
  }
  bbc_image_free(&col);
  bbc_image_free(&nm);
  if (r != BBC_OK) return bbc__fail(err, r, "impostor: out of memory");
  /* ready for the next frame: full-size images again */
  r = bbc_image_alloc(&f->col, w, w);
  if (r == BBC_OK) r = bbc_image_alloc(&f->nm, w, w);
  if (r != BBC_OK) return bbc__fail(err, r, "impostor: out of memory");
  return BBC_OK;
}

/* The options' zeros made their defaults, checked; the frame size from the
 * texel budget. */
static bbc_result resolve(const bbc_impostor_options *in, bbc_impostor_options *o, int *frame_size,
                          bbc_error *err) {
  if (in)
    *o = *in;
  else
    bbc_impostor_options_default(o);
  if (!o->frames) o->frames = 8;
  if (!o->texels) o->texels = 1 << 20;
  if (!o->samples) o->samples = 4;
  if (o->frames < 2 || o->frames > 64)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor: frames must be 2..64 (got %d)",
                     o->frames);
  if (o->samples < 1 || o->samples > 4)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor: samples must be 1..4 (got %d)",
                     o->samples);
  if (o->texels < 0 || o->texels > (1LL << 28))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "impostor: texels must be at most 268435456 (got %lld)", o->texels);
  long long side = (long long)sqrt((double)o->texels);
  while (side * side > o->texels) side--;
  while ((side + 1) * (side + 1) <= o->texels) side++;
  *frame_size = (int)(side / o->frames);
  if (*frame_size < 8)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "impostor: %lld texels leave %d x %d frames under 8 texels a side "
                     "(at least %lld texels)",
                     o->texels, o->frames, o->frames, 64LL * o->frames * o->frames);
  return BBC_OK;
}

bbc_result bbc_impostor_build(const bbc_mesh *mesh, const bbc_impostor_options *options,
                              bbc_impostor *imp, bbc_error *err) {
  assert(mesh && imp);
  memset(imp, 0, sizeof *imp);
  bbc_impostor_options o;
  int s;
  bbc_result r = resolve(options, &o, &s, err);
  if (r != BBC_OK) return r;
  if (mesh->vertex_count == 0 || (mesh->kind == BBC_MESH_TRIANGLES && mesh->triangle_count == 0))
    return bbc__fail(err, BBC_ERROR_EMPTY, "impostor: the model is empty");
  imp->frames = o.frames;
  imp->hemi = !o.full;
  imp->frame_size = s;
  imp->padding = s >= 64 ? s / 32 : 1;
  imp->up = bbc_up_axis(o.up);
  double r2 = 0;
  for (int a = 0; a < 3; a++) imp->center[a] = 0.5 * (mesh->bbox_min[a] + mesh->bbox_max[a]);
  for (size_t q = 0; q < mesh->vertex_count; q++) {
    const double *p = mesh->positions + 3 * q;
    double d2 = 0;
    for (int a = 0; a < 3; a++) d2 += (p[a] - imp->center[a]) * (p[a] - imp->center[a]);
    if (d2 > r2) r2 = d2;
  }
  imp->radius = r2 > 0 ? sqrt(r2) : 1.0;
  imp->half_extent = imp->radius * s / (s - 2.0 * imp->padding);
  int side = s * o.frames;
  if (bbc_image_alloc(&imp->albedo, side, side) != BBC_OK ||
      bbc_image_alloc(&imp->normal, side, side) != BBC_OK) {
    bbc_impostor_free(imp);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "impostor: out of memory for %d x %d atlases",
                     side, side);
  }
  build_ctx c = {mesh, imp, o.samples};
  int nf = o.frames * o.frames, failed = 0;
  bbc_error first;
  memset(&first, 0, sizeof first);
#pragma omp parallel num_threads(bbc__thread_count(o.threads))
  {
    frame_work f;
    int ok = work_alloc(&f, s * o.samples, s) == BBC_OK;
#pragma omp for schedule(dynamic, 1)
    for (int q = 0; q < nf; q++) {
      bbc_error e;
      memset(&e, 0, sizeof e);
      if (ok && build_frame(&c, q % o.frames, q / o.frames, &f, &e) == BBC_OK) continue;
      if (!ok) bbc__fail(&e, BBC_ERROR_OUT_OF_MEMORY, "impostor: out of memory");
      ok = 0; /* a failed frame may leave this thread's images freed */
#pragma omp critical(bbc_impostor_fail)
      if (!failed || q < failed - 1) { /* the first frame's error, whatever the threads */
        first = e;
        failed = q + 1;
      }
    }
    work_free(&f);
  }
  if (failed) {
    bbc_impostor_free(imp);
    if (err) *err = first;
    return first.code ? first.code : BBC_ERROR_OUT_OF_MEMORY;
  }
  return BBC_OK;
}
