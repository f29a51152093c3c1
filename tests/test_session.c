/* test_session.c — the library's BBCgen session (bbc_session_*): steps kept
 * between calls, the parameter classes deciding what a change needs, and a
 * failed or cancelled step leaving the session as it was. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app.h"
#include "test_util.h"

static int always(void *user) {
  (void)user;
  return 1;
}

static void test_session(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  bbc_session *s = bbc_session_new();
  assert_non_null(s);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.texres = 32;
  o.params.atlas_max = 0;
  bbc_error err;
  /* out of order */
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_null(bbc_session_get_model(s));
  assert_int_equal(bbc_session_stale_step(s, &o, NULL), -1);
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  assert_int_equal(bbc_session_load(s, path, &lo, &err), BBC_OK);
  assert_non_null(bbc_session_get_model(s));
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_session_run(s, &o, &err), BBC_OK);
  const bbc_cloud *c = bbc_session_get_cloud(s);
  assert_non_null(c);
  assert_int_equal(bbc_session_stale_step(s, &o, NULL), 0);
  /* a texturing change: step 3 alone, the very cloud a full run gives */
  o.params.quality = 0;
  const char *which;
  assert_int_equal(bbc_session_stale_step(s, &o, &which), 3);
  assert_string_equal(which, "quality");
  const bbc_planeset *before = bbc_session_get_planes(s);
  size_t planes = before->plane_count;
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_OK);
  assert_int_equal(bbc_session_get_planes(s)->plane_count, planes);
  const bbc_image *a = &bbc_session_get_cloud(s)->mesh.textures[0].image;
  bbc_session *t = bbc_session_new();
  assert_non_null(t);
  assert_int_equal(bbc_session_load(t, path, &lo, &err), BBC_OK);
  assert_int_equal(bbc_session_run(t, &o, &err), BBC_OK);
  const bbc_image *b = &bbc_session_get_cloud(t)->mesh.textures[0].image;
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  assert_memory_equal(a->rgba, b->rgba, (size_t)a->width * a->height * 4);
  bbc_session_free(t);
  /* a step-1 change: step 3 refused, naming it; the cloud stays */
  o.params.epsilon_pct = 9;
  assert_int_equal(bbc_session_stale_step(s, &o, &which), 1);
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "epsilon"));
  assert_non_null(bbc_session_get_cloud(s));
  /* a part's step-2 setting names the part */
  o.params.epsilon_pct = 6;
  o.part_override_count = 1;
  snprintf(o.part_overrides[0].part, sizeof o.part_overrides[0].part, "foliage");
  o.part_overrides[0].params = o.params;
  o.part_overrides[0].params.punish_value = 0.4;
  assert_int_equal(bbc_session_stale_step(s, &o, &which), 2);
  assert_string_equal(which, "foliage.punishval");
  o.part_override_count = 0;
  /* the split by content: patterns the caller later overwrites are copied */
  char pattern[64] = "trunk*";
  o.split.mode = BBC_SPLIT_PATTERNS;
  o.split.trunk_patterns = pattern;
  assert_int_equal(bbc_session_stale_step(s, &o, &which), 1);
  assert_string_equal(which, "split");
  assert_int_equal(bbc_session_grid_stale_step(s, &o, &which), 1);
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "split"));
  assert_int_equal(bbc_session_build_grid(s, &o, &err), BBC_OK);
  assert_null(bbc_session_get_cloud(s)); /* a new grid: planes and cloud are gone */
  assert_null(bbc_session_get_planes(s));
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_OK);
  assert_null(bbc_session_get_cloud(s)); /* new planes: the cloud is gone */
  assert_int_equal(bbc_session_stale_step(s, &o, NULL), 0);
  snprintf(pattern, sizeof pattern, "bark*");
  assert_int_equal(bbc_session_stale_step(s, &o, &which), 1);
  snprintf(pattern, sizeof pattern, "trunk*");
  /* a cancelled or failed step leaves the session as it was */
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_OK);
  planes = bbc_session_get_planes(s)->plane_count;
  o.callbacks.cancel = always;
  assert_int_equal(bbc_session_run(s, &o, &err), BBC_ERROR_CANCELLED);
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_ERROR_CANCELLED);
  o.callbacks.cancel = NULL;
  assert_non_null(bbc_session_get_cloud(s));
  assert_int_equal(bbc_session_get_planes(s)->plane_count, planes);
  assert_int_not_equal(bbc_session_load(s, "/no/such/model.obj", &lo, &err), BBC_OK);
  assert_non_null(bbc_session_get_cloud(s));
  bbc_session_free(s);
}

