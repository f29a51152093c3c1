/* test_mesh.c — bbc_mesh_finalize on hand-built meshes with known answers:
 * centre of gravity, radius, degenerate dropping, validation, normals. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#include "test_util.h"

/*  Two triangles: a big one (area 2) at x in [0,2] and a small one (area
 *  0.5) far away at x in [10,11]. The area-weighted centre is
 *  (2*c1 + 0.5*c2) / 2.5, not the vertex mean. */
static void test_center_is_area_weighted(void **state) {
  (void)state;
  const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 10, 0, 0, 11, 0, 0, 10, 1, 0};
  const uint32_t idx[] = {0, 1, 2, 3, 4, 5};
  bbc_mesh m;
  tu_mesh_from(&m, pos, 6, idx, 2);
  bbc_error err;
  assert_int_equal(bbc_mesh_finalize(&m, 1, "test", &err), BBC_OK);
  double c1[3] = {2.0 / 3, 2.0 / 3, 0}, c2[3] = {31.0 / 3, 1.0 / 3, 0};
  for (int k = 0; k < 3; k++)
    assert_true(fabs(m.center[k] - (2 * c1[k] + 0.5 * c2[k]) / 2.5) < 1e-12);
  /* Radius: farthest used vertex from the centre is (11, 0, 0). */
  double dx = 11 - m.center[0], dy = m.center[1];
  assert_true(fabs(m.radius - sqrt(dx * dx + dy * dy)) < 1e-12);
  assert_true(m.bbox_min[0] == 0 && m.bbox_max[0] == 11 && m.bbox_max[1] == 2);
  assert_int_equal(m.normals_generated, 1);
  /* Counter-clockwise in the XY plane: normal +Z. */
  assert_true(fabs(m.normals[2] - 1.0f) < 1e-6);
  bbc_mesh_free(&m);
}

/* A unit cube (12 triangles) centred at (1, 2, 3): centre exact, radius
 * sqrt(3)/2, smooth normals at corners point diagonally. */
static void test_cube(void **state) {
  (void)state;
  double pos[8 * 3];
  for (int i = 0; i < 8; i++) {
    pos[3 * i + 0] = 1 + ((i & 1) ? 0.5 : -0.5);
    pos[3 * i + 1] = 2 + ((i & 2) ? 0.5 : -0.5);
    pos[3 * i + 2] = 3 + ((i & 4) ? 0.5 : -0.5);
  }
  const uint32_t idx[] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                          2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  bbc_mesh m;
  tu_mesh_from(&m, pos, 8, idx, 12);
  bbc_error err;
  assert_int_equal(bbc_mesh_finalize(&m, 1, "cube", &err), BBC_OK);
  assert_true(fabs(m.center[0] - 1) < 1e-12 && fabs(m.center[1] - 2) < 1e-12 &&
              fabs(m.center[2] - 3) < 1e-12);
  assert_true(fabs(m.radius - sqrt(3.0) / 2) < 1e-12);
  /* Corner 7 is (+,+,+): its smooth normal is (1,1,1)/sqrt(3). */
  for (int k = 0; k < 3; k++) assert_true(fabs(m.normals[3 * 7 + k] - 0.57735f) < 1e-4);
  bbc_mesh_free(&m);
}

/* A two-sided leaf: a square made of two triangles, and its other side,
 * the same corners wound the other way (on the same vertices, and on
 * vertices of their own at the same positions). Summed as they are, the
 * two sides cancel at every corner and the normal left is noise; each
 * corner's normal must stay +-z (either side: the bake turns a two-sided
 * surface's normal to its face's side). */
static void test_two_sided_sheet_keeps_its_normal(void **state) {
  (void)state;
  const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  /* 0-3: the leaf */
                        0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}; /* 4-7: its copy */
  const uint32_t shared[] = {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2};
  const uint32_t apart[] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
  for (int smooth = 0; smooth <= 1; smooth++)
    for (int k = 0; k < 2; k++) {
      bbc_mesh m;
      tu_mesh_from(&m, pos, 8, k ? apart : shared, 4);
      bbc_error err;
      assert_int_equal(bbc_mesh_finalize(&m, smooth, "leaf", &err), BBC_OK);
      for (int v = 0; v < (k ? 8 : 4); v++) {
        const float *n = m.normals + 3 * v;
        assert_true(fabsf(n[0]) < 1e-6f && fabsf(n[1]) < 1e-6f && fabsf(fabsf(n[2]) - 1) < 1e-6f);
      }
      bbc_mesh_free(&m);
    }
}

