/* test_oom.c — out of memory reaches the caller. Every allocation the
 * library makes for a whole run (loading, steps 1 to 3 and the glTF write,
 * one thread) of a small tree, the same read from OBJ, and a point cloud on
 * it is made to fail in turn, through the linker's --wrap
 * of malloc, calloc and realloc (libbbc is a static library, so its calls
 * are wrapped; the C library's own and cmocka's are not). Each run must end
 * with BBC_OK or BBC_ERROR_OUT_OF_MEMORY — not another error, not a crash,
 * not a success with less in it — and in the sanitizer build nothing may
 * leak (there every seventh allocation, for time: the sanitizer build's
 * runs are 200 times slower; BBC_OOM_STEP=1 tries them all). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bbc.h"
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

void *__wrap_malloc(size_t size) {
  return should_fail() ? NULL : __real_malloc(size);
}

void *__wrap_calloc(size_t count, size_t size) {
  return should_fail() ? NULL : __real_calloc(count, size);
}

void *__wrap_realloc(void *p, size_t size) {
  return should_fail() ? NULL : __real_realloc(p, size);
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
  counted = 0;
  fail_at = at;
  armed = 1;
  bbc_result r = BBC_OK;
  if (path) {
    r = bbc_mesh_load(path, NULL, &loaded, &err);
    mesh = &loaded;
  }
  if (r == BBC_OK) r = bbc_planes_find(mesh, &o, &s, &err);
  if (r == BBC_OK) r = bbc_cloud_build(mesh, &s, &o.params, NULL, &cl, &err);
  if (r == BBC_OK) r = bbc_mesh_write_gltf(out, &cl.mesh, NULL, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("allocation %ld failing: error %d, %s", at, (int)r, err.message);
  bbc_cloud_free(&cl);
  bbc_planeset_free(&s);
  bbc_mesh_free(&loaded);
  return r;
}

/* Every allocation of one whole run made to fail in turn (every `step`-th
 * in the sanitizer build): each run out of memory, or (a failed allocation
 * with a fallback) the same file as without failures. */
static void every_allocation(const char *what, const bbc_mesh *mesh, const char *path) {
  time_t t0 = time(NULL);
  char out[2048];
  snprintf(out, sizeof out, "%s/oom.glb", tu_dir);
  assert_int_equal(whole_run(mesh, path, -1, out), BBC_OK);
  long total = counted;
  size_t whole_bytes = 0;
  unsigned char *ref = tu_read_file(out, &whole_bytes);
  assert_non_null(ref);
  assert_true(total > 100);
  long oom = 0, same = 0, step = 1;
#ifdef BBC_TEST_SANITIZE
  step = 7;
#endif
  if (getenv("BBC_OOM_STEP")) step = atol(getenv("BBC_OOM_STEP")); /* 1: all, by hand */
  if (step < 1) step = 1;
  for (long at = 0; at < total; at += step) {
    bbc_result r = whole_run(mesh, path, at, out);
    if (r == BBC_ERROR_OUT_OF_MEMORY) {
      oom++;
      continue;
    }
    size_t n = 0;
    unsigned char *got = tu_read_file(out, &n);
    if (!got || n != whole_bytes || memcmp(got, ref, n))
      fail_msg("%s: allocation %ld of %ld failing: BBC_OK with another output", what, at, total);
    free(got);
    same++;
  }
  printf("%s: %ld allocations: %ld runs out of memory, %ld the same output (%ld s)\n", what, total,
         oom, same, (long)(time(NULL) - t0));
  assert_true(oom > 0);
  free(ref);
}

static void test_every_allocation_fails_in_turn(void **state) {
  (void)state;
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 30;
  t.texture_size = 32;
  bbc_mesh tree, points;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&t, &tree, &err), BBC_OK);
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
  counted = 0;
  fail_at = at;
  armed = 1;
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
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 30;
  t.texture_size = 32;
  bbc_mesh tree;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&t, &tree, &err), BBC_OK);
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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_allocation_fails_in_turn),
      cmocka_unit_test(test_impostor_allocations),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
