/* test_impostor.c — octahedral impostors (src/cloud/impostor.c,
 * src/raster/impostor_draw.c, src/io/impostor_file.c): drawn along its
 * frames' directions an impostor is its model (block IoU against the
 * original's render), between frames close to it, from below too when it is
 * octahedral; its depths where the surface is; the same atlases with any
 * thread count; written and read back intact; bad options refused; its
 * mip levels keep each frame's coverage and colour. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>
#include <unistd.h>

#include "bbc.h"
#include "test_util.h"

static void tree(bbc_mesh *m, int seed) {
  bbc_tree_options o;
  bbc_tree_options_default(&o);
  o.seed = (uint64_t)seed;
  o.leaves = 3000;
  o.texture_size = 64;
  bbc_error err;
  if (bbc_tree_generate(&o, m, &err) != BBC_OK) fail_msg("%s", err.message);
}

static void build(const bbc_mesh *m, int frames, int full, long long texels, int threads,
                  bbc_impostor *imp) {
  bbc_impostor_options o;
  bbc_impostor_options_default(&o);
  o.frames = frames;
  o.full = full;
  o.texels = texels;
  o.threads = threads;
  bbc_error err;
  if (bbc_impostor_build(m, &o, imp, &err) != BBC_OK) fail_msg("%s", err.message);
}

/* The impostor against its model along `n` directions (camera towards the
 * model): the worst and the mean block IoU. */
static void judge(const bbc_mesh *m, const bbc_impostor *imp, const double *dirs, int n,
                  double *worst, double *mean) {
  bbc_eval_options o;
  bbc_eval_options_default(&o);
  o.directions = dirs;
  o.direction_count = (size_t)n;
  o.size = getenv("JSZ") ? atoi(getenv("JSZ")) : 256;
  o.impostor = imp;
  bbc_eval_result r;
  bbc_error err;
  if (bbc_eval(m, NULL, &o, &r, &err) != BBC_OK) fail_msg("%s", err.message);
  *worst = 1;
  *mean = 0;
  for (size_t k = 0; k < r.view_count; k++) {
    *worst = fmin(*worst, r.views[k].block_iou);
    *mean += r.views[k].block_iou / (double)r.view_count;
  }
  bbc_eval_result_free(&r);
}

/* Along each frame's own direction the impostor draws that frame alone, a
 * render of its model: on the frame's own texels against the model drawn
 * 4 x finer, blocks of 8 x 8 texels, block IoU >= 0.95 (the bound)
 * on every frame. Judged by bbc_eval at 256 pixels (the model's box framed,
 * 2 x the frames' texels): at the frames' directions and halfway between
 * neighbours (the three-frame blend with parallax), the figures printed and
 * bounded below; the same measure of the model against itself moved a
 * quarter of a pixel gives about 0.94 on this tree. */
static void test_frames_are_the_model(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m, 3);
  bbc_impostor imp;
  build(&m, 6, 0, 6 * 6 * 128 * 128, 0, &imp);
  assert_int_equal(imp.frame_size, 128);
  double per[36], worst_own = 0, mean_own = 0;
  bbc_error err;
  assert_int_equal(bbc_impostor_check(&m, &imp, per, &worst_own, &mean_own, &err), BBC_OK);
  double lo = 1;
  for (int k = 0; k < 36; k++) lo = fmin(lo, per[k]);
  assert_true(lo == worst_own);
  double dirs[36 * 3], mid[30 * 3];
  int n = 0, nm = 0;
  for (int j = 0; j < 6; j++)
    for (int i = 0; i < 6; i++) {
      double d[3], r[3], u[3], d2[3];
      bbc_impostor_frame_basis(&imp, i, j, d, r, u);
      for (int k = 0; k < 3; k++) dirs[3 * n + k] = -d[k];
      n++;
      if (i < 5) {
        bbc_impostor_frame_basis(&imp, i + 1, j, d2, r, u);
        double l = 0, h[3];
        for (int k = 0; k < 3; k++) {
          h[k] = d[k] + d2[k];
          l += h[k] * h[k];
        }
        for (int k = 0; k < 3; k++) mid[3 * nm + k] = -h[k] / sqrt(l);
        nm++;
      }
    }
  print_message("own texels: block IoU worst %.3f mean %.3f\n", worst_own, mean_own);
  assert_true(worst_own >= 0.95);
  /* the measure can fail: another model (seed 5) against these frames */
  bbc_mesh other;
  tree(&other, 5);
  double w2, m2;
  assert_int_equal(bbc_impostor_check(&other, &imp, NULL, &w2, &m2, &err), BBC_OK);
  print_message("another tree against these frames: worst %.3f mean %.3f\n", w2, m2);
  assert_true(m2 < 0.9);
  bbc_mesh_free(&other);
  double worst, mean;
  judge(&m, &imp, dirs, n, &worst, &mean);
  print_message("eval, frame directions: block IoU worst %.3f mean %.3f\n", worst, mean);
  assert_true(worst >= 0.85);
  judge(&m, &imp, mid, nm, &worst, &mean);
  print_message("eval, between frames: block IoU worst %.3f mean %.3f\n", worst, mean);
  assert_true(worst >= 0.75);
  assert_true(mean >= 0.8);
  bbc_impostor_free(&imp);
  bbc_mesh_free(&m);
}

