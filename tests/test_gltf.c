/* test_gltf.c — glTF 2.0 output (bbc_mesh_write_gltf): .glb and .gltf read
 * back with the project's loader (Assimp), the GLB container and JSON checked
 * with cJSON, the files checked by the Khronos glTF validator
 * (scripts/tools/gltf_validate.sh), and byte-identical repeated writes. And FBX
 * (bbc_scene_write_fbx): a chain of levels read back through Assimp, level
 * by level, and its records walked byte by byte. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cjson/cJSON.h>

#include "bbc.h"
#include "test_util.h"

/* ---- test meshes --------------------------------------------------------- */

#define TEX_W 4
#define TEX_H 4

/* The 4x4 test texture, rows top first: every texel a different colour, the
 * left half transparent. */
static void texel(int x, int y_top, uint8_t out[4]) {
  out[0] = (uint8_t)(40 * x + 20);
  out[1] = (uint8_t)(40 * y_top + 20);
  out[2] = 100;
  out[3] = x < 2 ? 0 : 255;
}

/* `quads` unit quads in the XY plane, quad q at x = 2 * (q % 200), y = 2 *
 * (q / 200), 4 vertices each, uvs at the centres of the texture's corner
 * texels (bottom-left vertex -> bottom-left texel, OpenGL convention).
 * Material 0 "leaf" is textured; with two_materials, every other triangle
 * uses material 1, untextured, whose name needs JSON escaping. */
