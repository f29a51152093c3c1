/*
 * test_treegen.c — the built-in tree generator (src/gen/treegen*.c):
 * determinism, the leaf texture's binary alpha, exact leaf counts, every
 * species at small and large sizes, option checking and progress reports.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "bbc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers ------------------------------------------------------------ */

static void generate(bbc_tree_species species, size_t leaves, uint64_t seed, bbc_mesh *mesh) {
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.species = species;
  opt.leaves = leaves;
  opt.seed = seed;
  bbc_error err;
  memset(&err, 0, sizeof err);
  bbc_result r = bbc_tree_generate(&opt, mesh, &err);
  if (r != BBC_OK) printf("  tree generation failed: %s\n", err.message);
  assert_int_equal(r, BBC_OK);
}

/* Index of the group/material called `name`, or -1. */
static int group_index(const bbc_mesh *m, const char *name) {
  for (size_t i = 0; i < m->group_count; i++)
    if (!strcmp(m->group_names[i], name)) return (int)i;
  return -1;
}

static int material_index(const bbc_mesh *m, const char *name) {
  for (size_t i = 0; i < m->material_count; i++)
    if (!strcmp(m->materials[i].name, name)) return (int)i;
  return -1;
}

static const bbc_image *leaf_image(const bbc_mesh *m) {
  int leaf = material_index(m, "leaf");
  assert_true(leaf >= 0);
  int tex = m->materials[leaf].texture;
  assert_true(tex >= 0 && (size_t)tex < m->texture_count);
  return &m->textures[tex].image;
}

static int same_array(const void *a, const void *b, size_t bytes) {
  if (bytes == 0) return 1;
  if (!a || !b) return a == b;
  return memcmp(a, b, bytes) == 0;
}

/* Unnormalised normal of triangle t from its corners. */
static void face_normal(const bbc_mesh *m, size_t t, double *n) {
  const double *p0 = m->positions + 3 * m->indices[3 * t];
  const double *p1 = m->positions + 3 * m->indices[3 * t + 1];
  const double *p2 = m->positions + 3 * m->indices[3 * t + 2];
  double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* ---- tests -------------------------------------------------------------- */

/* Same seed and options: byte-identical arrays and textures. Another seed:
 * another tree. */
static void test_deterministic(void **state) {
  (void)state;
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++) {
    bbc_mesh a, b, c;
    generate((bbc_tree_species)s, 2000, 42, &a);
    generate((bbc_tree_species)s, 2000, 42, &b);
    generate((bbc_tree_species)s, 2000, 43, &c);
    assert_int_equal(a.vertex_count, b.vertex_count);
    assert_int_equal(a.triangle_count, b.triangle_count);
    assert_true(same_array(a.positions, b.positions, a.vertex_count * 3 * sizeof(double)));
    assert_true(same_array(a.normals, b.normals, a.vertex_count * 3 * sizeof(float)));
    assert_true(same_array(a.uvs, b.uvs, a.vertex_count * 2 * sizeof(float)));
    assert_true(same_array(a.indices, b.indices, a.triangle_count * 3 * sizeof(uint32_t)));
    assert_true(same_array(a.face_group, b.face_group, a.triangle_count * sizeof(uint32_t)));
    assert_true(same_array(a.face_material, b.face_material, a.triangle_count * sizeof(uint32_t)));
    assert_int_equal(a.texture_count, b.texture_count);
    for (size_t i = 0; i < a.texture_count; i++) {
      const bbc_image *ia = &a.textures[i].image, *ib = &b.textures[i].image;
      assert_int_equal(ia->width, ib->width);
      assert_int_equal(ia->height, ib->height);
      assert_true(same_array(ia->rgba, ib->rgba, (size_t)ia->width * ia->height * 4));
    }
    int differs = a.vertex_count != c.vertex_count ||
                  !same_array(a.positions, c.positions, a.vertex_count * 3 * sizeof(double));
    assert_true(differs);
    bbc_mesh_free(&a);
    bbc_mesh_free(&b);
    bbc_mesh_free(&c);
  }
}

