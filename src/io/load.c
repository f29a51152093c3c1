/* load.c — bbc_mesh_load: picks the reader for a file and finishes the mesh. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Georeferenced coordinates (a centre beyond 10,000 units, e.g. UTM metres)
 * are moved near 0: read as doubles, they would lose millimetres as floats
 * in the outputs. The offset, the centre rounded to whole units, is kept in
 * mesh->origin. */
static void recentre(bbc_mesh *m) {
  double o[3] = {0, 0, 0};
  int far = 0;
  for (int k = 0; k < 3; k++)
    if (fabs(m->center[k]) > 1e4) far = 1;
  if (!far) return;
  for (int k = 0; k < 3; k++) o[k] = round(m->center[k]);
  for (size_t v = 0; v < m->vertex_count; v++)
    for (int k = 0; k < 3; k++) m->positions[3 * v + k] -= o[k];
  for (int k = 0; k < 3; k++) {
    m->center[k] -= o[k];
    m->bbox_min[k] -= o[k];
    m->bbox_max[k] -= o[k];
    m->origin[k] = o[k];
  }
}

bbc_result bbc_mesh_load(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                         bbc_error *err) {
  bbc_load_options defaults;
  if (!options) {
    bbc_load_options_default(&defaults);
    options = &defaults;
  }
  memset(mesh, 0, sizeof *mesh);
  if (err) {
    err->code = BBC_OK;
    err->message[0] = 0;
  }
  bbc_result r = bbc__check_input_file(path, err);
  if (r != BBC_OK) return r;

  char ext[16];
  bbc__path_extension(path, ext, sizeof ext);
  /* Point clouds and PLY have their own readers, which finish the mesh
   * themselves. Every .ply goes to ours, mesh or point cloud: Assimp would
   * drop the points, accept damaged binary bodies without complaint, read
   * out-of-range face indices from uninitialised memory, and it never
   * returns on a header without end_header. */
  if (!strcmp(ext, "xyz") || !strcmp(ext, "pts") || !strcmp(ext, "txt"))
    r = bbc__load_xyz_points(path, options, mesh, err);
  else if (!strcmp(ext, "ply"))
    r = bbc__load_ply(path, options, mesh, err);
  else {
    /* VRML: the project's reader (Debian's Assimp has no VRML importer). */
    if (!strcmp(ext, "wrl") || !strcmp(ext, "vrml"))
      r = bbc__load_vrml(path, options, mesh, err);
    else
      r = bbc__load_assimp(path, options, mesh, err);
    if (r == BBC_OK) r = bbc_mesh_finalize(mesh, options->compute_normals, path, err);
    if (r == BBC_OK && mesh->dropped_degenerate)
      bbc__log(&options->callbacks, BBC_LOG_WARNING, "%s: dropped %zu zero-area triangles", path,
               mesh->dropped_degenerate);
    bbc__progress(&options->callbacks, "load", 1.0);
  }
  if (r != BBC_OK)
    bbc_mesh_free(mesh);
  else {
    mesh->no_mipmaps = options->no_mipmaps;
    recentre(mesh);
  }
  return r;
}

bbc_result bbc_mesh_load_memory(const char *name, const void *data, size_t size,
                                const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  bbc_load_options defaults;
  if (!options) {
    bbc_load_options_default(&defaults);
    options = &defaults;
  }
  memset(mesh, 0, sizeof *mesh);
  if (err) {
    err->code = BBC_OK;
    err->message[0] = 0;
  }
  if (!name) name = "(memory)";
  char ext[16];
  bbc__path_extension(name, ext, sizeof ext);
  int ply = !strcmp(ext, "ply"), wrl = !strcmp(ext, "wrl") || !strcmp(ext, "vrml"),
      xyz = !strcmp(ext, "xyz") || !strcmp(ext, "pts") || !strcmp(ext, "txt");
  if (!ply && !wrl && !xyz) { /* Assimp's formats, then our mesh building */
    bbc_result r = bbc__load_assimp_memory(name, data, size, options, mesh, err);
    if (r == BBC_OK) r = bbc_mesh_finalize(mesh, options->compute_normals, name, err);
    if (r != BBC_OK) {
      bbc_mesh_free(mesh);
      return r;
    }
    mesh->no_mipmaps = options->no_mipmaps;
    recentre(mesh);
    return BBC_OK;
  }
  char *buf = malloc(size + 1);
  if (!buf) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
  if (size) memcpy(buf, data, size);
  buf[size] = 0;
  bbc_result r;
  if (ply) {
    r = bbc__parse_ply(name, buf, size, options, mesh, err);
  } else if (xyz) {
    r = bbc__parse_xyz(name, buf, size, options, mesh, err);
  } else {
    r = bbc__parse_vrml(name, buf, size, options, mesh, err);
    if (r == BBC_OK) r = bbc_mesh_finalize(mesh, options->compute_normals, name, err);
  }
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  mesh->no_mipmaps = options->no_mipmaps;
  recentre(mesh);
  return BBC_OK;
}
