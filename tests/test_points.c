/*
 * test_points.c — the PLY reader (point clouds and meshes) and the XYZ
 * reader (src/io/load_ply.c, load_xyz.c): the real scans in ../shared/data/points and
 * hand-made hostile files.
 *
 * Every case goes through the public bbc_mesh_load, which routes .xyz files
 * to the XYZ reader and every .ply file (mesh, point cloud or damaged) to the
 * PLY reader; none reaches Assimp. The PLY meshes are built here, byte by
 * byte, so that no test depends on a converter.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "bbc.h"
#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/* ---- helpers ------------------------------------------------------------ */

typedef struct progress_log {
  int calls;
  int ones;
  int decreasing;
  double last;
} progress_log;

static void on_progress(void *user, const char *stage, double fraction) {
  progress_log *p = user;
  assert_string_equal(stage, "load");
  if (p->calls && fraction < p->last) p->decreasing = 1;
  if (fraction == 1.0) p->ones++;
  p->last = fraction;
  p->calls++;
}

static bbc_result load(const char *path, bbc_mesh *mesh, bbc_error *err) {
  bbc_load_options opts;
  bbc_load_options_default(&opts);
  memset(err, 0, sizeof *err);
  bbc_result r = bbc_mesh_load(path, &opts, mesh, err);
  if (r != BBC_OK) printf("  %s -> %s: %s\n", path, bbc_result_string(r), err->message);
  return r;
}

/* Loads a real data file; skips the test when the file is missing. */
static int load_data(const char *rel, bbc_mesh *mesh) {
  char path[1024];
  tu_data_path(path, sizeof path, rel);
  if (!tu_have_file(path)) return 0;
  bbc_error err;
  bbc_load_options opts;
  bbc_load_options_default(&opts);
  progress_log prog = {0, 0, 0, 0.0};
  opts.callbacks.progress = on_progress;
  opts.callbacks.user = &prog;
  bbc_result r = bbc_mesh_load(path, &opts, mesh, &err);
  if (r != BBC_OK) printf("  %s: %s\n", path, err.message);
  assert_int_equal(r, BBC_OK);
  assert_int_equal(prog.ones, 1);
  assert_true(prog.last == 1.0);
  assert_false(prog.decreasing);
  return 1;
}

typedef struct fixture {
  char *dir;
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  if (!f) return -1;
  f->dir = tu_make_temp_dir();
  if (!f->dir) {
    free(f);
    return -1;
  }
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  tu_remove_dir(f->dir);
  free(f->dir);
  free(f);
  return 0;
}

/* Writes a file into the fixture's folder; caller frees the path. */
static char *write_text(void **state, const char *name, const char *text) {
  fixture *f = *state;
  char *p = tu_write_file(f->dir, name, text, strlen(text));
  assert_non_null(p);
  return p;
}

/* A growable byte buffer for binary PLY bodies. */
typedef struct bytes {
  unsigned char data[4096];
  size_t n;
} bytes;

static void put(bytes *b, const void *src, size_t n, int big_endian) {
  assert_true(b->n + n <= sizeof b->data);
  const unsigned char *s = src;
  /* Tests run on little-endian hosts; check that assumption once. */
  const uint16_t one = 1;
  unsigned char first;
  memcpy(&first, &one, 1);
  assert_int_equal(first, 1);
  for (size_t i = 0; i < n; i++) b->data[b->n + i] = big_endian ? s[n - 1 - i] : s[i];
  b->n += n;
}
static void put_text(bytes *b, const char *s) {
  size_t n = strlen(s);
  assert_true(b->n + n <= sizeof b->data);
  memcpy(b->data + b->n, s, n);
  b->n += n;
}
static void put_f32(bytes *b, float v, int be) {
  put(b, &v, 4, be);
}
static void put_f64(bytes *b, double v, int be) {
  put(b, &v, 8, be);
}
static void put_u8(bytes *b, uint8_t v) {
  put(b, &v, 1, 0);
}
static void put_i16(bytes *b, int16_t v, int be) {
  put(b, &v, 2, be);
}
static void put_i32(bytes *b, int32_t v, int be) {
  put(b, &v, 4, be);
}

static char *write_bytes(void **state, const char *name, const bytes *b) {
  fixture *f = *state;
  char *p = tu_write_file(f->dir, name, b->data, b->n);
  assert_non_null(p);
  return p;
}

static void expect_failure(const char *path, bbc_result code, const char *needle1,
                           const char *needle2) {
  bbc_mesh mesh;
  bbc_error err;
  bbc_result r = load(path, &mesh, &err);
  assert_int_equal(r, code);
  assert_int_equal(err.code, code);
  assert_null(mesh.positions);
  assert_int_equal(mesh.vertex_count, 0);
  assert_non_null(strstr(err.message, path)); /* messages start with the file */
  assert_ptr_equal(strstr(err.message, path), err.message);
  assert_null(strchr(err.message, '\n')); /* one line */
  if (needle1) assert_non_null(strstr(err.message, needle1));
  if (needle2) assert_non_null(strstr(err.message, needle2));
}

/* ---- real files ---------------------------------------------------------- */

static void test_b9_training(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("points/b9_training.ply", &m)) {
    skip();
    return;
  }
  assert_int_equal(m.kind, BBC_MESH_POINTS);
  assert_int_equal(m.vertex_count, 22300);
  assert_int_equal(m.triangle_count, 0);
  assert_non_null(m.colors);
  assert_null(m.normals);
  /* The first record, decoded independently: doubles right after the header,
   * then three colour bytes. */
  char path[1024];
  size_t size = 0;
  unsigned char *raw =
      tu_read_file(tu_data_path(path, sizeof path, "points/b9_training.ply"), &size);
  assert_non_null(raw);
  const char *eh = strstr((const char *)raw, "end_header\n");
  assert_non_null(eh);
  const unsigned char *body = (const unsigned char *)eh + strlen("end_header\n");
  double first[3];
  memcpy(first, body, sizeof first);
  for (int k = 0; k < 3; k++) /* moved by the origin when far from 0 */
    assert_true(fabs(m.positions[k] + m.origin[k] - first[k]) <= 1e-9 * (1 + fabs(first[k])));
  assert_int_equal(m.colors[0], body[24]);
  assert_int_equal(m.colors[1], body[25]);
  assert_int_equal(m.colors[2], body[26]);
  assert_int_equal(m.colors[3], 255);
  /* The last record as well: the whole body was walked in step. */
  const unsigned char *last = body + (size_t)22299 * 31;
  memcpy(first, last, sizeof first);
  for (int k = 0; k < 3; k++)
    assert_true(fabs(m.positions[3 * 22299 + k] + m.origin[k] - first[k]) <=
                1e-9 * (1 + fabs(first[k])));
  free(raw);
  /* Colours vary (it is an RGB scan, not one constant). */
  int varied = 0;
  for (size_t i = 1; i < m.vertex_count && !varied; i++)
    varied = memcmp(m.colors, m.colors + 4 * i, 3) != 0;
  assert_true(varied);
  assert_true(m.radius > 0);
  bbc_mesh_free(&m);
}

