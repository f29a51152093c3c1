/* test_cli.c — the bbcgen tool as a user runs it: `info --json` on the real
 * data, exit codes for hostile inputs and bad parameters, --help, tree,
 * planes, sample. The other commands: test_cli_exec.c (batch files and the
 * prompt), test_cli_view.c (the viewer), test_cli_cloud.c (making clouds). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cjson/cJSON.h>

#include "bbc.h"
#include "cli_util.h"
#include "test_util.h"

static void test_info_pine(void **state) {
  (void)state;
  cJSON *j = cli_info_json("trees/scopia/pine/pine.obj");
  if (!j) skip();
  assert_int_equal((int)cli_num(j, "triangles"), 108810);
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "groups")), 2);
  assert_int_equal((int)cli_group_triangles(j, "twigs_Cube.001"), 102600);
  assert_int_equal((int)cli_group_triangles(j, "tree"), 6210);
  /* The documented keys are all there. */
  const char *keys[] = {"triangles", "vertices", "materials", "groups", "bbox", "center", "radius"};
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
    assert_non_null(cJSON_GetObjectItemCaseSensitive(j, keys[i]));
  const cJSON *bbox = cJSON_GetObjectItem(j, "bbox");
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(bbox, "min")), 3);
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "center")), 3);
  assert_true(cli_num(j, "radius") > 250 && cli_num(j, "radius") < 350);
  cJSON_Delete(j);
}

static void test_info_cat_and_h60(void **state) {
  (void)state;
  cJSON *j = cli_info_json("models/cat.3ds");
  if (!j) skip();
  assert_int_equal((int)cli_num(j, "triangles"), 14348);
  cJSON_Delete(j);
  j = cli_info_json("models/flightgear/H-60.ac");
  if (!j) skip();
  assert_int_equal((int)cli_num(j, "triangles"), 5388);
  int png = 0;
  const cJSON *m;
  cJSON_ArrayForEach(m, cJSON_GetObjectItem(j, "materials")) {
    const cJSON *t = cJSON_GetObjectItem(m, "texture");
    if (cJSON_IsString(t) && strstr(t->valuestring, "H-60.png")) png = 1;
  }
  assert_true(png);
  cJSON_Delete(j);
}

static void test_info_oak_alpha(void **state) {
  (void)state;
  cJSON *j = cli_info_json("trees/eztree/oak_medium.obj");
  if (!j) skip();
  int leaf_alpha = 0;
  const cJSON *m;
  cJSON_ArrayForEach(m, cJSON_GetObjectItem(j, "materials")) {
    if (strstr(cJSON_GetObjectItem(m, "name")->valuestring, "leaves"))
      leaf_alpha = cJSON_IsTrue(cJSON_GetObjectItem(m, "texture_has_alpha"));
  }
  assert_true(leaf_alpha);
  cJSON_Delete(j);
}

static void test_info_points(void **state) {
  (void)state;
  cJSON *j = cli_info_json("points/b9_training.ply");
  if (!j) skip();
  assert_string_equal(cJSON_GetObjectItem(j, "kind")->valuestring, "points");
  assert_int_equal((int)cli_num(j, "points"), 22300);
  assert_int_equal((int)cli_num(j, "triangles"), 0);
  cJSON_Delete(j);
}

static void test_damaged_pond_refused(void **state) {
  (void)state;
  char path[1024], args[2048];
  tu_data_path(path, sizeof path, "points/pond.0.ply");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "info --json '%s'", path);
  char *out, *err;
  int rc = cli_run(args, &out, &err);
  assert_int_equal(rc, 4);
  assert_non_null(strstr(err, "pond.0.ply"));
  assert_true(strstr(err, "truncated") || strstr(err, "damaged"));
  /* One line, and no points printed. */
  assert_int_equal(strchr(err, '\n') - err + 1, (long)strlen(err));
  assert_true(out == NULL || out[0] == 0);
  free(out);
  free(err);
}

