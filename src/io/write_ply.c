/* write_ply.c — a point cloud as binary little-endian PLY (doubles, so
 * georeferenced coordinates keep their precision; colours and normals when
 * the cloud has them), atomically. */
#include "io.h"

#include <assert.h>
#include <stdio.h>
#include <string.h>

bbc_result bbc_points_write_ply(const char *path, const bbc_mesh *m, bbc_error *err) {
  assert(path && m);
  if (m->kind != BBC_MESH_POINTS)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "%s: only point clouds are written as PLY",
                     path);
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, path, err);
  if (r != BBC_OK) return r;
  fprintf(af.fp,
          "ply\nformat binary_little_endian 1.0\ncomment bbcgen " BBC_VERSION_STRING
          "\nelement vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
          "%s%send_header\n",
          m->vertex_count,
          m->normals ? "property float nx\nproperty float ny\nproperty float nz\n" : "",
          m->colors ? "property uchar red\nproperty uchar green\nproperty uchar blue\n" : "");
  unsigned char rec[39];
  for (size_t v = 0; v < m->vertex_count; v++) {
    for (int k = 0; k < 3; k++) { /* little endian, whatever the host */
      uint64_t bits;
      memcpy(&bits, m->positions + 3 * v + k, 8);
      for (int b = 0; b < 8; b++) rec[8 * k + b] = (unsigned char)(bits >> (8 * b));
    }
    size_t n = 24;
    if (m->normals)
      for (int k = 0; k < 3; k++, n += 4) {
        uint32_t bits;
        memcpy(&bits, m->normals + 3 * v + k, 4);
        for (int b = 0; b < 4; b++) rec[n + b] = (unsigned char)(bits >> (8 * b));
      }
    if (m->colors) {
      memcpy(rec + n, m->colors + 4 * v, 3);
      n += 3;
    }
    fwrite(rec, 1, n, af.fp);
  }
  return bbc__atomic_commit(&af, err);
}
