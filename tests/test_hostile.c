/* test_hostile.c — untrusted input: every damaged or hostile file gives an
 * error naming the file and the problem, never a crash or garbage. Run
 * under ASan/UBSan by `make test`. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bbc.h"
#include "test_util.h"

/* Loads `name` with `content` and expects `code` with both the file name
 * and `needle` (when given) in the message. */
static void expect_refused(const char *name, const void *content, size_t size, bbc_result code,
                           const char *needle) {
  char *p = tu_write_file(tu_dir, name, content, size);
  bbc_mesh m;
  bbc_error err;
  memset(&err, 0, sizeof err);
  bbc_result r = bbc_mesh_load(p, NULL, &m, &err);
  if (r != code)
    fail_msg("%s: expected '%s', got '%s': %s", name, bbc_result_string(code), bbc_result_string(r),
             err.message);
  assert_non_null(strstr(err.message, name));
  if (needle && !strstr(err.message, needle)) fail_msg("'%s' not in: %s", needle, err.message);
  /* Nothing is left allocated in the output. */
  assert_null(m.positions);
  assert_int_equal(m.triangle_count, 0);
  free(p);
}

#define TEXT(s) s, sizeof(s) - 1

static void test_nan_and_inf(void **state) {
  (void)state;
  expect_refused("nan_first.obj", TEXT("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                 BBC_ERROR_INVALID_GEOMETRY, "nan");
  expect_refused("nan_last.obj", TEXT("v 0 0 0\nv 1 0 0\nv 0 1 NaN\nf 1 2 3\n"),
                 BBC_ERROR_INVALID_GEOMETRY, "line 3");
  expect_refused("inf.obj", TEXT("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"),
                 BBC_ERROR_INVALID_GEOMETRY, "line 3");
  expect_refused("huge.obj", TEXT("v 0 0 0\nv 1 0 0\nv 0 1e38 0\nf 1 2 3\n"),
                 BBC_ERROR_INVALID_GEOMETRY, NULL);
  expect_refused("short.obj", TEXT("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"),
                 BBC_ERROR_INVALID_GEOMETRY, "line 2");
  /* PLY meshes have their own reader: a NaN is refused there too. */
  expect_refused("nan.ply",
                 TEXT("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                      "y\nproperty float z\nelement face 1\nproperty list uchar int "
                      "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"),
                 BBC_ERROR_INVALID_GEOMETRY, NULL);
}

static void test_index_out_of_range(void **state) {
  (void)state;
  expect_refused("idx.obj", TEXT("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"), BBC_ERROR_CORRUPT,
                 "index");
  expect_refused("idx.ply",
                 TEXT("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                      "y\nproperty float z\nelement face 1\nproperty list uchar int "
                      "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"),
                 BBC_ERROR_INVALID_GEOMETRY, "face 0 refers to vertex 9");
}

static void test_zero_area_dropped_and_counted(void **state) {
  (void)state;
  const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 2\n";
  char *p = tu_write_file(tu_dir, "zero.obj", obj, sizeof obj - 1);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(p, NULL, &m, &err), BBC_OK);
  assert_int_equal(m.triangles_read, 3);
  assert_int_equal(m.triangle_count, 1);
  assert_int_equal(m.dropped_degenerate, 2);
  bbc_mesh_free(&m);
  free(p);
  expect_refused("allzero.obj", TEXT("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), BBC_ERROR_EMPTY,
                 "degenerate");
}

static void test_empty(void **state) {
  (void)state;
  expect_refused("zerobytes.obj", "", 0, BBC_ERROR_EMPTY, "empty");
  expect_refused("comment.obj", TEXT("# nothing here\n"), BBC_ERROR_CORRUPT, NULL);
  expect_refused("verts_only.obj", TEXT("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\n"), BBC_ERROR_EMPTY,
                 NULL);
}

static void test_truncated_and_garbage(void **state) {
  (void)state;
  char path[1024];
  size_t n;
  unsigned char *cat = tu_read_file(tu_data_path(path, sizeof path, "models/cat.3ds"), &n);
  if (cat) {
    expect_refused("cut.3ds", cat, n / 3, BBC_ERROR_CORRUPT, NULL);
    expect_refused("header_only.3ds", cat, 16, BBC_ERROR_CORRUPT, NULL);
    free(cat);
  } else {
    printf("SKIP part: models/cat.3ds missing\n");
  }
  unsigned char *ac =
      tu_read_file(tu_data_path(path, sizeof path, "models/flightgear/H-60.ac"), &n);
  if (ac) {
    expect_refused("cut.ac", ac, 3000, BBC_ERROR_CORRUPT, NULL);
    free(ac);
  }
  unsigned char junk[777];
  uint32_t s = 12345;
  for (size_t i = 0; i < sizeof junk; i++) {
    s = s * 1103515245u + 12345u;
    junk[i] = (unsigned char)(s >> 16);
  }
  expect_refused("junk.glb", junk, sizeof junk, BBC_ERROR_CORRUPT, NULL);
  expect_refused("junk.3ds", junk, sizeof junk, BBC_ERROR_CORRUPT, NULL);
  expect_refused("junk.fbx", junk, sizeof junk, BBC_ERROR_CORRUPT, NULL);
  expect_refused("junk.dae", junk, sizeof junk, BBC_ERROR_CORRUPT, NULL);
  expect_refused("cut.glb", TEXT("glTF\x02\x00\x00\x00\xff\xff\x00\x00"), BBC_ERROR_CORRUPT, NULL);
  expect_refused("junk.qqq", junk, sizeof junk, BBC_ERROR_UNSUPPORTED_FORMAT, NULL);
}

static void test_paths(void **state) {
  (void)state;
  bbc_mesh m;
  bbc_error err;
  char path[1024];
  snprintf(path, sizeof path, "%s/folder.obj", tu_dir);
  mkdir(path, 0777);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_A_FILE);
  assert_non_null(strstr(err.message, "folder.obj"));
  assert_non_null(strstr(err.message, "folder"));
  snprintf(path, sizeof path, "%s/missing.obj", tu_dir);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_FOUND);
  assert_non_null(strstr(err.message, "missing.obj"));
  snprintf(path, sizeof path, "%s/nodir/missing.obj", tu_dir);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_FOUND);
  assert_int_equal(bbc_mesh_load("", NULL, &m, &err), BBC_ERROR_NOT_FOUND);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_nan_and_inf),
      cmocka_unit_test(test_index_out_of_range),
      cmocka_unit_test(test_zero_area_dropped_and_counted),
      cmocka_unit_test(test_empty),
      cmocka_unit_test(test_truncated_and_garbage),
      cmocka_unit_test(test_paths),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
