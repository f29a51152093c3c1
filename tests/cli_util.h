/* cli_util.h — helpers of the bbcgen tool's tests (test_cli*.c). */
#ifndef BBC_CLI_UTIL_H
#define BBC_CLI_UTIL_H

#include <cjson/cJSON.h>

/* Runs `bbcgen ARGS` (from BBC_BIN_DIR), stdout and stderr to files in
 * tu_dir; returns the exit code (128 when it did not exit) and the outputs
 * (caller frees; either pointer may be NULL). */
int cli_run(const char *args, char **out, char **errout);
/* The same from tu_dir, with `input` on standard input. */
int cli_run_in(const char *args, const char *input, char **out, char **errout);
/* `bbcgen info --json` on the shared data file `rel`, parsed; NULL (the
 * test skips) when the file is not there; fails the test on an error. */
cJSON *cli_info_json(const char *rel);
/* The number under `key` of object o; fails the test when there is none. */
double cli_num(const cJSON *o, const char *key);
/* The triangles of the group named `name` in `info --json`'s groups; -1
 * when no group has that name. */
double cli_group_triangles(const cJSON *j, const char *name);
/* The share of pixels of a PNG that differ from its bottom-right pixel
 * (the background). */
double cli_covered(const char *png);
/* A .glb's JSON chunk, parsed; fails the test when it cannot be read. */
cJSON *cli_glb_json(const char *path);
/* 1 when dir/name exists. */
int cli_file_exists(const char *dir, const char *name);

#endif
