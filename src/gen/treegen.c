/*
 * treegen.c — the built-in procedural tree generator (bbc_tree_generate).
 *
 * The thesis tests BBCgen on trees; this generator gives the toolkit test
 * trees of any size without shipping model files. A tree is made in three
 * steps:
 *   1. plan: from the species and the requested leaf count decide how many
 *      branches each level gets and how finely the tubes are tessellated, so
 *      the wood stays a modest fraction of the triangles at every size;
 *   2. skeleton: the trunk (or the stems of a bush) first, then each level's
 *      branches are spread over the level above by stratified sampling along
 *      the parents' lengths (linear time, even spacing with jitter). Every
 *      branch is grown as a polyline bent by gravity, phototropism and a
 *      smooth random wobble, and kept only at the rings that will be drawn,
 *      so children sit exactly on the drawn axis of their parent;
 *   3. geometry: every branch becomes a tapered tube of rings with shared
 *      vertices and a pointed tip; leaves are textured quads spread over the
 *      finest branches (the twigs), denser toward the twig tips.
 * Two textures are generated: the leaf (texture 0, alpha exactly 0 or 255;
 * a needle spray for the pine) and a small tileable bark pattern (texture
 * 1, repeated along the branches, multiplied by the bark's base colour).
 *
 * Levels: 0 trunk (or bush stems), 1 limbs, 2 branches, 3 twigs. The finest
 * level in use carries the leaves (the pine's limbs too). All randomness
 * comes from bbc__rng streams derived from the seed and the species, in a
 * fixed order, so the same options always give byte-identical arrays.
 *
 * This file holds the public entry, the species and the plan (step 1);
 * treegen_grow.c grows the skeleton (step 2) and treegen_mesh.c makes the
 * geometry and the textures (step 3); treegen.h is what they share.
 */
#include "treegen.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TG_MAX_LEAVES  5000000u
#define TG_MIN_TEXTURE 8
#define TG_MAX_TEXTURE 4096

/* ------------------------------------------------------------------------ */
/* Species                                                                   */
/* ------------------------------------------------------------------------ */

/* The oak's branching, shared by the winter oak. */
#define TG_OAK_BRANCHING                                                                           \
  .levels = 4, .twig_factor = 0.40, .branch_factor = 1.3, .leaf_exponent = 0.4,                    \
  .rules = {[1] = {{0, 0.32, 0.97, 1}},                                                            \
            [2] = {{1, 0.15, 1.0, 1}, {0, 0.80, 1.0, 1}},                                          \
            [3] = {{2, 0.10, 1.0, 1}, {1, 0.5, 1.0, 1}}},                                          \
  .leaf_rules = {{3, 0.40, 1.0, 1}}

