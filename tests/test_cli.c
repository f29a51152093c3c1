/* test_cli.c — the bbcgen tool as a user runs it: `info --json` on the real
 * data, exit codes for hostile inputs and bad parameters, --help, tree. */
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
#include "test_util.h"

/* Runs `bbcgen ARGS`, stdout and stderr to files; returns the exit code and
 * the outputs (caller frees). */
static int run(const char *args, char **out, char **errout) {
  char cmd[4096], o[1024], e[1024];
  snprintf(o, sizeof o, "%s/stdout.txt", tu_dir);
  snprintf(e, sizeof e, "%s/stderr.txt", tu_dir);
  snprintf(cmd, sizeof cmd, "'%s/bbcgen' %s > '%s' 2> '%s' < /dev/null", BBC_BIN_DIR, args, o, e);
  int st = system(cmd);
  if (out) *out = (char *)tu_read_file(o, NULL);
  if (errout) *errout = (char *)tu_read_file(e, NULL);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

/* The same with `input` on standard input. */
static int run_in(const char *args, const char *input, char **out, char **errout) {
  char cmd[4096], o[1024], e[1024];
  char *in = tu_write_file(tu_dir, "stdin.txt", input, strlen(input));
  snprintf(o, sizeof o, "%s/stdout.txt", tu_dir);
  snprintf(e, sizeof e, "%s/stderr.txt", tu_dir);
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' %s > '%s' 2> '%s' < '%s'", tu_dir, BBC_BIN_DIR,
           args, o, e, in);
  free(in);
  int st = system(cmd);
  if (out) *out = (char *)tu_read_file(o, NULL);
  if (errout) *errout = (char *)tu_read_file(e, NULL);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

static cJSON *info_json(const char *rel) {
  char path[1024], args[2048];
  tu_data_path(path, sizeof path, rel);
  if (!tu_have_file(path)) return NULL;
  snprintf(args, sizeof args, "info --json '%s'", path);
  char *out, *err;
  int rc = run(args, &out, &err);
  if (rc != 0) fail_msg("bbcgen info %s: exit %d: %s", rel, rc, err);
  cJSON *j = cJSON_Parse(out);
  if (!j) fail_msg("not JSON: %s", out);
  free(out);
  free(err);
  return j;
}

static double num(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!cJSON_IsNumber(v)) fail_msg("no number '%s'", key);
  return v->valuedouble;
}

static double group_triangles(const cJSON *j, const char *name) {
  const cJSON *g;
  cJSON_ArrayForEach(g, cJSON_GetObjectItem(j, "groups")) {
    if (!strcmp(cJSON_GetObjectItem(g, "name")->valuestring, name)) return num(g, "triangles");
  }
  return -1;
}

static void test_info_pine(void **state) {
  (void)state;
  cJSON *j = info_json("trees/scopia/pine/pine.obj");
  if (!j) skip();
  assert_int_equal((int)num(j, "triangles"), 108810);
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "groups")), 2);
  assert_int_equal((int)group_triangles(j, "twigs_Cube.001"), 102600);
  assert_int_equal((int)group_triangles(j, "tree"), 6210);
  /* The documented keys are all there. */
  const char *keys[] = {"triangles", "vertices", "materials", "groups", "bbox", "center", "radius"};
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
    assert_non_null(cJSON_GetObjectItemCaseSensitive(j, keys[i]));
  const cJSON *bbox = cJSON_GetObjectItem(j, "bbox");
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(bbox, "min")), 3);
  assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "center")), 3);
  assert_true(num(j, "radius") > 250 && num(j, "radius") < 350);
  cJSON_Delete(j);
}

static void test_info_cat_and_h60(void **state) {
  (void)state;
  cJSON *j = info_json("models/cat.3ds");
  if (!j) skip();
  assert_int_equal((int)num(j, "triangles"), 14348);
  cJSON_Delete(j);
  j = info_json("models/flightgear/H-60.ac");
  if (!j) skip();
  assert_int_equal((int)num(j, "triangles"), 5388);
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
  cJSON *j = info_json("trees/eztree/oak_medium.obj");
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
  cJSON *j = info_json("points/b9_training.ply");
  if (!j) skip();
  assert_string_equal(cJSON_GetObjectItem(j, "kind")->valuestring, "points");
  assert_int_equal((int)num(j, "points"), 22300);
  assert_int_equal((int)num(j, "triangles"), 0);
  cJSON_Delete(j);
}

static void test_damaged_pond_refused(void **state) {
  (void)state;
  char path[1024], args[2048];
  tu_data_path(path, sizeof path, "points/pond.0.ply");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "info --json '%s'", path);
  char *out, *err;
  int rc = run(args, &out, &err);
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
  assert_int_equal(run(args, &out, &err), 2);
  assert_non_null(strstr(err, "nothing.obj"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "info '%s'", tu_dir);
  assert_int_equal(run(args, &out, &err), 2);
  assert_non_null(strstr(err, "folder"));
  free(out);
  free(err);
  char *p = tu_write_file(tu_dir, "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 34);
  snprintf(args, sizeof args, "info '%s'", p);
  assert_int_equal(run(args, &out, &err), 4);
  assert_non_null(strstr(err, "nan.obj"));
  assert_int_equal(strchr(err, '\n') - err + 1, (long)strlen(err)); /* one line */
  free(out);
  free(err);
  free(p);
  p = tu_write_file(tu_dir, "x.qqq", "hello world, not a model\n", 25);
  snprintf(args, sizeof args, "info '%s'", p);
  assert_int_equal(run(args, &out, &err), 3);
  free(out);
  free(err);
  free(p);
  /* Parameters: out of range names the range. */
  assert_int_equal(run("setup --epsilon 150", &out, &err), 1);
  assert_non_null(strstr(err, "0.001 to 99"));
  free(out);
  free(err);
  assert_int_equal(run("setup --set texres=100", &out, &err), 1);
  assert_non_null(strstr(err, "power of two"));
  free(out);
  free(err);
  assert_int_equal(run("setup --set res=7", &out, &err), 1);
  free(out);
  free(err);
  assert_int_equal(run("setup --set nosuch=1", &out, &err), 1);
  free(out);
  free(err);
  assert_int_equal(run("setup --epsilon 6 --set texres=512 --posttweak off", &out, &err), 0);
  assert_non_null(strstr(out, "epsilon        6\n"));
  assert_non_null(strstr(out, "texres         512\n"));
  assert_non_null(strstr(out, "posttweak      0\n"));
  free(out);
  free(err);
  assert_int_equal(run("--bogus", &out, &err), 1);
  free(out);
  free(err);
}

static void test_help_lists_every_parameter(void **state) {
  (void)state;
  char *out, *err;
  assert_int_equal(run("--help", &out, &err), 0);
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
  assert_int_equal(run("--version", &out, &err), 0);
  assert_non_null(strstr(out, "bbcgen "));
  free(out);
  free(err);
}

static void test_tree_command(void **state) {
  (void)state;
  char args[2048];
  char *out, *err;
  snprintf(args, sizeof args, "tree --seed 7 --leaves 2000 -o '%s/t1.obj'", tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "tree --seed 7 --leaves 2000 -o '%s/t2.obj'", tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
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
  assert_int_equal(run(args, &out, &err), 0);
  cJSON *j = cJSON_Parse(out);
  assert_non_null(j);
  assert_int_equal((int)group_triangles(j, "leaves"), 4000);
  assert_true(group_triangles(j, "trunk") > 0);
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
  assert_int_equal(run(args, &out, &err), 5);
  free(out);
  free(err);
  assert_int_equal(run("tree --species cactus -o x.obj", &out, &err), 1);
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
    if (run(args, &out, &err) != 0) fail_msg("bbcgen planes failed: %s", err);
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
  assert_true(num(j, "epsilon_abs") > 0);
  assert_true(num(j, "radius") > 0);
  const cJSON *planes = cJSON_GetObjectItem(j, "planes");
  assert_true(cJSON_GetArraySize(planes) > 0);
  int cardboard = 0;
  const cJSON *p;
  cJSON_ArrayForEach(p, planes) {
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(p, "normal")), 3);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(p, "d")));
    assert_true(cJSON_IsString(cJSON_GetObjectItem(p, "kind")));
    assert_true(num(p, "faces") > 0);
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
  assert_int_equal(run(args, &out, &err), 1);
  assert_non_null(strstr(err, "0.001 to 99"));
  free(out);
  free(err);
}

