/* test_params.c — the Appendix A parameter table: defaults, parsing, ranges. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "app.h"

static void test_defaults_match_appendix_a(void **state) {
  (void)state;
  bbc_params p;
  bbc_params_thesis(&p);
  assert_int_equal(p.break_steps, 100);
  assert_int_equal(p.break_num, 2000);
  assert_int_equal(p.res_deg, 9);
  assert_int_equal(p.vertex_normals, 1);
  assert_int_equal(p.clustering, 2);
  assert_true(p.epsilon_pct == 5.0);
  assert_true(p.cb_coverage_pct == 50.0);
  assert_int_equal(p.post_tweak, 1);
  assert_true(p.punish_cutoff_deg == 30.0);
  assert_true(p.sub_penalty == 5.0);
  assert_int_equal(p.texres, 256);
  assert_int_equal(p.prelight, 1);
  assert_int_equal(p.normal_maps, 0);
  assert_int_equal(p.occlusion, 0);
  assert_true(p.nm_bend == 0);
  assert_true(p.point_size == 3.5);
  assert_int_equal(p.quality, 0);
  assert_int_equal(p.format, 0);
  assert_int_equal(p.max_planes, 0);
  assert_int_equal(p.atlas_max, 0);
  /* The toolkit's defaults differ from the thesis in thirteen places only:
   * ten for fidelity, three for lighting (a material engines light). */
  bbc_params d;
  bbc_params_default(&d);
  assert_int_equal(d.clustering, 0);
  assert_true(d.epsilon_pct == 6.0);
  assert_int_equal(d.quality, 2);
  assert_int_equal(d.max_planes, 32);
  assert_int_equal(d.atlas_max, 1024);
  assert_int_equal(d.min_planes, 24);
  assert_int_equal(d.dither, 1);
  assert_int_equal(d.refine, 16);
  assert_int_equal(d.stem, 3);
  assert_int_equal(d.limbs, 512);
  assert_int_equal(d.point_normals, 1);
  assert_int_equal(d.point_sample, 16384);
  assert_int_equal(d.face_sample, 16384);
  assert_int_equal(d.prelight, 0);
  assert_int_equal(d.normal_maps, 1);
  assert_int_equal(d.occlusion, 64);
  assert_true(d.nm_bend == 0);
  d.prelight = 1;
  d.normal_maps = 0;
  d.occlusion = 0;
  d.point_normals = 0;
  d.point_sample = 0;
  d.face_sample = 0;
  d.dither = 0;
  d.refine = 0;
  d.stem = 0;
  d.limbs = 0;
  d.min_planes = 0;
  d.clustering = 2;
  d.epsilon_pct = 5;
  d.quality = 0;
  d.max_planes = 0;
  d.atlas_max = 0;
  d.outline = 0;
  assert_memory_equal(&d, &p, sizeof p);
  p = d;
  bbc_params_default(&p);
  /* Every Appendix A name is in the table. */
  static const char *names[] = {
      "break",     "breaknum",     "debug",       "res",         "vn",
      "cardboard", "cbcoverage",   "clustering",  "epsilon",     "posttweak",
      "punishval", "punishcutoff", "subpenalty",  "supergreedy", "backface",
      "nm",        "pointsize",    "pointsmooth", "pointskip",   "polyskip",
      "prelight",  "pure",         "quality",     "texres",      "format"};
  size_t appendix_a = 0;
  for (size_t i = 0; i < bbc_param_count(); i++)
    appendix_a += strcmp(bbc_param_at(i)->group, "extension") != 0;
  assert_int_equal(appendix_a, sizeof names / sizeof names[0]);
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    const bbc_param_info *in = bbc_param_find(names[i]);
    assert_non_null(in);
    assert_true(bbc_params_get(&p, in) == in->default_value);
  }
  assert_true(bbc_param_find("cbcoverage")->flags & BBC_PARAM_STEP3_ONLY);
  assert_true(bbc_param_find("posttweak")->flags & BBC_PARAM_KEEPS_STEP1);
  assert_null(bbc_param_find("nonsense"));
}

