/*
 * test_parts.c — bbc_split_parts (src/planes/parts.c): trunk / foliage split by
 * names, by geometry and by the user's patterns, on hand-built meshes with
 * known answers and on the real trees of ../shared/data (exact counts), the
 * built-in tree, non-trees that must stay one part, and invalid options.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#include "test_util.h"

/* ---- running a split ---------------------------------------------------- */

typedef struct split_result {
  bbc_result code;
  size_t parts;
  char names[2][32];
  char why[512];
  size_t count[2]; /* triangles per part */
  uint32_t *face_part;
  bbc_error err;
} split_result;

/* Runs the split with face_part pre-filled with garbage, so that a face the
 * function forgot to write is caught, and checks the output's shape. */
static void run_split(const bbc_mesh *m, const bbc_split_options *opt, split_result *r) {
  memset(r, 0, sizeof *r);
  size_t nt = m->triangle_count;
  r->face_part = malloc((nt ? nt : 1) * sizeof *r->face_part);
  assert_non_null(r->face_part);
  memset(r->face_part, 0xAB, (nt ? nt : 1) * sizeof *r->face_part);
  memset(r->names, 'x', sizeof r->names);
  r->parts = 99;
  r->code =
      bbc_split_parts(m, opt, r->face_part, &r->parts, r->names, r->why, sizeof r->why, &r->err);
  if (r->code != BBC_OK) return;
  assert_true(r->parts == 1 || r->parts == 2);
  if (r->parts == 1) {
    assert_string_equal(r->names[0], "all");
  } else {
    assert_string_equal(r->names[0], "trunk");
    assert_string_equal(r->names[1], "foliage");
  }
  for (size_t t = 0; t < nt; t++) {
    assert_true(r->face_part[t] < r->parts);
    r->count[r->face_part[t]]++;
  }
  assert_true(strlen(r->why) > 0);
}

static void split_free(split_result *r) {
  free(r->face_part);
  r->face_part = NULL;
}

static bbc_split_options mode_options(bbc_split_mode mode) {
  bbc_split_options o;
  memset(&o, 0, sizeof o);
  o.mode = mode;
  o.branches_with_trunk = 1; /* the stem rule only where a test asks for it */
  return o;
}

