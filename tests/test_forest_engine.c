/* test_forest_engine.c — the forest engine's GL-free parts: frustum tests,
 * the LOD blending weights (thesis 3.2.3), culling over the grid, the
 * terrain quadtree (CDLOD: neighbours at most one level apart, no holes),
 * the prelit colour map with shadows, coverage-keeping alpha mipmaps, the
 * camera and stored positions, the demo landscape. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bbc_forest.h"
#include "test_util.h"

/* A flat or hilly world of (n+1)^2 vertices, without files. */
static void make_world(bbc_forest_world *w, int n, double spacing, int hilly) {
  memset(w, 0, sizeof *w);
  w->width = w->depth = n + 1;
  w->spacing = spacing;
  w->heightmap_bits = 8;
  w->height = calloc((size_t)(n + 1) * (n + 1), sizeof *w->height);
  assert_non_null(w->height);
  for (int z = 0; z <= n; z++)
    for (int x = 0; x <= n; x++)
      w->height[(size_t)z * (n + 1) + x] =
          hilly ? (float)(20 * sin(x * 0.1) * cos(z * 0.07) + 20) : 0.0f;
  w->green_fraction = 1;
}

static void look(bbc_forest_camera *c, double x, double y, double z, double yaw, double pitch) {
  c->pos[0] = x;
  c->pos[1] = y;
  c->pos[2] = z;
  c->yaw = yaw;
  c->pitch = pitch;
  c->zoom = 1;
}

static void test_frustum(void **state) {
  (void)state;
  bbc_forest_camera c;
  look(&c, 0, 0, 0, 0, 0); /* looks along -z */
  float vp[16];
  bbc_forest_camera_get_viewproj(&c, 1.0, 0.1, 100, vp);
  double p[6][4];
  bbc_forest_frustum_from_matrix(vp, p);
  double lo[3] = {-1, -1, -11}, hi[3] = {1, 1, -9};
  assert_int_equal(bbc_forest_frustum_test_box(p, lo, hi), 2); /* ahead */
  double lo2[3] = {-1, -1, 9}, hi2[3] = {1, 1, 11};
  assert_int_equal(bbc_forest_frustum_test_box(p, lo2, hi2), 0); /* behind */
  double lo3[3] = {-1, -1, -200}, hi3[3] = {1, 1, -50};
  assert_int_equal(bbc_forest_frustum_test_box(p, lo3, hi3), 1); /* crosses the far plane */
  double lo4[3] = {30, -1, -11}, hi4[3] = {40, 1, -9};
  assert_int_equal(bbc_forest_frustum_test_box(p, lo4, hi4), 0); /* far to the right */
  /* yaw 90 looks along +x */
  look(&c, 0, 0, 0, 90, 0);
  bbc_forest_camera_get_viewproj(&c, 1.0, 0.1, 100, vp);
  bbc_forest_frustum_from_matrix(vp, p);
  double lo5[3] = {9, -1, -1}, hi5[3] = {11, 1, 1};
  assert_int_equal(bbc_forest_frustum_test_box(p, lo5, hi5), 2);
}

static void test_lod_weights(void **state) {
  (void)state;
  double ranges[6] = {0, 100, 100, 300, 300, 1000};
  bbc_forest_lod_model m = {3, ranges, 10, 5};
  /* far from a switch: one level, whole */
  assert_true(bbc_forest_lod_get_weight(&m, 0, 50) == 1 &&
              bbc_forest_lod_get_weight(&m, 1, 50) == 0);
  /* the next level blends in before the switch while the first is whole */
  assert_true(bbc_forest_lod_get_weight(&m, 0, 95) == 1);
  assert_true(fabs(bbc_forest_lod_get_weight(&m, 1, 95) - 0.5) < 1e-9);
  /* at the switch both are whole; after it the first fades out */
  assert_true(bbc_forest_lod_get_weight(&m, 0, 100) == 1 &&
              bbc_forest_lod_get_weight(&m, 1, 100) == 1);
  assert_true(fabs(bbc_forest_lod_get_weight(&m, 0, 105) - 0.5) < 1e-9);
  assert_true(bbc_forest_lod_get_weight(&m, 0, 110) == 0 &&
              bbc_forest_lod_get_weight(&m, 1, 110) == 1);
  /* the last level fades out past its max; nothing beyond */
  assert_true(fabs(bbc_forest_lod_get_weight(&m, 2, 1005) - 0.5) < 1e-9);
  assert_true(bbc_forest_lod_get_weight(&m, 2, 1011) == 0);
  /* fade 0: a hard switch */
  m.fade = 0;
  assert_true(bbc_forest_lod_get_weight(&m, 0, 99.9) == 1 &&
              bbc_forest_lod_get_weight(&m, 1, 99.9) == 0);
  assert_true(bbc_forest_lod_get_weight(&m, 0, 100) == 0 &&
              bbc_forest_lod_get_weight(&m, 1, 100) == 1);
  /* always: weights are continuous in distance with fade > 0 */
  m.fade = 10;
  for (size_t l = 0; l < 3; l++)
    for (double d = 0; d < 1100; d += 0.5)
      assert_true(fabs(bbc_forest_lod_get_weight(&m, l, d + 0.5) -
                       bbc_forest_lod_get_weight(&m, l, d)) <= 0.05 + 1e-9);
}

/* The culling's records and last frame (bbc_forest_cull_get_records). */
static bbc_forest_records rec_of(const bbc_forest_cull *c) {
  bbc_forest_records r;
  bbc_forest_cull_get_records(c, &r);
  return r;
}

/* The cell culling's frame against the flat one (the thesis's, tree by
 * tree), `nb` buckets, bucket b a level of model model_of[b]: every record
 * the flat way draws (weight > 0) is drawn by the cells' ranges with the
 * same weight; the cells' ranges draw every record with the weight
 * bbc_forest_lod_get_weight gives at its distance (whole ranges: 1), and
 * what they draw beyond the flat way is outside the frustum (a cell the
 * frustum's boundary crosses). Returns how many records the cells drew. */