static void make_quads(bbc_mesh *m, size_t quads, int two_materials) {
  memset(m, 0, sizeof *m);
  m->vertex_count = 4 * quads;
  m->positions = malloc(m->vertex_count * 3 * sizeof(double));
  m->uvs = malloc(m->vertex_count * 2 * sizeof(float));
  m->triangle_count = 2 * quads;
  m->indices = malloc(m->triangle_count * 3 * sizeof(uint32_t));
  m->face_material = calloc(m->triangle_count, sizeof(uint32_t));
  m->face_group = calloc(m->triangle_count, sizeof(uint32_t));
  const double corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const float uv[4][2] = {{0.125f, 0.125f}, {0.875f, 0.125f}, {0.875f, 0.875f}, {0.125f, 0.875f}};
  for (size_t q = 0; q < quads; q++) {
    for (int c = 0; c < 4; c++) {
      double *p = m->positions + 3 * (4 * q + c);
      p[0] = 2.0 * (double)(q % 200) + corner[c][0];
      p[1] = 2.0 * (double)(q / 200) + corner[c][1];
      p[2] = 0.25;
      m->uvs[2 * (4 * q + c)] = uv[c][0];
      m->uvs[2 * (4 * q + c) + 1] = uv[c][1];
    }
    uint32_t b = (uint32_t)(4 * q);
    const uint32_t ix[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
    memcpy(m->indices + 6 * q, ix, sizeof ix);
    if (two_materials) m->face_material[2 * q + 1] = 1;
  }
  m->material_count = two_materials ? 2 : 1;
  m->materials = calloc(m->material_count, sizeof(bbc_material));
  m->materials[0].name = strdup("leaf");
  m->materials[0].texture = 0;
  for (int k = 0; k < 4; k++) m->materials[0].base_color[k] = 1.0f;
  if (two_materials) {
    m->materials[1].name = strdup("bark \"old\" \\ caf\xc3\xa9");
    m->materials[1].texture = -1;
    const float c[4] = {0.5f, 0.25f, 0.125f, 1.0f};
    memcpy(m->materials[1].base_color, c, sizeof c);
  }
  m->texture_count = 1;
  m->textures = calloc(1, sizeof(bbc_texture));
  assert_int_equal(bbc_image_alloc(&m->textures[0].image, TEX_W, TEX_H), BBC_OK);
  for (int y = 0; y < TEX_H; y++)
    for (int x = 0; x < TEX_W; x++) texel(x, y, m->textures[0].image.rgba + 4 * (y * TEX_W + x));
  m->textures[0].has_alpha = 1;
  m->group_count = 1;
  m->group_names = calloc(1, sizeof(char *));
  m->group_names[0] = strdup("quads");
  bbc_error err;
  if (bbc_mesh_finalize(m, 1, "quads", &err) != BBC_OK) fail_msg("%s", err.message);
}

/* ---- helpers ------------------------------------------------------------- */

static char *join(const char *dir, const char *name) {
  size_t n = strlen(dir) + strlen(name) + 2;
  char *p = malloc(n);
  snprintf(p, n, "%s/%s", dir, name);
  return p;
}

static void write_ok(const char *path, const bbc_mesh *m, int binary, const char *extras) {
  bbc_gltf_options opt = {binary ? BBC_GLTF_BINARY : BBC_GLTF_SEPARATE, extras, 0, NULL, NULL, 0};
  bbc_error err;
  bbc_result r = bbc_mesh_write_gltf(path, m, &opt, &err);
  if (r != BBC_OK) fail_msg("%s", err.message);
}

static void load_ok(const char *path, bbc_mesh *m) {
  bbc_error err;
  bbc_result r = bbc_mesh_load(path, NULL, m, &err);
  if (r != BBC_OK) fail_msg("%s", err.message);
}

static void assert_same_bbox(const bbc_mesh *a, const bbc_mesh *b) {
  double scale = 0;
  for (int k = 0; k < 3; k++) {
    scale = fmax(scale, fabs(a->bbox_min[k]));
    scale = fmax(scale, fabs(a->bbox_max[k]));
  }
  for (int k = 0; k < 3; k++) {
    if (fabs(a->bbox_min[k] - b->bbox_min[k]) > 1e-5 * scale ||
        fabs(a->bbox_max[k] - b->bbox_max[k]) > 1e-5 * scale)
      fail_msg("bbox axis %d: [%g, %g] written, [%g, %g] read", k, a->bbox_min[k], a->bbox_max[k],
               b->bbox_min[k], b->bbox_max[k]);
  }
}

/* The loaded quad mesh's texture, sampled at each vertex's uv (OpenGL
 * convention, nearest texel), is the colour of the texel that vertex's
 * corner was given: fails when v is not flipped on one side of the trip. */
static void assert_uv_orientation(const bbc_mesh *m) {
  assert_non_null(m->uvs);
  const bbc_texture *tex = NULL;
  for (size_t i = 0; i < m->material_count; i++)
    if (m->materials[i].texture >= 0) tex = &m->textures[m->materials[i].texture];
  assert_non_null(tex);
  assert_int_equal(tex->image.width, TEX_W);
  assert_int_equal(tex->image.height, TEX_H);
  assert_true(tex->has_alpha);
  for (size_t v = 0; v < m->vertex_count; v++) {
    const double *p = m->positions + 3 * v;
    int cx = fmod(p[0], 2.0) > 0.5, cy = fmod(p[1], 2.0) > 0.5; /* corner of its quad */
    uint8_t want[4];
    texel(cx ? TEX_W - 1 : 0, cy ? 0 : TEX_H - 1, want);
    int x = (int)floor(m->uvs[2 * v] * TEX_W);
    int y_top = (int)floor((1.0f - m->uvs[2 * v + 1]) * TEX_H);
    assert_true(x >= 0 && x < TEX_W && y_top >= 0 && y_top < TEX_H);
    const uint8_t *got = tex->image.rgba + 4 * (y_top * TEX_W + x);
    if (memcmp(got, want, 4))
      fail_msg("vertex %zu (%g, %g) uv (%g, %g): texel %d,%d is %d,%d,%d,%d, want %d,%d,%d,%d", v,
               p[0], p[1], m->uvs[2 * v], m->uvs[2 * v + 1], x, y_top, got[0], got[1], got[2],
               got[3], want[0], want[1], want[2], want[3]);
  }
}

static int g_validator_missing; /* once unavailable, skip at once */

/* Runs the Khronos validator on `path`: must report 0 errors. Skips (never
 * passes silently) when the validator cannot be installed. */
static void validate(const char *path) {
  if (g_validator_missing) {
    printf("SKIP: gltf-validator unavailable\n");
    skip();
  }
  int rc = tu_gltf_validate(path);
  if (rc == 3) {
    g_validator_missing = 1;
    printf("SKIP: gltf-validator unavailable\n");
    skip();
  }
  if (rc != 0) fail_msg("%s: the glTF validator reports errors (exit %d)", path, rc);
}

/* The GLB container: header, a space-padded JSON chunk and a zero-padded BIN
 * chunk, lengths consistent; returns the parsed JSON. */
static cJSON *read_glb_json(const char *path, size_t *bin_length) {
  size_t n;
  unsigned char *g = tu_read_file(path, &n);
  assert_non_null(g);
  assert_true(n >= 28 && n % 4 == 0);
  assert_memory_equal(g, "glTF", 4);
#define U32(p)                                                                                     \
  ((uint32_t)(p)[0] | (uint32_t)(p)[1] << 8 | (uint32_t)(p)[2] << 16 | (uint32_t)(p)[3] << 24)
  assert_int_equal(U32(g + 4), 2);
  assert_int_equal(U32(g + 8), n);
  uint32_t jlen = U32(g + 12);
  assert_memory_equal(g + 16, "JSON", 4);
  assert_true(jlen % 4 == 0 && 20 + (size_t)jlen + 8 <= n);
  const unsigned char *b = g + 20 + jlen;
  uint32_t blen = U32(b);
  assert_memory_equal(b + 4, "BIN\0", 4);
  assert_true(blen % 4 == 0);
  assert_int_equal(20 + (size_t)jlen + 8 + blen, n);
#undef U32
  cJSON *j = cJSON_ParseWithLength((const char *)g + 20, jlen);
  assert_non_null(j);
  *bin_length = blen;
  free(g);
  return j;
}

static cJSON *read_json_file(const char *path) {
  size_t n;
  unsigned char *t = tu_read_file(path, &n);
  assert_non_null(t);
  cJSON *j = cJSON_ParseWithLength((const char *)t, n);
  assert_non_null(j);
  free(t);
  return j;
}

static int json_int(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  assert_true(cJSON_IsNumber(v));
  return v->valueint;
}

/* Structure every file must have: accessor types and counts, POSITION
 * min/max, aligned bufferViews with targets, materials. */
static void check_structure(const cJSON *j, const bbc_mesh *m, int want_component) {
  const cJSON *asset = cJSON_GetObjectItemCaseSensitive(j, "asset");
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(asset, "version")->valuestring, "2.0");
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(asset, "generator")->valuestring,
                      "bbcgen " BBC_VERSION_STRING);
  const cJSON *views = cJSON_GetObjectItemCaseSensitive(j, "bufferViews");
  const cJSON *v;
  cJSON_ArrayForEach(v, views) {
    assert_int_equal(json_int(v, "byteOffset") % 4, 0);
    assert_null(cJSON_GetObjectItemCaseSensitive(v, "byteStride"));
  }
  const cJSON *accessors = cJSON_GetObjectItemCaseSensitive(j, "accessors");
  const cJSON *prims = cJSON_GetObjectItemCaseSensitive(
      cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "meshes"), 0), "primitives");
  size_t index_total = 0;
  const cJSON *p;
  cJSON_ArrayForEach(p, prims) {
    const cJSON *attr = cJSON_GetObjectItemCaseSensitive(p, "attributes");
    const cJSON *pos = cJSON_GetArrayItem(accessors, json_int(attr, "POSITION"));
    assert_int_equal(json_int(pos, "componentType"), 5126);
    assert_int_equal(json_int(pos, "count"), m->vertex_count);
    assert_int_equal(json_int(cJSON_GetArrayItem(views, json_int(pos, "bufferView")), "target"),
                     34962);
    const cJSON *mn = cJSON_GetObjectItemCaseSensitive(pos, "min");
    const cJSON *mx = cJSON_GetObjectItemCaseSensitive(pos, "max");
    /* Over every vertex (the spec's rule), not only the used ones of
     * bbox_min/max; the same float values. */
    for (int k = 0; k < 3; k++) {
      float lo = (float)m->positions[k], hi = lo;
      for (size_t i = 1; i < m->vertex_count; i++) {
        lo = fminf(lo, (float)m->positions[3 * i + k]);
        hi = fmaxf(hi, (float)m->positions[3 * i + k]);
      }
      assert_true((float)cJSON_GetArrayItem(mn, k)->valuedouble == lo);
      assert_true((float)cJSON_GetArrayItem(mx, k)->valuedouble == hi);
    }
    const cJSON *ix = cJSON_GetArrayItem(accessors, json_int(p, "indices"));
    assert_int_equal(json_int(ix, "componentType"), want_component);
    assert_int_equal(json_int(cJSON_GetArrayItem(views, json_int(ix, "bufferView")), "target"),
                     34963);
    index_total += (size_t)json_int(ix, "count");
  }
  assert_int_equal(index_total, 3 * m->triangle_count);
  const cJSON *mat;
  cJSON_ArrayForEach(mat, cJSON_GetObjectItemCaseSensitive(j, "materials")) {
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(mat, "alphaMode")->valuestring, "MASK");
    assert_true(cJSON_GetObjectItemCaseSensitive(mat, "alphaCutoff")->valuedouble == 0.5);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(mat, "doubleSided")));
  }
}