static int starts_with(const char *s, const char *prefix) {
  return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* Expects a split into exactly `trunk` and `foliage` triangles. */
static void expect_split(const split_result *r, size_t trunk, size_t foliage) {
  if (r->code != BBC_OK) fail_msg("split failed: %s", r->err.message);
  if (r->parts != 2 || r->count[0] != trunk || r->count[1] != foliage)
    fail_msg("expected trunk %zu / foliage %zu, got %zu parts: %zu / %zu (%s)", trunk, foliage,
             r->parts, r->count[0], r->count[1], r->why);
}

static void expect_one_part(const split_result *r, size_t triangles) {
  if (r->code != BBC_OK) fail_msg("split failed: %s", r->err.message);
  if (r->parts != 1) fail_msg("expected one part, got a split (%s)", r->why);
  assert_int_equal(r->count[0], triangles);
  assert_true(starts_with(r->why, "no split"));
}

/* ---- building meshes by hand -------------------------------------------- */

typedef struct builder {
  bbc_mesh m;
  size_t cap_v, cap_t;
} builder;

static void b_init(builder *b, const char *const *groups, size_t ng, const char *const *mats,
                   size_t nm) {
  memset(b, 0, sizeof *b);
  b->m.group_count = ng;
  b->m.group_names = calloc(ng, sizeof(char *));
  for (size_t i = 0; i < ng; i++) b->m.group_names[i] = strdup(groups[i]);
  b->m.material_count = nm;
  b->m.materials = calloc(nm, sizeof(bbc_material));
  for (size_t i = 0; i < nm; i++) {
    b->m.materials[i].name = strdup(mats[i]);
    b->m.materials[i].texture = -1;
    for (int k = 0; k < 4; k++) b->m.materials[i].base_color[k] = 1.0f;
  }
}

static uint32_t b_vertex(builder *b, double x, double y, double z) {
  if (b->m.vertex_count == b->cap_v) {
    b->cap_v = b->cap_v ? 2 * b->cap_v : 64;
    b->m.positions = realloc(b->m.positions, b->cap_v * 3 * sizeof(double));
    assert_non_null(b->m.positions);
  }
  double *p = b->m.positions + 3 * b->m.vertex_count;
  p[0] = x;
  p[1] = y;
  p[2] = z;
  return (uint32_t)b->m.vertex_count++;
}

static void b_triangle(builder *b, uint32_t v0, uint32_t v1, uint32_t v2, uint32_t group,
                       uint32_t material) {
  if (b->m.triangle_count == b->cap_t) {
    b->cap_t = b->cap_t ? 2 * b->cap_t : 64;
    b->m.indices = realloc(b->m.indices, b->cap_t * 3 * sizeof(uint32_t));
    b->m.face_group = realloc(b->m.face_group, b->cap_t * sizeof(uint32_t));
    b->m.face_material = realloc(b->m.face_material, b->cap_t * sizeof(uint32_t));
    assert_true(b->m.indices && b->m.face_group && b->m.face_material);
  }
  size_t t = b->m.triangle_count++;
  b->m.indices[3 * t] = v0;
  b->m.indices[3 * t + 1] = v1;
  b->m.indices[3 * t + 2] = v2;
  b->m.face_group[t] = group;
  b->m.face_material[t] = material;
}

/* A quad as two triangles with its own four vertices. */
static void b_quad(builder *b, const double *p0, const double *p1, const double *p2,
                   const double *p3, uint32_t group, uint32_t material) {
  uint32_t a = b_vertex(b, p0[0], p0[1], p0[2]);
  uint32_t c = b_vertex(b, p1[0], p1[1], p1[2]);
  uint32_t d = b_vertex(b, p2[0], p2[1], p2[2]);
  uint32_t e = b_vertex(b, p3[0], p3[1], p3[2]);
  b_triangle(b, a, c, d, group, material);
  b_triangle(b, a, d, e, group, material);
}

/* A tube of `sides` x `rings` quads (2 * sides * rings triangles) standing
 * at (x, 0, z). Every quad has its own vertices, as in a file that splits
 * vertices at UV seams or for flat shading: the tube is connected only
 * through equal positions, which the split must weld. */
static void b_tube_r(builder *b, double x, double z, double r, int sides, int rings, uint32_t group,
                     uint32_t material) {
  for (int i = 0; i < rings; i++)
    for (int j = 0; j < sides; j++) {
      double a0 = 2 * 3.14159265358979 * j / sides, a1 = 2 * 3.14159265358979 * (j + 1) / sides;
      double c0 = r * cos(a0), s0 = r * sin(a0), c1 = r * cos(a1), s1 = r * sin(a1);
      double p0[3] = {x + c0, i, z + s0}, p1[3] = {x + c1, i, z + s1};
      double p2[3] = {x + c1, i + 1, z + s1}, p3[3] = {x + c0, i + 1, z + s0};
      b_quad(b, p0, p1, p2, p3, group, material);
    }
}

static void b_tube(builder *b, double x, double z, int sides, int rings, uint32_t group,
                   uint32_t material) {
  b_tube_r(b, x, z, 1.0, sides, rings, group, material);
}

/* A separate leaf: one quad (2 triangles) at (x, y, z). */
static void b_leaf(builder *b, double x, double y, double z, uint32_t group, uint32_t material) {
  double p0[3] = {x, y, z}, p1[3] = {x + 0.3, y, z}, p2[3] = {x + 0.3, y + 0.3, z + 0.1},
         p3[3] = {x, y + 0.3, z + 0.1};
  b_quad(b, p0, p1, p2, p3, group, material);
}

/* A separate fan of n triangles around (x, y, z). */
static void b_fan(builder *b, double x, double y, double z, int n, uint32_t group,
                  uint32_t material) {
  uint32_t c = b_vertex(b, x, y, z);
  for (int i = 0; i < n; i++) {
    double a0 = 3.0 * i / n, a1 = 3.0 * (i + 1) / n;
    uint32_t v0 = b_vertex(b, x + 0.2 * cos(a0), y + 0.2 * sin(a0), z);
    uint32_t v1 = b_vertex(b, x + 0.2 * cos(a1), y + 0.2 * sin(a1), z);
    b_triangle(b, c, v0, v1, group, material);
  }
}

static void b_finish(builder *b) {
  bbc_error err;
  bbc_result r = bbc_mesh_finalize(&b->m, 0, "hand-built", &err);
  if (r != BBC_OK) fail_msg("finalize: %s", err.message);
}

/* The brief's tree: 30 leaves of 2 triangles (faces 0..59), then a tube of
 * 100 triangles (faces 60..159). Every face in group g, material mt. */
static void b_small_tree(builder *b, const char *group, const char *material) {
  const char *g[] = {group}, *mt[] = {material};
  b_init(b, g, 1, mt, 1);
  for (int i = 0; i < 30; i++) b_leaf(b, 5 + (i % 6), 3 + (i / 6), 0.5 * (i % 3), 0, 0);
  b_tube(b, 0, 0, 10, 5, 0, 0);
  b_finish(b);
}

/* ---- geometry ----------------------------------------------------------- */

static void test_geometry_tube_and_leaves(void **state) {
  (void)state;
  builder b;
  b_small_tree(&b, "", "");
  assert_int_equal(b.m.triangle_count, 160);
  bbc_split_options opt = mode_options(BBC_SPLIT_GEOMETRY);
  split_result r;
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 60);
  for (size_t t = 0; t < 160; t++) assert_int_equal(r.face_part[t], t < 60 ? 1 : 0);
  assert_true(starts_with(r.why, "geometry:"));
  assert_non_null(strstr(r.why, "30 small pieces"));
  split_free(&r);

  /* AUTO on a mesh whose names say nothing uses the geometry. */
  opt = mode_options(BBC_SPLIT_AUTO);
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 60);
  assert_true(starts_with(r.why, "geometry:"));
  split_free(&r);
  run_split(&b.m, NULL, &r); /* NULL options: AUTO */
  expect_split(&r, 100, 60);
  split_free(&r);

  /* NAMES alone cannot split it. */
  opt = mode_options(BBC_SPLIT_NAMES);
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 160);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* Welding is by exact position: moving one tube quad away by 1e-9 cuts it
 * off as a separate 2-triangle piece (it becomes foliage). */
