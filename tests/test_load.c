/* test_load.c — model loading through Assimp on the real data and on small
 * hand-made files: groups, materials, textures (found, missing, embedded),
 * transforms, OBJ write/read round trip, and the software rasterizer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb/stb_image_write.h>

#include "bbc.h"
#include "test_util.h"

typedef struct log_capture {
  int warnings;
  int texture_warnings; /* warnings that mention a texture */
  char last[1024];
} log_capture;

static void capture_log(void *user, bbc_log_level level, const char *msg) {
  log_capture *c = user;
  if (level == BBC_LOG_WARNING) c->warnings++;
  if (level == BBC_LOG_WARNING && strstr(msg, "texture")) c->texture_warnings++;
  snprintf(c->last, sizeof c->last, "%s", msg);
}

static int load_data(const char *rel, bbc_mesh *m, log_capture *cap) {
  char path[1024];
  tu_data_path(path, sizeof path, rel);
  if (!tu_have_file(path)) return 0;
  bbc_load_options opt;
  bbc_load_options_default(&opt);
  if (cap) {
    memset(cap, 0, sizeof *cap);
    opt.callbacks.log = capture_log;
    opt.callbacks.user = cap;
  }
  bbc_error err;
  bbc_result r = bbc_mesh_load(path, &opt, m, &err);
  if (r != BBC_OK) fail_msg("%s", err.message);
  return 1;
}

static size_t group_triangles(const bbc_mesh *m, const char *name) {
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; t++)
    if (!strcmp(m->group_names[m->face_group[t]], name)) n++;
  return n;
}

static void test_pine(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("trees/scopia/pine/pine.obj", &m, NULL)) skip();
  assert_int_equal(m.triangles_read, 108810);
  assert_int_equal(m.triangle_count, 108810);
  assert_int_equal(m.group_count, 2);
  assert_int_equal(group_triangles(&m, "twigs_Cube.001"), 102600);
  assert_int_equal(group_triangles(&m, "tree"), 6210);
  assert_int_equal(m.material_count, 2); /* Leaves, Trunk; Assimp's default dropped */
  assert_non_null(m.uvs);
  assert_non_null(m.normals);
  /* Units are cm and the tree stands on y = 0, about 5.5 m tall. */
  assert_true(fabs(m.bbox_min[1]) < 1e-3);
  assert_true(m.bbox_max[1] > 500 && m.bbox_max[1] < 600);
  assert_true(m.radius > 250 && m.radius < 350);
  assert_true(m.center[1] > 0 && m.center[1] < m.bbox_max[1]);
  /* The pine's JPG texture has no alpha. */
  for (size_t i = 0; i < m.material_count; i++) {
    assert_true(m.materials[i].texture >= 0);
    assert_false(m.textures[m.materials[i].texture].has_alpha);
  }
  bbc_mesh_free(&m);
}

static void test_cat_3ds(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("models/cat.3ds", &m, NULL)) skip();
  assert_int_equal(m.triangles_read, 14348);
  assert_true(m.radius > 0);
  bbc_mesh_free(&m);
}

static void test_h60_ac3d_texture(void **state) {
  (void)state;
  bbc_mesh m;
  log_capture cap;
  if (!load_data("models/flightgear/H-60.ac", &m, &cap)) skip();
  assert_int_equal(m.triangles_read, 5388);
  /* 14 of them are exactly collinear in the file: dropped and counted. */
  assert_int_equal(m.dropped_degenerate, 14);
  assert_int_equal(m.triangle_count, 5388 - 14);
  int found = 0;
  for (size_t i = 0; i < m.texture_count; i++)
    if (strstr(m.textures[i].path, "H-60.png") && m.textures[i].image.width == 1024) found = 1;
  assert_true(found);
  assert_int_equal(cap.texture_warnings, 0); /* the texture is found */
  assert_int_equal(cap.warnings, 1);         /* only the dropped triangles */
  bbc_mesh_free(&m);
}

static void test_oak_leaf_alpha(void **state) {
  (void)state;
  bbc_mesh m;
  if (!load_data("trees/eztree/oak_medium.obj", &m, NULL)) skip();
  assert_int_equal(m.triangles_read, 13806);
  assert_int_equal(group_triangles(&m, "leaves"), 10640);
  assert_int_equal(group_triangles(&m, "trunk"), 3166);
  int leaf_alpha = 0, bark_alpha = 1;
  for (size_t i = 0; i < m.material_count; i++) {
    const bbc_material *mat = &m.materials[i];
    assert_true(mat->texture >= 0);
    if (!strcmp(mat->name, "oak_leaves")) leaf_alpha = m.textures[mat->texture].has_alpha;
    if (!strcmp(mat->name, "oak_bark")) bark_alpha = m.textures[mat->texture].has_alpha;
  }
  assert_true(leaf_alpha);
  assert_false(bark_alpha);
  bbc_mesh_free(&m);
}

