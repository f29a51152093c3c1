/* test_session.c — the library's BBCgen session (bbc_session_*): steps kept
 * between calls, the parameter classes deciding what a change needs, and a
 * failed or cancelled step leaving the session as it was. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "bbc.h"
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
  assert_int_equal(bbc_session_planes(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_null(bbc_session_model(s));
  assert_int_equal(bbc_session_stale(s, &o, NULL), -1);
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  assert_int_equal(bbc_session_load(s, path, &lo, &err), BBC_OK);
  assert_non_null(bbc_session_model(s));
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_session_run(s, &o, &err), BBC_OK);
  const bbc_cloud *c = bbc_session_result(s);
  assert_non_null(c);
  assert_int_equal(bbc_session_stale(s, &o, NULL), 0);
  /* a texturing change: step 3 alone, the very cloud a full run gives */
  o.params.quality = 0;
  const char *which;
  assert_int_equal(bbc_session_stale(s, &o, &which), 3);
  assert_string_equal(which, "quality");
  const bbc_planeset *before = bbc_session_planeset(s);
  size_t planes = before->plane_count;
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_OK);
  assert_int_equal(bbc_session_planeset(s)->plane_count, planes);
  const bbc_image *a = &bbc_session_result(s)->mesh.textures[0].image;
  bbc_session *t = bbc_session_new();
  assert_non_null(t);
  assert_int_equal(bbc_session_load(t, path, &lo, &err), BBC_OK);
  assert_int_equal(bbc_session_run(t, &o, &err), BBC_OK);
  const bbc_image *b = &bbc_session_result(t)->mesh.textures[0].image;
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  assert_memory_equal(a->rgba, b->rgba, (size_t)a->width * a->height * 4);
  bbc_session_free(t);
  /* a step-1 change: step 3 refused, naming it; the cloud stays */
  o.params.epsilon_pct = 9;
  assert_int_equal(bbc_session_stale(s, &o, &which), 1);
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "epsilon"));
  assert_non_null(bbc_session_result(s));
  /* a part's step-2 setting names the part */
  o.params.epsilon_pct = 6;
  o.part_override_count = 1;
  snprintf(o.part_overrides[0].part, sizeof o.part_overrides[0].part, "foliage");
  o.part_overrides[0].params = o.params;
  o.part_overrides[0].params.punish_value = 0.4;
  assert_int_equal(bbc_session_stale(s, &o, &which), 2);
  assert_string_equal(which, "foliage.punishval");
  o.part_override_count = 0;
  /* the split by content: patterns the caller later overwrites are copied */
  char pattern[64] = "trunk*";
  o.split.mode = BBC_SPLIT_PATTERNS;
  o.split.trunk_patterns = pattern;
  assert_int_equal(bbc_session_stale(s, &o, &which), 1);
  assert_string_equal(which, "split");
  assert_int_equal(bbc_session_planes(s, &o, &err), BBC_OK);
  assert_null(bbc_session_result(s)); /* new planes: the cloud is gone */
  assert_int_equal(bbc_session_stale(s, &o, NULL), 0);
  snprintf(pattern, sizeof pattern, "bark*");
  assert_int_equal(bbc_session_stale(s, &o, &which), 1);
  snprintf(pattern, sizeof pattern, "trunk*");
  /* a cancelled or failed step leaves the session as it was */
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_OK);
  planes = bbc_session_planeset(s)->plane_count;
  o.callbacks.cancel = always;
  assert_int_equal(bbc_session_run(s, &o, &err), BBC_ERROR_CANCELLED);
  assert_int_equal(bbc_session_cloud(s, &o, &err), BBC_ERROR_CANCELLED);
  o.callbacks.cancel = NULL;
  assert_non_null(bbc_session_result(s));
  assert_int_equal(bbc_session_planeset(s)->plane_count, planes);
  assert_int_not_equal(bbc_session_load(s, "/no/such/model.obj", &lo, &err), BBC_OK);
  assert_non_null(bbc_session_result(s));
  bbc_session_free(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_session)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
