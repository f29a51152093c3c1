/* test_acceptance.c — step 3's acceptance on real models, through the tool:
 * `bbcgen MODEL -o OUT.glb --report R.json --preview P.png` for the Scopia
 * pine and bush, the ez-tree oak_medium and ash_large_hi, and the cat; each
 * .glb passes the Khronos validator, loads back through Assimp with the
 * triangle count the billboards' outlines give, and its bounding box matches
 * the original's within epsilon. Also --lod (one glTF node per level) and
 * VRML output. The four trees run in the release build only (too slow under ASan). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <cjson/cJSON.h>

#include "bbc.h"
#include "test_util.h"

static int run(const char *args) {
  char cmd[8192];
  snprintf(cmd, sizeof cmd, "'%s/bbcgen' %s -q < /dev/null", BBC_BIN_DIR, args);
  fflush(stdout);
  int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

static cJSON *read_json(const char *path) {
  char *text = (char *)tu_read_file(path, NULL);
  if (!text) fail_msg("%s: missing", path);
  cJSON *j = cJSON_Parse(text);
  free(text);
  if (!j) fail_msg("%s: not JSON", path);
  return j;
}

static double num(const cJSON *o, const char *name) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, name);
  if (!cJSON_IsNumber(v)) fail_msg("report: no number '%s'", name);
  return v->valuedouble;
}

static void accept_model(const char *rel, const char *extra, int big) {
#ifdef BBC_TEST_SANITIZE
  if (big) {
    printf("SKIP: %s: big models run in the release build only\n", rel);
    skip();
  }
#else
  (void)big;
#endif
  char model[1024];
  tu_data_path(model, sizeof model, rel);
  if (!tu_have_file(model)) skip();
  char *dir = tu_make_temp_dir();
  char out[1200], report[1200], preview[1200], args[6000];
  snprintf(out, sizeof out, "%s/cloud.glb", dir);
  snprintf(report, sizeof report, "%s/report.json", dir);
  snprintf(preview, sizeof preview, "%s/preview.png", dir);
  snprintf(args, sizeof args,
           "'%s' -o '%s' --report '%s' --preview '%s' --preview-size 64 --epsilon 6 "
           "--clustering 0 --quality 2 %s",
           model, out, report, preview, extra);
  assert_int_equal(run(args), 0);
  /* The validator: 0 errors. */
  int v = tu_gltf_validate(out);
  if (v == 3) {
    printf("SKIP: gltf-validator unavailable\n");
    skip();
  }
  assert_int_equal(v, 0);
  /* The report: one level, its outlines give the triangle count. */
  cJSON *rep = read_json(report);
  const cJSON *lods = cJSON_GetObjectItemCaseSensitive(rep, "lods");
  assert_int_equal(cJSON_GetArraySize(lods), 1);
  const cJSON *lod = cJSON_GetArrayItem(lods, 0);
  double eps = num(lod, "epsilon");
  const cJSON *list = cJSON_GetObjectItemCaseSensitive(lod, "billboard_list");
  size_t expect_tris = 0;
  const cJSON *b;
  cJSON_ArrayForEach(b, list) expect_tris += 2 * ((size_t)num(b, "corners") - 2);
  /* The trunk part as a mesh: at most `limbs` 512 and 4 times the
   * billboards' triangles. */
  size_t limb_tris = (size_t)num(lod, "limb_triangles");
  assert_true(limb_tris <= 512 && (limb_tris <= 4 * expect_tris || limb_tris <= 16));
  expect_tris += limb_tris;
  assert_int_equal((size_t)num(lod, "billboards"), (size_t)cJSON_GetArraySize(list));
  assert_int_equal((size_t)num(lod, "triangles"), expect_tris);
  assert_true(num(lod, "atlas_fill") > 0.1 && num(lod, "atlas_fill") <= 1);
  /* Assimp reads it back: the expected triangles, textured, in the bounds. */
  bbc_mesh orig, cloud;
  bbc_error err;
  if (bbc_mesh_load(model, NULL, &orig, &err) != BBC_OK) fail_msg("%s", err.message);
  if (bbc_mesh_load(out, NULL, &cloud, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(cloud.triangle_count, expect_tris);
  assert_true(cloud.texture_count >= 1 && cloud.textures[0].has_alpha);
  printf("%s: %zu billboards, %zu triangles, epsilon %g\n", rel, (size_t)num(lod, "billboards"),
         cloud.triangle_count, eps);
  for (int k = 0; k < 3; k++) {
    printf("  axis %d: cloud [%g, %g], model [%g, %g]\n", k, cloud.bbox_min[k], cloud.bbox_max[k],
           orig.bbox_min[k], orig.bbox_max[k]);
    double tol = eps * (1 + 1e-5) + 1e-6 * orig.radius; /* float positions in glTF */
    assert_true(fabs(cloud.bbox_min[k] - orig.bbox_min[k]) <= tol);
    assert_true(fabs(cloud.bbox_max[k] - orig.bbox_max[k]) <= tol);
  }
  /* The preview: 4 views by 3 rows. */
  bbc_image pv;
  if (bbc_image_load(preview, &pv, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_true(pv.width == 4 * 64 && pv.height == 3 * 64);
  bbc_image_free(&pv);
  bbc_mesh_free(&orig);
  bbc_mesh_free(&cloud);
  cJSON_Delete(rep);
  tu_remove_dir(dir);
  free(dir);
}

static void test_pine(void **state) {
  (void)state;
  accept_model("trees/scopia/pine/pine.obj", "--texres 256", 1);
}

static void test_bush(void **state) {
  (void)state;
  accept_model("trees/scopia/bush/bush.obj", "", 1);
}

static void test_oak_medium(void **state) {
  (void)state;
  accept_model("trees/eztree/oak_medium.obj", "", 1);
}

static void test_ash_large_hi(void **state) {
  (void)state;
  accept_model("trees/eztree/ash_large_hi.obj", "", 1);
}

static void test_cat(void **state) {
  (void)state;
  accept_model("models/cat.3ds", "--upaxis z --nm 1", 0);
}

/* --lod: one node per level, finest first, chained by MSFT_lod; VRML. */
static void test_lod_and_vrml(void **state) {
  (void)state;
  char model[1024];
  tu_data_path(model, sizeof model, "trees/eztree/aspen_small.obj");
  if (!tu_have_file(model)) skip();
  char *dir = tu_make_temp_dir();
  char args[4096], out[1200];
  snprintf(out, sizeof out, "%s/lod.glb", dir);
  snprintf(args, sizeof args, "'%s' -o '%s' --clustering 0 --lod 5,10,20 --texres 64", model, out);
  assert_int_equal(run(args), 0);
  int v = tu_gltf_validate(out);
  if (v != 3) assert_int_equal(v, 0);
  size_t n;
  unsigned char *g = tu_read_file(out, &n);
  assert_non_null(g);
  uint32_t jl =
      (uint32_t)g[12] | (uint32_t)g[13] << 8 | (uint32_t)g[14] << 16 | (uint32_t)g[15] << 24;
  cJSON *j = cJSON_ParseWithLength((const char *)g + 20, jl);
  assert_non_null(j);
  /* Three levels named as engines import LOD groups, children of one group
   * node (the scene's root); level 0 names the others through MSFT_lod and
   * carries decreasing MSFT_screencoverage hints. */
  const cJSON *nodes = cJSON_GetObjectItemCaseSensitive(j, "nodes");
  assert_int_equal(cJSON_GetArraySize(nodes), 4);
  const cJSON *group = cJSON_GetArrayItem(nodes, 3);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(group, "name")->valuestring, "aspen_small");
  const cJSON *children = cJSON_GetObjectItemCaseSensitive(group, "children");
  assert_int_equal(cJSON_GetArraySize(children), 3);
  const cJSON *scene_nodes = cJSON_GetObjectItemCaseSensitive(
      cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "scenes"), 0), "nodes");
  assert_int_equal(cJSON_GetArraySize(scene_nodes), 1);
  assert_int_equal(cJSON_GetArrayItem(scene_nodes, 0)->valueint, 3);
  const cJSON *ids = cJSON_GetObjectItemCaseSensitive(
      cJSON_GetObjectItemCaseSensitive(
          cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(nodes, 0), "extensions"), "MSFT_lod"),
      "ids");
  assert_int_equal(cJSON_GetArraySize(ids), 2);
  const cJSON *cover = cJSON_GetObjectItemCaseSensitive(
      cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(nodes, 0), "extras"),
      "MSFT_screencoverage");
  assert_int_equal(cJSON_GetArraySize(cover), 3);
  double prev = 0, prev_bb = 1e9, prev_cover = 2;
  for (int k = 0; k < 3; k++) {
    const cJSON *node = cJSON_GetArrayItem(nodes, k);
    char name[64];
    snprintf(name, sizeof name, "aspen_small_LOD%d", k);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(node, "name")->valuestring, name);
    assert_int_equal(cJSON_GetArrayItem(children, k)->valueint, k);
    const cJSON *ex = cJSON_GetObjectItemCaseSensitive(node, "extras");
    double e = num(ex, "epsilon_pct"), bb = num(ex, "billboards");
    assert_true(e > prev && bb <= prev_bb);
    prev = e;
    prev_bb = bb;
    double c = cJSON_GetArrayItem(cover, k)->valuedouble;
    assert_true(c > 0 && c <= 1 && c < prev_cover);
    prev_cover = c;
  }
  /* The three levels fit one atlas together: one image per map (colour,
   * normal, occlusion) for all of them. */
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "images")), 3);
  /* A third-party importer sees every level: Assimp's `assimp info`. */
  if (system("command -v assimp > /dev/null 2>&1") == 0) {
    char cmd[2600], *listing = NULL;
    snprintf(cmd, sizeof cmd, "assimp info '%s' > '%s.txt' 2>&1", out, out);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s.txt", out);
    listing = (char *)tu_read_file(cmd, NULL);
    assert_non_null(listing);
    for (int k = 0; k < 3; k++) {
      char name[64];
      /* each level's billboards, then its limbs (a second primitive) */
      snprintf(name, sizeof name, "aspen_small_LOD%d (mesh %d, %d)", k, 2 * k, 2 * k + 1);
      assert_non_null(strstr(listing, name));
    }
    free(listing);
  } else {
    printf("assimp (Debian assimp-utils) not installed: the Assimp import check is skipped\n");
  }
  /* The engine's view: each level loads on its own (lod_node), the levels
   * together make the whole file, and there is no fourth. */
  size_t whole = 0, sum = 0;
  for (int k = 0; k <= 4; k++) {
    bbc_load_options lo;
    bbc_load_options_default(&lo);
    lo.skip_textures = 1;
    lo.lod_node = k;
    bbc_mesh lm;
    bbc_error lerr;
    bbc_result lr = bbc_mesh_load(out, &lo, &lm, &lerr);
    if (k == 4) {
      assert_int_equal(lr, BBC_ERROR_NOT_FOUND);
      assert_non_null(strstr(lerr.message, "_LOD3"));
      continue;
    }
    if (lr != BBC_OK) fail_msg("%s", lerr.message);
    if (k == 0)
      whole = lm.triangle_count;
    else
      sum += lm.triangle_count;
    assert_true(lm.triangle_count > 0);
    bbc_mesh_free(&lm);
  }
  assert_int_equal(sum, whole);
  cJSON_Delete(j);
  free(g);
  /* VRML, both formats, and the OBJ chain. */
  for (int format = 0; format <= 1; format++) {
    snprintf(out, sizeof out, "%s/f%d.wrl", dir, format);
    snprintf(args, sizeof args, "'%s' -o '%s' --clustering 0 --texres 64 --format %d --nm 1", model,
             out, format);
    assert_int_equal(run(args), 0);
    char *text = (char *)tu_read_file(out, NULL);
    assert_non_null(text);
    assert_true(!strncmp(text, "#VRML V2.0 utf8", 15));
    assert_true((strstr(text, "NormalMap") != NULL) == (format == 0));
    free(text);
  }
  /* The Scopia palm's stem billboards are clipped to its trunk's bounds
   * into outlines whose fans a VRML file must carry whole. */
  char palm[1024];
  tu_data_path(palm, sizeof palm, "trees/scopia/palm/palm.obj");
  if (tu_have_file(palm)) {
    snprintf(out, sizeof out, "%s/palm.wrl", dir);
    snprintf(args, sizeof args, "'%s' -o '%s' --limbs 0", palm, out);
    assert_int_equal(run(args), 0);
    char *text = (char *)tu_read_file(out, NULL);
    assert_non_null(text);
    assert_non_null(strstr(text, "stem plane"));
    free(text);
    /* By default its trunk part is a mesh: one more Shape after the
     * billboards', read back whole. */
    snprintf(out, sizeof out, "%s/palm_limbs.wrl", dir);
    snprintf(args, sizeof args, "'%s' -o '%s'", palm, out);
    assert_int_equal(run(args), 0);
    text = (char *)tu_read_file(out, NULL);
    assert_non_null(text);
    assert_null(strstr(text, "stem plane"));
    assert_non_null(strstr(text, "DEF Limbs Shape"));
    free(text);
    bbc_mesh back;
    bbc_error e;
    if (bbc_mesh_load(out, NULL, &back, &e) != BBC_OK) fail_msg("%s", e.message);
    assert_true(back.triangle_count > 256);
    bbc_mesh_free(&back);
  }
  snprintf(out, sizeof out, "%s/c.obj", dir);
  snprintf(args, sizeof args, "'%s' -o '%s' --clustering 0 --texres 64 --lod 5,10", model, out);
  assert_int_equal(run(args), 0);
  snprintf(out, sizeof out, "%s/c_lod1.obj", dir);
  unsigned char *o1 = tu_read_file(out, &n);
  assert_non_null(o1);
  free(o1);
  tu_remove_dir(dir);
  free(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pine),       cmocka_unit_test(test_bush),
      cmocka_unit_test(test_oak_medium), cmocka_unit_test(test_ash_large_hi),
      cmocka_unit_test(test_cat),        cmocka_unit_test(test_lod_and_vrml),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
