/* cmd_impostor.c — `bbcgen impostor MODEL -o OUT.json [--frames N] [--texels N]
 * [--full] [--samples K] [--check]`: the octahedral impostor a game engine's
 * tools would bake, as PNG atlases and a JSON descriptor (docs/impostors.md),
 * so that `bbcgen eval` and `forest` can set it beside our clouds; --check
 * says how well its frames show the model (bbc_impostor_check). */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The command line into `o` and the paths: -1 to go on, else an exit code
 * (said). */
static int parse_impostor_args(cli *c, int argc, char **argv, bbc_impostor_options *o,
                               const char **path, const char **out, int *check) {
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *v;
    long long n;
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (!(*out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--frames")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((n = cli_parse_count(argv[i - 1], v, 64)) < 2) {
        if (n >= 0) cli_error("--frames: 2 to 64");
        return EXIT_USAGE;
      }
      o->frames = (int)n;
    } else if (!strcmp(argv[i], "--texels")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((n = cli_parse_count(argv[i - 1], v, 1LL << 26)) < 256) {
        if (n >= 0) cli_error("--texels: 256 to 67108864");
        return EXIT_USAGE;
      }
      o->texels = n;
    } else if (!strcmp(argv[i], "--samples")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((n = cli_parse_count(argv[i - 1], v, 4)) < 1) {
        if (n == 0) cli_error("--samples: 1 to 4");
        return EXIT_USAGE;
      }
      o->samples = (int)n;
    } else if (!strcmp(argv[i], "--full")) {
      o->full = 1;
    } else if (!strcmp(argv[i], "--check")) {
      *check = 1;
    } else if (!*path && argv[i][0] != '-') {
      *path = argv[i];
    } else {
      static const char *const own[] = {"-o",        "--output", "--frames", "--texels",
                                        "--samples", "--full",   "--check",  NULL};
      return cli_unknown_option("impostor", argv[i], own);
    }
  }
  return -1;
}

int cmd_impostor(cli *c, int argc, char **argv) {
  bbc_impostor_options o;
  bbc_impostor_options_default(&o);
  const char *path = NULL, *out = NULL;
  int check = 0;
  int rc = parse_impostor_args(c, argc, argv, &o, &path, &out, &check);
  if (rc >= 0) return rc;
  if (!path || !out) {
    cli_error("impostor: usage: bbcgen impostor MODEL -o OUT.json [--frames N] [--texels N] "
              "[--full] [--samples K] [--check]");
    return EXIT_USAGE;
  }
  size_t ol = strlen(out);
  if (ol < 5 || strcasecmp(out + ol - 5, ".json")) {
    cli_error("impostor: the output is its descriptor and must end in .json, not '%s'", out);
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  o.up = bbc_up_from_axis(c->params.up_axis);
  o.threads = c->params.threads;
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t0 = cli_now();
  rc = EXIT_OK;
  bbc_impostor imp;
  if (bbc_impostor_build(&m, &o, &imp, &err) != BBC_OK) {
    rc = cli_fail_in(path, &err, 0);
  } else if (bbc_impostor_write(out, &imp, &err) != BBC_OK) {
    rc = cli_fail(&err, 1);
  } else {
    cli_info(c, "wrote %s: %s impostor, %d x %d frames of %d texels, atlases %d x %d (%.2f s)", out,
             imp.hemi ? "hemi-octahedral" : "octahedral", imp.frames, imp.frames, imp.frame_size,
             imp.albedo.width, imp.albedo.height, cli_now() - t0);
    double worst, mean, *per = check ? malloc((size_t)imp.frames * imp.frames * sizeof *per) : NULL;
    if (check && !per) {
      cli_error("impostor: out of memory");
      rc = EXIT_RESOURCES;
    } else if (check && bbc_impostor_check(&m, &imp, per, &worst, &mean, &err) != BBC_OK) {
      rc = cli_fail(&err, 0);
    } else if (check) {
      int at = 0;
      for (int k = 1; k < imp.frames * imp.frames; k++)
        if (per[k] < per[at]) at = k;
      printf("frames against the model: block IoU worst %.3f (frame %d, %d), mean %.3f\n", worst,
             at % imp.frames, at / imp.frames, mean);
    }
    free(per);
  }
  bbc_impostor_free(&imp);
  bbc_mesh_free(&m);
  return rc;
}