static size_t check_against_flat(bbc_forest_cull *c, const float vp[16], const double eye[3],
                                 double zoom, const bbc_forest_lod_model *models,
                                 const size_t *model_of, size_t nb) {
  bbc_forest_cull_run(c, vp, eye, zoom);
  size_t vis = rec_of(c).trees_visible, cap = rec_of(c).static_count * 3, na = 0, nf = 0;
  bbc_forest_draw *a = malloc(cap * sizeof *a), *fl = malloc(cap * sizeof *fl);
  size_t *ab = malloc(cap * sizeof *ab), *fb = malloc(cap * sizeof *fb);
  assert_true(a && fl && ab && fb);
  double planes[6][4];
  bbc_forest_frustum_from_matrix(vp, planes);
  for (size_t k = 0; k < nb; k++) {
    size_t n = bbc_forest_cull_get_bucket_size(c, k);
    bbc_forest_draw *tmp = malloc((n + 1) * sizeof *tmp);
    assert_non_null(tmp);
    bbc_forest_cull_copy_bucket(c, k, tmp);
    const bbc_forest_lod_model *m = &models[model_of[k]];
    size_t level = k;
    while (level > 0 && model_of[level - 1] == model_of[k]) level--;
    level = k - level;
    for (size_t i = 0; i < n; i++) {
      double d =
          sqrt(pow(tmp[i].x - eye[0], 2) + pow(tmp[i].y - eye[1], 2) + pow(tmp[i].z - eye[2], 2)) /
          zoom;
      assert_true(fabs(tmp[i].fade - (float)bbc_forest_lod_get_weight(m, level, d)) < 1e-6);
      if (tmp[i].fade <= 0) continue;
      assert_true(na < cap);
      a[na] = tmp[i];
      ab[na++] = k;
    }
    free(tmp);
  }
  bbc_forest_cull_run_flat(c, vp, eye, zoom);
  assert_true(rec_of(c).trees_visible <= vis);
  for (size_t k = 0; k < nb; k++)
    for (size_t j = rec_of(c).bucket_start[k]; j < rec_of(c).bucket_start[k + 1]; j++) {
      fl[nf] = rec_of(c).draws[j];
      fb[nf++] = k;
    }
  /* every flat record among the cells' */
  uint8_t *used = calloc(na + 1, 1);
  assert_non_null(used);
  for (size_t i = 0; i < nf; i++) {
    int found = 0;
    for (size_t j = 0; j < na && !found; j++)
      if (!used[j] && ab[j] == fb[i] && !memcmp(&a[j], &fl[i], sizeof *a)) found = 1, used[j] = 1;
    assert_true(found);
  }
  /* the cells' others are outside the frustum */
  for (size_t j = 0; j < na; j++) {
    if (used[j]) continue;
    double rad = models[model_of[ab[j]]].radius * a[j].scale;
    int out = 0;
    for (int q = 0; q < 6; q++)
      out |= planes[q][0] * a[j].x + planes[q][1] * a[j].y + planes[q][2] * a[j].z + planes[q][3] <
             -rad;
    assert_true(out);
  }
  free(used);
  free(a);
  free(fl);
  free(ab);
  free(fb);
  return na;
}

/* The cells' frame against the flat one from many viewpoints, with
 * blending, a hard switch and two components. */
static void test_cull_matches_flat(void **state) {
  (void)state;
  bbc_forest_world w;
  make_world(&w, 256, 4, 1); /* 1024 x 1024 units, hills */
  w.instance_count = 20000;
  w.instances = calloc(w.instance_count, sizeof *w.instances);
  assert_non_null(w.instances);
  uint32_t s = 7;
  for (size_t i = 0; i < w.instance_count; i++) {
    s = s * 1664525u + 1013904223u;
    w.instances[i].x = (float)(s >> 8) / (float)(1u << 24) * 1024;
    s = s * 1664525u + 1013904223u;
    w.instances[i].z = (float)(s >> 8) / (float)(1u << 24) * 1024;
    w.instances[i].y = (float)bbc_forest_world_get_height(&w, w.instances[i].x, w.instances[i].z);
    w.instances[i].scale = 0.8f + (float)(i % 5) * 0.1f;
    w.instances[i].yaw_deg = (float)(i * 53 % 360);
    w.instances[i].placement = (uint32_t)(i % 3);
  }
  double r0[6] = {0, 40, 40, 150, 150, 600}, r1[4] = {0, 90, 90, 2000}, r2[2] = {10, 300};
  bbc_forest_lod_model models[3] = {{3, r0, 6, 4}, {2, r1, 0, 3}, {1, r2, 10, 2}};
  uint32_t pm[3][2] = {{0, UINT32_MAX}, {1, 2}, {2, UINT32_MAX}};
  bbc_forest_cull *c;
  bbc_error err;
  assert_int_equal(bbc_forest_cull_build(&w, models, 3, (const uint32_t(*)[2])pm, 3, &c, &err),
                   BBC_OK);
  size_t model_of[6] = {0, 0, 0, 1, 1, 2};
  assert_int_equal(rec_of(c).bucket_count, 6);
  size_t whole = 0, blend = 0;
  for (int v = 0; v < 12; v++) {
    bbc_forest_camera cam;
    look(&cam, 80 + 70 * v, 30 + 5 * (v % 4), 900 - 60 * v, v * 31.0, -(v % 5) * 8.0);
    float vp[16];
    bbc_forest_camera_get_viewproj(&cam, 1.3, 0.5, 1500, vp);
    double zoom = v % 4 == 3 ? 2.5 : 1;
    assert_true(check_against_flat(c, vp, cam.pos, zoom, models, model_of, 6) > 0);
    bbc_forest_cull_run(c, vp, cam.pos, zoom);
    for (size_t b = 0; b < 6; b++) {
      whole += rec_of(c).range_blend[b] - rec_of(c).range_start[b];
      blend += rec_of(c).range_start[b + 1] - rec_of(c).range_blend[b];
    }
  }
  assert_true(whole > 0 && blend > 0);
  bbc_forest_cull_free(c);
  bbc_forest_world_free(&w);
}