/* Batch files: the same planes as the flags, errors name file and line. */
static void test_exec_batch(void **state) {
  (void)state;
  char path[1024], args[2048], text[2048];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  snprintf(text, sizeof text,
           "# a comment\nload \"%s\"\nset epsilon 8\nset trunk.cardboard 1\nsplit auto\n"
           "planes \"%s/batch.json\"\n",
           path, tu_dir);
  char *bf = tu_write_file(tu_dir, "job.bbc", text, strlen(text));
  snprintf(args, sizeof args, "exec '%s' -q", bf);
  char *out, *err;
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args,
           "planes '%s' --epsilon 8 --set trunk.cardboard=1 -q --json '%s/flags.json'", path,
           tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  char a[1024], b[1024];
  snprintf(a, sizeof a, "%s/batch.json", tu_dir);
  snprintf(b, sizeof b, "%s/flags.json", tu_dir);
  assert_true(tu_same_file(a, b)); /* byte for byte */
  free(bf);
  bf = tu_write_file(tu_dir, "bad.bbc", "set epsilon 5\nfrobnicate\n", 25);
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(run(args, &out, &err), 1);
  assert_non_null(strstr(err, "bad.bbc:2"));
  free(out);
  free(err);
  free(bf);
}

/* Tree_1's saved cloud in vrml97models/A/... and vrml97models/B/... are the
 * same bytes. */
static void same_saves(const char *a, const char *b) {
  const char *files[] = {"Tree_1.wrl", "Tree_1_wrl_billboards.png", "Tree_1_wrl_billboards.dds"};
  for (int i = 0; i < 3; i++) {
    char fa[2048], fb[2048];
    snprintf(fa, sizeof fa, "%s/vrml97models/%s/Tree_1/Tree_1_e6.00_tex32_pl/%s", tu_dir, a,
             files[i]);
    snprintf(fb, sizeof fb, "%s/vrml97models/%s/Tree_1/Tree_1_e6.00_tex32_pl/%s", tu_dir, b,
             files[i]);
    size_t na, nb;
    unsigned char *ta = tu_read_file(fa, &na), *tb = tu_read_file(fb, &nb);
    if (!ta || !tb) fail_msg("missing %s or %s", fa, fb);
    assert_int_equal(na, nb);
    assert_memory_equal(ta, tb, na);
    free(ta);
    free(tb);
  }
}

/* Batch state (Appendix A's parameter classes): bbc3 after a texturing
 * change keeps steps 1 and 2 and gives the very cloud a full run gives;
 * any other change asks for the steps it needs, naming the parameter. */
static void test_exec_state(void **state) {
  (void)state;
  char path[1024], args[4096], text[4096], cmd[8192];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  snprintf(text, sizeof text, "load \"%s\"\nbbc\nset texres 32\nset quality 0\nbbc3\nsave a\n",
           path);
  char *bf = tu_write_file(tu_dir, "keep.bbc", text, strlen(text));
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' exec '%s' 2>&1", tu_dir, BBC_BIN_DIR, bf);
  FILE *pp = popen(cmd, "r");
  assert_non_null(pp);
  char buf[8192];
  size_t got = fread(buf, 1, sizeof buf - 1, pp);
  buf[got] = 0;
  int st = pclose(pp);
  if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) fail_msg("%s", buf);
  assert_non_null(strstr(buf, "steps 1+2 kept"));
  free(bf);
  snprintf(text, sizeof text, "load \"%s\"\nset texres 32\nset quality 0\nbbc\nsave b\n", path);
  bf = tu_write_file(tu_dir, "full.bbc", text, strlen(text));
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' exec '%s' -q > /dev/null 2>&1", tu_dir,
           BBC_BIN_DIR, bf);
  st = system(cmd);
  assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  free(bf);
  same_saves("a", "b");
  /* bbc2 on the grid of bbc1 after a step-2 change: the cloud of a full run */
  const char *pairs[2][2] = {
      {"c",
       "bbc1\nset punishval 0.5\nset maxplanes 20\nbbc2\nset texres 32\nset quality 0\nbbc3\n"},
      {"d", "set punishval 0.5\nset maxplanes 20\nset texres 32\nset quality 0\nbbc\n"}};
  for (int k = 0; k < 2; k++) {
    snprintf(text, sizeof text, "load \"%s\"\n%ssave %s\n", path, pairs[k][1], pairs[k][0]);
    bf = tu_write_file(tu_dir, "kept.bbc", text, strlen(text));
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' exec '%s' -q > /dev/null 2>&1", tu_dir,
             BBC_BIN_DIR, bf);
    st = system(cmd);
    assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    free(bf);
  }
  same_saves("c", "d");
  /* what a change needs, and commands out of order */
  const char *cases[][3] = {
      {"bbc\nset epsilon 8\nbbc3\n", "epsilon", "run bbc1 and bbc2"},
      {"bbc\nset punishval 0.5\nbbc3\n", "punishval", "run bbc2"},
      {"bbc\nset upaxis z\nbbc3\n", "upaxis", "step 1"},
      {"bbc\nsplit none\nbbc3\n", "split", "bbc1"},
      {"bbc\nset trunk.epsilon 9\nbbc3\n", "trunk.epsilon", "bbc1"},
      {"bbc\nset foliage.punishval 0.3\nbbc3\n", "foliage.punishval", "run bbc2"},
      {"bbc1\nbbc2\nsave x\n", "save needs a Billboard Cloud", ":4:"},
      {"bbc3\n", "bbc3 needs the planes", ":2:"},
      {"bbc2\n", "bbc2 needs the grid of bbc1", ":2:"},
      {"bbc1\nset epsilon 8\nbbc2\n", "epsilon changed since bbc1", "run bbc1"},
      {"bbc1\nset res 10\nbbc2\n", "res changed since bbc1", ":4:"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    snprintf(text, sizeof text, "load \"%s\"\n%s", path, cases[i][0]);
    bf = tu_write_file(tu_dir, "state.bbc", text, strlen(text));
    snprintf(args, sizeof args, "exec '%s' -q", bf);
    assert_int_equal(run(args, &out, &err), 1);
    if (!strstr(err, cases[i][1]) || !strstr(err, cases[i][2])) fail_msg("case %zu: %s", i, err);
    free(out);
    free(err);
    free(bf);
  }
  /* threads and the VRML format change no result, a split as it was changes
   * nothing, a part's texturing parameter needs step 3 only: bbc3 goes on;
   * format and dds set after the steps act on the next save */
  snprintf(text, sizeof text,
           "load \"%s\"\nset texres 16\nbbc\nset threads 1\nset format 1\nset dds 0\nsplit auto\n"
           "set trunk.quality 0\nbbc3\nset format 0\nsave free\n",
           path);
  bf = tu_write_file(tu_dir, "free.bbc", text, strlen(text));
  snprintf(args, sizeof args, "exec '%s' -q", bf);
  assert_int_equal(run_in(args, "", &out, &err), 0); /* in tu_dir: save writes there */
  free(out);
  free(err);
  free(bf);
  char saved[2048];
  snprintf(saved, sizeof saved, "%s/vrml97models/free/Tree_1/Tree_1_e6.00_tex16_pl/Tree_1.wrl",
           tu_dir);
  char *t = (char *)tu_read_file(saved, NULL);
  if (!t) fail_msg("missing %s", saved);
  assert_non_null(strstr(t, "# format 0 (VRML 2.0 with extensions)"));
  assert_null(strstr(t, ".dds"));
  free(t);
  snprintf(saved, sizeof saved,
           "%s/vrml97models/free/Tree_1/Tree_1_e6.00_tex16_pl/Tree_1_wrl_billboards.dds", tu_dir);
  assert_false(tu_have_file(saved));
}

