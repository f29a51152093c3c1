/* test_cloud.c — step 3: baking with analytic answers (texel-centre
 * coverage, small leaves surviving supersampling, front/back images, normal
 * maps), voxel shadowing, and the cloud of a real tree: outlines on their
 * planes inside the model's bounds + epsilon, disjoint atlas rectangles,
 * binary alpha, determinism across thread counts, glTF round trip. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#ifdef _OPENMP
#include <omp.h>
#endif
#include "test_util.h"

/* ---- a small hand-built scene ------------------------------------------- */

typedef struct scene {
  bbc_mesh m;
  bbc_planeset s;
} scene;

/* Material 0: invisible (alpha 0) frame; 1: red; 2: blue; all opaque but 0. */
static void scene_begin(scene *sc, size_t max_tris) {
  static const float col[3][4] = {{1, 1, 1, 0}, {1, 0, 0, 1}, {0, 0, 1, 1}};
  static const char *const names[3] = {"frame", "red", "blue"};
  memset(sc, 0, sizeof *sc);
  tu_mesh_begin(&sc->m, max_tris, 3, names, col, "g");
}

static void scene_tri(scene *sc, const double *a, const double *b, const double *c,
                      uint32_t material) {
  tu_mesh_tri(&sc->m, a, b, c, material);
}

/* The unit square [0,1]^2 at z = 0, invisible: it fixes the billboard. */
static void scene_frame(scene *sc) {
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  scene_tri(sc, p[0], p[1], p[2], 0);
  scene_tri(sc, p[0], p[2], p[3], 0);
}