static void test_set_and_ranges(void **state) {
  (void)state;
  bbc_params p;
  bbc_params_default(&p);
  bbc_error err;
  assert_int_equal(bbc_params_set(&p, "epsilon", "6", &err), BBC_OK);
  assert_true(p.epsilon_pct == 6.0);
  assert_int_equal(bbc_params_set_assignment(&p, "texres=512", &err), BBC_OK);
  assert_int_equal(p.texres, 512);
  assert_int_equal(bbc_params_set(&p, "posttweak", "off", &err), BBC_OK);
  assert_int_equal(p.post_tweak, 0);
  assert_int_equal(bbc_params_set(&p, "EPSILON", "7.5", &err), BBC_OK);
  assert_true(p.epsilon_pct == 7.5);

  /* Out of range: rejected, value unchanged, message names the range. */
  assert_int_equal(bbc_params_set(&p, "epsilon", "120", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_true(p.epsilon_pct == 7.5);
  assert_non_null(strstr(err.message, "epsilon"));
  assert_non_null(strstr(err.message, "0.001 to 99"));
  assert_int_equal(bbc_params_set(&p, "epsilon", "0.0001", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "texres", "300", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_non_null(strstr(err.message, "power of two"));
  assert_int_equal(p.texres, 512);
  assert_int_equal(bbc_params_set(&p, "res", "7", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_non_null(strstr(err.message, "divide 180"));
  assert_int_equal(bbc_params_set(&p, "res", "10", &err), BBC_OK);
  assert_int_equal(p.res_deg, 10);
  assert_int_equal(bbc_params_set(&p, "break", "4", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "breaknum", "9", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "quality", "2.5", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "punishval", "0.96", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "punishval", "0.7", &err), BBC_OK);
  assert_int_equal(bbc_params_set(&p, "polyskip", "99.5", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "cbcoverage", "99.9", &err), BBC_OK);
  assert_int_equal(bbc_params_set(&p, "nm", "2", &err), BBC_ERROR_OUT_OF_RANGE);
  /* Extensions: the up axis also by letter. */
  assert_int_equal(bbc_params_set(&p, "upaxis", "z", &err), BBC_OK);
  assert_int_equal(p.up_axis, 2);
  assert_int_equal(bbc_params_set(&p, "upaxis", "3", &err), BBC_ERROR_OUT_OF_RANGE);
  assert_int_equal(bbc_params_set(&p, "upaxis", "w", &err), BBC_ERROR_INVALID_ARGUMENT);

  /* Malformed. */
  assert_int_equal(bbc_params_set(&p, "epsilon", "abc", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_params_set(&p, "epsilon", "5x", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_params_set(&p, "epsilon", "nan", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_params_set(&p, "epsilon", "", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_params_set(&p, "bogus", "1", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "bogus"));
  assert_int_equal(bbc_params_set_assignment(&p, "epsilon", &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_params_set_assignment(&p, "=5", &err), BBC_ERROR_INVALID_ARGUMENT);
}

/* Which step a change forces (Appendix A's classes): '*' parameters only
 * step 3, '+' step 2, others step 1; upaxis changes step 1's grid; threads,
 * debug and format change no result. */
static void test_first_step(void **state) {
  (void)state;
  bbc_params a, b;
  bbc_error err;
  const char *which;
  bbc_params_default(&a);
  b = a;
  assert_int_equal(bbc_params_stale_step(&a, &b, &which), 0);
  assert_null(which);
  struct {
    const char *name, *value;
    int step;
  } cases[] = {{"texres", "64", 3},     {"quality", "0", 3},       {"nm", "0", 3},
               {"prelight", "1", 3},    {"pure", "1", 3},          {"polyskip", "5", 3},
               {"cbcoverage", "30", 3}, {"shade", "40", 3},        {"posttweak", "0", 2},
               {"occlusion", "32", 3},  {"nmbend", "0.5", 3},      {"occlusionmin", "0.3", 3},
               {"punishval", "0.7", 2}, {"punishcutoff", "55", 2}, {"supergreedy", "1", 2},
               {"epsilon", "8", 1},     {"res", "10", 1},          {"clustering", "2", 1},
               {"upaxis", "z", 1},      {"maxplanes", "0", 2},     {"threads", "1", 0},
               {"minplanes", "40", 2},  {"debug", "1", 0},         {"format", "1", 0}};
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    b = a;
    assert_int_equal(bbc_params_set(&b, cases[i].name, cases[i].value, &err), BBC_OK);
    int step = bbc_params_stale_step(&a, &b, &which);
    if (step != cases[i].step)
      fail_msg("%s: step %d, expected %d", cases[i].name, step, cases[i].step);
    if (step) assert_string_equal(which, cases[i].name);
  }
  /* the earliest step wins, and names its parameter */
  b = a;
  assert_int_equal(bbc_params_set(&b, "texres", "64", &err), BBC_OK);
  assert_int_equal(bbc_params_set(&b, "punishval", "0.5", &err), BBC_OK);
  assert_int_equal(bbc_params_stale_step(&a, &b, &which), 2);
  assert_string_equal(which, "punishval");
  assert_int_equal(bbc_params_set(&b, "epsilon", "3", &err), BBC_OK);
  assert_int_equal(bbc_params_stale_step(&a, &b, &which), 1);
  assert_string_equal(which, "epsilon");
  /* every parameter is in one class */
  for (size_t i = 0; i < bbc_param_count(); i++) {
    const bbc_param_info *info = bbc_param_at(i);
    b = a;
    double v = bbc_params_get(&a, info), nv = v + 1 <= info->max ? v + 1 : v - 1;
    if (info->type == BBC_PARAM_POW2) nv = v * 2 <= info->max ? v * 2 : v / 2;
    char text[64];
    snprintf(text, sizeof text, "%.17g", nv);
    if (bbc_params_set(&b, info->name, text, &err) != BBC_OK) {
      /* a value the parameter does not take (res: 180 must divide): its minimum */
      snprintf(text, sizeof text, "%.17g", info->min);
      if (bbc_params_set(&b, info->name, text, &err) != BBC_OK) fail_msg("%s", err.message);
    }
    int step = bbc_params_stale_step(&a, &b, NULL);
    assert_true(step >= 0 && step <= 3);
    if (info->flags & BBC_PARAM_STEP3_ONLY) assert_int_equal(step, 3);
  }
}

/* Values set by hand are meant: texres turns atlasmax off, epsilon the plane
 * budgets, unless they are set by hand too (any order); --thesis and LOD
 * chains keep what was set by hand. */
static void test_by_hand(void **state) {
  (void)state;
  bbc_params p, d;
  bbc_params_default(&d);
  bbc_hand hand = 0;
  bbc_error err;
  p = d;
  assert_int_equal(bbc_params_set_by_hand(&p, &hand, "texres", "64", &err), BBC_OK);
  assert_int_equal(p.atlas_max, 0);
  assert_true(bbc_params_by_hand(hand, "TEXRES"));
  assert_false(bbc_params_by_hand(hand, "atlasmax"));
  hand = 0;
  p = d;
  assert_int_equal(bbc_params_set_by_hand(&p, &hand, "maxplanes", "40", &err), BBC_OK);
  assert_int_equal(bbc_params_set_by_hand(&p, &hand, "epsilon", "3", &err), BBC_OK);
  assert_int_equal(p.max_planes, 40); /* by hand before epsilon: kept */
  assert_int_equal(p.min_planes, 0);  /* not by hand: off */
  assert_int_not_equal(bbc_params_set_by_hand(&p, &hand, "epsilon", "500", &err), BBC_OK);
  assert_true(p.epsilon_pct == 3);
  /* --thesis: Appendix A's defaults where nothing was set by hand */
  bbc_params_thesis_merge(&p, hand);
  bbc_params t;
  bbc_params_thesis(&t);
  assert_true(p.epsilon_pct == 3);
  assert_int_equal(p.max_planes, 40);
  assert_int_equal(p.clustering, t.clustering);
  assert_int_equal(p.quality, t.quality);
  /* a LOD chain: the budgets off unless by hand */
  p = d;
  bbc_params_lod_chain(&p, 0);
  assert_int_equal(p.max_planes, 0);
  assert_int_equal(p.min_planes, 0);
  p = d;
  hand = 0;
  assert_int_equal(bbc_params_set_by_hand(&p, &hand, "minplanes", "8", &err), BBC_OK);
  bbc_params_lod_chain(&p, hand);
  assert_int_equal(p.min_planes, 8);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_defaults_match_appendix_a),
      cmocka_unit_test(test_set_and_ranges),
      cmocka_unit_test(test_first_step),
      cmocka_unit_test(test_by_hand),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