static void test_cull(void **state) {
  (void)state;
  bbc_forest_world w;
  make_world(&w, 64, 4, 0); /* 256 x 256 units */
  /* a 16 x 16 grid of trees, two placements: one model; two components */
  w.instance_count = 256;
  w.instances = calloc(w.instance_count, sizeof *w.instances);
  assert_non_null(w.instances);
  for (int i = 0; i < 256; i++) {
    w.instances[i].x = (float)(8 + 16 * (i % 16));
    w.instances[i].z = (float)(8 + 16 * (i / 16));
    w.instances[i].scale = 1;
    w.instances[i].yaw_deg = (float)(i * 37 % 360);
    w.instances[i].placement = (uint32_t)(i % 2);
  }
  double r0[4] = {0, 50, 50, 1000}, r1[2] = {0, 1000};
  bbc_forest_lod_model models[2] = {{2, r0, 5, 3}, {1, r1, 0, 2}};
  uint32_t pm[2][2] = {{0, UINT32_MAX}, {0, 1}};
  bbc_forest_cull *c;
  bbc_error err;
  assert_int_equal(bbc_forest_cull_build(&w, models, 2, (const uint32_t(*)[2])pm, 2, &c, &err),
                   BBC_OK);
  assert_int_equal(rec_of(c).bucket_count, 3);
  size_t model_of[3] = {0, 0, 1};
  bbc_forest_camera cam;
  look(&cam, 128, 10, 300, 0, 0); /* south of the map, looking north over it */
  float vp[16];
  bbc_forest_camera_get_viewproj(&cam, 1.0, 0.5, 2000, vp);
  bbc_forest_cull_run(c, vp, cam.pos, 1);
  /* every tree ahead within the 60 degree view; count by brute force */
  double planes[6][4];
  bbc_forest_frustum_from_matrix(vp, planes);
  size_t expect_visible = 0;
  for (size_t i = 0; i < w.instance_count; i++) {
    const bbc_forest_instance *in = &w.instances[i];
    int out = 0;
    for (int k = 0; k < 6; k++)
      out |= planes[k][0] * in->x + planes[k][1] * in->y + planes[k][2] * in->z + planes[k][3] < -3;
    expect_visible += !out;
  }
  assert_true(expect_visible > 50 && expect_visible < 256);
  /* the cells in view hold them all, and some outside the frustum */
  assert_true(rec_of(c).trees_visible >= expect_visible && rec_of(c).trees_visible < 256);
  /* whole cells and cells across the switch at 50 (level 0's end: tree by
   * tree) */
  size_t whole = 0;
  for (size_t b = 0; b < 3; b++) whole += rec_of(c).range_blend[b] - rec_of(c).range_start[b];
  assert_true(whole > 0 && rec_of(c).bucket_start[3] > 0);
  size_t total = 0;
  for (size_t b = 0; b < 3; b++) total += bbc_forest_cull_get_bucket_size(c, b);
  bbc_forest_draw *grid = malloc(total * sizeof *grid);
  assert_non_null(grid);
  for (size_t b = 0, at = 0; b < 3; b++) {
    bbc_forest_cull_copy_bucket(c, b, grid + at);
    at += bbc_forest_cull_get_bucket_size(c, b);
  }
  /* records carry the instance and a weight in [0, 1] */
  for (size_t i = 0; i < total; i++)
    assert_true(grid[i].fade >= 0 && grid[i].fade <= 1 && grid[i].scale == 1);
  /* the same frame again: the same output (no state carried over) */
  {
    bbc_forest_draw *again = malloc(total * sizeof *again);
    assert_non_null(again);
    bbc_forest_cull_run(c, vp, cam.pos, 1);
    for (size_t b = 0, at = 0; b < 3; b++) {
      bbc_forest_cull_copy_bucket(c, b, again + at);
      at += bbc_forest_cull_get_bucket_size(c, b);
    }
    assert_memory_equal(grid, again, total * sizeof *grid);
    free(again);
  }
  free(grid);
  /* against the flat way (forest --naive), tree by tree */
  check_against_flat(c, vp, cam.pos, 1, models, model_of, 3);
  bbc_forest_cull_run_flat(c, vp, cam.pos, 1);
  assert_int_equal(rec_of(c).range_start[3], 0);
  assert_int_equal(rec_of(c).trees_visible, expect_visible);
  /* looking away: nothing */
  look(&cam, 128, 10, 300, 180, 0);
  bbc_forest_camera_get_viewproj(&cam, 1.0, 0.5, 2000, vp);
  bbc_forest_cull_run(c, vp, cam.pos, 1);
  assert_int_equal(rec_of(c).bucket_start[3] + rec_of(c).range_start[3], 0);
  assert_int_equal(rec_of(c).trees_visible, 0);
  /* zooming in (distances / zoom) moves trees to finer levels */
  look(&cam, 128, 10, 300, 0, 0);
  bbc_forest_camera_get_viewproj(&cam, 1.0, 0.5, 2000, vp);
  bbc_forest_cull_run(c, vp, cam.pos, 1);
  size_t fine0 = bbc_forest_cull_get_bucket_size(c, 0);
  bbc_forest_cull_run(c, vp, cam.pos, 8);
  assert_true(bbc_forest_cull_get_bucket_size(c, 0) > fine0);
  bbc_forest_cull_free(c);
  bbc_forest_world_free(&w);
}

/* Every terrain square is covered by exactly one selected node, and where
 * two nodes touch their levels differ by at most one. */
static void check_terrain_cover(const bbc_forest_terrain *t, int squares, int check_levels) {
  int *level = malloc((size_t)squares * squares * sizeof *level);
  assert_non_null(level);
  for (int i = 0; i < squares * squares; i++) level[i] = -1;
  for (size_t i = 0; i < t->node_count; i++) {
    const bbc_forest_terrain_node *n = &t->nodes[i];
    for (int z = n->z; z < n->z + n->size; z++)
      for (int x = n->x; x < n->x + n->size; x++) {
        assert_int_equal(level[z * squares + x], -1); /* no overlap */
        level[z * squares + x] = n->level;
      }
  }
  for (int z = 0; z < squares; z++)
    for (int x = 0; x < squares; x++) {
      int l = level[z * squares + x];
      if (!check_levels || l < 0) continue;
      if (x + 1 < squares && level[z * squares + x + 1] >= 0)
        assert_true(abs(level[z * squares + x + 1] - l) <= 1);
      if (z + 1 < squares && level[(z + 1) * squares + x] >= 0)
        assert_true(abs(level[(z + 1) * squares + x] - l) <= 1);
    }
  free(level);
}