/* An octahedral impostor sees its model from below as well; a
 * hemi-octahedral one does not have those frames (its horizon's stand in). */
static void test_full_sphere_from_below(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m, 5);
  bbc_impostor full, hemi;
  build(&m, 8, 1, 8 * 8 * 48 * 48, 0, &full);
  build(&m, 8, 0, 8 * 8 * 48 * 48, 0, &hemi);
  double below[3 * 3] = {0.3, 0.9, 0.2, -0.5, 0.8, 0.1, 0.05, 1, -0.1}; /* looking up */
  for (int k = 0; k < 3; k++) {
    double *d = below + 3 * k, l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int c = 0; c < 3; c++) d[c] /= l;
  }
  double wf, mf, wh, mh;
  judge(&m, &full, below, 3, &wf, &mf);
  judge(&m, &hemi, below, 3, &wh, &mh);
  print_message("from below: octahedral %.3f, hemi-octahedral %.3f (mean block IoU)\n", mf, mh);
  assert_true(wf >= 0.7);
  assert_true(mf > mh + 0.1);
  bbc_impostor_free(&full);
  bbc_impostor_free(&hemi);
  bbc_mesh_free(&m);
}

/* Two squares facing +z at z = +0.5 and z = -0.5 (up = y): the frame that
 * looks along -z stores the near square's depth where it covers (nearer
 * the viewer: negative) and the far one's beside it. */
static void test_depths(void **state) {
  (void)state;
  bbc_mesh m;
  tu_mesh_begin(&m, 4, 1, (const char *const[]){"m"}, NULL, "g");
  tu_mesh_quad(&m, (double[3]){-1, -1, 0.5}, (double[3]){0, -1, 0.5}, (double[3]){0, 1, 0.5},
               (double[3]){-1, 1, 0.5}, 0);
  tu_mesh_quad(&m, (double[3]){0, -1, -0.5}, (double[3]){1, -1, -0.5}, (double[3]){1, 1, -0.5},
               (double[3]){0, 1, -0.5}, 0);
  bbc_error e;
  assert_int_equal(bbc_mesh_finalize(&m, 1, "squares", &e), BBC_OK);
  bbc_impostor imp;
  build(&m, 3, 1, 3 * 3 * 64 * 64, 1, &imp);
  /* the full octahedron's frame (1, 1) looks from +y (the top), (2, 1) from +x, (1, 2) from +z */
  int fi = -1, fj = -1;
  for (int j = 0; j < 3; j++)
    for (int i = 0; i < 3; i++) {
      double d[3], r[3], u[3];
      bbc_impostor_frame_basis(&imp, i, j, d, r, u);
      if (d[2] > 0.999) fi = i, fj = j;
    }
  assert_true(fi >= 0);
  int s = imp.frame_size, near = 0, far = 0;
  for (int y = 0; y < s; y++)
    for (int x = 0; x < s; x++) {
      size_t o = (size_t)(fj * s + y) * imp.albedo.width + (size_t)(fi * s + x);
      if (!imp.albedo.rgba[4 * o + 3]) continue;
      double d = (imp.normal.rgba[4 * o + 3] / 127.5 - 1) * imp.radius;
      double nz = imp.normal.rgba[4 * o + 2] / 127.5 - 1;
      assert_true(nz > 0.95); /* the model's +z, towards this frame's viewer */
      if (fabs(d + 0.5) < 0.02) near++;
      if (fabs(d - 0.5) < 0.02) far++;
    }
  assert_true(near > s * s / 8 && far > s * s / 8);
  bbc_impostor_free(&imp);
  bbc_mesh_free(&m);
}