static void test_quaternius_no_maps(void **state) {
  (void)state;
  bbc_mesh m;
  log_capture cap;
  if (!load_data("trees/quaternius/OBJ/Birch_1.obj", &m, &cap)) skip();
  /* The MTL names no maps: colours only, and no texture warning either
   * (the file has 6 zero-area triangles: that warning is expected). */
  for (size_t i = 0; i < m.material_count; i++) {
    assert_int_equal(m.materials[i].texture, -1);
    assert_null(m.materials[i].texture_ref);
  }
  assert_int_equal(cap.texture_warnings, 0);
  assert_int_equal(m.dropped_degenerate, 6);
  bbc_mesh_free(&m);
}

/* dir/a.obj and dir/a.mtl with these texts; returns a.obj's path. */
static char *write_obj_mtl(const char *dir, const char *obj, size_t on, const char *mtl,
                           size_t mn) {
  free(tu_write_file(dir, "a.mtl", mtl, mn));
  return tu_write_file(dir, "a.obj", obj, on);
}

/* Loads `path` with its log captured into *cap; fails the test on an error. */
static void load_logged(const char *path, log_capture *cap, bbc_mesh *m) {
  bbc_load_options opt;
  bbc_load_options_default(&opt);
  memset(cap, 0, sizeof *cap);
  opt.callbacks.log = capture_log;
  opt.callbacks.user = cap;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(path, &opt, m, &err), BBC_OK);
}

/* A texture named by the MTL but absent: a warning and the base colour. */
static void test_missing_texture_is_warning(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  const char obj[] = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                     "o leaf\nusemtl green\nf 1/1 2/2 3/3\n";
  const char mtl[] = "newmtl green\nKd 0.1 0.8 0.2\nmap_Kd nowhere/leaf.png\n";
  char *p = write_obj_mtl(dir, obj, sizeof obj - 1, mtl, sizeof mtl - 1);
  log_capture cap;
  bbc_mesh m;
  load_logged(p, &cap, &m);
  assert_int_equal(cap.warnings, 1);
  assert_non_null(strstr(cap.last, "leaf.png"));
  assert_int_equal(m.materials[0].texture, -1);
  assert_string_equal(m.materials[0].texture_ref, "nowhere/leaf.png");
  assert_true(fabsf(m.materials[0].base_color[1] - 0.8f) < 1e-6f);
  assert_int_equal(m.group_count, 1);
  assert_string_equal(m.group_names[0], "leaf");
  bbc_mesh_free(&m);
  free(p);
  tu_remove_dir(dir);
  free(dir);
}

/* Texture names as artists' files spell them: blanks after the name (a
 * CRLF file with "map_Kd leaf.png \r"), and a name whose case differs from
 * the file's (made where file systems ignore case): both found, no warning. */
static void test_texture_name_blanks_and_case(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  char sub[1024];
  snprintf(sub, sizeof sub, "%s/textures", dir);
  assert_int_equal(mkdir(sub, 0755), 0);
  const uint8_t px[4 * 4] = {40, 200, 60, 255, 40, 200, 60, 255,
                             40, 200, 60, 255, 40, 200, 60, 255};
  char png[1100];
  snprintf(png, sizeof png, "%s/Leaf.png", sub);
  assert_true(stbi_write_png(png, 2, 2, 4, px, 8) != 0);
  const char obj[] =
      "mtllib a.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 1 1 0\r\nvt 0 0\r\nvt 1 0\r\n"
      "vt 0 1\r\nvt 1 1\r\no leaf\r\nusemtl a\r\nf 1/1 2/2 3/3\r\nusemtl b\r\n"
      "f 2/2 4/4 3/3\r\n";
  const char mtl[] = "newmtl a\r\nKd 1 1 1\r\nmap_Kd textures/leaf.png \r\n"
                     "newmtl b\r\nKd 1 1 1\r\nmap_Kd LEAF.PNG\t\r\n";
  char *p = write_obj_mtl(dir, obj, sizeof obj - 1, mtl, sizeof mtl - 1);
  log_capture cap;
  bbc_mesh m;
  load_logged(p, &cap, &m);
  assert_int_equal(cap.texture_warnings, 0);
  assert_int_equal(m.material_count, 2);
  for (size_t i = 0; i < 2; i++) {
    assert_true(m.materials[i].texture >= 0);
    const bbc_image *img = &m.textures[m.materials[i].texture].image;
    assert_int_equal(img->width, 2);
    assert_int_equal(img->rgba[1], 200); /* the leaf's green, not the base colour */
  }
  bbc_mesh_free(&m);
  free(p);
  unlink(png);
  rmdir(sub);
  tu_remove_dir(dir);
  free(dir);
}