static void test_terrain_select(void **state) {
  (void)state;
  bbc_forest_world w;
  make_world(&w, 512, 2, 1);
  bbc_forest_terrain t;
  bbc_error err;
  assert_int_equal(bbc_forest_terrain_init(&t, &w, &err), BBC_OK);
  assert_int_equal(t.leaf, 32);
  assert_int_equal(t.levels, 5); /* 32, 64, 128, 256, 512 */
  /* from above the middle, looking straight down far up: the whole map */
  bbc_forest_camera cam;
  look(&cam, 512, 3000, 512, 0, -89);
  float vp[16];
  bbc_forest_camera_get_viewproj(&cam, 1.0, 1, 10000, vp);
  bbc_forest_terrain_select(&t, &w, vp, cam.pos, 10);
  check_terrain_cover(&t, 512, 1);
  size_t covered = 0;
  for (size_t i = 0; i < t.node_count; i++) covered += (size_t)t.nodes[i].size * t.nodes[i].size;
  assert_int_equal(covered, 512 * 512);
  /* low over the ground: finest near the camera, coarse far away */
  for (int k = 0; k < 8; k++) {
    look(&cam, 100 + 100 * k, 60, 900 - 80 * k, 30 + 40 * k, -10);
    bbc_forest_camera_get_viewproj(&cam, 1.5, 1, 3000, vp);
    bbc_forest_terrain_select(&t, &w, vp, cam.pos, 2 + 2 * k);
    assert_true(t.node_count > 0 && t.node_count < t.capacity);
    check_terrain_cover(&t, 512, 1);
    int lo = 99, hi = -1;
    for (size_t i = 0; i < t.node_count; i++) {
      lo = t.nodes[i].level < lo ? t.nodes[i].level : lo;
      hi = t.nodes[i].level > hi ? t.nodes[i].level : hi;
    }
    assert_int_equal(lo, 0);
    assert_true(hi >= 1);
  }
  /* more detail, more nodes */
  look(&cam, 100, 60, 900, 45, -10);
  bbc_forest_camera_get_viewproj(&cam, 1.5, 1, 3000, vp);
  bbc_forest_terrain_select(&t, &w, vp, cam.pos, 10);
  size_t coarse = t.node_count;
  bbc_forest_terrain_select(&t, &w, vp, cam.pos, 60);
  assert_true(t.node_count > coarse);
  bbc_forest_terrain_free(&t);
  /* not (2^n + 1)^2: refused */
  bbc_forest_world w2;
  make_world(&w2, 100, 1, 0);
  assert_int_equal(bbc_forest_terrain_init(&t, &w2, &err), BBC_ERROR_INVALID_ARGUMENT);
  bbc_forest_world_free(&w2);
  bbc_forest_world_free(&w);
}

/* Whether the ray from e to p goes below the terrain (bilinear over the
 * heightmap: the finest the terrain is drawn) anywhere short of p. */
static int ray_blocked(const bbc_forest_world *w, const double e[3], const double p[3]) {
  double dx = p[0] - e[0], dz = p[2] - e[2], len = sqrt(dx * dx + dz * dz);
  int n = (int)(len / (0.25 * w->spacing)) + 2;
  for (int i = 1; i < n; i++) {
    double t = (double)i / n;
    if (bbc_forest_world_get_height(w, e[0] + t * dx, e[2] + t * dz) > e[1] + t * (p[1] - e[1]))
      return 1;
  }
  return 0;
}

/* Occlusion by the terrain: a box behind a ridge is hidden, one above it
 * or beside it is not; and on hills, every box found hidden has every ray
 * to it (a grid of its points) going below the terrain somewhere, while
 * many are found hidden. */
static void test_terrain_occlusion(void **state) {
  (void)state;
  bbc_forest_world w;
  make_world(&w, 256, 4, 0); /* flat, 1024 units */
  /* a ridge 40 high across x = 400..460 (the test steps 12 % of the
   * distance: a thinner occluder may be missed, never one wrongly found) */
  for (int z = 0; z <= 256; z++)
    for (int x = 100; x <= 115; x++) w.height[(size_t)z * 257 + x] = 40;
  bbc_forest_terrain t;
  bbc_forest_occluder o;
  bbc_error err;
  assert_int_equal(bbc_forest_terrain_init(&t, &w, &err), BBC_OK);
  assert_int_equal(bbc_forest_occluder_init(&o, &w, &err), BBC_OK);
  bbc_forest_camera cam;
  float vp[16];
  look(&cam, 200, 10, 512, 90, 0);
  bbc_forest_camera_get_viewproj(&cam, 1.5, 1, 3000, vp);
  bbc_forest_terrain_select(&t, &w, vp, cam.pos, 10);
  bbc_forest_occluder_begin(&o, &t, cam.pos);
  const float behind[6] = {600, 0, 500, 620, 15, 520}, tall[6] = {600, 0, 500, 620, 200, 520};
  const float before[6] = {300, 0, 500, 320, 15, 520}, aside[6] = {100, 0, 500, 120, 15, 520};
  assert_true(bbc_forest_occluder_hides(&o, behind));
  assert_false(bbc_forest_occluder_hides(&o, tall));   /* rises above the ridge */
  assert_false(bbc_forest_occluder_hides(&o, before)); /* in front of it */
  assert_false(bbc_forest_occluder_hides(&o, aside));  /* behind the eye, nothing between */
  /* the eye below the ground: nothing is hidden */
  double under[3] = {200, -5, 512};
  bbc_forest_occluder_begin(&o, &t, under);
  assert_false(bbc_forest_occluder_hides(&o, behind));
  bbc_forest_occluder_free(&o);
  bbc_forest_terrain_free(&t);
  bbc_forest_world_free(&w);
  /* hills: conservative, and not empty */
  make_world(&w, 256, 4, 1);
  assert_int_equal(bbc_forest_terrain_init(&t, &w, &err), BBC_OK);
  assert_int_equal(bbc_forest_occluder_init(&o, &w, &err), BBC_OK);
  size_t tried = 0, hidden = 0;
  uint32_t rs = 11;
  for (int view = 0; view < 6; view++) {
    double ex = 100 + 150 * view, ez = 900 - 130 * view;
    look(&cam, ex, bbc_forest_world_get_height(&w, ex, ez) + 3 + 4 * view, ez, 40 + 50 * view, -5);
    bbc_forest_camera_get_viewproj(&cam, 1.5, 1, 3000, vp);
    bbc_forest_terrain_select(&t, &w, vp, cam.pos, 6 + 2 * view);
    bbc_forest_occluder_begin(&o, &t, cam.pos);
    for (int b = 0; b < 400; b++) {
      rs = rs * 1664525u + 1013904223u;
      double x = (rs >> 8) / (double)(1u << 24) * 1000 + 12;
      rs = rs * 1664525u + 1013904223u;
      double z = (rs >> 8) / (double)(1u << 24) * 1000 + 12;
      double g = bbc_forest_world_get_height(&w, x, z);
      float box[6] = {(float)(x - 10), (float)g,        (float)(z - 10),
                      (float)(x + 10), (float)(g + 12), (float)(z + 10)};
      tried++;
      if (!bbc_forest_occluder_hides(&o, box)) continue;
      hidden++;
      for (int i = 0; i <= 4; i++)
        for (int j = 0; j <= 4; j++)
          for (int k = 0; k <= 2; k++) {
            double p[3] = {box[0] + (box[3] - box[0]) * i / 4, box[1] + (box[4] - box[1]) * k / 2,
                           box[2] + (box[5] - box[2]) * j / 4};
            if (!ray_blocked(&w, cam.pos, p))
              fail_msg("view %d: box at %.1f, %.1f found hidden, its point %.1f %.1f %.1f seen",
                       view, x, z, p[0], p[1], p[2]);
          }
    }
  }
  print_message("terrain occlusion on hills: %zu of %zu boxes hidden\n", hidden, tried);
  assert_true(hidden * 10 > tried);
  bbc_forest_occluder_free(&o);
  bbc_forest_terrain_free(&t);
  bbc_forest_world_free(&w);
}