static void test_exit_codes(void **state) {
  (void)state;
  char args[2048];
  char *out, *err;
  snprintf(args, sizeof args, "info '%s/nothing.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 2);
  assert_non_null(strstr(err, "nothing.obj"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "info '%s'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 2);
  assert_non_null(strstr(err, "folder"));
  free(out);
  free(err);
  char *p = tu_write_file(tu_dir, "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 34);
  snprintf(args, sizeof args, "info '%s'", p);
  assert_int_equal(cli_run(args, &out, &err), 4);
  assert_non_null(strstr(err, "nan.obj"));
  assert_int_equal(strchr(err, '\n') - err + 1, (long)strlen(err)); /* one line */
  free(out);
  free(err);
  free(p);
  p = tu_write_file(tu_dir, "x.qqq", "hello world, not a model\n", 25);
  snprintf(args, sizeof args, "info '%s'", p);
  assert_int_equal(cli_run(args, &out, &err), 3);
  free(out);
  free(err);
  free(p);
  /* Parameters: out of range names the range. */
  assert_int_equal(cli_run("setup --epsilon 150", &out, &err), 1);
  assert_non_null(strstr(err, "0.001 to 99"));
  free(out);
  free(err);
  assert_int_equal(cli_run("setup --set texres=100", &out, &err), 1);
  assert_non_null(strstr(err, "power of two"));
  free(out);
  free(err);
  assert_int_equal(cli_run("setup --set res=7", &out, &err), 1);
  free(out);
  free(err);
  assert_int_equal(cli_run("setup --set nosuch=1", &out, &err), 1);
  free(out);
  free(err);
  assert_int_equal(cli_run("setup --epsilon 6 --set texres=512 --posttweak off", &out, &err), 0);
  assert_non_null(strstr(out, "epsilon        6\n"));
  assert_non_null(strstr(out, "texres         512\n"));
  assert_non_null(strstr(out, "posttweak      0\n"));
  free(out);
  free(err);
  assert_int_equal(cli_run("--bogus", &out, &err), 1);
  free(out);
  free(err);
}

static void test_help_lists_every_parameter(void **state) {
  (void)state;
  char *out, *err;
  assert_int_equal(cli_run("--help", &out, &err), 0);
  static const char *names[] = {
      "break",     "breaknum",     "debug",       "res",         "vn",
      "cardboard", "cbcoverage",   "clustering",  "epsilon",     "posttweak",
      "punishval", "punishcutoff", "subpenalty",  "supergreedy", "backface",
      "nm",        "pointsize",    "pointsmooth", "pointskip",   "polyskip",
      "prelight",  "pure",         "quality",     "texres",      "format"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    char needle[64];
    snprintf(needle, sizeof needle, "\n    %s", names[i]);
    if (!strstr(out, needle)) fail_msg("--help lacks parameter %s", names[i]);
  }
  assert_non_null(strstr(out, "Exit codes"));
  free(out);
  free(err);
  assert_int_equal(cli_run("--version", &out, &err), 0);
  assert_non_null(strstr(out, "bbcgen "));
  free(out);
  free(err);
}

static void test_tree_command(void **state) {
  (void)state;
  char args[2048];
  char *out, *err;
  snprintf(args, sizeof args, "tree --seed 7 --leaves 2000 -o '%s/t1.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "tree --seed 7 --leaves 2000 -o '%s/t2.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  /* Not a terminal: no progress bar characters in the log. */
  assert_null(strstr(err, "\r"));
  free(out);
  free(err);
  char a[1024], b[1024];
  size_t na, nb;
  snprintf(a, sizeof a, "%s/t1.obj", tu_dir);
  snprintf(b, sizeof b, "%s/t2.obj", tu_dir);
  unsigned char *fa = tu_read_file(a, &na), *fb = tu_read_file(b, &nb);
  assert_non_null(fa);
  assert_non_null(fb);
  /* The files differ only in the mtllib name; compare after the header. */
  assert_int_equal(na, nb);
  const char *ba = strstr((char *)fa, "\nv "), *bb = strstr((char *)fb, "\nv ");
  assert_non_null(ba);
  assert_memory_equal(ba, bb, na - (size_t)(ba - (char *)fa));
  free(fa);
  free(fb);
  snprintf(a, sizeof a, "%s/t1_obj_leaf.png", tu_dir);
  snprintf(b, sizeof b, "%s/t2_obj_leaf.png", tu_dir);
  fa = tu_read_file(a, &na);
  fb = tu_read_file(b, &nb);
  assert_non_null(fa);
  assert_int_equal(na, nb);
  assert_memory_equal(fa, fb, na);
  free(fa);
  free(fb);
  /* The written tree loads back with its two groups. */
  snprintf(args, sizeof args, "info --json '%s/t1.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  cJSON *j = cJSON_Parse(out);
  assert_non_null(j);
  assert_int_equal((int)cli_group_triangles(j, "leaves"), 4000);
  assert_true(cli_group_triangles(j, "trunk") > 0);
  cJSON_Delete(j);
  free(out);
  free(err);
  /* Outputs get the permissions the umask asks for (not a temp file's 0600),
   * and no temporary file is left beside them. */
  mode_t mask = umask(022);
  umask(mask);
  struct stat st;
  snprintf(a, sizeof a, "%s/t1.obj", tu_dir);
  assert_int_equal(stat(a, &st), 0);
  assert_int_equal(st.st_mode & 0777, 0666 & ~mask);
  DIR *d = opendir(tu_dir);
  struct dirent *e;
  while ((e = readdir(d)) != NULL)
    if (strstr(e->d_name, ".tmp.")) fail_msg("temporary file left: %s", e->d_name);
  closedir(d);
  /* No half-written outputs: an unwritable destination fails cleanly. */
  snprintf(args, sizeof args, "tree -o '%s/no/such/dir/t.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 5);
  free(out);
  free(err);
  assert_int_equal(cli_run("tree --species cactus -o x.obj", &out, &err), 1);
  free(out);
  free(err);
}

/* `bbcgen planes`: 1 and 2 threads, and two runs, write identical JSON; the
 * JSON has the documented keys; per-part settings are applied. */
static void test_planes_json_identical(void **state) {
  (void)state;
  char path[1024], args[2048];
  tu_data_path(path, sizeof path, "trees/eztree/oak_medium.obj");
  if (!tu_have_file(path)) skip();
  const char *extra = "--epsilon 6 --supergreedy 1 --set trunk.cardboard=1 --punishval 0.7 "
                      "--punishcutoff 55 --limbs 0";
  unsigned char *text[3];
  size_t len[3];
  for (int i = 0; i < 3; i++) {
    snprintf(args, sizeof args, "planes '%s' %s --threads %d -q --json '%s/p%d.json'", path, extra,
             i == 0 ? 1 : 2, tu_dir, i);
    char *out, *err;
    if (cli_run(args, &out, &err) != 0) fail_msg("bbcgen planes failed: %s", err);
    free(out);
    free(err);
    char jp[1024];
    snprintf(jp, sizeof jp, "%s/p%d.json", tu_dir, i);
    text[i] = tu_read_file(jp, &len[i]);
    assert_non_null(text[i]);
  }
  assert_int_equal(len[0], len[1]);
  assert_memory_equal(text[0], text[1], len[0]);
  assert_int_equal(len[1], len[2]);
  assert_memory_equal(text[1], text[2], len[1]);
  cJSON *j = cJSON_Parse((const char *)text[0]);
  assert_non_null(j);
  assert_true(cli_num(j, "epsilon_abs") > 0);
  assert_true(cli_num(j, "radius") > 0);
  const cJSON *planes = cJSON_GetObjectItem(j, "planes");
  assert_true(cJSON_GetArraySize(planes) > 0);
  int cardboard = 0;
  const cJSON *p;
  cJSON_ArrayForEach(p, planes) {
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(p, "normal")), 3);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(p, "d")));
    assert_true(cJSON_IsString(cJSON_GetObjectItem(p, "kind")));
    assert_true(cli_num(p, "faces") > 0);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(p, "area")));
    if (!strcmp(cJSON_GetObjectItem(p, "kind")->valuestring, "cardboard")) {
      cardboard++;
      /* Cardboard planes only for the trunk (set per part). */
      assert_string_equal(cJSON_GetObjectItem(p, "part")->valuestring, "trunk");
    }
  }
  assert_true(cardboard > 0);
  /* One plane index per triangle. */
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "face_plane")), 13806);
  cJSON_Delete(j);
  for (int i = 0; i < 3; i++) free(text[i]);
  /* Bad per-part settings are refused with the range. */
  char *out, *err;
  snprintf(args, sizeof args, "planes '%s' --set trunk.epsilon=200", path);
  assert_int_equal(cli_run(args, &out, &err), 1);
  assert_non_null(strstr(err, "0.001 to 99"));
  free(out);
  free(err);
}