static const tg_species tg_species_table[BBC_TREE_SPECIES_COUNT] = {
    {.name = "oak",
     .shape = BBC_TREE_OAK,
     .height = 13.0,
     .default_leaves = 20000,
     .leaf_size = 0.24,
     .bark = {0.46f, 0.37f, 0.29f},
     .leaf = {0.22f, 0.40f, 0.12f},
     TG_OAK_BRANCHING},
    {.name = "pine",
     .shape = BBC_TREE_PINE,
     .height = 20.0,
     .default_leaves = 8000,
     .leaf_size = 0.45,
     .bark = {0.50f, 0.36f, 0.27f},
     .leaf = {0.12f, 0.27f, 0.11f},
     .levels = 3,
     .twig_factor = 0.50,
     .leaf_exponent = 1.0,
     /* Level 1 (the whorls) is placed by its own code. */
     .rules = {[2] = {{1, 0.10, 0.95, 1}}},
     .leaf_rules = {{2, 0.0, 1.0, 1}, {1, 0.35, 1.0, 0.8}}},
    {.name = "birch",
     .shape = BBC_TREE_BIRCH,
     .height = 16.0,
     .default_leaves = 20000,
     .leaf_size = 0.13,
     .bark = {0.90f, 0.88f, 0.84f},
     .leaf = {0.33f, 0.52f, 0.14f},
     .levels = 4,
     .twig_factor = 0.40,
     .branch_factor = 0.9,
     .leaf_exponent = 0.8,
     .rules = {[1] = {{0, 0.27, 0.97, 1}}, [2] = {{1, 0.15, 1.0, 1}}, [3] = {{2, 0.10, 1.0, 1}}},
     .leaf_rules = {{3, 0.0, 1.0, 1}, {2, 0.4, 1.0, 0.5}}},
    {.name = "bush",
     .shape = BBC_TREE_BUSH,
     .height = 2.6,
     .default_leaves = 8000,
     .leaf_size = 0.12,
     .bark = {0.46f, 0.39f, 0.32f},
     .leaf = {0.17f, 0.36f, 0.11f},
     .levels = 3,
     .twig_factor = 0.40,
     .leaf_exponent = 0.6,
     .rules = {[1] = {{0, 0.12, 0.95, 1}}, [2] = {{1, 0.10, 1.0, 1}, {0, 0.50, 1.0, 0.6}}},
     .leaf_rules = {{2, 0.15, 1.0, 1}}},
    /* Airy species (sparse crowns, thin parts: what clouds find hardest). */
    {.name = "larch", /* a conifer: needle tufts on long thin twigs, see-through */
     .shape = BBC_TREE_PINE,
     .height = 18.0,
     .default_leaves = 2500,
     .leaf_size = 0.22,
     .bark = {0.45f, 0.33f, 0.26f},
     .leaf = {0.30f, 0.45f, 0.16f},
     .levels = 3,
     .twig_factor = 0.9,
     .leaf_exponent = 1.0,
     .twig_thin = 0.6,
     .rules = {[2] = {{1, 0.10, 0.95, 1}}},
     .leaf_rules = {{2, 0.2, 1.0, 1}}},
    {.name = "weeping", /* a weeping birch: thin twigs hanging in curtains */
     .shape = BBC_TREE_BIRCH,
     .height = 15.0,
     .default_leaves = 6000,
     .leaf_size = 0.10,
     .bark = {0.88f, 0.86f, 0.82f},
     .leaf = {0.36f, 0.55f, 0.16f},
     .levels = 4,
     .twig_factor = 0.9,
     .branch_factor = 0.9,
     .leaf_exponent = 1.0,
     .droop = 2.5,
     .twig_thin = 0.6,
     .rules = {[1] = {{0, 0.30, 0.97, 1}}, [2] = {{1, 0.15, 1.0, 1}}, [3] = {{2, 0.10, 1.0, 1}}},
     .leaf_rules = {{3, 0.0, 1.0, 1}}},
    {.name = "winter", /* a leafless oak: branches and twigs only */
     .shape = BBC_TREE_OAK,
     .height = 12.0,
     .default_leaves = 0,
     .structure_leaves = 20000,
     .leaf_size = 0.24,
     .bark = {0.42f, 0.36f, 0.30f},
     .leaf = {0.22f, 0.40f, 0.12f},
     TG_OAK_BRANCHING},
    {.name = "palm", /* a coconut-like palm: leaning stem, fronds of leaflet cards */
     .shape = BBC_TREE_PALM,
     .height = 11.0,
     .default_leaves = 1400,
     .leaf_size = 0.8,
     .bark = {0.55f, 0.47f, 0.38f},
     .leaf = {0.26f, 0.43f, 0.12f},
     .levels = 2,
     .leaf_exponent = 1.0,
     .rules = {[1] = {{0, 0.965, 1.0, 1}}},
     .leaf_rules = {{1, 0.1, 0.98, 1}}},
};

const char *bbc_tree_species_name(bbc_tree_species species) {
  if ((int)species < 0 || (int)species >= BBC_TREE_SPECIES_COUNT) return NULL;
  return tg_species_table[species].name;
}

int bbc_tree_species_from_name(const char *name) {
  if (!name) return -1;
  for (int s = 0; s < BBC_TREE_SPECIES_COUNT; s++) {
    const char *a = name, *b = tg_species_table[s].name;
    /* ASCII case folding: names come from command lines, "Oak" is meant. */
    while (*a && *b) {
      char ca = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
      if (ca != *b) break;
      a++;
      b++;
    }
    if (!*a && !*b) return s;
  }
  return -1;
}

void bbc_tree_options_default(bbc_tree_options *options) {
  assert(options);
  memset(options, 0, sizeof *options);
}

static size_t tg_round(double v) {
  return v <= 0 ? 0 : (size_t)(v + 0.5);
}

/* ------------------------------------------------------------------------ */
/* Plan                                                                      */
/* ------------------------------------------------------------------------ */