static void check_unit_normals(const bbc_mesh *m) {
  assert_non_null(m->normals);
  for (size_t i = 0; i < m->vertex_count; i++) {
    const float *n = m->normals + 3 * i;
    double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
    assert_true(fabs(len - 1.0) < 1e-5 || len == 0.0);
  }
}

static void test_ball(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("points/ball.ply", &m)) {
    skip();
    return;
  }
  assert_int_equal(m.vertex_count, 31374);
  assert_null(m.colors);
  check_unit_normals(&m);
  /* First line: 37.3579 -12.3512 -3.52648 0.82434 0.366492 0.431448 1 */
  assert_true(m.positions[0] == 37.3579);
  assert_true(m.positions[1] == -12.3512);
  assert_true(m.positions[2] == -3.52648);
  assert_true(fabs(m.normals[0] - 0.82434) < 1e-4);
  bbc_mesh_free(&m);
}

static void test_hippo(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("points/hippo1.ply", &m)) {
    skip();
    return;
  }
  assert_int_equal(m.vertex_count, 6104);
  assert_null(m.colors);
  check_unit_normals(&m);
  bbc_mesh_free(&m);
}

static void test_pond_damaged(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "points/pond.0.ply");
  if (!tu_have_file(path)) {
    skip();
    return;
  }
  bbc_mesh m;
  bbc_error err;
  bbc_result r = load(path, &m, &err);
  assert_int_equal(r, BBC_ERROR_CORRUPT);
  assert_non_null(strstr(err.message, "pond.0.ply"));
  assert_true(strstr(err.message, "truncated") || strstr(err.message, "damaged"));
  /* The size check, not the NaN it would meet later, is the reason given. */
  assert_non_null(strstr(err.message, "69 bytes shorter"));
  assert_non_null(strstr(err.message, "70051 vertices"));
  assert_null(m.positions);
}

static void test_xyz_counts(void **state) {
  (void)state;
  static const struct {
    const char *rel;
    size_t count;
  } files[] = {{"points/adtree/tree7.xyz", 15130},
               {"points/adtree/tree13.xyz", 6992},
               {"points/adtree/house.xyz", 7706},
               {"points/lidr_tree.xyz", 17709}};
  int loaded = 0;
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
    bbc_mesh m;
    if (!load_data(files[i].rel, &m)) continue;
    assert_int_equal(m.kind, BBC_MESH_POINTS);
    assert_int_equal(m.vertex_count, files[i].count);
    assert_null(m.normals);
    assert_null(m.colors);
    bbc_mesh_free(&m);
    loaded++;
  }
  if (!loaded) skip();
}

/* UTM coordinates (5e5, 5e6) must survive in full double precision: the
 * centre equals the mean computed here in long double from the text. */
static void test_lidr_precision(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("points/lidr_tree.xyz", &m)) {
    skip();
    return;
  }
  char path[1024];
  size_t size = 0;
  char *text = (char *)tu_read_file(tu_data_path(path, sizeof path, "points/lidr_tree.xyz"), &size);
  assert_non_null(text);
  long double sum[3] = {0, 0, 0};
  size_t n = 0;
  for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
    if (line[0] == '#') continue;
    char *p = line;
    long double v[3];
    for (int k = 0; k < 3; k++) v[k] = strtold(p, &p);
    if (n == 0) {
      /* The first point read as doubles, moved by the whole-unit origin
       * (georeferenced: the centre rounded), so that as a float it keeps
       * a tenth of a millimetre. */
      const double want[3] = {519054.680, 5357592.050, 4.760};
      for (int k = 0; k < 3; k++) {
        assert_true(m.origin[k] == round(m.origin[k]));
        assert_true(fabs(m.positions[k] + m.origin[k] - want[k]) < 1e-9);
        assert_true(fabs((double)(float)m.positions[k] + m.origin[k] - want[k]) < 1e-4);
      }
      assert_true(m.origin[0] > 5e5 && m.origin[1] > 5e6);
    }
    for (int k = 0; k < 3; k++) sum[k] += v[k];
    n++;
  }
  free(text);
  assert_int_equal(n, 17709);
  for (int k = 0; k < 3; k++) {
    double mean = (double)(sum[k] / (long double)n);
    if (fabs(m.center[k] + m.origin[k] - mean) > 1e-6)
      printf("  centre[%d] %.9f vs mean %.9f\n", k, m.center[k] + m.origin[k], mean);
    assert_true(fabs(m.center[k] + m.origin[k] - mean) <= 1e-6);
    assert_true(fabs(m.center[k]) < 1); /* near 0 */
  }
  /* Bounds: the input's, moved by the same origin. */
  assert_true(m.bbox_min[0] + m.origin[0] > 5e5 && m.bbox_max[1] + m.origin[1] < 6e6);
  bbc_mesh_free(&m);
}

/* ---- hand-made PLY files ------------------------------------------------- */

static const char ascii_header[] = "ply\nformat ascii 1.0\nelement vertex 3\n"
                                   "property float x\nproperty float y\nproperty float z\n"
                                   "end_header\n";

static void test_ply_ascii_nan(void **state) {
  char text[512];
  snprintf(text, sizeof text, "%s0 0 0\n1 nan 2\n3 4 5\n", ascii_header);
  char *p = write_text(state, "nan.ply", text);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 1 ", "nan");
  free(p);
  snprintf(text, sizeof text, "%s0 0 0\n1 1 2\n3 4 -1e38\n", ascii_header);
  p = write_text(state, "huge.ply", text);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 2 ", "line 10");
  free(p);
}

static void test_ply_ascii_malformed_lines(void **state) {
  char text[512];
  snprintf(text, sizeof text, "%s0 0 0\n1 2\n3 4 5\n", ascii_header);
  char *p = write_text(state, "short.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 9", "too few");
  free(p);
  snprintf(text, sizeof text, "%s0 0 0\n1 x 2\n3 4 5\n", ascii_header);
  p = write_text(state, "word.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 9", "'x'");
  free(p);
  snprintf(text, sizeof text, "%s0 0 0\n1 1 2 7\n3 4 5\n", ascii_header);
  p = write_text(state, "long.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 9", "more values");
  free(p);
  snprintf(text, sizeof text, "%s0 0 0\n1 1 2\n", ascii_header);
  p = write_text(state, "cut.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "truncated", NULL);
  free(p);
  snprintf(text, sizeof text, "%s0 0 0\n1 1 2\n3 4 5\n6 7 8\n", ascii_header);
  p = write_text(state, "trailing.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 11", "after the last element");
  free(p);
}

static void test_ply_ascii_crlf_and_types(void **state) {
  /* Windows line ends, comments, obj_info, aliases, float colours in [0,1],
   * normals to be normalised, blank line at the end. */
  const char *text = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info x\r\n"
                     "element vertex 2\r\nproperty float64 x\r\nproperty float32 y\r\n"
                     "property int16 z\r\nproperty float nx\r\nproperty float ny\r\n"
                     "property float nz\r\nproperty float red\r\nproperty float green\r\n"
                     "property float blue\r\nend_header\r\n"
                     "1.5 2.5 3 0 0 2 1 0.5 0\r\n-1 -2 -3 3 4 0 0 1 0.25\r\n\r\n";
  char *p = write_text(state, "crlf.ply", text);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.vertex_count, 2);
  assert_true(m.positions[0] == 1.5 && m.positions[1] == 2.5 && m.positions[2] == 3);
  assert_true(m.positions[3] == -1 && m.positions[4] == -2 && m.positions[5] == -3);
  assert_non_null(m.normals);
  assert_true(fabsf(m.normals[2] - 1.0f) < 1e-6f);
  assert_true(fabsf(m.normals[3] - 0.6f) < 1e-6f && fabsf(m.normals[4] - 0.8f) < 1e-6f);
  assert_non_null(m.colors);
  assert_int_equal(m.colors[0], 255);
  assert_int_equal(m.colors[1], 128);
  assert_int_equal(m.colors[2], 0);
  assert_int_equal(m.colors[3], 255);
  assert_int_equal(m.colors[6], 64);
  assert_true(m.center[0] == 0.25);
  bbc_mesh_free(&m);
  free(p);
}

