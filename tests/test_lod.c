/* test_lod.c — LOD chains as assets (issue 32): levels chosen by screen size
 * with texels and triangles falling, one file per level for engines that do
 * not read MSFT_lod, and eval judging each level alone at its own size. Runs
 * bbcgen as a user would. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#include <cmocka.h>
#include <sys/wait.h>

#include "bbc.h"
#include "test_util.h"

static int run(const char *args, char **errout) {
  char cmd[8192], e[1024];
  snprintf(e, sizeof e, "%s/stderr.txt", tu_dir);
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' %s > /dev/null 2> '%s' < /dev/null", tu_dir,
           BBC_BIN_DIR, args, e);
  int st = system(cmd);
  char *err = (char *)tu_read_file(e, NULL);
  if (errout)
    *errout = err ? err : strdup("");
  else
    free(err);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

static cJSON *read_json(const char *name) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", tu_dir, name);
  size_t n = 0;
  unsigned char *d = tu_read_file(p, &n);
  if (!d) fail_msg("%s missing", name);
  cJSON *j;
  if (n > 20 && !memcmp(d, "glTF", 4)) {
    size_t jl = (size_t)d[12] | (size_t)d[13] << 8 | (size_t)d[14] << 16 | (size_t)d[15] << 24;
    j = cJSON_ParseWithLength((const char *)d + 20, jl);
  } else {
    j = cJSON_ParseWithLength((const char *)d, n);
  }
  free(d);
  if (!j) fail_msg("%s: not JSON", name);
  return j;
}

static double num(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!cJSON_IsNumber(v)) fail_msg("no number '%s'", key);
  return v->valuedouble;
}

/* --lod-pixels: screen sizes where the levels start; texels and triangles
 * fall, within a level's budget; the sizes in the report, the nodes' extras and
 * MSFT_screencoverage;
 * --lod-files: a file a level, one node each, valid; eval: a level each at
 * its own size, keeping the original's density there. */
static void test_chain_by_pixels(void **state) {
  (void)state;
  char model[1024], args[4096];
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(model)) skip();
  snprintf(args, sizeof args, "'%s' -o t.glb --lod-pixels 256,64,16 --lod-files --report r.json",
           model);
  assert_int_equal(run(args, NULL), 0);
  cJSON *r = read_json("r.json");
  const cJSON *levels = cJSON_GetObjectItemCaseSensitive(r, "lods");
  assert_int_equal(cJSON_GetArraySize(levels), 3);
  const double want_px[3] = {256, 64, 16};
  for (int k = 0; k < 3; k++) {
    const cJSON *l = cJSON_GetArrayItem(levels, k);
    assert_true(num(l, "screen_px") == want_px[k]);
    assert_true(num(l, "texres_used") <= want_px[k]); /* at most a texel a pixel */
    /* at most max(32, P^2 / 64) triangles (without the rule: 562, 530, 350) */
    double budget = fmax(32, want_px[k] * want_px[k] / 64);
    if (num(l, "triangles") > budget)
      fail_msg("level %d: %g triangles, budget %g", k, num(l, "triangles"), budget);
    if (k) {
      const cJSON *p = cJSON_GetArrayItem(levels, k - 1);
      assert_true(num(l, "texels") < num(p, "texels"));
      assert_true(num(l, "triangles") < num(p, "triangles"));
      assert_true(num(l, "epsilon_pct_used") > num(p, "epsilon_pct_used"));
    }
  }
  cJSON *g = read_json("t.glb");
  const cJSON *nodes = cJSON_GetObjectItemCaseSensitive(g, "nodes");
  int found = 0;
  const cJSON *node;
  cJSON_ArrayForEach(node, nodes) {
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(node, "extensions");
    const cJSON *lod = cJSON_GetObjectItemCaseSensitive(ext, "MSFT_lod");
    if (!lod) continue;
    const cJSON *cov = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(node, "extras"), "MSFT_screencoverage");
    assert_int_equal(cJSON_GetArraySize(cov), 3);
    /* level k gives way where the tree is level k + 1's size on 1080 lines */
    assert_true(fabs(cJSON_GetArrayItem(cov, 0)->valuedouble - 64.0 / 1080) < 1e-6);
    assert_true(fabs(cJSON_GetArrayItem(cov, 1)->valuedouble - 16.0 / 1080) < 1e-6);
    found = 1;
  }
  assert_true(found);
  cJSON_Delete(g);
  for (int k = 0; k < 3; k++) {
    char name[64], path[2048];
    snprintf(name, sizeof name, "t_LOD%d.glb", k);
    cJSON *f = read_json(name);
    const cJSON *fn = cJSON_GetObjectItemCaseSensitive(f, "nodes");
    assert_int_equal(cJSON_GetArraySize(fn), 1);
    char want[64];
    snprintf(want, sizeof want, "Tree_1_LOD%d", k);
    assert_string_equal(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(fn, 0), "name")->valuestring, want);
    char *text = cJSON_PrintUnformatted(f);
    assert_null(strstr(text, "MSFT_lod"));
    cJSON_free(text);
    cJSON_Delete(f);
    snprintf(path, sizeof path, "%s/%s", tu_dir, name);
    int v = tu_gltf_validate(path);
    if (v != 3) assert_int_equal(v, 0);
  }
  cJSON_Delete(r);
  /* eval: each level alone at its size */
  snprintf(args, sizeof args, "eval '%s' t.glb --views 16 --no-lit --json e.json", model);
  assert_int_equal(run(args, NULL), 0);
  cJSON *e = read_json("e.json");
  const cJSON *el = cJSON_GetObjectItemCaseSensitive(e, "levels");
  assert_int_equal(cJSON_GetArraySize(el), 3);
  for (int k = 0; k < 3; k++) {
    const cJSON *l = cJSON_GetArrayItem(el, k);
    assert_true(num(l, "screen_px") == want_px[k]);
    double cov = num(l, "coverage_ratio_side_mean");
    if (!(cov >= 0.85 && cov <= 1.15)) fail_msg("level %d: side coverage %.3f", k, cov);
    assert_true(num(l, "block_iou_side_mean") > 0.5);
  }
  cJSON_Delete(e);
}

