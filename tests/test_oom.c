/* test_oom.c — out of memory reaches the caller. Every allocation the
 * library makes for a whole run (loading, steps 1 to 3 and the glTF write,
 * one thread; the cloud written as glTF, OBJ and VRML with DDS) of a small
 * tree, the same read from OBJ, and a point cloud on it is made to fail in
 * turn, through the linker's --wrap
 * of malloc, calloc and realloc (libbbc is a static library, so its calls
 * are wrapped; the C library's own and cmocka's are not). Each run must end
 * with BBC_OK or BBC_ERROR_OUT_OF_MEMORY — not another error, not a crash,
 * not a success with less in it — and in the sanitizer build nothing may
 * leak (there every seventh allocation, for time: the sanitizer build's
 * runs are 200 times slower; BBC_OOM_STEP=1 tries them all). The same for
 * an impostor, a three-level LOD chain written as .glb and .fbx (as bbcgen
 * makes it, through the session), the forest's world, culling, terrain,
 * occluder and baked colour, and the tools' other calls (the generator,
 * the baselines, points on a mesh, a software render, an evaluation). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <dirent.h>
#include <unistd.h>

#include "app.h"
#include "bbc.h"
#include "bbc_forest.h"
#include "test_util.h"

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_realloc(void *p, size_t size);

/* armed: the allocations are counted; the one numbered fail_at fails. */
static int armed;
static long counted, fail_at = -1;

static int should_fail(void) {
  if (!armed) return 0;
  return counted++ == fail_at;
}

/* Counting from 0, allocation `at` to fail (-1: none). */
static void arm(long at) {
  counted = 0;
  fail_at = at;
  armed = 1;
}

void *__wrap_malloc(size_t size) {
  return should_fail() ? NULL : __real_malloc(size);
}

void *__wrap_calloc(size_t count, size_t size) {
  return should_fail() ? NULL : __real_calloc(count, size);
}

void *__wrap_realloc(void *p, size_t size) {
  return should_fail() ? NULL : __real_realloc(p, size);
}

/* FNV-1a over bytes, folded into *h. */
static void digest_bytes(uint64_t *h, const void *data, size_t n) {
  const unsigned char *b = data;
  for (size_t i = 0; i < n; i++) *h = (*h ^ b[i]) * 1099511628211ull;
}

static void digest_file(uint64_t *h, const char *path) {
  size_t n = 0;
  unsigned char *b = tu_read_file(path, &n);
  if (b) digest_bytes(h, b, n);
  free(b);
}

/* A whole run with allocation `at` failing (-1: none): the model `path`
 * loaded (when given) or `mesh`, its planes, its cloud, the glTF written to
 * `out`; returns the first error (BBC_OK when every step succeeded). */