/* Elements before and after the vertices, with lists, are skipped. */
static void test_ply_extra_elements(void **state) {
  const char *text = "ply\nformat ascii 1.0\n"
                     "element camera 1\nproperty float fx\nproperty list uchar int ids\n"
                     "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                     "property list uchar float extra\nproperty uchar red\n"
                     "property uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                     "element face 0\nproperty list uchar int vertex_indices\n"
                     "element segment 2\nproperty list int int points\nproperty int id\n"
                     "end_header\n"
                     "500 3 1 2 3\n"
                     "1 2 3 2 0.5 0.25 10 20 30 40\n"
                     "4 5 6 0 50 60 70 80\n"
                     "3 0 1 1 7\n"
                     "0 8\n";
  char *p = write_text(state, "extra.ply", text);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.vertex_count, 2);
  assert_true(m.positions[3] == 4 && m.positions[4] == 5 && m.positions[5] == 6);
  assert_null(m.normals);
  assert_non_null(m.colors);
  assert_memory_equal(m.colors, ((const uint8_t[]){10, 20, 30, 40, 50, 60, 70, 80}), 8);
  bbc_mesh_free(&m);
  free(p);

  /* The same in binary: a list element after the vertices. */
  bytes b = {{0}, 0};
  put_text(&b, "ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
               "property double x\nproperty double y\nproperty double z\n"
               "element segment 3\nproperty list uchar int points\nproperty float w\n"
               "end_header\n");
  for (int i = 0; i < 6; i++) put_f64(&b, 0.5 * i, 0);
  put_u8(&b, 2);
  put_i32(&b, 0, 0);
  put_i32(&b, 1, 0);
  put_f32(&b, 1.0f, 0);
  put_u8(&b, 0);
  put_f32(&b, 2.0f, 0);
  put_u8(&b, 1);
  put_i32(&b, 1, 0);
  put_f32(&b, 3.0f, 0);
  p = write_bytes(state, "extra_bin.ply", &b);
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.vertex_count, 2);
  assert_true(m.positions[5] == 2.5);
  bbc_mesh_free(&m);
  free(p);

  /* One list item missing at the end: the walk notices. */
  b.n -= 5;
  put_f32(&b, 3.0f, 0);
  p = write_bytes(state, "extra_bin_cut.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "segment 2", "truncated");
  free(p);
}

static void build_binary(bytes *b, int big_endian, int vertices) {
  char header[512];
  snprintf(header, sizeof header,
           "ply\nformat %s 1.0\ncomment big or little\nelement vertex %d\n"
           "property float x\nproperty float y\nproperty float z\nproperty short label\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
           "property double nx\nproperty double ny\nproperty double nz\nend_header\n",
           big_endian ? "binary_big_endian" : "binary_little_endian", vertices);
  b->n = 0;
  put_text(b, header);
  for (int i = 0; i < vertices; i++) {
    put_f32(b, 1.25f + (float)i, big_endian);
    put_f32(b, -2.5f * (float)i, big_endian);
    put_f32(b, 1024.0f, big_endian);
    put_i16(b, (int16_t)(-300 + i), big_endian);
    put_u8(b, (uint8_t)(10 * i));
    put_u8(b, 200);
    put_u8(b, 7);
    put_f64(b, 0.0, big_endian);
    put_f64(b, -2.0, big_endian);
    put_f64(b, 0.0, big_endian);
  }
}

static void check_binary(const bbc_mesh *m, int vertices) {
  assert_int_equal(m->vertex_count, (size_t)vertices);
  for (int i = 0; i < vertices; i++) {
    assert_true(m->positions[3 * i] == 1.25 + i);
    assert_true(m->positions[3 * i + 1] == -2.5 * i);
    assert_true(m->positions[3 * i + 2] == 1024.0);
    assert_int_equal(m->colors[4 * i], 10 * i);
    assert_int_equal(m->colors[4 * i + 1], 200);
    assert_int_equal(m->colors[4 * i + 2], 7);
    assert_int_equal(m->colors[4 * i + 3], 255);
    assert_true(m->normals[3 * i] == 0.0f && m->normals[3 * i + 1] == -1.0f);
  }
}

static void test_ply_binary_endianness(void **state) {
  for (int be = 0; be <= 1; be++) {
    bytes b;
    build_binary(&b, be, 5);
    char *p = write_bytes(state, be ? "be.ply" : "le.ply", &b);
    bbc_mesh m;
    bbc_error err;
    assert_int_equal(load(p, &m, &err), BBC_OK);
    check_binary(&m, 5);
    bbc_mesh_free(&m);
    free(p);
  }
}