static void test_terrain_colour(void **state) {
  (void)state;
  bbc_forest_world w;
  make_world(&w, 64, 1, 0);
  /* a slope facing the light on one half: brighter than flat ground */
  for (int z = 0; z <= 64; z++)
    for (int x = 32; x <= 64; x++) w.height[(size_t)z * 65 + x] = (float)(-(x - 32) * 0.8);
  assert_int_equal(bbc_image_alloc(&w.colour, 64, 64), BBC_OK); /* one colour everywhere */
  for (int i = 0; i < 64 * 64; i++) {
    uint8_t px[4] = {100, 150, 80, 255};
    memcpy(w.colour.rgba + 4 * i, px, 4);
  }
  w.instance_count = 1;
  w.instances = calloc(1, sizeof *w.instances);
  assert_non_null(w.instances);
  w.instances[0].x = 16;
  w.instances[0].z = 16;
  double light[3] = {1, 1, 0}, shadow[1][2] = {{6, 2}};
  bbc_image im;
  bbc_error err;
  assert_int_equal(bbc_forest_terrain_bake_colour(&w, light, (const double(*)[2])shadow, &im, &err),
                   BBC_OK);
  assert_int_equal(im.width, 64);
  const uint8_t *flat = im.rgba + 4 * (40 * 64 + 10), *lit = im.rgba + 4 * (40 * 64 + 50);
  const uint8_t *under = im.rgba + 4 * (16 * 64 + 16), *edge = im.rgba + 4 * (16 * 64 + 20);
  assert_int_equal(flat[1], 150);                             /* flat ground keeps its colour */
  assert_true(lit[1] > flat[1] + 10);                         /* faces the light */
  assert_true(under[1] < flat[1] * 0.6);                      /* the shadow's centre */
  assert_true(edge[1] > under[1] && edge[1] < flat[1]);       /* falling off */
  assert_int_equal(im.rgba[4 * (16 * 64 + 30) + 1], flat[1]); /* outside the radius */
  bbc_image_free(&im);
  /* no light (forest lights per pixel): the colours and the shadows only */
  assert_int_equal(bbc_forest_terrain_bake_colour(&w, NULL, (const double(*)[2])shadow, &im, &err),
                   BBC_OK);
  assert_int_equal(im.rgba[4 * (40 * 64 + 10) + 1], 150);
  assert_int_equal(im.rgba[4 * (40 * 64 + 50) + 1], 150); /* the slope is not lit */
  assert_true(im.rgba[4 * (16 * 64 + 16) + 1] < 150 * 0.6);
  bbc_image_free(&im);
  bbc_forest_world_free(&w);
}

static void test_sun(void **state) {
  (void)state;
  double d[3], az, el;
  bbc_forest_sun_direction(0, 0, d); /* azimuth 0: towards +z */
  assert_true(fabs(d[0]) < 1e-12 && fabs(d[1]) < 1e-12 && fabs(d[2] - 1) < 1e-12);
  bbc_forest_sun_direction(90, 0, d); /* 90: towards +x */
  assert_true(fabs(d[0] - 1) < 1e-12 && fabs(d[2]) < 1e-12);
  bbc_forest_sun_direction(200, 90, d); /* noon whatever the azimuth */
  assert_true(fabs(d[1] - 1) < 1e-12);
  for (int a = 0; a < 360; a += 45)
    for (int e = -30; e < 90; e += 20) {
      bbc_forest_sun_direction(a, e, d);
      assert_true(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1) < 1e-12);
      bbc_forest_sun_angles(d, &az, &el);
      assert_true(fabs(az - a) < 1e-9 && fabs(el - e) < 1e-9);
    }
  /* the maps' default light (1 1 0.5): the same direction, any length */
  double light[3] = {2, 2, 1};
  bbc_forest_sun_angles(light, &az, &el);
  bbc_forest_sun_direction(az, el, d);
  assert_true(fabs(d[0] - 2.0 / 3) < 1e-12 && fabs(d[1] - 2.0 / 3) < 1e-12 &&
              fabs(d[2] - 1.0 / 3) < 1e-12);
  /* a surface facing the sun keeps its colour; away, the ambient share,
   * which the occlusion darkens (and only it) */
  assert_true(fabs(bbc_forest_sun_shade(0.4, 1, 1) - 1) < 1e-12);
  assert_true(fabs(bbc_forest_sun_shade(0.4, 1, -0.5) - 0.4 / 1.4) < 1e-12);
  assert_true(fabs(bbc_forest_sun_shade(0.4, 0.75, -1) - 0.3 / 1.4) < 1e-12);
  assert_true(fabs(bbc_forest_sun_shade(0.4, 0.75, 1) - 1.3 / 1.4) < 1e-12);
  assert_true(bbc_forest_sun_shade(0.4, 1, 0.5) > bbc_forest_sun_shade(0.4, 1, 0.2));
}

