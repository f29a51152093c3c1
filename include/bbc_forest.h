/*
 * bbc_forest.h — public interface of libbbc_forest, the forest engine's
 * runtime without its drawing: the map and model description files of the
 * thesis's Appendix B, the world they describe, culling and levels of
 * detail, terrain level of detail and colour, the camera, and a procedural
 * landscape. GL-free: `forest` draws with it (the thesis's Perfect Motion
 * engine, section 3.2 and Appendix B). Conventions as in bbc.h; distances
 * are world units, angles degrees.
 *
 * Start here — a map to the trees one frame draws:
 *
 *   bbc_forest_map map;          bbc_forest_world world;    bbc_error err;
 *   bbc_forest_map_load("map.txt", &map, &err);            // 1. the map file
 *   bbc_forest_world_build(&map, "maps/", &world, &err);    // 2. terrain, trees
 *   bbc_forest_cull *cull;                                  // 3. one LOD model
 *   bbc_forest_cull_build(&world, models, n,                //    per model file,
 *                         placement_models, map.placement_count, &cull, &err);
 *   bbc_forest_camera cam = {{500, 80, 500}, 135, -6, 1};  // 4. each frame:
 *   float vp[16];
 *   bbc_forest_camera_get_viewproj(&cam, 16.0 / 9, 1, 2000, vp);
 *   bbc_forest_cull_run(cull, vp, cam.pos, cam.zoom);      //    the trees, by level
 *   // draw bucket b's bbc_forest_cull_get_bucket_size(cull, b) records
 *   bbc_forest_cull_free(cull); bbc_forest_world_free(&world);
 *   bbc_forest_map_free(&map);
 *
 * Sections: 1 map and model description files; 2 the world; 3 culling and
 * levels of detail; 4 terrain; 5 the camera; 6 a procedural landscape.
 */
#ifndef BBC_FOREST_H
#define BBC_FOREST_H

#include "bbc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ======================================================================== */
/* 1. Map and model description files (thesis Appendix B)                   */
/* ======================================================================== */
/* The forest engine's text files, as the thesis's "Perfect Motion manual"
 * defines them: whitespace-separated words, a command's arguments wherever
 * the lines break, comment lines beginning with ' (high comma), a word in
 * double quotes may hold spaces. Parsed from memory (`name` is the file
 * name used in messages) or from a file; every error is
 * BBC_ERROR_CORRUPT (or a read or memory error) with "file:line: command:
 * what was expected", and nothing is returned. File names are kept as
 * written (relative to the file's folder). */

typedef enum bbc_forest_place_kind {
  BBC_FOREST_OBJECT2D = 0, /* one model at a map position */
  BBC_FOREST_RNDTREE,      /* `count` models where the colour map is green */
  BBC_FOREST_RNDTREE2      /* ... of two components (file and file2) */
} bbc_forest_place_kind;

typedef struct bbc_forest_placement {
  bbc_forest_place_kind kind;
  char *file;             /* model description file or 3D model */
  char *file2;            /* rndtree2: the second component, else NULL */
  double scale;           /* > 0 */
  size_t count;           /* rndtree, rndtree2: how many; object2d: 1 */
  int mipmap;             /* 0 or 1 */
  int random;             /* rndtree, rndtree2: random orientation (0 or 1) */
  double x, y;            /* object2d: map position, OpenGL units */
  double rotation_deg[3]; /* xr, yr, zr */
  double altitude;        /* added altitude */
  int line;               /* where it is written */
} bbc_forest_placement;

/* The map's `wind STRENGTH [DIRX DIRZ]`. */
typedef struct bbc_forest_wind {
  double strength; /* 0 = still; 1 = a breeze: a tree's top leans about 4 % of
                    * its height, more in gusts */
  double dir[2];   /* x, z of the direction it blows towards (unit) */
} bbc_forest_wind;

typedef struct bbc_forest_map {
  char *hmap;                                 /* hmap: heightmap image (required) */
  int hmap_filter_radius, hmap_filter_passes; /* hmapfilter (0 0 = none) */
  char *colmap;                               /* colmap: colour map image, NULL = none */
  double heightscale;                         /* heightscale (1): vertical scale */
  double stretch;                             /* stretch (1): horizontal scale */
  double light[3];                            /* light (1 1 0.5): the sun's default direction */
  bbc_forest_wind wind;                       /* wind (0, towards +x): still */
  double farclip;                             /* farclip: map vertices, 0 = not given */
  double roetger;                             /* roetger (10): terrain detail factor */
  char *skymap;                               /* skymap: file stem, NULL = none */
  int has_water;                              /* waterheight given */
  double water_height;
  int has_fog; /* fog given */
  double fog_start, fog_end;
  int has_numobjs; /* numobjs given */
  size_t numobjs;
  size_t placement_count; /* object2d, rndtree, rndtree2 lines in order */
  bbc_forest_placement *placements;
  char *name;                              /* the map file's name, as parsed */
  int hmap_line, colmap_line, skymap_line; /* where those commands are (0: not given) */
} bbc_forest_map;