static void test_geometry_weld_is_exact(void **state) {
  (void)state;
  builder b;
  b_small_tree(&b, "Object01", "Material.001");
  /* Faces 60, 61 are the tube's first quad: vertices 120..123. */
  for (uint32_t v = 120; v < 124; v++) b.m.positions[3 * v + 2] += 1e-9;
  bbc_split_options opt = mode_options(BBC_SPLIT_GEOMETRY);
  split_result r;
  run_split(&b.m, &opt, &r);
  expect_split(&r, 98, 62);
  assert_int_equal(r.face_part[60], 1);
  assert_int_equal(r.face_part[62], 0);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* 40 triangles that meet only at their apex, each with its own copy of
 * it, half of them written (-0, 1, -0): one piece (a long run of equal
 * positions, and -0 == +0). */
static void test_geometry_weld_star(void **state) {
  (void)state;
  const char *g[] = {""}, *mt[] = {""};
  builder b;
  b_init(&b, g, 1, mt, 1);
  for (int i = 0; i < 30; i++) b_leaf(&b, 5 + (i % 6), 3 + (i / 6), 0.5 * (i % 3), 0, 0);
  for (int i = 0; i < 40; i++) {
    double a0 = 0.15 * i, a1 = 0.15 * i + 0.1, zero = i % 2 ? -0.0 : 0.0;
    uint32_t apex = b_vertex(&b, zero, 1, zero);
    uint32_t v0 = b_vertex(&b, cos(a0), 0, sin(a0)), v1 = b_vertex(&b, cos(a1), 0, sin(a1));
    b_triangle(&b, apex, v0, v1, 0, 0);
  }
  b_finish(&b);
  bbc_split_options opt = mode_options(BBC_SPLIT_GEOMETRY);
  split_result r;
  run_split(&b.m, &opt, &r);
  expect_split(&r, 40, 60);
  assert_true(starts_with(r.why, "geometry: 1 large piece (40 triangles"));
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* Not tree-like: too few small pieces, small pieces of all sizes (a made
 * object), or a single piece: one part. */
static void test_geometry_refuses_non_trees(void **state) {
  (void)state;
  bbc_split_options opt = mode_options(BBC_SPLIT_GEOMETRY);
  split_result r;
  builder b;
  const char *g[] = {""}, *mt[] = {""};

  /* Tube and 10 leaves: too few. */
  b_init(&b, g, 1, mt, 1);
  b_tube(&b, 0, 0, 10, 5, 0, 0);
  for (int i = 0; i < 10; i++) b_leaf(&b, 5 + i, 3, 0, 0, 0);
  b_finish(&b);
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 120);
  assert_non_null(strstr(r.why, "too few"));
  split_free(&r);
  bbc_mesh_free(&b.m);

  /* Tube and 25 pieces of 1..25 triangles: parts of a machine. */
  b_init(&b, g, 1, mt, 1);
  b_tube(&b, 0, 0, 10, 5, 0, 0);
  for (int i = 0; i < 25; i++) b_fan(&b, 5 + i, 3, 0, i + 1, 0, 0);
  b_finish(&b);
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 100 + 25 * 26 / 2);
  assert_non_null(strstr(r.why, "differ"));
  split_free(&r);
  /* ... whereas 25 equal pieces of 4 triangles are foliage. */
  bbc_mesh_free(&b.m);
  b_init(&b, g, 1, mt, 1);
  b_tube(&b, 0, 0, 10, 5, 0, 0);
  for (int i = 0; i < 25; i++) b_fan(&b, 5 + i, 3, 0, 4, 0, 0);
  b_finish(&b);
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 100);
  split_free(&r);
  bbc_mesh_free(&b.m);

  /* One connected tube. */
  b_init(&b, g, 1, mt, 1);
  b_tube(&b, 0, 0, 10, 5, 0, 0);
  b_finish(&b);
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 100);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* ---- names -------------------------------------------------------------- */

/* Groups and materials given per face block: `n` faces (leaves of 2
 * triangles, so n is even) in group g, material mt. */
typedef struct block {
  uint32_t group, material;
  int faces;
} block;

static void b_blocks(builder *b, const char *const *groups, size_t ng, const char *const *mats,
                     size_t nm, const block *blocks, size_t nb) {
  b_init(b, groups, ng, mats, nm);
  int k = 0;
  for (size_t i = 0; i < nb; i++)
    for (int f = 0; f < blocks[i].faces; f += 2, k++)
      b_leaf(b, k % 10, k / 10, 0, blocks[i].group, blocks[i].material);
  b_finish(b);
}