static int files_equal(const char *a, const char *b) {
  size_t na, nb;
  unsigned char *x = tu_read_file(a, &na), *y = tu_read_file(b, &nb);
  int eq = x && y && na == nb && !memcmp(x, y, na);
  free(x);
  free(y);
  return eq;
}

/* ---- tests ------------------------------------------------------------------ */

/* One textured quad as .glb and as .gltf: read back with its transparent
 * texels and the right uv orientation; the validator finds no error. */
static void test_textured_quad(void **state) {
  (void)state;
  bbc_mesh m, b;
  make_quads(&m, 1, 0);
  char *glb = join(tu_dir, "quad.glb"), *gltf = join(tu_dir, "quad.gltf");
  write_ok(glb, &m, 1, NULL);
  write_ok(gltf, &m, 0, NULL);

  size_t bin_len;
  cJSON *j = read_glb_json(glb, &bin_len);
  check_structure(j, &m, 5123);
  const cJSON *img = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "images"), 0);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(img, "mimeType")->valuestring, "image/png");
  cJSON_Delete(j);
  j = read_json_file(gltf);
  check_structure(j, &m, 5123);
  const cJSON *buf = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "buffers"), 0);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(buf, "uri")->valuestring, "quad.bin");
  img = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "images"), 0);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(img, "uri")->valuestring,
                      "quad_gltf_leaf.png");
  cJSON_Delete(j);

  const char *files[2] = {glb, gltf};
  for (int f = 0; f < 2; f++) {
    load_ok(files[f], &b);
    assert_int_equal(b.triangle_count, 2);
    assert_same_bbox(&m, &b);
    assert_uv_orientation(&b);
    bbc_mesh_free(&b);
  }
  validate(glb);
  validate(gltf);
  bbc_mesh_free(&m);
  free(glb);
  free(gltf);
}