/* Writes the defaults above into `map`, nothing placed. */
void bbc_forest_map_default(bbc_forest_map *map);
/* Parses a map file's `size` bytes of text (`name` names it in messages)
 * into `map` (bbc_forest_map_free). */
bbc_result bbc_forest_map_parse(const char *text, size_t size, const char *name,
                                bbc_forest_map *map, bbc_error *err);
/* Reads and parses the map file at `path`. */
bbc_result bbc_forest_map_load(const char *path, bbc_forest_map *map, bbc_error *err);
/* Releases what the map owns and zeroes it (NULL: nothing). */
void bbc_forest_map_free(bbc_forest_map *map);

typedef struct bbc_forest_lod_file {
  char *file;
  int displaylist, mipmap, lighting; /* the options written after it */
} bbc_forest_lod_file;

typedef struct bbc_forest_lod {
  bbc_forest_lod_file part[2]; /* file1, file2 (two components: foliage and stem) */
  int part_count;              /* 1 or 2 */
  double min_dist, max_dist;   /* drawn from min to max (0 <= min < max) */
  int line;                    /* where its LOD block starts */
} bbc_forest_lod;

typedef struct bbc_forest_model {
  double fade;          /* fade: units for half an LOD transition (0 = not given) */
  double shadow_radius; /* shadowrad: 0 = no shadow */
  double shadow_cutoff; /* shadowcutoff: full darkness up to it, 0 = not given */
  size_t lod_count;     /* at least one, in the order written */
  bbc_forest_lod *lods;
} bbc_forest_model;

/* Parses a model description file's `size` bytes of text (`name` names it
 * in messages) into `model` (bbc_forest_model_free). */
bbc_result bbc_forest_model_parse(const char *text, size_t size, const char *name,
                                  bbc_forest_model *model, bbc_error *err);
/* Reads and parses the model description file at `path`. */
bbc_result bbc_forest_model_load(const char *path, bbc_forest_model *model, bbc_error *err);
/* Releases what the model owns and zeroes it (NULL: nothing). */
void bbc_forest_model_free(bbc_forest_model *model);

/* ======================================================================== */
/* 2. The world: the terrain's heights, its colour map and every object     */
/* ======================================================================== */
typedef struct bbc_forest_instance {
  float x, y, z;      /* world units: x, z across the map from its corner, y up */
  float yaw_deg;      /* rotation about the up axis */
  float scale;        /* the placement's scale */
  uint32_t placement; /* index into bbc_forest_map.placements */
} bbc_forest_instance;

typedef struct bbc_forest_world {
  int width, depth;   /* terrain vertices along x and z: (2^n + 1) each */
  float *height;      /* width x depth heights, world units (heightmap value 0..255
                       * times heightscale; 16-bit maps keep their fractions) */
  double spacing;     /* world units between vertices (stretch) */
  int heightmap_bits; /* 8 or 16 */
  bbc_image colour;   /* (width - 1) x (depth - 1) colour map; empty without colmap */
  size_t instance_count;
  bbc_forest_instance *instances; /* in placement order */
  size_t placements_short;        /* rndtree lines that found too little green ground
                                   * for all their objects */
  double green_fraction;          /* of the colour map's texels, green enough for
                                   * vegetation (1 without a colour map) */
  char note[512];                 /* what was resampled, for the log ("" = nothing) */
} bbc_forest_world;

/* Builds the world of `map`, its files relative to `folder` (NULL = as
 * written): a heightmap of another size than (2^n+1)^2 is resampled
 * (bilinear) to the next such size and a colour map to (2^n)^2 (nearest),
 * both said in world->note; `hmapfilter` box-filters the heights; object2d
 * stands at (x, y) of the map, rndtree objects at random places whose
 * colour-map texel is green (G > 70, R < 2/3 G; anywhere without a colour
 * map), facing a random direction with `random 1`. Deterministic. */
bbc_result bbc_forest_world_build(const bbc_forest_map *map, const char *folder,
                                  bbc_forest_world *world, bbc_error *err);
