/* cli_util.c — helpers of the bbcgen tool's tests (test_cli*.c): running
 * the tool, reading its JSON and its images. */
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
/* Runs `bbcgen ARGS`, stdout and stderr to files; returns the exit code and
 * the outputs (caller frees). */
int cli_run(const char *args, char **out, char **errout) {
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
int cli_run_in(const char *args, const char *input, char **out, char **errout) {
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

cJSON *cli_info_json(const char *rel) {
  char path[1024], args[2048];
  tu_data_path(path, sizeof path, rel);
  if (!tu_have_file(path)) return NULL;
  snprintf(args, sizeof args, "info --json '%s'", path);
  char *out, *err;
  int rc = cli_run(args, &out, &err);
  if (rc != 0) fail_msg("bbcgen info %s: exit %d: %s", rel, rc, err);
  cJSON *j = cJSON_Parse(out);
  if (!j) fail_msg("not JSON: %s", out);
  free(out);
  free(err);
  return j;
}

double cli_num(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!cJSON_IsNumber(v)) fail_msg("no number '%s'", key);
  return v->valuedouble;
}

double cli_group_triangles(const cJSON *j, const char *name) {
  const cJSON *g;
  cJSON_ArrayForEach(g, cJSON_GetObjectItem(j, "groups")) {
    if (!strcmp(cJSON_GetObjectItem(g, "name")->valuestring, name)) return cli_num(g, "triangles");
  }
  return -1;
}

/* The share of pixels of a PNG that differ from its bottom-right pixel (the
 * background; show bbc's mini-model is top left). */
double cli_covered(const char *png) {
  bbc_image im;
  bbc_error e;
  if (bbc_image_load(png, &im, &e) != BBC_OK) fail_msg("%s: %s", png, e.message);
  size_t n = (size_t)im.width * im.height, diff = 0;
  for (size_t i = 0; i < n; i++) diff += memcmp(im.rgba + 4 * i, im.rgba + 4 * (n - 1), 3) != 0;
  bbc_image_free(&im);
  return (double)diff / n;
}

/* Reads a .glb's JSON chunk. */
cJSON *cli_glb_json(const char *path) {
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

int cli_file_exists(const char *dir, const char *name) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return access(p, F_OK) == 0;
}