/* The leaf texture has real transparency: alpha is 0 or 255, both occur. */
static void test_leaf_texture_alpha(void **state) {
  (void)state;
  static const int sizes[] = {8, 64, 128, 512};
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++)
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
      bbc_tree_options opt;
      bbc_tree_options_default(&opt);
      opt.seed = 1; /* the tree these checks were written for */
      opt.species = (bbc_tree_species)s;
      opt.leaves = 300;
      opt.texture_size = sizes[k];
      bbc_mesh m;
      bbc_error err;
      assert_int_equal(bbc_tree_generate(&opt, &m, &err), BBC_OK);
      const bbc_image *img = leaf_image(&m);
      assert_int_equal(img->width, sizes[k]);
      assert_int_equal(img->height, sizes[k]);
      size_t n = (size_t)img->width * img->height, zero = 0, full = 0, other = 0;
      for (size_t i = 0; i < n; i++) {
        uint8_t a = img->rgba[4 * i + 3];
        if (a == 0)
          zero++;
        else if (a == 255)
          full++;
        else
          other++;
      }
      assert_int_equal(other, 0);
      assert_true(zero > 0);
      assert_true(full > 0);
      int leaf = material_index(&m, "leaf");
      assert_int_equal(m.textures[m.materials[leaf].texture].has_alpha, 1);
      bbc_mesh_free(&m);
    }
}

/* Groups, materials and the exact number of leaf quads. */
static void test_groups_and_materials(void **state) {
  (void)state;
  static const size_t counts[] = {1, 7, 1234, 20000};
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++)
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
      bbc_mesh m;
      generate((bbc_tree_species)s, counts[k], 5, &m);
      int trunk = group_index(&m, "trunk"), leaves = group_index(&m, "leaves");
      assert_true(trunk >= 0);
      assert_true(leaves >= 0);
      int bark = material_index(&m, "bark"), leaf = material_index(&m, "leaf");
      assert_true(bark >= 0);
      assert_true(leaf >= 0);
      assert_true(m.materials[leaf].texture >= 0);
      assert_non_null(leaf_image(&m)->rgba);
      size_t per_group[8] = {0};
      assert_true(m.group_count <= 8);
      bbc_mesh_count_group_triangles(&m, per_group);
      assert_int_equal(per_group[leaves], 2 * counts[k]);
      assert_true(per_group[trunk] > 0);
      assert_int_equal(m.dropped_degenerate, 0);
      /* Leaves use the leaf material, wood the bark; leaf UVs span the
       * texture. */
      for (size_t t = 0; t < m.triangle_count; t++) {
        int is_leaf = (int)m.face_group[t] == leaves;
        assert_int_equal(m.face_material[t], (uint32_t)(is_leaf ? leaf : bark));
        if (!is_leaf) continue;
        for (int c = 0; c < 3; c++) {
          const float *uv = m.uvs + 2 * m.indices[3 * t + c];
          assert_true(uv[0] >= 0.0f && uv[0] <= 1.0f && uv[1] >= 0.0f && uv[1] <= 1.0f);
        }
      }
      bbc_mesh_free(&m);
    }
}

/* Every species, small: plausible size, finite, on the ground, unit normals
 * that agree with the winding (counter-clockwise = front). */