static void test_ply_binary_truncated(void **state) {
  bytes b;
  build_binary(&b, 0, 5);
  b.n -= 40; /* cut in the middle of the last record */
  char *p = write_bytes(state, "cut.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "40 bytes shorter than the 5 vertices", "truncated");
  free(p);

  /* A text-mode conversion that dropped bytes: same diagnosis. */
  build_binary(&b, 0, 5);
  memmove(b.data + b.n - 60, b.data + b.n - 59, 59);
  b.n--;
  p = write_bytes(state, "shifted.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "1 byte shorter", "line-ending conversion");
  free(p);

  /* Trailing junk after the last record. */
  build_binary(&b, 0, 5);
  put_text(&b, "JUNKJUNK");
  p = write_bytes(state, "junk.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "8 bytes longer", NULL);
  free(p);

  /* A single trailing newline is harmless. */
  build_binary(&b, 0, 5);
  put_text(&b, "\n");
  p = write_bytes(state, "newline.ply", &b);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  check_binary(&m, 5);
  bbc_mesh_free(&m);
  free(p);
}

static void test_ply_binary_absurd_values(void **state) {
  bytes b;
  build_binary(&b, 1, 3);
  char *p;
  /* Second vertex x = 1e38 (big-endian float). */
  size_t header = b.n - 3 * 41;
  float huge = 1e38f;
  unsigned char raw[4], swapped[4];
  memcpy(raw, &huge, 4);
  for (int k = 0; k < 4; k++) swapped[k] = raw[3 - k];
  memcpy(b.data + header + 41, swapped, 4);
  p = write_bytes(state, "huge.ply", &b);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 1 ", "1e+38");
  free(p);

  float nan = NAN;
  build_binary(&b, 0, 3);
  header = b.n - 3 * 41; /* "little" is not as long as "big" */
  memcpy(b.data + header + 2 * 41 + 8, &nan, 4);
  p = write_bytes(state, "nan.ply", &b);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 2 ", "nan");
  free(p);
}

static void test_ply_header_errors(void **state) {
  /* No end_header: the PLY reader says exactly what is wrong (Assimp 5.2
   * loops forever on this one, which is why no .ply goes to Assimp). */
  const char *text = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                     "property float y\nproperty float z\n0 0 0\n1 1 1\n";
  char *p = write_text(state, "noend.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 7", "no end_header");
  free(p);
  p = write_text(state, "noend2.ply", "ply\nformat ascii 1.0\nelement vertex 2\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "no end_header", "truncated");
  free(p);

  static const struct {
    const char *name, *text, *needle;
    bbc_result code;
  } cases[] = {
      /* Not PLY at all, despite the name: refused, not handed to Assimp. */
      {"magic.ply", "plx\nformat ascii 1.0\nend_header\n", "not a PLY file",
       BBC_ERROR_UNSUPPORTED_FORMAT},
      {"format.ply", "ply\nformat text 1.0\nelement vertex 1\nend_header\n1\n", "format 'text'",
       BBC_ERROR_CORRUPT},
      {"type.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property quad z\nend_header\n1 2 3\n",
       "unknown type 'quad'", BBC_ERROR_CORRUPT},
      {"keyword.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperties float x\nend_header\n",
       "line 4", BBC_ERROR_CORRUPT},
      {"count.ply", "ply\nformat ascii 1.0\nelement vertex -5\nend_header\n", "line 3",
       BBC_ERROR_CORRUPT},
      {"noxyz.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n1 2\n",
       "'z'", BBC_ERROR_CORRUPT},
      {"binary.ply", "ply\nformat ascii 1.0\nel\x01\x02ment vertex 1\nend_header\n", "binary data",
       BBC_ERROR_CORRUPT},
      {"empty.ply", "", "empty", BBC_ERROR_EMPTY},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    p = write_text(state, cases[i].name, cases[i].text);
    expect_failure(p, cases[i].code, cases[i].needle, NULL);
    free(p);
  }
}

static void test_ply_absurd_count(void **state) {
  const char *text = "ply\nformat ascii 1.0\nelement vertex 1000000000000\n"
                     "property float x\nproperty float y\nproperty float z\nend_header\n"
                     "0 0 0\n";
  char *p = write_text(state, "count_ascii.ply", text);
  expect_failure(p, BBC_ERROR_CORRUPT, "1000000000000 vertices", "truncated");
  free(p);
  bytes b;
  build_binary(&b, 0, 2);
  const char *bin_header = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                           "property float x\nproperty float y\nproperty float z\nend_header\n";
  b.n = 0;
  put_text(&b, bin_header);
  for (int i = 0; i < 6; i++) put_f32(&b, 1.0f, 0);
  p = write_bytes(state, "count_bin.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "1000000000000 vertices", "truncated");
  free(p);
  /* So large that count * record size overflows 64 bits. */
  b.n = 0;
  put_text(&b, "ply\nformat binary_big_endian 1.0\nelement vertex 18446744073709551615\n"
               "property double x\nproperty double y\nproperty double z\nend_header\n");
  put_f64(&b, 1.0, 1);
  p = write_bytes(state, "count_overflow.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "damaged", NULL);
  free(p);
}

static void test_ply_zero_vertices(void **state) {
  const char *text = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n";
  char *p = write_text(state, "zero.ply", text);
  expect_failure(p, BBC_ERROR_EMPTY, "0 vertices", NULL);
  free(p);
}

/* A face element with records makes a mesh; "element face 0" does not. */
static void test_ply_routing(void **state) {
  const char *mesh = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                     "property float y\nproperty float z\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n"
                     "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  char *p = write_text(state, "mesh.ply", mesh);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_TRIANGLES);
  assert_int_equal(m.triangle_count, 1);
  bbc_mesh_free(&m);
  free(p);
  const char *cloud = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 0\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n";
  p = write_text(state, "cloud.ply", cloud);
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_POINTS);
  assert_int_equal(m.vertex_count, 3);
  assert_int_equal(m.triangle_count, 0);
  bbc_mesh_free(&m);
  free(p);
}

static void test_ply_negative_list(void **state) {
  bytes b = {{0}, 0};
  put_text(&b, "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
               "property float x\nproperty float y\nproperty float z\n"
               "element seg 1\nproperty list char int ids\nend_header\n");
  for (int i = 0; i < 3; i++) put_f32(&b, 1.0f, 0);
  put_u8(&b, 0xff); /* -1 as char */
  for (int i = 0; i < 4; i++) put_i32(&b, 0, 0);
  char *p = write_bytes(state, "negative.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "negative length", "seg 0");
  free(p);
}

static void test_missing_file(void **state) {
  fixture *f = *state;
  char path[1024];
  snprintf(path, sizeof path, "%s/absent.xyz", f->dir);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(path, &m, &err), BBC_ERROR_NOT_FOUND);
  snprintf(path, sizeof path, "%s/absent.ply", f->dir);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_FOUND);
  assert_int_equal(load(path, &m, &err), BBC_ERROR_NOT_FOUND);
  /* folders named like a PLY and an XYZ file */
  snprintf(path, sizeof path, "%s/folder.ply", f->dir);
  assert_int_equal(mkdir(path, 0777), 0);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_A_FILE);
  snprintf(path, sizeof path, "%s/folder.xyz", f->dir);
  assert_int_equal(mkdir(path, 0777), 0);
  assert_int_equal(bbc_mesh_load(path, NULL, &m, &err), BBC_ERROR_NOT_A_FILE);
}

/* ---- hand-made PLY meshes ------------------------------------------------ */

/* A unit square (vertices 0-3, z = 0) and a convex pentagon (vertices 4-8,
 * z = 1), counter-clockwise seen from +z: the quad must become 2 triangles,
 * the pentagon 3, as fans from their first corner. */
static const double k_poly_pos[9][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1},
                                        {2, 0, 1}, {3, 1, 1}, {1, 3, 1}, {-1, 1, 1}};
static const uint32_t k_poly_tris[15] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8};

/* The two polygons in ASCII with normals and (s, t) texture coordinates. */
static void poly_ascii(char *out, size_t size, const char *faces) {
  int n = snprintf(out, size, "%s",
                   "ply\nformat ascii 1.0\ncomment a quad and a pentagon\nelement vertex 9\n"
                   "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
                   "property float ny\nproperty float nz\nproperty float s\nproperty float t\n"
                   "element face 2\nproperty list uchar int vertex_indices\nend_header\n");
  for (int i = 0; i < 9; i++) {
    const double *p = k_poly_pos[i];
    n += snprintf(out + n, size - (size_t)n, "%g %g %g 0 0 %d %g %g\n", p[0], p[1], p[2],
                  i < 4 ? 1 : 3, p[0] / 4, p[1] / 4);
  }
  snprintf(out + n, size - (size_t)n, "%s", faces);
}

/* The same in binary with other types and names: double coordinates, float
 * normals, (texture_u, texture_v), a colour (ignored for meshes), faces
 * with a flag before and per-face texture coordinates after the index list
 * ("vertex_index", uint indices), and an element after the faces. */
static void poly_binary(bytes *b, int be) {
  b->n = 0;
  put_text(b,
           be ? "ply\nformat binary_big_endian 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
  put_text(b, "element vertex 9\nproperty double x\nproperty double y\nproperty double z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              "property float texture_u\nproperty float texture_v\nproperty uchar red\n"
              "element face 2\nproperty uchar flags\nproperty list uchar uint vertex_index\n"
              "property list uchar float texcoord\nelement edge 1\nproperty int vertex1\n"
              "property int vertex2\nend_header\n");
  for (int i = 0; i < 9; i++) {
    const double *p = k_poly_pos[i];
    for (int k = 0; k < 3; k++) put_f64(b, p[k], be);
    put_f32(b, 0.0f, be);
    put_f32(b, 0.0f, be);
    put_f32(b, i < 4 ? 1.0f : 3.0f, be);
    put_f32(b, (float)(p[0] / 4), be);
    put_f32(b, (float)(p[1] / 4), be);
    put_u8(b, 200);
  }
  for (int f = 0; f < 2; f++) {
    int n = f == 0 ? 4 : 5, first = f == 0 ? 0 : 4;
    put_u8(b, 7); /* flags */
    put_u8(b, (uint8_t)n);
    for (int j = 0; j < n; j++) put_i32(b, first + j, be);
    put_u8(b, (uint8_t)(2 * n));
    for (int j = 0; j < 2 * n; j++) put_f32(b, 0.5f, be);
  }
  put_i32(b, 0, be);
  put_i32(b, 1, be);
}

static void check_poly_mesh(const bbc_mesh *m, const char *stem) {
  assert_int_equal(m->kind, BBC_MESH_TRIANGLES);
  assert_int_equal(m->vertex_count, 9);
  assert_int_equal(m->triangle_count, 5);
  assert_int_equal(m->triangles_read, 5);
  assert_int_equal(m->dropped_degenerate, 0);
  assert_memory_equal(m->indices, k_poly_tris, sizeof k_poly_tris);
  for (int i = 0; i < 9; i++)
    for (int k = 0; k < 3; k++) assert_true(m->positions[3 * i + k] == k_poly_pos[i][k]);
  /* The file's normals, normalised; its texture coordinates as written. */
  assert_non_null(m->normals);
  assert_int_equal(m->normals_generated, 0);
  assert_non_null(m->uvs);
  for (int i = 0; i < 9; i++) {
    assert_true(m->normals[3 * i] == 0.0f && m->normals[3 * i + 1] == 0.0f);
    assert_true(m->normals[3 * i + 2] == 1.0f);
    assert_true(m->uvs[2 * i] == (float)(k_poly_pos[i][0] / 4));
    assert_true(m->uvs[2 * i + 1] == (float)(k_poly_pos[i][1] / 4));
  }
  assert_null(m->colors);
  /* One material, one group named after the file. */
  assert_int_equal(m->material_count, 1);
  assert_string_equal(m->materials[0].name, "default");
  for (int k = 0; k < 3; k++) assert_true(m->materials[0].base_color[k] == 0.8f);
  assert_true(m->materials[0].base_color[3] == 1.0f);
  assert_int_equal(m->materials[0].texture, -1);
  assert_null(m->materials[0].texture_ref);
  assert_int_equal(m->texture_count, 0);
  assert_int_equal(m->group_count, 1);
  assert_string_equal(m->group_names[0], stem);
  for (size_t t = 0; t < m->triangle_count; t++) {
    assert_int_equal(m->face_material[t], 0);
    assert_int_equal(m->face_group[t], 0);
  }
  assert_true(m->radius > 0);
}

static void test_ply_mesh_ascii(void **state) {
  char text[2048];
  poly_ascii(text, sizeof text, "4 0 1 2 3\n5 4 5 6 7 8\n");
  char *p = write_text(state, "polygons.ply", text);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  check_poly_mesh(&m, "polygons");
  bbc_mesh_free(&m);
  free(p);
}

static void test_ply_mesh_binary(void **state) {
  for (int be = 0; be <= 1; be++) {
    bytes b;
    poly_binary(&b, be);
    char *p = write_bytes(state, be ? "poly_be.ply" : "poly_le.ply", &b);
    bbc_mesh m;
    bbc_error err;
    assert_int_equal(load(p, &m, &err), BBC_OK);
    check_poly_mesh(&m, be ? "poly_be" : "poly_le");
    bbc_mesh_free(&m);
    free(p);

    /* Cut inside the last record, and cut short of the minimum size. */
    bytes cut = b;
    cut.n -= 5;
    p = write_bytes(state, "poly_cut.ply", &cut);
    expect_failure(p, BBC_ERROR_CORRUPT, "edge 0", "truncated");
    free(p);
    cut.n -= 200; /* below the minimum: every list empty */
    p = write_bytes(state, "poly_short.ply", &cut);
    expect_failure(p, BBC_ERROR_CORRUPT, "shorter", "at least");
    free(p);
    /* Junk after the last record. */
    put_text(&b, "JUNK");
    p = write_bytes(state, "poly_junk.ply", &b);
    expect_failure(p, BBC_ERROR_CORRUPT, "4 bytes longer", NULL);
    free(p);
  }
}

/* One triangle with three vertices; `faces` follows the vertices. */
static char *tri_ascii(void **state, const char *name, const char *vertices, const char *faces,
                       int face_count) {
  char text[1024];
  snprintf(text, sizeof text,
           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
           "end_header\n%s%s",
           face_count, vertices ? vertices : "0 0 0\n1 0 0\n0 1 0\n", faces);
  return write_text(state, name, text);
}

/* The same in binary: int indices (or `index_type`). Returns the header
 * length: the vertices start there, 12 bytes each, then the face. */
static size_t tri_binary(bytes *b, int be, const char *index_type, const int32_t *indices,
                         int count) {
  char header[512];
  snprintf(header, sizeof header,
           "ply\nformat %s 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar %s vertex_indices\n"
           "end_header\n",
           be ? "binary_big_endian" : "binary_little_endian", index_type);
  b->n = 0;
  put_text(b, header);
  static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int i = 0; i < 9; i++) put_f32(b, v[i], be);
  put_u8(b, (uint8_t)count);
  for (int i = 0; i < count; i++) {
    if (!strcmp(index_type, "short"))
      put_i16(b, (int16_t)indices[i], be);
    else
      put_i32(b, indices[i], be);
  }
  return strlen(header);
}

static void test_ply_mesh_bad_faces(void **state) {
  /* Out of range: refused with the file, the face and the numbers (Assimp
   * read vertex 21912 from uninitialised memory for this). */
  char *p = tri_ascii(state, "range.ply", NULL, "3 0 1 9\n3 0 1 2\n", 2);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY,
                 "face 0 refers to vertex 9, but the file has 3 "
                 "vertices",
                 "line 13");
  free(p);
  p = tri_ascii(state, "negative.ply", NULL, "3 0 1 2\n3 0 -1 2\n", 2);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "face 1 refers to vertex -1", NULL);
  free(p);
  p = tri_ascii(state, "two.ply", NULL, "3 0 1 2\n2 0 1\n", 2);
  expect_failure(p, BBC_ERROR_CORRUPT, "face 1 has 2 vertex indices", "at least 3");
  free(p);
  p = tri_ascii(state, "none.ply", NULL, "0\n", 1);
  expect_failure(p, BBC_ERROR_CORRUPT, "face 0 has 0 vertex indices", NULL);
  free(p);
  p = tri_ascii(state, "fraction.ply", NULL, "3 0 1.5 2\n", 1);
  expect_failure(p, BBC_ERROR_CORRUPT, "face 0", "whole number");
  free(p);
  p = tri_ascii(state, "missing.ply", NULL, "3 0 1 2\n", 2);
  expect_failure(p, BBC_ERROR_CORRUPT, "1 of the 2 face records", "truncated");
  free(p);
  p = tri_ascii(state, "items.ply", NULL, "3 0 1\n", 1);
  expect_failure(p, BBC_ERROR_CORRUPT, "line 13", "2 of the 3 items");
  free(p);
  p = tri_ascii(state, "nan.ply", "0 0 0\nnan 0 0\n0 1 0\n", "3 0 1 2\n", 1);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 1 ", "line 11");
  free(p);
  p = tri_ascii(state, "huge.ply", "0 0 0\n1 0 0\n0 1e38 0\n", "3 0 1 2\n", 1);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "vertex 2 ", "absurd");
  free(p);
  /* All corners on a line: finalize drops it and nothing is left. */
  p = tri_ascii(state, "flat.ply", "0 0 0\n1 0 0\n2 0 0\n", "3 0 1 2\n", 1);
  expect_failure(p, BBC_ERROR_EMPTY, "non-zero area", NULL);
  free(p);

  /* Binary, both byte orders. */
  for (int be = 0; be <= 1; be++) {
    bytes b;
    char where[80];
    size_t header = tri_binary(&b, be, "int", (const int32_t[]){0, 1, 9}, 3);
    snprintf(where, sizeof where, "face 0 (byte offset %zu) refers to vertex 9", header + 36);
    p = write_bytes(state, "range_bin.ply", &b);
    expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, where, "3 vertices");
    free(p);
    tri_binary(&b, be, "int", (const int32_t[]){0, -1, 2}, 3);
    p = write_bytes(state, "negative_bin.ply", &b);
    expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "face 0", "refers to vertex -1");
    free(p);
    tri_binary(&b, be, "short", (const int32_t[]){2, -7, 0}, 3);
    p = write_bytes(state, "negative_short.ply", &b);
    expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "face 0", "refers to vertex -7");
    free(p);
    tri_binary(&b, be, "int", (const int32_t[]){0, 1}, 2);
    p = write_bytes(state, "two_bin.ply", &b);
    snprintf(where, sizeof where, "face 0 (byte offset %zu) has 2 vertex indices", header + 36);
    expect_failure(p, BBC_ERROR_CORRUPT, where, NULL);
    free(p);
    tri_binary(&b, be, "int", (const int32_t[]){2, 1, 0}, 3);
    p = write_bytes(state, "ok_bin.ply", &b);
    bbc_mesh m;
    bbc_error err;
    assert_int_equal(load(p, &m, &err), BBC_OK);
    assert_int_equal(m.triangle_count, 1);
    assert_memory_equal(m.indices, ((const uint32_t[]){2, 1, 0}), 3 * sizeof(uint32_t));
    assert_int_equal(m.normals_generated, 1);
    assert_true(m.normals[2] == -1.0f); /* clockwise from +z: faces -z */
    bbc_mesh_free(&m);
    free(p);
    b.n -= 3; /* cut inside the last index */
    p = write_bytes(state, "cut_bin.ply", &b);
    expect_failure(p, BBC_ERROR_CORRUPT, "face 0", "truncated");
    free(p);
    /* NaN in the last vertex. */
    tri_binary(&b, be, "int", (const int32_t[]){0, 1, 2}, 3);
    unsigned char nan_bytes[4];
    float nan = NAN;
    memcpy(nan_bytes, &nan, 4);
    for (int k = 0; k < 4; k++) b.data[header + 24 + 8 + k] = nan_bytes[be ? 3 - k : k];
    p = write_bytes(state, "nan_bin.ply", &b);
    snprintf(where, sizeof where, "vertex 2 (byte offset %zu)", header + 24);
    expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, where, "nan");
    free(p);
  }
}

