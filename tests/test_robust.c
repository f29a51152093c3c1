/* test_robust.c — nothing lost, bad input refused (issue 32, items 4 and 5):
 * one output never damages another's files, one run's files appear all
 * together or not at all, and damaged, compressed or misplaced inputs get a
 * clear error instead of a partial model. Runs the tools as a user would. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>
#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "test_util.h"

/* Runs `TOOL ARGS` (bbcgen or forest) in tu_dir, stdout and stderr to
 * files; returns the exit code and stderr (caller frees). */
static int run_tool(const char *tool, const char *args, char **errout) {
  char cmd[8192], o[1024], e[1024];
  snprintf(o, sizeof o, "%s/stdout.txt", tu_dir);
  snprintf(e, sizeof e, "%s/stderr.txt", tu_dir);
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/%s' %s > '%s' 2> '%s' < /dev/null", tu_dir, BBC_BIN_DIR,
           tool, args, o, e);
  int st = system(cmd);
  char *err = (char *)tu_read_file(e, NULL);
  if (errout)
    *errout = err ? err : strdup("");
  else
    free(err);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

static int file_exists(const char *dir, const char *name) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return access(p, F_OK) == 0;
}

/* The names in a folder, sorted, as one string "a b c" (caller frees). */
static char *listing(const char *dir) {
  char *names[256];
  size_t n = 0, total = 1;
  DIR *d = opendir(dir);
  assert_non_null(d);
  struct dirent *e;
  while ((e = readdir(d)) && n < 256)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
      names[n] = strdup(e->d_name);
      total += strlen(e->d_name) + 1;
      n++;
    }
  closedir(d);
  for (size_t i = 1; i < n; i++)
    for (size_t j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
      char *t = names[j];
      names[j] = names[j - 1];
      names[j - 1] = t;
    }
  char *s = calloc(total, 1);
  for (size_t i = 0; i < n; i++) {
    if (i) strcat(s, " ");
    strcat(s, names[i]);
    free(names[i]);
  }
  return s;
}

/* Every file of `dir` read into memory, to compare later. */
typedef struct snapshot {
  size_t n;
  char names[64][256];
  unsigned char *data[64];
  size_t size[64];
} snapshot;

static void take(snapshot *s, const char *dir) {
  memset(s, 0, sizeof *s);
  DIR *d = opendir(dir);
  assert_non_null(d);
  struct dirent *e;
  while ((e = readdir(d)) && s->n < 64) {
    if (e->d_name[0] == '.') continue;
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
    snprintf(s->names[s->n], sizeof s->names[0], "%s", e->d_name);
    s->data[s->n] = tu_read_file(p, &s->size[s->n]);
    s->n++;
  }
  closedir(d);
}

/* Each file of the snapshot still there with the same bytes. */
static void unchanged(const snapshot *s, const char *dir) {
  for (size_t i = 0; i < s->n; i++) {
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", dir, s->names[i]);
    size_t n = 0;
    unsigned char *now = tu_read_file(p, &n);
    if (!now || n != s->size[i] || memcmp(now, s->data[i], n))
      fail_msg("%s changed or went missing", s->names[i]);
    free(now);
  }
}

static void drop(snapshot *s) {
  for (size_t i = 0; i < s->n; i++) free(s->data[i]);
}

/* The case: a .gltf chain, then an .obj chain of the same name in
 * the same folder; every file the glTF wrote keeps its bytes. */