/* Returns the terrain's height at (x, z), bilinear (0 without heights). */
double bbc_forest_world_get_height(const bbc_forest_world *world, double x, double z);
/* Returns 1 when the ground at (x, z) is green enough for vegetation. */
int bbc_forest_world_is_green(const bbc_forest_world *world, double x, double z);
/* Releases what the world owns and zeroes it (NULL: nothing). */
void bbc_forest_world_free(bbc_forest_world *world);

/* ======================================================================== */
/* 3. Culling and levels of detail (thesis 3.2.3)                           */
/* ======================================================================== */
/* Every tree is stored once per model it uses as a static draw record
 * (weight 1), ordered by model and then by cell of a grid over the map
 * (cells numbered in blocks of 8 x 8), so that the drawing layer uploads
 * them once. Each frame blocks and then cells are tested against the view
 * frustum and classified by their nearest and farthest tree: a cell wholly
 * inside the frustum whose trees all get one level of a model, whole, is
 * drawn straight from the static records as a range (neighbouring ranges
 * merged); only cells on the frustum's boundary or across an LOD switch are
 * handled tree by tree, into per-frame records with the thesis's blending:
 * across a switch at distance D the next level blends in over [D - fade, D]
 * while the previous is still whole, then the previous fades out over
 * [D, D + fade] (Wimmer et al. 2002). No allocation per frame. */

typedef struct bbc_forest_lod_model {
  size_t lod_count;
  const double *ranges; /* 2 per level: min and max distance, world units */
  double fade;          /* world units for half a transition; 0 = switch at once */
  double radius;        /* bounding sphere around the model's origin, model units */
} bbc_forest_lod_model;

/* One tree drawn with one level: 24 bytes, the GPU's instance record. */
typedef struct bbc_forest_draw {
  float x, y, z;
  float yaw;   /* radians about the up axis */
  float scale; /* the placement's scale */
  float fade;  /* 0..1: how much of the tree this level draws (1 = whole) */
} bbc_forest_draw;

/* The culling state (opaque): the static records, the grid and this
 * frame's ranges and records. */
typedef struct bbc_forest_cull bbc_forest_cull;
struct bbc_forest_occluder; /* section 4 */
struct bbc_forest_terrain;

/* What the culling gives the drawing layer (bbc_forest_cull_get_records):
 * read-only views of its arrays. Those marked "fixed" stay valid and
 * unchanged for the culling's life; the frame's until the next run or the
 * free. */
typedef struct bbc_forest_records {
  /* fixed */
  size_t model_count;
  const bbc_forest_lod_model *models; /* the copies of the models' levels */
  const size_t *bucket_base;          /* per model: its level 0's bucket; level l of model
                                       * m is bucket bucket_base[m] + l */
  size_t bucket_count;                /* the sum of the models' lod_count */
  size_t cell_count;                  /* cells of the grid over the map */
  size_t static_count;
  const bbc_forest_draw *statics;   /* every tree once per model it uses, fade 1, ordered
                                     * by model and then by cell */
  const uint8_t *static_first;      /* per static record: 1 where the model is the tree's
                                     * first component (a tree counts once) */
  const uint32_t *model_cell_start; /* model m, cell k: its records are statics[start[m *
                                     * (cell_count + 1) + k] .. start[m * (cell_count
                                     * + 1) + k + 1]) */
  /* this frame: bucket b draws the static ranges ranges[range_start[b] ..
   * range_start[b + 1]), each (first, count) into statics: those before
   * range_blend[b] whole (weight 1), those from it weighted per tree by
   * bbc_forest_lod_get_weight at its distance from `eye` / `zoom` (0: not
   * drawn; the drawing layer computes it, e.g. in a vertex shader); and
   * the per-frame records draws[bucket_start[b] .. bucket_start[b + 1]),
   * with their weights in `fade` */
  const uint32_t (*ranges)[2];
  const size_t *range_start; /* bucket_count + 1 */
  const size_t *range_blend; /* bucket_count */
  const bbc_forest_draw *draws;
  const size_t *bucket_start; /* bucket_count + 1; bucket_start[bucket_count]: all of them */
  double eye[3], zoom;        /* the frame's */
  /* the frame's statistics: cells in view, (model, cell)s handled tree by
   * tree, trees whose first component is in a range or a record (cells in
   * view: some may be just outside the frustum), cells in the frustum that
   * the occluder hid (not in cells_visible) */
  size_t cells_visible, cells_tested_per_tree, trees_visible, cells_occluded;
} bbc_forest_records;