/* ---- GLB with an embedded PNG (built here byte by byte) ---------------- */

typedef struct membuf {
  unsigned char *data;
  size_t size;
} membuf;

static void mem_write(void *ctx, void *data, int size) {
  membuf *b = ctx;
  b->data = realloc(b->data, b->size + (size_t)size);
  memcpy(b->data + b->size, data, (size_t)size);
  b->size += (size_t)size;
}

static void put_u32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)v;
  p[1] = (unsigned char)(v >> 8);
  p[2] = (unsigned char)(v >> 16);
  p[3] = (unsigned char)(v >> 24);
}

/* One triangle, translated by node (10, 0, 0), textured with a 4x4 PNG whose
 * left half is transparent. */
static unsigned char *make_glb(size_t *out_size) {
  unsigned char px[4 * 4 * 4];
  for (int i = 0; i < 16; i++) {
    px[4 * i + 0] = 200;
    px[4 * i + 1] = 30;
    px[4 * i + 2] = 40;
    px[4 * i + 3] = (i % 4) < 2 ? 0 : 255;
  }
  membuf png = {NULL, 0};
  stbi_write_png_to_func(mem_write, &png, 4, 4, 4, px, 16);
  float geo[9 + 6] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
  size_t png_off = sizeof geo, png_len = png.size;
  size_t bin_len = (png_off + png_len + 3) & ~(size_t)3;
  char json[2048];
  snprintf(
      json, sizeof json,
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
      "\"nodes\":[{\"mesh\":0,\"name\":\"leafnode\",\"translation\":[10,0,0]}],"
      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},"
      "\"material\":0}]}],"
      "\"materials\":[{\"name\":\"leafmat\",\"pbrMetallicRoughness\":{\"baseColorTexture\":"
      "{\"index\":0}},\"alphaMode\":\"MASK\"}],"
      "\"textures\":[{\"source\":0}],\"images\":[{\"bufferView\":2,\"mimeType\":\"image/png\"}],"
      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
      "\"min\":[0,0,0],\"max\":[1,1,0]},"
      "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}],"
      "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
      "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24},"
      "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
      "\"buffers\":[{\"byteLength\":%zu}]}",
      png_off, png_len, bin_len);
  size_t jlen = strlen(json);
  size_t jpad = (jlen + 3) & ~(size_t)3;
  size_t total = 12 + 8 + jpad + 8 + bin_len;
  unsigned char *g = calloc(1, total);
  memcpy(g, "glTF", 4);
  put_u32(g + 4, 2);
  put_u32(g + 8, (uint32_t)total);
  put_u32(g + 12, (uint32_t)jpad);
  memcpy(g + 16, "JSON", 4);
  memset(g + 20, ' ', jpad);
  memcpy(g + 20, json, jlen);
  unsigned char *b = g + 20 + jpad;
  put_u32(b, (uint32_t)bin_len);
  memcpy(b + 4, "BIN\0", 4);
  memcpy(b + 8, geo, sizeof geo);
  memcpy(b + 8 + png_off, png.data, png_len);
  free(png.data);
  *out_size = total;
  return g;
}