static void test_outputs_do_not_clash(void **state) {
  (void)state;
  char model[1024], args[4096];
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(model)) skip();
  char *dir = tu_make_temp_dir();
  snprintf(args, sizeof args, "'%s' -o '%s/peach.gltf' --lod 5,10 --texres 32 -q", model, dir);
  assert_int_equal(run_tool("bbcgen", args, NULL), 0);
  snapshot gl;
  take(&gl, dir);
  assert_true(gl.n >= 3); /* .gltf, .bin, the atlases */
  for (const char *ext = "obj"; ext; ext = !strcmp(ext, "obj") ? "wrl" : NULL) {
    snprintf(args, sizeof args, "'%s' -o '%s/peach.%s' --lod 5,10 --texres 32 -q", model, dir, ext);
    assert_int_equal(run_tool("bbcgen", args, NULL), 0);
  }
  unchanged(&gl, dir);
  drop(&gl);
  assert_true(file_exists(dir, "peach_gltf_billboards_LOD0.png"));
  assert_true(file_exists(dir, "peach_obj_billboards_LOD0.png"));
  assert_true(file_exists(dir, "peach_lod1_wrl_billboards_LOD1.png"));
  tu_remove_dir(dir);
  free(dir);
}

/* A run that cannot put one of its files in place writes none of them and
 * leaves no temporary folder. */
static void test_all_or_nothing(void **state) {
  (void)state;
  char model[1024], args[4096], *err;
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(model)) skip();
  char *dir = tu_make_temp_dir(), sub[2048];
  snprintf(sub, sizeof sub, "%s/t.mtl", dir); /* a folder where the .mtl goes */
  assert_int_equal(mkdir(sub, 0777), 0);
  snprintf(args, sizeof args, "'%s' -o '%s/t.obj' --texres 32 -q", model, dir);
  assert_int_equal(run_tool("bbcgen", args, &err), 5);
  assert_non_null(strstr(err, "t.mtl"));
  assert_null(strstr(err, ".bbcgen-")); /* the final names, not the staging folder's */
  free(err);
  char *l = listing(dir);
  assert_string_equal(l, "t.mtl"); /* no t.obj, no atlas, no temporary folder */
  free(l);
  assert_int_equal(rmdir(sub), 0);
  /* With the way clear, the same run writes all three. */
  assert_int_equal(run_tool("bbcgen", args, NULL), 0);
  l = listing(dir);
  assert_string_equal(l, "t.mtl t.obj t_obj_billboards.png");
  free(l);
  tu_remove_dir(dir);
  free(dir);
}

/* Ctrl-C during a run: "interrupted", exit 130 (documented), nothing
 * written. ash_large_hi takes seconds; the signal comes after half a
 * second, while the model loads or the planes are chosen. */
static void test_ctrl_c(void **state) {
  (void)state;
  char model[1024], args[4096], *err;
  tu_data_path(model, sizeof model, "trees/eztree/ash_large_hi.obj");
  if (!tu_have_file(model)) skip();
  char *dir = tu_make_temp_dir();
  char cmd[8192], e[1024];
  snprintf(e, sizeof e, "%s/stderr.txt", tu_dir);
  snprintf(args, sizeof args, "'%s' -o '%s/a.glb' --report '%s/a.json'", model, dir, dir);
  snprintf(cmd, sizeof cmd,
           "timeout --preserve-status -s INT 0.5 '%s/bbcgen' %s 2> '%s' > /dev/null", BBC_BIN_DIR,
           args, e);
  int st = system(cmd);
  err = (char *)tu_read_file(e, NULL);
  assert_non_null(err);
  assert_true(WIFEXITED(st));
  if (WEXITSTATUS(st) != 130) fail_msg("exit %d: %s", WEXITSTATUS(st), err);
  assert_non_null(strstr(err, "interrupted"));
  assert_null(strstr(err, "cancelled")); /* said once */
  free(err);
  char *l = listing(dir);
  assert_string_equal(l, "");
  free(l);
  tu_remove_dir(dir);
  free(dir);
}

/* `bbcgen info FILE` on bytes written to FILE: the exit code, and stderr
 * holding `want` (when not NULL). */
static int info_on(const char *name, const void *bytes, size_t n, int want_rc, const char *want) {
  char *path = tu_write_file(tu_dir, name, bytes, n), args[2048], *err;
  snprintf(args, sizeof args, "info '%s'", path);
  int rc = run_tool("bbcgen", args, &err);
  if (rc != want_rc || (want && !strstr(err, want)))
    fail_msg("%s: exit %d (wanted %d), stderr: %s (wanted '%s')", name, rc, want_rc, err,
             want ? want : "");
  free(err);
  free(path);
  return rc;
}