static void test_species_small(void **state) {
  (void)state;
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++)
    for (uint64_t seed = 1; seed <= 3; seed++) {
      bbc_mesh m;
      generate((bbc_tree_species)s, 300, seed, &m);
      double height = m.bbox_max[1] - m.bbox_min[1];
      printf("  %s seed %llu: %zu triangles, height %.2f m\n",
             bbc_tree_species_name((bbc_tree_species)s), (unsigned long long)seed, m.triangle_count,
             height);
      assert_true(height >= 2.0 && height <= 40.0);
      assert_true(m.bbox_min[1] >= -0.5);
      assert_true(m.triangle_count >= 600 && m.triangle_count < 2000);
      for (size_t i = 0; i < 3 * m.vertex_count; i++) assert_true(isfinite(m.positions[i]));
      assert_non_null(m.normals);
      for (size_t v = 0; v < m.vertex_count; v++) {
        const float *n = m.normals + 3 * v;
        double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        assert_true(fabs(l - 1.0) < 1e-3);
      }
      size_t agree = 0;
      for (size_t t = 0; t < m.triangle_count; t++) {
        double fn[3], vn[3] = {0, 0, 0};
        face_normal(&m, t, fn);
        for (int c = 0; c < 3; c++)
          for (int k = 0; k < 3; k++) vn[k] += m.normals[3 * m.indices[3 * t + c] + k];
        if (fn[0] * vn[0] + fn[1] * vn[1] + fn[2] * vn[2] > 0) agree++;
      }
      assert_int_equal(agree, m.triangle_count);
      bbc_mesh_free(&m);
    }
}

/* Large trees: over 100k triangles from 50k leaves, the wood a modest part,
 * and the species default within its documented range: 5,000-20,000 leaves
 * for the dense species, 1,000-10,000 for the airy larch and weeping birch,
 * none for the winter oak (its twigs planned for 20,000: thousands of wood
 * triangles). */
static void test_large_and_default(void **state) {
  (void)state;
  bbc_mesh m;
  generate(BBC_TREE_OAK, 50000, 7, &m);
  assert_true(m.triangle_count > 100000);
  size_t per_group[2];
  assert_int_equal(m.group_count, 2);
  bbc_mesh_count_group_triangles(&m, per_group);
  size_t trunk = per_group[group_index(&m, "trunk")];
  assert_true(trunk * 2 < m.triangle_count);
  bbc_mesh_free(&m);

  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++) {
    generate((bbc_tree_species)s, 0, 1, &m);
    bbc_mesh_count_group_triangles(&m, per_group);
    size_t leaves = per_group[group_index(&m, "leaves")] / 2;
    printf("  %s default: %zu leaves, %zu triangles\n", bbc_tree_species_name((bbc_tree_species)s),
           leaves, m.triangle_count);
    if (s == BBC_TREE_WINTER) {
      assert_int_equal(leaves, 0);
      assert_true(m.triangle_count > 5000);
    } else if (s >= BBC_TREE_LARCH) {
      assert_true(leaves >= 1000 && leaves <= 10000);
    } else {
      assert_true(leaves >= 5000 && leaves <= 20000);
    }
    bbc_mesh_free(&m);
  }
}

static void expect_invalid(const bbc_tree_options *opt, const char *why) {
  bbc_mesh m;
  memset(&m, 0x55, sizeof m); /* the generator must zero it */
  bbc_error err;
  memset(&err, 0, sizeof err);
  bbc_result r = bbc_tree_generate(opt, &m, &err);
  printf("  %s -> %s\n", why, err.message);
  assert_int_equal(r, BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(err.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_true(strlen(err.message) > 10);
  assert_int_equal(m.vertex_count, 0);
  assert_null(m.positions);
  bbc_mesh_free(&m);
}

static void test_invalid_options(void **state) {
  (void)state;
  static const int bad_sizes[] = {-64, 4, 100, 8192, 3}; /* 0: the default */
  for (size_t i = 0; i < sizeof bad_sizes / sizeof bad_sizes[0]; i++) {
    bbc_tree_options opt;
    bbc_tree_options_default(&opt);
    opt.seed = 1; /* the tree these checks were written for */
    opt.texture_size = bad_sizes[i];
    expect_invalid(&opt, "texture size");
  }
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.species = BBC_TREE_SPECIES_COUNT;
  expect_invalid(&opt, "species");
  opt.species = (bbc_tree_species)-1;
  expect_invalid(&opt, "species");
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.leaves = 5000001;
  expect_invalid(&opt, "leaves");
  /* The limits themselves are accepted. */
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.texture_size = 8;
  opt.leaves = 1;
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&opt, &m, &err), BBC_OK);
  bbc_mesh_free(&m);
}