static int same_planes(const bbc_planeset *a, const bbc_planeset *b) {
  if (a->plane_count != b->plane_count || a->epsilon_scale != b->epsilon_scale) return 0;
  for (size_t i = 0; i < a->plane_count; i++)
    if (memcmp(a->planes[i].normal, b->planes[i].normal, sizeof a->planes[i].normal) ||
        a->planes[i].d != b->planes[i].d || a->planes[i].kind != b->planes[i].kind)
      return 0;
  return !memcmp(a->face_plane, b->face_plane, a->face_count * sizeof *a->face_plane);
}

/* Step 2 on a kept grid gives what steps 1 and 2 from scratch give, also
 * when minplanes makes it visit other epsilons; step-1 changes are refused. */
static void test_steps(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(path, &lo, &m, &err), BBC_OK);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_grid *g;
  assert_int_equal(bbc_grid_build(&m, &o, &g, &err), BBC_OK);
  const double punish[3] = {0, 0.7, 0.3};
  for (int k = 0; k < 3; k++) {
    o.params.punish_value = punish[k];
    o.params.min_planes = k == 2 ? 60 : 16; /* k = 2: smaller epsilons, more grids */
    o.params.max_planes = k == 2 ? 100 : 32;
    bbc_planeset kept, fresh;
    assert_int_equal(bbc_planes_select(g, &o, &kept, &err), BBC_OK);
    assert_int_equal(bbc_planes_find(&m, &o, &fresh, &err), BBC_OK);
    assert_true(same_planes(&kept, &fresh));
    if (k == 2) assert_true(kept.attempts > 1);
    bbc_planeset_free(&kept);
    bbc_planeset_free(&fresh);
  }
  /* a step-1 parameter changed: refused, naming it; the grid stays usable */
  o.params.res_deg = 6;
  bbc_planeset set;
  assert_int_equal(bbc_planes_select(g, &o, &set, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "res"));
  o.params.res_deg = 9;
  assert_int_equal(bbc_planes_select(g, &o, &set, &err), BBC_OK);
  bbc_planeset_free(&set);
  bbc_grid_free(g);

  /* the session: bbc2 before bbc1 refused; bbc1, bbc2 as bbc */
  bbc_session *s = bbc_session_new();
  assert_non_null(s);
  assert_int_equal(bbc_session_load(s, path, &lo, &err), BBC_OK);
  assert_int_equal(bbc_session_grid_stale_step(s, &o, NULL), -1);
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "step 1"));
  assert_int_equal(bbc_session_build_grid(s, &o, &err), BBC_OK);
  assert_non_null(bbc_session_get_grid(s));
  o.params.punish_value = 0.7;
  assert_int_equal(bbc_session_grid_stale_step(s, &o, NULL), 0);
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_OK);
  bbc_planeset fresh;
  assert_int_equal(bbc_planes_find(&m, &o, &fresh, &err), BBC_OK);
  assert_true(same_planes(bbc_session_get_planes(s), &fresh));
  bbc_planeset_free(&fresh);
  o.params.epsilon_pct = 8;
  const char *which = NULL;
  assert_int_equal(bbc_session_grid_stale_step(s, &o, &which), 1);
  assert_string_equal(which, "epsilon");
  assert_int_equal(bbc_session_select_planes(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "epsilon"));
  assert_non_null(bbc_session_get_planes(s)); /* refused: kept as it was */
  bbc_session_free(s);
  bbc_mesh_free(&m);
}

/* show bbc's geometry: the discretised domain (step 1's cells) holds the
 * continuous one (every exact valid plane sampled), for faces of both
 * parts; the density view has cubes; the faces view marks the plane. */