static void test_ply_mesh_header_problems(void **state) {
  /* No end_header: refused at once (Assimp 5.2 never returns on this). */
  time_t start = time(NULL);
  char *p = write_text(state, "noend_mesh.ply",
                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list uchar int vertex_indices\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "line 9", "no end_header");
  free(p);
  bytes b;
  tri_binary(&b, 0, "int", (const int32_t[]){0, 1, 2}, 3);
  char *eh = strstr((char *)b.data, "end_header\n");
  assert_non_null(eh);
  memmove(eh, eh + 11, b.n - (size_t)((unsigned char *)eh + 11 - b.data));
  b.n -= 11;
  p = write_bytes(state, "noend_bin.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "binary data", "no end_header");
  free(p);
  /* A long header without end_header: only the first MiB is scanned. */
  size_t big = 3u << 20;
  char *text = malloc(big + 1);
  assert_non_null(text);
  size_t n = (size_t)snprintf(text, big, "ply\nformat ascii 1.0\nelement face 1\n");
  while (n + 16 < big) n += (size_t)snprintf(text + n, big - n, "comment %06zu\n", n % 999999);
  fixture *f = *state;
  p = tu_write_file(f->dir, "noend_big.ply", text, n);
  assert_non_null(p);
  free(text);
  expect_failure(p, BBC_ERROR_CORRUPT, "no end_header", "first 1048576 bytes");
  free(p);
  assert_true(time(NULL) - start < 30);

  /* A face element without an index list. */
  p = write_text(state, "nolist.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 "property float y\nproperty float z\nelement face 1\n"
                 "property list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "'face'", "'vertex_indices'");
  free(p);
  p = write_text(state, "scalar.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 "property float y\nproperty float z\nelement face 1\n"
                 "property int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "not a list", NULL);
  free(p);
  /* Faces declared but no vertex element at all. */
  p = write_text(state, "novertex.ply",
                 "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int "
                 "vertex_indices\nend_header\n3 0 1 2\n");
  expect_failure(p, BBC_ERROR_EMPTY, "no vertex element", NULL);
  free(p);
  /* Absurd face count: the size check refuses it before allocating. */
  p = write_text(state, "faces_count.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 "property float y\nproperty float z\nelement face 1000000000000\n"
                 "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                 "3 0 1 2\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "1000000000000 'face' records", "truncated");
  free(p);
  tri_binary(&b, 1, "int", (const int32_t[]){0, 1, 2}, 3);
  char *fc = strstr((char *)b.data, "face 1\n");
  assert_non_null(fc);
  char patched[4096];
  size_t head = (size_t)(fc - (char *)b.data);
  memcpy(patched, b.data, head);
  size_t m = head + (size_t)sprintf(patched + head, "face 4000000000\n");
  size_t rest = b.n - head - 7;
  memcpy(patched + m, fc + 7, rest);
  memcpy(b.data, patched, m + rest);
  b.n = m + rest;
  p = write_bytes(state, "faces_count_bin.ply", &b);
  expect_failure(p, BBC_ERROR_CORRUPT, "4000000000 'face' records", "at least");
  free(p);
}

static void test_ply_tristrips(void **state) {
  /* 0 1 2 3 is a strip of two triangles (winding alternates), -1 restarts,
   * 4 5 6 is one triangle, and the repeated 6 and 4 are a joint that makes
   * no triangles. */
  const char *head = "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\n"
                     "property float y\nproperty float z\nelement tristrips 1\n"
                     "property list int int vertex_indices\nend_header\n"
                     "0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n3 0 0\n2 1 0\n";
  char text[1024];
  snprintf(text, sizeof text, "%s10 0 1 2 3 -1 4 5 6 6 4\n", head);
  char *p = write_text(state, "strips.ply", text);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_TRIANGLES);
  assert_int_equal(m.triangle_count, 3);
  assert_int_equal(m.dropped_degenerate, 0);
  assert_memory_equal(m.indices, ((const uint32_t[]){0, 1, 2, 2, 1, 3, 4, 5, 6}),
                      9 * sizeof(uint32_t));
  /* Consistent winding: every flat normal points the same way. */
  for (size_t v = 0; v < 3; v++) assert_true(m.normals[3 * v + 2] == m.normals[2]);
  bbc_mesh_free(&m);
  free(p);
  snprintf(text, sizeof text, "%s4 0 1 -2 3\n", head);
  p = write_text(state, "strips_bad.ply", text);
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "tristrips 0 refers to vertex -2", "7 vertices");
  free(p);
}

typedef struct log_capture {
  int warnings;
  char last[512];
} log_capture;

static void on_log(void *user, bbc_log_level level, const char *message) {
  log_capture *c = user;
  if (level == BBC_LOG_WARNING) c->warnings++;
  snprintf(c->last, sizeof c->last, "%s", message);
}

static void test_ply_texture_file(void **state) {
  fixture *f = *state;
  bbc_image img;
  assert_int_equal(bbc_image_alloc(&img, 2, 1), BBC_OK);
  memset(img.rgba, 255, 8);
  img.rgba[7] = 0; /* second texel transparent */
  char png[1024];
  snprintf(png, sizeof png, "%s/leaf skin.png", f->dir);
  bbc_error err;
  assert_int_equal(bbc_image_write_png(png, &img, &err), BBC_OK);
  bbc_image_free(&img);

  const char *faces = "4 0 1 2 3\n5 4 5 6 7 8\n";
  char text[2048];
  poly_ascii(text, sizeof text, faces);
  /* Insert the comment after the format line; the name has a blank and a
   * Windows folder that is not there (the base name is found beside). */
  char with[2100];
  const char *after = strstr(text, "comment");
  snprintf(with, sizeof with, "%.*scomment TextureFile C:\\maps\\leaf skin.png  \n%s",
           (int)(after - text), text, after);
  char *p = write_text(state, "textured.ply", with);
  bbc_load_options opts;
  bbc_load_options_default(&opts);
  log_capture cap = {0, ""};
  opts.callbacks.log = on_log;
  opts.callbacks.user = &cap;
  bbc_mesh m;
  assert_int_equal(bbc_mesh_load(p, &opts, &m, &err), BBC_OK);
  assert_int_equal(cap.warnings, 0);
  assert_int_equal(m.texture_count, 1);
  assert_int_equal(m.materials[0].texture, 0);
  assert_string_equal(m.materials[0].texture_ref, "C:\\maps\\leaf skin.png");
  assert_string_equal(m.textures[0].path, png);
  assert_int_equal(m.textures[0].image.width, 2);
  assert_int_equal(m.textures[0].has_alpha, 1);
  bbc_mesh_free(&m);
  free(p);

  /* Missing: a warning, the reference kept, the base colour used. */
  snprintf(with, sizeof with, "%.*scomment TextureFile absent.png\n%s", (int)(after - text), text,
           after);
  p = write_text(state, "untextured.ply", with);
  assert_int_equal(bbc_mesh_load(p, &opts, &m, &err), BBC_OK);
  assert_int_equal(cap.warnings, 1);
  assert_non_null(strstr(cap.last, "absent.png"));
  assert_ptr_equal(strstr(cap.last, p), cap.last);
  assert_int_equal(m.texture_count, 0);
  assert_int_equal(m.materials[0].texture, -1);
  assert_string_equal(m.materials[0].texture_ref, "absent.png");
  bbc_mesh_free(&m);
  free(p);
}

/* A cube of side 2 around the origin, six quads wound counter-clockwise
 * seen from outside, written by hand: the centre of gravity and the radius
 * are known exactly (the triangle centroids cancel in pairs). */
static void test_ply_cube_frame(void **state) {
  const char *cube = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n"
                     "property float y\nproperty float z\nelement face 6\n"
                     "property list uchar int vertex_indices\nend_header\n"
                     "-1 -1 -1\n1 -1 -1\n-1 1 -1\n1 1 -1\n-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n"
                     "4 4 6 2 0\n4 1 3 7 5\n4 0 1 5 4\n4 6 7 3 2\n4 2 3 1 0\n4 4 5 7 6\n";
  char *p = write_text(state, "cube.ply", cube);
  bbc_load_options opts;
  bbc_load_options_default(&opts);
  opts.flat_normals = 1; /* flat normals: outward for this winding */
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(p, &opts, &m, &err), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_TRIANGLES);
  assert_int_equal(m.triangle_count, 12);
  assert_int_equal(m.dropped_degenerate, 0);
  for (int k = 0; k < 3; k++) {
    assert_true(m.center[k] == 0.0);
    assert_true(m.bbox_min[k] == -1.0);
    assert_true(m.bbox_max[k] == 1.0);
  }
  assert_true(m.radius == sqrt(3.0));
  assert_string_equal(m.group_names[0], "cube");
  assert_int_equal(m.normals_generated, 1);
  check_unit_normals(&m);
  /* Every triangle faces away from the centre. */
  for (size_t t = 0; t < m.triangle_count; t++) {
    const uint32_t *ix = m.indices + 3 * t;
    double c[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    for (int j = 0; j < 3; j++)
      for (int k = 0; k < 3; k++) c[k] += m.positions[3 * ix[j] + k];
    const double *a = m.positions + 3 * ix[0], *b = m.positions + 3 * ix[1],
                 *d = m.positions + 3 * ix[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    assert_true(c[0] * n[0] + c[1] * n[1] + c[2] * n[2] > 0);
  }
  bbc_mesh_free(&m);
  free(p);
}

/* A binary grid big enough for progress reports (80,000 records): progress
 * rises, ends at 1 exactly once, and the frame is right. */
static void test_ply_mesh_progress(void **state) {
  enum { N = 200 };
  size_t cap = 1024 + (size_t)N * N * 12 + (size_t)(N - 1) * (N - 1) * 17;
  unsigned char *buf = malloc(cap);
  assert_non_null(buf);
  size_t n = (size_t)snprintf((char *)buf, 1024,
                              "ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "element face %d\nproperty list uchar int vertex_indices\n"
                              "end_header\n",
                              N * N, (N - 1) * (N - 1));
  for (int y = 0; y < N; y++)
    for (int x = 0; x < N; x++) {
      float v[3] = {(float)x, (float)y, 0.0f};
      memcpy(buf + n, v, 12);
      n += 12;
    }
  for (int y = 0; y + 1 < N; y++)
    for (int x = 0; x + 1 < N; x++) {
      int32_t q[4] = {y * N + x, y * N + x + 1, (y + 1) * N + x + 1, (y + 1) * N + x};
      buf[n++] = 4;
      memcpy(buf + n, q, 16);
      n += 16;
    }
  assert_true(n <= cap);
  fixture *f = *state;
  char *p = tu_write_file(f->dir, "grid.ply", buf, n);
  free(buf);
  assert_non_null(p);
  bbc_load_options opts;
  bbc_load_options_default(&opts);
  progress_log prog = {0, 0, 0, 0.0};
  opts.callbacks.progress = on_progress;
  opts.callbacks.user = &prog;
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(p, &opts, &m, &err), BBC_OK);
  assert_int_equal(m.triangle_count, 2 * (N - 1) * (N - 1));
  assert_true(prog.calls > 2);
  assert_int_equal(prog.ones, 1);
  assert_true(prog.last == 1.0);
  assert_false(prog.decreasing);
  assert_true(fabs(m.center[0] - (N - 1) / 2.0) < 1e-9);
  assert_true(fabs(m.center[1] - (N - 1) / 2.0) < 1e-9);
  assert_true(m.center[2] == 0.0);
  bbc_mesh_free(&m);
  free(p);
}

/* ---- hand-made XYZ files ------------------------------------------------- */

static void test_xyz_formats(void **state) {
  const char *text = "// exported by a scanner\n"
                     "# another comment\n"
                     "\n"
                     "X,Y,Z,Intensity\n"
                     "1.5,2.5,3.5,100\n"
                     "  4 , 5 , 6\n"
                     "\t7\t8\t9\textra words here\n"
                     "# comment between points\n"
                     "519054.680 5357592.050 4.760 0 0\r\n"
                     "-1e-3 0x10 +2";
  char *p = write_text(state, "mixed.xyz", text);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.vertex_count, 5);
  const double want[15] = {1.5, 2.5,        3.5,         4,     5,     6,  7, 8,
                           9,   519054.680, 5357592.050, 4.760, -1e-3, 16, 2};
  for (int i = 0; i < 15; i++) /* moved by the origin (the UTM point is far from 0) */
    assert_true(fabs(m.positions[i] + m.origin[i % 3] - want[i]) <= 1e-9 * (1 + fabs(want[i])));
  assert_true(m.origin[0] != 0);
  assert_null(m.normals);
  assert_null(m.colors);
  bbc_mesh_free(&m);
  free(p);

  /* Leica PTS: a count line first. */
  p = write_text(state, "scan.pts", "2\n1 2 3 40 255 0 0\n4 5 6 41 0 255 0\n");
  assert_int_equal(load(p, &m, &err), BBC_OK);
  assert_int_equal(m.vertex_count, 2);
  bbc_mesh_free(&m);
  free(p);
}