static void test_species_names(void **state) {
  (void)state;
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++) {
    const char *name = bbc_tree_species_name((bbc_tree_species)s);
    assert_non_null(name);
    assert_int_equal(bbc_tree_species_from_name(name), s);
  }
  assert_string_equal(bbc_tree_species_name(BBC_TREE_PINE), "pine");
  assert_int_equal(bbc_tree_species_from_name("Birch"), BBC_TREE_BIRCH);
  assert_int_equal(bbc_tree_species_from_name("maple"), -1);
  assert_int_equal(bbc_tree_species_from_name("oa"), -1);
  assert_int_equal(bbc_tree_species_from_name("oaks"), -1);
  assert_int_equal(bbc_tree_species_from_name(""), -1);
  assert_int_equal(bbc_tree_species_from_name(NULL), -1);
  assert_null(bbc_tree_species_name(BBC_TREE_SPECIES_COUNT));
  assert_null(bbc_tree_species_name((bbc_tree_species)-1));
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  /* The defaults are a zeroed struct: an oak, seed 0, the species' leaves,
   * texture size 0 standing for 128; NULL options are the same. */
  bbc_tree_options zero;
  memset(&zero, 0, sizeof zero);
  bbc_tree_options_default(&opt);
  assert_memory_equal(&opt, &zero, sizeof opt);
  bbc_tree_options explicit_size = zero;
  explicit_size.texture_size = 128;
  explicit_size.leaves = 300;
  zero.leaves = 300;
  bbc_mesh a, b, c;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&zero, &a, &err), BBC_OK);
  assert_int_equal(bbc_tree_generate(&explicit_size, &b, &err), BBC_OK);
  assert_int_equal(bbc_tree_generate(NULL, &c, &err), BBC_OK);
  assert_int_equal(a.vertex_count, b.vertex_count);
  assert_memory_equal(a.positions, b.positions, 3 * a.vertex_count * sizeof *a.positions);
  assert_int_equal(a.textures[0].image.width, 128);
  assert_int_equal(b.textures[0].image.width, 128);
  assert_true(c.triangle_count > a.triangle_count); /* the species' own leaf count */
  bbc_mesh_free(&a);
  bbc_mesh_free(&b);
  bbc_mesh_free(&c);
}

typedef struct progress_log {
  int calls, ones, decreasing, bad_stage;
  double last;
} progress_log;

static void on_progress(void *user, const char *stage, double fraction) {
  progress_log *p = user;
  if (strcmp(stage, "tree")) p->bad_stage = 1;
  if (p->calls && fraction < p->last) p->decreasing = 1;
  if (fraction == 1.0) p->ones++;
  p->last = fraction;
  p->calls++;
}

static void test_progress(void **state) {
  (void)state;
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  opt.leaves = 30000;
  progress_log log = {0, 0, 0, 0, 0.0};
  opt.callbacks.progress = on_progress;
  opt.callbacks.user = &log;
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&opt, &m, &err), BBC_OK);
  assert_true(log.calls >= 3 && log.calls <= 50);
  assert_int_equal(log.ones, 1);
  assert_int_equal(log.decreasing, 0);
  assert_int_equal(log.bad_stage, 0);
  assert_true(log.last == 1.0);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_deterministic),        cmocka_unit_test(test_leaf_texture_alpha),
      cmocka_unit_test(test_groups_and_materials), cmocka_unit_test(test_species_small),
      cmocka_unit_test(test_large_and_default),    cmocka_unit_test(test_invalid_options),
      cmocka_unit_test(test_species_names),        cmocka_unit_test(test_progress),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