static void test_names_materials_and_groups(void **state) {
  (void)state;
  bbc_split_options opt = mode_options(BBC_SPLIT_NAMES);
  split_result r;
  builder b;

  /* Quaternius: one group for everything; materials decide. */
  {
    const char *g[] = {"Tree_1_Cylinder.037"}, *mt[] = {"Bark", "Tree_Leaves"};
    const block bl[] = {{0, 1, 10}, {0, 0, 4}, {0, 1, 6}};
    b_blocks(&b, g, 1, mt, 2, bl, 3);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 4, 16);
    assert_int_equal(r.face_part[10], 0);
    assert_int_equal(r.face_part[9], 1);
    assert_true(starts_with(r.why, "names:"));
    assert_non_null(strstr(r.why, "Bark"));
    assert_non_null(strstr(r.why, "Tree_Leaves"));
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* A single group naming the whole tree is ignored, even with a keyword. */
  {
    const char *g[] = {"OakWithLeaves"}, *mt[] = {"Bark", "Leaf"};
    const block bl[] = {{0, 0, 6}, {0, 1, 8}};
    b_blocks(&b, g, 1, mt, 2, bl, 2);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 6, 8);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* Groups decide where materials say nothing; case and plurals, camel
   * case ("OldLeaves"), whole-word keywords ("stems_1.001"). */
  {
    const char *g[] = {"stems_1.001", "OldLeaves", "TRUNK.001", "needles"}, *mt[] = {"default"};
    const block bl[] = {{0, 0, 2}, {1, 0, 4}, {2, 0, 6}, {3, 0, 8}};
    b_blocks(&b, g, 4, mt, 1, bl, 4);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 8, 12);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* Whole-word keywords do not fire inside other words: no split. */
  {
    const char *g[] = {"System", "Logo", "Hollywood", "Crowned"}, *mt[] = {"Catalog"};
    const block bl[] = {{0, 0, 2}, {1, 0, 2}, {2, 0, 2}, {3, 0, 2}};
    b_blocks(&b, g, 4, mt, 1, bl, 4);
    run_split(&b.m, &opt, &r);
    expect_one_part(&r, 8);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* Material and group contradict (Scopia copper beech: material Branch in
   * group twig...): foliage. */
  {
    const char *g[] = {"tree_tree.002", "twig.534_tree"}, *mt[] = {"Trunk", "Branch", "Leaves"};
    const block bl[] = {{0, 0, 4}, {1, 1, 6}, {1, 2, 10}};
    b_blocks(&b, g, 2, mt, 3, bl, 3);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 4, 16);
    assert_non_null(strstr(r.why, "named trunk and foliage"));
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* A name with both kinds of keyword (a texture atlas) says nothing. */
  {
    const char *g[] = {"trunk", "leaves"}, *mt[] = {"BarkLeavesAtlas"};
    const block bl[] = {{0, 0, 6}, {1, 0, 4}};
    b_blocks(&b, g, 2, mt, 1, bl, 2);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 6, 4);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
}

static void test_names_unknown_faces(void **state) {
  (void)state;
  bbc_split_options opt = mode_options(BBC_SPLIT_NAMES);
  split_result r;
  builder b;
  /* Both kinds named: the rest (fruit) joins the foliage. */
  {
    const char *g[] = {"trunk", "leaves", "fruit"}, *mt[] = {"m"};
    const block bl[] = {{0, 0, 4}, {1, 0, 6}, {2, 0, 8}};
    b_blocks(&b, g, 3, mt, 1, bl, 3);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 4, 14);
    assert_non_null(strstr(r.why, "8 triangles with other names joined the foliage"));
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* Only foliage named: the rest is the trunk. */
  {
    const char *g[] = {"Object01", "Object02"}, *mt[] = {"Material.001", "Leaves"};
    const block bl[] = {{0, 0, 4}, {1, 1, 6}};
    b_blocks(&b, g, 2, mt, 2, bl, 2);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 4, 6);
    assert_int_equal(r.face_part[0], 0);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
  /* Only trunk named: the rest is the foliage. */
  {
    const char *g[] = {"Object01", "Object02"}, *mt[] = {"wood", "Material.001"};
    const block bl[] = {{0, 0, 4}, {1, 1, 6}};
    b_blocks(&b, g, 2, mt, 2, bl, 2);
    run_split(&b.m, &opt, &r);
    expect_split(&r, 4, 6);
    split_free(&r);
    bbc_mesh_free(&b.m);
  }
}

/* Names that make every face one kind settle it: one part, also in AUTO,
 * even where the geometry alone would split (a leafless tree of many
 * pieces) — unless all_trunk_by_geometry asks AUTO to let the geometry
 * split an all-trunk model (limbs: the limbs a mesh, the twigs on planes);
 * names that make every face foliage still settle it. */
static void test_names_all_one_kind(void **state) {
  (void)state;
  builder b;
  b_small_tree(&b, "DeadTree_1_Cylinder.038", "Bark");
  split_result r;
  bbc_split_options opt = mode_options(BBC_SPLIT_AUTO);
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 160);
  assert_non_null(strstr(r.why, "every face trunk"));
  split_free(&r);
  opt = mode_options(BBC_SPLIT_GEOMETRY);
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 60);
  split_free(&r);
  opt = mode_options(BBC_SPLIT_AUTO);
  opt.all_trunk_by_geometry = 1;
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 60);
  assert_non_null(strstr(r.why, "geometry"));
  split_free(&r);
  opt = mode_options(BBC_SPLIT_NAMES); /* names only: it stays one part */
  opt.all_trunk_by_geometry = 1;
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 160);
  split_free(&r);
  bbc_mesh_free(&b.m);
  b_small_tree(&b, "leaves", "Leaf");
  opt = mode_options(BBC_SPLIT_AUTO);
  opt.all_trunk_by_geometry = 1;
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 160);
  assert_non_null(strstr(r.why, "every face foliage"));
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* limbs: of a trunk of several pieces, the thickest that fit twice the
 * budget stay (the stem always), the thinner join the foliage, and
 * stem_only is not applied; limbs 0 moves nothing. The tree: 30 leaves
 * (faces 0..59), a stem of radius 1 (100 triangles), four twigs of radius
 * 0.1 and two branches of radius 0.4 (24 triangles each). */
