/* cmd_tree.c — `bbcgen tree`: the built-in procedural tree as OBJ+MTL+PNG. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int cmd_tree(cli *c, int argc, char **argv) {
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1;           /* bbcgen's default tree */
  opt.texture_size = 128; /* (0 from --texture-size is refused below) */
  opt.callbacks = c->callbacks;
  const char *out = NULL, *preview = NULL;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *a = argv[i];
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(a, "--preview")) {
      if (!(preview = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(a, "--seed")) {
      const char *v = cli_option_value(argc, argv, &i);
      long long s = v ? cli_parse_count(a, v, 0x7fffffffffffffffLL) : -1;
      if (s < 0) return EXIT_USAGE;
      opt.seed = (uint64_t)s;
    } else if (!strcmp(a, "--leaves")) {
      const char *v = cli_option_value(argc, argv, &i);
      long long n = v ? cli_parse_count(a, v, 5000000) : -1;
      if (n < 0) return EXIT_USAGE;
      opt.leaves = (size_t)n;
    } else if (!strcmp(a, "--texture-size")) {
      const char *v = cli_option_value(argc, argv, &i);
      long long n = v ? cli_parse_count(a, v, 4096) : -1;
      if (n < 0) return EXIT_USAGE;
      opt.texture_size = (int)n;
    } else if (!strcmp(a, "--species")) {
      const char *v = cli_option_value(argc, argv, &i);
      if (!v) return EXIT_USAGE;
      int s = bbc_tree_species_from_name(v);
      if (s < 0) {
        cli_error(
            "tree: unknown species '%s' (oak, pine, birch, bush, larch, weeping, winter, palm)", v);
        return EXIT_USAGE;
      }
      opt.species = (bbc_tree_species)s;
    } else {
      static const char *const own[] = {"-o",       "--output",       "--preview", "--seed",
                                        "--leaves", "--texture-size", "--species", NULL};
      return cli_unknown_option("tree", a, own);
    }
  }
  if (!out) {
    cli_error("tree: where to? usage: bbcgen tree [--seed S] [--leaves N] [--species NAME] "
              "-o OUT.obj");
    return EXIT_USAGE;
  }
  size_t n = strlen(out);
  if (n < 5 || strcasecmp(out + n - 4, ".obj")) {
    cli_error("tree: the output must be an .obj file (OBJ + MTL + PNG), not '%s'", out);
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  bbc_mesh m;
  bbc_error err;
  double t0 = cli_now();
  if (opt.texture_size == 0) { /* the library would take 0 for its default */
    err.code = BBC_ERROR_INVALID_ARGUMENT;
    snprintf(err.message, sizeof err.message,
             "tree generator: texture size 0 must be a power of two from 8 to 4096");
    return cli_fail(&err, 0);
  }
  if (bbc_tree_generate(&opt, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t1 = cli_now();
  if (bbc_mesh_write_obj(out, &m, NULL, &err) != BBC_OK) {
    bbc_mesh_free(&m);
    return cli_fail(&err, 1);
  }
  double t2 = cli_now();
  size_t *counts = calloc(m.group_count ? m.group_count : 1, sizeof *counts);
  if (counts) {
    bbc_mesh_count_group_triangles(&m, counts);
    cli_info(c,
             "wrote %s: %s tree, seed %llu, %zu triangles (%s %zu, %s %zu), height %.2f m; "
             "generated in %.3f s, written in %.3f s",
             out, bbc_tree_species_name(opt.species), (unsigned long long)opt.seed,
             m.triangle_count, m.group_names[0], counts[0],
             m.group_count > 1 ? m.group_names[1] : "-", m.group_count > 1 ? counts[1] : 0,
             m.bbox_max[1] - m.bbox_min[1], t1 - t0, t2 - t1);
    free(counts);
  }
  int rc = EXIT_OK;
  if (preview) {
    rc = render_views_png(&m, 0, 512, 1, preview);
    if (rc == EXIT_OK) cli_info(c, "wrote %s", preview);
  }
  bbc_mesh_free(&m);
  return rc;
}

/* bbcgen sample MODEL -o OUT.ply [--points N] [--seed S] [--normals]: a
 * point cloud on the model's surface (test input for the point-cloud path,
 * thesis 2.4), with the surface's normals when asked (a scan's PLY). */
int cmd_sample(cli *c, int argc, char **argv) {
  const char *model = NULL, *out = NULL;
  long long points = 1000000, seed = 1;
  int normals = 0;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *a = argv[i];
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(a, "--normals")) {
      normals = 1;
    } else if (!strcmp(a, "--points") || !strcmp(a, "--seed")) {
      const char *v = cli_option_value(argc, argv, &i);
      long long n =
          v ? cli_parse_count(a, v, a[2] == 'p' ? 1000000000LL : 0x7fffffffffffffffLL) : -1;
      if (n < 0 || (a[2] == 'p' && n < 1)) {
        if (n == 0) cli_error("sample: --points must be at least 1");
        return EXIT_USAGE;
      }
      *(a[2] == 'p' ? &points : &seed) = n;
    } else if (a[0] != '-' && !model) {
      model = a;
    } else {
      static const char *const own[] = {"-o", "--output", "--points", "--seed", "--normals", NULL};
      return cli_unknown_option("sample", a, own);
    }
  }
  size_t n = out ? strlen(out) : 0;
  if (!model || !out || n < 5 || strcasecmp(out + n - 4, ".ply")) {
    cli_error("sample: usage: bbcgen sample MODEL -o OUT.ply [--points N] [--seed S] [--normals]");
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_mesh m, p;
  bbc_error err;
  if (bbc_mesh_load(model, &lo, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t0 = cli_now();
  bbc_result r = bbc_mesh_sample_points(&m, (size_t)points, (uint64_t)seed, &p, &err);
  bbc_mesh_free(&m);
  if (r != BBC_OK) return cli_fail(&err, 0);
  if (!normals) {
    free(p.normals);
    p.normals = NULL;
  }
  r = bbc_points_write_ply(out, &p, &err);
  if (r == BBC_OK)
    cli_info(c, "wrote %s: %zu points on %s's surface (seed %lld) in %.2f s", out, p.vertex_count,
             model, seed, cli_now() - t0);
  bbc_mesh_free(&p);
  return r == BBC_OK ? EXIT_OK : cli_fail(&err, 1);
}