static void test_wind(void **state) {
  (void)state;
  bbc_forest_wind w = {1.5, {0.6, 0.8}}, still = {0, {1, 0}};
  const double base[3] = {120.5, 7, 33.25}, H = 12;
  double o[3], o2[3];
  /* the base stays put, at any time; no wind, no sway */
  for (double t = 0; t < 30; t += 0.37) {
    double foot[3] = {0.4, 0, -0.2}, top[3] = {1, H, 2};
    bbc_forest_wind_offset(&w, t, base, foot, H, o);
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 0);
    bbc_forest_wind_offset(&still, t, base, top, H, o);
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 0);
  }
  /* on the axis it leans downwind, more the higher: h^2 */
  double mean_along = 0, mean_across = 0, top_max = 0;
  int n = 0;
  for (double t = 0; t < 120; t += 0.1, n++) {
    double mid[3] = {0, H / 2, 0}, top[3] = {0, H, 0};
    bbc_forest_wind_offset(&w, t, base, mid, H, o);
    bbc_forest_wind_offset(&w, t, base, top, H, o2);
    double a1 = o[0] * w.dir[0] + o[2] * w.dir[1], a2 = o2[0] * w.dir[0] + o2[2] * w.dir[1];
    assert_true(a1 > 0 && fabs(a2 - 4 * a1) < 1e-9 * H);
    assert_true(fabs(o2[1]) < 1e-12); /* no flutter on the axis */
    mean_along += a2;
    mean_across += -o2[0] * w.dir[1] + o2[2] * w.dir[0];
    double m = sqrt(o2[0] * o2[0] + o2[2] * o2[2]);
    if (m > top_max) top_max = m;
  }
  mean_along /= n;
  mean_across /= n;
  fprintf(stderr, "wind 1.5, tree 12 high: the top leans %.3f on average, %.3f at most\n",
          mean_along, top_max);
  assert_true(fabs(mean_across) < 1e-9);
  /* a breeze: a few percent of the height (0.04 x strength x height x gusts) */
  assert_true(mean_along > 0.01 * 1.5 * H && top_max <= 0.04 * 1.5 * H * 1.3 + 1e-9);
  /* gusts: it moves (not a fixed lean) */
  double lo = 1e30, hi = 0;
  for (double t = 0; t < 60; t += 0.25) {
    double top[3] = {0, H, 0};
    bbc_forest_wind_offset(&w, t, base, top, H, o);
    double a = o[0] * w.dir[0] + o[2] * w.dir[1];
    lo = a < lo ? a : lo;
    hi = a > hi ? a : hi;
  }
  assert_true(hi > 2 * lo);
  /* leaves away from the axis flutter: every direction moves */
  double leaf[3] = {3, 0.8 * H, -2}, spread[3] = {0, 0, 0};
  for (double t = 0; t < 10; t += 0.05) {
    bbc_forest_wind_offset(&w, t, base, leaf, H, o);
    for (int k = 0; k < 3; k++) spread[k] = fmax(spread[k], fabs(o[k]));
  }
  assert_true(spread[0] > 0 && spread[1] > 0 && spread[2] > 0);
  /* trees sway out of step (a phase per tree), deterministically */
  double top[3] = {0, H, 0}, other[3] = {57.1, 7, 90.4};
  bbc_forest_wind_offset(&w, 3.3, base, top, H, o);
  bbc_forest_wind_offset(&w, 3.3, other, top, H, o2);
  assert_true(fabs(o[0] - o2[0]) > 1e-3);
  bbc_forest_wind_offset(&w, 3.3, base, top, H, o2);
  assert_true(o[0] == o2[0] && o[1] == o2[1] && o[2] == o2[2]);
  /* the same point of two levels moves alike: a function of the point */
  double p1[3] = {1.25, 7.5, -0.5}, p2[3] = {1.25, 7.5, -0.5};
  bbc_forest_wind_offset(&w, 8.1, base, p1, H, o);
  bbc_forest_wind_offset(&w, 8.1, base, p2, H, o2);
  assert_true(o[0] == o2[0] && o[1] == o2[1] && o[2] == o2[2]);
}

static void test_mipmaps(void **state) {
  (void)state;
  /* thin vertical lines one texel wide every 4 texels: 25 % opaque. A
   * plain box filter with an alpha test at 0.5 loses all of them at the
   * second level; the coverage-keeping chain keeps 25 % at every level. */
  bbc_image im;
  assert_int_equal(bbc_image_alloc(&im, 64, 32), BBC_OK);
  for (int y = 0; y < 32; y++)
    for (int x = 0; x < 64; x++) {
      uint8_t *p = im.rgba + 4 * (y * 64 + x);
      p[0] = 40;
      p[1] = 160;
      p[2] = 30;
      p[3] = x % 4 == 0 ? 255 : 0;
    }
  bbc_image *lv;
  int n;
  bbc_error err;
  assert_int_equal(bbc_image_mipmaps(&im, &lv, &n, &err), BBC_OK);
  assert_int_equal(n, 6); /* 32x16 16x8 8x4 4x2 2x1 1x1 */
  assert_int_equal(lv[0].width, 32);
  assert_int_equal(lv[5].width, 1);
  for (int l = 0; l < 4; l++) {
    size_t opaque = 0, total = (size_t)lv[l].width * lv[l].height;
    for (size_t i = 0; i < total; i++) {
      uint8_t a = lv[l].rgba[4 * i + 3];
      assert_true(a == 0 || a == 255); /* binary */
      opaque += a == 255;
      /* colour stays the leaves' colour, no dark fringe */
      assert_int_equal(lv[l].rgba[4 * i + 1], 160);
    }
    assert_true(fabs((double)opaque / total - 0.25) < 0.02);
  }
  for (int l = 0; l < n; l++) bbc_image_free(&lv[l]);
  free(lv);
  bbc_image_free(&im);
}

/* Each part of a level keeps its own coverage: a texture whose left half
 * is sparse (1 texel in 8 opaque, a cloud's dithered thin leaves) and whose
 * right half is dense (7 in 8, a crown). A threshold over the whole level
 * keeps the 50 % total by filling the right half and emptying the left
 * (the Scopia palm's fronds gone from its far levels); here each half
 * keeps its share at every level down to 8 x 8 texels. And a solid shape
 * stays solid (the most covered texels of each block turn opaque, not a
 * dither of them): a disc's level-1 texels inside it are all opaque. */
static void test_mipmaps_local(void **state) {
  (void)state;
  bbc_image im;
  assert_int_equal(bbc_image_alloc(&im, 64, 64), BBC_OK);
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) {
      uint8_t *p = im.rgba + 4 * (y * 64 + x);
      int k = (x * 5 + y * 3) % 8; /* spread: no two neighbours alike */
      p[1] = 200;
      p[3] = x < 32 ? (k == 0 ? 255 : 0) : (k != 0 ? 255 : 0);
    }
  bbc_image *lv;
  int n;
  bbc_error err;
  assert_int_equal(bbc_image_mipmaps(&im, &lv, &n, &err), BBC_OK);
  for (int l = 0; l < 3; l++) { /* 32, 16, 8 texels a side (blocks of 4 x 4 chosen whole) */
    int w = lv[l].width;
    double half[2] = {0, 0};
    for (int y = 0; y < w; y++)
      for (int x = 0; x < w; x++) half[x >= w / 2] += lv[l].rgba[4 * (y * w + x) + 3] == 255;
    double cells = (double)w * w / 2;
    assert_true(fabs(half[0] / cells - 0.125) < 0.07);
    assert_true(fabs(half[1] / cells - 0.875) < 0.07);
  }
  for (int l = 0; l < n; l++) bbc_image_free(&lv[l]);
  free(lv);
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) {
      double dx = x + 0.5 - 32, dy = y + 0.5 - 32;
      im.rgba[4 * (y * 64 + x) + 3] = dx * dx + dy * dy < 20.0 * 20.0 ? 255 : 0;
    }
  assert_int_equal(bbc_image_mipmaps(&im, &lv, &n, &err), BBC_OK);
  for (int y = 0; y < 32; y++)
    for (int x = 0; x < 32; x++) {
      double dx = 2 * x + 1 - 32, dy = 2 * y + 1 - 32;
      if (dx * dx + dy * dy < 18.0 * 18.0) assert_int_equal(lv[0].rgba[4 * (y * 32 + x) + 3], 255);
      if (dx * dx + dy * dy > 22.0 * 22.0) assert_int_equal(lv[0].rgba[4 * (y * 32 + x) + 3], 0);
    }
  for (int l = 0; l < n; l++) bbc_image_free(&lv[l]);
  free(lv);
  bbc_image_free(&im);
}