#define INFO(name, text, rc, want) info_on(name, text, sizeof text - 1, rc, want)

/* Files cut short are refused, naming the file and what is missing; whole
 * files without a last line end are not. */
static void test_cut_short(void **state) {
  (void)state;
  const char *quad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n";
  char buf[512];
  snprintf(buf, sizeof buf, "%sf 2 4 ", quad); /* the last face cut */
  info_on("face.obj", buf, strlen(buf), 4, "face.obj: cut short");
  snprintf(buf, sizeof buf, "%sf 2 4 3", quad); /* whole, no line end */
  info_on("whole.obj", buf, strlen(buf), 0, NULL);
  snprintf(buf, sizeof buf,
           "v 0.500000 0.000000 0.000000\nv 1.000000 0.000000 0.000000\n"
           "v 0.000000 1.000000 0.000000\nf 1 2 3\nv 0.000000 1.0");
  info_on("vertex.obj", buf, strlen(buf), 4, "'v 0.000000 1.0' is incomplete");
  snprintf(buf, sizeof buf, "%sf 2/1 4/2 3/", quad); /* a corner cut */
  info_on("corner.obj", buf, strlen(buf), 4, "cut short");
  INFO("pts.xyz", "1.5 2.5 3.5 7 9\n1.5 2.5 3.5 7 9\n1.5 2.5 3.5", 4, "pts.xyz: cut short");
  INFO("ok.xyz", "1.5 2.5 3.5\n1.5 2.5 4.5\n1.5 3.5 3.5", 0, NULL);
  INFO("count.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n1 0 0\n",
       4, "truncated");
  /* a binary PLY whose body is short of its header's count */
  char bin[256];
  int hn = snprintf(bin, sizeof bin,
                    "ply\nformat binary_little_endian 1.0\nelement vertex 10\n"
                    "property float x\nproperty float y\nproperty float z\nend_header\n");
  memset(bin + hn, 0, 40);
  info_on("short.ply", bin, (size_t)hn + 40, 4, "truncated");
  /* an OBJ cut at a line end: its last vertices serve no face (said) */
  char big[8192];
  size_t n = 0;
  for (int i = 0; i < 60; i++)
    n += (size_t)snprintf(big + n, sizeof big - n, "v %d %d 0\nv %d %d 1\n", i, i % 7, i, i % 5);
  n += (size_t)snprintf(big + n, sizeof big - n, "f 1 2 3\nf 2 3 4\n");
  info_on("tail.obj", big, n, 0, "used by no face");
  /* an OBJ cut where only vertices followed its last face: refused, exit 4,
   * nothing written (parameter acceptunused 1 loads it) */
  n = (size_t)snprintf(big, sizeof big, "%s", quad);
  for (int i = 0; i < 200; i++) n += (size_t)snprintf(big + n, sizeof big - n, "v %d 2 0\n", i);
  info_on("leaves.obj", big, n, 4, "leaves.obj: cut short? 200 of its 204 vertices follow");
  char *err = NULL;
  assert_int_equal(run_tool("bbcgen", "leaves.obj -o leaves.glb -q", &err), 4);
  assert_false(file_exists(tu_dir, "leaves.glb"));
  free(err);
  assert_int_equal(run_tool("bbcgen", "info leaves.obj --acceptunused 1 -q", &err), 0);
  free(err);
}