static void test_xyz_errors(void **state) {
  char *p = write_text(state, "two.xyz", "x y z\n1 2 3\n4 5\n6 7 8\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "line 3", "2 numbers");
  free(p);
  p = write_text(state, "word.xyz", "1 2 3\n4 5 6\n7 eight 9\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "line 3", "'eight'");
  free(p);
  /* A second header-like line is not a header any more. */
  p = write_text(state, "late.xyz", "1 2 3\nx y z\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "line 2", "'x'");
  free(p);
  p = write_text(state, "nan.xyz", "1 2 3\n4 5 6\n7 8 9\n1 NaN 2\n");
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "line 4", "point 3 ");
  free(p);
  p = write_text(state, "huge.xyz", "1 2 3\n4 5 1e300\n");
  expect_failure(p, BBC_ERROR_INVALID_GEOMETRY, "line 2", "absurd");
  free(p);
  p = write_text(state, "empty.xyz", "# nothing\n\n// here\n");
  expect_failure(p, BBC_ERROR_EMPTY, "no points", NULL);
  free(p);
  p = write_text(state, "glued.xyz", "1 2 3abc\n");
  expect_failure(p, BBC_ERROR_CORRUPT, "line 1", "'3abc'");
  free(p);
  fixture *f = *state;
  static const unsigned char bin[] = {'1', ' ', '2', ' ', '3', '\n', 0, 1, 2, 3};
  p = tu_write_file(f->dir, "binary.xyz", bin, sizeof bin);
  expect_failure(p, BBC_ERROR_CORRUPT, "binary data", "offset 6");
  free(p);
}

/* Appendix A's VRML point cloud: one PointSet with point and color; a
 * colour count that does not match is refused with its line. */
static void test_vrml_pointset(void **state) {
  char *p = write_text(state, "ps.wrl",
                       "#VRML V2.0 utf8\n"
                       "Transform { translation 10 0 0 children [\n"
                       "Shape { geometry PointSet {\n"
                       "  coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0, 0 0 1 ] }\n"
                       "  color Color { color [ 1 0 0, 0 1 0, 0 0 1, 1 1 1 ] } } } ] }\n");
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(p, NULL, &m, &err), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_POINTS);
  assert_int_equal(m.vertex_count, 4);
  assert_non_null(m.colors);
  assert_true(m.positions[0] == 10 && m.positions[3] == 11); /* the transform applied */
  assert_int_equal(m.colors[0], 255);
  assert_int_equal(m.colors[4 + 1], 255);
  assert_int_equal(m.colors[8 + 2], 255);
  bbc_mesh_free(&m);
  free(p);
  p = write_text(state, "bad.wrl",
                 "#VRML V2.0 utf8\nShape { geometry PointSet {\n"
                 "  coord Coordinate { point [ 0 0 0, 1 0 0 ] }\n"
                 "  color Color { color [ 1 0 0 ] } } }\n");
  assert_int_not_equal(bbc_mesh_load(p, NULL, &m, &err), BBC_OK);
  assert_non_null(strstr(err.message, "bad.wrl"));
  assert_non_null(strstr(err.message, "color"));
  free(p);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_b9_training),
      cmocka_unit_test(test_ball),
      cmocka_unit_test(test_hippo),
      cmocka_unit_test(test_pond_damaged),
      cmocka_unit_test(test_xyz_counts),
      cmocka_unit_test(test_lidr_precision),
      cmocka_unit_test_setup_teardown(test_vrml_pointset, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_ascii_nan, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_ascii_malformed_lines, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_ascii_crlf_and_types, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_extra_elements, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_binary_endianness, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_binary_truncated, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_binary_absurd_values, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_header_errors, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_absurd_count, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_zero_vertices, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_routing, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_negative_list, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_mesh_ascii, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_mesh_binary, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_mesh_bad_faces, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_mesh_header_problems, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_tristrips, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_texture_file, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_cube_frame, setup, teardown),
      cmocka_unit_test_setup_teardown(test_ply_mesh_progress, setup, teardown),
      cmocka_unit_test_setup_teardown(test_missing_file, setup, teardown),
      cmocka_unit_test_setup_teardown(test_xyz_formats, setup, teardown),
      cmocka_unit_test_setup_teardown(test_xyz_errors, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