static void tg_tessellation(tg_ctx *c, double q) {
  int bush = c->shape == BBC_TREE_BUSH;
  c->sides[0] = bush ? 4 + (int)lround(6 * q) : 6 + (int)lround(18 * q);
  c->rings[0] = 3 + (int)lround(13 * q);
  c->sides[1] = 3 + (int)lround(9 * q);
  c->rings[1] = 1 + (int)lround(9 * q);
  c->sides[2] = 3 + (int)lround(3 * q);
  c->rings[2] = 1 + (int)lround(3 * q);
  c->sides[3] = 3 + (int)lround(q);
  c->rings[3] = 1 + (int)lround(q);
}

static size_t tg_tube_triangles(int sides, int rings) {
  return (size_t)sides * (size_t)(2 * (rings - 1) + 1);
}
static size_t tg_tube_vertices(int sides, int rings) {
  return (size_t)rings * (size_t)(sides + 1) + 1;
}

static size_t tg_wood_triangles(const tg_ctx *c) {
  size_t n = 0;
  for (int l = 0; l < c->levels; l++)
    n += c->count[l] * tg_tube_triangles(c->sides[l], c->rings[l]);
  return n;
}

/* Branch counts per level and tessellation. The twig count follows the leaf
 * count (about leaves^0.8 twigs, so big trees get more leaves per twig, as
 * real ones do), and the tessellation is the finest that keeps the wood
 * within about 30% of the leaf triangles. */
static void tg_plan(tg_ctx *c) {
  const tg_species *sp = c->info;
  /* A leafless tree is planned as if it had structure_leaves. */
  double n = (double)(c->leaves ? c->leaves : sp->structure_leaves ? sp->structure_leaves : 1);
  bbc__rng *rng = &c->rng_shape;
  c->levels = sp->levels;
  memset(c->count, 0, sizeof c->count);
  /* Bushes vary less: a much smaller one would be a different plant. */
  double spread = c->shape == BBC_TREE_BUSH ? 0.08 : 0.12;
  c->height = sp->height * rnd(rng, 1 - spread, 1 + spread);
  /* Fewer leaves are drawn somewhat larger so a low-polygon tree still
   * reads as foliage; more leaves, somewhat smaller. */
  double dl = sp->default_leaves ? (double)sp->default_leaves : (double)sp->structure_leaves;
  double scale = clampd(pow(dl / n, 0.25), 0.75, 1.6);
  c->leaf_size = sp->leaf_size * scale;

  size_t twigs = tg_round(sp->twig_factor * pow(n, 0.8));
  if (twigs < 1) twigs = 1;
  if (c->leaves && twigs > c->leaves) twigs = c->leaves;
  size_t branches = tg_round(sp->branch_factor * pow(n, 0.55));
  if (branches < 4) branches = 4;
  c->count[0] = 1;
  switch (c->shape) {
  case BBC_TREE_OAK:
    c->count[1] = 8 + (size_t)(bbc__rng_next(rng) % 4);
    c->count[2] = branches;
    c->count[3] = twigs;
    break;
  case BBC_TREE_PINE: {
    double w = 2.6 * log2(n) - 6;
    c->whorls = (int)clampd(floor(w + 0.5), 10, 40);
    c->per_whorl = 4 + (int)(bbc__rng_next(rng) % 3);
    c->count[1] = (size_t)c->whorls * (size_t)c->per_whorl;
    c->count[2] = twigs;
    break;
  }
  case BBC_TREE_PALM:
    c->count[1] = 14 + (size_t)(bbc__rng_next(rng) % 5);
    break;
  case BBC_TREE_BIRCH:
    c->count[1] = (size_t)clampd(floor(10 + 0.9 * pow(n, 0.3) + 0.5), 12, 40);
    c->count[2] = branches;
    c->count[3] = twigs;
    break;
  case BBC_TREE_BUSH:
  default:
    c->count[0] = 6 + (size_t)(bbc__rng_next(rng) % 4);
    c->count[1] = (size_t)clampd(floor(0.5 * pow(n, 0.55) + 0.5), 6, 1e9);
    c->count[2] = twigs;
    break;
  }

  double budget = fmax(300.0, 0.3 * 2.0 * n);
  double lo = 0, hi = 1;
  tg_tessellation(c, 1);
  if ((double)tg_wood_triangles(c) > budget) {
    for (int it = 0; it < 24; it++) {
      double mid = 0.5 * (lo + hi);
      tg_tessellation(c, mid);
      if ((double)tg_wood_triangles(c) <= budget)
        lo = mid;
      else
        hi = mid;
    }
    tg_tessellation(c, lo);
  }
}