static void test_threads_and_round_trip(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m, 3);
  bbc_impostor a, b, c;
  build(&m, 4, 0, 4 * 4 * 32 * 32, 1, &a);
  build(&m, 4, 0, 4 * 4 * 32 * 32, 3, &b);
  size_t bytes = 4 * (size_t)a.albedo.width * a.albedo.height;
  assert_memory_equal(a.albedo.rgba, b.albedo.rgba, bytes);
  assert_memory_equal(a.normal.rgba, b.normal.rgba, bytes);
  char dir[] = "/tmp/bbc_impostor_XXXXXX", path[256];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/tree.json", dir);
  bbc_error err;
  assert_int_equal(bbc_impostor_write(path, &a, &err), BBC_OK);
  assert_int_equal(bbc_impostor_read(path, &c, &err), BBC_OK);
  assert_int_equal(c.frames, a.frames);
  assert_int_equal(c.frame_size, a.frame_size);
  assert_int_equal(c.padding, a.padding);
  assert_int_equal(c.hemi, a.hemi);
  assert_int_equal(c.up, a.up);
  for (int k = 0; k < 3; k++) assert_true(c.center[k] == a.center[k]);
  assert_true(c.radius == a.radius && c.half_extent == a.half_extent);
  assert_memory_equal(c.albedo.rgba, a.albedo.rgba, bytes);
  assert_memory_equal(c.normal.rgba, a.normal.rgba, bytes);
  bbc_impostor_free(&c);
  /* a descriptor that lies is refused, and says what it lacks */
  FILE *fp = fopen(path, "w");
  fputs("{\"format\": \"bbc-impostor\", \"layout\": \"cubic\"}", fp);
  fclose(fp);
  assert_int_equal(bbc_impostor_read(path, &c, &err), BBC_ERROR_CORRUPT);
  assert_non_null(strstr(err.message, "layout"));
  char f1[300], f2[300];
  snprintf(f1, sizeof f1, "%s/tree_json_albedo.png", dir);
  snprintf(f2, sizeof f2, "%s/tree_json_normal.png", dir);
  assert_int_equal(unlink(f1), 0);
  assert_int_equal(unlink(f2), 0);
  unlink(path);
  rmdir(dir);
  bbc_impostor_free(&a);
  bbc_impostor_free(&b);
  bbc_impostor_free(&c);
  bbc_mesh_free(&m);
}

