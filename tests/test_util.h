/* test_util.h — small helpers shared by the unit tests. */
#ifndef BBC_TEST_UTIL_H
#define BBC_TEST_UTIL_H

#include <stddef.h>
#include <stdint.h>

#include "bbc.h"

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

/* Small hand-built triangle meshes. tu_mesh_begin: an empty mesh with room
 * for max_tris triangles and 4 * max_tris vertices, `materials` untextured
 * materials named names[i] of colour colours[i] (NULL: white, opaque) and
 * one group named `group`; triangles and quads are then appended, each with
 * vertices of its own. bbc_mesh_finalize and bbc_mesh_free as for any mesh. */
void tu_mesh_begin(bbc_mesh *m, size_t max_tris, size_t materials, const char *const *names,
                   const float (*colours)[4], const char *group);
/* Appends triangle abc of material `material`. */
void tu_mesh_tri(bbc_mesh *m, const double *a, const double *b, const double *c, uint32_t material);
/* Appends quad abcd (four vertices, triangles abc and acd). */
void tu_mesh_quad(bbc_mesh *m, const double *a, const double *b, const double *c, const double *d,
                  uint32_t material);
/* A mesh of the given vertices and triangles (copied), one white material
 * "m", one group "g". */
void tu_mesh_from(bbc_mesh *m, const double *pos, size_t nv, const uint32_t *idx, size_t nt);

/* cmocka group fixtures: a temporary folder in tu_dir for the whole group. */
extern char *tu_dir;
int tu_group_setup(void **state);
int tu_group_teardown(void **state);

#endif