static void test_limbs_thin_pieces(void **state) {
  (void)state;
  builder b;
  const char *g[] = {"leaves", "trunk"}, *mt[] = {"leaf", "bark"};
  b_init(&b, g, 2, mt, 2);
  for (int i = 0; i < 30; i++) b_leaf(&b, 5 + (i % 6), 3 + (i / 6), 0.5 * (i % 3), 0, 0);
  b_tube(&b, 0, 0, 10, 5, 1, 1);
  for (int i = 0; i < 4; i++) b_tube_r(&b, 3 + i, 0, 0.1, 6, 2, 1, 1);
  b_tube_r(&b, 8, 0, 0.4, 6, 2, 1, 1);
  b_tube_r(&b, 10, 0, 0.4, 6, 2, 1, 1);
  b_finish(&b);
  assert_int_equal(b.m.triangle_count, 304);
  bbc_split_options opt = mode_options(BBC_SPLIT_AUTO);
  split_result r;
  run_split(&b.m, &opt, &r); /* no limbs: the names decide */
  expect_split(&r, 244, 60);
  split_free(&r);
  opt.limbs = 80; /* 160 triangles: the stem and the two branches */
  opt.branches_with_trunk = 0;
  run_split(&b.m, &opt, &r);
  expect_split(&r, 148, 156);
  for (size_t t = 60; t < 160; t++) assert_int_equal(r.face_part[t], 0);  /* the stem */
  for (size_t t = 160; t < 256; t++) assert_int_equal(r.face_part[t], 1); /* the twigs */
  for (size_t t = 256; t < 304; t++) assert_int_equal(r.face_part[t], 0); /* the branches */
  assert_non_null(strstr(r.why, "limbs: 96 triangles of thin branches join the foliage"));
  assert_null(strstr(r.why, "stem only"));
  split_free(&r);
  opt.limbs = 40; /* 80 triangles: the stem still */
  run_split(&b.m, &opt, &r);
  expect_split(&r, 100, 204);
  split_free(&r);
  opt.limbs = 1000; /* everything fits */
  run_split(&b.m, &opt, &r);
  expect_split(&r, 244, 60);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

/* ---- none, patterns, points, explanations -------------------------------- */

static void test_none_mode(void **state) {
  (void)state;
  builder b;
  b_small_tree(&b, "trunk", "bark");
  bbc_split_options opt = mode_options(BBC_SPLIT_NONE);
  split_result r;
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 160);
  assert_int_equal(r.names[1][0], 0);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

static void test_patterns_hand_built(void **state) {
  (void)state;
  const char *g[] = {"Stamm_01", "Krone_02", "misc"}, *mt[] = {"matA", "matB"};
  const block bl[] = {{0, 0, 4}, {1, 1, 6}, {2, 1, 8}, {2, 0, 2}};
  builder b;
  b_blocks(&b, g, 3, mt, 2, bl, 4); /* faces 0-3, 4-9, 10-17, 18-19 */
  split_result r;
  bbc_split_options opt = mode_options(BBC_SPLIT_PATTERNS);

  opt.trunk_patterns = "stamm_*";
  run_split(&b.m, &opt, &r); /* rest NULL: foliage */
  expect_split(&r, 4, 16);
  assert_true(starts_with(r.why, "patterns:"));
  split_free(&r);

  opt.trunk_patterns = NULL;
  opt.foliage_patterns = "KRONE_0?";
  opt.rest = "trunk";
  run_split(&b.m, &opt, &r);
  expect_split(&r, 14, 6);
  split_free(&r);

  /* '?' is exactly one character, the match is whole-name. */
  opt.foliage_patterns = "krone_?";
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 20); /* nothing matches: all goes to the trunk */
  split_free(&r);
  opt.foliage_patterns = "krone";
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 20);
  split_free(&r);

  /* Lists, blanks around items, materials: matB faces are foliage, trunk
   * patterns win over foliage patterns. */
  opt.trunk_patterns = " nothing , St*01 ";
  opt.foliage_patterns = "x?z,  *B";
  opt.rest = "TRUNK";
  run_split(&b.m, &opt, &r);
  expect_split(&r, 6, 14);
  for (size_t t = 0; t < 20; t++) assert_int_equal(r.face_part[t], t < 4 || t >= 18 ? 0 : 1);
  split_free(&r);

  opt.trunk_patterns = "*";
  opt.foliage_patterns = "*";
  run_split(&b.m, &opt, &r);
  expect_one_part(&r, 20);
  split_free(&r);
  bbc_mesh_free(&b.m);
}

