/* test_oom.c — out of memory reaches the caller. Every allocation the
 * library makes for a small tree's whole run (steps 1 to 3 and the glTF
 * write, one thread) is made to fail in turn, through the linker's --wrap
 * of malloc, calloc and realloc (libbbc is a static library, so its calls
 * are wrapped; the C library's own and cmocka's are not). Each run must end
 * with BBC_OK or BBC_ERROR_OUT_OF_MEMORY — not another error, not a crash,
 * not a success with less in it — and in the sanitizer build nothing may
 * leak (there every third allocation, for time: the sanitizer build's
 * runs are 200 times slower; BBC_OOM_STEP=1 tries them all). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* The small tree's whole run with allocation `at` failing (-1: none);
 * returns the first error (BBC_OK when every step succeeded). */
static bbc_result whole_run(const bbc_mesh *tree, long at, const char *out, bbc_cloud *kept) {
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.threads = 1;
  o.params.texres = 64;
  o.params.max_planes = 0;
  o.params.min_planes = 0;
  bbc_planeset s;
  bbc_cloud cl;
  memset(&s, 0, sizeof s);
  memset(&cl, 0, sizeof cl);
  bbc_error err;
  counted = 0;
  fail_at = at;
  armed = 1;
  bbc_result r = bbc_planes_find(tree, &o, &s, &err);
  if (r == BBC_OK) r = bbc_cloud_build(tree, &s, &o.params, NULL, &cl, &err);
  if (r == BBC_OK) r = bbc_mesh_write_gltf(out, &cl.mesh, NULL, &err);
  armed = 0;
  if (r != BBC_OK && r != BBC_ERROR_OUT_OF_MEMORY)
    fail_msg("allocation %ld failing: error %d, %s", at, (int)r, err.message);
  if (kept && r == BBC_OK) {
    *kept = cl;
  } else {
    bbc_cloud_free(&cl);
  }
  bbc_planeset_free(&s);
  return r;
}

static void test_every_allocation_fails_in_turn(void **state) {
  (void)state;
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 60;
  t.texture_size = 32;
  bbc_mesh tree;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&t, &tree, &err), BBC_OK);
  char out[2048];
  snprintf(out, sizeof out, "%s/oom.glb", tu_dir);

  bbc_cloud whole;
  assert_int_equal(whole_run(&tree, -1, out, &whole), BBC_OK);
  long total = counted;
  size_t whole_bytes = 0;
  unsigned char *ref = tu_read_file(out, &whole_bytes);
  assert_non_null(ref);
  assert_true(total > 100);

  /* Every allocation of the run once; the runs that succeed anyway (a
   * failed allocation that has a fallback) write the same file. */
  long oom = 0, same = 0, step = 1;
#ifdef BBC_TEST_SANITIZE
  step = 3;
#endif
  if (getenv("BBC_OOM_STEP")) step = atol(getenv("BBC_OOM_STEP")); /* 1: all, by hand */
  if (step < 1) step = 1;
  for (long at = 0; at < total; at += step) {
    bbc_result r = whole_run(&tree, at, out, NULL);
    if (r == BBC_ERROR_OUT_OF_MEMORY) {
      oom++;
      continue;
    }
    size_t n = 0;
    unsigned char *got = tu_read_file(out, &n);
    if (!got || n != whole_bytes || memcmp(got, ref, n))
      fail_msg("allocation %ld of %ld failing: BBC_OK with another output", at, total);
    free(got);
    same++;
  }
  printf("%ld allocations: %ld runs out of memory, %ld the same output\n", total, oom, same);
  assert_true(oom > 0);
  free(ref);
  bbc_cloud_free(&whole);
  bbc_mesh_free(&tree);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_allocation_fails_in_turn),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