/* An opaque texture atlas's texels no triangle uses are padded by those it
 * does, so that its mip levels do not mix in its background, its mip
 * levels average only the texels used and stop where they would mix its
 * islands (bbc_mesh_texture_padded, bbc_image_mipmaps_masked: what forest
 * uploads for opaque textures): a 64 x 64 texture, its left
 * half red and used by a quad, its right half white and unused. */
static void test_padded_texture(void **state) {
  (void)state;
  static const char *const names[] = {"leaf"};
  bbc_mesh m;
  tu_mesh_begin(&m, 2, 1, names, NULL, "g");
  double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {1, 1, 0}, d[3] = {0, 1, 0};
  tu_mesh_quad(&m, a, b, c, d, 0);
  m.uvs = calloc(2 * m.vertex_count, sizeof *m.uvs);
  m.textures = calloc(1, sizeof *m.textures);
  assert_non_null(m.uvs);
  assert_non_null(m.textures);
  m.texture_count = 1;
  m.materials[0].texture = 0;
  bbc_image *im = &m.textures[0].image;
  assert_int_equal(bbc_image_alloc(im, 64, 64), BBC_OK);
  for (int i = 0; i < 64 * 64; i++) {
    uint8_t *p = im->rgba + 4 * i;
    int red = i % 64 < 32;
    p[0] = 255;
    p[1] = p[2] = red ? 0 : 255;
    p[3] = 255;
  }
  /* the quad shows the left half: u 0..0.5 (an inset of a texel) */
  const float uv[4][2] = {{0.02f, 0.02f}, {0.48f, 0.02f}, {0.48f, 0.98f}, {0.02f, 0.98f}};
  memcpy(m.uvs, uv, sizeof uv);
  bbc_image out;
  int levels = -1;
  bbc_error err;
  assert_int_equal(bbc_mesh_texture_padded(&m, 0, &out, &levels, NULL, &err), BBC_OK);
  int white = 0;
  for (int i = 0; i < 64 * 64; i++) white += out.rgba[4 * i + 1] > 0;
  assert_int_equal(white, 0); /* the unused half took the red */
  /* the island is about 31 texels wide: texels up to 4 x 4 keep it
   * apart from what is around it (2 levels), not the whole chain (6) */
  print_message("padded: levels apart %d\n", levels);
  assert_int_equal(levels, 2);
  bbc_image_free(&out);
  /* repeating the texture across (u 0.12..2.88, wrapped): every texel
   * used, the copy as it was, one island 62 texels tall (3 levels) */
  for (int k = 0; k < 4; k++) m.uvs[2 * k] *= 6;
  assert_int_equal(bbc_mesh_texture_padded(&m, 0, &out, &levels, NULL, &err), BBC_OK);
  assert_memory_equal(out.rgba, im->rgba, 4 * 64 * 64);
  assert_int_equal(levels, 3);
  bbc_image_free(&out);
  assert_int_equal(bbc_mesh_texture_padded(&m, 1, &out, NULL, NULL, &err),
                   BBC_ERROR_INVALID_ARGUMENT);
  /* The island's own texels, and no others, make its levels: the quad
   * shows u 0.02..0.48 of a texture red there and white around it (an
   * atlas's background, which its bilinear ring and so its padding keep).
   * Plain levels of the padded copy turn its edge pink; levels from the
   * used texels stay red wherever the quad reaches. */
  for (int k = 0; k < 4; k++) m.uvs[2 * k] /= 6;
  for (int i = 0; i < 64 * 64; i++) {
    int x = i % 64, y = i / 64;
    int red = x >= 1 && x <= 30 && y >= 1 && y <= 62; /* what the quad reaches */
    im->rgba[4 * i + 1] = im->rgba[4 * i + 2] = red ? 0 : 255;
  }
  uint8_t *used = NULL;
  assert_int_equal(bbc_mesh_texture_padded(&m, 0, &out, &levels, &used, &err), BBC_OK);
  assert_non_null(used);
  bbc_image *lv, *plain;
  int n, n2;
  assert_int_equal(bbc_image_mipmaps_masked(&out, used, &lv, &n, &err), BBC_OK);
  assert_int_equal(bbc_image_mipmaps(&out, &plain, &n2, &err), BBC_OK);
  assert_int_equal(n, n2);
  int pink_plain = 0;
  for (int l = 0; l < 2; l++) { /* 32 and 16 texels a side */
    int w = lv[l].width, f = 64 / w;
    for (int y = 0; y < w; y++)
      for (int x = 0; x < w; x++) {
        int reached = 0; /* any used texel under this one */
        for (int dy = 0; dy < f; dy++)
          for (int dx = 0; dx < f; dx++) reached |= used[(y * f + dy) * 64 + x * f + dx];
        const uint8_t *p = lv[l].rgba + 4 * (y * w + x), *q = plain[l].rgba + 4 * (y * w + x);
        assert_int_equal(p[3], 255);
        if (!reached) continue;
        assert_int_equal(p[1], 0);
        pink_plain += q[1] > 0;
      }
  }
  print_message("levels 1-2: %d texels over the island pink from its padding\n", pink_plain);
  assert_true(pink_plain > 0);
  for (int l = 0; l < n; l++) {
    bbc_image_free(&lv[l]);
    bbc_image_free(&plain[l]);
  }
  free(lv);
  free(plain);
  free(used);
  bbc_image_free(&out);
  bbc_mesh_free(&m);
}