static void test_glb_embedded_texture_and_transform(void **state) {
  (void)state;
  size_t n;
  unsigned char *glb = make_glb(&n);
  char *dir = tu_make_temp_dir();
  char *p = tu_write_file(dir, "tri.glb", glb, n);
  bbc_mesh m;
  bbc_error err;
  bbc_result r = bbc_mesh_load(p, NULL, &m, &err);
  if (r != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(m.triangle_count, 1);
  /* The node's translation is applied: x in [10, 11]. */
  assert_true(fabs(m.bbox_min[0] - 10) < 1e-6 && fabs(m.bbox_max[0] - 11) < 1e-6);
  assert_string_equal(m.group_names[0], "leafnode");
  assert_int_equal(m.material_count, 1);
  assert_true(m.materials[0].texture >= 0);
  const bbc_texture *t = &m.textures[m.materials[0].texture];
  assert_int_equal(t->image.width, 4);
  assert_true(t->has_alpha);
  assert_int_equal(t->image.rgba[3], 0); /* left half transparent */
  assert_int_equal(t->image.rgba[4 * 3 + 3], 255);
  bbc_mesh_free(&m);

  /* The same file cut short: refused as damaged, naming the file. */
  char *q = tu_write_file(dir, "cut.glb", glb, n / 2);
  assert_int_equal(bbc_mesh_load(q, NULL, &m, &err), BBC_ERROR_CORRUPT);
  assert_non_null(strstr(err.message, "cut.glb"));
  free(q);
  free(glb);
  free(p);
  tu_remove_dir(dir);
  free(dir);
}

/* Write the oak as OBJ and read it back: same triangles, groups, alpha. */
static void test_obj_round_trip(void **state) {
  (void)state;
  bbc_mesh a, b;
  if (!load_data("trees/eztree/oak_medium.obj", &a, NULL)) skip();
  char *dir = tu_make_temp_dir();
  char path[1024];
  snprintf(path, sizeof path, "%s/oak copy.obj", dir);
  bbc_error err;
  assert_int_equal(bbc_mesh_write_obj(path, &a, NULL, &err), BBC_OK);
  assert_int_equal(bbc_mesh_load(path, NULL, &b, &err), BBC_OK);
  assert_int_equal(b.triangle_count, a.triangle_count);
  assert_int_equal(group_triangles(&b, "leaves"), 10640);
  for (int k = 0; k < 3; k++) {
    assert_true(fabs(a.bbox_min[k] - b.bbox_min[k]) < 1e-5);
    assert_true(fabs(a.center[k] - b.center[k]) < 1e-5);
  }
  int alpha = 0;
  for (size_t i = 0; i < b.texture_count; i++) alpha |= b.textures[i].has_alpha;
  assert_true(alpha);
  bbc_mesh_free(&a);
  bbc_mesh_free(&b);
  tu_remove_dir(dir);
  free(dir);
}

/* A library caller may call setlocale: under a locale with a decimal comma
 * the writers still spell their numbers with '.' (OBJ, its MTL, glTF's
 * JSON; VRML's writer shares the same formatter). Skipped only where no
 * such locale is installed (scripts/dev/setup.sh makes de_DE.UTF-8). */
static void test_writers_decimal_comma(void **state) {
  (void)state;
  static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8",
                                      "fr_FR.utf8",  "de_DE",      NULL};
  char *dir = tu_make_temp_dir();
  static const char obj[] = "v 0.5 0 0\nv 1.25 0 0\nv 0 0.75 0\nvt 0.25 0.5\nvt 1 0\nvt 0 1\n"
                            "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n";
  char *in = tu_write_file(dir, "in.obj", obj, sizeof obj - 1);
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_mesh_load(in, NULL, &m, &err), BBC_OK);
  m.materials[0].base_color[0] = 0.5f;
  m.materials[0].base_color[3] = 0.25f;
  const char *got = NULL;
  for (int i = 0; names[i] && !got; i++)
    if (setlocale(LC_NUMERIC, names[i])) got = names[i];
  if (!got) {
    fprintf(stderr, "no locale with a decimal comma installed: test skipped\n");
    bbc_mesh_free(&m);
    free(in);
    tu_remove_dir(dir);
    free(dir);
    skip();
  }
  char probe[16];
  snprintf(probe, sizeof probe, "%.2f", 0.5);
  int comma = !strcmp(probe, "0,50"); /* the locale does write a comma */
  char path[1024];
  snprintf(path, sizeof path, "%s/out.obj", dir);
  assert_int_equal(bbc_mesh_write_obj(path, &m, NULL, &err), BBC_OK);
  char *o = (char *)tu_read_file(path, NULL);
  snprintf(path, sizeof path, "%s/out.mtl", dir);
  char *mtl = (char *)tu_read_file(path, NULL);
  snprintf(path, sizeof path, "%s/out.gltf", dir);
  assert_int_equal(bbc_mesh_write_gltf(path, &m, NULL, &err), BBC_OK);
  char *g = (char *)tu_read_file(path, NULL);
  setlocale(LC_NUMERIC, "C");
  fprintf(stderr, "locale %s (decimal comma: %s)\n", got, comma ? "yes" : "no");
  assert_true(comma);
  assert_non_null(o);
  assert_non_null(mtl);
  assert_non_null(g);
  assert_non_null(strstr(o, "v 1.25 0 0\n"));
  assert_non_null(strstr(o, "vt 0.25 0.5\n"));
  assert_null(strstr(o, "0,5"));
  assert_null(strstr(o, "1,25"));
  assert_non_null(strstr(mtl, "Kd 0.5 "));
  assert_non_null(strstr(mtl, "d 0.25\n"));
  assert_null(strstr(mtl, "0,5"));
  assert_non_null(strstr(g, "1.25"));
  assert_null(strstr(g, "1,25"));
  free(o);
  free(mtl);
  free(g);
  bbc_mesh_free(&m);
  free(in);
  tu_remove_dir(dir);
  free(dir);
}