/* The prompt: commands line by line, errors reported and the session goes
 * on; -x runs a batch first; on a terminal, completion. */
static void test_prompt(void **state) {
  (void)state;
  char path[1024], text[4096], args[4096];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  snprintf(text, sizeof text,
           "help bbc3\nload \"%s\"\nbogus\nbbc3\nset texres 16\nbbc\nset quality 0\nbbc3\nsave p\n"
           "bbcload x.wrl\nquit\nsetup\n",
           path);
  /* the session went on after each error; the status is the last failure's
   * (bbcload of a missing file: 2) */
  assert_int_equal(run_in("-i", text, &out, &err), 2);
  assert_non_null(strstr(out, "step 3 on the kept planes"));
  assert_non_null(strstr(err, "'bogus' is not a command"));
  assert_non_null(strstr(err, "bbc3 needs the planes"));
  assert_non_null(strstr(err, "steps 1+2 kept"));
  assert_non_null(strstr(err, "x.wrl")); /* bbcload of a missing file: reported */
  assert_null(strstr(out, "texres"));    /* nothing after quit */
  free(out);
  free(err);
  char wrl[2048];
  snprintf(wrl, sizeof wrl, "%s/vrml97models/p/Tree_1/Tree_1_e6.00_tex16_pl/Tree_1.wrl", tu_dir);
  assert_true(tu_have_file(wrl));
  /* -x: the batch, then the prompt (unless the batch quits) */
  snprintf(text, sizeof text, "load \"%s\"\nset texres 16\n", path);
  char *bf = tu_write_file(tu_dir, "x.bbc", text, strlen(text));
  snprintf(args, sizeof args, "-x '%s'", bf);
  assert_int_equal(run_in(args, "setup\n", &out, &err), 0);
  assert_non_null(strstr(out, "texres         16"));
  free(out);
  free(err);
  free(bf);
  bf = tu_write_file(tu_dir, "xq.bbc", "set texres 16\nquit\n", 19);
  snprintf(args, sizeof args, "-x '%s'", bf);
  assert_int_equal(run_in(args, "setup\n", &out, &err), 0);
  assert_null(strstr(out, "texres"));
  free(out);
  free(err);
  free(bf);
  assert_int_equal(run_in("-x", "", &out, &err), 1);
  assert_non_null(strstr(err, "-x needs a batch file"));
  free(out);
  free(err);
  /* on a terminal (script(1) gives a pseudo-terminal): Tab completes a
   * command and a parameter name */
  char cmd[4096], o[1024];
  snprintf(o, sizeof o, "%s/pty.txt", tu_dir);
  snprintf(cmd, sizeof cmd,
           "(sleep 1; printf 'hel\\t\\n'; sleep 0.5; printf 'set texr\\t 64\\n'; sleep 0.5; "
           "printf 'setup\\n'; sleep 0.5; printf 'quit\\n') | BBCGEN_BIN='%s/bbcgen' timeout 30 "
           "script -qec '\"$BBCGEN_BIN\"' /dev/null > '%s' 2>&1",
           BBC_BIN_DIR, o);
  int st = system(cmd);
  assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  char *pty = (char *)tu_read_file(o, NULL);
  assert_non_null(pty);
  assert_non_null(strstr(pty, "bbcgen> "));
  assert_non_null(strstr(pty, "step 3 on the kept planes")); /* help ran */
  assert_non_null(strstr(pty, "texres         64"));         /* set texr<Tab> 64 */
  free(pty);
}

/* The share of pixels of a PNG that differ from its bottom-right pixel (the
 * background; show bbc's mini-model is top left). */
static double covered(const char *png) {
  bbc_image im;
  bbc_error e;
  if (bbc_image_load(png, &im, &e) != BBC_OK) fail_msg("%s: %s", png, e.message);
  size_t n = (size_t)im.width * im.height, diff = 0;
  for (size_t i = 0; i < n; i++) diff += memcmp(im.rgba + 4 * i, im.rgba + 4 * (n - 1), 3) != 0;
  bbc_image_free(&im);
  return (double)diff / n;
}

/* The viewer: bbcgen view draws each view headless; the prompt's show
 * model opens a window (under xvfb-run) whose scripted arrow keys cycle the
 * views and Esc returns to the prompt. Every view differs and none is blank. */