/* bbcgen sample: points on a model's surface as binary PLY with colours,
 * the same bytes for the same seed, read back as a point cloud. */
static void test_sample(void **state) {
  (void)state;
  char path[1024], args[4096], a[1200], b[1200];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  for (int k = 0; k < 2; k++) {
    snprintf(args, sizeof args, "sample '%s' -o s%d.ply --points 5000 --seed 7 -q", path, k);
    if (cli_run_in(args, "", &out, &err)) fail_msg("%s", err);
    free(out);
    free(err);
  }
  snprintf(a, sizeof a, "%s/s0.ply", tu_dir);
  snprintf(b, sizeof b, "%s/s1.ply", tu_dir);
  assert_true(tu_same_file(a, b)); /* byte for byte */
  bbc_mesh m;
  bbc_error e;
  assert_int_equal(bbc_mesh_load(a, NULL, &m, &e), BBC_OK);
  assert_int_equal(m.kind, BBC_MESH_POINTS);
  assert_int_equal(m.vertex_count, 5000);
  assert_non_null(m.colors);
  bbc_mesh_free(&m);
  assert_int_equal(cli_run_in("sample x.obj -o y.txt", "", &out, &err), 1);
  assert_non_null(strstr(err, "usage"));
  free(out);
  free(err);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_info_pine),
      cmocka_unit_test(test_info_cat_and_h60),
      cmocka_unit_test(test_info_oak_alpha),
      cmocka_unit_test(test_info_points),
      cmocka_unit_test(test_damaged_pond_refused),
      cmocka_unit_test(test_exit_codes),
      cmocka_unit_test(test_help_lists_every_parameter),
      cmocka_unit_test(test_tree_command),
      cmocka_unit_test(test_planes_json_identical),
      cmocka_unit_test(test_sample),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