static void test_invalid_options(void **state) {
  (void)state;
  builder b;
  b_small_tree(&b, "trunk", "bark");
  split_result r;
  bbc_split_options opt = mode_options(BBC_SPLIT_AUTO);

  opt.rest = "leaves";
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_int_equal(r.err.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(r.err.message, "rest"));
  assert_non_null(strstr(r.err.message, "leaves"));
  split_free(&r);

  opt = mode_options(BBC_SPLIT_PATTERNS);
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(r.err.message, "patterns"));
  split_free(&r);
  opt.trunk_patterns = "  ";
  opt.foliage_patterns = "";
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  split_free(&r);
  opt.trunk_patterns = "bark,,trunk";
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(r.err.message, "empty pattern"));
  split_free(&r);
  opt.trunk_patterns = "bark";
  opt.foliage_patterns = "leaf*,";
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  split_free(&r);

  opt = mode_options((bbc_split_mode)42);
  run_split(&b.m, &opt, &r);
  assert_int_equal(r.code, BBC_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(r.err.message, "42"));
  split_free(&r);

  /* err may be NULL. */
  opt = mode_options(BBC_SPLIT_PATTERNS);
  uint32_t fp[160];
  size_t parts;
  char names[2][32];
  assert_int_equal(bbc_split_parts(&b.m, &opt, fp, &parts, names, NULL, 0, NULL),
                   BBC_ERROR_INVALID_ARGUMENT);
  bbc_mesh_free(&b.m);
}

static void test_points_and_why(void **state) {
  (void)state;
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  m.kind = BBC_MESH_POINTS;
  m.vertex_count = 3;
  m.positions = calloc(9, sizeof(double));
  m.positions[3] = 1;
  m.positions[7] = 1;
  bbc_split_options opt = mode_options(BBC_SPLIT_GEOMETRY);
  split_result r;
  run_split(&m, &opt, &r);
  assert_int_equal(r.code, BBC_OK);
  assert_int_equal(r.parts, 1);
  assert_string_equal(r.names[0], "all");
  assert_non_null(strstr(r.why, "point cloud"));
  split_free(&r);
  bbc_mesh_free(&m);

  /* `why` may be NULL, and is cut (terminated) to its size. */
  builder b;
  b_small_tree(&b, "", "");
  uint32_t fp[160];
  size_t parts = 0;
  char names[2][32], why[9];
  assert_int_equal(bbc_split_parts(&b.m, NULL, fp, &parts, names, NULL, 0, NULL), BBC_OK);
  assert_int_equal(parts, 2);
  memset(why, 'x', sizeof why);
  assert_int_equal(bbc_split_parts(&b.m, NULL, fp, &parts, names, why, sizeof why, NULL), BBC_OK);
  assert_string_equal(why, "geometry");
  bbc_mesh_free(&b.m);
}

/* ---- real data ---------------------------------------------------------- */

static int load_data(const char *rel, bbc_mesh *m) {
  char path[1024];
  tu_data_path(path, sizeof path, rel);
  if (!tu_have_file(path)) return 0;
  bbc_load_options opt;
  bbc_load_options_default(&opt);
  opt.skip_textures = 1;
  bbc_error err;
  if (bbc_mesh_load(path, &opt, m, &err) != BBC_OK) fail_msg("%s", err.message);
  return 1;
}

/* Splits `m` in `mode` and expects trunk / foliage (0 / 0: one part) and
 * an explanation starting with `why_prefix` (NULL: any). */
static void check_split(const bbc_mesh *m, const char *what, bbc_split_mode mode, size_t trunk,
                        size_t foliage, const char *why_prefix) {
  bbc_split_options opt = mode_options(mode);
  split_result r;
  run_split(m, &opt, &r);
  if (trunk + foliage == 0)
    expect_one_part(&r, m->triangle_count);
  else
    expect_split(&r, trunk, foliage);
  if (why_prefix && !starts_with(r.why, why_prefix))
    fail_msg("%s: explanation \"%s\" does not start with \"%s\"", what, r.why, why_prefix);
  split_free(&r);
}

static void check_file(const char *rel, bbc_split_mode mode, size_t trunk, size_t foliage,
                       const char *why_prefix) {
  bbc_mesh m;
  if (!load_data(rel, &m)) skip();
  check_split(&m, rel, mode, trunk, foliage, why_prefix);
  bbc_mesh_free(&m);
}

static size_t group_triangles(const bbc_mesh *m, const char *name) {
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; t++)
    if (!strcmp(m->group_names[m->face_group[t]], name)) n++;
  return n;
}