static void test_bad_options(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m, 3);
  bbc_impostor imp;
  bbc_impostor_options o;
  bbc_error err;
  bbc_impostor_options_default(&o);
  o.frames = 1;
  assert_int_equal(bbc_impostor_build(&m, &o, &imp, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_null(imp.albedo.rgba);
  o.frames = 16;
  o.texels = 16 * 16 * 7 * 7; /* 7-texel frames */
  assert_int_equal(bbc_impostor_build(&m, &o, &imp, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "texels"));
  o.texels = 0;
  o.samples = 5;
  assert_int_equal(bbc_impostor_build(&m, &o, &imp, &err), BBC_ERROR_INVALID_ARGUMENT);
  bbc_mesh empty;
  memset(&empty, 0, sizeof empty);
  assert_int_equal(bbc_impostor_build(&empty, NULL, &imp, &err), BBC_ERROR_EMPTY);
  bbc_mesh_free(&m);
}

/* Lit by a sun, an impostor is as bright as its tree: the Scopia pine's
 * needles give texels whose samples' normals point every way, and a
 * renormalised mean normal lit them 4-14 % too bright. Its octahedral and
 * hemi-octahedral impostors (8 x 8 frames, 1M texels), 16 views above the
 * horizon at 128 px, three suns: luminance within 6 % of the tree's. */
static void test_sunlit_like_the_tree(void **state) {
  (void)state;
  char path[4096];
  tu_data_path(path, sizeof path, "trees/scopia/pine/pine.obj");
  if (!tu_have_file(path)) skip();
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, NULL, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  double dirs[16 * 3];
  for (int k = 0; k < 16; k++) { /* camera towards the model, from above or level */
    double az = 2 * 3.14159265358979 * (k + 0.5) / 16, el = (k % 4) * 20.0 * 3.14159265358979 / 180;
    dirs[3 * k] = -cos(el) * sin(az);
    dirs[3 * k + 1] = -sin(el);
    dirs[3 * k + 2] = -cos(el) * cos(az);
  }
  const double suns[3][3] = {{0.5, 0.7, 0.5}, {-0.6, 0.5, 0.2}, {0, 1, 0}};
  for (int full = 0; full < 2; full++) {
    bbc_impostor imp;
    build(&m, 8, full, 1 << 20, 0, &imp);
    for (int s = 0; s < 3; s++) {
      bbc_eval_options o;
      bbc_eval_options_default(&o);
      o.directions = dirs;
      o.direction_count = 16;
      o.size = 128;
      o.impostor = &imp;
      o.lighting = o.sun = 1;
      double l = sqrt(suns[s][0] * suns[s][0] + suns[s][1] * suns[s][1] + suns[s][2] * suns[s][2]);
      for (int k = 0; k < 3; k++) o.light[k] = suns[s][k] / l;
      bbc_eval_result r;
      if (bbc_eval(&m, NULL, &o, &r, &err) != BBC_OK) fail_msg("%s", err.message);
      print_message("%s, sun %d: luminance %.3f of the tree's\n",
                    full ? "octahedral" : "hemi-octahedral", s, r.luminance_ratio);
      assert_true(fabs(r.luminance_ratio - 1) <= 0.06);
      bbc_eval_result_free(&r);
    }
    bbc_impostor_free(&imp);
  }
  bbc_mesh_free(&m);
}

/* A point cloud's impostor is drawn from its splats (all of them: it was
 * empty when none was passed) with their depths, covers about as much as
 * the points, and its frames match them (bbc_impostor_check). */
static void test_points(void **state) {
  (void)state;
  bbc_mesh m, pts;
  tree(&m, 5);
  bbc_error err;
  assert_int_equal(bbc_mesh_sample_points(&m, 20000, 1, &pts, &err), BBC_OK);
  bbc_impostor imp;
  build(&pts, 6, 1, 6 * 6 * 64 * 64, 0, &imp);
  bbc_eval_options o;
  bbc_eval_options_default(&o);
  o.views = 8;
  o.size = 96;
  o.impostor = &imp;
  bbc_eval_result r;
  if (bbc_eval(&pts, NULL, &o, &r, &err) != BBC_OK) fail_msg("%s", err.message);
  print_message("points: coverage ratio %.3f, IoU %.3f\n", r.coverage_ratio_mean, r.iou_mean);
  /* with the splats' depths the frames' parallax follows the points (0.61
   * when every splat lay on the centre plane) */
  assert_true(r.coverage_ratio_mean > 0.85 && r.coverage_ratio_mean < 1.15);
  assert_true(r.iou_mean > 0.68);
  bbc_eval_result_free(&r);
  double worst, mean;
  assert_int_equal(bbc_impostor_check(&pts, &imp, NULL, &worst, &mean, &err), BBC_OK);
  print_message("points: frames against the points worst %.3f mean %.3f\n", worst, mean);
  assert_true(worst > 0.9);
  bbc_impostor_free(&imp);
  bbc_mesh_free(&pts);
  bbc_mesh_free(&m);
}

/* Covered pixels (alpha >= 128) of an image, as a share of its area. */
static double covered_share(const bbc_image *im) {
  size_t n = (size_t)im->width * im->height, c = 0;
  for (size_t i = 0; i < n; i++) c += im->rgba[4 * i + 3] >= 128;
  return (double)c / (double)n;
}

/* The atlases' mip levels (bbc_impostor_level): level 0 the atlases, each
 * level's frames keep their coverage and colour, its alpha binary; out of
 * range refused; drawn far away at the level a pixel's size picks, the
 * impostor covers what its model covers. A frame size that is no power of
 * two (100: levels of 100, 50, 25, 12, 6, 3 and 1 texels). */
static void test_levels(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m, 4);
  bbc_impostor imp;
  build(&m, 6, 0, 6 * 6 * 100 * 100, 0, &imp);
  assert_int_equal(imp.frame_size, 100);
  int count = bbc_impostor_level_count(&imp);
  assert_int_equal(count, 7);
  const int sizes[7] = {100, 50, 25, 12, 6, 3, 1};
  for (int l = 0; l < count; l++) assert_int_equal(bbc_impostor_level_size(&imp, l), sizes[l]);
  bbc_image a, nm;
  bbc_error err;
  assert_int_equal(bbc_impostor_level(&imp, count, &a, &nm, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_null(a.rgba);
  assert_int_equal(bbc_impostor_level(&imp, -1, &a, &nm, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_impostor_level(&imp, 0, &a, &nm, &err), BBC_OK);
  size_t bytes = 4 * (size_t)imp.albedo.width * imp.albedo.height;
  assert_memory_equal(a.rgba, imp.albedo.rgba, bytes);
  assert_memory_equal(nm.rgba, imp.normal.rgba, bytes);
  bbc_image_free(&a);
  bbc_image_free(&nm);
  int S = imp.frame_size, W0 = imp.albedo.width;
  double worst_cov = 0, worst_col = 0;
  for (int l = 1; l < count - 1; l++) {
    assert_int_equal(bbc_impostor_level(&imp, l, &a, &nm, &err), BBC_OK);
    int s = sizes[l], W = a.width;
    assert_int_equal(W, 6 * s);
    for (int j = 0; j < 6; j++)
      for (int i = 0; i < 6; i++) {
        double c0 = 0, cl = 0, col0[3] = {0, 0, 0}, coll[3] = {0, 0, 0};
        for (int y = 0; y < S; y++)
          for (int x = 0; x < S; x++) {
            const uint8_t *p =
                imp.albedo.rgba + 4 * ((size_t)(j * S + y) * W0 + (size_t)(i * S + x));
            if (!p[3]) continue;
            c0++;
            for (int k = 0; k < 3; k++) col0[k] += p[k];
          }
        for (int y = 0; y < s; y++)
          for (int x = 0; x < s; x++) {
            size_t o = 4 * ((size_t)(j * s + y) * W + (size_t)(i * s + x));
            const uint8_t *p = a.rgba + o, *e = nm.rgba + o;
            assert_true(p[3] == 0 || p[3] == 255);
            if (!p[3]) continue;
            cl++;
            double len = 0;
            for (int k = 0; k < 3; k++) {
              coll[k] += p[k];
              len += (e[k] / 127.5 - 1) * (e[k] / 127.5 - 1);
            }
            assert_true(sqrt(len) <= 1.02);
          }
        if (c0 < 1) continue;
        double f0 = c0 / ((double)S * S), fl = cl / ((double)s * s);
        /* off by at most 2 % of the covered texels and two (error
         * diffusion's last residual, and what non-candidates absorb) */
        worst_cov = fmax(worst_cov, (fabs(fl - f0) * s * s - 2) / (f0 * s * s));
        for (int k = 0; k < 3 && cl > 0; k++)
          worst_col = fmax(worst_col, fabs(coll[k] / cl - col0[k] / c0));
      }
    bbc_image_free(&a);
    bbc_image_free(&nm);
  }
  print_message("levels: coverage off by %.3f of the covered texels (less two), colour by %.1f at "
                "worst\n",
                worst_cov, worst_col);
  assert_true(worst_cov <= 0.02);
  assert_true(worst_col <= 12.0);
  /* far away: 24 pixels across (about 4 frame texels a pixel, level 2) */
  bbc_view v;
  bbc_impostor_frame_view(&imp, 2, 3, &v);
  bbc_image far, fine;
  assert_int_equal(bbc_image_alloc(&far, 24, 24), BBC_OK);
  assert_int_equal(bbc_image_alloc(&fine, 24 * 8, 24 * 8), BBC_OK);
  assert_int_equal(bbc_render_ortho(&m, &v, &fine, &err), BBC_OK);
  double want = covered_share(&fine), got[2];
  for (int k = 0; k < 2; k++) {
    assert_int_equal(bbc_impostor_render_level(&imp, &v, k ? -1 : 0, &far, &err), BBC_OK);
    got[k] = covered_share(&far) / want;
  }
  print_message("24 pixels: coverage ratio %.3f at level 0, %.3f at level 2\n", got[0], got[1]);
  assert_true(got[1] > 0.85 && got[1] < 1.15);
  assert_int_equal(bbc_impostor_render_level(&imp, &v, 99, &far, &err), BBC_OK); /* the last */
  bbc_image_free(&far);
  bbc_image_free(&fine);
  bbc_impostor_free(&imp);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_frames_are_the_model),
      cmocka_unit_test(test_full_sphere_from_below),
      cmocka_unit_test(test_depths),
      cmocka_unit_test(test_threads_and_round_trip),
      cmocka_unit_test(test_bad_options),
      cmocka_unit_test(test_sunlit_like_the_tree),
      cmocka_unit_test(test_points),
      cmocka_unit_test(test_levels),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