/* Prepares the culling of `world`'s trees: models[model_count] are the
 * levels of each model (copied), and placement_models[p] names the
 * model(s) of placement p: [0] and, for two components, [1] (UINT32_MAX
 * when none). Stores every tree once per model as a static record; *cull
 * is released by bbc_forest_cull_free (NULL on failure). */
bbc_result bbc_forest_cull_build(const bbc_forest_world *world, const bbc_forest_lod_model *models,
                                 size_t model_count, const uint32_t (*placement_models)[2],
                                 size_t placement_count, bbc_forest_cull **cull, bbc_error *err);
/* Occlusion for the next frames (NULL: none): cells (and blocks of them)
 * that `occluder` finds hidden behind the terrain as `terrain` draws it
 * this frame are not drawn. Both are the caller's and must outlive the
 * frames that use them. */
void bbc_forest_cull_set_occluder(bbc_forest_cull *cull, struct bbc_forest_occluder *occluder,
                                  const struct bbc_forest_terrain *terrain);
/* The records and the last frame's ranges (above) into *records. */
void bbc_forest_cull_get_records(const bbc_forest_cull *cull, bbc_forest_records *records);
/* One frame: `viewproj` column-major (OpenGL), `eye` the camera position;
 * distances are divided by `zoom` (zooming in shows finer levels). Work per
 * cell of the grid: after it, bucket b draws its static ranges, whole or
 * blend, and its per-frame records (above), those only for cells across a
 * switch or the frustum's boundary within reach of level 0 (the polygon
 * model, whose vertices are worth a test per tree). Every tree inside the
 * frustum is in each
 * level whose weight at its distance is > 0; trees of cells the frustum's
 * boundary crosses may be outside it (the GPU clips them). */
void bbc_forest_cull_run(bbc_forest_cull *cull, const float viewproj[16], const double eye[3],
                         double zoom);
/* The same without the grid, the way the thesis did it: every tree tested
 * against the frustum and given its level one by one, all into per-frame
 * records with their weights, no static ranges (the naive mode that
 * `forest --naive` measures against). */
void bbc_forest_cull_run_flat(bbc_forest_cull *cull, const float viewproj[16], const double eye[3],
                              double zoom);
/* The model whose level bucket b is (its level in *level, may be NULL). */
size_t bbc_forest_cull_get_bucket_model(const bbc_forest_cull *cull, size_t bucket, size_t *level);
/* How many records bucket b draws this frame (static ranges and per-frame). */
size_t bbc_forest_cull_get_bucket_size(const bbc_forest_cull *cull, size_t bucket);
/* Writes bucket b's records of this frame into out (bbc_forest_cull_get_bucket_size
 * of them): its static ranges (blend ranges' records with their weights, 0
 * for those the level does not draw), then its per-frame records. */
void bbc_forest_cull_copy_bucket(const bbc_forest_cull *cull, size_t bucket, bbc_forest_draw *out);
/* The weight (0..1) level `lod` of `model` gets at distance d. */
double bbc_forest_lod_get_weight(const bbc_forest_lod_model *model, size_t lod, double d);
/* Releases the culling and all it owns (NULL: nothing). */
void bbc_forest_cull_free(bbc_forest_cull *cull);

/* Frustum planes (a, b, c, d: inside when a x + b y + c z + d >= 0) of a
 * column-major view-projection matrix. */
void bbc_forest_frustum_from_matrix(const float viewproj[16], double planes[6][4]);
/* 0 = the box is outside, 1 = it crosses the frustum, 2 = wholly inside. */
int bbc_forest_frustum_test_box(const double planes[6][4], const double lo[3], const double hi[3]);

/* ======================================================================== */
/* 4. Terrain (thesis 3.2.1)                                                */
/* ======================================================================== */
/* Continuous level of detail on the GPU's terms (CDLOD, Strugar 2010, in
 * place of Roettger et al. 1998): a quadtree over the (2^n+1)^2 heightmap
 * whose leaves are 32 x 32 squares; each frame the nodes to draw are chosen
 * by distance ranges that double per level, the finest (3.5 + `detail` /
 * 4) leaves (`detail` is the map's `roetger`; 3.5 leaves at the least, so
 * neighbours differ by one level at most). The vertex shader morphs each
 * node's odd vertices onto the coarser grid as they near the end of its
 * range, so there are no cracks and no pops. */

#define BBC_FOREST_TERRAIN_LEAF 32 /* squares along a leaf node */