static void test_viewer(void **state) {
  (void)state;
  char path[1024], args[4096], text[4096];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  const char *modes[] = {"input",      "rects", "cloud-rects", "cloud", "domain",
                         "continuous", "both",  "density",     "faces"};
  unsigned char *img[9];
  size_t len[9];
  for (int m = 0; m < 9; m++) {
    snprintf(args, sizeof args, "view '%s' --mode %s --size 96 --texres 32 -q --screenshot v%d.png",
             path, modes[m], m);
    /* The ASan build: GCC 12's LeakSanitizer crashes at exit on the dynamic
     * TLS that Mesa's libEGL_mesa (loaded by libglvnd) leaves in the main
     * thread ("Tracer caught signal 11"; in the input view only, and only
     * in some builds' memory layouts), so that one run goes without the
     * leak check; the other eight views, which run the same code and more,
     * keep it. */
    const char *asan = getenv("ASAN_OPTIONS");
    char *saved = asan ? strdup(asan) : NULL;
    if (m == 0) {
      char opts[1024];
      snprintf(opts, sizeof opts, "%s%sdetect_leaks=0", asan ? asan : "", asan ? ":" : "");
      setenv("ASAN_OPTIONS", opts, 1);
    }
    int rc = run_in(args, "", &out, &err);
    if (m == 0) {
      if (saved)
        setenv("ASAN_OPTIONS", saved, 1);
      else
        unsetenv("ASAN_OPTIONS");
    }
    free(saved);
    if (rc == 6 && !getenv("CI")) { /* no OpenGL here (never under CI) */
      fprintf(stderr, "no OpenGL: viewer test skipped: %s\n", err);
      free(out);
      free(err);
      skip();
    }
    if (rc) fail_msg("view %s: %s", modes[m], err);
    free(out);
    free(err);
    char p[1200];
    snprintf(p, sizeof p, "%s/v%d.png", tu_dir, m);
    double c = covered(p);
    if (c < 0.02 || c > 0.9) fail_msg("view %s: %.3f of the pixels covered", modes[m], c);
    img[m] = tu_read_file(p, &len[m]);
    assert_non_null(img[m]);
  }
  for (int a = 0; a < 9; a++)
    for (int b = a + 1; b < 9; b++)
      assert_false(len[a] == len[b] && !memcmp(img[a], img[b], len[a]));
  for (int m = 0; m < 9; m++) free(img[m]);
  /* the selection: a face out of range, an unknown part, one vertex's domain */
  snprintf(args, sizeof args, "view '%s' --mode domain --face 99999 --screenshot f.png", path);
  assert_int_equal(run_in(args, "", &out, &err), 1);
  assert_non_null(strstr(err, "--face 99999: part foliage has"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "view '%s' --mode domain --part twig --screenshot f.png", path);
  assert_int_equal(run_in(args, "", &out, &err), 1);
  assert_non_null(strstr(err, "parts are trunk and foliage"));
  free(out);
  free(err);
  snprintf(args, sizeof args,
           "view '%s' --mode continuous --part trunk --face 3 --vertex 2 --size 96 --screenshot "
           "f.png --limbs 0",
           path);
  assert_int_equal(run_in(args, "", &out, &err), 0);
  assert_non_null(strstr(err, "part trunk, face 3"));
  free(out);
  free(err);
  /* by default the trunk part is a mesh (limbs): said, not drawn from nothing */
  snprintf(args, sizeof args, "view '%s' --mode domain --part trunk --screenshot f.png", path);
  assert_int_equal(run_in(args, "", &out, &err), 1);
  assert_non_null(strstr(err, "kept as a mesh (limbs)"));
  free(out);
  free(err);
  assert_int_equal(run_in("view x.obj --mode sideways --screenshot a.png", "", &out, &err), 1);
  assert_non_null(strstr(err, "--mode sideways: expected"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "view '%s' --screenshot a.jpg", path);
  assert_int_equal(run_in(args, "", &out, &err), 1);
  assert_non_null(strstr(err, ".png"));
  free(out);
  free(err);
  /* show model in a window, driven from the prompt */
  if (system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    if (getenv("CI")) fail_msg("xvfb-run is missing (scripts/dev/setup.sh test installs it)");
    fprintf(stderr, "xvfb-run is not installed: window test skipped\n");
    skip();
  }
  snprintf(text, sizeof text,
           "load \"%s\"\nset texres 32\nbbc\nsave s\nshow model shot:s0.png,left,shot:s1.png,right,"
           "right,shot:s2.png,right,shot:s3.png,esc\n"
           "show bbc shot:s4.png,down,shot:s5.png,f6,shot:s6.png,down,shot:s7.png,down,"
           "shot:s8.png,right,shot:s9.png,down,esc\n"
           "show model f2,shot:s10.png,f2,f10,shot:s11.png,esc\n"
           "bbcload vrml97models/s/Tree_1/Tree_1_e6.00_tex32_pl/Tree_1.wrl\n"
           "show model right,right,shot:l3.png,esc\nbbcload nosuch.wrl\n"
           "set texres 16\nsetup\nquit\n",
           path);
  /* without a display show model says so and the session goes on (the
   * status: the last failure, bbcload of a missing file) */
  if (!getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
    assert_int_equal(run_in("-i", text, &out, &err), 2);
    assert_non_null(strstr(err, "show: no display"));
    assert_non_null(strstr(out, "texres         16"));
    free(out);
    free(err);
  }
  char o[1024], e[1024], sf[1024], cmd[8192];
  snprintf(o, sizeof o, "%s/win_out.txt", tu_dir);
  snprintf(e, sizeof e, "%s/win_err.txt", tu_dir);
  snprintf(sf, sizeof sf, "%s/win_status.txt", tu_dir);
  char *in = tu_write_file(tu_dir, "win.txt", text, strlen(text));
  /* the prompt on a pseudo-terminal (script(1)), as a person types it; its
   * exit status is written by the shell inside xvfb-run, so that
   * xvfb-run's own troubles (it can fail to clean up its temporary folder
   * when other tests run it at the same time) are told apart */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && BBCGEN_BIN='%s/bbcgen' TMPDIR=/tmp timeout 180 xvfb-run -a -s '-screen 0 "
           "1024x768x24' sh "
           "-c \"script -qec '\\\"\\$BBCGEN_BIN\\\"' /dev/null < '%s' > '%s' 2> '%s'; echo \\$? > "
           "'%s'\" 2> xvfb_err.txt",
           tu_dir, BBC_BIN_DIR, in, o, e, sf);
  free(in);
  int xst = system(cmd);
  char *so = (char *)tu_read_file(o, NULL);
  char *status = (char *)tu_read_file(sf, NULL);
  int st = status ? atoi(status) : -1;
  free(status);
  /* 2: the last failure, bbcload nosuch.wrl; everything before it worked */
  if (st != 2) {
    char *se = (char *)tu_read_file(e, NULL);
    size_t n = so ? strlen(so) : 0;
    fprintf(stderr, "show: exit %d (xvfb-run %d); its output's end:\n%s\nstderr:\n%s\n", st,
            WIFEXITED(xst) ? WEXITSTATUS(xst) : -1, so ? so + (n > 3000 ? n - 3000 : 0) : "",
            se ? se : "");
    free(se);
    fail_msg("show: exit %d, not 2", st);
  }
  assert_non_null(so);
  assert_non_null(strstr(so, "bbcgen> "));
  assert_non_null(strstr(so, "show bbc: faces, part foliage")); /* down x 4 */
  assert_non_null(strstr(so, "texres         16"));             /* back at the prompt after Esc */
  assert_non_null(strstr(so, "nosuch.wrl"));
  free(so);
  /* bbcload: the saved cloud shown in place of the cloud; a missing file is
   * reported and the session goes on */
  char lp[1200];
  snprintf(lp, sizeof lp, "%s/l3.png", tu_dir);
  assert_true(covered(lp) > 0.01);
  /* show model's four views, then show bbc's: domain, continuous, its third
   * vertex's (F6), both, density, another face's density */
  for (int m = 0; m < 10; m++) {
    char p[1200];
    snprintf(p, sizeof p, "%s/s%d.png", tu_dir, m);
    double c = covered(p);
    if (c < 0.01) fail_msg("show view %d is blank", m);
    size_t n;
    unsigned char *im = tu_read_file(p, &n);
    if (m < 9) {
      img[m] = im;
      len[m] = n;
    } else {
      free(im);
    }
  }
  for (int a = 0; a < 9; a++)
    for (int b = a + 1; b < 9; b++)
      assert_false(len[a] == len[b] && !memcmp(img[a], img[b], len[a]));
  /* F2 (vertex domains) and F10 (shadow voxels) over the rectangles view */
  for (int m = 10; m < 12; m++) {
    char p[1200];
    snprintf(p, sizeof p, "%s/s%d.png", tu_dir, m);
    size_t n;
    unsigned char *im = tu_read_file(p, &n);
    if (!im) fail_msg("show model F%d: no picture", m == 10 ? 2 : 10);
    assert_false(n == len[0] && !memcmp(im, img[0], n));
    free(im);
  }
  for (int m = 0; m < 9; m++) free(img[m]);
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
    if (run_in(args, "", &out, &err)) fail_msg("%s", err);
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
  assert_int_equal(run_in("sample x.obj -o y.txt", "", &out, &err), 1);
  assert_non_null(strstr(err, "usage"));
  free(out);
  free(err);
}

/* Every command's errors in a batch file: the message names file:line and
 * the batch stops with a non-zero status. */
static void test_exec_errors(void **state) {
  (void)state;
  char path[1024], args[4096], text[8192];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  const char *cases[][3] = {
      /* {lines after an optional load ("L" = load first), expected text, "L" or ""} */
      {"load\n", "load needs an argument", ""},
      {"load /no/such/tree.obj\n", "no such file", ""},
      {"load @ nocache\n", "'nocache' is not a flag", ""},
      {"set epsilon\n", "set needs NAME VALUE", ""},
      {"set epslon 5\n", "did you mean epsilon", ""},
      {"set epsilon 500\n", "epsilon", ""},
      {"set trunk.res 7\n", "res", ""},
      {"split sideways\n", "split must be auto", ""},
      {"split auto extra\n", "split takes one word", ""},
      {"load @ nocg bogus\n", "is not a flag", ""},
      {"split trunk=\n", "needs patterns", ""},
      {"bbc1\n", "bbc1 before load", ""},
      {"bbc2\n", "bbc2 before load", ""},
      {"bbc3\n", "bbc3 before load", ""},
      {"bbc\n", "bbc before load", ""},
      {"planes\n", "planes before load", ""},
      {"shade many\n", "shade NUMVOXELS", ""},
      {"shade 40 3\n", "ambient 0..1", ""},
      {"save\n", "save needs a Billboard Cloud", "L"},
      {"exec\n", "exec needs an argument", ""},
      {"exec /no/such.bbc\n", "cannot open batch file", ""},
      {"help frobnicate\n", "no command 'frobnicate'", ""},
      {"show\n", "needs model or bbc", ""},
      {"show sideways\n", "expected show model or show bbc", "L"},
      {"show model\n", "show before load", ""},
      {"show bbc\n", "show bbc needs the grid", "L"},
      {"bbcload\n", "bbcload needs an argument", ""},
      {"bbcload /no/such/cloud.wrl\n", "no such file", ""},
      {"frobnicate\n", "'frobnicate' is not a command", ""},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char body[2048]; /* @ = the model */
    const char *at = strchr(cases[i][0], '@');
    if (at)
      snprintf(body, sizeof body, "%.*s\"%s\"%s", (int)(at - cases[i][0]), cases[i][0], path,
               at + 1);
    else
      snprintf(body, sizeof body, "%s", cases[i][0]);
    int line = cases[i][2][0] ? 2 : 1;
    if (cases[i][2][0])
      snprintf(text, sizeof text, "load \"%s\"\n%snext\n", path, body);
    else
      snprintf(text, sizeof text, "%snext\n", body);
    char *bf = tu_write_file(tu_dir, "err.bbc", text, strlen(text));
    snprintf(args, sizeof args, "exec '%s' -q", bf);
    char *out, *err;
    int rc = run_in(args, "", &out, &err);
    char where[64];
    snprintf(where, sizeof where, "err.bbc:%d:", line);
    if (rc == 0 || !strstr(err, cases[i][1]) || !strstr(err, where) || strstr(err, "'next'"))
      fail_msg("case %zu (%s): rc %d: %s", i, cases[i][0], rc, err);
    free(out);
    free(err);
    free(bf);
  }
  /* load ... nomip: the model's textures at full resolution in the bake */
  char tex[1024];
  tu_data_path(tex, sizeof tex, "trees/eztree/oak_medium.obj");
  if (tu_have_file(tex)) {
    const char *flags[2] = {"", " nocg nomip"};
    for (int k = 0; k < 2; k++) {
      snprintf(text, sizeof text, "load \"%s\"%s\nset texres 32\nbbc\nsave m%d\n", tex, flags[k],
               k);
      char *mf = tu_write_file(tu_dir, "mip.bbc", text, strlen(text));
      snprintf(args, sizeof args, "exec '%s' -q", mf);
      char *o2, *e2;
      if (run_in(args, "", &o2, &e2)) fail_msg("nomip: %s", e2);
      free(o2);
      free(e2);
      free(mf);
    }
    char pa[2048], pb[2048];
    snprintf(pa, sizeof pa, "%s/vrml97models/m0/oak_medium/oak_medium_e6.00_tex32_pl/%s", tu_dir,
             "oak_medium_wrl_billboards.png");
    snprintf(pb, sizeof pb, "%s/vrml97models/m1/oak_medium/oak_medium_e6.00_tex32_pl/%s", tu_dir,
             "oak_medium_wrl_billboards.png");
    size_t na, nb;
    unsigned char *ta = tu_read_file(pa, &na), *tb = tu_read_file(pb, &nb);
    if (!ta || !tb) fail_msg("missing %s or %s", pa, pb);
    assert_false(na == nb && !memcmp(ta, tb, na)); /* other texture colours */
    free(ta);
    free(tb);
  }
  /* exec of itself: the depth limit */
  snprintf(text, sizeof text, "exec \"%s/self.bbc\"\n", tu_dir);
  char *bf = tu_write_file(tu_dir, "self.bbc", text, strlen(text));
  snprintf(args, sizeof args, "exec '%s' -q", bf);
  char *out, *err;
  assert_int_not_equal(run_in(args, "", &out, &err), 0);
  assert_non_null(strstr(err, "nested more than 8 deep"));
  free(out);
  free(err);
  free(bf);
}

/* The debug levels: step 2 opens a window per pick (1) and per greedy step
 * (2) as it runs; End goes on without more of them. */
static void test_debug_views(void **state) {
  (void)state;
  char path[1024], text[4096], cmd[8192], o[1024];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  if (system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    if (getenv("CI")) fail_msg("xvfb-run is missing (scripts/dev/setup.sh test installs it)");
    skip();
  }
  snprintf(text, sizeof text, "load \"%s\"\nset debug 1\nbbc1\nbbc2\nset debug 2\nbbc\nquit\n",
           path);
  char *bf = tu_write_file(tu_dir, "debug.bbc", text, strlen(text));
  snprintf(o, sizeof o, "%s/debug_out.txt", tu_dir);
  /* bbc2 shows every pick (a picture each); bbc's first window ends them */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && BBCGEN_DEBUG_KEYS='shot:dbg%%d.png,esc' TMPDIR=/tmp timeout 180 xvfb-run -a "
           "-s '-screen "
           "0 800x600x24' '%s/bbcgen' -x '%s' > '%s' 2>&1",
           tu_dir, BBC_BIN_DIR, bf, o);
  int st = system(cmd);
  char *so = (char *)tu_read_file(o, NULL);
  if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) fail_msg("debug: %s", so ? so : "");
  int picks = 0;
  for (const char *p = so; (p = strstr(p, "plane picked")); p++) picks++;
  assert_true(picks >= 20); /* Tree_1: 32 planes and more picks before merging */
  assert_non_null(strstr(so, "greedy step"));
  for (int i = 1; i <= picks; i++) {
    char png[1200];
    snprintf(png, sizeof png, "%s/dbg%d.png", tu_dir, i);
    if (covered(png) < 0.005) fail_msg("debug view %d missing or blank", i);
  }
  free(so);
  /* End: the first window of a step is its last */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && BBCGEN_DEBUG_KEYS='end' TMPDIR=/tmp timeout 180 xvfb-run -a '%s/bbcgen' -x "
           "'%s' > '%s' "
           "2>&1",
           tu_dir, BBC_BIN_DIR, bf, o);
  st = system(cmd);
  so = (char *)tu_read_file(o, NULL);
  if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) fail_msg("debug: %s", so ? so : "");
  int views = 0;
  for (const char *p = so; (p = strstr(p, "(view ")); p++) views++;
  assert_int_equal(views, 2); /* one for bbc2, one for bbc */
  free(so);
  free(bf);
}

