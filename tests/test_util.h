/* test_util.h — small helpers shared by the unit tests. */
#ifndef BBC_TEST_UTIL_H
#define BBC_TEST_UTIL_H

#include <stddef.h>

/* Path of a shared real-data file: BBC_DATA_DIR "/" rel (static buffer per
 * call site is not needed: caller passes the buffer). */
const char *tu_data_path(char *buf, size_t size, const char *rel);
/* 1 when the file exists; otherwise prints a skip message naming it. */
int tu_have_file(const char *path);
/* A fresh temporary folder under $TMPDIR (or /tmp); caller frees. */
char *tu_make_temp_dir(void);
/* Writes `size` bytes to dir/name; returns the path (caller frees). */
char *tu_write_file(const char *dir, const char *name, const void *data, size_t size);
/* Reads a whole file; NULL when it cannot. *size receives its length. */
unsigned char *tu_read_file(const char *path, size_t *size);
/* 1 when both files can be read and are the same byte for byte. */
int tu_same_file(const char *a, const char *b);
/* Removes a folder and everything in it (one level deep is enough here). */
void tu_remove_dir(const char *dir);

/* Runs scripts/tools/gltf_validate.sh (the Khronos validator) on a .glb/.gltf:
 * 0 no errors, 1 errors, 3 the validator is unavailable, other: failure. */
int tu_gltf_validate(const char *path);

/* cmocka group fixtures: a temporary folder in tu_dir for the whole group. */
extern char *tu_dir;
int tu_group_setup(void **state);
int tu_group_teardown(void **state);

#endif