typedef struct bbc_forest_terrain_node {
  int x, z;    /* first square, heightmap squares */
  int size;    /* squares along the node (a quarter of a node: half its size) */
  int level;   /* 0 = finest: vertices every 2^level squares */
  int quarter; /* -1 the whole node's grid; 0..3 one quarter of the grid of a node
                * twice this size at (x - (quarter & 1) * size, z - (quarter >> 1) * size) */
} bbc_forest_terrain_node;

typedef struct bbc_forest_terrain {
  int squares;      /* 2^n squares along the map */
  int leaf;         /* squares along a leaf node: BBC_FOREST_TERRAIN_LEAF, or fewer on small maps */
  int levels;       /* quadtree levels (root = levels - 1) */
  float **bounds;   /* per level: min and max height per node, row-major */
  double range[24]; /* per level, world units */
  double morph_start[24]; /* per level: where its odd vertices begin to morph */
  size_t node_count, capacity;
  bbc_forest_terrain_node *nodes;
} bbc_forest_terrain;

/* The quadtree of `world`'s heightmap and its nodes' height bounds (free
 * with bbc_forest_terrain_free; zeroed on failure). */
bbc_result bbc_forest_terrain_init(bbc_forest_terrain *t, const bbc_forest_world *world,
                                   bbc_error *err);
/* Chooses the nodes for a camera at `eye` with view-projection `viewproj`
 * (column-major) and detail factor `detail` (roetger). */
void bbc_forest_terrain_select(bbc_forest_terrain *t, const bbc_forest_world *world,
                               const float viewproj[16], const double eye[3], double detail);
/* Releases what the terrain owns and zeroes it (NULL: nothing). */
void bbc_forest_terrain_free(bbc_forest_terrain *t);

/* Occlusion by the terrain (src/forest/occlude.c): the minima of the
 * heightmap's aligned blocks of 2^k squares, below the terrain as drawn. */
#define BBC_FOREST_OCCLUDER_BINS 1024 /* azimuths around the eye */
typedef struct bbc_forest_occluder {
  int squares, levels; /* squares along the map; min[k]: (squares >> k)^2 minima */
  float **min;
  const float *height;    /* the world's heights (not owned) */
  double spacing;         /* world units a square */
  double lowest, highest; /* the map's */
  /* per frame: distance steps, and per azimuth bin and step the steepest
   * rise from the eye the terrain blocks so far (bin-major; a bin's column
   * made when first asked, bin_done) */
  int steps;
  double *step, *bin_dir;
  uint8_t *bin_done;
  int *step_lod; /* per step: the terrain's coarsest grid level there */
  float *horizon;
  double eye[3];
  int ready; /* this frame's table holds (0: the eye is not above the terrain) */
} bbc_forest_occluder;

/* The block minima of `world`'s heightmap (free with
 * bbc_forest_occluder_free; zeroed on failure). */
bbc_result bbc_forest_occluder_init(bbc_forest_occluder *occluder, const bbc_forest_world *world,
                                    bbc_error *err);
/* This frame's table for `eye`, the terrain drawn as `terrain` says (its
 * ranges, chosen for this eye by bbc_forest_terrain_select). */
void bbc_forest_occluder_begin(bbc_forest_occluder *occluder, const bbc_forest_terrain *terrain,
                               const double eye[3]);
/* 1 when the terrain as drawn this frame hides every point of `box` (min
 * xyz, max xyz, grown here by a tenth of its height for the wind) from the
 * frame's eye; 0 when it may not (conservative). */
int bbc_forest_occluder_hides(bbc_forest_occluder *occluder, const float box[6]);
/* Releases the minima and zeroes it (NULL: nothing). */
void bbc_forest_occluder_free(bbc_forest_occluder *occluder);

/* The terrain's colour texture with the `light` direction's lighting baked
 * in (thesis 3.2.1; NULL: none, for a renderer that lights it per pixel as
 * forest does) and a soft dark disc under every object whose model
 * casts a shadow (3.2.4): shadow[p] = {radius, cutoff} for placement p in
 * world units ({0, 0} = none; full darkness up to cutoff, then falling off
 * to none at radius). Without a colour map, grass and rock by slope and
 * height. (width - 1) x (depth - 1) texels. */
bbc_result bbc_forest_terrain_bake_colour(const bbc_forest_world *world, const double light[3],
                                          const double (*shadow)[2], bbc_image *out,
                                          bbc_error *err);