/* bbcgen MODEL -o OUT: option errors before any work; batch bbc/shade/save
 * write the thesis's VRML folder. */
static void test_cloud_command(void **state) {
  (void)state;
  char path[1024], args[4096], text[2048];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  const char *bad[][3] = {
      {"--lod 10,5", "1", "must increase"},
      {"--lod 5,abc", "1", "not a list"},
      {"--preview p.jpg", "1", ".png"},
      {"--report r.txt", "1", ".json"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/t.glb' %s", path, tu_dir, bad[i][0]);
    assert_int_equal(run(args, &out, &err), atoi(bad[i][1]));
    if (!strstr(err, bad[i][2])) fail_msg("%s: %s", bad[i][0], err);
    free(out);
    free(err);
  }
  snprintf(args, sizeof args, "'%s' -o '%s/no/such/t.glb'", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 5);
  assert_non_null(strstr(err, "does not exist"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "'%s' -o '%s/t.png'", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 1);
  free(out);
  free(err);
  /* Extensions in capitals are the same formats (a Windows user's T.GLB). */
  snprintf(args, sizeof args, "'%s' -o '%s/UP.GLB' --preview '%s/UP.PNG' -q", path, tu_dir, tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "'%s' -o '%s/UP.OBJ' -q", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  /* A space in an OBJ's name stays out of the names mtllib and map_Kd
   * give: they split at spaces. */
  snprintf(args, sizeof args, "'%s' -o '%s/my tree.obj' -q", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "%s/my tree.obj", tu_dir);
  char *obj = (char *)tu_read_file(args, NULL);
  assert_non_null(obj);
  assert_non_null(strstr(obj, "\nmtllib my_tree.mtl\n"));
  free(obj);
  snprintf(args, sizeof args, "%s/my_tree.mtl", tu_dir);
  char *mtl = (char *)tu_read_file(args, NULL);
  assert_non_null(mtl);
  assert_non_null(strstr(mtl, "\nmap_Kd my_tree_obj_billboards.png\n"));
  free(mtl);
  const char *made[] = {"UP.GLB",
                        "UP.PNG",
                        "UP.OBJ",
                        "UP.mtl",
                        "UP_OBJ_billboards.png",
                        "my_tree_obj_billboards.png"};
  for (size_t i = 0; i < sizeof made / sizeof made[0]; i++) {
    char f[1200];
    snprintf(f, sizeof f, "%s/%s", tu_dir, made[i]);
    if (!tu_have_file(f)) fail_msg("%s not written", made[i]);
  }
  /* An output that is a folder is refused before any work; a point cloud
   * makes a cloud (thesis 2.4) the Khronos validator passes; a folder is no
   * batch file (exit 2); an unknown baseline method is a usage error. */
  char folder[1200];
  snprintf(folder, sizeof folder, "%s/folder.glb", tu_dir);
  assert_int_equal(mkdir(folder, 0777), 0);
  snprintf(args, sizeof args, "'%s' -o '%s'", path, folder);
  assert_int_equal(run(args, &out, &err), 5);
  rmdir(folder);
  assert_non_null(strstr(err, "is a folder"));
  free(out);
  free(err);
  char pts[1024];
  tu_data_path(pts, sizeof pts, "points/b9_training.ply");
  if (tu_have_file(pts)) {
    snprintf(args, sizeof args, "'%s' -o '%s/p.glb' -q", pts, tu_dir);
    if (run(args, &out, &err)) fail_msg("%s", err);
    free(out);
    free(err);
    char glb[1200];
    snprintf(glb, sizeof glb, "%s/p.glb", tu_dir);
    int v = tu_gltf_validate(glb);
    if (v == 3 && getenv("CI")) fail_msg("the glTF validator is unavailable");
    if (v != 3) assert_int_equal(v, 0);
  }
  snprintf(args, sizeof args, "exec '%s'", tu_dir);
  assert_int_equal(run(args, &out, &err), 2);
  free(out);
  free(err);
  snprintf(args, sizeof args, "baseline '%s' -o '%s/b.glb' --method foo", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 1);
  assert_non_null(strstr(err, "foo"));
  free(out);
  free(err);
  /* eval: side-view figures are null when no view is a side view. */
  snprintf(args, sizeof args,
           "eval '%s' '%s' --views 2 --side-elevation 10 --size 16 --json '%s/e.json'", path, path,
           tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  assert_non_null(strstr(out, "side n/a"));
  free(out);
  free(err);
  char ej[1200];
  snprintf(ej, sizeof ej, "%s/e.json", tu_dir);
  char *etext = (char *)tu_read_file(ej, NULL);
  cJSON *e = cJSON_Parse(etext);
  assert_non_null(e);
  assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(e, "iou_side_mean")));
  assert_true(cJSON_GetObjectItemCaseSensitive(e, "iou_mean")->valuedouble == 1.0);
  cJSON_Delete(e);
  free(etext);
  /* Batch: bbc3 needs bbc2; bbc then save writes the Appendix A folder. */
  snprintf(text, sizeof text, "load \"%s\"\nbbc3\n", path);
  char *bf = tu_write_file(tu_dir, "c3.bbc", text, strlen(text));
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(run(args, &out, &err), 1);
  assert_non_null(strstr(err, "bbc3 needs the planes of bbc2"));
  free(out);
  free(err);
  free(bf);
  /* load reads the model at once: a missing one is named at its line */
  bf = tu_write_file(tu_dir, "nomodel.bbc", "load /no/such/x.obj\nbbc\n", 25);
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(run(args, &out, &err), 2);
  assert_non_null(strstr(err, "x.obj"));
  free(out);
  free(err);
  free(bf);
  snprintf(text, sizeof text, "load \"%s\"\nset texres 32\nshade 20 0.5\nbbc\nsave forest\n", path);
  bf = tu_write_file(tu_dir, "save.bbc", text, strlen(text));
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' exec '%s' -q > /dev/null 2>&1", tu_dir,
           BBC_BIN_DIR, bf);
  int st = system(cmd);
  assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  char wrl[2048], png[2048];
  snprintf(wrl, sizeof wrl, "%s/vrml97models/forest/Tree_1/Tree_1_e6.00_tex32_pl/Tree_1.wrl",
           tu_dir);
  snprintf(png, sizeof png,
           "%s/vrml97models/forest/Tree_1/Tree_1_e6.00_tex32_pl/Tree_1_wrl_billboards.png", tu_dir);
  size_t n;
  unsigned char *w = tu_read_file(wrl, &n), *p = tu_read_file(png, NULL);
  assert_non_null(w);
  assert_non_null(p);
  assert_true(n > 100 && !memcmp(w, "#VRML V2.0 utf8", 15));
  free(w);
  free(p);
  free(bf);
}

/* Reads a .glb's JSON chunk. */
static cJSON *glb_json(const char *path) {
  size_t n = 0;
  unsigned char *g = tu_read_file(path, &n);
  if (!g || n < 20) fail_msg("%s: not read", path);
  uint32_t jl =
      (uint32_t)g[12] | (uint32_t)g[13] << 8 | (uint32_t)g[14] << 16 | (uint32_t)g[15] << 24;
  cJSON *j = cJSON_ParseWithLength((const char *)g + 20, jl);
  free(g);
  if (!j) fail_msg("%s: JSON chunk not parsed", path);
  return j;
}

static int file_exists(const char *dir, const char *name) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return access(p, F_OK) == 0;
}