static void test_views(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(path, &lo, &m, &err), BBC_OK);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_grid *g;
  /* With `limbs` the trunk part is a mesh: no faces in the grid, and its
   * views are refused, not drawn from nothing. */
  assert_int_equal(bbc_grid_build(&m, &o, &g, &err), BBC_OK);
  assert_int_equal(bbc_grid_get_part_count(g), 2);
  for (size_t part = 0; part < 2; part++)
    if (bbc_grid_get_part_faces(g, part) == 0) {
      bbc_grid_view_options vo = {BBC_GRID_VIEW_DOMAIN, part, 0, -1, 0};
      bbc_geometry dom;
      assert_int_not_equal(bbc_grid_view_build(g, &vo, &dom, &err), BBC_OK);
    }
  bbc_grid_free(g);
  o.params.limbs = 0; /* both parts on planes */
  assert_int_equal(bbc_grid_build(&m, &o, &g, &err), BBC_OK);
  assert_int_equal(bbc_grid_get_part_count(g), 2);
  size_t checked = 0;
  for (size_t part = 0; part < 2; part++) {
    size_t n = bbc_grid_get_part_faces(g, part);
    const size_t faces[3] = {0, n / 2, bbc_grid_get_largest_face(g, part)};
    for (int f = 0; f < 3; f++) {
      bbc_grid_view_options vo = {BBC_GRID_VIEW_DOMAIN, part, faces[f], -1, 0};
      bbc_geometry dom, cont;
      assert_int_equal(bbc_grid_view_build(g, &vo, &dom, &err), BBC_OK);
      assert_true(dom.tri_count > 0 && dom.tri_count % 12 == 0);
      vo.kind = BBC_GRID_VIEW_CONTINUOUS;
      assert_int_equal(bbc_grid_view_build(g, &vo, &cont, &err), BBC_OK);
      assert_true(cont.tri_count > 0);
      size_t cubes = dom.tri_count / 12;
      for (size_t v = 0; v < 3 * cont.tri_count; v += 7) {
        const float *p = cont.tris + 6 * v;
        int inside = 0;
        for (size_t c = 0; c < cubes && !inside; c++) {
          float lo3[3] = {1e9f, 1e9f, 1e9f}, hi3[3] = {-1e9f, -1e9f, -1e9f};
          for (size_t k = 0; k < 36; k++)
            for (int a = 0; a < 3; a++) {
              float x = dom.tris[6 * (36 * c + k) + a];
              lo3[a] = x < lo3[a] ? x : lo3[a];
              hi3[a] = x > hi3[a] ? x : hi3[a];
            }
          inside = 1;
          for (int a = 0; a < 3; a++) { /* the cube as drawn is inset by 8 % */
            float mid = 0.5f * (lo3[a] + hi3[a]), half = 0.5f * (hi3[a] - lo3[a]) / 0.92f;
            if (p[a] < mid - half - 1e-4f || p[a] > mid + half + 1e-4f) inside = 0;
          }
        }
        if (!inside) fail_msg("part %zu face %zu: a valid plane outside the cells", part, faces[f]);
        checked++;
      }
      bbc_geometry_free(&dom);
      bbc_geometry_free(&cont);
    }
  }
  assert_true(checked > 100);
  bbc_grid_view_options vo = {BBC_GRID_VIEW_DENSITY, 1, 0, -1, 0};
  bbc_geometry geo;
  assert_int_equal(bbc_grid_view_build(g, &vo, &geo, &err), BBC_OK);
  assert_true(geo.tri_count > 12 * 10);
  bbc_geometry_free(&geo);
  vo.face = 1u << 30;
  assert_int_equal(bbc_grid_view_build(g, &vo, &geo, &err), BBC_ERROR_INVALID_ARGUMENT);
  /* faces: the selected face's plane solid, the rest as wireframe */
  bbc_planeset set;
  assert_int_equal(bbc_planes_select(g, &o, &set, &err), BBC_OK);
  uint8_t *st = malloc(m.triangle_count);
  assert_non_null(st);
  size_t sel = (size_t)bbc_grid_get_face_triangle(g, 1, bbc_grid_get_largest_face(g, 1)), valid = 0;
  bbc_faces_get_state(&set, sel, st, m.triangle_count);
  for (size_t t = 0; t < m.triangle_count; t++) valid += st[t] == BBC_FACE_VALID;
  assert_int_equal(valid, set.planes[set.face_plane[sel]].face_count);
  assert_int_equal(bbc_faces_view_build(&m, st, sel, &geo, &err), BBC_OK);
  assert_int_equal(geo.tri_count, valid); /* the selected one yellow instead of blue */
  assert_int_equal(geo.line_count, 3 * (m.triangle_count - valid) + 3);
  bbc_geometry_free(&geo);
  free(st);
  bbc_planeset_free(&set);
  bbc_grid_free(g);
  bbc_mesh_free(&m);
}