static bbc_result whole_run(const bbc_mesh *mesh, const char *path, long at, const char *out) {
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.threads = 1;
  o.params.texres = 32;
  o.params.max_planes = 0;
  o.params.min_planes = 0;
  bbc_mesh loaded;
  bbc_planeset s;
  bbc_cloud cl;
  memset(&loaded, 0, sizeof loaded);
  memset(&s, 0, sizeof s);
  memset(&cl, 0, sizeof cl);
  bbc_error err;
  arm(at);
  bbc_result r = BBC_OK;
  if (path) {
    r = bbc_mesh_load(path, NULL, &loaded, &err);
    mesh = &loaded;
  }
  if (r == BBC_OK) r = bbc_planes_find(mesh, &o, &s, &err);
  if (r == BBC_OK) r = bbc_cloud_build(mesh, &s, &o.params, NULL, &cl, &err);
  if (r == BBC_OK) r = bbc_mesh_write_gltf(out, &cl.mesh, NULL, &err);
  /* the same cloud as OBJ (with its MTL and PNGs) and as VRML with DDS */
  char obj[2048], wrl[2048];
  snprintf(obj, sizeof obj, "%s/oom.obj", tu_dir);
  snprintf(wrl, sizeof wrl, "%s/oom.wrl", tu_dir);
  bbc_vrml_options vo = {.dds = 1};
  if (r == BBC_OK) r = bbc_mesh_write_obj(obj, &cl.mesh, NULL, &err);
  if (r == BBC_OK) r = bbc_cloud_write_vrml(wrl, &cl, &vo, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("allocation %ld failing: error %d, %s", at, (int)r, err.message);
  bbc_cloud_free(&cl);
  bbc_planeset_free(&s);
  bbc_mesh_free(&loaded);
  return r;
}

static int name_order(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The files a whole run wrote (tu_dir's oom.*, the side files too), in
 * name order, folded into one digest; remove = 1 deletes them instead. */
static uint64_t whole_outputs(int remove) {
  uint64_t h = 14695981039346656037ull;
  DIR *d = opendir(tu_dir);
  assert_non_null(d);
  char *names[64];
  size_t n = 0;
  for (struct dirent *e; (e = readdir(d)) && n < 64;)
    if (!strncmp(e->d_name, "oom.", 4) || !strncmp(e->d_name, "oom_", 4))
      names[n++] = strdup(e->d_name);
  closedir(d);
  qsort(names, n, sizeof *names, name_order);
  for (size_t i = 0; i < n; i++) {
    char path[2300];
    snprintf(path, sizeof path, "%s/%s", tu_dir, names[i]);
    if (remove) {
      unlink(path);
    } else {
      digest_bytes(&h, names[i], strlen(names[i]) + 1);
      digest_file(&h, path);
    }
    free(names[i]);
  }
  return h;
}

/* Every allocation of one whole run made to fail in turn (every `step`-th
 * in the sanitizer build): each run out of memory, or (a failed allocation
 * with a fallback) the same files as without failures. */
static void every_allocation(const char *what, const bbc_mesh *mesh, const char *path) {
  time_t t0 = time(NULL);
  char out[2048];
  snprintf(out, sizeof out, "%s/oom.glb", tu_dir);
  whole_outputs(1);
  assert_int_equal(whole_run(mesh, path, -1, out), BBC_OK);
  long total = counted;
  uint64_t ref = whole_outputs(0);
  assert_true(total > 100);
  long oom = 0, same = 0, step = 1;
#ifdef BBC_TEST_SANITIZE
  step = 7;
#endif
  if (getenv("BBC_OOM_STEP")) step = atol(getenv("BBC_OOM_STEP")); /* 1: all, by hand */
  if (step < 1) step = 1;
  for (long at = 0; at < total; at += step) {
    whole_outputs(1);
    bbc_result r = whole_run(mesh, path, at, out);
    if (r == BBC_ERROR_OUT_OF_MEMORY) {
      oom++;
      continue;
    }
    if (whole_outputs(0) != ref)
      fail_msg("%s: allocation %ld of %ld failing: BBC_OK with other files", what, at, total);
    same++;
  }
  printf("%s: %ld allocations: %ld runs out of memory, %ld the same output (%ld s)\n", what, total,
         oom, same, (long)(time(NULL) - t0));
  assert_true(oom > 0);
}

/* The small generated tree every test runs on (30 leaves, a 32-texel leaf
 * texture). */
static void small_tree(bbc_mesh *tree) {
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 30;
  t.texture_size = 32;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&t, tree, &err), BBC_OK);
}

static void test_every_allocation_fails_in_turn(void **state) {
  (void)state;
  bbc_mesh tree, points;
  bbc_error err;
  small_tree(&tree);
  every_allocation("a generated tree", &tree, NULL);
  /* the same tree read back from OBJ (its MTL and leaf texture too) */
  char obj[2048];
  snprintf(obj, sizeof obj, "%s/tree.obj", tu_dir);
  assert_int_equal(bbc_mesh_write_obj(obj, &tree, NULL, &err), BBC_OK);
  every_allocation("the tree as OBJ", NULL, obj);
  /* a point cloud sampled on it */
  assert_int_equal(bbc_mesh_sample_points(&tree, 1500, 1, &points, &err), BBC_OK);
  every_allocation("1,500 points on it", &points, NULL);
  bbc_mesh_free(&points);
  bbc_mesh_free(&tree);
}

/* An impostor of the tree (2 x 2 frames of 16 texels, one thread) built
 * and written with allocation `at` failing: out of memory said, nothing
 * else. Returns the result. */
static bbc_result impostor_run(const bbc_mesh *mesh, long at, const char *out) {
  bbc_impostor_options o;
  bbc_impostor_options_default(&o);
  o.frames = 2;
  o.texels = 2 * 2 * 16 * 16;
  o.threads = 1;
  bbc_impostor imp;
  bbc_error err;
  arm(at);
  bbc_result r = bbc_impostor_build(mesh, &o, &imp, &err);
  if (r == BBC_OK) r = bbc_impostor_write(out, &imp, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY && r != BBC_ERROR_IO)
    fail_msg("impostor, allocation %ld failing: error %d, %s", at, (int)r, err.message);
  bbc_impostor_free(&imp);
  return r;
}

static void test_impostor_allocations(void **state) {
  (void)state;
  bbc_mesh tree;
  small_tree(&tree);
  char out[2048];
  snprintf(out, sizeof out, "%s/oom.json", tu_dir);
  assert_int_equal(impostor_run(&tree, -1, out), BBC_OK);
  long total = counted, oom = 0;
  assert_true(total > 10);
  for (long at = 0; at < total; at++) oom += impostor_run(&tree, at, out) != BBC_OK;
  printf("an impostor of the tree: %ld allocations, %ld runs failing\n", total, oom);
  assert_true(oom > 0);
  bbc_mesh_free(&tree);
}

/* Every allocation of `run` (its result; `at` the allocation failing, -1
 * none) made to fail in turn (every `sanitize_step`-th in the sanitizer
 * build): each run BBC_OK with the output (its digest) the same as without
 * failures, or out of memory. */
typedef bbc_result (*oom_run)(long at, const char *out, uint64_t *digest);
static void each_allocation(const char *what, oom_run run, const char *out, long sanitize_step) {
  uint64_t ref = 0, got = 0;
  counted = 0;
  assert_int_equal(run(-1, out, &ref), BBC_OK);
  long total = counted, oom = 0, same = 0, step = 1;
  assert_true(total > 10);
#ifdef BBC_TEST_SANITIZE
  step = sanitize_step;
#else
  (void)sanitize_step;
#endif
  if (getenv("BBC_OOM_STEP")) step = atol(getenv("BBC_OOM_STEP"));
  if (step < 1) step = 1;
  for (long at = 0; at < total; at += step) {
    bbc_result r = run(at, out, &got);
    if (r == BBC_ERROR_OUT_OF_MEMORY) {
      oom++;
    } else if (r != BBC_OK || got != ref) {
      fail_msg("%s: allocation %ld of %ld failing: error %d, or BBC_OK with another output", what,
               at, total, (int)r);
    } else {
      same++;
    }
  }
  printf("%s: %ld allocations: %ld runs out of memory, %ld the same output\n", what, total, oom,
         same);
  assert_true(oom > 0);
}

/* A chain of three levels (256, 64 and 24 pixels) of the tree read from
 * OBJ, made by the session as bbcgen makes it and written as one .glb and
 * as FBX. */
static char chain_obj[2048];
static bbc_result chain_run(long at, const char *out, uint64_t *digest) {
  bbc_session *s = bbc_session_new();
  assert_non_null(s);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.threads = 1;
  bbc_params_lod_chain(&o.params, 0);
  bbc_lod_level lv[3] = {{0, 256, 0}, {0, 64, 0}, {0, 24, 0}};
  char fbx[2100];
  snprintf(fbx, sizeof fbx, "%s.fbx", out);
  bbc_error err;
  arm(at);
  bbc_result r = bbc_session_load(s, chain_obj, NULL, &err);
  if (r == BBC_OK) r = bbc_session_run_chain(s, &o, lv, 3, &err);
  if (r == BBC_OK) r = bbc_session_write(s, out, NULL, &err);
  if (r == BBC_OK) r = bbc_session_write(s, fbx, NULL, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("chain, allocation %ld failing: error %d, %s", at, (int)r, err.message);
  bbc_session_free(s);
  *digest = 14695981039346656037ull;
  if (r == BBC_OK) {
    digest_file(digest, out);
    digest_file(digest, fbx);
  }
  return r;
}

static void test_chain_allocations(void **state) {
  (void)state;
  bbc_mesh tree;
  bbc_error err;
  small_tree(&tree);
  snprintf(chain_obj, sizeof chain_obj, "%s/chain_tree.obj", tu_dir);
  assert_int_equal(bbc_mesh_write_obj(chain_obj, &tree, NULL, &err), BBC_OK);
  bbc_mesh_free(&tree);
  char out[2048];
  snprintf(out, sizeof out, "%s/chain.glb", tu_dir);
  each_allocation("a three-level chain (.glb and .fbx)", chain_run, out, 11);
}

/* The forest's world of a small demo landscape (a map file, its heightmap
 * and colour map, 400 trees of two models), the culling of a frame with
 * the terrain's occlusion, and the terrain's baked colour. */
static char forest_dir[2048];
static bbc_result forest_run(long at, const char *out, uint64_t *digest) {
  (void)out;
  const char *text = "hmap h.png\ncolmap c.png\nheightscale 0.5\nstretch 2\n"
                     "object2d house.txt 1 0 30 45 0 90 0 0.5\n"
                     "rndtree tree.txt 1 400 1 1 0 0 0 0\n";
  bbc_forest_map map;
  bbc_forest_world world;
  bbc_forest_terrain terrain;
  bbc_forest_occluder occ;
  bbc_image colour;
  memset(&map, 0, sizeof map);
  memset(&world, 0, sizeof world);
  memset(&terrain, 0, sizeof terrain);
  memset(&occ, 0, sizeof occ);
  memset(&colour, 0, sizeof colour);
  bbc_forest_cull *cull = NULL;
  double r0[4] = {0, 40, 40, 400}, r1[2] = {0, 300};
  bbc_forest_lod_model models[2] = {{2, r0, 5, 3}, {1, r1, 0, 6}};
  uint32_t pm[2][2] = {{1, UINT32_MAX}, {0, UINT32_MAX}};
  const double light[3] = {0.3, 0.8, 0.5}, shadow[2][2] = {{0, 0}, {4, 1}};
  bbc_error err;
  arm(at);
  bbc_result r = bbc_forest_map_parse(text, strlen(text), "w.txt", &map, &err);
  if (r == BBC_OK) r = bbc_forest_world_build(&map, forest_dir, &world, &err);
  if (r == BBC_OK)
    r = bbc_forest_cull_build(&world, models, 2, (const uint32_t(*)[2])pm, 2, &cull, &err);
  if (r == BBC_OK) r = bbc_forest_terrain_init(&terrain, &world, &err);
  if (r == BBC_OK) r = bbc_forest_occluder_init(&occ, &world, &err);
  if (r == BBC_OK) r = bbc_forest_terrain_bake_colour(&world, light, shadow, &colour, &err);
  *digest = 14695981039346656037ull;
  if (r == BBC_OK) {
    bbc_forest_camera cam = {{60, 40, 60}, 135, -10, 1};
    float vp[16];
    bbc_forest_camera_get_viewproj(&cam, 1.5, 0.5, 2000, vp);
    bbc_forest_terrain_select(&terrain, &world, vp, cam.pos, 2);
    bbc_forest_occluder_begin(&occ, &terrain, cam.pos);
    bbc_forest_cull_set_occluder(cull, &occ, &terrain);
    bbc_forest_cull_run(cull, vp, cam.pos, 1);
    bbc_forest_records rec;
    bbc_forest_cull_get_records(cull, &rec);
    digest_bytes(digest, world.instances, world.instance_count * sizeof *world.instances);
    digest_bytes(digest, rec.statics, rec.static_count * sizeof *rec.statics);
    digest_bytes(digest, rec.range_start, (rec.bucket_count + 1) * sizeof *rec.range_start);
    digest_bytes(digest, rec.draws, rec.bucket_start[rec.bucket_count] * sizeof *rec.draws);
    digest_bytes(digest, terrain.nodes, terrain.node_count * sizeof *terrain.nodes);
    digest_bytes(digest, colour.rgba, (size_t)colour.width * (size_t)colour.height * 4);
  }
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("forest, allocation %ld failing: error %d, %s", at, (int)r, err.message);
  bbc_image_free(&colour);
  bbc_forest_occluder_free(&occ);
  bbc_forest_terrain_free(&terrain);
  bbc_forest_cull_free(cull);
  bbc_forest_world_free(&world);
  bbc_forest_map_free(&map);
  return r;
}

static void test_forest_allocations(void **state) {
  (void)state;
  bbc_image h, c;
  double water = 0;
  bbc_error err;
  assert_int_equal(bbc_forest_demo_terrain(64, 3, BBC_FOREST_DEMO_HILLS, &h, &c, &water, &err),
                   BBC_OK);
  snprintf(forest_dir, sizeof forest_dir, "%s", tu_dir);
  char path[2100];
  snprintf(path, sizeof path, "%s/h.png", forest_dir);
  assert_int_equal(bbc_image_write_png(path, &h, &err), BBC_OK);
  snprintf(path, sizeof path, "%s/c.png", forest_dir);
  assert_int_equal(bbc_image_write_png(path, &c, &err), BBC_OK);
  bbc_image_free(&h);
  bbc_image_free(&c);
  each_allocation("the forest's world, culling, terrain, occluder and colour", forest_run, NULL, 1);
}

/* The tools' other library calls: the tree generator, crossed billboards,
 * meshoptimizer's simplification, points sampled on a mesh, a software
 * render, an evaluation, the points' estimated normals, the vertices' shade
 * and a PLY file (one thread). */
static bbc_result misc_run(long at, const char *out, uint64_t *digest) {
  (void)out;
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 30;
  t.texture_size = 32;
  bbc_params p;
  bbc_params_default(&p);
  p.threads = 1;
  p.texres = 32;
  bbc_mesh tree, simple, pts;
  bbc_cloud crossed;
  bbc_image img;
  bbc_eval_result ev;
  memset(&tree, 0, sizeof tree);
  memset(&simple, 0, sizeof simple);
  memset(&pts, 0, sizeof pts);
  memset(&crossed, 0, sizeof crossed);
  memset(&img, 0, sizeof img);
  memset(&ev, 0, sizeof ev);
  bbc_eval_options eo;
  bbc_eval_options_default(&eo);
  eo.views = 4;
  eo.size = 32;
  eo.threads = 1;
  bbc_view v;
  memset(&v, 0, sizeof v);
  v.direction[2] = -1;
  v.up[1] = 1;
  v.half_extent = 10;
  v.lighting = 1;
  bbc_error err;
  arm(at);
  bbc_result r = bbc_tree_generate(&t, &tree, &err);
  if (r == BBC_OK) r = bbc_baseline_crossed(&tree, 3, 1, &p, 4096, NULL, &crossed, &err);
  if (r == BBC_OK) r = bbc_baseline_simplify(&tree, 200, 0, &simple, &err);
  if (r == BBC_OK) r = bbc_mesh_sample_points(&tree, 500, 1, &pts, &err);
  if (r == BBC_OK) r = bbc_image_alloc(&img, 48, 48);
  if (r == BBC_OK) r = bbc_render_ortho(&tree, &v, &img, &err);
  if (r == BBC_OK) r = bbc_eval(&tree, &crossed.mesh, &eo, &ev, &err);
  float *pn = NULL, *shade = NULL;
  char ply[2048];
  snprintf(ply, sizeof ply, "%s/misc.ply", tu_dir);
  if (r == BBC_OK && !(pn = malloc(3 * pts.vertex_count * sizeof *pn))) r = BBC_ERROR_OUT_OF_MEMORY;
  if (r == BBC_OK) r = bbc_points_estimate_normals(&pts, 1, pn, &err);
  if (r == BBC_OK && !(shade = malloc(tree.vertex_count * sizeof *shade)))
    r = BBC_ERROR_OUT_OF_MEMORY;
  if (r == BBC_OK) r = bbc_shade_vertices(&tree, 16, 0.4, BBC_AXIS_Y, shade, &err);
  if (r == BBC_OK) r = bbc_points_write_ply(ply, &pts, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("misc, allocation %ld failing: error %d, %s", at, (int)r, err.message);
  *digest = 14695981039346656037ull;
  if (r == BBC_OK) {
    digest_bytes(digest, tree.positions, 3 * tree.vertex_count * sizeof *tree.positions);
    digest_bytes(digest, crossed.mesh.textures[0].image.rgba,
                 4 * (size_t)crossed.mesh.textures[0].image.width *
                     (size_t)crossed.mesh.textures[0].image.height);
    digest_bytes(digest, simple.indices, 3 * simple.triangle_count * sizeof *simple.indices);
    digest_bytes(digest, pts.positions, 3 * pts.vertex_count * sizeof *pts.positions);
    digest_bytes(digest, img.rgba, 4 * 48 * 48);
    digest_bytes(digest, &ev.iou_mean, sizeof ev.iou_mean);
    digest_bytes(digest, &ev.block_iou_mean, sizeof ev.block_iou_mean);
    digest_bytes(digest, pn, 3 * pts.vertex_count * sizeof *pn);
    digest_bytes(digest, shade, tree.vertex_count * sizeof *shade);
    digest_file(digest, ply);
  }
  free(pn);
  free(shade);
  bbc_eval_result_free(&ev);
  bbc_image_free(&img);
  bbc_mesh_free(&pts);
  bbc_mesh_free(&simple);
  bbc_cloud_free(&crossed);
  bbc_mesh_free(&tree);
  return r;
}

static void test_misc_allocations(void **state) {
  (void)state;
  each_allocation("generator, baselines, points, render, eval, normals, shade, PLY", misc_run, NULL,
                  3);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_allocation_fails_in_turn),
      cmocka_unit_test(test_impostor_allocations),
      cmocka_unit_test(test_chain_allocations),
      cmocka_unit_test(test_forest_allocations),
      cmocka_unit_test(test_misc_allocations),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