/* An epsilon chain keeps its epsilons, and its texels fall even where the
 * atlas budget would give a coarser level a larger texres. */
static void test_chain_by_epsilons_falls(void **state) {
  (void)state;
  char model[1024], args[4096];
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Birch_1.obj");
  if (!tu_have_file(model)) skip();
  snprintf(args, sizeof args, "'%s' -o b.gltf --lod 6,10,15 --report rb.json", model);
  assert_int_equal(run(args, NULL), 0);
  cJSON *r = read_json("rb.json");
  const cJSON *levels = cJSON_GetObjectItemCaseSensitive(r, "lods");
  assert_int_equal(cJSON_GetArraySize(levels), 3);
  for (int k = 1; k < 3; k++) {
    const cJSON *l = cJSON_GetArrayItem(levels, k), *p = cJSON_GetArrayItem(levels, k - 1);
    assert_true(num(l, "texels") < num(p, "texels"));
    assert_true(num(l, "triangles") < num(p, "triangles"));
  }
  cJSON_Delete(r);
}

/* -o OUT.fbx: the chain in one FBX for engines' LOD groups, read back by
 * the loader (Assimp) level by level from its _LOD<k> names, each with the
 * triangles the glTF chain's level has and its colour atlas found beside
 * it; the same run with 1 thread gives the same bytes. */
static void test_chain_fbx(void **state) {
  (void)state;
  char model[1024], args[4096];
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(model)) skip();
  snprintf(args, sizeof args, "'%s' -o f.fbx --lod-pixels 256,64,16 --report rf.json", model);
  assert_int_equal(run(args, NULL), 0);
  snprintf(args, sizeof args, "'%s' -o f1/f.fbx --lod-pixels 256,64,16 --threads 1", model);
  char dir[1100];
  snprintf(dir, sizeof dir, "%s/f1", tu_dir);
  assert_int_equal(mkdir(dir, 0755), 0);
  assert_int_equal(run(args, NULL), 0);
  char a[1100], b[1100], png[1100];
  snprintf(a, sizeof a, "%s/f.fbx", tu_dir);
  snprintf(b, sizeof b, "%s/f1/f.fbx", tu_dir);
  snprintf(png, sizeof png, "%s/f_fbx_billboards_LOD0.png", tu_dir);
  assert_true(tu_same_file(a, b));
  assert_true(tu_have_file(png));
  cJSON *r = read_json("rf.json");
  const cJSON *levels = cJSON_GetObjectItemCaseSensitive(r, "lods");
  assert_int_equal(cJSON_GetArraySize(levels), 3);
  for (int k = 0; k < 3; k++) {
    bbc_load_options lo;
    bbc_load_options_default(&lo);
    lo.lod_node = k + 1;
    bbc_mesh m;
    bbc_error err;
    if (bbc_mesh_load(a, &lo, &m, &err) != BBC_OK) fail_msg("level %d: %s", k, err.message);
    assert_int_equal((double)m.triangle_count, num(cJSON_GetArrayItem(levels, k), "triangles"));
    int textured = 0;
    for (size_t i = 0; i < m.material_count; i++)
      textured |= m.materials[i].texture >= 0 && m.textures[m.materials[i].texture].has_alpha;
    assert_true(textured);
    bbc_mesh_free(&m);
  }
  cJSON_Delete(r);
}

/* Orders and mixes that make no chain are refused, naming why. */
static void test_chain_refusals(void **state) {
  (void)state;
  char *err;
  assert_int_equal(run("x.obj -o y.glb --lod-pixels 128,512", &err), 1);
  assert_non_null(strstr(err, "must fall"));
  free(err);
  assert_int_equal(run("x.obj -o y.glb --lod-pixels 512,abc", &err), 1);
  assert_non_null(strstr(err, "e.g. 512,128,32"));
  free(err);
  assert_int_equal(run("x.obj -o y.glb --lod 6,10 --lod-pixels 512,128", &err), 1);
  assert_non_null(strstr(err, "give one"));
  free(err);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_chain_by_pixels),
      cmocka_unit_test(test_chain_by_epsilons_falls),
      cmocka_unit_test(test_chain_refusals),
      cmocka_unit_test(test_chain_fbx),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