/* An epsilon typed by hand is kept; maxplanes moves only the default, and
 * the report says when it did. A generated bush needs more than 8 planes at
 * epsilon 3. */
static void test_hand_epsilon_kept(void **state) {
  (void)state;
  char args[4096], *out, *err;
  snprintf(args, sizeof args, "tree --species bush --leaves 600 --seed 3 -o '%s/eb.obj'", tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  const char *cases[][3] = {
      /* options, epsilon used (0: more than asked), adjusted_by */
      {"--epsilon 3 --texres 32", "3", ""},
      {"--set epsilon=3 --texres 32", "3", ""},
      {"--epsilon 3 --maxplanes 8 --texres 32", "0", "maxplanes"},
      {"--maxplanes 8 --epsilon 3 --texres 32", "0", "maxplanes"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    snprintf(args, sizeof args, "'%s/eb.obj' -o '%s/eb.glb' --report '%s/eb.json' %s", tu_dir,
             tu_dir, tu_dir, cases[i][0]);
    assert_int_equal(run(args, &out, &err), 0);
    free(out);
    char rp[1200];
    snprintf(rp, sizeof rp, "%s/eb.json", tu_dir);
    char *text = (char *)tu_read_file(rp, NULL);
    cJSON *r = cJSON_Parse(text);
    assert_non_null(r);
    const cJSON *lod = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(r, "lods"), 0);
    double used = num(lod, "epsilon_pct_used");
    const cJSON *by = cJSON_GetObjectItemCaseSensitive(lod, "epsilon_adjusted_by");
    if (cases[i][2][0]) {
      assert_true(used > 3.0);
      assert_true(cJSON_IsString(by) && !strcmp(by->valuestring, cases[i][2]));
      assert_true(num(lod, "planes") <= 8);
      /* The info line says what moved it. */
      if (!strstr(err, "raised from 3 % by maxplanes 8")) fail_msg("%s", err);
    } else {
      assert_true(used == 3.0);
      assert_true(cJSON_IsString(by) && !strcmp(by->valuestring, "none"));
      assert_true(num(lod, "planes") > 8);
    }
    /* The glTF node's extras state the epsilon used. */
    snprintf(rp, sizeof rp, "%s/eb.glb", tu_dir);
    cJSON *g = glb_json(rp);
    const cJSON *ex = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(g, "nodes"), 0), "extras");
    assert_true(num(ex, "epsilon_pct_used") == used);
    cJSON_Delete(g);
    cJSON_Delete(r);
    free(text);
    free(err);
  }
  /* VRML: the header gives the epsilon used and why. */
  snprintf(args, sizeof args, "'%s/eb.obj' -o '%s/eb.wrl' --epsilon 3 --maxplanes 8 --texres 32",
           tu_dir, tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  char wp[1200];
  snprintf(wp, sizeof wp, "%s/eb.wrl", tu_dir);
  char *w = (char *)tu_read_file(wp, NULL);
  assert_non_null(w);
  assert_non_null(strstr(w, "(raised from 3 % by maxplanes 8)"));
  assert_null(strstr(w, "# epsilon: 3 %"));
  free(w);
}