/* ---- rasterizer --------------------------------------------------------- */

/* A square of two triangles covering exactly the pixel centres inside it:
 * every pixel whose centre is inside is painted once, none outside, and the
 * shared diagonal leaves no gap. */
static void test_raster_coverage(void **state) {
  (void)state;
  /* 8x8 image showing [-4, 4]^2; square [-2, 2] x [-1, 3] in XY, z = 0. */
  const double pos[] = {-2, -1, 0, 2, -1, 0, 2, 3, 0, -2, 3, 0};
  const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  m.vertex_count = 4;
  m.positions = malloc(sizeof pos);
  memcpy(m.positions, pos, sizeof pos);
  m.triangle_count = 2;
  m.indices = malloc(sizeof idx);
  memcpy(m.indices, idx, sizeof idx);
  m.face_material = calloc(2, sizeof(uint32_t));
  m.face_group = calloc(2, sizeof(uint32_t));
  m.material_count = 1;
  m.materials = calloc(1, sizeof(bbc_material));
  m.materials[0].name = strdup("white");
  m.materials[0].texture = -1;
  for (int k = 0; k < 4; k++) m.materials[0].base_color[k] = 1.0f;
  m.group_count = 1;
  m.group_names = calloc(1, sizeof(char *));
  m.group_names[0] = strdup("");
  bbc_error err;
  assert_int_equal(bbc_mesh_finalize(&m, 1, "square", &err), BBC_OK);
  bbc_view v;
  memset(&v, 0, sizeof v);
  v.direction[2] = -1;
  v.up[1] = 1;
  v.half_extent = 4;
  bbc_image img;
  assert_int_equal(bbc_image_alloc(&img, 8, 8), BBC_OK);
  assert_int_equal(bbc_render_ortho(&m, &v, &img, &err), BBC_OK);
  /* Pixel x covers model x in [x-4, x-3]; centre x-3.5. Inside: centres in
   * (-2, 2) -> x = 2..5. Row y (down) covers model y from 4-y: centres
   * 3.5-y in (-1, 3) -> y = 1..4. */
  int count = 0;
  for (int y = 0; y < 8; y++)
    for (int x = 0; x < 8; x++) {
      int inside = x >= 2 && x <= 5 && y >= 1 && y <= 4;
      assert_int_equal(img.rgba[4 * (y * 8 + x) + 3], inside ? 255 : 0);
      count += inside;
    }
  assert_int_equal(count, 16);
  bbc_image_free(&img);
  bbc_mesh_free(&m);
}

/* An OBJ whose mtllib is not beside it: said with its line (Assimp says
 * nothing and the materials come out grey); one that is there: nothing. */
static void test_missing_mtllib(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  const char *obj = "# made by test_load\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  char *path = tu_write_file(dir, "m.obj", obj, strlen(obj));
  bbc_load_options opt;
  bbc_load_options_default(&opt);
  log_capture cap;
  memset(&cap, 0, sizeof cap);
  opt.callbacks.log = capture_log;
  opt.callbacks.user = &cap;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &opt, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_mesh_free(&m);
  assert_int_equal(cap.warnings, 1);
  if (!strstr(cap.last, "m.obj:2: material library 'gone.mtl' not found")) fail_msg("%s", cap.last);
  free(tu_write_file(dir, "gone.mtl", "newmtl a\nKd 1 0 0\n", 19));
  memset(&cap, 0, sizeof cap);
  if (bbc_mesh_load(path, &opt, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_mesh_free(&m);
  assert_int_equal(cap.warnings, 0);
  free(path);
  tu_remove_dir(dir);
  free(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_missing_mtllib),
      cmocka_unit_test(test_texture_name_blanks_and_case),
      cmocka_unit_test(test_pine),
      cmocka_unit_test(test_cat_3ds),
      cmocka_unit_test(test_h60_ac3d_texture),
      cmocka_unit_test(test_oak_leaf_alpha),
      cmocka_unit_test(test_quaternius_no_maps),
      cmocka_unit_test(test_missing_texture_is_warning),
      cmocka_unit_test(test_glb_embedded_texture_and_transform),
      cmocka_unit_test(test_obj_round_trip),
      cmocka_unit_test(test_writers_decimal_comma),
      cmocka_unit_test(test_raster_coverage),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