static void test_positions(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  char path[512];
  snprintf(path, sizeof path, "%s/save.txt", dir);
  bbc_forest_camera *cams;
  size_t n;
  bbc_error err;
  assert_int_equal(bbc_forest_positions_read(path, &cams, &n, &err), BBC_OK);
  assert_int_equal(n, 0); /* no file yet */
  bbc_forest_camera a, b;
  look(&a, 1.5, 2.25, -3, 45, -10);
  look(&b, 100, 20, 300, 270.5, 12);
  assert_int_equal(bbc_forest_positions_append(path, &a, &err), BBC_OK);
  assert_int_equal(bbc_forest_positions_append(path, &b, &err), BBC_OK);
  assert_int_equal(bbc_forest_positions_read(path, &cams, &n, &err), BBC_OK);
  assert_int_equal(n, 2);
  assert_true(fabs(cams[1].pos[2] - 300) < 1e-3 && fabs(cams[1].yaw - 270.5) < 1e-3);
  assert_true(fabs(cams[0].pitch + 10) < 1e-3);
  free(cams);
  free(tu_write_file(dir, "bad.txt", "1 2 3 4 5\n1 2 three 4 5\n", 24));
  snprintf(path, sizeof path, "%s/bad.txt", dir);
  assert_int_equal(bbc_forest_positions_read(path, &cams, &n, &err), BBC_ERROR_CORRUPT);
  assert_non_null(strstr(err.message, "bad.txt:2"));
  /* comments, as in map files */
  const char *cm = "' the ridge\n1 2 3 4 5\n  # and the lake\n6 7 8 9 10\n";
  free(tu_write_file(dir, "cm.txt", cm, strlen(cm)));
  snprintf(path, sizeof path, "%s/cm.txt", dir);
  assert_int_equal(bbc_forest_positions_read(path, &cams, &n, &err), BBC_OK);
  assert_int_equal(n, 2);
  assert_true(fabs(cams[1].pos[0] - 6) < 1e-9);
  free(cams);
  tu_remove_dir(dir);
  free(dir);
}

static void test_demo_terrain(void **state) {
  (void)state;
  bbc_image h[2], c[2];
  double water;
  bbc_error err;
  for (int k = 0; k < 2; k++)
    assert_int_equal(
        bbc_forest_demo_terrain(128, 7, BBC_FOREST_DEMO_HILLS, &h[k], &c[k], &water, &err), BBC_OK);
  assert_int_equal(h[0].width, 129);
  assert_int_equal(c[0].width, 128);
  assert_memory_equal(h[0].rgba, h[1].rgba, (size_t)129 * 129 * 4);
  assert_memory_equal(c[0].rgba, c[1].rgba, (size_t)128 * 128 * 4);
  /* a lake (below the water level), green ground for trees, and meadows */
  size_t below = 0, green = 0, other = 0;
  for (size_t i = 0; i < (size_t)129 * 129; i++) below += h[0].rgba[4 * i] < water;
  for (size_t i = 0; i < (size_t)128 * 128; i++) {
    const uint8_t *p = c[0].rgba + 4 * i;
    if (p[1] > 70 && 3 * p[0] < 2 * p[1])
      green++;
    else
      other++;
  }
  assert_true(below > 129 * 129 / 100);
  assert_true(green > 128 * 128 / 4 && other > 128 * 128 / 5);
  for (int k = 0; k < 2; k++) {
    bbc_image_free(&h[k]);
    bbc_image_free(&c[k]);
  }
  assert_int_equal(
      bbc_forest_demo_terrain(100, 7, BBC_FOREST_DEMO_HILLS, &h[0], &c[0], &water, &err),
      BBC_ERROR_INVALID_ARGUMENT);
}

/* Run-length BMP (stb does not read it; old heightmaps come that way). */
static void test_bmp_rle(void **state) {
  (void)state;
  uint8_t f[1200] = {0};
  /* header: 14 + 40 bytes, 256 grey palette entries, then RLE8 data */
  size_t data_at = 14 + 40 + 1024;
  f[0] = 'B';
  f[1] = 'M';
  f[10] = (uint8_t)(data_at & 255);
  f[11] = (uint8_t)(data_at >> 8);
  f[14] = 40;
  f[18] = 5; /* width 5 */
  f[22] = 3; /* height 3, bottom-up */
  f[26] = 1; /* planes */
  f[28] = 8; /* bits */
  f[30] = 1; /* BI_RLE8 */
  for (int i = 0; i < 256; i++) f[54 + 4 * i] = f[55 + 4 * i] = f[56 + 4 * i] = (uint8_t)i;
  /* bottom row: 5 x 10; middle: literal 1 2 3 then 2 x 7; top: delta then 4 x 9 */
  const uint8_t rle[] = {5, 10, 0, 0, 0, 3, 1, 2, 3, 0, 2, 7, 0, 0, 0, 2, 1, 0, 4, 9, 0, 1};
  memcpy(f + data_at, rle, sizeof rle);
  size_t size = data_at + sizeof rle;
  bbc_image im;
  bbc_error err;
  assert_int_equal(bbc_image_load_memory(f, size, &im, &err), BBC_OK);
  assert_int_equal(im.width, 5);
  assert_int_equal(im.height, 3);
  const int want[3][5] = {{0, 9, 9, 9, 9}, {1, 2, 3, 7, 7}, {10, 10, 10, 10, 10}}; /* top first */
  for (int y = 0; y < 3; y++)
    for (int x = 0; x < 5; x++) assert_int_equal(im.rgba[4 * (y * 5 + x)], want[y][x]);
  bbc_image_free(&im);
  /* cut short in a literal run: refused, no read past the end */
  assert_int_equal(bbc_image_load_memory(f, data_at + 7, &im, &err), BBC_ERROR_CORRUPT);
  /* a palette that does not fit: refused */
  assert_int_equal(bbc_image_load_memory(f, 300, &im, &err), BBC_ERROR_CORRUPT);
  /* the shared Irrlicht heightmap (RLE8) reads */
  char path[1024];
  tu_data_path(path, sizeof path, "terrain/irrlicht_terrain-heightmap.bmp");
  if (tu_have_file(path)) {
    assert_int_equal(bbc_image_load(path, &im, &err), BBC_OK);
    assert_int_equal(im.width, 256);
    int lo = 255, hi = 0;
    for (int i = 0; i < 256 * 256; i++) {
      lo = im.rgba[4 * i] < lo ? im.rgba[4 * i] : lo;
      hi = im.rgba[4 * i] > hi ? im.rgba[4 * i] : hi;
    }
    assert_true(hi - lo > 100); /* hills, not a blank */
    bbc_image_free(&im);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_frustum),
      cmocka_unit_test(test_lod_weights),
      cmocka_unit_test(test_cull),
      cmocka_unit_test(test_cull_matches_flat),
      cmocka_unit_test(test_terrain_select),
      cmocka_unit_test(test_terrain_occlusion),
      cmocka_unit_test(test_terrain_colour),
      cmocka_unit_test(test_mipmaps),
      cmocka_unit_test(test_mipmaps_local),
      cmocka_unit_test(test_positions),
      cmocka_unit_test(test_demo_terrain),
      cmocka_unit_test(test_bmp_rle),
      cmocka_unit_test(test_sun),
      cmocka_unit_test(test_wind),
      cmocka_unit_test(test_padded_texture),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