/* Unknown options and commands: named, with the nearest suggestion. */
static void test_suggestions(void **state) {
  (void)state;
  const char *cases[][3] = {
      {"x.obj -o x.glb --epslon 6", "did you mean --epsilon?", "1"},
      {"infoo x.obj", "unknown command 'infoo' (did you mean bbcgen info?)", "1"},
      {"plane x.obj", "did you mean bbcgen planes?", "1"},
      {"eval a.obj b.glb --jsn x", "eval: unknown option '--jsn' (did you mean --json?)", "1"},
      {"tree --specis oak -o t.obj", "did you mean --species?", "1"},
      {"x.obj -o x.glb --prev p.png", "did you mean --preview?", "1"},
      {"--verison", "did you mean --version?", "1"},
      {"x.obj -o x.glb --zzzzzz 1", "unknown option '--zzzzzz' (try bbcgen --help)", "1"},
      {"frobnicate", "unknown command 'frobnicate'", "1"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char *out, *err;
    assert_int_equal(run(cases[i][0], &out, &err), atoi(cases[i][2]));
    if (!strstr(err, cases[i][1])) fail_msg("bbcgen %s: '%s'", cases[i][0], err);
    free(out);
    free(err);
  }
  /* Every command answers --help (it used to be "unknown option '--help'
   * (did you mean --help?)"). */
  /* Each with its own part of the help (the cloud: all of it). */
  const char *helps[][3] = {
      {"tree --help", "larch", "eval ORIGINAL"}, {"eval --help", "side-elevation", "larch"},
      {"info -h", "--no-textures", "larch"},     {"render --help", "Software render", "larch"},
      {"planes --help", "epsilon", "larch"},     {"baseline --help", "crossed", "larch"},
      {"x.obj -o x.glb --help", "larch", NULL}};
  for (size_t i = 0; i < sizeof helps / sizeof helps[0]; i++) {
    char *out, *err;
    assert_int_equal(run(helps[i][0], &out, &err), 0);
    if (!strstr(out, "Usage:") || !strstr(out, helps[i][1]) || !strstr(out, "Exit codes") ||
        (helps[i][2] && strstr(out, helps[i][2])))
      fail_msg("bbcgen %s: '%s'", helps[i][0], out);
    free(out);
    free(err);
  }
}

/* Materials and texture files: prelit clouds are unlit in every format
 * (KHR_materials_unlit, VRML without Material, MTL illum 0), relightable
 * ones lit; texture files are <stem>_<material>[_nm].png in all three. */
/* atlasmax: the largest texres whose images the packer fits, not the one
 * that fills 70 % (the ez-tree oak at epsilon 5: 128 fills 79 % of one
 * 1024 x 1024 atlas, where the 70 % rule took 64). */
/* A part's parameters for a part the model does not have are said. */
static void test_unknown_part(void **state) {
  (void)state;
  char path[1024], args[4096];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "planes '%s' --set bogus.epsilon=8", path);
  char *out, *err;
  assert_int_equal(run(args, &out, &err), 0);
  if (!strstr(err, "parameters for part 'bogus' are not used")) fail_msg("%s", err);
  free(out);
  free(err);
}

static void test_atlas_budget(void **state) {
  (void)state;
  char path[1024], args[4096];
  tu_data_path(path, sizeof path, "trees/eztree/oak_medium.obj");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "'%s' -o '%s/ab.glb' --epsilon 5 --report '%s/ab.json' -q", path,
           tu_dir, tu_dir);
  char *out, *err;
  assert_int_equal(run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(path, sizeof path, "%s/ab.json", tu_dir);
  char *t = (char *)tu_read_file(path, NULL);
  assert_non_null(t);
  cJSON *j = cJSON_Parse(t);
  const cJSON *l = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "lods"), 0);
  int texres = cJSON_GetObjectItemCaseSensitive(l, "texres_used")->valueint;
  double fill = cJSON_GetObjectItemCaseSensitive(l, "atlas_fill")->valuedouble;
  double texels = cJSON_GetObjectItemCaseSensitive(l, "texels")->valuedouble;
  if (texres != 128 || fill < 0.7 || texels / fill > 1024.0 * 1024.0 + 0.5)
    fail_msg("texres %d, atlas fill %.3f, %.0f texels", texres, fill, texels);
  cJSON_Delete(j);
  free(t);
}