static void test_scopia_pine(void **state) {
  (void)state;
  const char *rel = "trees/scopia/pine/pine.obj";
  bbc_mesh m;
  if (!load_data(rel, &m)) skip();
  check_split(&m, rel, BBC_SPLIT_AUTO, 6210, 102600, "names:");
  check_split(&m, rel, BBC_SPLIT_NAMES, 6210, 102600, "names:");
  /* The trunk is one piece of 6,210 triangles, the foliage 4,500 twigs. */
  check_split(&m, rel, BBC_SPLIT_GEOMETRY, 6210, 102600,
              "geometry: 1 large piece (6,210 triangles");
  check_split(&m, rel, BBC_SPLIT_NONE, 0, 0, "no split");

  split_result r;
  bbc_split_options opt = mode_options(BBC_SPLIT_AUTO);
  run_split(&m, &opt, &r);
  for (size_t t = 0; t < m.triangle_count; t++)
    assert_int_equal(r.face_part[t], strcmp(m.group_names[m.face_group[t]], "tree") ? 1 : 0);
  split_free(&r);

  opt = mode_options(BBC_SPLIT_PATTERNS);
  opt.trunk_patterns = "tree";
  opt.rest = "foliage";
  run_split(&m, &opt, &r);
  expect_split(&r, 6210, 102600);
  split_free(&r);
  opt.trunk_patterns = NULL;
  opt.foliage_patterns = "Tw?gs_*";
  opt.rest = "trunk";
  run_split(&m, &opt, &r);
  expect_split(&r, 6210, 102600);
  split_free(&r);
  opt.foliage_patterns = "leav?s"; /* the foliage's material */
  run_split(&m, &opt, &r);
  expect_split(&r, 6210, 102600);
  split_free(&r);
  bbc_mesh_free(&m);
}

static void test_scopia_others(void **state) {
  (void)state;
  /* Twigs with material "Branch" inside the twig group are foliage; the
   * geometry agrees: one trunk piece, 9,940 twig clusters. */
  const char *rel = "trees/scopia/copperBeech/copperBeech.obj";
  bbc_mesh m;
  if (!load_data(rel, &m)) skip();
  check_split(&m, rel, BBC_SPLIT_AUTO, 6400, 180908, "names:");
  check_split(&m, rel, BBC_SPLIT_GEOMETRY, 6400, 180908, "geometry: 1 large piece");
  bbc_mesh_free(&m);
  /* Fronds 41,745 and old leaves 130 (group ShorOldPalms). */
  check_file("trees/scopia/palm/palm.obj", BBC_SPLIT_AUTO, 1448, 41875, "names:");
  /* Stems 2,844 and trunk 500 against leaves 36,948. */
  check_file("trees/scopia/bush/bush.obj", BBC_SPLIT_AUTO, 3344, 36948, "names:");
}

static void test_eztree(void **state) {
  (void)state;
  static const char *const files[] = {"oak_medium", "pine_medium", "ash_large_hi", "bush_1",
                                      "aspen_small"};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
    char rel[256];
    snprintf(rel, sizeof rel, "trees/eztree/%s.obj", files[i]);
    bbc_mesh m;
    if (!load_data(rel, &m)) skip();
    size_t trunk = group_triangles(&m, "trunk"), leaves = group_triangles(&m, "leaves");
    assert_int_equal(trunk + leaves, m.triangle_count);
    check_split(&m, rel, BBC_SPLIT_AUTO, trunk, leaves, "names:");
    if (i == 0) {
      assert_int_equal(trunk, 3166);
      assert_int_equal(leaves, 10640);
    }
    if (i == 1) {
      /* ez-tree's branches are separate tubes of 120+ triangles here, its
       * leaves cards of 2: the geometry finds every branch. */
      assert_int_equal(trunk, 10024);
      assert_int_equal(leaves, 9840);
      check_split(&m, rel, BBC_SPLIT_GEOMETRY, trunk, leaves, "geometry: 83 large pieces");
    }
    bbc_mesh_free(&m);
  }
}

static void test_quaternius(void **state) {
  (void)state;
  check_file("trees/quaternius/OBJ/Birch_1.obj", BBC_SPLIT_AUTO, 1204, 1104, "names:");
  check_file("trees/quaternius/OBJ/Pine_1.obj", BBC_SPLIT_AUTO, 148, 516, "names:");
  check_file("trees/quaternius/OBJ/Tree_1.obj", BBC_SPLIT_AUTO, 444, 360, "names:");
  check_file("trees/quaternius/OBJ/Tree_3.obj", BBC_SPLIT_AUTO, 1392, 696, "names:");
  /* No leaves: every face is Bark. */
  check_file("trees/quaternius/OBJ/DeadTree_1.obj", BBC_SPLIT_AUTO, 0, 0,
             "no split: the names make every face trunk");
}

static void test_non_trees(void **state) {
  (void)state;
  check_file("models/cat.3ds", BBC_SPLIT_AUTO, 0, 0, "no split: geometry");
  /* 83 pieces of all sizes: parts of a helicopter, not leaves. */
  const char *rel = "models/flightgear/H-60.ac";
  bbc_mesh m;
  if (!load_data(rel, &m)) skip();
  check_split(&m, rel, BBC_SPLIT_AUTO, 0, 0, "no split: geometry: the small pieces differ");
  check_split(&m, rel, BBC_SPLIT_NAMES, 0, 0, "no split: no material or group name");
  bbc_mesh_free(&m);
  check_file("models/flightgear/dauphin.ac", BBC_SPLIT_AUTO, 0, 0, NULL);
  check_file("models/horse.3ds", BBC_SPLIT_AUTO, 0, 0, NULL);
  check_file("models/teapot.obj", BBC_SPLIT_AUTO, 0, 0, NULL);
}

/* The built-in tree: split by its names; forced geometry makes every leaf
 * foliage (leaves are separate quads) and finds the trunk and big branches
 * as the trunk (twigs are small separate cones and go with the foliage). */