/* Two materials on interleaved faces -> two primitives; the untextured one
 * keeps its colour and its name (quotes, backslash, UTF-8) survives. */
static void test_two_materials(void **state) {
  (void)state;
  bbc_mesh m, b;
  make_quads(&m, 6, 1);
  char *glb = join(tu_dir, "two.glb"), *gltf = join(tu_dir, "two words.gltf");
  write_ok(glb, &m, 1, NULL);
  write_ok(gltf, &m, 0, NULL);
  size_t bin_len;
  cJSON *j = read_glb_json(glb, &bin_len);
  check_structure(j, &m, 5123);
  assert_int_equal(
      cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(
          cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "meshes"), 0), "primitives")),
      2);
  const cJSON *mat1 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "materials"), 1);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(mat1, "name")->valuestring,
                      m.materials[1].name);
  assert_null(cJSON_GetObjectItemCaseSensitive(
      cJSON_GetObjectItemCaseSensitive(mat1, "pbrMetallicRoughness"), "baseColorTexture"));
  cJSON_Delete(j);
  /* A stem with a space: side files get a URI-safe name. */
  j = read_json_file(gltf);
  const cJSON *buf = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "buffers"), 0);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(buf, "uri")->valuestring, "two_words.bin");
  cJSON_Delete(j);

  const char *files[2] = {glb, gltf};
  for (int f = 0; f < 2; f++) {
    load_ok(files[f], &b);
    assert_int_equal(b.triangle_count, m.triangle_count);
    assert_same_bbox(&m, &b);
    assert_int_equal(b.material_count, 2);
    int found = 0;
    for (size_t i = 0; i < b.material_count; i++) {
      if (strcmp(b.materials[i].name, m.materials[1].name)) continue;
      found = 1;
      assert_int_equal(b.materials[i].texture, -1);
      for (int k = 0; k < 4; k++)
        assert_true(fabsf(b.materials[i].base_color[k] - m.materials[1].base_color[k]) < 1e-6f);
    }
    assert_true(found);
    /* Half the triangles each. */
    size_t per[2] = {0, 0};
    for (size_t t = 0; t < b.triangle_count; t++)
      per[b.materials[b.face_material[t]].texture >= 0]++;
    assert_int_equal(per[0], 6);
    assert_int_equal(per[1], 6);
    assert_uv_orientation(&b);
    bbc_mesh_free(&b);
  }
  validate(glb);
  validate(gltf);
  bbc_mesh_free(&m);
  free(glb);
  free(gltf);
}