/* A program linking libbbc gets what bbcgen gives: the session's LOD chain
 * and save are byte for byte bbcgen's files; writes need a cloud and a
 * known extension. */
static void test_outputs(void **state) {
  (void)state;
  char path[1024], cmd[4096], a[1200], b[1200];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  bbc_session *s = bbc_session_new();
  assert_non_null(s);
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  bbc_error err;
  assert_int_equal(bbc_session_load(s, path, &lo, &err), BBC_OK);
  snprintf(a, sizeof a, "%s/lib.glb", tu_dir);
  assert_int_equal(bbc_session_write(s, a, NULL, &err), BBC_ERROR_INVALID_ARGUMENT);
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.texres = 32;
  o.params.atlas_max = 0;
  bbc_params_lod_chain(&o.params, 0);
  const double eps[3] = {4, 8, 16};
  assert_int_equal(bbc_session_run_levels(s, &o, eps, 3, &err), BBC_OK);
  assert_int_equal(bbc_session_get_level_count(s), 3);
  assert_int_equal(bbc_session_write(s, a, NULL, &err), BBC_OK);
  snprintf(b, sizeof b, "%s/lib.png", tu_dir);
  assert_int_equal(bbc_session_write(s, b, NULL, &err), BBC_ERROR_INVALID_ARGUMENT);
  snprintf(cmd, sizeof cmd, "'%s/bbcgen' '%s' -o '%s/tool.glb' --texres 32 --lod 4,8,16 -q",
           BBC_BIN_DIR, path, tu_dir);
  assert_int_equal(system(cmd), 0);
  snprintf(b, sizeof b, "%s/tool.glb", tu_dir);
  assert_true(tu_same_file(a, b)); /* byte for byte */
  /* step 3 again (level 0 was made at epsilon 4): one level; save into Appendix A's folder */
  o.params.epsilon_pct = 4;
  assert_int_equal(bbc_session_build_cloud(s, &o, &err), BBC_OK);
  assert_int_equal(bbc_session_get_level_count(s), 1);
  char saved[4600], cwd[4096];
  assert_non_null(getcwd(cwd, sizeof cwd));
  assert_int_equal(chdir(tu_dir), 0);
  assert_int_equal(bbc_session_save(s, "../x", NULL, saved, sizeof saved, &err),
                   BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_session_save(s, "lib", NULL, saved, sizeof saved, &err), BBC_OK);
  /* the library's defaults: a material (normal maps), no baked light */
  assert_string_equal(saved, "vrml97models/lib/Tree_1/Tree_1_e4.00_tex32_nm/Tree_1.wrl");
  assert_int_equal(chdir(cwd), 0);
  bbc_session_free(s);
}

/* A batch line's words in quotes hold blanks ("my trees/oak.obj"), the
 * quotes dropped; unquoted words are as before. */
static void test_quoted_words(void **state) {
  (void)state;
  bbc_command k;
  bbc_error err;
  const char *t1 = "load \"my trees/b\xc3\xa4ume.obj\" nomip";
  memset(&k, 0, sizeof k);
  assert_int_equal(bbc_command_parse(t1, strlen(t1), &k, &err), BBC_OK);
  assert_int_equal(k.kind, BBC_COMMAND_LOAD);
  assert_string_equal(k.arg, "my trees/b\xc3\xa4ume.obj");
  assert_int_equal(k.nomip, 1);
  const char *t2 = "load 'a, b.obj'";
  memset(&k, 0, sizeof k);
  assert_int_equal(bbc_command_parse(t2, strlen(t2), &k, &err), BBC_OK);
  assert_string_equal(k.arg, "a, b.obj");
  const char *t3 = "load plain.obj";
  memset(&k, 0, sizeof k);
  assert_int_equal(bbc_command_parse(t3, strlen(t3), &k, &err), BBC_OK);
  assert_string_equal(k.arg, "plain.obj");
  const char *t4 = "load my trees/oak.obj"; /* unquoted: "trees/oak.obj" is no flag */
  memset(&k, 0, sizeof k);
  assert_int_equal(bbc_command_parse(t4, strlen(t4), &k, &err), BBC_ERROR_INVALID_ARGUMENT);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_session), cmocka_unit_test(test_steps),
                                     cmocka_unit_test(test_views), cmocka_unit_test(test_outputs),
                                     cmocka_unit_test(test_quoted_words)};
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