static void test_builtin_tree(void **state) {
  (void)state;
  bbc_tree_options to;
  bbc_tree_options_default(&to);
  to.seed = 1; /* the tree these checks were written for */
  to.leaves = 3000;
  bbc_mesh m;
  bbc_error err;
  assert_int_equal(bbc_tree_generate(&to, &m, &err), BBC_OK);
  size_t trunk = group_triangles(&m, "trunk"), leaves = group_triangles(&m, "leaves");
  assert_int_equal(leaves, 6000);
  assert_int_equal(trunk + leaves, m.triangle_count);

  bbc_split_options opt = mode_options(BBC_SPLIT_AUTO);
  split_result r;
  run_split(&m, &opt, &r);
  expect_split(&r, trunk, leaves);
  assert_true(starts_with(r.why, "names:"));
  split_free(&r);

  opt = mode_options(BBC_SPLIT_GEOMETRY);
  run_split(&m, &opt, &r);
  assert_int_equal(r.parts, 2);
  size_t geo_trunk = 0;
  for (size_t t = 0; t < m.triangle_count; t++) {
    int is_leaf = !strcmp(m.group_names[m.face_group[t]], "leaves");
    if (is_leaf) assert_int_equal(r.face_part[t], 1);
    geo_trunk += r.face_part[t] == 0;
  }
  /* The stem and the biggest branches (201 triangles of 1,245 here), at
   * most all the wood. */
  assert_true(geo_trunk >= 50 && geo_trunk <= trunk);
  split_free(&r);
  bbc_mesh_free(&m);
}

/* stem_only: the pine's trunk keeps its stem, the branches join the
 * foliage; every trunk face lies near the stem's axis. */
static void test_stem_only_pine(void **state) {
  (void)state;
  char path[1024];
  tu_data_path(path, sizeof path, "trees/scopia/pine/pine.obj");
  if (!tu_have_file(path)) skip();
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.skip_textures = 1;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) fail_msg("%s", err.message);
  bbc_split_options o;
  memset(&o, 0, sizeof o);
  o.mode = BBC_SPLIT_AUTO;
  o.branches_with_trunk = 0;
  o.up = BBC_UP_Y;
  uint32_t *fp = malloc(m.triangle_count * sizeof *fp);
  size_t parts;
  char names[2][32], why[320];
  assert_int_equal(bbc_split_parts(&m, &o, fp, &parts, names, why, sizeof why, &err), BBC_OK);
  assert_int_equal(parts, 2);
  assert_non_null(strstr(why, "stem only"));
  size_t trunk = 0;
  double xmin = 1e300, xmax = -1e300, zmin = 1e300, zmax = -1e300, ymax = -1e300;
  for (size_t t = 0; t < m.triangle_count; t++) {
    if (fp[t] != 0) continue;
    trunk++;
    for (int j = 0; j < 3; j++) {
      const double *p = m.positions + 3 * m.indices[3 * t + j];
      xmin = p[0] < xmin ? p[0] : xmin;
      xmax = p[0] > xmax ? p[0] : xmax;
      zmin = p[2] < zmin ? p[2] : zmin;
      zmax = p[2] > zmax ? p[2] : zmax;
      ymax = p[1] > ymax ? p[1] : ymax;
    }
  }
  /* A stem: a few hundred triangles, narrow (the crown is ~4 m wide), tall. */
  assert_true(trunk > 300 && trunk < 3000);
  assert_true(xmax - xmin < 80 && zmax - zmin < 80);
  assert_true(ymax > 300);
  /* With limbs too: the pine's trunk is one piece, stem_only still acts. */
  o.limbs = 512;
  assert_int_equal(bbc_split_parts(&m, &o, fp, &parts, names, why, sizeof why, &err), BBC_OK);
  assert_non_null(strstr(why, "stem only"));
  assert_null(strstr(why, "limbs:"));
  o.limbs = 0;
  /* Without stem_only the trunk keeps its 6,210 triangles. */
  o.branches_with_trunk = 1;
  assert_int_equal(bbc_split_parts(&m, &o, fp, &parts, names, NULL, 0, &err), BBC_OK);
  trunk = 0;
  for (size_t t = 0; t < m.triangle_count; t++) trunk += fp[t] == 0;
  assert_int_equal(trunk, 6210);
  free(fp);
  bbc_mesh_free(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_stem_only_pine),
      cmocka_unit_test(test_geometry_tube_and_leaves),
      cmocka_unit_test(test_geometry_weld_is_exact),
      cmocka_unit_test(test_geometry_weld_star),
      cmocka_unit_test(test_geometry_refuses_non_trees),
      cmocka_unit_test(test_names_materials_and_groups),
      cmocka_unit_test(test_names_unknown_faces),
      cmocka_unit_test(test_names_all_one_kind),
      cmocka_unit_test(test_limbs_thin_pieces),
      cmocka_unit_test(test_none_mode),
      cmocka_unit_test(test_patterns_hand_built),
      cmocka_unit_test(test_invalid_options),
      cmocka_unit_test(test_points_and_why),
      cmocka_unit_test(test_scopia_pine),
      cmocka_unit_test(test_scopia_others),
      cmocka_unit_test(test_eztree),
      cmocka_unit_test(test_quaternius),
      cmocka_unit_test(test_non_trees),
      cmocka_unit_test(test_builtin_tree),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
