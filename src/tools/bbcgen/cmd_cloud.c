/* cmd_cloud.c — `bbcgen MODEL -o OUT.glb|.gltf|.obj [options]`: the whole
 * pipeline, steps 1 to 3 (step 3 is a first version: see README, Status). */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cmd_cloud(cli *c, int argc, char **argv) {
  const char *path = argv[0], *out = NULL;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else {
      cli_error("unknown option '%s' (try bbcgen --help)", argv[i]);
      return EXIT_USAGE;
    }
  }
  if (!out) {
    cli_error("usage: bbcgen MODEL -o OUT.glb|OUT.gltf|OUT.obj [options]");
    return EXIT_USAGE;
  }
  size_t n = strlen(out);
  int glb = n > 4 && !strcmp(out + n - 4, ".glb"), gltf = n > 5 && !strcmp(out + n - 5, ".gltf");
  int obj = n > 4 && !strcmp(out + n - 4, ".obj");
  if (!glb && !gltf && !obj) {
    cli_error("the output must end in .glb, .gltf or .obj, not '%s'", out);
    return EXIT_USAGE;
  }
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.compute_normals = c->params.vertex_normals;
  lo.callbacks = c->callbacks;
  bbc_mesh m;
  bbc_error err;
  double t0 = cli_now();
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t1 = cli_now();
  bbc_planeset set;
  if (bbc_planes_find(&m, &po, &set, &err) != BBC_OK) {
    bbc_mesh_free(&m);
    return cli_fail(&err, 0);
  }
  double t2 = cli_now();
  bbc_cloud cloud;
  int rc = EXIT_OK;
  if (bbc_cloud_build(&m, &set, &c->params, &c->callbacks, &cloud, &err) != BBC_OK) {
    rc = cli_fail(&err, 0);
  } else {
    double t3 = cli_now();
    bbc_result r;
    if (obj) {
      r = bbc_mesh_write_obj(out, &cloud.mesh, &err);
    } else {
      bbc_gltf_options go = {glb, NULL, 0};
      r = bbc_mesh_write_gltf(out, &cloud.mesh, &go, &err);
    }
    if (r != BBC_OK) {
      rc = cli_fail(&err, 1);
    } else {
      const bbc_image *a = &cloud.mesh.textures[0].image;
      cli_info(c,
               "wrote %s: %zu billboards (%zu planes), atlas %dx%d; load %.2f s, steps 1+2 "
               "%.2f s, step 3 %.2f s",
               out, cloud.billboard_count, set.plane_count, a->width, a->height, t1 - t0, t2 - t1,
               t3 - t2);
    }
    bbc_cloud_free(&cloud);
  }
  bbc_planeset_free(&set);
  bbc_mesh_free(&m);
  return rc;
}