/* More than 65535 vertices: uint32 indices. */
static void test_uint32_indices(void **state) {
  (void)state;
  bbc_mesh m, b;
  make_quads(&m, 16400, 0); /* 65600 vertices */
  char *glb = join(tu_dir, "big.glb");
  write_ok(glb, &m, 1, NULL);
  size_t bin_len;
  cJSON *j = read_glb_json(glb, &bin_len);
  check_structure(j, &m, 5125);
  cJSON_Delete(j);
  load_ok(glb, &b);
  assert_int_equal(b.triangle_count, m.triangle_count);
  assert_same_bbox(&m, &b);
  bbc_mesh_free(&b);
  validate(glb);
  bbc_mesh_free(&m);
  free(glb);
}

/* The built-in tree (trunk + alpha-textured leaves) as .glb. */
static void test_tree(void **state) {
  (void)state;
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.leaves = 500;
  bbc_mesh m, b;
  bbc_error err;
  if (bbc_tree_generate(&opt, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  char *glb = join(tu_dir, "tree.glb");
  write_ok(glb, &m, 1, "{\"source\": \"bbcgen tree\", \"leaves\": 500}");
  size_t bin_len;
  cJSON *j = read_glb_json(glb, &bin_len);
  check_structure(j, &m, m.vertex_count <= 65535 ? 5123 : 5125);
  cJSON_Delete(j);
  load_ok(glb, &b);
  assert_int_equal(b.triangle_count, m.triangle_count);
  assert_same_bbox(&m, &b);
  int alpha = 0;
  for (size_t i = 0; i < b.texture_count; i++) alpha |= b.textures[i].has_alpha;
  assert_true(alpha);
  bbc_mesh_free(&b);
  validate(glb);
  bbc_mesh_free(&m);
  free(glb);
}

/* extras_json lands in asset.extras; refused when not one JSON object. */
static void test_extras(void **state) {
  (void)state;
  bbc_mesh m;
  make_quads(&m, 1, 0);
  char *glb = join(tu_dir, "extras.glb");
  write_ok(glb, &m, 1,
           " {\"planes\": [1, 2.5e3, -0.5], \"name\": \"a\\\"b\\u00e9\", \"ok\": true} ");
  size_t bin_len;
  cJSON *j = read_glb_json(glb, &bin_len);
  const cJSON *extras =
      cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "asset"), "extras");
  assert_true(cJSON_IsObject(extras));
  const cJSON *planes = cJSON_GetObjectItemCaseSensitive(extras, "planes");
  assert_int_equal(cJSON_GetArraySize(planes), 3);
  assert_true(cJSON_GetArrayItem(planes, 1)->valuedouble == 2500);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(extras, "name")->valuestring,
                      "a\"b\xc3\xa9");
  cJSON_Delete(j);
  validate(glb);

  const char *bad[] = {"[1, 2]",      "{", "{\"a\": }", "{\"a\": 1} x",
                       "{\"a\": 01}", "",  "null",      "{'a': 1}"};
  char *other = join(tu_dir, "bad_extras.glb");
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    bbc_gltf_options opt = {1, bad[i], 0, NULL, NULL, 0};
    bbc_error err;
    assert_int_equal(bbc_mesh_write_gltf(other, &m, &opt, &err), BBC_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "bad_extras.glb"));
    struct stat st;
    assert_int_not_equal(stat(other, &st), 0); /* nothing written */
  }
  free(other);
  bbc_mesh_free(&m);
  free(glb);
}