/* ------------------------------------------------------------------------ */
/* Entry point                                                               */
/* ------------------------------------------------------------------------ */

static int tg_is_pow2(int v) {
  return v > 0 && (v & (v - 1)) == 0;
}

static bbc_result tg_oom(tg_ctx *c, bbc_mesh *mesh, bbc_error *err) {
  free(c->branches);
  free(c->nodes);
  bbc_mesh_free(mesh);
  return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "tree generator: out of memory");
}

static void *tg_array(size_t count, size_t size) {
  return count > SIZE_MAX / size ? NULL : malloc(count * size);
}

/* The options' ranges: a species of the table, a power-of-two texture edge,
 * a leaf count the generator allows. */
static bbc_result check_options(const bbc_tree_options *options, bbc_error *err) {
  assert(options->texture_size != 0); /* made the default by the caller */
  if ((int)options->species < 0 || (int)options->species >= BBC_TREE_SPECIES_COUNT)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: species %d is not one of oak (0), pine (1), birch (2), "
                     "bush (3), larch (4), weeping (5), winter (6), palm (7)",
                     (int)options->species);
  if (!tg_is_pow2(options->texture_size) || options->texture_size < TG_MIN_TEXTURE ||
      options->texture_size > TG_MAX_TEXTURE)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: texture size %d must be a power of two from %d to %d",
                     options->texture_size, TG_MIN_TEXTURE, TG_MAX_TEXTURE);
  if (options->leaves > TG_MAX_LEAVES)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: %zu leaves asked for; at most %u are allowed",
                     options->leaves, TG_MAX_LEAVES);
  return BBC_OK;
}

/* The tree's context: species, leaf count, random streams and plan. */
static void start_tree(tg_ctx *c, const bbc_tree_options *options) {
  memset(c, 0, sizeof *c);
  c->species = options->species;
  c->info = &tg_species_table[c->species];
  c->shape = c->info->shape;
  c->leaves = options->leaves ? options->leaves : c->info->default_leaves;
  /* Independent streams: the textures never depend on the leaf count, and
   * the trunk and limbs of a seed mostly stay when only the leaf count
   * changes. */
  bbc__rng seeder = {options->seed ^ (0x5DEECE66Dull * (uint64_t)(c->species + 1))};
  c->rng_shape.state = bbc__rng_next(&seeder);
  c->rng_fine.state = bbc__rng_next(&seeder);
  c->rng_leaf.state = bbc__rng_next(&seeder);
  c->rng_texture.state = bbc__rng_next(&seeder);
  tg_plan(c);
}

/* What the plan makes: branches, skeleton nodes, mesh vertices, triangles. */
typedef struct tg_totals {
  size_t branches, nodes, nv, nt;
} tg_totals;

static tg_totals plan_totals(const tg_ctx *c) {
  size_t total_branches = 0, total_nodes = 0, nv = 4 * c->leaves, nt = 2 * c->leaves;
  for (int l = 0; l < c->levels; l++) {
    total_branches += c->count[l];
    total_nodes += c->count[l] * (size_t)(c->rings[l] + 1);
    nv += c->count[l] * tg_tube_vertices(c->sides[l], c->rings[l]);
  }
  nt += tg_wood_triangles(c);
  tg_totals t = {total_branches, total_nodes, nv, nt};
  return t;
}

/* The mesh's arrays for nv vertices and nt triangles, its two materials
 * (bark, leaf) and two groups (trunk, leaves); 0 when out of memory. */
