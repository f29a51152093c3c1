/*
 * test_load_obj.c — our OBJ reader (src/io/load_obj.c) against Assimp's:
 * for every OBJ of the data set, a generated tree written as OBJ, and made
 * files that exercise objects, groups, material runs, quads (a concave
 * one), relative indices, missing normals and texture coordinates,
 * unknown materials and the MTL's keys, the mesh our reader gives equals
 * the one Assimp's path gives, bit for bit (positions, normals, texture
 * coordinates, triangles, groups, materials, textures); what the reader
 * leaves to Assimp (polygons, lines, indentation, texture options) is
 * deferred, and bbc_mesh_load still gives Assimp's mesh.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "bbc.h"
#include "io.h"
#include "test_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void assert_same_floats(const float *a, const float *b, size_t n) {
  assert_true((a == NULL) == (b == NULL));
  if (a) assert_memory_equal(a, b, n * sizeof *a);
}

static void assert_same_string(const char *a, const char *b) {
  assert_true((a == NULL) == (b == NULL));
  if (a) assert_string_equal(a, b);
}

/* Every field the loaders fill, bit for bit. */
static void assert_same_mesh(const bbc_mesh *a, const bbc_mesh *b) {
  assert_int_equal(a->kind, b->kind);
  assert_int_equal(a->vertex_count, b->vertex_count);
  assert_int_equal(a->triangle_count, b->triangle_count);
  assert_memory_equal(a->positions, b->positions, 3 * a->vertex_count * sizeof *a->positions);
  assert_same_floats(a->normals, b->normals, 3 * a->vertex_count);
  assert_same_floats(a->uvs, b->uvs, 2 * a->vertex_count);
  assert_same_floats(a->tangents, b->tangents, 4 * a->vertex_count);
  assert_memory_equal(a->indices, b->indices, 3 * a->triangle_count * sizeof *a->indices);
  assert_memory_equal(a->face_material, b->face_material,
                      a->triangle_count * sizeof *a->face_material);
  assert_memory_equal(a->face_group, b->face_group, a->triangle_count * sizeof *a->face_group);
  assert_int_equal(a->group_count, b->group_count);
  for (size_t g = 0; g < a->group_count; g++)
    assert_string_equal(a->group_names[g], b->group_names[g]);
  assert_int_equal(a->material_count, b->material_count);
  for (size_t i = 0; i < a->material_count; i++) {
    const bbc_material *x = &a->materials[i], *y = &b->materials[i];
    assert_string_equal(x->name, y->name);
    assert_memory_equal(x->base_color, y->base_color, sizeof x->base_color);
    assert_memory_equal(x->ambient, y->ambient, sizeof x->ambient);
    assert_true(x->roughness == y->roughness);
    assert_int_equal(x->texture, y->texture);
    assert_same_string(x->texture_ref, y->texture_ref);
    assert_int_equal(x->normal_map, y->normal_map);
    assert_int_equal(x->occlusion_map, y->occlusion_map);
    assert_int_equal(x->single_sided, y->single_sided);
    assert_int_equal(x->unlit, y->unlit);
  }
  assert_int_equal(a->texture_count, b->texture_count);
  for (size_t i = 0; i < a->texture_count; i++) {
    assert_same_string(a->textures[i].path, b->textures[i].path);
    assert_int_equal(a->textures[i].image.width, b->textures[i].image.width);
    assert_int_equal(a->textures[i].image.height, b->textures[i].image.height);
  }
  assert_int_equal(a->dropped_degenerate, b->dropped_degenerate);
  assert_memory_equal(a->center, b->center, sizeof a->center);
  assert_true(a->radius == b->radius);
}

/* The file through our reader (1: read by it, 0: deferred to Assimp) and
 * through Assimp's path; when read, the two meshes must be the same. */