static void test_degenerates_dropped_and_counted(void **state) {
  (void)state;
  /* Triangle 1 repeats an index, triangle 2 is collinear: both dropped. */
  const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
  const uint32_t idx[] = {0, 1, 2, 0, 0, 1, 0, 1, 3};
  bbc_mesh m;
  tu_mesh_from(&m, pos, 4, idx, 3);
  bbc_error err;
  assert_int_equal(bbc_mesh_finalize(&m, 0, "deg", &err), BBC_OK);
  assert_int_equal(m.triangle_count, 1);
  assert_int_equal(m.triangles_read, 3);
  assert_int_equal(m.dropped_degenerate, 2);
  /* Bounds only count used vertices: vertex 3 at x = 2 is not used. */
  assert_true(m.bbox_max[0] == 1.0);
  bbc_mesh_free(&m);

  /* Nothing left: an error, not an empty mesh. */
  const uint32_t idx2[] = {0, 1, 3};
  tu_mesh_from(&m, pos, 4, idx2, 1);
  assert_int_equal(bbc_mesh_finalize(&m, 0, "deg", &err), BBC_ERROR_EMPTY);
  assert_non_null(strstr(err.message, "deg"));
  bbc_mesh_free(&m);
}

static void test_invalid_geometry_refused(void **state) {
  (void)state;
  const double pos[] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
  const uint32_t idx[] = {0, 1, 2};
  bbc_mesh m;
  bbc_error err;
  tu_mesh_from(&m, pos, 3, idx, 1);
  assert_int_equal(bbc_mesh_finalize(&m, 1, "nan.obj", &err), BBC_ERROR_INVALID_GEOMETRY);
  assert_non_null(strstr(err.message, "nan.obj"));
  assert_non_null(strstr(err.message, "vertex 2"));
  bbc_mesh_free(&m);

  const double pos2[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t bad[] = {0, 1, 3};
  tu_mesh_from(&m, pos2, 3, bad, 1);
  assert_int_equal(bbc_mesh_finalize(&m, 1, "idx.obj", &err), BBC_ERROR_INVALID_GEOMETRY);
  assert_non_null(strstr(err.message, "vertex 3"));
  bbc_mesh_free(&m);

  const double huge[] = {0, 0, 0, 1, 0, 0, 0, 1e38, 0};
  tu_mesh_from(&m, huge, 3, idx, 1);
  assert_int_equal(bbc_mesh_finalize(&m, 1, "huge", &err), BBC_ERROR_INVALID_GEOMETRY);
  bbc_mesh_free(&m);

  bbc_mesh_free(NULL); /* safe */
}

static void test_points_frame(void **state) {
  (void)state;
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  m.kind = BBC_MESH_POINTS;
  m.vertex_count = 4;
  m.positions = malloc(12 * sizeof(double));
  const double p[] = {600000, 5000000, 10, 600002, 5000000, 10,
                      600000, 5000002, 10, 600002, 5000002, 14};
  memcpy(m.positions, p, sizeof p);
  bbc_error err;
  assert_int_equal(bbc_mesh_finalize(&m, 1, "pts", &err), BBC_OK);
  assert_true(fabs(m.center[0] - 600001) < 1e-9 && fabs(m.center[1] - 5000001) < 1e-9 &&
              fabs(m.center[2] - 11) < 1e-9);
  assert_true(fabs(m.radius - sqrt(1 + 1 + 9)) < 1e-9);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_center_is_area_weighted),
      cmocka_unit_test(test_cube),
      cmocka_unit_test(test_two_sided_sheet_keeps_its_normal),
      cmocka_unit_test(test_degenerates_dropped_and_counted),
      cmocka_unit_test(test_invalid_geometry_refused),
      cmocka_unit_test(test_points_frame),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