static void test_materials_and_texture_names(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *dir = tu_make_temp_dir();
  /* glTF: lit materials by default, VRML and OBJ baked. */
  const char *runs[][2] = {{"u.glb", "--lighting baked"},
                           {"l.glb", ""},
                           {"f.glb", "--lighting baked --unlit 0"},
                           {"u.gltf", "--lighting baked --nm 1"},
                           {"u.wrl", "--nm 1"},
                           {"l.wrl", "--prelight 0"},
                           {"u.obj", ""},
                           {"l.obj", "--prelight 0"},
                           {"m.gltf", "--lighting material"}};
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/%s' --texres 32 -q %s", path, dir, runs[i][0],
             runs[i][1]);
    assert_int_equal(run(args, &out, &err), 0);
    free(out);
    free(err);
  }
  char p[2048];
  for (int k = 0; k < 3; k++) {
    const char *names[3] = {"u.glb", "l.glb", "f.glb"};
    snprintf(p, sizeof p, "%s/%s", dir, names[k]);
    cJSON *g = glb_json(p);
    const cJSON *mat = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(g, "materials"), 0);
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(mat, "extensions");
    int unlit = ext && cJSON_GetObjectItemCaseSensitive(ext, "KHR_materials_unlit");
    assert_int_equal(unlit, k == 0);
    if (k == 1) {
      assert_non_null(cJSON_GetObjectItemCaseSensitive(mat, "normalTexture"));
      assert_non_null(cJSON_GetObjectItemCaseSensitive(mat, "occlusionTexture"));
    } else {
      assert_null(cJSON_GetObjectItemCaseSensitive(mat, "occlusionTexture"));
    }
    cJSON_Delete(g);
    int v = tu_gltf_validate(p);
    if (v != 3) assert_int_equal(v, 0);
  }
  /* Each output its own side files, though u.gltf, u.wrl and u.obj share a
   * folder and a stem. */
  assert_true(file_exists(dir, "u_gltf_billboards.png") &&
              file_exists(dir, "u_obj_billboards.png"));
  assert_true(file_exists(dir, "u_gltf_billboards_nm.png") &&
              file_exists(dir, "u_wrl_billboards_nm.png"));
  assert_true(file_exists(dir, "l_wrl_billboards.png") && file_exists(dir, "l_obj_billboards.png"));
  assert_false(file_exists(dir, "u_billboards.png"));
  assert_true(file_exists(dir, "u.mtl") && file_exists(dir, "l.mtl"));
  snprintf(p, sizeof p, "%s/u.gltf", dir);
  char *t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "\"uri\":\"u_gltf_billboards.png\""));
  assert_non_null(strstr(t, "\"uri\":\"u_gltf_billboards_nm.png\""));
  free(t);
  assert_true(file_exists(dir, "m_gltf_billboards_nm.png") &&
              file_exists(dir, "m_gltf_billboards_ao.png"));
  snprintf(p, sizeof p, "%s/u.wrl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_null(strstr(t, "Material {"));
  /* the DDS with the atlas's mip levels first, the PNG for other readers */
  assert_non_null(strstr(t, "url [ \"u_wrl_billboards.dds\" \"u_wrl_billboards.png\" ]"));
  assert_true(file_exists(dir, "u_wrl_billboards.dds"));
  free(t);
  snprintf(p, sizeof p, "%s/l.wrl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "Material { diffuseColor 1 1 1 }"));
  free(t);
  snprintf(p, sizeof p, "%s/u.mtl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "illum 0"));
  assert_non_null(strstr(t, "map_Kd u_obj_billboards.png"));
  free(t);
  snprintf(p, sizeof p, "%s/l.mtl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_null(strstr(t, "illum 0"));
  free(t);
  /* Read back, the unlit flag survives (and eval --lit lights only the
   * original then). */
  snprintf(args, sizeof args, "info --json '%s/u.glb'", dir);
  assert_int_equal(run(args, &out, &err), 0);
  assert_non_null(strstr(out, "\"unlit\":\ttrue"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "info --json '%s/l.glb'", dir);
  assert_int_equal(run(args, &out, &err), 0);
  assert_non_null(strstr(out, "\"unlit\":\tfalse"));
  free(out);
  free(err);
  tu_remove_dir(dir);
  free(dir);
}

/* Lit once: a baked (prelit, unlit material) cloud and a relightable one
 * look as bright
 * as the original, per channel within 10 %, lit (the original lit by the
 * same light; the prelit cloud shown as baked, its material being unlit)
 * and unlit. */
static void test_brightness(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_3.obj");
  if (!tu_have_file(path)) skip();
  const char *runs[][3] = {
      /* cloud options, eval options, 1 = must match */
      {"--lighting baked", "--lit", "1"},
      {"--lighting baked", "", "1"},
      /* A relightable cloud's one material has no Ka of its own: compared
       * lit, without the fixed-function ambient (Tree_3's MTL says Ka 1). */
      {"--prelight 0", "--lit --ambient 0", "1"},
      {"--prelight 0", "", "1"},
  };
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/br.glb' --texres 64 -q %s", path, tu_dir, runs[i][0]);
    assert_int_equal(run(args, &out, &err), 0);
    free(out);
    free(err);
    snprintf(args, sizeof args,
             "eval '%s' '%s/br.glb' --views 16 --size 128 --json '%s/br.json' %s", path, tu_dir,
             tu_dir, runs[i][1]);
    assert_int_equal(run(args, &out, &err), 0);
    free(out);
    free(err);
    char jp[1200];
    snprintf(jp, sizeof jp, "%s/br.json", tu_dir);
    char *text = (char *)tu_read_file(jp, NULL);
    cJSON *j = cJSON_Parse(text);
    assert_non_null(j);
    /* eval lights the original by itself when the cloud is prelit. */
    int want_lit = strstr(runs[i][1], "--lit") ||
                   (!strstr(runs[i][0], "--prelight 0") && !strstr(runs[i][1], "--no-lit"));
    assert_int_equal(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(j, "lit")), want_lit);
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(j, "brightness_ratio");
    assert_int_equal(cJSON_GetArraySize(b), 3);
    int within = 1;
    for (int c = 0; c < 3; c++) {
      double v = cJSON_GetArrayItem(b, c)->valuedouble;
      within &= v > 0.9 && v < 1.1;
    }
    if (within != atoi(runs[i][2]))
      fail_msg("cloud %s, eval %s: brightness %.3f %.3f %.3f", runs[i][0], runs[i][1],
               cJSON_GetArrayItem(b, 0)->valuedouble, cJSON_GetArrayItem(b, 1)->valuedouble,
               cJSON_GetArrayItem(b, 2)->valuedouble);
    cJSON_Delete(j);
    free(text);
  }
}

/* eval --sun: original and cloud lit alike by an engine's sun and ambient
 * light. The default (material) cloud follows the sun as the original
 * does; a baked cloud, drawn unlit, is far too bright under the same
 * lights (what three.js shows, docs/lighting.md). Bad values are said. */
static void test_sun(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_3.obj");
  if (!tu_have_file(path)) skip();
  const char *clouds[2] = {"", "--lighting baked"};
  double lum[2][2];
  for (int c = 0; c < 2; c++) {
    snprintf(args, sizeof args, "'%s' -o '%s/sun%d.glb' --texres 64 %s", path, tu_dir, c,
             clouds[c]);
    assert_int_equal(run(args, &out, &err), 0);
    assert_non_null(strstr(err, c ? "lighting: baked" : "lighting: material"));
    free(out);
    free(err);
    for (int s = 0; s < 2; s++) {
      snprintf(args, sizeof args,
               "eval '%s' '%s/sun%d.glb' --views 8 --size 96 --sun %s --json '%s/sun.json'", path,
               tu_dir, c, s ? "180,15" : "0,50", tu_dir);
      assert_int_equal(run(args, &out, &err), 0);
      assert_non_null(strstr(out, "luminance ratio over 1 sun:"));
      free(out);
      free(err);
      char jp[1200];
      snprintf(jp, sizeof jp, "%s/sun.json", tu_dir);
      char *text = (char *)tu_read_file(jp, NULL);
      cJSON *j = cJSON_Parse(text);
      const cJSON *s0 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "suns"), 0);
      lum[c][s] = cJSON_GetObjectItemCaseSensitive(s0, "luminance_ratio")->valuedouble;
      cJSON_Delete(j);
      free(text);
    }
  }
  for (int s = 0; s < 2; s++) {
    if (!(lum[0][s] > 0.85 && lum[0][s] < 1.15)) fail_msg("material cloud: %.3f", lum[0][s]);
    if (!(lum[1][s] > 1.3)) fail_msg("baked cloud, drawn unlit: %.3f", lum[1][s]);
  }
  /* The sweep: 16 suns, a line each and the range. */
  snprintf(args, sizeof args, "eval '%s' '%s/sun0.glb' --views 4 --size 64 --sun sweep", path,
           tu_dir);
  assert_int_equal(run(args, &out, &err), 0);
  int rows = 0;
  for (const char *p = out; (p = strstr(p, "\n")) != NULL; p++) rows += p[1] == ' ';
  assert_int_equal(rows, 16);
  assert_non_null(strstr(out, "luminance ratio over 16 suns:"));
  free(out);
  free(err);
  const char *bad[] = {"--sun 400,0", "--sun 30", "--sun north", "--sun-ambient 0 --sun 0,0"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(args, sizeof args, "eval '%s' '%s/sun0.glb' %s", path, tu_dir, bad[i]);
    assert_int_equal(run(args, &out, &err), 1);
    assert_non_null(strstr(err, "--sun"));
    free(out);
    free(err);
  }
  snprintf(args, sizeof args, "'%s' -o '%s/x.glb' --lighting sunny", path, tu_dir);
  assert_int_equal(run(args, &out, &err), 1);
  assert_non_null(strstr(err, "--lighting: 'material'"));
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
      cmocka_unit_test(test_exec_batch),
      cmocka_unit_test(test_exec_state),
      cmocka_unit_test(test_prompt),
      cmocka_unit_test(test_viewer),
      cmocka_unit_test(test_debug_views),
      cmocka_unit_test(test_exec_errors),
      cmocka_unit_test(test_sample),
      cmocka_unit_test(test_cloud_command),
      cmocka_unit_test(test_hand_epsilon_kept),
      cmocka_unit_test(test_suggestions),
      cmocka_unit_test(test_materials_and_texture_names),
      cmocka_unit_test(test_atlas_budget),
      cmocka_unit_test(test_unknown_part),
      cmocka_unit_test(test_brightness),
      cmocka_unit_test(test_sun),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
