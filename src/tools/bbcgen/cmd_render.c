/* cmd_render.c — `bbcgen render`: a model seen from the front, the side and
 * above, side by side in one PNG, through the library's software rasterizer. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int render_views_png(const bbc_mesh *m, int z_up, int size, int lighting, const char *out_path) {
  /* Directions are camera -> model. */
  static const double y_dirs[3][3] = {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}};
  static const double y_ups[3][3] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}};
  static const double z_dirs[3][3] = {{0, 1, 0}, {-1, 0, 0}, {0, 0, -1}};
  static const double z_ups[3][3] = {{0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
  bbc_image sheet, view_img;
  bbc_error err;
  if (bbc_image_alloc(&sheet, 3 * size, size) != BBC_OK ||
      bbc_image_alloc(&view_img, size, size) != BBC_OK) {
    bbc_image_free(&sheet);
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  for (int v = 0; v < 3; v++) {
    bbc_view view;
    bbc_view_frame_mesh(m, z_up ? z_dirs[v] : y_dirs[v], z_up ? z_ups[v] : y_ups[v], &view);
    view.lighting = lighting;
    if (bbc_render_ortho(m, &view, &view_img, &err) != BBC_OK) {
      bbc_image_free(&sheet);
      bbc_image_free(&view_img);
      return cli_fail(&err, 0);
    }
    for (int y = 0; y < size; y++)
      memcpy(sheet.rgba + 4 * ((size_t)y * sheet.width + (size_t)v * size),
             view_img.rgba + 4 * (size_t)y * size, 4 * (size_t)size);
  }
  bbc_image_free(&view_img);
  bbc_result r = bbc_image_write_png(out_path, &sheet, &err);
  bbc_image_free(&sheet);
  if (r != BBC_OK) return cli_fail(&err, 1);
  return EXIT_OK;
}

int cmd_render(cli *c, int argc, char **argv) {
  const char *path = NULL, *out = NULL;
  int size = 512, z_up = 0, lighting = 1;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *a = argv[i];
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(a, "--size")) {
      const char *v = cli_option_value(argc, argv, &i);
      long long n = v ? cli_parse_count(a, v, 8192) : -1;
      if (n < 16) {
        if (n >= 0) cli_error("render: --size must be at least 16");
        return EXIT_USAGE;
      }
      size = (int)n;
    } else if (!strcmp(a, "--up")) {
      const char *v = cli_option_value(argc, argv, &i);
      if (!v) return EXIT_USAGE;
      if (!strcmp(v, "y") || !strcmp(v, "Y"))
        z_up = 0;
      else if (!strcmp(v, "z") || !strcmp(v, "Z"))
        z_up = 1;
      else {
        cli_error("render: --up must be y or z, not '%s'", v);
        return EXIT_USAGE;
      }
    } else if (!strcmp(a, "--unlit")) {
      lighting = 0;
    } else if (a[0] == '-' && a[1]) {
      static const char *const own[] = {"-o", "--output", "--size", "--up", "--unlit", NULL};
      return cli_unknown_option("render", a, own);
    } else if (!path) {
      path = a;
    } else {
      cli_error("render: one model at a time");
      return EXIT_USAGE;
    }
  }
  if (!path || !out) {
    cli_error("render: usage: bbcgen render MODEL -o OUT.png [--size PX] [--up y|z]");
    return EXIT_USAGE;
  }
  size_t n = strlen(out);
  if (n < 5 || strcasecmp(out + n - 4, ".png")) {
    cli_error("render: the output must be a .png file, not '%s'", out);
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out)) return EXIT_OUTPUT;
  bbc_load_options opt;
  cli_load_options(c, &opt);
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &opt, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  double t0 = cli_now();
  int rc = render_views_png(&m, z_up, size, lighting, out);
  if (rc == EXIT_OK) cli_info(c, "wrote %s (%.2f s)", out, cli_now() - t0);
  bbc_mesh_free(&m);
  return rc;
}
