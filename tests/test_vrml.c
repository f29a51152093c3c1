/* test_vrml.c — VRML output of a Billboard Cloud: the file's text parsed
 * back against the cloud's mesh (one Shape per billboard side, outlines as
 * one polygon wound like the triangles, texture coordinates), the PNG atlases
 * beside it, format 0 / 1, refused paths writing nothing, determinism. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include "bbc.h"
#include "test_util.h"

/* ---- a small cloud --------------------------------------------------------- */

/* Two planes: z = 0 (the unit square, a red triangle in front, a blue one
 * behind) and x = 2 (a square in y, z with a red triangle in front). The
 * squares use an invisible material; they fix the billboards. */
static void add_tri(bbc_mesh *m, const double p[3][3], uint32_t material) {
  tu_mesh_tri(m, p[0], p[1], p[2], material);
}

static void build_cloud(int back_images, int normal_maps, bbc_cloud *cl) {
  enum { MAX_TRIS = 8 };
  static const float col[3][4] = {{1, 1, 1, 0}, {1, 0, 0, 1}, {0, 0, 1, 1}};
  static const char *const names[3] = {"frame", "red", "blue"};
  bbc_mesh m;
  tu_mesh_begin(&m, MAX_TRIS, 3, names, col, "all");
  /* Plane 0: z = 0. */
  add_tri(&m, (const double[3][3]){{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 0);
  add_tri(&m, (const double[3][3]){{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}, 0);
  add_tri(&m, (const double[3][3]){{0.05, 0.05, 0.004}, {0.45, 0.05, 0.004}, {0.05, 0.95, 0.004}},
          1);
  add_tri(&m,
          (const double[3][3]){{0.02, 0.02, -0.004}, {0.98, 0.02, -0.004}, {0.02, 0.98, -0.004}},
          2);
  /* Plane 1: x = 2, normal +x. */
  add_tri(&m, (const double[3][3]){{2, 0, 0}, {2, 1, 0}, {2, 1, 1}}, 0);
  add_tri(&m, (const double[3][3]){{2, 0, 0}, {2, 1, 1}, {2, 0, 1}}, 0);
  add_tri(&m, (const double[3][3]){{2.003, 0.1, 0.1}, {2.003, 0.8, 0.1}, {2.003, 0.1, 0.7}}, 1);
  bbc_error err;
  if (bbc_mesh_finalize(&m, 0, "vrml scene", &err) != BBC_OK) fail_msg("%s", err.message);
  const uint32_t face_plane[7] = {0, 0, 0, 0, 1, 1, 1};
  assert_int_equal(m.triangle_count, 7);

  bbc_planeset s;
  memset(&s, 0, sizeof s);
  s.radius = m.radius;
  s.epsilon_abs = 0.01;
  s.plane_count = 2;
  s.planes = calloc(2, sizeof *s.planes);
  for (int i = 0; i < 2; i++) {
    s.planes[i].normal[i == 0 ? 2 : 0] = 1;
    s.planes[i].d = i == 0 ? 0 : 2;
    s.planes[i].kind = i == 0 ? BBC_PLANE_STANDARD : BBC_PLANE_COPLANAR;
    s.planes[i].face_count = i == 0 ? 4 : 3;
    s.planes[i].area = 1;
    s.planes[i].mother = -1;
    s.planes[i].coverage_pct = 100;
  }
  s.face_count = 7;
  s.face_plane = calloc(7, sizeof *s.face_plane);
  memcpy(s.face_plane, face_plane, sizeof face_plane);
  s.face_part = calloc(7, sizeof *s.face_part);
  s.part_count = 1;
  s.parts = calloc(1, sizeof *s.parts);
  strcpy(s.parts[0].name, "all");
  s.parts[0].epsilon_abs = 0.01;
  s.parts[0].face_count = 7;
  s.parts[0].plane_count = 2;

  bbc_params p;
  bbc_params_default(&p);
  p.texres = 32;
  p.atlas_max = 0;
  p.quality = 0;
  p.prelight = 0;
  p.threads = 1;
  p.back_images = back_images;
  p.normal_maps = normal_maps;
  if (bbc_cloud_build(&m, &s, &p, NULL, cl, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(cl->billboard_count, 2);
  assert_int_equal(cl->mesh.materials[0].single_sided, back_images);
  assert_int_equal(cl->mesh.materials[0].normal_map, normal_maps ? 2 : 0);
  bbc_mesh_free(&m);
  bbc_planeset_free(&s);
}

/* ---- helpers --------------------------------------------------------------- */

static char *path_in(const char *dir, const char *name) {
  size_t n = strlen(dir) + strlen(name) + 2;
  char *p = malloc(n);
  assert_non_null(p);
  snprintf(p, n, "%s/%s", dir, name);
  return p;
}

/* A fresh empty folder tu_dir/name; caller frees. */
static char *sub_dir(const char *name) {
  char *d = path_in(tu_dir, name);
  assert_int_equal(mkdir(d, 0777), 0);
  return d;
}

static int entries(const char *dir) {
  DIR *d = opendir(dir);
  assert_non_null(d);
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
  closedir(d);
  return n;
}

static int file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

static size_t count(const char *s, const char *needle) {
  size_t n = 0;
  for (const char *p = strstr(s, needle); p; p = strstr(p + 1, needle)) n++;
  return n;
}

/* Numbers of the list opened by the first '[' after `key` in [s, end), into
 * v[max]; returns how many (the list must close before end). */
static size_t parse_list(const char *s, const char *end, const char *key, double *v, size_t max) {
  const char *p = strstr(s, key);
  assert_true(p != NULL && p < end);
  p = strchr(p, '[');
  assert_non_null(p);
  p++;
  size_t n = 0;
  for (;;) {
    while (*p == ' ' || *p == '\n' || *p == ',') p++;
    if (*p == ']') break;
    char *q;
    double x = strtod(p, &q);
    assert_true(q != p);
    assert_true(n < max);
    v[n++] = x;
    p = q;
  }
  assert_true(p < end);
  return n;
}

/* Checks the Shapes of a written file against the cloud's mesh. */
static void check_shapes(const char *text, const bbc_cloud *cl, const char *stem, int nm_nodes) {
  const bbc_mesh *m = &cl->mesh;
  int sides = m->materials[0].single_sided ? 2 : 1;
  assert_int_equal(count(text, "Shape {"), sides * cl->billboard_count);
  assert_int_equal(count(text, "IndexedFaceSet {"), sides * cl->billboard_count);
  char url[300];
  snprintf(url, sizeof url, "url \"%s_wrl_billboards.png\" repeatS FALSE repeatT FALSE", stem);
  assert_int_equal(count(text, url), sides * cl->billboard_count);
  assert_int_equal(count(text, sides == 2 ? "solid TRUE" : "solid FALSE"),
                   sides * cl->billboard_count);
  assert_int_equal(count(text, sides == 2 ? "solid FALSE" : "solid TRUE"), 0);
  assert_int_equal(count(text, "ccw TRUE"), sides * cl->billboard_count);
  snprintf(url, sizeof url, "NormalMap { url \"%s_wrl_billboards_nm.png\" }", stem);
  assert_int_equal(count(text, url), nm_nodes ? sides * cl->billboard_count : 0);

  size_t base = 0, tri = 0;
  const char *p = text;
  for (size_t k = 0; k < cl->billboard_count; k++) {
    const bbc_cloud_billboard *b = &cl->billboards[k];
    int n = b->corner_count;
    char line[200];
    snprintf(line, sizeof line, "# billboard %zu: %s plane, part 0 (all), %d corners\n", k,
             bbc_plane_kind_name(b->kind), n);
    assert_non_null(strstr(text, line));
    for (int side = 0; side < sides; side++, base += (size_t)n) {
      char def[64];
      snprintf(def, sizeof def, "DEF BB%zu_%s Shape {", k, side ? "back" : "front");
      const char *shape = strstr(p, def);
      assert_non_null(shape);
      /* Shapes come in order: billboard k front, then back. */
      assert_ptr_equal(shape + strlen(def) - strlen("Shape {"), strstr(p, "Shape {"));
      const char *end = strstr(shape + strlen(def), "Shape {");
      if (!end) end = text + strlen(text);
      double v[64];
      /* Coordinates: the outline's corners, as in the mesh. */
      size_t np = parse_list(shape, end, "coord Coordinate { point", v, 64);
      assert_int_equal(np, 3 * (size_t)n);
      for (size_t i = 0; i < np; i++)
        assert_true(fabs(v[i] - m->positions[3 * base + i]) <= 1e-7 * (1 + fabs(v[i])));
      size_t nt = parse_list(shape, end, "texCoord TextureCoordinate { point", v, 64);
      assert_int_equal(nt, 2 * (size_t)n);
      for (size_t i = 0; i < nt; i++) assert_true(fabs(v[i] - m->uvs[2 * base + i]) <= 1e-6);
      /* One polygon, wound like the side's triangles, ended by -1. */
      size_t ni = parse_list(shape, end, "coordIndex", v, 64);
      assert_int_equal(ni, (size_t)n + 1);
      assert_true(v[n] == -1);
      for (int c = 0; c < n; c++) assert_true(v[c] == (side ? n - 1 - c : c));
      /* Every triangle of the side winds the same way round the polygon. */
      for (int i = 0; i < n - 2; i++, tri++) {
        int pos[3];
        for (int j = 0; j < 3; j++) {
          pos[j] = -1;
          for (int c = 0; c < n; c++)
            if (m->indices[3 * tri + (size_t)j] == base + (size_t)v[c]) pos[j] = c;
          assert_true(pos[j] >= 0);
        }
        assert_true((pos[1] - pos[0] + n) % n < (pos[2] - pos[0] + n) % n);
      }
      p = shape + strlen(def);
    }
  }
  assert_int_equal(base, m->vertex_count);
  assert_int_equal(tri, m->triangle_count);
}

static char *read_text(const char *path) {
  char *s = (char *)tu_read_file(path, NULL);
  assert_non_null(s);
  return s;
}

static void check_png(const char *path, const bbc_image *expected) {
  bbc_image img;
  bbc_error err;
  if (bbc_image_load(path, &img, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(img.width, expected->width);
  assert_int_equal(img.height, expected->height);
  assert_memory_equal(img.rgba, expected->rgba, (size_t)img.width * img.height * 4);
  bbc_image_free(&img);
}

/* ---- tests ----------------------------------------------------------------- */

static void test_formats_with_back_images_and_normal_maps(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(1, 1, &cl);
  char *dir = sub_dir("both");
  bbc_error err;
  for (int format = 0; format <= 1; format++) {
    char name[64], stem[16];
    snprintf(stem, sizeof stem, "cloud%d", format);
    snprintf(name, sizeof name, "%s.wrl", stem);
    char *wrl = path_in(dir, name);
    if (bbc_cloud_write_vrml(wrl, &cl,
                             &(bbc_vrml_options){.format = (bbc_vrml_format)format,
                                                 .comment = "made by test_vrml\nsecond line"},
                             &err) != BBC_OK)
      fail_msg("%s", err.message);
    char *text = read_text(wrl);
    assert_true(!strncmp(text, "#VRML V2.0 utf8\n", 16));
    assert_true(
        !strncmp(text + 16,
                 "# Billboard Cloud: 2 billboards, written by bbcgen " BBC_VERSION_STRING
                 "\n# made by test_vrml\n# second line\n",
                 strlen("# Billboard Cloud: 2 billboards, written by bbcgen " BBC_VERSION_STRING
                        "\n# made by test_vrml\n# second line\n")));
    check_shapes(text, &cl, stem, format == 0);
    if (format == 0) {
      assert_int_equal(
          count(text, "PROTO NormalMap [ exposedField MFString url [] ] { Group { } }"), 1);
    } else {
      assert_null(strstr(text, "NormalMap"));
      assert_null(strstr(text, "PROTO"));
    }
    snprintf(name, sizeof name, "%s_wrl_billboards.png", stem);
    char *png = path_in(dir, name);
    check_png(png, &cl.mesh.textures[0].image);
    snprintf(name, sizeof name, "%s_wrl_billboards_nm.png", stem);
    char *nm = path_in(dir, name);
    if (format == 0)
      check_png(nm, &cl.mesh.textures[1].image);
    else /* VRML97 has no normal maps: no unreferenced file beside it */
      assert_int_equal(access(nm, F_OK), -1);
    free(text);
    free(wrl);
    free(png);
    free(nm);
  }
  assert_int_equal(entries(dir), 5); /* no temporary files left */
  free(dir);
  bbc_cloud_free(&cl);
}

static void test_double_sided_without_back_images(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(0, 0, &cl);
  char *dir = sub_dir("single");
  char *wrl = path_in(dir, "one.wrl");
  bbc_error err;
  if (bbc_cloud_write_vrml(wrl, &cl, &(bbc_vrml_options){.comment = "a\r\n\nb\n"}, &err) != BBC_OK)
    fail_msg("%s", err.message);
  char *text = read_text(wrl);
  assert_non_null(strstr(text, BBC_VERSION_STRING "\n# a\n#\n# b\n# format 0"));
  assert_int_equal(count(text, "Shape {"), cl.billboard_count);
  assert_int_equal(count(text, "solid FALSE"), cl.billboard_count);
  assert_null(strstr(text, "_back"));
  assert_null(strstr(text, "NormalMap")); /* format 0 without normal maps */
  check_shapes(text, &cl, "one", 0);
  assert_int_equal(entries(dir), 2); /* one.wrl, one_wrl_billboards.png */
  free(text);
  /* A name outside the URL-safe characters: the file keeps it, the url
   * percent-encodes it. */
  char *spaced = path_in(dir, "my cloud#1.wrl");
  if (bbc_cloud_write_vrml(spaced, &cl, &(bbc_vrml_options){.format = BBC_VRML_97}, &err) != BBC_OK)
    fail_msg("%s", err.message);
  text = read_text(spaced);
  check_shapes(text, &cl, "my%20cloud%231", 0);
  char *spaced_png = path_in(dir, "my cloud#1_wrl_billboards.png");
  check_png(spaced_png, &cl.mesh.textures[0].image);
  assert_int_equal(entries(dir), 4);
  free(spaced_png);
  free(spaced);
  free(text);
  free(wrl);
  free(dir);
  bbc_cloud_free(&cl);
}

/* Under a locale with a decimal comma (a library caller may call
 * setlocale) the file is the same, byte for byte, as in the C locale:
 * numbers spelt with '.'. Skipped only where no such locale is installed
 * (scripts/dev/setup.sh makes de_DE.UTF-8). */
static void test_decimal_comma_locale(void **state) {
  (void)state;
  static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8",
                                      NULL};
  bbc_cloud cl;
  build_cloud(0, 0, &cl);
  char *dir = sub_dir("locale");
  char *c_wrl = path_in(dir, "c.wrl"), *comma_wrl = path_in(dir, "comma.wrl");
  bbc_error err;
  assert_int_equal(bbc_cloud_write_vrml(c_wrl, &cl, NULL, &err), BBC_OK);
  const char *got = NULL;
  for (int i = 0; names[i] && !got; i++)
    if (setlocale(LC_NUMERIC, names[i])) got = names[i];
  char probe[16];
  snprintf(probe, sizeof probe, "%.2f", 0.5);
  int comma = got && !strcmp(probe, "0,50");
  bbc_result r = got ? bbc_cloud_write_vrml(comma_wrl, &cl, NULL, &err) : BBC_OK;
  setlocale(LC_NUMERIC, "C");
  if (!got) {
    fprintf(stderr, "no locale with a decimal comma installed: test skipped\n");
  } else {
    assert_true(comma);
    assert_int_equal(r, BBC_OK);
    char *a = read_text(c_wrl), *b = read_text(comma_wrl);
    /* the same but for the textures' names, which follow the file's */
    size_t n = strlen(b), k = 0;
    char *c = malloc(n + 1);
    assert_non_null(c);
    for (size_t i = 0; i < n;)
      if (!strncmp(b + i, "comma_wrl", 9)) {
        memcpy(c + k, "c_wrl", 5);
        k += 5;
        i += 9;
      } else {
        c[k++] = b[i++];
      }
    c[k] = 0;
    assert_string_equal(a, c);
    free(c);
    free(a);
    free(b);
  }
  free(c_wrl);
  free(comma_wrl);
  free(dir);
  bbc_cloud_free(&cl);
  if (!got) skip();
}

static void test_refused_paths_write_nothing(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(1, 1, &cl);
  char *dir = sub_dir("refused");
  bbc_error err;
  const char *bad[] = {"cloud.obj", "cloud.vrml", "cloud", ".wrl", "cloud.wrl.png"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    char *p = path_in(dir, bad[i]);
    assert_int_equal(bbc_cloud_write_vrml(p, &cl, &(bbc_vrml_options){.format = BBC_VRML_97}, &err),
                     BBC_ERROR_INVALID_ARGUMENT);
    assert_true(strlen(err.message) > 0);
    free(p);
  }
  char *wrl = path_in(dir, "cloud.wrl");
  assert_int_equal(
      bbc_cloud_write_vrml(wrl, &cl, &(bbc_vrml_options){.format = (bbc_vrml_format)2}, &err),
      BBC_ERROR_INVALID_ARGUMENT);
  bbc_cloud empty;
  memset(&empty, 0, sizeof empty);
  assert_int_equal(bbc_cloud_write_vrml(wrl, &empty, NULL, &err), BBC_ERROR_EMPTY);
  assert_int_equal(entries(dir), 0);
  /* A missing folder: an error, and nothing anywhere. */
  char *missing = path_in(dir, "missing/cloud.wrl");
  assert_int_not_equal(bbc_cloud_write_vrml(missing, &cl, NULL, &err), BBC_OK);
  assert_int_equal(err.code, BBC_ERROR_IO);
  assert_int_equal(entries(dir), 0);
  assert_false(file_exists(missing));
  free(missing);
  free(wrl);
  free(dir);
  bbc_cloud_free(&cl);
}

/* Read back (src/io/load_vrml.c): both formats (format 0 declares a PROTO
 * for its normal maps) give the cloud's triangles, texture coordinates and
 * atlas; damaged files are refused with file:line. */
/* BBC_VRML_DDS: the atlas also as a DDS with its mip levels (those of
 * bbc_image_mipmaps, alpha 0/255), named first in every url; reading the
 * .wrl back takes the PNG after it. */
static uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void count_texture_warning(void *user, bbc_log_level level, const char *msg) {
  if (level == BBC_LOG_WARNING && strstr(msg, "cannot be read")) ++*(int *)user;
}

static void test_dds_mip_levels(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(1, 0, &cl);
  const bbc_image *atlas = &cl.mesh.textures[0].image;
  assert_true(bbc_image_has_transparency(atlas));
  char *dir = sub_dir("dds");
  char *wrl = path_in(dir, "d.wrl"), *dds = path_in(dir, "d_wrl_billboards.dds");
  bbc_error err;
  if (bbc_cloud_write_vrml(wrl, &cl, &(bbc_vrml_options){.format = BBC_VRML_97, .dds = 1}, &err) !=
      BBC_OK)
    fail_msg("%s", err.message);
  char *text = read_text(wrl);
  assert_int_equal(count(text, "url [ \"d_wrl_billboards.dds\" \"d_wrl_billboards.png\" ]"), 4);
  assert_int_equal(count(text, "url"), 4);
  size_t size = 0;
  unsigned char *f = tu_read_file(dds, &size);
  assert_non_null(f);
  bbc_image *lv = NULL;
  int n = 0;
  if (bbc_image_mipmaps(atlas, &lv, &n, &err) != BBC_OK) fail_msg("%s", err.message);
  int side = atlas->width > atlas->height ? atlas->width : atlas->height, want = 1;
  while (side > 1) {
    side /= 2;
    want++;
  }
  assert_int_equal(n + 1, want); /* down to 1 x 1 */
  size_t total = 128 + (size_t)atlas->width * atlas->height * 4;
  for (int l = 0; l < n; l++) total += (size_t)lv[l].width * lv[l].height * 4;
  assert_int_equal(size, total);
  assert_memory_equal(f, "DDS ", 4);
  assert_int_equal(le32(f + 4), 124);
  assert_int_equal(le32(f + 12), atlas->height);
  assert_int_equal(le32(f + 16), atlas->width);
  assert_int_equal(le32(f + 28), n + 1);
  assert_int_equal(le32(f + 80), 0x41); /* RGB with alpha, 32 bits, R lowest */
  assert_int_equal(le32(f + 88), 32);
  assert_int_equal(le32(f + 92), 0xff);
  assert_int_equal(le32(f + 104), 0xff000000u);
  const unsigned char *px = f + 128;
  assert_memory_equal(px, atlas->rgba, (size_t)atlas->width * atlas->height * 4);
  px += (size_t)atlas->width * atlas->height * 4;
  for (int l = 0; l < n; l++) {
    size_t bytes = (size_t)lv[l].width * lv[l].height * 4;
    assert_memory_equal(px, lv[l].rgba, bytes);
    for (size_t i = 3; i < bytes; i += 4) assert_true(px[i] == 0 || px[i] == 255);
    px += bytes;
    bbc_image_free(&lv[l]);
  }
  free(lv);
  bbc_mesh m;
  if (bbc_mesh_load(wrl, NULL, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(m.texture_count, 1);
  const char *tp = m.textures[0].path;
  assert_true(strlen(tp) > 20 && !strcmp(tp + strlen(tp) - 20, "d_wrl_billboards.png"));
  assert_int_equal(m.textures[0].image.width, atlas->width);
  bbc_mesh_free(&m);
  assert_int_equal(entries(dir), 3); /* .wrl, .png, .dds; no temporary files */
  /* Without the PNG: said once, and the shapes keep their colour (as a
   * missing map_Kd) instead of drawing an empty texture. */
  char *png = path_in(dir, "d_wrl_billboards.png");
  assert_int_equal(remove(png), 0);
  int warnings = 0;
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.callbacks.log = count_texture_warning;
  lo.callbacks.user = &warnings;
  if (bbc_mesh_load(wrl, &lo, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(warnings, 1);
  for (size_t i = 0; i < m.material_count; i++) {
    assert_int_equal(m.materials[i].texture, -1);
    assert_non_null(m.materials[i].texture_ref);
  }
  bbc_mesh_free(&m);
  free(png);
  free(f);
  free(text);
  free(wrl);
  free(dds);
  free(dir);
  bbc_cloud_free(&cl);
}

static void test_read_back(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(1, 1, &cl);
  char *dir = sub_dir("read");
  bbc_error err;
  for (int format = 0; format <= 1; format++) {
    char name[32];
    snprintf(name, sizeof name, "r %d.wrl", format); /* a space: its url is escaped */
    char *wrl = path_in(dir, name);
    if (bbc_cloud_write_vrml(wrl, &cl, &(bbc_vrml_options){.format = (bbc_vrml_format)format},
                             &err) != BBC_OK)
      fail_msg("%s", err.message);
    bbc_mesh m;
    if (bbc_mesh_load(wrl, NULL, &m, &err) != BBC_OK) fail_msg("%s", err.message);
    assert_int_equal(m.triangle_count, cl.mesh.triangle_count);
    assert_int_equal(m.material_count, 1);
    assert_true(m.materials[0].unlit == cl.mesh.materials[0].unlit);
    assert_true(m.materials[0].single_sided == cl.mesh.materials[0].single_sided);
    assert_int_equal(m.textures[0].image.width, cl.mesh.textures[0].image.width);
    for (int k = 0; k < 3; k++) {
      assert_true(fabs(m.bbox_min[k] - cl.mesh.bbox_min[k]) < 1e-6 * (1 + cl.mesh.radius));
      assert_true(fabs(m.bbox_max[k] - cl.mesh.bbox_max[k]) < 1e-6 * (1 + cl.mesh.radius));
    }
    /* Every corner read is a corner of the cloud with its texture
     * coordinates (polygons may be fanned from another corner), and the
     * area is the cloud's. */
    double area[2] = {0, 0};
    const bbc_mesh *ms[2] = {&m, &cl.mesh};
    for (int w = 0; w < 2; w++)
      for (size_t t = 0; t < ms[w]->triangle_count; t++) {
        double c[3];
        const uint32_t *ix = ms[w]->indices + 3 * t;
        const double *p0 = ms[w]->positions + 3 * ix[0], *p1 = ms[w]->positions + 3 * ix[1],
                     *p2 = ms[w]->positions + 3 * ix[2];
        double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        c[0] = e1[1] * e2[2] - e1[2] * e2[1];
        c[1] = e1[2] * e2[0] - e1[0] * e2[2];
        c[2] = e1[0] * e2[1] - e1[1] * e2[0];
        area[w] += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      }
    assert_true(fabs(area[0] - area[1]) < 1e-6 * (1 + area[1]));
    double tol = 1e-6 * (1 + cl.mesh.radius);
    for (size_t v = 0; v < m.vertex_count; v++) {
      int found = 0;
      for (size_t u = 0; u < cl.mesh.vertex_count && !found; u++) {
        found = 1;
        for (int k = 0; k < 3; k++)
          found &= fabs(m.positions[3 * v + k] - cl.mesh.positions[3 * u + k]) < tol;
        for (int k = 0; k < 2; k++) found &= fabs(m.uvs[2 * v + k] - cl.mesh.uvs[2 * u + k]) < 1e-6;
      }
      assert_true(found);
    }
    bbc_mesh_free(&m);
    free(wrl);
  }
  static const struct {
    const char *text, *needle;
  } bad[] = {
      {"#VRML V2.0 utf8\nShape { geometry IndexedFaceSet {\n", "not closed"},
      {"#VRML V2.0 utf8\nUSE Nothing\n", "no DEF"},
      {"#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 "
       "0, 0 1 0 ] }\n coordIndex [ 0 1 7 -1 ] } }\n",
       ":3: a coordIndex"},
      {"#VRML V2.0 utf8\nShape { geometry IndexedFaceSet { coord Coordinate { point [ 0 0 x ] } "
       "} }\n",
       ":2: field 'point'"},
      {"#VRML V1.0 ascii\nSeparator { }\n", "VRML 2.0"},
      {"#VRML V2.0 utf8\nShape { geometry Box { } }\n", "no IndexedFaceSet"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    char name[32];
    snprintf(name, sizeof name, "bad%zu.wrl", i);
    char *wrl = path_in(dir, name);
    FILE *f = fopen(wrl, "w");
    assert_non_null(f);
    fputs(bad[i].text, f);
    fclose(f);
    bbc_mesh m;
    memset(&err, 0, sizeof err);
    if (bbc_mesh_load(wrl, NULL, &m, &err) == BBC_OK) fail_msg("%s accepted", name);
    if (!strstr(err.message, name) || !strstr(err.message, bad[i].needle))
      fail_msg("%s: '%s' lacks '%s'", name, err.message, bad[i].needle);
    free(wrl);
  }
  /* Deep nesting is refused, not a stack overflow. */
  char *deep = path_in(dir, "deep.wrl");
  FILE *f = fopen(deep, "w");
  assert_non_null(f);
  fputs("#VRML V2.0 utf8\n", f);
  for (int i = 0; i < 5000; i++) fputs("Group { children [ ", f);
  fclose(f);
  bbc_mesh m;
  assert_int_not_equal(bbc_mesh_load(deep, NULL, &m, &err), BBC_OK);
  assert_non_null(strstr(err.message, "deeply"));
  free(deep);
  free(dir);
  bbc_cloud_free(&cl);
}

static void test_deterministic(void **state) {
  (void)state;
  bbc_cloud cl;
  build_cloud(1, 1, &cl);
  char *dirs[2] = {sub_dir("det_a"), sub_dir("det_b")};
  const char *names[3] = {"c.wrl", "c_wrl_billboards.png", "c_wrl_billboards_nm.png"};
  unsigned char *first[3] = {0};
  size_t first_size[3] = {0};
  bbc_error err;
  for (int run = 0; run < 3; run++) { /* a, b, and a again over the first files */
    char *wrl = path_in(dirs[run == 1], "c.wrl");
    if (bbc_cloud_write_vrml(wrl, &cl, &(bbc_vrml_options){.comment = "same"}, &err) != BBC_OK)
      fail_msg("%s", err.message);
    free(wrl);
    for (int f = 0; f < 3; f++) {
      char *p = path_in(dirs[run == 1], names[f]);
      size_t size = 0;
      unsigned char *data = tu_read_file(p, &size);
      assert_non_null(data);
      if (run == 0) {
        first[f] = data;
        first_size[f] = size;
      } else {
        assert_int_equal(size, first_size[f]);
        assert_memory_equal(data, first[f], size);
        free(data);
      }
      free(p);
    }
  }
  assert_int_equal(entries(dirs[0]), 3);
  for (int f = 0; f < 3; f++) free(first[f]);
  free(dirs[0]);
  free(dirs[1]);
  bbc_cloud_free(&cl);
}

/* A scan whose cloud has a billboard with a degenerate outline (its points
 * on one line): the mesh dropped that outline's zero-area triangles, and the
 * file still has every billboard's polygon. The rectangle of a plane whose
 * points lie in one spot is the same with any thread count. */
static void test_point_cloud_degenerate_outline(void **state) {
  (void)state;
  char path[1024];
  if (!tu_have_file(tu_data_path(path, sizeof path, "points/adtree/tree13.xyz"))) {
    skip();
    return;
  }
  bbc_error err;
  bbc_mesh m;
  if (bbc_mesh_load(path, NULL, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_planes_options po;
  bbc_planes_options_default(&po);
  bbc_planeset set;
  if (bbc_planes_find(&m, &po, &set, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_cloud cl[2];
  for (int threads = 1; threads <= 2; threads++) {
    po.params.threads = threads;
    if (bbc_cloud_build(&m, &set, &po.params, NULL, &cl[threads - 1], &err) != BBC_OK)
      fail_msg("%s", err.message);
  }
  assert_int_equal(cl[0].billboard_count, cl[1].billboard_count);
  for (size_t k = 0; k < cl[0].billboard_count; k++)
    assert_memory_equal(&cl[0].billboards[k].rect, &cl[1].billboards[k].rect,
                        sizeof cl[0].billboards[k].rect);
  assert_true(cl[0].mesh.dropped_degenerate > 0); /* what this test is about */
  char *dir = sub_dir("scan");
  char *wrl = path_in(dir, "scan.wrl");
  if (bbc_cloud_write_vrml(wrl, &cl[0], NULL, &err) != BBC_OK) fail_msg("%s", err.message);
  char *text = read_text(wrl);
  int sides = cl[0].mesh.materials[0].single_sided ? 2 : 1;
  assert_int_equal(count(text, "IndexedFaceSet"), cl[0].billboard_count * (size_t)sides);
  free(text);
  free(wrl);
  free(dir);
  bbc_cloud_free(&cl[0]);
  bbc_cloud_free(&cl[1]);
  bbc_planeset_free(&set);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_formats_with_back_images_and_normal_maps),
      cmocka_unit_test(test_double_sided_without_back_images),
      cmocka_unit_test(test_refused_paths_write_nothing),
      cmocka_unit_test(test_deterministic),
      cmocka_unit_test(test_decimal_comma_locale),
      cmocka_unit_test(test_read_back),
      cmocka_unit_test(test_dds_mip_levels),
      cmocka_unit_test(test_point_cloud_degenerate_outline),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