static int compare_readers(const char *path) {
  size_t size;
  unsigned char *buf = tu_read_file(path, &size);
  assert_non_null(buf);
  char *text = realloc(buf, size + 1);
  assert_non_null(text);
  text[size] = 0;
  bbc_load_options o;
  bbc_load_options_default(&o);
  bbc_mesh ours, theirs;
  bbc_error err;
  memset(&ours, 0, sizeof ours);
  int deferred = 0;
  bbc_result r = bbc__parse_obj(path, text, size, &o, &ours, &deferred, &err);
  free(text);
  if (deferred) return 0;
  r = bbc__load_finish(path, r, 1, &o, &ours, &err);
  if (r != BBC_OK) fail_msg("%s: our reader: %s", path, err.message);
  memset(&theirs, 0, sizeof theirs);
  r = bbc__load_assimp(path, &o, &theirs, &err);
  r = bbc__load_finish(path, r, 1, &o, &theirs, &err);
  if (r != BBC_OK) fail_msg("%s: Assimp: %s", path, err.message);
  assert_same_mesh(&ours, &theirs);
  bbc_mesh_free(&ours);
  bbc_mesh_free(&theirs);
  return 1;
}

/* Whether an OBJ has what our reader leaves to Assimp: a face of more
 * than 4 corners (Assimp cuts them by ear clipping) or points. */
static int left_to_assimp(const char *path) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  char line[4096];
  int found = 0;
  while (!found && fgets(line, sizeof line, f)) {
    if (line[1] != ' ' && line[1] != '\t') continue;
    if (line[0] == 'p') found = 1;
    if (line[0] != 'f') continue;
    int corners = 0;
    for (char *t = strtok(line + 1, " \t\r\n"); t; t = strtok(NULL, " \t\r\n")) corners++;
    found = corners > 4;
  }
  fclose(f);
  return found;
}

/* Every OBJ of the data set: read by ours, giving Assimp's mesh, unless
 * it has polygons of more than 4 corners (the Quaternius trees' trunk
 * caps, one in the Scopia pine, palm and beech), which are left to
 * Assimp. The Scopia bush's loose edges (`l`) are read. */
static void test_data_set(void **state) {
  (void)state;
  static const char *files[] = {"trees/scopia/palm/palm.obj",
                                "trees/scopia/pine/pine.obj",
                                "trees/scopia/copperBeech/copperBeech.obj",
                                "trees/scopia/bush/bush.obj",
                                "trees/eztree/oak_medium.obj",
                                "trees/eztree/ash_large_hi.obj",
                                "trees/eztree/bush_1.obj",
                                "trees/eztree/pine_medium.obj",
                                "trees/eztree/aspen_small.obj",
                                "trees/quaternius/OBJ/Birch_1.obj",
                                "trees/quaternius/OBJ/Tree_3.obj",
                                "trees/quaternius/OBJ/Pine_1.obj",
                                "trees/quaternius/OBJ/Tree_1.obj",
                                "trees/quaternius/OBJ/DeadTree_1.obj",
                                "models/teapot.obj",
                                "models/bunny.obj"};
  int present = 0, read = 0;
  for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
    char path[1024];
    tu_data_path(path, sizeof path, files[i]);
    if (!tu_have_file(path)) continue;
    present++;
    int ours = compare_readers(path);
    read += ours;
    print_message("%s: %s\n", files[i], ours ? "read by ours, the same mesh" : "left to Assimp");
    assert_int_equal(ours, !left_to_assimp(path));
  }
  if (!present) skip();
  assert_true(read >= 1);
}

