/* cmd_baseline.c — `bbcgen baseline MODEL -o OUT.glb --method M [...]`: the
 * far-LOD alternatives a user would otherwise pick, as glTF like our clouds,
 * so any viewer and `bbcgen eval` can judge them. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int cmd_baseline(cli *c, int argc, char **argv) {
  const char *path = NULL, *out = NULL, *method = NULL;
  long long planes = 3, texels = 1 << 20, triangles = 0;
  int horizontal = 0;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *v;
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--method")) {
      if (!(method = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--planes")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((planes = cli_parse_count(argv[i - 1], v, 16)) < 1) {
        if (planes == 0) cli_error("--planes: 1 to 16");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--horizontal")) {
      horizontal = 1;
    } else if (!strcmp(argv[i], "--texels")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      /* 2^26 texels: a 8192 x 8192 atlas; more cannot fit one image. */
      if ((texels = cli_parse_count(argv[i - 1], v, 1LL << 26)) < 16) {
        if (texels >= 0) cli_error("--texels: 16 to 67108864");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--triangles")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((triangles = cli_parse_count(argv[i - 1], v, 1LL << 32)) < 1) {
        if (triangles == 0) cli_error("--triangles: at least 1");
        return EXIT_USAGE;
      }
    } else if (!path && argv[i][0] != '-') {
      path = argv[i];
    } else {
      static const char *const own[] = {"-o",           "--output", "--method",    "--planes",
                                        "--horizontal", "--texels", "--triangles", NULL};
      return cli_unknown_option("baseline", argv[i], own);
    }
  }
  int crossed = method && !strcmp(method, "crossed"),
      simplify = method && !strcmp(method, "simplify"),
      sloppy = method && !strcmp(method, "sloppy");
  if (method && !(crossed || simplify || sloppy)) {
    cli_error("baseline: unknown method '%s' (crossed, simplify or sloppy)", method);
    return EXIT_USAGE;
  }
  if (!path || !out || !(crossed || simplify || sloppy)) {
    cli_error("baseline: usage: bbcgen baseline MODEL -o OUT.glb|.gltf|.obj --method "
              "crossed [--planes K] [--horizontal] [--texels N] | --method simplify|sloppy "
              "--triangles N");
    return EXIT_USAGE;
  }
  if ((simplify || sloppy) && !triangles) {
    cli_error("baseline: --method %s needs --triangles N", method);
    return EXIT_USAGE;
  }
  const char *ext = strrchr(out, '.');
  if (!ext || (strcasecmp(ext, ".glb") && strcasecmp(ext, ".gltf") && strcasecmp(ext, ".obj"))) {
    cli_error("the output must end in .glb, .gltf or .obj, not '%s'", out);
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_mesh m, res;
  bbc_cloud cl;
  bbc_error err;
  memset(&cl, 0, sizeof cl);
  memset(&res, 0, sizeof res);
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t0 = cli_now();
  bbc_result r;
  const bbc_mesh *what;
  if (crossed) {
    r = bbc_baseline_crossed(&m, (int)planes, horizontal, &c->params, (size_t)texels, &c->callbacks,
                             &cl, &err);
    what = &cl.mesh;
  } else {
    r = bbc_baseline_simplify(&m, (size_t)triangles, sloppy, &res, &err);
    what = &res;
  }
  int rc = EXIT_OK;
  if (r != BBC_OK) {
    rc = cli_fail_in(path, &err, 0);
  } else {
    double t1 = cli_now();
    r = !strcasecmp(ext, ".obj") ? bbc_mesh_write_obj(out, what, &err)
                                 : bbc_mesh_write_gltf(out, what, NULL, &err);
    if (r != BBC_OK)
      rc = cli_fail(&err, 1);
    else if (crossed)
      cli_info(c, "wrote %s: %zu crossed billboards, %zu texels, atlas %dx%d (%.2f s)", out,
               cl.billboard_count, cl.texels, cl.mesh.textures[0].image.width,
               cl.mesh.textures[0].image.height, t1 - t0);
    else
      cli_info(c, "wrote %s: %zu triangles (asked %lld), %s (%.2f s)", out, res.triangle_count,
               triangles, sloppy ? "meshopt_simplifySloppy" : "meshopt_simplify", t1 - t0);
  }
  bbc_cloud_free(&cl);
  bbc_mesh_free(&res);
  bbc_mesh_free(&m);
  return rc;
}