/* Finishes the mesh and one plane z = 0 (normal +z) holding every face. */
static void scene_end(scene *sc, double eps) {
  bbc_error err;
  if (bbc_mesh_finalize(&sc->m, 0, "scene", &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_planeset *s = &sc->s;
  size_t nf = sc->m.triangle_count;
  s->radius = sc->m.radius;
  s->epsilon_abs = eps;
  s->plane_count = 1;
  s->planes = calloc(1, sizeof *s->planes);
  s->planes[0].normal[2] = 1;
  s->planes[0].kind = BBC_PLANE_STANDARD;
  s->planes[0].face_count = nf;
  s->planes[0].area = 1;
  s->planes[0].mother = -1;
  s->planes[0].coverage_pct = 100;
  s->face_count = nf;
  s->face_plane = calloc(nf, sizeof *s->face_plane);
  s->face_part = calloc(nf, sizeof *s->face_part);
  s->part_count = 1;
  s->parts = calloc(1, sizeof *s->parts);
  strcpy(s->parts[0].name, "all");
  s->parts[0].epsilon_abs = eps;
  s->parts[0].face_count = nf;
  s->parts[0].plane_count = 1;
}

static void scene_free(scene *sc) {
  bbc_mesh_free(&sc->m);
  bbc_planeset_free(&sc->s);
}

static void params_for(bbc_params *p, int texres, int quality) {
  bbc_params_default(p);
  p->texres = texres;
  p->atlas_max = 0; /* texres as set */
  p->quality = quality;
  p->prelight = 0;
  p->occlusion = 0; /* the tests below turn maps on one at a time */
  p->nm_bend = 0;
  p->normal_maps = 0;
  p->threads = 1;
  p->soft_alpha = 0; /* masks as baked: alpha 0 or 255 (test_soft_alpha) */
}

/* The atlas texel showing model point q on billboard b (front or back). */
static const uint8_t *texel_at(const bbc_cloud *c, const bbc_cloud_billboard *b, int back,
                               const double *q) {
  const bbc_billboard *r = &b->rect;
  double d[3] = {q[0] - r->origin[0], q[1] - r->origin[1], q[2] - r->origin[2]};
  double s = (d[0] * r->u[0] + d[1] * r->u[1] + d[2] * r->u[2]) / r->width;
  double t = (d[0] * r->w[0] + d[1] * r->w[1] + d[2] * r->w[2]) / r->height;
  const bbc_atlas_rect *rc = back ? &b->back : &b->front;
  int x = (int)floor(s * rc->width), y = (int)floor((1 - t) * rc->height);
  assert_true(x >= 0 && x < rc->width && y >= 0 && y < rc->height);
  const bbc_image *a = &c->mesh.textures[0].image;
  return a->rgba + 4 * ((size_t)(rc->y + y) * a->width + rc->x + x);
}

/* Signed distance-like test: > 0 inside triangle abc (2D, counter-clockwise). */
static double inside2(const double *a, const double *b, const double *c, double x, double y) {
  double e0 = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
  double e1 = (c[0] - b[0]) * (y - b[1]) - (c[1] - b[1]) * (x - b[0]);
  double e2 = (a[0] - c[0]) * (y - c[1]) - (a[1] - c[1]) * (x - c[0]);
  return fmin(e0, fmin(e1, e2));
}

static void test_texel_centres_quality0(void **state) {
  (void)state;
  scene sc;
  scene_begin(&sc, 8);
  scene_frame(&sc);
  const double a[3] = {0.137, 0.081, 0.001}, b[3] = {0.913, 0.347, 0.001},
               c[3] = {0.402, 0.871, 0.001};
  scene_tri(&sc, a, b, c, 1);
  scene_end(&sc, 0.01);
  bbc_params p;
  params_for(&p, 32, 0);
  p.back_images = 0;
  bbc_cloud cl;
  bbc_error err;
  if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(cl.billboard_count, 1);
  const bbc_cloud_billboard *bb = &cl.billboards[0];
  assert_int_equal(bb->tex_width, 32);
  assert_int_equal(bb->tex_height, 32);
  assert_int_equal(bb->front.width, 32);
  size_t red = 0, expected = 0;
  for (int j = 0; j < 32; j++)
    for (int i = 0; i < 32; i++) {
      double q[3] = {(i + 0.5) / 32, (j + 0.5) / 32, 0};
      double in = inside2(a, b, c, q[0], q[1]);
      const uint8_t *t = texel_at(&cl, bb, 0, q);
      if (fabs(in) < 1e-9) continue; /* on an edge: either answer is right */
      if (in > 0) {
        expected++;
        assert_true(t[3] == 255 && t[0] == 255 && t[1] == 0 && t[2] == 0);
        red++;
      } else {
        assert_int_equal(t[3], 0);
      }
    }
  assert_true(expected > 100 && red == expected);
  /* One double-sided outline without back images. */
  assert_int_equal(cl.mesh.materials[0].single_sided, 0);
  assert_int_equal(cl.mesh.triangle_count, (size_t)bb->corner_count - 2);
  bbc_cloud_free(&cl);
  scene_free(&sc);
}

/* A leaf 0.2 texels across around a sample position of texel (5, 9) of a
 * 16-texel grid, away from the texel centre, at `samples` a texel side:
 * quality 0 loses it, quality 2 grows it into its texel. */
static void small_leaf_survives(int samples) {
  scene sc;
  scene_begin(&sc, 8);
  scene_frame(&sc);
  const int N = 16;
  double off = samples == 4 ? 0.375 : 0.25; /* a sample's centre, not the texel's */
  double cx = (5 + off) / N, cy = (9 + off) / N, r = 0.1 / N;
  const double a[3] = {cx - r, cy - r, 0.002}, b[3] = {cx + r, cy - r, 0.002},
               c[3] = {cx, cy + r, 0.002};
  scene_tri(&sc, a, b, c, 2);
  scene_end(&sc, 0.01);
  const double q[3] = {cx, cy, 0};
  for (int quality = 0; quality <= 2; quality += 2) {
    bbc_params p;
    params_for(&p, N, quality);
    p.samples = samples;
    p.dither = 0; /* the thesis's growing */
    p.refine = 0; /* the mask as baked */
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    const bbc_cloud_billboard *bb = &cl.billboards[0];
    assert_int_equal(bb->front.width, N);
    const uint8_t *t = texel_at(&cl, bb, 0, q);
    if (quality == 0) {
      assert_int_equal(t[3], 0); /* lost: it covers no texel centre */
    } else {
      assert_int_equal(t[3], 255); /* grown: one of its samples is opaque */
      assert_true(t[2] == 255 && t[0] == 0);
    }
    /* Alpha stays binary in the whole atlas. */
    const bbc_image *at = &cl.mesh.textures[0].image;
    size_t opaque = 0;
    for (size_t i = 0; i < (size_t)at->width * at->height; i++) {
      uint8_t al = at->rgba[4 * i + 3];
      assert_true(al == 0 || al == 255);
      opaque += al == 255;
    }
    /* Front and back each show the leaf in exactly one texel. */
    assert_int_equal(opaque, quality ? 2 : 0);
    bbc_cloud_free(&cl);
  }
  scene_free(&sc);
}

static void test_small_leaf_survives_quality2(void **state) {
  (void)state;
  small_leaf_survives(4);
  small_leaf_survives(2);
}

/* 256 leaves, each 0.2 texels across on one of the samples of its own
 * texel of a 16 x 16 grid (1/16 of the texel's samples at 4 a side, 1/4 at
 * 2), and one solid 4 x 4-texel leaf. Growing makes every small leaf a full
 * texel (16x or 4x the density); dithering keeps about 1/16 or 1/4 of them,
 * and the solid leaf whole. */
static void dither_keeps_density(int samples) {
  const int N = 16;
  double off = samples == 4 ? 0.375 : 0.25;
  scene sc;
  scene_begin(&sc, 2 + (size_t)N * N + 2);
  scene_frame(&sc);
  for (int ty = 0; ty < N; ty++)
    for (int tx = 0; tx < N; tx++) {
      if (tx >= 2 && tx < 6 && ty >= 2 && ty < 6) continue; /* the solid leaf's texels */
      double cx = (tx + off) / N, cy = (ty + off) / N, r = 0.1 / N;
      const double a[3] = {cx - r, cy - r, 0.002}, b[3] = {cx + r, cy - r, 0.002},
                   c[3] = {cx, cy + r, 0.002};
      scene_tri(&sc, a, b, c, 2);
    }
  const double s0[3] = {2.0 / N, 2.0 / N, 0.001}, s1[3] = {6.0 / N, 2.0 / N, 0.001},
               s2[3] = {6.0 / N, 6.0 / N, 0.001}, s3[3] = {2.0 / N, 6.0 / N, 0.001};
  scene_tri(&sc, s0, s1, s2, 1);
  scene_tri(&sc, s0, s2, s3, 1);
  scene_end(&sc, 0.01);
  size_t small_leaves = (size_t)N * N - 16, opaque[2] = {0, 0}, solid[2] = {0, 0};
  for (int dither = 0; dither < 2; dither++) {
    bbc_params p;
    params_for(&p, N, 2);
    p.samples = samples;
    p.dither = dither;
    p.refine = 0; /* the mask as baked */
    p.back_images = 0;
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    const bbc_cloud_billboard *bb = &cl.billboards[0];
    assert_int_equal(bb->front.width, N);
    for (int ty = 0; ty < N; ty++)
      for (int tx = 0; tx < N; tx++) {
        const double q[3] = {(tx + 0.5) / N, (ty + 0.5) / N, 0};
        const uint8_t *t = texel_at(&cl, bb, 0, q);
        assert_true(t[3] == 0 || t[3] == 255);
        int in_solid = tx >= 2 && tx < 6 && ty >= 2 && ty < 6;
        if (in_solid)
          solid[dither] += t[3] == 255;
        else
          opaque[dither] += t[3] == 255;
      }
    bbc_cloud_free(&cl);
  }
  size_t share = (size_t)(samples * samples);
  printf("%d samples a side: small leaves %zu: opaque texels growing %zu, dithering %zu; solid "
         "%zu, %zu of 16\n",
         samples, small_leaves, opaque[0], opaque[1], solid[0], solid[1]);
  assert_int_equal(opaque[0], small_leaves);
  assert_true(opaque[1] >= small_leaves / share - 4 && opaque[1] <= small_leaves / share + 4);
  assert_int_equal(solid[0], 16);
  assert_int_equal(solid[1], 16);
  scene_free(&sc);
}

static void test_dither_keeps_density(void **state) {
  (void)state;
  dither_keeps_density(4);
  dither_keeps_density(2);
}

/* A quad textured with a checker of one texture pixel, 4 x 4 cells a
 * cloud texel (red and blue): at 4 samples a texel side the texel's 16
 * samples average it (purple); at 2, each sample's colour is the mean of 4
 * texture points (at 4 x 4 points a texel in all), so the texel averages
 * it too, where 4 point samples would all fall on one colour. */
static void test_samples_average_texture(void **state) {
  (void)state;
  const int N = 16, T = 4 * N;
  for (int samples = 4; samples >= 2; samples -= 2) {
    scene sc;
    scene_begin(&sc, 4);
    scene_frame(&sc);
    const double q0[3] = {0, 0, 0.001}, q1[3] = {1, 0, 0.001}, q2[3] = {1, 1, 0.001},
                 q3[3] = {0, 1, 0.001};
    scene_tri(&sc, q0, q1, q2, 1);
    scene_tri(&sc, q0, q2, q3, 1);
    bbc_mesh *m = &sc.m;
    m->uvs = calloc(2 * m->vertex_count, sizeof *m->uvs);
    for (size_t v = 6; v < m->vertex_count; v++)
      for (int k = 0; k < 2; k++) m->uvs[2 * v + k] = (float)m->positions[3 * v + k];
    m->textures = calloc(1, sizeof *m->textures);
    m->texture_count = 1;
    assert_int_equal(bbc_image_alloc(&m->textures[0].image, T, T), BBC_OK);
    for (int y = 0; y < T; y++)
      for (int x = 0; x < T; x++) {
        uint8_t *px = m->textures[0].image.rgba + 4 * ((size_t)y * T + x);
        int red = (x + y) % 2 == 0;
        px[0] = red ? 255 : 0;
        px[2] = red ? 0 : 255;
        px[3] = 255;
      }
    m->materials[1].texture = 0;
    const float white[4] = {1, 1, 1, 1};
    memcpy(m->materials[1].base_color, white, sizeof white);
    scene_end(&sc, 0.01);
    bbc_params p;
    params_for(&p, N, 2);
    p.samples = samples;
    p.refine = 0;
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    const bbc_cloud_billboard *bb = &cl.billboards[0];
    const double q[3] = {3.5 / N, 11.5 / N, 0}; /* away from the quad's diagonal */
    const uint8_t *t = texel_at(&cl, bb, 0, q);
    printf("%d samples a side: the checker's texel %d %d %d\n", samples, t[0], t[1], t[2]);
    assert_int_equal(t[3], 255);
    assert_true(abs((int)t[0] - 128) <= 16 && abs((int)t[2] - 128) <= 16);
    bbc_cloud_free(&cl);
    scene_free(&sc);
  }
}

/* The share of billboard 0's front image (N x N texels over [0, 1]^2)
 * that a client's bilinear filter and alpha test at 0.5 shows (8 x 8
 * points a texel), against the texels opaque to nearest sampling. */
static double bilinear_share(const bbc_cloud *cl, int N, size_t *nearest) {
  const bbc_image *at = &cl->mesh.textures[0].image;
  const bbc_atlas_rect *rc = &cl->billboards[0].front;
  size_t shown = 0;
  *nearest = 0;
  for (int y = 0; y < rc->height; y++)
    for (int x = 0; x < rc->width; x++)
      *nearest += at->rgba[4 * ((size_t)(rc->y + y) * at->width + rc->x + x) + 3] >= 128;
  for (int y = 0; y < 8 * rc->height; y++)
    for (int x = 0; x < 8 * rc->width; x++) {
      double fx = (x + 0.5) / 8 - 0.5, fy = (y + 0.5) / 8 - 0.5;
      int x0 = (int)floor(fx), y0 = (int)floor(fy);
      double tx = fx - x0, ty = fy - y0, al = 0;
      for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
          int xx = rc->x + x0 + i, yy = rc->y + y0 + j; /* the atlas's gutter is transparent */
          double wgt = (i ? tx : 1 - tx) * (j ? ty : 1 - ty);
          al += wgt * at->rgba[4 * ((size_t)yy * at->width + xx) + 3];
        }
      shown += al >= 127.5;
    }
  (void)N;
  return (double)shown / 64.0 / (double)(*nearest ? *nearest : 1);
}

/* softalpha: isolated opaque texels (every other texel of every other row:
 * a sparse, dithered crown) keep their area under a client's bilinear alpha
 * test (0.61 of it with alpha 0 and 255), and the mask nearest sampling
 * sees is the same. */
static void test_soft_alpha(void **state) {
  (void)state;
  const int N = 32;
  scene sc;
  scene_begin(&sc, 2 + (size_t)N * N / 2);
  scene_frame(&sc);
  for (int ty = 1; ty < N - 1; ty += 2)
    for (int tx = 1; tx < N - 1; tx += 2) {
      const double a[3] = {(double)tx / N, (double)ty / N, 0.002},
                   b[3] = {(tx + 1.0) / N, (double)ty / N, 0.002},
                   c[3] = {(tx + 1.0) / N, (ty + 1.0) / N, 0.002},
                   d[3] = {(double)tx / N, (ty + 1.0) / N, 0.002};
      scene_tri(&sc, a, b, c, 2);
      scene_tri(&sc, a, c, d, 2);
    }
  scene_end(&sc, 0.01);
  double share[2];
  size_t nearest[2];
  uint8_t *mask[2];
  for (int k = 0; k < 2; k++) {
    bbc_params p;
    params_for(&p, N, 2);
    p.samples = 4;
    p.refine = 0;
    p.back_images = 0;
    p.soft_alpha = k;
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    share[k] = bilinear_share(&cl, N, &nearest[k]);
    const bbc_image *at = &cl.mesh.textures[0].image;
    mask[k] = malloc((size_t)at->width * at->height);
    for (size_t i = 0; i < (size_t)at->width * at->height; i++)
      mask[k][i] = at->rgba[4 * i + 3] >= 128;
    if (k) assert_memory_equal(mask[0], mask[1], (size_t)at->width * at->height);
    bbc_cloud_free(&cl);
  }
  printf("isolated texels %zu: bilinear alpha test shows %.3f of them at 0/255, %.3f softened\n",
         nearest[0], share[0], share[1]);
  assert_true(nearest[0] >= 150 && nearest[0] == nearest[1]);
  assert_true(share[0] < 0.7);
  assert_true(share[1] > 0.9 && share[1] < 1.1);
  free(mask[0]);
  free(mask[1]);
  scene_free(&sc);
}

static void test_front_and_back(void **state) {
  (void)state;
  scene sc;
  scene_begin(&sc, 8);
  scene_frame(&sc);
  /* Red in front (+z side) over the left half, blue behind over all. */
  const double r0[3] = {0.05, 0.05, 0.004}, r1[3] = {0.45, 0.05, 0.004},
               r2[3] = {0.05, 0.95, 0.004};
  const double b0[3] = {0.02, 0.02, -0.004}, b1[3] = {0.98, 0.02, -0.004},
               b2[3] = {0.02, 0.98, -0.004};
  scene_tri(&sc, r0, r1, r2, 1);
  scene_tri(&sc, b0, b1, b2, 2);
  scene_end(&sc, 0.01);
  bbc_params p;
  params_for(&p, 64, 0);
  p.normal_maps = 1;
  bbc_cloud cl;
  bbc_error err;
  if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
  const bbc_cloud_billboard *bb = &cl.billboards[0];
  const double both[3] = {0.15, 0.15, 0}, blue_only[3] = {0.6, 0.2, 0}, none[3] = {0.9, 0.9, 0};
  const uint8_t *f = texel_at(&cl, bb, 0, both), *k = texel_at(&cl, bb, 1, both);
  assert_true(f[3] == 255 && f[0] == 255 && f[2] == 0); /* front: red */
  assert_true(k[3] == 255 && k[2] == 255 && k[0] == 0); /* back: blue */
  f = texel_at(&cl, bb, 0, blue_only);
  k = texel_at(&cl, bb, 1, blue_only);
  assert_true(f[3] == 255 && f[2] == 255 && k[3] == 255 && k[2] == 255);
  assert_int_equal(texel_at(&cl, bb, 0, none)[3], 0);
  assert_int_equal(texel_at(&cl, bb, 1, none)[3], 0);
  /* Two one-sided copies of the outline, facing opposite ways. */
  assert_int_equal(cl.mesh.materials[0].single_sided, 1);
  assert_int_equal(cl.mesh.triangle_count, 2 * ((size_t)bb->corner_count - 2));
  const float *n0 = cl.mesh.normals, *n1 = cl.mesh.normals + 3 * (size_t)bb->corner_count;
  assert_true(n0[2] > 0.99f && n1[2] < -0.99f);
  /* The normal maps: faces parallel to the plane give (0, 0, 1) facing
   * each image's viewer. */
  assert_int_equal(cl.mesh.texture_count, 2);
  assert_int_equal(cl.mesh.materials[0].normal_map, 2);
  assert_non_null(cl.mesh.tangents);
  const bbc_image *nm = &cl.mesh.textures[1].image;
  for (int back = 0; back < 2; back++) {
    const uint8_t *t = nm->rgba + (texel_at(&cl, bb, back, both) - cl.mesh.textures[0].image.rgba);
    assert_int_equal(t[3], 255);
    assert_true(abs(t[0] - 128) <= 1 && abs(t[1] - 128) <= 1 && t[2] == 255);
  }
  bbc_cloud_free(&cl);
  /* backface: each image shows only faces wound towards its viewer. Both
   * triangles are counter-clockwise seen from +z: the back image is empty. */
  p.backface = 1;
  p.normal_maps = 0;
  if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
  bb = &cl.billboards[0];
  assert_int_equal(texel_at(&cl, bb, 0, both)[0], 255);
  assert_int_equal(texel_at(&cl, bb, 1, both)[3], 0);
  bbc_cloud_free(&cl);
  scene_free(&sc);
}

/* The default maps (issue 31): the occlusion atlas beside the normal atlas
 * in the same layout, grey within [occlusionmin, 1]; normals bent away from
 * the crown's centre by nmbend; transparent texels carrying the colour of
 * their opaque neighbours (alpha 0). */
static void test_material_maps(void **state) {
  (void)state;
  scene sc;
  scene_begin(&sc, 8);
  scene_frame(&sc);
  const double r0[3] = {0.05, 0.05, 0.004}, r1[3] = {0.45, 0.05, 0.004},
               r2[3] = {0.05, 0.95, 0.004};
  scene_tri(&sc, r0, r1, r2, 1);
  scene_end(&sc, 0.01);
  bbc_params p;
  params_for(&p, 64, 0);
  p.normal_maps = 1;
  p.occlusion = 16;
  p.occlusion_min = 0.5;
  p.nm_bend = 1;
  bbc_cloud cl;
  bbc_error err;
  if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
  const bbc_cloud_billboard *bb = &cl.billboards[0];
  assert_int_equal(cl.mesh.texture_count, 3);
  assert_int_equal(cl.mesh.materials[0].normal_map, 2);
  assert_int_equal(cl.mesh.materials[0].occlusion_map, 3);
  const bbc_image *col = &cl.mesh.textures[0].image, *nm = &cl.mesh.textures[1].image,
                  *ao = &cl.mesh.textures[2].image;
  assert_true(ao->width == col->width && ao->height == col->height);
  const double q[3] = {0.1, 0.1, 0}, none[3] = {0.9, 0.9, 0};
  const uint8_t *c = texel_at(&cl, bb, 0, q);
  assert_true(c[3] == 255 && c[0] == 255);
  size_t off = (size_t)(c - col->rgba);
  const uint8_t *a = ao->rgba + off, *n = nm->rgba + off;
  assert_true(a[0] == a[1] && a[1] == a[2] && a[0] >= 127 && a[3] == 255);
  /* Bent: the centre of the faces' bounds is (0.5, 0.5, 0), so this texel's
   * normal leans to -x and -y, half way (nmbend 1 adds a unit vector). */
  double tn[3], w[3];
  for (int k = 0; k < 3; k++) tn[k] = n[k] / 127.5 - 1.0;
  for (int k = 0; k < 3; k++)
    w[k] = tn[0] * bb->rect.u[k] + tn[1] * bb->rect.w[k] + tn[2] * bb->normal[k];
  const double want[3] = {-0.5, -0.5, 0.7071};
  for (int k = 0; k < 3; k++)
    if (fabs(w[k] - want[k]) > 0.03) fail_msg("bent normal %.3f %.3f %.3f", w[0], w[1], w[2]);
  /* Far from the red face: transparent, coloured red all the same. */
  const uint8_t *e = texel_at(&cl, bb, 0, none);
  assert_int_equal(e[3], 0);
  assert_int_equal(e[0], 255);
  bbc_cloud_free(&cl);
  scene_free(&sc);
}

static void test_tilted_normal_map(void **state) {
  (void)state;
  scene sc;
  scene_begin(&sc, 8);
  scene_frame(&sc);
  /* A face tilted 0.5 degrees about y; its normal n = (-sin, 0, cos). */
  double ang = 0.5 * 3.14159265358979323846 / 180, sl = tan(ang);
  const double a[3] = {0.1, 0.1, 0.1 * sl}, b[3] = {0.9, 0.1, 0.9 * sl},
               c[3] = {0.1, 0.9, 0.1 * sl};
  scene_tri(&sc, a, b, c, 1);
  scene_end(&sc, 0.02);
  bbc_params p;
  params_for(&p, 32, 0);
  p.normal_maps = 1;
  bbc_cloud cl;
  bbc_error err;
  if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
  const bbc_cloud_billboard *bb = &cl.billboards[0];
  const bbc_image *nm = &cl.mesh.textures[1].image;
  const double q[3] = {0.3, 0.3, 0};
  const uint8_t *col = texel_at(&cl, bb, 0, q);
  assert_int_equal(col[3], 255);
  const uint8_t *t = nm->rgba + (col - cl.mesh.textures[0].image.rgba);
  double tn[3], n[3];
  for (int k = 0; k < 3; k++) tn[k] = t[k] / 127.5 - 1.0;
  for (int k = 0; k < 3; k++)
    n[k] = tn[0] * bb->rect.u[k] + tn[1] * bb->rect.w[k] + tn[2] * bb->normal[k];
  double expect[3] = {-sin(ang), 0, cos(ang)};
  for (int k = 0; k < 3; k++) assert_true(fabs(n[k] - expect[k]) < 0.012);
  bbc_cloud_free(&cl);
  scene_free(&sc);
}

static void test_voxel_shading(void **state) {
  (void)state;
  /* A dense layer of small faces above a lone face: the lone face is in
   * shadow (ambient), the layer's top stays lit. */
  scene sc;
  scene_begin(&sc, 402);
  for (int i = 0; i < 400; i++) {
    double x = (i % 20) / 20.0, z = (i / 20) / 20.0;
    const double a[3] = {x, 1.0, z}, b[3] = {x + 0.04, 1.0, z}, c[3] = {x, 1.0, z + 0.04};
    scene_tri(&sc, a, b, c, 1);
  }
  const double a[3] = {0.5, 0.8, 0.5}, b[3] = {0.54, 0.8, 0.5}, c[3] = {0.5, 0.8, 0.54};
  scene_tri(&sc, a, b, c, 1);
  bbc_error err;
  if (bbc_mesh_finalize(&sc.m, 0, "scene", &err) != BBC_OK) fail_msg("%s", err.message);
  float *sh = malloc(sc.m.vertex_count * sizeof *sh);
  assert_int_equal(bbc_shade_vertices(&sc.m, 20, 0.4, 1, sh, &err), BBC_OK);
  for (size_t v = 0; v < 1200; v++) assert_true(sh[v] > 0.99f); /* nothing above */
  for (size_t v = 1200; v < 1203; v++) assert_true(sh[v] < 0.5f && sh[v] >= 0.4f - 1e-6f);
  assert_int_equal(bbc_shade_vertices(&sc.m, 0, 0.4, 1, sh, &err), BBC_ERROR_INVALID_ARGUMENT);
  free(sh);
  scene_free(&sc);
}

/* Refinement against renders of the original (refine.c): on an airy
 * generated tree (larch: needles on thin twigs) the cloud's side-view
 * coverage comes closer to the original's, within 0.85-1.15 and its block
 * IoU (the tree seen 8x farther away) rises; the views the refinement used
 * are not eval's; the result is the same with one thread or two. */
/* A cancel callback: answers yes from its n-th question on. */
static int cancel_after(void *user) {
  int *n = user;
  return --*n <= 0;
}

/* Steps 1 to 3 stop when the caller's cancel callback asks, free what they
 * made (ASan checks) and say BBC_ERROR_CANCELLED; without it, the same run
 * finishes. */
static void test_cancel(void **state) {
  (void)state;
  bbc_tree_options to;
  bbc_tree_options_default(&to);
  to.seed = 1; /* the tree these checks were written for */
  to.leaves = 3000;
  bbc_mesh m;
  bbc_error err;
  if (bbc_tree_generate(&to, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_planeset s;
  for (int after = 1; after <= 3; after++) { /* at the grid, then during selection */
    int n = after;
    o.callbacks.cancel = cancel_after;
    o.callbacks.user = &n;
    assert_int_equal(bbc_planes_find(&m, &o, &s, &err), BBC_ERROR_CANCELLED);
    assert_int_equal(err.code, BBC_ERROR_CANCELLED);
    assert_null(s.planes);
  }
  o.callbacks.cancel = NULL;
  if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_cloud c;
  for (int after = 1; after <= 4; after += 3) {
    int n = after;
    bbc_callbacks cb = {0};
    cb.cancel = cancel_after;
    cb.user = &n;
    o.params.threads = after == 1 ? 1 : 2;
    assert_int_equal(bbc_cloud_build(&m, &s, &o.params, &cb, &c, &err), BBC_ERROR_CANCELLED);
    assert_int_equal(err.code, BBC_ERROR_CANCELLED);
  }
  if (bbc_cloud_build(&m, &s, &o.params, NULL, &c, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_true(c.billboard_count > 0);
  bbc_cloud_free(&c);
  bbc_planeset_free(&s);
  bbc_mesh_free(&m);
}

/* pure 0 draws a leaf into every billboard whose slab it crosses, pure 1
 * into its own plane's only, pure 2 into each with half its coverage:
 * two planes z = 0 and z = 0.01, a leaf of 8 x 8 texels at z = 0.005
 * between them (eps 0.02). */
static void test_pure_split(void **state) {
  (void)state;
  const int N = 16;
  size_t opaque[3][2];
  for (int pure = 0; pure < 3; pure++) {
    scene sc;
    scene_begin(&sc, 4);
    scene_frame(&sc);
    const double l0[3] = {0.25, 0.25, 0.005}, l1[3] = {0.75, 0.25, 0.005},
                 l2[3] = {0.75, 0.75, 0.005}, l3[3] = {0.25, 0.75, 0.005};
    scene_tri(&sc, l0, l1, l2, 1);
    scene_tri(&sc, l0, l2, l3, 1);
    scene_end(&sc, 0.02);
    bbc_planeset *st = &sc.s;
    bbc_plane *pl = realloc(st->planes, 2 * sizeof *pl);
    assert_non_null(pl);
    st->planes = pl;
    pl[1] = pl[0];
    pl[1].d = 0.01;
    pl[0].face_count = 2; /* the leaf's plane */
    pl[1].face_count = 2; /* the frame's */
    st->face_plane[0] = st->face_plane[1] = 1;
    st->plane_count = 2;
    st->parts[0].plane_count = 2;
    bbc_params p;
    params_for(&p, N, 2);
    p.pure = pure;
    p.refine = 0; /* the masks as baked */
    p.back_images = 0;
    p.stem = 0;
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    assert_int_equal(cl.billboard_count, 2);
    for (int k = 0; k < 2; k++) {
      const bbc_cloud_billboard *bb = &cl.billboards[k];
      opaque[pure][k] = 0;
      for (int ty = 4; ty < 12; ty++)
        for (int tx = 4; tx < 12; tx++) {
          const double q[3] = {(tx + 0.5) / N, (ty + 0.5) / N, bb->d};
          opaque[pure][k] += texel_at(&cl, bb, 0, q)[3] == 255;
        }
    }
    bbc_cloud_free(&cl);
    scene_free(&sc);
  }
  for (int pure = 0; pure < 3; pure++)
    printf("pure %d: leaf texels opaque %zu + %zu of 64 + 64\n", pure, opaque[pure][0],
           opaque[pure][1]);
  assert_int_equal(opaque[0][0] + opaque[0][1], 128);
  assert_int_equal(opaque[1][0] + opaque[1][1], 64);
  for (int k = 0; k < 2; k++) assert_true(opaque[2][k] >= 28 && opaque[2][k] <= 36);
}

/* A generated larch of `leaves` leaves (0: the species' default, as `bbcgen
 * tree` grows it): an airy conifer, limbs on whorls. */
static void larch(bbc_mesh *m, int leaves) {
  bbc_tree_options to;
  bbc_tree_options_default(&to);
  to.seed = 1; /* the tree these checks were written for */
  to.species = BBC_TREE_LARCH;
  to.leaves = leaves;
  bbc_error err;
  if (bbc_tree_generate(&to, m, &err) != BBC_OK) fail_msg("%s", err.message);
}

static void test_refine_keeps_density(void **state) {
  (void)state;
  bbc_mesh m;
  bbc_error err;
  larch(&m, 1500);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.prelight = 0;
  o.params.limbs = 0; /* every part on billboards: their alpha is refined */
  bbc_planeset s;
  if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
  double cov[2], block[2];
  bbc_cloud c[3];
  for (int k = 0; k < 3; k++) {
    bbc_params p = o.params;
    p.refine = k ? 16 : 0;
    p.threads = k == 2 ? 2 : 1;
    if (bbc_cloud_build(&m, &s, &p, NULL, &c[k], &err) != BBC_OK) fail_msg("%s", err.message);
    if (k == 2) break;
    bbc_eval_options eo;
    bbc_eval_options_default(&eo);
    eo.views = 32;
    bbc_eval_result r;
    if (bbc_eval(&m, &c[k].mesh, &eo, &r, &err) != BBC_OK) fail_msg("%s", err.message);
    cov[k] = r.coverage_ratio_side_mean;
    block[k] = r.block_iou_side_mean;
    bbc_eval_result_free(&r);
  }
  printf("larch side coverage ratio %.3f -> %.3f, block IoU %.3f -> %.3f\n", cov[0], cov[1],
         block[0], block[1]);
  assert_true(fabs(log(cov[1])) < fabs(log(cov[0])));
  assert_true(cov[1] >= 0.85 && cov[1] <= 1.15);
  assert_true(block[1] > block[0] + 0.03);
  const bbc_image *a = &c[1].mesh.textures[0].image, *b = &c[2].mesh.textures[0].image;
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  assert_memory_equal(a->rgba, b->rgba, 4 * (size_t)a->width * a->height);
  for (int k = 0; k < 3; k++) bbc_cloud_free(&c[k]);
  bbc_planeset_free(&s);
  bbc_mesh_free(&m);
}

/* At 2 samples a texel side the larch (needles on alpha cards on thin
 * twigs, grown as `bbcgen tree --species larch` does) keeps the side
 * coverage it has at 4, within 2.5 %: faces passing their alpha test at a
 * sample's taps but not at its centre (bbc__bake.taps) make their texels
 * candidates for the dithering and the refinement. Without them it kept
 * 0.955 of it (side coverage ratio 0.990 against 1.037). */
static void test_larch_samples_keep_coverage(void **state) {
  (void)state;
  bbc_mesh m;
  bbc_error err;
  larch(&m, 0);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_planeset s;
  if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
  double cov[2];
  for (int k = 0; k < 2; k++) {
    bbc_params p = o.params;
    p.samples = k ? 2 : 4;
    assert_true(p.texres >= 128); /* where the default samples 2 */
    bbc_cloud c;
    if (bbc_cloud_build(&m, &s, &p, NULL, &c, &err) != BBC_OK) fail_msg("%s", err.message);
    bbc_eval_options eo;
    bbc_eval_options_default(&eo);
    bbc_eval_result r;
    if (bbc_eval(&m, &c.mesh, &eo, &r, &err) != BBC_OK) fail_msg("%s", err.message);
    cov[k] = r.coverage_ratio_side_mean;
    bbc_eval_result_free(&r);
    bbc_cloud_free(&c);
  }
  printf("larch side coverage ratio: 4 samples a side %.3f, 2 samples %.3f\n", cov[0], cov[1]);
  assert_true(fabs(log(cov[1] / cov[0])) < 0.025);
  bbc_planeset_free(&s);
  bbc_mesh_free(&m);
}

/* A stem that holds from every side (stem.c): a vertical cylinder in the
 * part "trunk", simplified by one plane through its axis with a slab
 * thinner than the cylinder. Without stem billboards the trunk vanishes
 * where that plane is seen edge-on; with three (60 degrees apart) every
 * side view shows at least 80 % of it. */
static void test_stem_holds_from_every_side(void **state) {
  (void)state;
  enum { SIDES = 16 };
  scene sc;
  scene_begin(&sc, 2 * SIDES + 2 * (SIDES - 2));
  const double r = 0.05, h = 1.0;
  for (int i = 0; i < SIDES; i++) {
    double a0 = 2 * 3.14159265358979323846 * i / SIDES,
           a1 = 2 * 3.14159265358979323846 * (i + 1) / SIDES;
    const double p00[3] = {r * cos(a0), 0, r * sin(a0)}, p10[3] = {r * cos(a1), 0, r * sin(a1)};
    const double p01[3] = {r * cos(a0), h, r * sin(a0)}, p11[3] = {r * cos(a1), h, r * sin(a1)};
    scene_tri(&sc, p00, p10, p11, 1);
    scene_tri(&sc, p00, p11, p01, 1);
  }
  scene_end(&sc, 0.01);
  strcpy(sc.s.parts[0].name, "trunk");
  double dirs[12][3];
  for (int k = 0; k < 12; k++) {
    double a = 2 * 3.14159265358979323846 * (k + 0.25) / 12;
    dirs[k][0] = cos(a);
    dirs[k][1] = 0;
    dirs[k][2] = sin(a);
  }
  double min_recall[2];
  for (int with = 0; with < 2; with++) {
    bbc_params p;
    params_for(&p, 64, 2);
    p.stem = with ? 3 : 0;
    bbc_cloud cl;
    bbc_error err;
    if (bbc_cloud_build(&sc.m, &sc.s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    size_t stems = 0;
    for (size_t b = 0; b < cl.billboard_count; b++) {
      const bbc_cloud_billboard *cb = &cl.billboards[b];
      if (cb->kind != BBC_PLANE_STEM) continue;
      stems++;
      assert_true(fabs(cb->normal[1]) < 1e-6); /* through the vertical axis */
      for (size_t c = 0; c < b; c++)
        if (cl.billboards[c].kind == BBC_PLANE_STEM) /* 60 degrees apart */
          assert_true(fabs(fabs(cb->normal[0] * cl.billboards[c].normal[0] +
                                cb->normal[2] * cl.billboards[c].normal[2]) -
                           0.5) < 1e-6);
    }
    assert_int_equal(stems, with ? 3 : 0);
    bbc_eval_options eo;
    bbc_eval_options_default(&eo);
    eo.directions = &dirs[0][0];
    eo.direction_count = 12;
    eo.size = 128;
    bbc_eval_result er;
    if (bbc_eval(&sc.m, &cl.mesh, &eo, &er, &err) != BBC_OK) fail_msg("%s", err.message);
    min_recall[with] = 1;
    for (size_t v = 0; v < er.view_count; v++)
      min_recall[with] = fmin(min_recall[with], er.views[v].recall);
    bbc_eval_result_free(&er);
    bbc_cloud_free(&cl);
  }
  printf("trunk: least side-view recall %.3f without stem billboards, %.3f with\n", min_recall[0],
         min_recall[1]);
  assert_true(min_recall[0] < 0.3);
  assert_true(min_recall[1] >= 0.8);
  scene_free(&sc);
}

/* The trunk part as a mesh (`limbs`, limbs.c): on a generated larch (its
 * limbs on whorls, near-horizontal planes seen edge-on from the side) the
 * trunk part gets no planes and no stem billboards; its faces become at
 * most `limbs` triangles at the end of the cloud's mesh, inside the
 * original's bounds, on one opaque swatch of the atlas; the side views'
 * density (block IoU at 1/8) rises; the same with 1 and 2 threads, and
 * written as VRML it reads back whole. */
static void test_limbs_mesh(void **state) {
  (void)state;
  bbc_mesh m;
  bbc_error err;
  larch(&m, 1500);
  double block[2];
  for (int with = 0; with < 2; with++) {
    bbc_planes_options o;
    bbc_planes_options_default(&o);
    o.params.prelight = 0;
    o.params.limbs = with ? 200 : 0;
    bbc_planeset s;
    if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
    int trunk = -1;
    for (size_t pi = 0; pi < s.part_count; pi++)
      if (!strcmp(s.parts[pi].name, "trunk")) trunk = (int)pi;
    assert_true(trunk >= 0 && s.part_count == 2);
    size_t trunk_planes = 0;
    for (size_t i = 0; i < s.plane_count; i++) trunk_planes += s.planes[i].part == (uint32_t)trunk;
    if (with) {
      assert_int_equal(trunk_planes, 0);
      assert_int_equal(s.parts[trunk].limbs, 200);
      for (size_t t = 0; t < s.face_count; t++)
        assert_int_equal(s.face_plane[t] == BBC_NO_PLANE, s.face_part[t] == (uint32_t)trunk);
    } else {
      assert_true(trunk_planes > 0);
      for (size_t t = 0; t < s.face_count; t++) assert_true(s.face_plane[t] != BBC_NO_PLANE);
    }
    bbc_cloud c[2];
    for (int k = 0; k < (with ? 2 : 1); k++) {
      bbc_params p = o.params;
      p.threads = k + 1;
      if (bbc_cloud_build(&m, &s, &p, NULL, &c[k], &err) != BBC_OK) fail_msg("%s", err.message);
    }
    const bbc_cloud *cl = &c[0];
    if (with) {
      size_t nl = cl->limb_triangles, nt = cl->mesh.triangle_count;
      assert_true(nl > 20 && nl <= 200);
      size_t stems = 0;
      for (size_t b = 0; b < cl->billboard_count; b++)
        stems += cl->billboards[b].kind == BBC_PLANE_STEM;
      assert_int_equal(stems, 0);
      const bbc_image *atlas = &cl->mesh.textures[0].image;
      const float *uv0 = cl->mesh.uvs + 2 * (size_t)cl->mesh.indices[3 * (nt - nl)];
      int x = (int)(uv0[0] * atlas->width), y = (int)((1 - uv0[1]) * atlas->height);
      const uint8_t *px = atlas->rgba + 4 * ((size_t)y * atlas->width + x);
      assert_int_equal(px[3], 255);
      assert_true(px[0] > px[2]); /* bark: brown, more red than blue */
      double tol = 1e-6 * m.radius;
      for (size_t t = nt - nl; t < nt; t++)
        for (int k = 0; k < 3; k++) {
          size_t v = cl->mesh.indices[3 * t + k];
          assert_memory_equal(cl->mesh.uvs + 2 * v, uv0, 2 * sizeof *uv0);
          for (int j = 0; j < 3; j++) {
            double q = cl->mesh.positions[3 * v + j];
            assert_true(q >= m.bbox_min[j] - tol && q <= m.bbox_max[j] + tol);
          }
        }
      /* one thread or two: the same mesh and atlas */
      assert_int_equal(c[1].mesh.vertex_count, cl->mesh.vertex_count);
      assert_memory_equal(c[1].mesh.positions, cl->mesh.positions,
                          3 * cl->mesh.vertex_count * sizeof *cl->mesh.positions);
      assert_memory_equal(c[1].mesh.textures[0].image.rgba, atlas->rgba,
                          4 * (size_t)atlas->width * atlas->height);
      /* VRML: the billboards' shapes, then the limbs' */
      char *dir = tu_make_temp_dir(), path[1200];
      snprintf(path, sizeof path, "%s/l.wrl", dir);
      if (bbc_cloud_write_vrml(path, cl, NULL, &err) != BBC_OK) fail_msg("%s", err.message);
      bbc_mesh back;
      if (bbc_mesh_load(path, NULL, &back, &err) != BBC_OK) fail_msg("%s", err.message);
      assert_int_equal(back.triangle_count, nt);
      bbc_mesh_free(&back);
      tu_remove_dir(dir);
      free(dir);
      bbc_cloud_free(&c[1]);
    }
    bbc_eval_options eo;
    bbc_eval_options_default(&eo);
    eo.views = 32;
    bbc_eval_result r;
    if (bbc_eval(&m, &cl->mesh, &eo, &r, &err) != BBC_OK) fail_msg("%s", err.message);
    block[with] = r.block_iou_side_mean;
    bbc_eval_result_free(&r);
    bbc_cloud_free(&c[0]);
    bbc_planeset_free(&s);
  }
  printf("larch side block IoU %.3f without limbs, %.3f with\n", block[0], block[1]);
  assert_true(block[1] > block[0] + 0.02);
  bbc_mesh_free(&m);
}

/* ---- a real tree ----------------------------------------------------------- */

static void build(const bbc_mesh *m, int quality, int threads, bbc_planeset *s, bbc_cloud *cloud) {
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.epsilon_pct = 6;
  o.params.clustering = 0;
  o.params.quality = quality;
  o.params.texres = 128;
  o.params.atlas_max = 0;
  o.params.max_planes = 0;
  o.params.min_planes = 0;
  o.params.threads = threads;
  o.params.normal_maps = quality == 2;
  o.params.shade_voxels = quality == 2 ? 40 : 0;
  o.params.limbs = 0; /* the trunk part on billboards and stem billboards */
  bbc_error err;
#ifdef _OPENMP
  int before = omp_get_max_threads();
#endif
  if (bbc_planes_find(m, &o, s, &err) != BBC_OK) fail_msg("%s", err.message);
  if (bbc_cloud_build(m, s, &o.params, NULL, cloud, &err) != BBC_OK) fail_msg("%s", err.message);
#ifdef _OPENMP
  /* `threads` holds for the library's parallel loops, then the caller's
   * default team size is back */
  assert_int_equal(omp_get_max_threads(), before);
#endif
}

static int rects_overlap(const bbc_atlas_rect *a, const bbc_atlas_rect *b) {
  return a->x < b->x + b->width && b->x < a->x + a->width && a->y < b->y + b->height &&
         b->y < a->y + a->height;
}

/* The data tree the cloud tests build on (skips when absent). */
static void load_aspen(bbc_mesh *m) {
  char path[1024];
  tu_data_path(path, sizeof path, "trees/eztree/aspen_small.obj");
  if (!tu_have_file(path)) skip();
  bbc_error err;
  if (bbc_mesh_load(path, NULL, m, &err) != BBC_OK) fail_msg("%s", err.message);
}

static void test_cloud_of_a_tree(void **state) {
  (void)state;
  bbc_mesh m;
  load_aspen(&m);
  bbc_error err;
  for (int quality = 0; quality <= 2; quality += 2) {
    bbc_planeset s;
    bbc_cloud cl;
    build(&m, quality, 1, &s, &cl);
    const bbc_mesh *cm = &cl.mesh;
    size_t stems = 0;
    for (size_t b = 0; b < cl.billboard_count; b++)
      stems += cl.billboards[b].kind == BBC_PLANE_STEM;
    assert_int_equal(stems, 3);                                  /* the trunk part's stem */
    assert_int_equal(cl.billboard_count, s.plane_count + stems); /* polyskip 0, no cardboard */
    size_t tris = 0, verts = 0;
    for (size_t k = 0; k < cl.billboard_count; k++) {
      const bbc_cloud_billboard *b = &cl.billboards[k];
      assert_true(b->corner_count >= 3 && b->corner_count <= 10);
      tris += 2 * ((size_t)b->corner_count - 2);
      verts += 2 * (size_t)b->corner_count;
      /* Atlas rectangles: inside the atlas, disjoint. */
      const bbc_atlas_rect *r[2] = {&b->front, &b->back};
      const bbc_image *a = &cm->textures[0].image;
      for (int i = 0; i < 2; i++) {
        assert_true(r[i]->x >= 0 && r[i]->y >= 0 && r[i]->x + r[i]->width <= a->width &&
                    r[i]->y + r[i]->height <= a->height);
        assert_int_equal(r[i]->width, b->tex_width);
      }
      assert_false(rects_overlap(r[0], r[1]));
      for (size_t j = 0; j < k; j++) {
        const bbc_cloud_billboard *o = &cl.billboards[j];
        assert_false(rects_overlap(r[0], &o->front) || rects_overlap(r[0], &o->back) ||
                     rects_overlap(r[1], &o->front) || rects_overlap(r[1], &o->back));
      }
    }
    assert_int_equal(cm->triangle_count, tris);
    assert_int_equal(cm->vertex_count, verts);
    /* Every vertex lies on its billboard's plane. */
    size_t v = 0;
    for (size_t k = 0; k < cl.billboard_count; k++) {
      const bbc_cloud_billboard *b = &cl.billboards[k];
      for (int c = 0; c < 2 * b->corner_count; c++, v++) {
        const double *x = cm->positions + 3 * v;
        double d = b->normal[0] * x[0] + b->normal[1] * x[1] + b->normal[2] * x[2] - b->d;
        assert_true(fabs(d) < 1e-6 * m.radius);
      }
    }
    /* The cloud stays within the model's bounds grown by epsilon. */
    for (int k = 0; k < 3; k++) {
      assert_true(cm->bbox_min[k] >= m.bbox_min[k] - s.epsilon_abs * (1 + 1e-6));
      assert_true(cm->bbox_max[k] <= m.bbox_max[k] + s.epsilon_abs * (1 + 1e-6));
    }
    /* The atlas has real transparency, a mask at quality 2: alpha at most
     * 50 or at least 205, softened at its edges (softalpha). */
    const bbc_image *a = &cm->textures[0].image;
    size_t zero = 0, full = 0, soft = 0, mid = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
      uint8_t al = a->rgba[4 * i + 3];
      zero += al == 0;
      full += al == 255;
      soft += (al > 0 && al <= 50) || (al >= 205 && al < 255);
      mid += al > 50 && al < 205;
    }
    assert_true(zero > 0 && full > 0);
    if (quality == 2) assert_true(soft > 0);
    assert_int_equal(mid, 0);
    assert_true(cl.atlas_fill > 0.2 && cl.atlas_fill <= 1.0);
    /* Deterministic, with any number of threads. */
    bbc_planeset s2;
    bbc_cloud c2;
    build(&m, quality, 2, &s2, &c2);
    assert_int_equal(c2.mesh.textures[0].image.width, a->width);
    assert_memory_equal(c2.mesh.textures[0].image.rgba, a->rgba, (size_t)a->width * a->height * 4);
    assert_memory_equal(c2.mesh.positions, cm->positions, cm->vertex_count * 3 * sizeof(double));
    assert_int_equal(c2.mesh.texture_count, cm->texture_count);
    if (cm->texture_count == 2)
      assert_memory_equal(c2.mesh.textures[1].image.rgba, cm->textures[1].image.rgba,
                          (size_t)a->width * a->height * 4);
    bbc_cloud_free(&c2);
    bbc_planeset_free(&s2);
    /* glTF round trip. */
    char *dir = tu_make_temp_dir();
    char out[1024];
    snprintf(out, sizeof out, "%s/aspen.glb", dir);
    assert_int_equal(bbc_mesh_write_gltf(out, cm, NULL, &err), BBC_OK);
    bbc_mesh back;
    if (bbc_mesh_load(out, NULL, &back, &err) != BBC_OK) fail_msg("%s", err.message);
    assert_int_equal(back.triangle_count, cm->triangle_count);
    assert_true(back.textures[0].has_alpha);
    /* glTF's doubleSided comes back: one-sided copies with back images. */
    assert_int_equal(back.materials[0].single_sided, cm->materials[0].single_sided);
    assert_int_equal(back.materials[0].single_sided, 1);
    bbc_mesh_free(&back);
    tu_remove_dir(dir);
    free(dir);
    bbc_cloud_free(&cl);
    bbc_planeset_free(&s);
  }
  bbc_mesh_free(&m);
}

/* Renders a cloud from a few directions (unlit), images appended to out. */
static void render_views(const bbc_mesh *cm, const bbc_mesh *frame, bbc_image out[4]) {
  static const double dirs[4][3] = {{0, 0, -1}, {-1, 0, 0}, {0.6, -0.5, 0.62}, {0, -1, 0}};
  static const double ups[4][3] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 0, 1}};
  bbc_error err;
  for (int v = 0; v < 4; v++) {
    bbc_view view;
    bbc_view_frame_mesh(frame, dirs[v], ups[v], &view);
    view.lighting = 0;
    if (bbc_image_alloc(&out[v], 96, 96) != BBC_OK) fail_msg("out of memory");
    if (bbc_render_ortho(cm, &view, &out[v], &err) != BBC_OK) fail_msg("%s", err.message);
  }
}

/* Levels of detail in one atlas: every level looks exactly as it did with
 * its own atlas; the shared atlas holds every level's images; a budget too
 * small changes nothing. */
/* The outline's inside test at (s, t): the polygon is convex and
 * counter-clockwise, so inside means left of (or on) every edge. */
static int inside_outline(const bbc_cloud_billboard *b, double s, double t) {
  for (int c = 0; c < b->corner_count; c++) {
    const double *P = b->corners[c], *Q = b->corners[(c + 1) % b->corner_count];
    if ((Q[0] - P[0]) * (t - P[1]) - (Q[1] - P[1]) * (s - P[0]) < -1e-12) return 0;
  }
  return 1;
}

static double outline_area(const bbc_cloud_billboard *b) {
  double a = 0;
  for (int c = 0; c < b->corner_count; c++) {
    const double *P = b->corners[c], *Q = b->corners[(c + 1) % b->corner_count];
    a += P[0] * Q[1] - Q[0] * P[1];
  }
  return 0.5 * a;
}

/* outline: each billboard's outline a convex polygon of at most `outline`
 * corners inside its rectangle that holds every opaque texel of its images
 * (so nothing drawn is lost), smaller in all than the clipped rectangles
 * of outline 0; maxtris cuts the corners to fit. */
static void test_tight_outlines(void **state) {
  (void)state;
  bbc_mesh m;
  load_aspen(&m);
  bbc_error err;
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.texres = 64;
  o.params.atlas_max = 0;
  bbc_planeset s;
  if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
  double area[2] = {0, 0};
  size_t tris[3];
  for (int run = 0; run < 3; run++) {
    bbc_params p = o.params;
    p.outline = run == 1 ? 0 : 6;
    if (run == 2) p.max_tris = 1; /* quads at least */
    bbc_cloud cl;
    if (bbc_cloud_build(&m, &s, &p, NULL, &cl, &err) != BBC_OK) fail_msg("%s", err.message);
    tris[run] = cl.mesh.triangle_count - cl.limb_triangles;
    const bbc_image *a = &cl.mesh.textures[0].image;
    for (size_t k = 0; k < cl.billboard_count; k++) {
      const bbc_cloud_billboard *b = &cl.billboards[k];
      if (run == 0) assert_true(b->corner_count >= 3 && b->corner_count <= 6);
      if (run == 2) assert_true(b->corner_count <= 4);
      for (int c = 0; c < b->corner_count; c++) {
        assert_true(b->corners[c][0] >= 0 && b->corners[c][0] <= 1);
        assert_true(b->corners[c][1] >= 0 && b->corners[c][1] <= 1);
        const double *P = b->corners[c], *Q = b->corners[(c + 1) % b->corner_count];
        const double *R = b->corners[(c + 2) % b->corner_count];
        assert_true((Q[0] - P[0]) * (R[1] - Q[1]) - (Q[1] - P[1]) * (R[0] - Q[0]) > 0);
      }
      if (run < 2) area[run] += outline_area(b) * b->rect.width * b->rect.height;
      /* every opaque texel's centre inside, front and back */
      const bbc_atlas_rect *r[2] = {&b->front, &b->back};
      for (int i = 0; i < 2; i++)
        for (int y = 0; y < r[i]->height; y++)
          for (int x = 0; x < r[i]->width; x++) {
            size_t at = (size_t)(r[i]->y + y) * a->width + (size_t)(r[i]->x + x);
            if (!a->rgba[4 * at + 3]) continue;
            double ts = (x + 0.5) / r[i]->width, tt = 1 - (y + 0.5) / r[i]->height;
            if (!inside_outline(b, ts, tt))
              fail_msg("run %d billboard %zu: opaque texel (%d, %d) outside", run, k, x, y);
          }
    }
    bbc_cloud_free(&cl);
  }
  print_message("outline 6: %.4g model units^2 of billboards, %zu triangles; outline 0: %.4g, "
                "%zu; maxtris: %zu\n",
                area[0], tris[0], area[1], tris[1], tris[2]);
  assert_true(area[0] < 0.97 * area[1]); /* the empty corners gone */
  assert_true(tris[0] > tris[1]);        /* for a few more corners */
  assert_true(tris[2] <= tris[1]);
  bbc_planeset_free(&s);
  bbc_mesh_free(&m);
}

static void test_shared_atlas(void **state) {
  (void)state;
  bbc_tree_options to;
  bbc_tree_options_default(&to);
  to.seed = 1; /* the tree these checks were written for */
  to.leaves = 800;
  bbc_mesh m;
  bbc_error err;
  if (bbc_tree_generate(&to, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_planeset sets[2];
  bbc_cloud clouds[2];
  bbc_image before[2][4], after[2][4];
  for (int k = 0; k < 2; k++) {
    bbc_planes_options o;
    bbc_planes_options_default(&o);
    o.params.epsilon_pct = k ? 15 : 6;
    o.params.texres = 32;
    o.params.atlas_max = 0;
    o.params.normal_maps = 1;
    if (bbc_planes_find(&m, &o, &sets[k], &err) != BBC_OK) fail_msg("%s", err.message);
    if (bbc_cloud_build(&m, &sets[k], &o.params, NULL, &clouds[k], &err) != BBC_OK)
      fail_msg("%s", err.message);
    render_views(&clouds[k].mesh, &m, before[k]);
  }
  int shared = 1;
  assert_int_equal(bbc_clouds_share_atlas(clouds, 2, 16, &shared, &err), BBC_OK);
  assert_int_equal(shared, 0); /* does not fit: unchanged */
  assert_int_equal(bbc_clouds_share_atlas(clouds, 2, 1024, &shared, &err), BBC_OK);
  assert_int_equal(shared, 1);
  const bbc_image *a0 = &clouds[0].mesh.textures[0].image, *a1 = &clouds[1].mesh.textures[0].image;
  assert_int_equal(a0->width, a1->width);
  assert_int_equal(a0->height, a1->height);
  assert_memory_equal(a0->rgba, a1->rgba, 4 * (size_t)a0->width * a0->height);
  assert_int_equal(clouds[0].mesh.textures[1].image.width, a0->width);
  int aw = a0->width, ah = a0->height;
  for (int k = 0; k < 2; k++) {
    render_views(&clouds[k].mesh, &m, after[k]);
    for (int v = 0; v < 4; v++) {
      size_t differ = 0, n = (size_t)96 * 96;
      for (size_t i = 0; i < 4 * n; i++) differ += before[k][v].rgba[i] != after[k][v].rgba[i];
      if (differ) fail_msg("level %d view %d: %zu bytes differ", k, v, differ);
      bbc_image_free(&before[k][v]);
      bbc_image_free(&after[k][v]);
    }
    for (size_t b = 0; b < clouds[k].billboard_count; b++) {
      const bbc_atlas_rect *q = &clouds[k].billboards[b].front;
      assert_true(q->x >= 0 && q->y >= 0 && q->x + q->width <= aw && q->y + q->height <= ah);
    }
    bbc_cloud_free(&clouds[k]);
    bbc_planeset_free(&sets[k]);
  }
  bbc_mesh_free(&m);
}

/* Mean RGB (sum of the three) over the opaque texels of a cloud's atlas. */
static double atlas_mean(const bbc_cloud *c) {
  const bbc_image *a = &c->mesh.textures[0].image;
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < (size_t)a->width * a->height; i++)
    if (a->rgba[4 * i + 3] == 255) {
      sum += a->rgba[4 * i] + a->rgba[4 * i + 1] + a->rgba[4 * i + 2];
      n++;
    }
  return n ? sum / n : 0;
}

/* Prelight aims at a lit viewer: a generated tree's prelit images are about
 * 2/3 as bright as its colours (a headlight's |n . v|); bbc_light_gain_measure has
 * the analytic value on a quad; the ambient term as X3D viewers add it. */
static void test_prelight_for_a_lit_viewer(void **state) {
  (void)state;
  bbc_tree_options to;
  bbc_tree_options_default(&to);
  to.seed = 1; /* the tree these checks were written for */
  to.leaves = 1500;
  bbc_mesh m;
  bbc_error err;
  if (bbc_tree_generate(&to, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  m.no_mipmaps = 1; /* both read the texels themselves: only the light differs */
  double mean[2];
  for (int lit = 0; lit < 2; lit++) {
    bbc_planes_options o;
    bbc_planes_options_default(&o);
    o.params.texres = 64;
    o.params.atlas_max = 0;
    o.params.prelight = lit;
    o.params.occlusion = 0;
    o.params.normal_maps = 0;
    bbc_planeset s;
    bbc_cloud c;
    if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) fail_msg("%s", err.message);
    if (bbc_cloud_build(&m, &s, &o.params, NULL, &c, &err) != BBC_OK) fail_msg("%s", err.message);
    mean[lit] = atlas_mean(&c);
    bbc_cloud_free(&c);
    bbc_planeset_free(&s);
  }
  /* Baked for a lit viewer: a headlight shows a tree's faces at about
   * |n . v| ~ 2/3 of their colour (no ambient in a generated tree). */
  double ratio = mean[1] / mean[0];
  if (!(ratio > 0.5 && ratio < 0.85)) fail_msg("prelit / unlit brightness %.3f", ratio);
  /* A horizontal white quad under a light from above (sun factor 1), seen
   * from elevations 0 and 20 degrees: headlit |n . v| = sin(elevation),
   * and its pixels are in proportion to sin(elevation) too (none edge-on),
   * so gain = sin^2 20 / sin 20 = 0.342. */
  double light[3] = {0, 1, 0};
  bbc_mesh q;
  memset(&q, 0, sizeof q);
  double pos[12] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
  float nrm[12] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
  bbc_material mat;
  memset(&mat, 0, sizeof mat);
  mat.name = (char *)"white";
  mat.texture = -1;
  for (int k = 0; k < 4; k++) mat.base_color[k] = 1.0f;
  uint32_t fm[2] = {0, 0};
  q.kind = BBC_MESH_TRIANGLES;
  q.positions = pos;
  q.normals = nrm;
  q.vertex_count = 4;
  q.indices = idx;
  q.triangle_count = 2;
  q.materials = &mat;
  q.material_count = 1;
  q.face_material = fm;
  q.bbox_max[0] = q.bbox_max[2] = 1;
  double expect = sin(20 * 3.14159265358979323846 / 180), g = 0;
  if (bbc_light_gain_measure(&q, light, 1, &g, &err) != BBC_OK) fail_msg("%s", err.message);
  if (fabs(g - expect) > 0.01) fail_msg("gain %.4f, expected %.4f", g, expect);
  /* The same quad for up = x lies along the up axis: its pixels and its
   * headlight are the same at every azimuth. */
  double g2 = 0;
  if (bbc_light_gain_measure(&q, light, 0, &g2, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_true(g2 > 0.5 && g2 < 1.0);
  /* The fixed-function ambient, facing the headlight: for a grey Kd colour
   * Kd + 0.2 Ka, and 0.2 x 0.2 when the material has no Ka (materials 0, 1).
   * A coloured Kd (2, 3): ambientIntensity is the mean over the channels of Ka / Kd
   * (view3dscene drew a face-on quad of Kd 0.4 0.3 0.1, Ka 1 0.5 0.2 as 144
   * 108 36, and of Kd 0.2 0.5 0.8, Ka 0.3 as 59 149 238); the mean Ka over
   * the mean Kd would give 134 101 34 and 63 156 250. */
  bbc_image img;
  assert_int_equal(bbc_image_alloc(&img, 16, 16), BBC_OK);
  const float kds[4][3] = {
      {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {0.4f, 0.3f, 0.1f}, {0.2f, 0.5f, 0.8f}};
  const float kas[4][3] = {{0, 0, 0}, {1, 1, 1}, {1.0f, 0.5f, 0.2f}, {0.3f, 0.3f, 0.3f}};
  const double want[4][3] = {
      {137.7, 137.7, 137.7}, {178.5, 178.5, 178.5}, {144, 108, 36}, {59, 149, 238}};
  for (int c = 0; c < 4; c++) {
    for (int k = 0; k < 3; k++) {
      mat.base_color[k] = kds[c][k];
      mat.ambient[k] = kas[c][k];
    }
    bbc_view v;
    double down[3] = {0, -1, 0}, upz[3] = {0, 0, 1};
    bbc_view_frame_mesh(&q, down, upz, &v);
    v.lighting = 1;
    v.headlight = 1;
    v.ambient = 1;
    if (bbc_render_ortho(&q, &v, &img, &err) != BBC_OK) fail_msg("%s", err.message);
    const uint8_t *px = img.rgba + 4 * (8 * 16 + 8);
    for (int k = 0; k < 3; k++)
      if (fabs(px[k] - want[c][k]) > 1)
        fail_msg("ambient, material %d, channel %d: %d, expected %.1f", c, k, px[k], want[c][k]);
  }
  bbc_image_free(&img);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_texel_centres_quality0),
      cmocka_unit_test(test_small_leaf_survives_quality2),
      cmocka_unit_test(test_dither_keeps_density),
      cmocka_unit_test(test_samples_average_texture),
      cmocka_unit_test(test_larch_samples_keep_coverage),
      cmocka_unit_test(test_soft_alpha),
      cmocka_unit_test(test_refine_keeps_density),
      cmocka_unit_test(test_pure_split),
      cmocka_unit_test(test_cancel),
      cmocka_unit_test(test_stem_holds_from_every_side),
      cmocka_unit_test(test_limbs_mesh),
      cmocka_unit_test(test_front_and_back),
      cmocka_unit_test(test_tilted_normal_map),
      cmocka_unit_test(test_material_maps),
      cmocka_unit_test(test_voxel_shading),
      cmocka_unit_test(test_cloud_of_a_tree),
      cmocka_unit_test(test_tight_outlines),
      cmocka_unit_test(test_shared_atlas),
      cmocka_unit_test(test_prelight_for_a_lit_viewer),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