/* Refusals name the path: wrong extension, missing folder, no triangles. */
static void test_errors(void **state) {
  (void)state;
  bbc_mesh m;
  make_quads(&m, 1, 0);
  bbc_error err;
  bbc_gltf_options glb = {BBC_GLTF_BINARY, NULL, 0, NULL, NULL, 0};
  bbc_gltf_options gltf = {BBC_GLTF_SEPARATE, NULL, 0, NULL, NULL, 0};
  char *p = join(tu_dir, "wrong.gltf");
  assert_int_equal(bbc_mesh_write_gltf(p, &m, &glb, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(err.message, "wrong.gltf"));
  free(p);
  p = join(tu_dir, "wrong.glb");
  assert_int_equal(bbc_mesh_write_gltf(p, &m, &gltf, &err), BBC_ERROR_INVALID_ARGUMENT);
  free(p);
  p = join(tu_dir, "no/such/folder/x.glb");
  assert_int_equal(bbc_mesh_write_gltf(p, &m, &glb, &err), BBC_ERROR_IO);
  assert_non_null(strstr(err.message, "no/such/folder/x.glb"));
  free(p);
  /* NULL options: the format follows the extension. */
  p = join(tu_dir, "default.glb");
  assert_int_equal(bbc_mesh_write_gltf(p, &m, NULL, &err), BBC_OK);
  size_t n;
  unsigned char *g = tu_read_file(p, &n);
  assert_non_null(g);
  assert_memory_equal(g, "glTF", 4);
  free(g);
  free(p);
  bbc_mesh empty;
  memset(&empty, 0, sizeof empty);
  p = join(tu_dir, "empty.glb");
  assert_int_equal(bbc_mesh_write_gltf(p, &empty, &glb, &err), BBC_ERROR_EMPTY);
  assert_non_null(strstr(err.message, "empty.glb"));
  free(p);
  bbc_mesh_free(&m);
}

/* The same mesh written twice gives byte-identical files. */
static void test_deterministic(void **state) {
  (void)state;
  bbc_mesh m;
  make_quads(&m, 6, 1);
  char *a = join(tu_dir, "det_a.glb"), *b = join(tu_dir, "det_b.glb");
  write_ok(a, &m, 1, "{\"k\":1}");
  write_ok(b, &m, 1, "{\"k\":1}");
  assert_true(files_equal(a, b));
  /* .gltf: write, keep copies, write again over them, compare. */
  char *g = join(tu_dir, "det.gltf"), *bin = join(tu_dir, "det.bin");
  char *png = join(tu_dir, "det_gltf_leaf.png");
  const char *names[3] = {g, bin, png};
  char *copies[3];
  write_ok(g, &m, 0, NULL);
  for (int i = 0; i < 3; i++) {
    size_t n;
    unsigned char *d = tu_read_file(names[i], &n);
    assert_non_null(d);
    char name[32];
    snprintf(name, sizeof name, "copy%d", i);
    copies[i] = tu_write_file(tu_dir, name, d, n);
    free(d);
  }
  write_ok(g, &m, 0, NULL);
  for (int i = 0; i < 3; i++) {
    assert_true(files_equal(names[i], copies[i]));
    free(copies[i]);
  }
  free(g);
  free(bin);
  free(png);
  free(a);
  free(b);
  bbc_mesh_free(&m);
}

/* ---- FBX ------------------------------------------------------------------ */

/* Walks the FBX 7.4 records from `at` to `end` (exclusive; a 13-byte zero
 * record ends each list): every end offset inside its parent and past its
 * header, every property of a known type and inside its record, nested
 * lists terminated. Counts records named `name` into *found. */
static size_t walk_fbx(const uint8_t *b, size_t at, size_t end, const char *name, int *found) {
  while (at + 13 <= end) {
    uint32_t eo = (uint32_t)b[at] | (uint32_t)b[at + 1] << 8 | (uint32_t)b[at + 2] << 16 |
                  (uint32_t)b[at + 3] << 24;
    if (eo == 0) return at + 13; /* the list's end */
    uint32_t np = (uint32_t)b[at + 4] | (uint32_t)b[at + 5] << 8 | (uint32_t)b[at + 6] << 16 |
                  (uint32_t)b[at + 7] << 24;
    uint32_t pl = (uint32_t)b[at + 8] | (uint32_t)b[at + 9] << 8 | (uint32_t)b[at + 10] << 16 |
                  (uint32_t)b[at + 11] << 24;
    uint8_t nl = b[at + 12];
    assert_true(eo > at && eo <= end);
    if (strlen(name) == nl && !memcmp(b + at + 13, name, nl)) (*found)++;
    size_t p = at + 13 + nl, pe = p + pl;
    assert_true(pe <= eo);
    for (uint32_t i = 0; i < np; i++) {
      assert_true(p < pe);
      char t = (char)b[p++];
      size_t len = 0;
      switch (t) {
      case 'C':
        len = 1;
        break;
      case 'Y':
        len = 2;
        break;
      case 'I':
      case 'F':
        len = 4;
        break;
      case 'L':
      case 'D':
        len = 8;
        break;
      case 'S':
      case 'R':
        len = 4 + ((uint32_t)b[p] | (uint32_t)b[p + 1] << 8 | (uint32_t)b[p + 2] << 16 |
                   (uint32_t)b[p + 3] << 24);
        break;
      case 'i':
      case 'd':
      case 'f':
      case 'l':
      case 'b':
        len = 12 + ((uint32_t)b[p + 8] | (uint32_t)b[p + 9] << 8 | (uint32_t)b[p + 10] << 16 |
                    (uint32_t)b[p + 11] << 24);
        break;
      default:
        fail_msg("record at %zu: property type '%c'", at, t);
      }
      p += len;
    }
    assert_true(p == pe);
    if (pe < eo) assert_true(walk_fbx(b, pe, eo, name, found) == eo);
    at = eo;
  }
  fail_msg("an FBX record list without its end");
  return end;
}

/* Three levels (different meshes, one shared atlas) as one FBX: the file's
 * records are well formed; Assimp reads three nodes named _LOD0.._LOD2 with
 * every triangle, the texture found beside it with its texels, and each
 * level alone by its name (lod_node); a second write is byte-identical. */
static void test_fbx_chain(void **state) {
  (void)state;
  bbc_mesh lv[3];
  for (int k = 0; k < 3; k++) make_quads(&lv[k], (size_t)(3 - k) * 2, k == 0);
  char *path = join(tu_dir, "tree.fbx");
  char *png = join(tu_dir, "tree_fbx_leaf.png");
  const bbc_fbx_node nodes[3] = {
      {&lv[0], "tree_LOD0"}, {&lv[1], "tree_LOD1"}, {&lv[2], "tree_LOD2"}};
  bbc_error err;
  if (bbc_scene_write_fbx(path, nodes, 3, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_true(tu_have_file(png)); /* the three levels' identical atlases: one file */
  size_t n;
  uint8_t *b = tu_read_file(path, &n);
  assert_non_null(b);
  assert_true(n > 27 + 13);
  assert_memory_equal(b, "Kaydara FBX Binary  \0\x1a\0", 23);
  assert_int_equal(b[23] | b[24] << 8, 7400);
  int models = 0;
  size_t end = walk_fbx(b, 27, n, "Model", &models);
  assert_int_equal(models, 3);
  int geoms = 0;
  walk_fbx(b, 27, n, "Geometry", &geoms);
  assert_int_equal(geoms, 3);
  assert_true(end < n); /* the footer follows */
  free(b);

  bbc_mesh all;
  load_ok(path, &all);
  assert_int_equal(all.triangle_count,
                   lv[0].triangle_count + lv[1].triangle_count + lv[2].triangle_count);
  for (int k = 0; k < 3; k++) {
    char want[32];
    snprintf(want, sizeof want, "tree_LOD%d", k);
    int seen = 0;
    for (size_t g = 0; g < all.group_count; g++) seen |= strstr(all.group_names[g], want) != NULL;
    if (!seen) fail_msg("no group named %s", want);
  }
  bbc_mesh_free(&all);
  for (int k = 0; k < 3; k++) {
    bbc_load_options lo;
    bbc_load_options_default(&lo);
    lo.lod_node = k + 1;
    bbc_mesh one;
    if (bbc_mesh_load(path, &lo, &one, &err) != BBC_OK) fail_msg("level %d: %s", k, err.message);
    assert_int_equal(one.triangle_count, lv[k].triangle_count);
    assert_same_bbox(&lv[k], &one);
    assert_uv_orientation(&one); /* the texture found, its texels and v the right way */
    bbc_mesh_free(&one);
  }
  /* the same meshes again: the same bytes (the names inside depend on the
   * file's, so the same name in another folder) */
  char *sub = join(tu_dir, "again");
  assert_int_equal(mkdir(sub, 0755), 0);
  char *again = join(sub, "tree.fbx");
  if (bbc_scene_write_fbx(again, nodes, 3, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_true(tu_same_file(path, again));
  free(sub);
  /* errors: the extension, nothing to write */
  char *bad = join(tu_dir, "tree.fbx.txt");
  assert_int_equal(bbc_scene_write_fbx(bad, nodes, 3, &err), BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(bbc_scene_write_fbx(path, nodes, 0, &err), BBC_ERROR_EMPTY);
  assert_false(tu_have_file(bad));
  for (int k = 0; k < 3; k++) bbc_mesh_free(&lv[k]);
  free(bad);
  free(png);
  free(again);
  free(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_textured_quad),  cmocka_unit_test(test_two_materials),
      cmocka_unit_test(test_uint32_indices), cmocka_unit_test(test_tree),
      cmocka_unit_test(test_extras),         cmocka_unit_test(test_errors),
      cmocka_unit_test(test_deterministic),  cmocka_unit_test(test_fbx_chain),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
