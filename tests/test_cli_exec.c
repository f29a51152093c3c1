/* test_cli_exec.c — the bbcgen tool's batch language as a user runs it:
 * `exec` files, their state and errors, and the interactive prompt. */
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
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args,
           "planes '%s' --epsilon 8 --set trunk.cardboard=1 -q --json '%s/flags.json'", path,
           tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  char a[1024], b[1024];
  snprintf(a, sizeof a, "%s/batch.json", tu_dir);
  snprintf(b, sizeof b, "%s/flags.json", tu_dir);
  assert_true(tu_same_file(a, b)); /* byte for byte */
  free(bf);
  bf = tu_write_file(tu_dir, "bad.bbc", "set epsilon 5\nfrobnicate\n", 25);
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(cli_run(args, &out, &err), 1);
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
    assert_int_equal(cli_run(args, &out, &err), 1);
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
  assert_int_equal(cli_run_in(args, "", &out, &err), 0); /* in tu_dir: save writes there */
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
  assert_int_equal(cli_run_in("-i", text, &out, &err), 2);
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
  assert_int_equal(cli_run_in(args, "setup\n", &out, &err), 0);
  assert_non_null(strstr(out, "texres         16"));
  free(out);
  free(err);
  free(bf);
  bf = tu_write_file(tu_dir, "xq.bbc", "set texres 16\nquit\n", 19);
  snprintf(args, sizeof args, "-x '%s'", bf);
  assert_int_equal(cli_run_in(args, "setup\n", &out, &err), 0);
  assert_null(strstr(out, "texres"));
  free(out);
  free(err);
  free(bf);
  assert_int_equal(cli_run_in("-x", "", &out, &err), 1);
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
    int rc = cli_run_in(args, "", &out, &err);
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
      if (cli_run_in(args, "", &o2, &e2)) fail_msg("nomip: %s", e2);
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
  assert_int_not_equal(cli_run_in(args, "", &out, &err), 0);
  assert_non_null(strstr(err, "nested more than 8 deep"));
  free(out);
  free(err);
  free(bf);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_exec_batch),
      cmocka_unit_test(test_exec_state),
      cmocka_unit_test(test_prompt),
      cmocka_unit_test(test_exec_errors),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