/* A generated tree written as OBJ (what `bbcgen tree` writes). */
static void test_generated_tree(void **state) {
  (void)state;
  bbc_tree_options t;
  bbc_tree_options_default(&t);
  t.leaves = 800;
  t.seed = 3;
  bbc_mesh m;
  bbc_error err;
  if (bbc_tree_generate(&t, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  char *dir = tu_make_temp_dir();
  char path[1024];
  snprintf(path, sizeof path, "%s/tree.obj", dir);
  if (bbc_mesh_write_obj(path, &m, NULL, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_mesh_free(&m);
  assert_int_equal(compare_readers(path), 1);
  tu_remove_dir(dir);
  free(dir);
}

/* Made files: each read by ours and equal to Assimp's, or deferred. */
typedef struct made {
  const char *obj, *mtl;
  int deferred;
} made;

static const made k_made[] = {
    /* objects, groups, material runs, quads (the second concave), negative
     * indices, faces without normals beside faces with them */
    {"mtllib m.mtl\n"
     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.3 0.3 0\nv 2 0 1e-3\nv 2.5 1.25 -0.000125\n"
     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1 0.5\n"
     "vn 0 0 1\nvn 0 0.6 0.8\n"
     "o first\nusemtl leaf\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf 1/1/2 2/2/2 5/3/2 4/4/2\n"
     "usemtl bark\nf 2/2 6/3 7/4\nf -5/-4 -4/-3 -3/-2\n"
     "g twigs\nf 1//1 2//1 3//2\nusemtl leaf\nf 1 2 6\ns 1\nf 2 6 7\n"
     "o first\nf 3 4 7\ng twigs\nf 4 5 6\ng other\nusemtl nothere\nf 1 3 7\n",
     "# made\nnewmtl leaf\nKd 0.2 0.7 0.1\nKa 0.1 0.1 0.1\nd 0.5\nNs 96.078431\nillum 2\n"
     "map_Kd leaf.png\nmap_d leaf.png\n\nnewmtl bark\n\tKd 0.46 0.37 0.29\n\tillum 0\n"
     "\tNs 0\n\tKs 0.5 0.5 0.5\n",
     0},
    /* faces before any object or material, then a usemtl before an object,
     * a library that is missing (no material then: plain named ones) */
    {"mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nusemtl a\nf 1 2 4\n"
     "usemtl b\nf 1 3 4\no later\nf 2 3 4\nusemtl a\nf 3 2 1\n",
     NULL, 0},
    /* numbers: exponents, 20 decimals, signs, CRLF line ends */
    {"v 1.2345678901234567890 -0.5e-3 +3\r\nv 1E2 2.5e+1 -7.0000001\r\nv 0.1 0.2 0.3\r\n"
     "v 123456789.123 -0.000000001 42\r\nf 1 2 3\r\nf 2 3 4\r\n",
     NULL, 0},
    /* lines beside quads (a concave one) with normals and texture
     * coordinates (Assimp's SortByPType then gives the triangles a vertex
     * a corner), an object of lines alone, relative line indices */
    {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.3 0.3 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
     "o mixed\nf 1/1/1 2/2/1 5/3/1 4/1/1\nl 1 2 3\nf 2/2/1 3/3/1 4/1/1\nf 1 2 3 4\n"
     "o edges\nl 1 3\nl -1 -2 -3 -4\no plain\nf 1 2 3\n",
     NULL, 0},
    /* degenerate quads: a corner twice, three corners in a line, a bow tie */
    {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\nv 3 3 0\n"
     "f 1 2 2 3\nf 1 1 2 3\nf 4 5 6 3\nf 1 3 2 4\nf 1 2 3 1\nf 1 2 3 4\n",
     NULL, 0},
    /* a library with CRLF line ends (as Windows exporters write it) */
    {"mtllib m.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nusemtl x\r\nf 1 2 3\r\nusemtl y\r\n"
     "f 3 2 1\r\n",
     "newmtl x\r\nKd 0.5 0.25 0.125\r\nd 0.5\r\n\r\nnewmtl y\r\nillum 0\r\nmap_Kd leaf.png\r\n", 0},
    /* left to Assimp: a pentagon, points, an indented line, texture options */
    {"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4 5\n", NULL, 1},
    {"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\np 1 2\n", NULL, 1},
    {"v 0 0 0\nv 1 0 0\nv 1 1 0\n  f 1 2 3\nf 1 2 3\n", NULL, 1},
    {"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl x\nf 1 2 3\n",
     "newmtl x\nmap_Kd -s 2 2 1 leaf.png\n", 1},
};

static void test_made_files(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  /* a 2x2 texture for map_Kd */
  bbc_image img;
  assert_int_equal(bbc_image_alloc(&img, 2, 2), BBC_OK);
  memset(img.rgba, 200, 16);
  char png[1024];
  snprintf(png, sizeof png, "%s/leaf.png", dir);
  bbc_error err;
  if (bbc_image_write_png(png, &img, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_image_free(&img);
  for (size_t i = 0; i < sizeof k_made / sizeof *k_made; i++) {
    char name[32];
    snprintf(name, sizeof name, "made%zu.obj", i);
    char *path = tu_write_file(dir, name, k_made[i].obj, strlen(k_made[i].obj));
    if (k_made[i].mtl) free(tu_write_file(dir, "m.mtl", k_made[i].mtl, strlen(k_made[i].mtl)));
    int read = compare_readers(path);
    print_message("made %zu: %s\n", i, read ? "read by ours, the same mesh" : "left to Assimp");
    assert_int_equal(read, !k_made[i].deferred);
    /* bbc_mesh_load either way */
    bbc_mesh m;
    if (bbc_mesh_load(path, NULL, &m, &err) != BBC_OK) fail_msg("%s: %s", path, err.message);
    assert_true(m.triangle_count >= 1);
    bbc_mesh_free(&m);
    free(path);
  }
  tu_remove_dir(dir);
  free(dir);
}

/* An OBJ cut short where it held only vertices: a trunk's quads (n_faces)
 * with their vertices, then `trailing` more vertices and no face (the
 * leaves' block the cut fell in). */
static char *cut_obj(int trailing, int tail_face, size_t *len) {
  size_t cap = 64 * (size_t)(trailing + 64), n = 0;
  char *b = malloc(cap);
  assert_non_null(b);
  for (int i = 0; i < 20; i++) n += (size_t)snprintf(b + n, cap - n, "v %d 0 0\nv %d 1 0\n", i, i);
  for (int i = 0; i < 19; i++)
    n += (size_t)snprintf(b + n, cap - n, "f %d %d %d %d\n", 2 * i + 1, 2 * i + 3, 2 * i + 4,
                          2 * i + 2);
  n += (size_t)snprintf(b + n, cap - n, "o leaves\n");
  for (int i = 0; i < trailing; i++)
    n += (size_t)snprintf(b + n, cap - n, "v %d.5 2 0.25\n", i % 19);
  if (tail_face) n += (size_t)snprintf(b + n, cap - n, "f 41 42 43\n");
  *len = n;
  return b;
}

/* A file cut short is refused (BBC_ERROR_CORRUPT, naming the vertices
 * after its last face) unless accept_unused says otherwise; a whole file
 * of the same lines, or a few stray vertices at the end, loads. */
static void test_cut_short(void **state) {
  (void)state;
  bbc_load_options o;
  bbc_load_options_default(&o);
  bbc_mesh m;
  bbc_error err;
  size_t len;
  char *b = cut_obj(5000, 0, &len);
  assert_int_equal(bbc_mesh_load_memory("cut.obj", b, len, &o, &m, &err), BBC_ERROR_CORRUPT);
  assert_non_null(strstr(err.message, "5000 of its 5040 vertices follow its last face"));
  char *dir = tu_make_temp_dir();
  char *path = tu_write_file(dir, "cut.obj", b, len);
  assert_int_equal(bbc_mesh_load(path, &o, &m, &err), BBC_ERROR_CORRUPT);
  o.accept_unused = 1;
  assert_int_equal(bbc_mesh_load(path, &o, &m, &err), BBC_OK);
  assert_int_equal(m.triangle_count, 38);
  assert_int_equal(m.vertex_count, 40); /* the unused vertices dropped */
  bbc_mesh_free(&m);
  free(path);
  tu_remove_dir(dir);
  free(dir);
  free(b);
  o.accept_unused = 0;
  /* the same vertices with a face after them: whole */
  b = cut_obj(5000, 1, &len);
  if (bbc_mesh_load_memory("whole.obj", b, len, &o, &m, &err) != BBC_OK)
    fail_msg("%s", err.message);
  bbc_mesh_free(&m);
  free(b);
  /* 99 stray vertices at the end: loaded */
  b = cut_obj(99, 0, &len);
  if (bbc_mesh_load_memory("stray.obj", b, len, &o, &m, &err) != BBC_OK)
    fail_msg("%s", err.message);
  bbc_mesh_free(&m);
  free(b);
}

/* Random files of the subset (LCG, seed fixed): numbers in several forms,
 * triangles, quads and lines in every index form, relative indices,
 * objects, groups and materials switched at random (names reused), a
 * library of two of the four names: each read by ours equal to Assimp's.
 * (It found that `o NAME` of a name used twice goes back to the first such
 * object, as Assimp looks, not the last.) */
static uint64_t lcg(uint64_t *x) {
  *x = *x * 6364136223846793005ULL + 1442695040888963407ULL;
  return *x >> 33;
}

static void test_random_files(void **state) {
  (void)state;
  char *dir = tu_make_temp_dir();
  const char *mtl = "newmtl leaf\nKd 0.3 0.6 0.2\nd 0.75\nNs 10\nnewmtl bark\nKa 0.1 0.2 0.3\n"
                    "illum 0\n";
  free(tu_write_file(dir, "m.mtl", mtl, strlen(mtl)));
  static const char *names[] = {"leaf", "bark", "twig", "DefaultMaterial"};
  uint64_t x = 42;
  int read = 0;
  for (int file = 0; file < 300; file++) {
    size_t cap = 1 << 16, n = 0;
    char *b = malloc(cap);
    assert_non_null(b);
#define OUT(...) n += (size_t)snprintf(b + n, cap - n, __VA_ARGS__)
    if (file % 2) OUT("mtllib m.mtl\n");
    int nv = 0, nt = 0, nn = 0;
    for (int i = 0; i < 200; i++) {
      uint64_t r = lcg(&x) % 100;
      if (n > cap - 256) break;
      if (r < 30 || nv < 4) {
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = ((double)(lcg(&x) % 20001) - 10000) / 997.0;
        if (r % 3 == 0)
          OUT("v %.9g %.3e %g\n", c[0], c[1], c[2]);
        else if (r % 3 == 1)
          OUT("v %.6f %.15f %.2f\n", c[0], c[1], c[2]);
        else
          OUT("v %.20f %.8E %+.1f\n", c[0], c[1] * 1e-7, c[2] * 1e6);
        nv++;
      } else if (r < 38) {
        OUT("vt %.5f %.5f\n", (double)(lcg(&x) % 1000) / 999.0, (double)(lcg(&x) % 1000) / 999.0);
        nt++;
      } else if (r < 44) {
        OUT("vn %.4f %.4f %.4f\n", 0.1 * (double)(lcg(&x) % 10), 0.5, -0.25);
        nn++;
      } else if (r < 80) {
        int corners = 3 + (int)(lcg(&x) % 2), form = (int)(lcg(&x) % 4);
        if ((form & 1) && !nt) form &= ~1;
        if ((form & 2) && !nn) form &= ~2;
        OUT("f");
        for (int k = 0; k < corners; k++) {
          int v = 1 + (int)(lcg(&x) % (uint64_t)nv), rel = lcg(&x) % 5 == 0;
          OUT(" %d", rel ? v - nv - 1 : v);
          if (form == 1) OUT("/%d", 1 + (int)(lcg(&x) % (uint64_t)nt));
          if (form == 2) OUT("//%d", 1 + (int)(lcg(&x) % (uint64_t)nn));
          if (form == 3)
            OUT("/%d/%d", 1 + (int)(lcg(&x) % (uint64_t)nt), 1 + (int)(lcg(&x) % (uint64_t)nn));
        }
        OUT("\n");
      } else if (r < 84) {
        OUT("l %d %d %d\n", 1 + (int)(lcg(&x) % (uint64_t)nv), 1 + (int)(lcg(&x) % (uint64_t)nv),
            -1);
      } else if (r < 89) {
        OUT("usemtl %s\n", names[lcg(&x) % 4]);
      } else if (r < 93) {
        OUT("o %s\n", names[lcg(&x) % 4]);
      } else if (r < 97) {
        OUT("g %s\n", names[lcg(&x) % 4]);
      } else {
        OUT("s %d\n", (int)(lcg(&x) % 2));
      }
    }
    OUT("f 1 2 3\n");
#undef OUT
    char name[32];
    snprintf(name, sizeof name, "r%d.obj", file);
    char *path = tu_write_file(dir, name, b, n);
    free(b);
    read += compare_readers(path);
    free(path);
  }
  print_message("%d of 300 random files read by ours, each the same mesh as Assimp's\n", read);
  assert_int_equal(read, 300);
  tu_remove_dir(dir);
  free(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_data_set),   cmocka_unit_test(test_generated_tree),
      cmocka_unit_test(test_made_files), cmocka_unit_test(test_random_files),
      cmocka_unit_test(test_cut_short),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