/* ======================================================================== */
/* 4b. The sun and the wind (GL-free: the shaders do the same per vertex    */
/*     and per pixel)                                                       */
/* ======================================================================== */

/* The direction towards the sun (unit, world axes, y up) at `azimuth_deg`
 * around the vertical (0 = towards +z, 90 = towards +x, as bbcgen's
 * lightazim) and `elevation_deg` above the horizon (as lightelev). */
void bbc_forest_sun_direction(double azimuth_deg, double elevation_deg, double dir[3]);
/* The azimuth and elevation (degrees) of the direction `light` (any
 * length, not zero; a map's `light`). */
void bbc_forest_sun_angles(const double light[3], double *azimuth_deg, double *elevation_deg);

/* The ambient light the forest's sun comes with (the sun's being 1), as
 * bbcgen eval --sun lights (docs/lighting.md). */
#define BBC_FOREST_SUN_AMBIENT 0.4
/* How bright a surface is under the sun, as a glTF viewer lights a lit
 * material: (ambient x occlusion + max(0, n . l)) / (ambient + 1), so that
 * a surface facing the sun keeps its colour. `n_dot_l`: its (bent, turned
 * to the side seen) normal against the direction towards the sun;
 * `occlusion` the occlusion map's value (1 = none). */
double bbc_forest_sun_shade(double ambient, double occlusion, double n_dot_l);

/* Where the wind moves a point of a tree at `time` seconds: `q` the point
 * relative to the tree's base (world units, after the tree's scale and
 * turn), `base` the base's world position (its x, z give the tree's phase
 * and where the slow gusts are), `height` the tree's height (world units;
 * the same for every level of a model, so that levels sway alike and the
 * cross-fade stays seamless). Writes the displacement: nothing at the base
 * (q.y <= 0), growing with the height above it (squared) and, a little,
 * with the distance from the axis (leaves flutter). Mirrored by
 * forest_model.vert.glsl. */
void bbc_forest_wind_offset(const bbc_forest_wind *wind, double time, const double base[3],
                            const double q[3], double height, double out[3]);

/* ======================================================================== */
/* 5. The camera and stored positions                                       */
/* ======================================================================== */
typedef struct bbc_forest_camera {
  double pos[3]; /* world units */
  double yaw;    /* degrees: 0 looks along -z, 90 along +x */
  double pitch;  /* degrees, up positive, within +-89 */
  double zoom;   /* 1 = the normal field of view (60 degrees vertical) */
} bbc_forest_camera;

/* Unit vector the camera looks along. */
void bbc_forest_camera_get_forward(const bbc_forest_camera *cam, double f[3]);
/* Column-major perspective x view matrix (OpenGL clip space). */
void bbc_forest_camera_get_viewproj(const bbc_forest_camera *cam, double aspect, double near_clip,
                                    double far_clip, float viewproj[16]);
/* Stored positions (Appendix B's F3/F2): text lines "x y z yaw pitch".
 * Appends one; reads all into a malloc'd array (NULL and 0 when the file
 * does not exist). */
bbc_result bbc_forest_positions_append(const char *path, const bbc_forest_camera *cam,
                                       bbc_error *err);
bbc_result bbc_forest_positions_read(const char *path, bbc_forest_camera **cams, size_t *count,
                                     bbc_error *err);

/* ======================================================================== */
/* 6. A procedural landscape for the demo maps                              */
/* ======================================================================== */
typedef enum bbc_forest_demo_kind {
  BBC_FOREST_DEMO_HILLS = 0, /* hills, a ridge, a lake */
  BBC_FOREST_DEMO_ISLANDS    /* islands in a sea (the thesis's Tropic Islands) */
} bbc_forest_demo_kind;

/* A (size + 1)^2 8-bit heightmap (grey in `height`'s RGB) and a size^2
 * colour map. Hills: rolling hills from value noise, a ridge along one
 * side, a lake basin (its floor below `*water_level`, in heightmap units
 * 0..255), meadows (yellow-green: no trees by the Appendix B rule), forest
 * floor (green: trees), rock where steep or high, sand on the shore.
 * Islands: a sea (below `*water_level`) with islands of green ground, sandy
 * beaches and rock, none touching the map's edge. `size` a power of two,
 * 16..4096. Deterministic from `seed`. */
bbc_result bbc_forest_demo_terrain(int size, uint32_t seed, bbc_forest_demo_kind kind,
                                   bbc_image *height, bbc_image *colour, double *water_level,
                                   bbc_error *err);

#ifdef __cplusplus
}
#endif

#endif /* BBC_FOREST_H */
