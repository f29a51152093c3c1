/* cmd_baseline.c — `bbcgen baseline MODEL -o OUT.glb --method M [...]`: the
 * far-LOD alternatives a user would otherwise pick, as glTF like our clouds,
 * so any viewer and `bbcgen eval` can judge them. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* What `bbcgen baseline` is asked for. */
typedef struct baseline_args {
  const char *path, *out, *method;
  long long planes, texels, triangles;
  int horizontal;
  int crossed, simplify, sloppy, impostor; /* the method */
  const char *ext;                         /* the output's extension */
} baseline_args;

/* The command line into `ba`: -1 to go on, else an exit code (said). */
static int parse_baseline_args(cli *c, int argc, char **argv, baseline_args *ba) {
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *v;
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (!(ba->out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--method")) {
      if (!(ba->method = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--planes")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((ba->planes = cli_parse_count(argv[i - 1], v, 16)) < 1) {
        if (ba->planes == 0) cli_error("--planes: 1 to 16");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--horizontal")) {
      ba->horizontal = 1;
    } else if (!strcmp(argv[i], "--texels")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      /* 2^26 texels: a 8192 x 8192 atlas; more cannot fit one image. */
      if ((ba->texels = cli_parse_count(argv[i - 1], v, 1LL << 26)) < 16) {
        if (ba->texels >= 0) cli_error("--texels: 16 to 67108864");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--triangles")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((ba->triangles = cli_parse_count(argv[i - 1], v, 1LL << 32)) < 1) {
        if (ba->triangles == 0) cli_error("--triangles: at least 1");
        return EXIT_USAGE;
      }
    } else if (!ba->path && argv[i][0] != '-') {
      ba->path = argv[i];
    } else {
      static const char *const own[] = {"-o",           "--output", "--method",    "--planes",
                                        "--horizontal", "--texels", "--triangles", NULL};
      return cli_unknown_option("baseline", argv[i], own);
    }
  }
  return -1;
}

/* The method, what it needs, and the output's name and folder: an exit
 * code. */
static int check_baseline_args(baseline_args *ba) {
  const char *method = ba->method, *out = ba->out;
  ba->crossed = method && !strcmp(method, "crossed");
  ba->simplify = method && !strcmp(method, "simplify");
  ba->sloppy = method && !strcmp(method, "sloppy");
  ba->impostor = method && !strcmp(method, "impostor");
  if (method && !(ba->crossed || ba->simplify || ba->sloppy || ba->impostor)) {
    cli_error("baseline: unknown method '%s' (crossed, simplify, sloppy or impostor)", method);
    return EXIT_USAGE;
  }
  if (!ba->path || !out || !(ba->crossed || ba->simplify || ba->sloppy || ba->impostor)) {
    cli_error("baseline: usage: bbcgen baseline MODEL -o OUT.glb|.gltf|.obj --method "
              "crossed [--planes K] [--horizontal] [--texels N] | --method simplify|sloppy "
              "--triangles N | -o OUT.json --method impostor [--texels N]");
    return EXIT_USAGE;
  }
  if (ba->impostor) return EXIT_OK; /* bbcgen impostor's checks */
  if ((ba->simplify || ba->sloppy) && !ba->triangles) {
    cli_error("baseline: --method %s needs --triangles N", method);
    return EXIT_USAGE;
  }
  const char *ext = strrchr(out, '.');
  if (!ext || (strcasecmp(ext, ".glb") && strcasecmp(ext, ".gltf") && strcasecmp(ext, ".obj"))) {
    cli_error("the output must end in .glb, .gltf or .obj, not '%s'", out);
    return EXIT_USAGE;
  }
  ba->ext = ext;
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  return EXIT_OK;
}

int cmd_baseline(cli *c, int argc, char **argv) {
  baseline_args ba;
  memset(&ba, 0, sizeof ba);
  ba.planes = 3;
  ba.texels = 1 << 20;
  int rc = parse_baseline_args(c, argc, argv, &ba);
  if (rc >= 0) return rc;
  if ((rc = check_baseline_args(&ba)) != EXIT_OK) return rc;
  if (ba.impostor) { /* the octahedral impostor at the texels asked: bbcgen impostor */
    char texels[32];
    snprintf(texels, sizeof texels, "%lld", ba.texels);
    char *args[] = {"impostor", (char *)ba.path, "-o", (char *)ba.out, "--texels", texels, NULL};
    return cmd_impostor(c, 6, args);
  }
  const char *path = ba.path, *out = ba.out;
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
  if (ba.crossed) {
    r = bbc_baseline_crossed(&m, (int)ba.planes, ba.horizontal, &c->params, (size_t)ba.texels,
                             &c->callbacks, &cl, &err);
    what = &cl.mesh;
  } else {
    r = bbc_baseline_simplify(&m, (size_t)ba.triangles, ba.sloppy, &res, &err);
    what = &res;
  }
  if (r != BBC_OK) {
    rc = cli_fail_in(path, &err, 0);
  } else {
    double t1 = cli_now();
    r = !strcasecmp(ba.ext, ".obj") ? bbc_mesh_write_obj(out, what, NULL, &err)
                                    : bbc_mesh_write_gltf(out, what, NULL, &err);
    if (r != BBC_OK)
      rc = cli_fail(&err, 1);
    else if (ba.crossed)
      cli_info(c, "wrote %s: %zu crossed billboards, %zu texels, atlas %dx%d (%.2f s)", out,
               cl.billboard_count, cl.texels, cl.mesh.textures[0].image.width,
               cl.mesh.textures[0].image.height, t1 - t0);
    else
      cli_info(c, "wrote %s: %zu triangles (asked %lld), %s (%.2f s)", out, res.triangle_count,
               ba.triangles, ba.sloppy ? "meshopt_simplifySloppy" : "meshopt_simplify", t1 - t0);
  }
  bbc_cloud_free(&cl);
  bbc_mesh_free(&res);
  bbc_mesh_free(&m);
  return rc;
}
