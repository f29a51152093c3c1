/* test_fuzz_replay.c — every regression input the fuzzers found (tests/fuzz/
 * HARNESS/) replayed through the function its harness calls, so
 * `make test` runs them under ASan and UBSan; and for each format we parse,
 * a truncated, a huge-count and a binary-garbage input refused with a
 * one-line message naming the input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "bbc_forest.h"
#include "test_util.h"

#ifndef BBC_SOURCE_DIR
#define BBC_SOURCE_DIR "."
#endif

/* What each harness calls (fuzz/fuzz_*.c). */
static bbc_result feed(const char *format, const char *name, const void *data, size_t size,
                       bbc_error *err) {
  if (!strcmp(format, "forest_map")) {
    bbc_forest_map map;
    bbc_result r = bbc_forest_map_parse(data, size, name, &map, err);
    if (r == BBC_OK) bbc_forest_map_free(&map);
    return r;
  }
  if (!strcmp(format, "forest_model")) {
    bbc_forest_model model;
    bbc_result r = bbc_forest_model_parse(data, size, name, &model, err);
    if (r == BBC_OK) bbc_forest_model_free(&model);
    return r;
  }
  if (!strcmp(format, "batch")) { /* as bbcgen exec reads a batch file */
    bbc_command *k = malloc(sizeof *k);
    if (!k) return BBC_ERROR_OUT_OF_MEMORY;
    size_t pos = 0;
    int line = 0;
    bbc_result r;
    do r = bbc_script_next(data, size, name, &pos, &line, k, err);
    while (r == BBC_OK && k->kind != BBC_COMMAND_NONE);
    free(k);
    return r;
  }
  bbc_load_options o;
  bbc_load_options_default(&o);
  o.skip_textures = 1;
  bbc_mesh m;
  bbc_result r = bbc_mesh_load_memory(name, data, size, &o, &m, err);
  if (r == BBC_OK) bbc_mesh_free(&m);
  return r;
}

static const char *const k_formats[] = {"ply",   "xyz", "wrl", "forest_map", "forest_model",
                                        "batch", "obj", "3ds", "glb"};

static void test_replay(void **state) {
  (void)state;
  size_t replayed = 0;
  for (size_t f = 0; f < sizeof k_formats / sizeof k_formats[0]; f++) {
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/tests/fuzz/%s", BBC_SOURCE_DIR, k_formats[f]);
    DIR *d = opendir(dir);
    if (!d) fail_msg("%s: missing", dir);
    struct dirent *e;
    while ((e = readdir(d))) {
      if (e->d_name[0] == '.' || !strcmp(e->d_name, "README")) continue;
      char path[2048], name[64];
      snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
      size_t n = 0;
      unsigned char *data = tu_read_file(path, &n);
      if (!data) fail_msg("%s: cannot read", path);
      snprintf(name, sizeof name, "replay.%s", k_formats[f][0] == 'f' ? "txt" : k_formats[f]);
      bbc_error err;
      feed(k_formats[f], name, data, n, &err); /* no crash, no sanitizer report */
      free(data);
      replayed++;
    }
    closedir(d);
  }
  printf("replayed %zu regression inputs\n", replayed);
}

/* A refusal: not OK, one line, naming the input. */
static void refused(const char *format, const char *name, const void *data, size_t size) {
  bbc_error err;
  bbc_result r = feed(format, name, data, size, &err);
  if (r == BBC_OK) fail_msg("%s (%s): accepted", name, format);
  if (!strstr(err.message, name))
    fail_msg("%s: the message does not name it: %s", name, err.message);
  if (strchr(err.message, '\n')) fail_msg("%s: more than one line: %s", name, err.message);
}

static void test_hostile_per_format(void **state) {
  (void)state;
  unsigned char garbage[512];
  uint64_t x = 0x9E3779B97F4A7C15ull;
  for (size_t i = 0; i < sizeof garbage; i++) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    garbage[i] = (unsigned char)x;
  }
  garbage[3] = 0; /* binary */
  /* PLY: truncated body, a count far beyond the file, garbage */
  const char trunc_ply[] = "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty "
                           "double x\nproperty double y\nproperty double z\nend_header\n\1\2\3";
  refused("ply", "trunc.ply", trunc_ply, sizeof trunc_ply - 1);
  const char huge_ply[] = "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty "
                          "float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
  refused("ply", "huge.ply", huge_ply, sizeof huge_ply - 1);
  refused("ply", "garbage.ply", garbage, sizeof garbage);
  /* XYZ: a line cut in the middle of a point, a PTS count beyond the file,
   * binary */
  const char trunc_xyz[] = "1 2 3\n4 5";
  refused("xyz", "trunc.xyz", trunc_xyz, sizeof trunc_xyz - 1);
  const char huge_pts[] = "99999999999999\n1 2 3\n";
  refused("xyz", "huge.pts", huge_pts, sizeof huge_pts - 1);
  refused("xyz", "garbage.xyz", garbage, sizeof garbage);
  /* VRML: cut inside a node, a coordIndex beyond the points, binary */
  const char trunc_wrl[] = "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate "
                           "{ point [ 0 0 0, 1 0 0";
  refused("wrl", "trunc.wrl", trunc_wrl, sizeof trunc_wrl - 1);
  const char huge_wrl[] =
      "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate "
      "{ point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 4000000000 -1 ] } }\n";
  refused("wrl", "huge.wrl", huge_wrl, sizeof huge_wrl - 1);
  refused("wrl", "garbage.wrl", garbage, sizeof garbage);
  /* forest's map and model files: cut in a command, a count beyond reason,
   * binary */
  const char trunc_map[] = "hmap terrain.png\nrndtree oak.txt 1.0";
  refused("forest_map", "trunc_map.txt", trunc_map, sizeof trunc_map - 1);
  const char huge_map[] = "hmap t.png\nnumobjs 99999999999999999999\n";
  refused("forest_map", "huge_map.txt", huge_map, sizeof huge_map - 1);
  refused("forest_map", "garbage_map.txt", garbage, sizeof garbage);
  const char trunc_model[] = "LOD\n(\n    file1 tree.wrl\n    min 0\n";
  refused("forest_model", "trunc_model.txt", trunc_model, sizeof trunc_model - 1);
  const char huge_model[] = "LOD\n(\n file1 t.wrl\n min 0\n max 1e999\n)\n";
  refused("forest_model", "huge_model.txt", huge_model, sizeof huge_model - 1);
  refused("forest_model", "garbage_model.txt", garbage, sizeof garbage);
  /* batch files: a command cut before its argument, a line longer than any
   * command, binary; the error names file and line */
  const char trunc_batch[] = "load tree.obj\nset epsilon 5\nset epsilon";
  refused("batch", "trunc.bbc", trunc_batch, sizeof trunc_batch - 1);
  bbc_error err;
  if (feed("batch", "trunc.bbc", trunc_batch, sizeof trunc_batch - 1, &err) == BBC_OK ||
      !strstr(err.message, "trunc.bbc:3: "))
    fail_msg("the batch error does not name line 3: %s", err.message);
  size_t huge_n = 3 * BBC_COMMAND_LINE_MAX;
  char *huge_batch = malloc(huge_n);
  assert_non_null(huge_batch);
  memcpy(huge_batch, "set epsilon ", 12);
  memset(huge_batch + 12, '5', huge_n - 12);
  refused("batch", "huge.bbc", huge_batch, huge_n);
  free(huge_batch);
  refused("batch", "garbage.bbc", garbage, sizeof garbage);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_replay),
                                     cmocka_unit_test(test_hostile_per_format)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
