/* test_eval.c — fidelity metrics (bbc_eval): a model against itself, against
 * a moved copy, and two quads with an analytic overlap; the baselines
 * (crossed billboards, meshoptimizer) and how they score. */
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
#include "test_util.h"

static void tree(bbc_mesh *m) {
  bbc_tree_options o;
  bbc_tree_options_default(&o);
  o.seed = 1; /* the tree these checks were written for */
  o.seed = 3;
  o.leaves = 3000;
  o.texture_size = 64;
  bbc_error err;
  if (bbc_tree_generate(&o, m, &err) != BBC_OK) fail_msg("%s", err.message);
}

static void test_self_and_moved(void **state) {
  (void)state;
  bbc_mesh a, b;
  tree(&a);
  tree(&b);
  bbc_eval_options o;
  bbc_eval_options_default(&o);
  o.views = 24;
  o.size = 128;
  bbc_eval_result r;
  bbc_error err;
  assert_int_equal(bbc_eval(&a, &b, &o, &r, &err), BBC_OK);
  assert_int_equal(r.view_count, 24);
  assert_true(r.side_count > 0 && r.side_count < 24);
  assert_true(r.iou_mean == 1.0 && r.iou_min == 1.0 && r.iou_side_mean == 1.0);
  assert_true(r.recall_mean == 1.0 && r.false_mean == 0.0);
  assert_true(r.psnr_mean >= 60 && r.mae_mean == 0);
  bbc_eval_result_free(&r);
  /* Moved by 5 % of the radius along x: clearly worse, from every side. */
  for (size_t v = 0; v < b.vertex_count; v++) b.positions[3 * v] += 0.05 * a.radius;
  if (bbc_mesh_finalize(&b, 1, "moved", &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(bbc_eval(&a, &b, &o, &r, &err), BBC_OK);
  printf("moved: iou %.3f side %.3f psnr %.1f\n", r.iou_mean, r.iou_side_mean, r.psnr_mean);
  assert_true(r.iou_mean < 0.85 && r.iou_side_mean < 0.85);
  assert_true(r.psnr_mean < 40);
  /* Same numbers with one thread. */
  bbc_eval_result r1;
  o.threads = 1;
  assert_int_equal(bbc_eval(&a, &b, &o, &r1, &err), BBC_OK);
  for (size_t k = 0; k < r.view_count; k++) {
    assert_true(r.views[k].iou == r1.views[k].iou);
    assert_true(r.views[k].psnr == r1.views[k].psnr);
  }
  bbc_eval_result_free(&r);
  bbc_eval_result_free(&r1);
  bbc_mesh_free(&a);
  bbc_mesh_free(&b);
}

/* n opaque red quads at z = 0, 1 high, `width` wide, the k-th from
 * x0 + k * period. */
static void stripes(bbc_mesh *m, double x0, double width, int n, double period) {
  static const float red[1][4] = {{1, 0, 0, 1}};
  static const char *const names[1] = {"red"};
  tu_mesh_begin(m, 2 * (size_t)n, 1, names, red, "q");
  for (int k = 0; k < n; k++) {
    double x = x0 + k * period;
    const double p[4][3] = {{x, 0, 0}, {x + width, 0, 0}, {x + width, 1, 0}, {x, 1, 0}};
    tu_mesh_quad(m, p[0], p[1], p[2], p[3], 0);
  }
  bbc_error err;
  if (bbc_mesh_finalize(m, 0, "quad", &err) != BBC_OK) fail_msg("%s", err.message);
}

/* A unit quad at z = 0 from x0 to x0 + 1, opaque red. */
static void quad(bbc_mesh *m, double x0) {
  stripes(m, x0, 1, 1, 1);
}

static void test_two_quads(void **state) {
  (void)state;
  bbc_mesh a, b;
  quad(&a, 0);
  quad(&b, 0.5);
  const double dirs[6] = {0, 0, -1, 0, 0, 1};
  bbc_eval_options o;
  bbc_eval_options_default(&o);
  o.directions = dirs;
  o.direction_count = 2;
  o.size = 512;
  bbc_eval_result r;
  bbc_error err;
  assert_int_equal(bbc_eval(&a, &b, &o, &r, &err), BBC_OK);
  for (int k = 0; k < 2; k++) {
    const bbc_eval_view *v = &r.views[k];
    printf("view %d: iou %.4f recall %.4f false %.4f\n", k, v->iou, v->recall, v->false_coverage);
    /* Overlap 0.5, union 1.5: IoU 1/3, recall 1/2, false coverage 1/2;
     * pixel edges cost at most a few pixel columns of 512. */
    assert_true(fabs(v->iou - 1.0 / 3.0) < 0.01);
    assert_true(fabs(v->recall - 0.5) < 0.01);
    assert_true(fabs(v->false_coverage - 0.5) < 0.01);
    /* Same colour where both cover: no colour error. */
    assert_true(v->mae == 0.0);
  }
  assert_true(fabs(r.iou_mean - 1.0 / 3.0) < 0.01);
  bbc_eval_result_free(&r);
  /* The sheet labels each difference cell with the view's coverage ratio
   * and block IoU in black digits on white, top left: "1.00". */
  bbc_image sheet = {0, 0, NULL};
  o.sheet = &sheet;
  assert_int_equal(bbc_eval(&a, &b, &o, &r, &err), BBC_OK);
  assert_int_equal(sheet.width, 3 * o.size);
  size_t black = 0, white = 0;
  for (int y = 2; y < 2 + 16; y++)
    for (int x = 2 * o.size + 2; x < 2 * o.size + 2 + 34; x++) {
      const uint8_t *p = sheet.rgba + 4 * ((size_t)y * sheet.width + x);
      black += p[0] == 0 && p[1] == 0 && p[2] == 0;
      white += p[0] == 255 && p[1] == 255 && p[2] == 255;
    }
  assert_true(black > 20 && white > 100);
  bbc_image_free(&sheet);
  o.sheet = NULL;
  /* As many pixels each: coverage ratio 1. */
  assert_true(fabs(r.coverage_ratio_mean - 1.0) < 0.01);
  assert_true(fabs(r.views[0].coverage_ratio - 1.0) < 0.01);
  bbc_eval_result_free(&r);
  /* Density: 64 stripes 1/128 wide (about 4 pixels) against the same
   * stripes shifted by their width. Pixel by pixel they never overlap
   * (IoU 0), but every 16-pixel block is half covered by each: seen 8x
   * farther they are the same (block IoU 1, coverage ratio 1). Against a
   * solid quad: half as dense (ratio 0.5, block IoU 0.5). */
  bbc_mesh s1, s2;
  stripes(&s1, 0, 1.0 / 128, 64, 1.0 / 64);
  stripes(&s2, 1.0 / 128, 1.0 / 128, 64, 1.0 / 64);
  assert_int_equal(bbc_eval(&s1, &s2, &o, &r, &err), BBC_OK);
  printf("stripes: iou %.4f coverage ratio %.4f block iou %.4f\n", r.iou_mean,
         r.coverage_ratio_mean, r.block_iou_mean);
  assert_true(r.iou_mean < 0.05);
  assert_true(fabs(r.coverage_ratio_mean - 1.0) < 0.05);
  assert_true(r.block_iou_mean > 0.9);
  bbc_eval_result_free(&r);
  bbc_mesh solid;
  stripes(&solid, 0, 1.0 / 128 + 63.0 / 64, 1, 1);
  assert_int_equal(bbc_eval(&solid, &s1, &o, &r, &err), BBC_OK);
  printf("solid vs stripes: coverage ratio %.4f block iou %.4f\n", r.coverage_ratio_mean,
         r.block_iou_mean);
  assert_true(fabs(r.coverage_ratio_mean - 0.5) < 0.05);
  assert_true(fabs(r.block_iou_mean - 0.5) < 0.05);
  assert_true(r.side_count == 2 && fabs(r.block_iou_side_mean - r.block_iou_mean) < 1e-12);
  bbc_eval_result_free(&r);
  bbc_mesh_free(&s1);
  bbc_mesh_free(&s2);
  bbc_mesh_free(&solid);
  /* Bad options are refused. */
  o.directions = NULL;
  o.direction_count = 0;
  o.views = -1;
  assert_int_equal(bbc_eval(&a, &b, &o, &r, &err), BBC_ERROR_INVALID_ARGUMENT);
  /* Zeroed options are the defaults: 64 views of 256 pixels. */
  bbc_eval_options zero;
  memset(&zero, 0, sizeof zero);
  zero.size = 32; /* (quicker; the default size is checked below) */
  assert_int_equal(bbc_eval(&a, &b, &zero, &r, &err), BBC_OK);
  assert_int_equal(r.view_count, 64);
  bbc_eval_result_free(&r);
  bbc_eval_options_default(&o);
  assert_memory_equal(&o, &(bbc_eval_options){0}, sizeof o);
  bbc_mesh_free(&a);
  bbc_mesh_free(&b);
}

static void test_baselines(void **state) {
  (void)state;
  bbc_mesh m;
  tree(&m);
  bbc_params p;
  bbc_params_default(&p);
  p.prelight = 0;
  p.threads = 1;
  bbc_error err;
  /* Crossed billboards: 3 vertical + 1 horizontal, about the texel budget. */
  bbc_cloud x;
  assert_int_equal(bbc_baseline_crossed(&m, 3, 1, &p, 200000, NULL, &x, &err), BBC_OK);
  assert_int_equal(x.billboard_count, 4);
  for (size_t k = 0; k < 4; k++) {
    const bbc_cloud_billboard *b = &x.billboards[k];
    assert_int_equal(b->corner_count, 4); /* the whole rectangle */
    double up = b->normal[1];
    if (k < 3)
      assert_true(fabs(up) < 1e-9); /* vertical */
    else
      assert_true(fabs(up - 1) < 1e-9); /* horizontal */
  }
  assert_true(x.texels >= 200000 / 2 && x.texels <= 200000 * 2);
  /* The vertical billboards span the whole model's height. */
  assert_true(fabs(x.mesh.bbox_max[1] - m.bbox_max[1]) < 1e-6 * m.radius);
  assert_true(fabs(x.mesh.bbox_min[1] - m.bbox_min[1]) < 1e-6 * m.radius);
  bbc_eval_options o;
  bbc_eval_options_default(&o);
  o.views = 16;
  o.size = 96;
  bbc_eval_result r;
  assert_int_equal(bbc_eval(&m, &x.mesh, &o, &r, &err), BBC_OK);
  printf("crossed 3+h: iou %.3f side %.3f\n", r.iou_mean, r.iou_side_mean);
  assert_true(r.iou_mean > 0.2 && r.iou_mean < 1.0);
  bbc_eval_result_free(&r);
  bbc_cloud_free(&x);
  /* meshoptimizer: sloppy reaches the target; both keep UVs and textures. */
  for (int sloppy = 0; sloppy <= 1; sloppy++) {
    bbc_mesh s;
    size_t target = m.triangle_count / 10;
    assert_int_equal(bbc_baseline_simplify(&m, target, sloppy, &s, &err), BBC_OK);
    printf("%s: %zu of %zu triangles (target %zu)\n", sloppy ? "sloppy" : "simplify",
           s.triangle_count, m.triangle_count, target);
    assert_true(s.triangle_count < m.triangle_count);
    if (sloppy) assert_true(s.triangle_count <= target + target / 10);
    assert_non_null(s.uvs);
    assert_int_equal(s.material_count, m.material_count);
    assert_int_equal(s.texture_count, m.texture_count);
    assert_int_equal(bbc_eval(&m, &s, &o, &r, &err), BBC_OK);
    assert_true(r.iou_mean > 0.05 && r.iou_mean < 1.0);
    bbc_eval_result_free(&r);
    bbc_mesh_free(&s);
  }
  /* A target above the model's count keeps it whole. */
  bbc_mesh s;
  assert_int_equal(bbc_baseline_simplify(&m, 10 * m.triangle_count, 1, &s, &err), BBC_OK);
  assert_int_equal(s.triangle_count, m.triangle_count);
  bbc_mesh_free(&s);
  bbc_mesh_free(&m);
}

/* The engine's lighting (bbc_view.sun) on a red quad facing +z, seen
 * from +z: without maps the sun from the front lights it fully and a sun
 * from the side leaves the ambient light; a normal map turning every
 * texel's normal to +x (through a +x tangent) swaps the two; an occlusion
 * map at half darkens the ambient light by half. */
static void test_sun_lighting(void **state) {
  (void)state;
  bbc_mesh m;
  quad(&m, 0);
  m.uvs = calloc(2 * m.vertex_count, sizeof(float));
  m.tangents = calloc(4 * m.vertex_count, sizeof(float));
  for (size_t v = 0; v < m.vertex_count; v++) {
    m.uvs[2 * v] = (float)m.positions[3 * v];
    m.uvs[2 * v + 1] = (float)m.positions[3 * v + 1];
    m.tangents[4 * v] = 1;
    m.tangents[4 * v + 3] = 1;
  }
  m.textures = calloc(2, sizeof(bbc_texture));
  m.texture_count = 2;
  const uint8_t texel[2][4] = {{255, 128, 128, 255}, {128, 128, 128, 255}};
  for (int t = 0; t < 2; t++) {
    assert_int_equal(bbc_image_alloc(&m.textures[t].image, 1, 1), BBC_OK);
    memcpy(m.textures[t].image.rgba, texel[t], 4);
  }
  bbc_view v;
  const double dir[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  bbc_view_frame_mesh(&m, dir, up, &v);
  v.sun = 1;
  v.sun_ambient = 0.4;
  v.background[3] = 0;
  bbc_image img;
  assert_int_equal(bbc_image_alloc(&img, 16, 16), BBC_OK);
  const double front[3] = {0, 0, 1}, side[3] = {1, 0, 0};
  const double lit = 255.0, amb = 255.0 * 0.4 / 1.4;
  /* normal map, occlusion map, light, expected red */
  const struct {
    int nm, ao;
    const double *light;
    double red;
  } cases[] = {{0, 0, front, lit},
               {0, 0, side, amb},
               {1, 0, front, amb},
               {1, 0, side, lit},
               {0, 1, side, amb * 128 / 255},
               {1, 1, side, lit - amb + amb * 128 / 255}};
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    m.materials[0].normal_map = cases[i].nm ? 1 : 0;
    m.materials[0].occlusion_map = cases[i].ao ? 2 : 0;
    memcpy(v.light, cases[i].light, sizeof v.light);
    bbc_error err;
    assert_int_equal(bbc_render_ortho(&m, &v, &img, &err), BBC_OK);
    const uint8_t *px = img.rgba + 4 * (8 * 16 + 8);
    assert_int_equal(px[3], 255);
    if (fabs(px[0] - cases[i].red) > 1.5 || px[1] != 0)
      fail_msg("case %zu: red %d, want %.1f", i, px[0], cases[i].red);
  }
  bbc_image_free(&img);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_self_and_moved),
      cmocka_unit_test(test_two_quads),
      cmocka_unit_test(test_baselines),
      cmocka_unit_test(test_sun_lighting),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