/* glTF: a GLB cut short, accessors and buffers claiming more than is there. */
static void test_gltf_claims(void **state) {
  (void)state;
  char model[1024], args[4096];
  tu_data_path(model, sizeof model, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(model)) skip();
  snprintf(args, sizeof args, "'%s' -o t.glb --texres 16 -q", model);
  assert_int_equal(run_tool("bbcgen", args, NULL), 0);
  char path[2048];
  snprintf(path, sizeof path, "%s/t.glb", tu_dir);
  size_t n = 0;
  unsigned char *g = tu_read_file(path, &n);
  assert_non_null(g);
  info_on("cut.glb", g, n / 2, 4, "cut short: its header says");
  /* the first accessor's count made 9...9 (same length: the chunks hold) */
  char *c = strstr((char *)g + 20, "\"count\":");
  assert_non_null(c);
  for (char *d = c + 8; *d >= '0' && *d <= '9'; d++) *d = '9';
  info_on("claims.glb", g, n, 4, "claims.glb: accessor 0 claims");
  free(g);
  /* indices past the vertices (fuzz_glb: Assimp crashed on it after reading) */
  char *err0;
  snprintf(args, sizeof args, "info '%s/tests/fuzz/glb/index-past-vertices.glb'", BBC_SOURCE_DIR);
  assert_int_equal(run_tool("bbcgen", args, &err0), 4);
  assert_non_null(strstr(err0, "index 2 is 5, past its 3 vertices"));
  free(err0);
  snprintf(args, sizeof args, "info '%s/tests/fuzz/glb/assimp-overread-not-gltf.glb'",
           BBC_SOURCE_DIR);
  assert_int_equal(run_tool("bbcgen", args, &err0), 4);
  assert_non_null(strstr(err0, "not a glTF file"));
  free(err0);
  /* a .gltf whose .bin is shorter than its buffer says */
  snprintf(args, sizeof args, "'%s' -o s.gltf --texres 16 -q", model);
  assert_int_equal(run_tool("bbcgen", args, NULL), 0);
  snprintf(path, sizeof path, "%s/s.bin", tu_dir);
  assert_int_equal(truncate(path, 64), 0);
  char *err;
  assert_int_equal(run_tool("bbcgen", "info s.gltf", &err), 4);
  assert_non_null(strstr(err, "buffer 0 claims"));
  free(err);
}

/* Compressed files, LAS, images, material libraries and forest files given
 * as a model are named as what they are; forest given a model says so. */
static void test_not_a_model(void **state) {
  (void)state;
  INFO("tree.obj.gz", "\x1f\x8b\x08\x00\x00\x00\x00\x00", 3, "decompress it first (gunzip -k");
  INFO("tree.ply.xz",
       "\xfd"
       "7zXZ\0\0\0",
       3, "xz-compressed");
  INFO("tree.obj.bz2", "BZh91AY&SY", 3, "bzip2-compressed");
  INFO("tree.obj.zst", "\x28\xb5\x2f\xfd\0\0", 3, "zstd-compressed");
  INFO("scan.las", "LASF\0\0\0\0\0\0", 3, "LAS/LAZ point cloud");
  INFO("scan.laz", "LASF\0\0\0\0\0\0", 3, "convert it to PLY or XYZ");
  INFO("tree.mtl", "# made by hand\nnewmtl bark\nKd 1 1 1\n", 3, "a material library");
  INFO("bark.png", "\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 3, "an image");
  INFO("bark.jpg", "\xff\xd8\xff\xe0\0\x10JFIF", 3, "an image");
  INFO("map.txt", "' my map\nhmap height.png\nheightscale 0.5\n", 3, "a forest map file");
  INFO("oak.txt", "LOD ( oak.glb min 0 max 100 )\n", 3, "a forest model description file");
  char *err;
  assert_int_equal(run_tool("forest", "bark.png.glb", &err), 2);
  assert_non_null(strstr(err, "not a map"));
  assert_non_null(strstr(err, "bbcgen view"));
  free(err);
  /* a word-valued parameter's message lists the words */
  assert_int_equal(run_tool("bbcgen", "info x.obj --set upaxis=w", &err), 1);
  assert_non_null(strstr(err, "x, y or z"));
  free(err);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_outputs_do_not_clash),
      cmocka_unit_test(test_all_or_nothing),
      cmocka_unit_test(test_ctrl_c),
      cmocka_unit_test(test_cut_short),
      cmocka_unit_test(test_gltf_claims),
      cmocka_unit_test(test_not_a_model),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