static int alloc_mesh(const tg_ctx *c, bbc_mesh *mesh, size_t nv, size_t nt) {
  mesh->kind = BBC_MESH_TRIANGLES;
  mesh->vertex_count = nv;
  mesh->triangle_count = nt;
  mesh->positions = tg_array(nv, 3 * sizeof *mesh->positions);
  mesh->normals = tg_array(nv, 3 * sizeof *mesh->normals);
  mesh->uvs = tg_array(nv, 2 * sizeof *mesh->uvs);
  mesh->indices = tg_array(nt, 3 * sizeof *mesh->indices);
  mesh->face_material = tg_array(nt, sizeof *mesh->face_material);
  mesh->face_group = tg_array(nt, sizeof *mesh->face_group);
  mesh->materials = calloc(2, sizeof *mesh->materials);
  mesh->textures = calloc(2, sizeof *mesh->textures);
  mesh->group_names = calloc(2, sizeof *mesh->group_names);
  if (!mesh->positions || !mesh->normals || !mesh->uvs || !mesh->indices || !mesh->face_material ||
      !mesh->face_group || !mesh->materials || !mesh->textures || !mesh->group_names)
    return 0;
  mesh->material_count = 2;
  mesh->texture_count = 2;
  mesh->group_count = 2;
  mesh->materials[0].name = bbc__strdup("bark");
  mesh->materials[1].name = bbc__strdup("leaf");
  mesh->group_names[0] = bbc__strdup("trunk");
  mesh->group_names[1] = bbc__strdup("leaves");
  if (!mesh->materials[0].name || !mesh->materials[1].name || !mesh->group_names[0] ||
      !mesh->group_names[1])
    return 0;
  for (int k = 0; k < 3; k++) mesh->materials[0].base_color[k] = c->info->bark[k];
  mesh->materials[0].base_color[3] = 1.0f;
  mesh->materials[0].texture = 1;
  /* White: renderers multiply the base colour with the texture. */
  for (int k = 0; k < 4; k++) mesh->materials[1].base_color[k] = 1.0f;
  mesh->materials[1].texture = 0;
  return 1;
}

/* The leaf texture (ts x ts) and the bark texture; 0 when out of memory. */
static int make_textures(tg_ctx *c, bbc_mesh *mesh, int ts) {
  /* Bark is seen small: half the leaf texture's edge is plenty. */
  int bs = ts / 2 < 8 ? 8 : ts / 2 > 128 ? 128 : ts / 2;
  if (bbc_image_alloc(&mesh->textures[0].image, ts, ts) != BBC_OK ||
      bbc_image_alloc(&mesh->textures[1].image, bs, bs) != BBC_OK)
    return 0;
  bbc__tree_leaf_texture(c, &mesh->textures[0].image);
  mesh->textures[0].has_alpha = 1;
  bbc__tree_bark_texture(c, &mesh->textures[1].image);
  mesh->textures[1].has_alpha = 0;
  return 1;
}

bbc_result bbc_tree_generate(const bbc_tree_options *options_in, bbc_mesh *mesh, bbc_error *err) {
  assert(mesh);
  bbc_tree_options resolved; /* zeros made the defaults they stand for */
  if (options_in)
    resolved = *options_in;
  else
    memset(&resolved, 0, sizeof resolved);
  if (resolved.texture_size == 0) resolved.texture_size = 128;
  const bbc_tree_options *options = &resolved;
  assert(options && mesh);
  memset(mesh, 0, sizeof *mesh);
  bbc_result r = check_options(options, err);
  if (r != BBC_OK) return r;
  const bbc_callbacks *cb = &options->callbacks;
  bbc__progress(cb, "tree", 0.0);

  tg_ctx c;
  start_tree(&c, options);
  tg_totals total = plan_totals(&c);
  size_t nv = total.nv, nt = total.nt;
  if (nv > UINT32_MAX)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "tree generator: %zu vertices do not fit 32-bit indices", nv);
  c.branches = tg_array(total.branches, sizeof *c.branches);
  c.nodes = tg_array(total.nodes, sizeof *c.nodes);
  if (!c.branches || !c.nodes) return tg_oom(&c, mesh, err);

  if (bbc__tree_skeleton(&c) != BBC_OK) return tg_oom(&c, mesh, err);
  /* Every planned branch was placed: the vertex count above depends on it. */
  assert(c.branch_count == total.branches && c.node_count == total.nodes);
  bbc__progress(cb, "tree", 0.15);

  if (!alloc_mesh(&c, mesh, nv, nt) || !make_textures(&c, mesh, options->texture_size))
    return tg_oom(&c, mesh, err);

  tg_out o = {mesh, 0, 0};
  for (size_t i = 0; i < c.branch_count; i++) bbc__tree_emit_tube(&c, &c.branches[i], &o);
  bbc__progress(cb, "tree", 0.3);
  if (bbc__tree_emit_leaves(&c, &o, cb) != BBC_OK) return tg_oom(&c, mesh, err);
  assert(o.v == nv && o.t == nt);
  free(c.branches);
  free(c.nodes);

  /* Every vertex has its normal, so the smoothing flag changes nothing; 0
   * spares finalize the position sort that smoothing needs. */
  r = bbc_mesh_finalize(mesh, 0, "built-in tree", err);
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  bbc__progress(cb, "tree", 1.0);
  return BBC_OK;
}
