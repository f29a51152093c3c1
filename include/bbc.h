/*
 * bbc.h — public interface of libbbc, the Billboard Cloud generator library.
 *
 * The library implements BBCgen from "Billboard Clouds for rendering huge
 * forests" (diploma thesis, 2004; see README.md). This header is its manual:
 * every function says what it returns, who owns what, and the units of every
 * field.
 *
 * Conventions, stated once:
 *   - Errors: functions that can fail on bad data or bad parameters return a
 *     bbc_result and, when `err` is not NULL, write a one-line message a user
 *     can act on (naming the file and the problem) into err->message.
 *     Programmer errors (NULL where not allowed) are assertions.
 *   - The library never prints and never exits. It reports warnings and
 *     progress through the optional callbacks in bbc_callbacks.
 *   - No global state: everything a function needs is in its arguments, so
 *     functions may be called from several threads on different objects.
 *   - Ownership: `*_free()` releases what a `*_load()`/`*_generate()` filled
 *     in; `*_free(NULL)` and freeing a zeroed struct are safe.
 *   - Geometry stays in the model's own coordinates (double precision).
 *     Texture coordinates follow OpenGL: v = 0 is the bottom row of an image.
 *   - Images are RGBA8, straight (not premultiplied) alpha, rows top first.
 */
#ifndef BBC_H
#define BBC_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define BBC_VERSION_MAJOR  0
#define BBC_VERSION_MINOR  1
#define BBC_VERSION_PATCH  0
#define BBC_VERSION_STRING "0.1.0"

/* ------------------------------------------------------------------------ */
/* Results, errors, callbacks                                                */
/* ------------------------------------------------------------------------ */

typedef enum bbc_result {
  BBC_OK = 0,
  BBC_ERROR_INVALID_ARGUMENT,   /* unknown parameter, malformed value */
  BBC_ERROR_OUT_OF_RANGE,       /* parameter value outside its range */
  BBC_ERROR_NOT_FOUND,          /* input path does not exist */
  BBC_ERROR_NOT_A_FILE,         /* input path is a folder or a device */
  BBC_ERROR_IO,                 /* read or write failed (permissions, disk) */
  BBC_ERROR_UNSUPPORTED_FORMAT, /* no reader for this file */
  BBC_ERROR_CORRUPT,            /* truncated or damaged file, parse error */
  BBC_ERROR_INVALID_GEOMETRY,   /* NaN/Inf coordinates, index out of range */
  BBC_ERROR_EMPTY,              /* no usable triangles or points */
  BBC_ERROR_OUT_OF_MEMORY,
  BBC_ERROR_CANCELLED, /* the caller's cancel callback asked to stop */
  BBC_RESULT_COUNT
} bbc_result;

/* Short English name of a result ("corrupt file"); never NULL. */
const char *bbc_result_string(bbc_result result);

/* Filled by failing functions: the code and a one-line message. */
typedef struct bbc_error {
  bbc_result code;
  char message[512];
} bbc_error;

typedef enum bbc_log_level { BBC_LOG_INFO = 0, BBC_LOG_WARNING = 1 } bbc_log_level;

/* Optional reporting hooks. Every member may be NULL. */
/* What step 2 shows at the `debug` levels of Appendix A, as it happens. */
typedef struct bbc_debug_event {
  int level;             /* 1: a plane was picked; 2: a step of the recursive greedy
                          * select; 3: the cluster kept from a densest cell */
  const char *where;     /* the part and run, e.g. "foliage" ("" with one part) */
  size_t plane;          /* planes picked so far in this part */
  int step;              /* level 2: the recursion step (0 = the grid cell) */
  const uint32_t *faces; /* mesh triangles: level 1 the plane's faces, 2 those
                          * simply valid for the step's subcell, 3 the cluster */
  size_t face_count;
  const uint32_t *done; /* mesh triangles of this part simplified by earlier planes */
  size_t done_count;
} bbc_debug_event;

typedef struct bbc_callbacks {
  /* A message for the user (a missing texture, dropped faces). */
  void (*log)(void *user, bbc_log_level level, const char *message);
  /* Progress of a long stage: `stage` is a short static name, `fraction` in
   * [0, 1], non-decreasing within a stage, 1 exactly once at its end. */
  void (*progress)(void *user, const char *stage, double fraction);
  void *user;
  /* Asked now and then during steps 1 to 3 (bbc_planes_find,
   * bbc_cloud_build): non-zero stops the step, which frees what it made and
   * returns BBC_ERROR_CANCELLED. NULL: never. */
  int (*cancel)(void *user);
  /* Step 2's internals at parameter `debug` >= the event's level (NULL:
   * none); the step waits for it to return and its result does not depend
   * on it. Arrays are valid during the call only. */
  void (*debug)(void *user, const bbc_debug_event *event);
} bbc_callbacks;

/* ------------------------------------------------------------------------ */
/* Images                                                                    */
/* ------------------------------------------------------------------------ */

typedef struct bbc_image {
  int width;     /* texels */
  int height;    /* texels */
  uint8_t *rgba; /* width * height * 4 bytes, rows top first */
} bbc_image;

/* Allocates a width x height image, all texels (0,0,0,0). */
bbc_result bbc_image_alloc(bbc_image *image, int width, int height);
void bbc_image_free(bbc_image *image);
/* Loads PNG, JPEG, BMP, TGA, ... into RGBA8 (opaque alpha when the file has
 * none). */
bbc_result bbc_image_load(const char *path, bbc_image *image, bbc_error *err);
/* Decodes an image held in memory (textures embedded in GLB). */
bbc_result bbc_image_load_memory(const void *data, size_t size, bbc_image *image, bbc_error *err);
/* Writes a PNG atomically: a temporary file renamed over `path` at the end,
 * so a failed write never leaves a partial file. */
bbc_result bbc_image_write_png(const char *path, const bbc_image *image, bbc_error *err);
/* 1 when at least one texel has alpha < 255. */
int bbc_image_has_transparency(const bbc_image *image);
/* The mip chain of an alpha-tested image below level 0, halving down to
 * 1 x 1 (`*count` levels into a malloc'd array, each freed with
 * bbc_image_free, then the array with free): colours averaged weighted by
 * alpha (transparent texels keep the average of their footprint, so no
 * dark fringes), alpha binary (0 or 255) and chosen per level so that the
 * fraction of opaque texels stays level 0's (Castano 2010, "Computing
 * Alpha Mipmaps": leaves neither thin out nor vanish in the distance). An
 * opaque image gets plain box-filtered levels. */
bbc_result bbc_image_mipmaps(const bbc_image *base, bbc_image **levels, int *count, bbc_error *err);
/* Writes `image` with its bbc_image_mipmaps chain as an uncompressed DDS
 * (RGBA8, every level down to 1 x 1; Microsoft's DirectDraw Surface
 * layout, which view3dscene and DirectX-style engines read with their mip
 * levels), atomically. PNG has no place for mip levels: this is how an
 * alpha-tested atlas keeps its coverage at a distance in viewers that
 * would otherwise build their own (averaged alpha thins sparse foliage). */
bbc_result bbc_image_write_dds(const char *path, const bbc_image *image, bbc_error *err);

/* ------------------------------------------------------------------------ */
/* Meshes and point clouds                                                   */
/* ------------------------------------------------------------------------ */

typedef struct bbc_texture {
  char *path;      /* resolved file path; NULL for generated or embedded images */
  bbc_image image; /* decoded texels */
  int has_alpha;   /* 1 when some texel is not fully opaque */
} bbc_texture;

typedef struct bbc_material {
  char *name;          /* never NULL ("" when the file has none) */
  float base_color[4]; /* RGBA in [0, 1]; alpha is the material's opacity */
  int texture;         /* diffuse texture: index into mesh->textures, -1 none */
  char *texture_ref;   /* the texture path as the file wrote it, NULL when the
                        * material names none; kept when the file is missing */
  int normal_map;      /* tangent-space normal map: 1 + index into mesh->textures,
                        * 0 = none (zeroed materials have none) */
  int single_sided;    /* 1 = only the counter-clockwise side is drawn (glTF
                        * doubleSided false); 0 = both sides */
  int unlit;           /* 1 = drawn without lighting (glTF KHR_materials_unlit,
                        * MTL illum 0): its colours carry the light already */
  float ambient[3];    /* ambient reflectance (MTL Ka; 0 when the file gives
                        * none): what a lit viewer's global ambient adds */
} bbc_material;

/* 1 when `material` is the one bbcgen gives a cloud's limbs (`limbs`: the
 * trunk part kept as a mesh), named "limbs" or "limbs_LOD<k>". */
int bbc_material_is_limbs(const bbc_material *material);

typedef enum bbc_mesh_kind {
  BBC_MESH_TRIANGLES = 0, /* a polygon model, triangulated */
  BBC_MESH_POINTS = 1     /* a point cloud: vertices only (thesis 2.4) */
} bbc_mesh_kind;

typedef struct bbc_mesh {
  bbc_mesh_kind kind;

  size_t vertex_count;
  double *positions; /* 3 per vertex, model coordinates */
  float *normals;    /* 3 per vertex, unit length; NULL for points without */
  float *uvs;        /* 2 per vertex; NULL when the model has none */
  uint8_t *colors;   /* 4 per vertex (RGBA), NULL when none (points only) */
  float *tangents;   /* 4 per vertex (unit tangent along +u, handedness w = +-1,
                      * glTF TANGENT): for normal maps; NULL when none */

  size_t triangle_count;
  uint32_t *indices;       /* 3 per triangle, counter-clockwise = front */
  uint32_t *face_material; /* per triangle: index into materials */
  uint32_t *face_group;    /* per triangle: index into group_names */

  size_t material_count;
  bbc_material *materials; /* at least one for triangle meshes */
  size_t texture_count;
  bbc_texture *textures;
  size_t group_count;
  char **group_names; /* object/group/node names; "" when unnamed */

  /* What loading changed (reported, never silent). */
  size_t triangles_read;     /* triangles in the input after triangulation,
                              * before zero-area ones were dropped */
  size_t dropped_degenerate; /* zero-area triangles removed */
  int normals_generated;     /* 1 when normals were computed, not read */
  double origin[3];          /* subtracted from the file's coordinates on load when
                              * they lie far from 0 (georeferenced scans: the centre
                              * rounded to whole units), so that float outputs keep
                              * their precision; 0 0 0 when nothing was */
  int no_mipmaps;            /* Appendix A's `load ... nomip`: its textures are
                              * sampled at full resolution (baking, viewer) */

  /* Frame (thesis 2.1.4): area-weighted centre of gravity of the triangles
   * (mean of the points for a point cloud) and the radius of the bounding
   * sphere around it. Axis-aligned bounds of the used vertices. */
  double center[3];
  double radius;
  double bbox_min[3];
  double bbox_max[3];
} bbc_mesh;

typedef struct bbc_load_options {
  /* Thesis parameter `vn`: 1 = smooth vertex normals (area-weighted) where
   * the file has none; 0 = flat face normals where the file has none. Normals
   * present in the file are always kept. */
  int compute_normals;
  /* 1 = decode diffuse textures; 0 = record their paths only (faster). */
  int load_textures;
  /* 0 = every node; k + 1 = only the level of detail k: the nodes (and
   * their subtrees) named "<anything>_LOD<k>", the engines' convention that
   * bbcgen's glTF LOD chains follow (Assimp-read formats; BBC_ERROR_NOT_FOUND
   * when the file has no such node). */
  int lod_node;
  /* 1 = no mipmaps for the model's textures (bbc_mesh.no_mipmaps). */
  int no_mipmaps;
  bbc_callbacks callbacks;
} bbc_load_options;

void bbc_load_options_default(bbc_load_options *options);

/* A model from bytes in memory, the reader chosen by the extension of
 * `name` (which names it in messages): the project's own for PLY,
 * XYZ/PTS/TXT and VRML, Assimp's for the rest (with no other files: an
 * OBJ's MTL or a .gltf's buffers are not found; .glb is whole), finished as
 * bbc_mesh_load finishes a file. For embedding, and for the fuzzers. */
bbc_result bbc_mesh_load_memory(const char *name, const void *data, size_t size,
                                const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

/* Loads a model (through Assimp: OBJ+MTL, 3DS, glTF/GLB, AC3D, FBX,
 * COLLADA, ...; PLY with the library's own reader: a mesh when it has faces,
 * a point cloud otherwise) or a point cloud in XYZ text. Node
 * transforms are applied, so the result is in the file's world frame.
 * Texture paths are resolved against the model's folder; a texture that
 * cannot be found or decoded is a warning and the material keeps its base
 * colour. On failure `mesh` is left zeroed. */
bbc_result bbc_mesh_load(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                         bbc_error *err);

/* Releases everything the mesh owns and zeroes it. */
void bbc_mesh_free(bbc_mesh *mesh);

/* Checks and completes a mesh whose arrays have been filled in: refuses
 * non-finite coordinates and out-of-range indices (BBC_ERROR_INVALID_GEOMETRY),
 * drops zero-area triangles (counted in dropped_degenerate), computes missing
 * normals (`compute_normals` as in bbc_load_options), bounds, centre and
 * radius. BBC_ERROR_EMPTY when nothing usable remains. Loaders and
 * generators call it; `source` names the input in messages. */
bbc_result bbc_mesh_finalize(bbc_mesh *mesh, int compute_normals, const char *source,
                             bbc_error *err);

/* Number of triangles of each group, written to counts[group_count]. */
void bbc_mesh_group_triangle_counts(const bbc_mesh *mesh, size_t *counts);

/* ------------------------------------------------------------------------ */
/* Writers                                                                   */
/* ------------------------------------------------------------------------ */

/* Writes OBJ + MTL (same stem) + one PNG per textured material, atomically.
 * Groups become `g` statements, materials `usemtl`. `obj_path` must end in
 * ".obj". */
bbc_result bbc_mesh_write_obj(const char *obj_path, const bbc_mesh *mesh, bbc_error *err);
/* The same with `comment` (may be NULL) as # lines at the top of the OBJ,
 * and unlit = 1: every material `illum 0` (colour without lighting, for
 * prelit clouds). Texture files follow bbc_texture_file_name. */
bbc_result bbc_mesh_write_obj_ex(const char *obj_path, const bbc_mesh *mesh, const char *comment,
                                 int unlit, bbc_error *err);

/* Writes `size` bytes to `path` atomically (temporary file, then rename):
 * reports, JSON and other text outputs of the tools. */
bbc_result bbc_write_file_atomic(const char *path, const void *data, size_t size, bbc_error *err);

/* glTF 2.0 output of a textured triangle mesh (billboard clouds, baselines).
 * Every material becomes a glTF material (baseColorFactor = base_color,
 * baseColorTexture = its texture as PNG), alphaMode MASK with alphaCutoff
 * 0.5, doubleSided; positions (float, with min/max), normals when present,
 * TEXCOORD_0 when present (v flipped to glTF's top-left origin), indices
 * (uint16 when they fit, else uint32); one primitive per material, one mesh,
 * one node. `extras_json`, when not NULL, must be exactly one JSON object;
 * it is stored verbatim as the asset's "extras" (anything else is
 * BBC_ERROR_INVALID_ARGUMENT and nothing is written). For .gltf the side files
 * are <stem>.bin and one PNG per texture named by the rule all writers
 * share (bbc_texture_file_name), with characters outside [A-Za-z0-9_.-] of
 * the stem replaced by '_'. Normals are written renormalised. */
typedef struct bbc_gltf_options {
  int binary;                    /* 1 = .glb (one file), 0 = .gltf + .bin + .png files */
  const char *extras_json;       /* may be NULL */
  int lod_chain;                 /* bbc_scene_write_gltf: 1 = the nodes are levels of detail
                                  * of one object, finest first: every level is a child
                                  * of one group node (the scene's root, named
                                  * lod_group_name), and node 0 names the coarser ones
                                  * through MSFT_lod */
  const char *lod_group_name;    /* lod_chain: the group node's name (may be NULL) */
  const double *screen_coverage; /* lod_chain: node_count decreasing values in (0, 1],
                                  * written as node 0's MSFT_screencoverage hint:
                                  * level k is drawn while the object covers more
                                  * than screen_coverage[k] of the screen's height
                                  * (may be NULL) */
  int unlit;                     /* 1 = every material KHR_materials_unlit: colours
                                  * shown as they are (prelit textures) */
} bbc_gltf_options;

/* Writes `mesh` as glTF 2.0, atomically (every file). options may be NULL:
 * the format then follows the extension (.glb or .gltf). */
bbc_result bbc_mesh_write_gltf(const char *path, const bbc_mesh *mesh,
                               const bbc_gltf_options *options, bbc_error *err);

/* Several meshes in one glTF file, one node each (name and extras optional,
 * extras one JSON object), as bbc_mesh_write_gltf writes one. Materials with
 * a normal_map get normalTexture (when the mesh has tangents, written as
 * TANGENT); single_sided materials are doubleSided false. */
typedef struct bbc_gltf_node {
  const bbc_mesh *mesh;
  const char *name;
  const char *extras_json;
} bbc_gltf_node;

bbc_result bbc_scene_write_gltf(const char *path, const bbc_gltf_node *nodes, size_t node_count,
                                const bbc_gltf_options *options, bbc_error *err);

/* The rule every writer (OBJ, glTF, VRML) names texture files by:
 * <stem>_<material>.png for a material's colour texture and
 * <stem>_<material>_nm.png for its normal map, the material being the first
 * that uses texture `t`, its name with characters outside [A-Za-z0-9_.-]
 * replaced by '_' ("unnamed" when empty). Writes "<material>" or
 * "<material>_nm" (no stem, no extension) into out. */
void bbc_texture_file_name(const bbc_mesh *mesh, size_t t, char *out, size_t out_size);

/* ------------------------------------------------------------------------ */
/* Texture atlas                                                             */
/* ------------------------------------------------------------------------ */

typedef struct bbc_atlas_rect {
  int x, y;          /* top-left texel of the image inside the atlas */
  int width, height; /* = the image's size */
} bbc_atlas_rect;

/* Packs `count` images into one power-of-two RGBA atlas (square or 2:1),
 * leaving `padding` texels around each image, and dilates the colour of
 * opaque texels into neighbouring transparent ones (alpha stays 0) so that
 * filtering and mipmaps do not bleed dark fringes. rects[count] receives
 * where each image went. Deterministic. BBC_ERROR_OUT_OF_RANGE when the
 * images do not fit in max_size x max_size. count = 0 gives a 1x1
 * transparent atlas (rects may then be NULL). */
bbc_result bbc_atlas_pack(const bbc_image *images, size_t count, int padding, int max_size,
                          bbc_image *atlas, bbc_atlas_rect *rects, bbc_error *err);

/* ------------------------------------------------------------------------ */
/* Parameters (thesis Appendix A, "Parameter Reference")                      */
/* ------------------------------------------------------------------------ */

typedef enum bbc_param_type {
  BBC_PARAM_BOOL = 0, /* 0 or 1 */
  BBC_PARAM_INT,      /* integer in [min, max] */
  BBC_PARAM_REAL,     /* real in [min, max] */
  BBC_PARAM_POW2      /* power of two in [min, max] */
} bbc_param_type;

/* Flags from Appendix A. */
#define BBC_PARAM_STEP3_ONLY  1u /* '*': used only by step 3 (texturing) */
#define BBC_PARAM_KEEPS_STEP1 2u /* '+': may change before step 2 without redoing step 1 */

typedef struct bbc_params {
  /* performance */
  int break_steps;    /* break: stop recursive greedy select after n steps */
  int break_num;      /* breaknum: ... only if more than n primitives valid */
  int debug;          /* debug: graphical debug level 0..3 */
  int res_deg;        /* res: grid theta/phi resolution, degrees per cell */
  int vertex_normals; /* vn: compute vertex normals on load */
  /* plane */
  int cardboard;            /* cardboard: cardboard plane finding (2.3.7) */
  double cb_coverage_pct;   /* cbcoverage: minimum cardboard coverage, % */
  int clustering;           /* clustering: 0 off, 1 simple, 2 pre-clustering */
  double epsilon_pct;       /* epsilon: error threshold, % of bounding radius */
  int post_tweak;           /* posttweak: post-plane tweaking (2.3.3) */
  double punish_value;      /* punishval: view-dependent penalty maximum */
  double punish_cutoff_deg; /* punishcutoff: penalty cutoff angle, degrees */
  double sub_penalty;       /* subpenalty: penalty factor for subcells */
  int super_greedy;         /* supergreedy: supergreedy select (2.3.6) */
  /* billboard */
  int backface;         /* backface: backface culling when texturing */
  int normal_maps;      /* nm: normal maps (2.3.1) */
  double point_size;    /* pointsize: point size for point clouds */
  int point_smooth;     /* pointsmooth: round points */
  int point_skip;       /* pointskip: skip planes with fewer points */
  int point_normals;    /* pointnormals: weigh points by their normals (file or estimated) */
  double poly_skip_pct; /* polyskip: skip planes below n% coverage */
  int prelight;         /* prelight: lighting while texturing */
  int pure;             /* pure: only a plane's own faces in its texture */
  int quality;          /* quality: 0 fast, 2 supersample+squash, 3 supersample */
  int texres;           /* texres: maximum texture resolution, power of 2 */
  /* output */
  int format; /* format: 0 VRML2.0/Open Inventor mix, 1 VRML97 */
  int dds;    /* dds: VRML output also carries the atlas as DDS with mip levels */
  /* extensions beyond Appendix A */
  int up_axis;           /* upaxis: the model's up axis, 0 = x, 1 = y, 2 = z
                          * (view-dependent penalty, previews) */
  int threads;           /* threads: worker threads, 0 = all cores; never changes results */
  int merge;             /* merge: after step 2, dissolve planes whose faces all fit other
                          * planes (smallest first) */
  int candidates;        /* candidates: densest cells refined per plane, the plane
                          * simplifying the largest projected area wins (1 = thesis) */
  int back_images;       /* backimages: 1 = each billboard is two one-sided quads,
                          * front and back image; 0 = one double-sided quad */
  int unlit;             /* unlit: 0 = lit material (relightable: viewers light the
                          * billboards, with the normal map when nm), 1 = unlit
                          * (KHR_materials_unlit, VRML without Material: colours
                          * shown as baked), 2 = unlit when prelight is on */
  int viewer_ambient;    /* ambient: prelight adds the ambient light X3D/OpenGL
                          * viewers give the original (bbc_view.ambient) */
  double light_elev_deg; /* lightelev: prelight direction, degrees above the horizon */
  double light_azim_deg; /* lightazim: ... degrees around the up axis */
  int shade_voxels;      /* shade: voxel shadowing grid, voxels per axis, 0 off (2.3.11) */
  double shade_ambient;  /* shadeambient: ambient share of voxel shadowing, 0..1 */
  int dither;            /* dither: quality 2: texel opacity by coverage-preserving error
                          * diffusion of its samples' coverage (1) or by growing (0) */
  int stem;              /* stem: billboards through the trunk part's axis, 180/n
                          * degrees apart, each showing the whole stem (0 = off) */
  int limbs;             /* limbs: > 0: the trunk part (stem and limbs) kept as a mesh of
                          * at most this many triangles inside the cloud instead of
                          * billboards, when the model has a foliage part (0 = off) */
  int refine;            /* refine: quality 2: views of the original each billboard's
                          * alpha is refined against (0 = off; src/core/refine.c) */
  int grow_min;          /* growmin: quality 2: a texel is opaque when at least this
                          * many of its 16 samples are (1 = the thesis's growing) */
  int max_planes;        /* maxplanes: > 0: when steps 1-2 give more planes, they run
                          * again with every epsilon 1.25-2x larger until they do not */
  int min_planes;        /* minplanes: > 0: when they give fewer (and never had too
                          * many), they run again with epsilon 1.25-2x smaller (down
                          * to 1/5) while the count stays within maxplanes */
  int atlas_max;         /* atlasmax: > 0: texres is chosen as the largest power of two
                          * whose cloud fits one atlas_max x atlas_max atlas */
} bbc_params;

typedef struct bbc_param_info {
  const char *name; /* Appendix A name, e.g. "epsilon" */
  bbc_param_type type;
  double min, max; /* inclusive range */
  double default_value;
  unsigned flags;          /* BBC_PARAM_STEP3_ONLY | BBC_PARAM_KEEPS_STEP1 */
  const char *group;       /* "performance", "plane", "billboard", "output",
                            * "extension" (not in Appendix A) */
  const char *unit;        /* "%", "deg", "texels", "" */
  const char *description; /* one line */
} bbc_param_info;

/* Fills every parameter with the toolkit's default: Appendix A's, except
 * where the fidelity benchmark found better far LODs for trees (README,
 * "Defaults"): clustering 0 (thesis 2), epsilon 6 (5), quality 2 (0), and the
 * extensions maxplanes 32, minplanes 16 and atlasmax 1024 (thesis: none, 0). */
void bbc_params_default(bbc_params *params);
/* The thesis's Appendix A defaults exactly (maxplanes, minplanes, atlasmax off). */
void bbc_params_thesis(bbc_params *params);

size_t bbc_param_count(void);
/* i < bbc_param_count(); in Appendix A order. */
const bbc_param_info *bbc_param_at(size_t i);
/* NULL when no parameter has that name (case-insensitive). */
const bbc_param_info *bbc_param_find(const char *name);
/* Parses `text` (a number; "on"/"off"/"true"/"false" for switches) and
 * stores it after the range check. On error the parameter is unchanged and
 * the message names the parameter and its allowed range. */
bbc_result bbc_params_set(bbc_params *params, const char *name, const char *text, bbc_error *err);
/* Parses "name=value". */
bbc_result bbc_params_set_assignment(bbc_params *params, const char *assignment, bbc_error *err);
/* Copies one parameter's value from `src` to `dst`. */
void bbc_params_copy(bbc_params *dst, const bbc_params *src, const bbc_param_info *info);
/* Current value of a parameter as a double. */
double bbc_params_get(const bbc_params *params, const bbc_param_info *info);
/* The parameter classes of Appendix A, for a session that keeps its steps:
 * the first step that must run again when the parameters change from
 * `before` to `after` — 3 when only texturing ('*') parameters changed, 2
 * when step-2 ('+') ones did too, 1 for anything else, 0 when nothing that
 * changes a result changed (threads, debug and the VRML format never do).
 * `which` (may be NULL) gets the name of a parameter that forces that step. */
int bbc_params_first_step(const bbc_params *before, const bbc_params *after, const char **which);

/* `count` points on a triangle mesh's surface, uniform by area, coloured as
 * the surface there (material colour times texture), the same for the same
 * seed: a point cloud (`out`, freed with bbc_mesh_free). */
bbc_result bbc_mesh_sample_points(const bbc_mesh *mesh, size_t count, uint64_t seed, bbc_mesh *out,
                                  bbc_error *err);
/* A point cloud as binary little-endian PLY: x y z as doubles, red green
 * blue when it has colours. Atomic. */
bbc_result bbc_points_write_ply(const char *path, const bbc_mesh *points, bbc_error *err);

/* A normal for each point of a point cloud (3 floats a point, unit, or zero
 * where a point has fewer than 3 neighbours): the direction of least spread
 * of the points around it (principal components within a cell of a grid
 * holding about 12 points). Deterministic for any thread count (0 = all). */
bbc_result bbc_point_normals(const bbc_mesh *mesh, int threads, float *normals, bbc_error *err);

/* ------------------------------------------------------------------------ */
/* Plane selection: steps 1 and 2 of the Billboard Cloud algorithm          */
/* ------------------------------------------------------------------------ */

/* Why a plane exists; the thesis's colour code in brackets. */
typedef enum bbc_plane_kind {
  BBC_PLANE_STANDARD = 0, /* found by the recursive greedy select [light blue] */
  BBC_PLANE_COPLANAR,     /* replaced by its coplanar faces' plane, 2.3.2 [orange] */
  BBC_PLANE_POSTTWEAKED,  /* refined by post-plane tweaking, 2.3.3 [pink] */
  BBC_PLANE_CARDBOARD,    /* perpendicular to its mother plane, 2.3.7 [green] */
  BBC_PLANE_PARACHUTE,    /* found by the fail-safe, 2.3.4 [cyan] */
  BBC_PLANE_STEM,         /* step 3: through the trunk's axis (`stem`) [yellow] */
  BBC_PLANE_KIND_COUNT
} bbc_plane_kind;

/* "standard", "coplanar", "posttweaked", "cardboard", "parachute". */
const char *bbc_plane_kind_name(bbc_plane_kind kind);

typedef struct bbc_plane {
  double normal[3]; /* unit normal n; the plane is n . x = d */
  double d;         /* model units, in the model's own frame */
  bbc_plane_kind kind;
  uint32_t part;       /* index into bbc_planeset.parts */
  size_t face_count;   /* faces it simplifies (cardboard: mother's faces
                        * valid for it, which stay assigned to the mother) */
  double area;         /* sum of those faces' areas projected onto it */
  int32_t mother;      /* cardboard: index of the mother plane, else -1 */
  double coverage_pct; /* cardboard: area / mother's area * 100, else 100 */
} bbc_plane;

/* A part of a model simplified on its own (thesis 2.2.4, 3.1.1). */
typedef struct bbc_part_result {
  char name[32];      /* "trunk", "foliage", "all" or a user's name */
  double epsilon_abs; /* its error threshold, model units */
  double center[3];   /* centre of the dual grid (the part's centre of gravity) */
  double radius;      /* the part's bounding radius around that centre */
  size_t face_count;
  size_t plane_count;
  double step1_s;    /* wall-clock seconds of step 1 (grid and density) */
  double step2_s;    /* ... of step 2 (greedy select) */
  size_t grid_cells; /* cells of its dual grid */
  int limbs;         /* > 0: no planes; step 3 keeps its faces as a mesh of at most
                      * this many triangles (the trunk part with `limbs`) */
} bbc_part_result;

#define BBC_NO_PLANE UINT32_MAX /* face_plane of a face no plane simplifies */

typedef struct bbc_planeset {
  double radius;      /* the whole model's bounding radius */
  double epsilon_abs; /* the largest epsilon used by any part */
  size_t plane_count;
  bbc_plane *planes;    /* parts' planes one part after another */
  size_t face_count;    /* = mesh->triangle_count */
  uint32_t *face_plane; /* per triangle of the mesh (its order): the plane
                         * that simplifies it; never a cardboard plane;
                         * BBC_NO_PLANE for the trunk part's faces kept as
                         * a mesh (`limbs`) */
  size_t part_count;
  bbc_part_result *parts;
  uint32_t *face_part;  /* per triangle: index into parts */
  char split_why[320];  /* how the parts were chosen, for people */
  double epsilon_scale; /* maxplanes/minplanes: the factor every part's epsilon was
                         * multiplied by (1 = as asked) */
  int attempts;         /* runs of steps 1 and 2 (> 1 when maxplanes raised epsilon) */
  double retry_s;       /* wall-clock seconds of the discarded runs */
} bbc_planeset;

void bbc_planeset_free(bbc_planeset *set);

/* How faces are split into parts. */
typedef enum bbc_split_mode {
  BBC_SPLIT_AUTO = 0, /* by names where they tell, else by geometry */
  BBC_SPLIT_NONE,     /* one part, "all" */
  BBC_SPLIT_NAMES,    /* by group/material names only (trunk/bark/stem/... vs
                       * leaf/leaves/twig/foliage/needle/...) */
  BBC_SPLIT_GEOMETRY, /* the few large connected pieces are the trunk */
  BBC_SPLIT_PATTERNS  /* the user's patterns in bbc_split_options */
} bbc_split_mode;

typedef struct bbc_split_options {
  bbc_split_mode mode;
  /* BBC_SPLIT_PATTERNS: comma-separated, case-insensitive glob patterns
   * ('*', '?') matched against each face's group and material names. A
   * face matching trunk_patterns is trunk, else matching foliage_patterns is
   * foliage, else it goes to `rest` ("trunk" or "foliage"). */
  const char *trunk_patterns;
  const char *foliage_patterns;
  const char *rest;
  /* 1 = the trunk part keeps only the stem; the branches join the foliage,
   * among whose leaves they lie (thesis 2.2.4: "separate the stem and the
   * foliage plus branches"). The stem is followed up the up axis from the
   * trunk's base. 0 = the trunk part keeps every trunk face. */
  int stem_only;
  int up_axis; /* 0 = x, 1 = y, 2 = z: for stem_only */
  /* BBC_SPLIT_AUTO: 1 = when the names make every face trunk (a leafless
   * tree), split by geometry instead of keeping one part (set when the
   * trunk part becomes a mesh, `limbs`, and the twigs then go on planes). */
  int all_trunk_by_geometry;
  /* The trunk kept as a mesh of at most `limbs` triangles (0 = billboards):
   * of a trunk made of several pieces (branch tubes), the thickest that fit
   * twice that stay, the thinner join the foliage, and stem_only is not
   * applied. */
  int limbs;
} bbc_split_options;

/* Splits the faces of `mesh` into parts: writes part names (at most 2 parts:
 * "trunk" then "foliage"; or one part "all") and face_part[triangle_count].
 * Returns the number of parts (1 or 2) in *part_count. `why` (may be NULL)
 * receives a short explanation ("names: material Leaves / Trunk"). */
bbc_result bbc_split_parts(const bbc_mesh *mesh, const bbc_split_options *options,
                           uint32_t *face_part, size_t *part_count, char names[2][32], char *why,
                           size_t why_size, bbc_error *err);

typedef struct bbc_planes_options {
  bbc_params params;          /* for every part unless overridden */
  size_t part_override_count; /* parameters per part: */
  struct {
    char part[32]; /* "trunk", "foliage" or "all" */
    bbc_params params;
  } part_overrides[4];
  bbc_split_options split;
  bbc_callbacks callbacks;
} bbc_planes_options;

void bbc_planes_options_default(bbc_planes_options *options);
/* bbc_params_first_step over whole plane-selection options: the parameters,
 * the per-part overrides (which then names e.g. "trunk.epsilon", in a
 * static buffer) and the split (which = "split": step 1). */
int bbc_planes_options_first_step(const bbc_planes_options *before, const bbc_planes_options *after,
                                  const char **which);

/* Steps 1 and 2 of the thesis (2.1.3-2.1.8 with the extensions of 2.3):
 * finds planes such that every triangle of `mesh` is simplified by exactly
 * one plane and each of its vertices lies within the part's epsilon of it.
 * epsilon is in percent of the whole model's radius for every part.
 * Deterministic: the same input and options give identical results with any
 * thread count. */
bbc_result bbc_planes_find(const bbc_mesh *mesh, const bbc_planes_options *options,
                           bbc_planeset *set, bbc_error *err);

/* The same as two calls, so that step 2 can run again on the same step 1
 * (Appendix A's bbc1 and bbc2): bbc_planes_find is bbc_grid_build then
 * bbc_planes_select, with identical results. */
typedef struct bbc_grid bbc_grid;
/* Step 1: the model split into parts, each part's faces in dual form and its
 * dual grid of plane space with the faces' density (2.1.4-2.1.7), at the
 * asked epsilon. The grid keeps a copy of the options (split texts too). */
bbc_result bbc_grid_build(const bbc_mesh *mesh, const bbc_planes_options *options, bbc_grid **grid,
                          bbc_error *err);
void bbc_grid_free(bbc_grid *grid);
/* Step 2 on a grid of step 1 (the greedy select and what follows it, on a
 * copy of the density: the grid stays whole for the next call). `options`
 * may differ from the grid's only in step-2 and step-3 parameters
 * (bbc_planes_options_first_step != 1), else BBC_ERROR_INVALID_ARGUMENT
 * naming the parameter. When maxplanes/minplanes move epsilon, the grids at
 * the other epsilons are built into `grid` and kept too. */
bbc_result bbc_planes_select(bbc_grid *grid, const bbc_planes_options *options, bbc_planeset *set,
                             bbc_error *err);

/* The billboard of a plane (thesis 2.1.9): the minimum-area rectangle, on
 * the plane, around its faces' projected vertices (convex hull and rotating
 * calipers). A cardboard plane's rectangle surrounds its mother's faces that
 * are valid for it. Points of the rectangle are
 *   origin + s * width * u + t * height * w,  s, t in [0, 1]. */
typedef struct bbc_billboard {
  uint32_t plane;       /* index into bbc_planeset.planes */
  double origin[3];     /* corner, model coordinates */
  double u[3], w[3];    /* unit in-plane axes, u x w = the plane's normal */
  double width, height; /* extents along u and w, model units (width >= height) */
} bbc_billboard;

/* One billboard per plane of `set` into billboards[set->plane_count]. */
bbc_result bbc_billboards_compute(const bbc_mesh *mesh, const bbc_planeset *set,
                                  bbc_billboard *billboards, bbc_error *err);

/* One billboard of a cloud. */
typedef struct bbc_cloud_billboard {
  bbc_billboard rect;         /* its plane's rectangle (2.1.9) */
  bbc_plane_kind kind;        /* its plane's kind */
  uint32_t part;              /* its plane's part */
  double normal[3];           /* the front side's normal (the plane's) */
  double d;                   /* the plane: normal . x = d */
  int tex_width, tex_height;  /* texels of each of its images */
  bbc_atlas_rect front, back; /* where its images lie in the atlas (back: all 0
                               * when backimages = 0) */
  size_t face_count;          /* triangles drawn into its images */
  int corner_count;           /* its outline, 3..10 corners: the rectangle
                               * clipped to the bounds (+- epsilon) of the faces
                               * drawn, so the cloud stays inside the model's
                               * bounding box grown by epsilon */
  double corners[10][2];      /* (s, t) in [0, 1] on the rectangle, counter-
                               * clockwise seen from the front */
} bbc_cloud_billboard;

typedef struct bbc_cloud {
  /* The cloud as a mesh, in the original model's frame: per billboard its
   * outline fan-triangulated, facing the front with the front image, and
   * (backimages = 1) a second copy facing the back with the back image;
   * material 0 "billboards" (single-sided with back images, else
   * double-sided) whose texture 0 is the colour atlas; with nm its
   * normal_map is texture 1, the normal atlas (same layout), and the mesh
   * has tangents. Groups are the parts. */
  bbc_mesh mesh;
  size_t billboard_count;
  bbc_cloud_billboard *billboards;
  double epsilon_abs;    /* the planes' (largest) epsilon, model units */
  size_t texels;         /* texels of all images (front and back) */
  double atlas_fill;     /* texels / atlas texels */
  double bake_s;         /* wall-clock seconds: baking */
  double atlas_s;        /* ... packing the atlas and building the mesh */
  int texres;            /* the texture resolution used (atlasmax may choose it) */
  size_t limb_triangles; /* `limbs`: the mesh's last triangles are the trunk part's,
                          * simplified (on the mesh's last vertices), textured by a
                          * swatch of their colour in the atlas: */
  bbc_atlas_rect limb_swatch;
} bbc_cloud;

/* Step 3 (thesis 2.1.9, 2.2.5, 2.3.1, 2.3.5, 2.3.9, 2.3.11): bakes every
 * kept plane's billboard and builds the Billboard Cloud. Kept: planes whose
 * projected area is at least `polyskip` % of the part's largest (2.3.5),
 * cardboard planes with coverage >= `cbcoverage`. Texture sizes: the longest
 * billboard side gets `texres` texels, the others the next smaller power of
 * two at the same texel size (2.1.9). Each billboard's images show the faces
 * within +-epsilon of its plane, clipped to that slab (`pure`: only its own
 * faces, 2.2.5), the front image as seen from the front, the back image from
 * behind (`backimages`), with `backface` culling; `quality` 2 renders 4 x 4
 * supersampled and keeps a texel opaque when any of its samples is, with the
 * mean colour of the opaque ones (2.3.9), 3 keeps the supersampled images.
 * `prelight`: Lambert shading (two-sided, 0.35 ambient) from the directional
 * light `lightelev`/`lightazim` in the model's frame (`upaxis` is up);
 * `shade` > 0: voxel shadowing (bbc_shade_vertices); `nm`: normal maps in
 * the billboard's tangent space. Planes are baked in parallel (`threads`);
 * the result does not depend on the thread count. `callbacks` may be NULL. */
bbc_result bbc_cloud_build(const bbc_mesh *mesh, const bbc_planeset *set, const bbc_params *params,
                           const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
void bbc_cloud_free(bbc_cloud *cloud);

/* The levels of detail of one model (clouds[count], finest first) in one
 * atlas: when all their images fit into max_size x max_size, every cloud's
 * colour (and normal) atlas becomes that shared atlas and its texture
 * coordinates and image rectangles move with it; *shared = 1. Otherwise
 * nothing changes and *shared = 0 (not an error). Writers store identical
 * textures once (glTF), so the levels then bind one texture. Clouds must
 * all have normal maps or none. */
bbc_result bbc_clouds_share_atlas(bbc_cloud *clouds, size_t count, int max_size, int *shared,
                                  bbc_error *err);

/* Writes a cloud as VRML (thesis Appendix A, "save"), atomically: `wrl_path`
 * (must end in .wrl) and beside it the colour atlas (PNG with alpha) and,
 * with normal maps, the normal atlas. One Shape per billboard side
 * (front, and back when the cloud has back images): ImageTexture of the
 * atlas, IndexedFaceSet with its outline as one polygon, texture
 * coordinates into the atlas, `solid TRUE` for one-sided copies and FALSE
 * for a double-sided one. format 1 = pure VRML97; format 0 = the thesis's
 * VRML 2.0 with Open Inventor-style extensions: the same file plus, with
 * normal maps, a `NormalMap { url "<stem>_nm.png" }` node beside each Shape
 * (the two in a Group; VRML97's Appearance takes no extra fields), declared
 * by a no-op PROTO at the top, so VRML97 readers still parse it. `comment`
 * (may be NULL) goes into the header as # lines. format | BBC_VRML_UNLIT
 * leaves the Material out of every Appearance, so viewers draw the textures
 * unlit (VRML97 6.4): for prelit clouds. Texture files follow
 * bbc_texture_file_name: <stem>_<material>.png, <stem>_<material>_nm.png. */
#define BBC_VRML_UNLIT 0x100
/* format | BBC_VRML_DDS: an alpha-tested colour atlas is also written as
 * <stem>_<material>.dds (bbc_image_write_dds: mip levels that keep its
 * coverage) and named first in each url, the PNG second, for VRML readers
 * without DDS (VRML97 4.5.2: the first location that can be read). */
#define BBC_VRML_DDS 0x200
bbc_result bbc_cloud_write_vrml(const char *wrl_path, const bbc_cloud *cloud, int format,
                                const char *comment, bbc_error *err);

/* Whether a cloud baked with `params` is written with unlit materials
 * (the `unlit` parameter; 2 follows `prelight`). */
int bbc_params_unlit(const bbc_params *params);

/* The unit direction towards the prelight light (lightelev, lightazim,
 * upaxis of `params`) in the model's frame. */
void bbc_params_light_direction(const bbc_params *params, double light[3]);

/* Voxel shadowing (thesis 2.3.11): a grid of `voxels` cubes along the
 * model's longest axis (1..512) counts the vertices in each voxel; each voxel's
 * shadow is the count of the voxels above it (along `up_axis`) within 40 %
 * of the bounding radius, weighted down linearly with the distance; the
 * 95th percentile of the shadowed vertices' shadows maps to `ambient`, no shadow to
 * 1. Writes one factor in [ambient, 1] per vertex into shade[vertex_count]. */
bbc_result bbc_shade_vertices(const bbc_mesh *mesh, int voxels, double ambient, int up_axis,
                              float *shade, bbc_error *err);
/* The occupied voxels of the same grid, for showing them (`show model`
 * F10): 4 floats a voxel, its centre and its light (ambient..1), in `boxes`
 * (the caller frees it); a voxel's side is bbc_shade_voxel_size. */
bbc_result bbc_shade_voxels(const bbc_mesh *mesh, int voxels, double ambient, int up_axis,
                            float **boxes, size_t *count, bbc_error *err);
double bbc_shade_voxel_size(const bbc_mesh *mesh, int voxels);

/* ------------------------------------------------------------------------ */
/* Software rendering (no GPU): previews now, baking and evaluation later    */
/* ------------------------------------------------------------------------ */

/* An orthographic camera. The image shows the square of side
 * 2 * half_extent around `center`, seen along `direction`. */
typedef struct bbc_view {
  double direction[3];   /* viewing direction, camera towards the model */
  double up[3];          /* up hint; must not be parallel to direction */
  double center[3];      /* model point at the image centre */
  double half_extent;    /* half the image side, model units, > 0 */
  int lighting;          /* 1 = Lambert shading from a light over the viewer's
                          * left shoulder (two-sided); 0 = unlit colours */
  float point_size_px;   /* point clouds: splat width in pixels (>= 1) */
  int point_round;       /* point clouds: round splats (pointsmooth), else squares */
  uint8_t background[4]; /* RGBA written where nothing covers a pixel */
  /* Baking (all optional, zero = off): */
  double half_extent_y;        /* > 0: the image shows 2 half_extent x 2 half_extent_y
                                * (independent scales in x and y) */
  double depth_min, depth_max; /* when depth_max > depth_min: only surface points
                                * whose depth along `direction` from `center` lies
                                * in [depth_min, depth_max] are drawn (a slab) */
  const uint8_t *face_mask;    /* when not NULL: triangle t drawn only if mask[t] */
  /* Lighting (optional): */
  double light[3];           /* not zero: with `lighting`, the direction towards a
                              * directional light in the model's frame (else the
                              * light follows the camera, as described below) */
  const float *vertex_shade; /* not NULL: per vertex factor in [0, 1] multiplying
                              * the colour (voxel shadowing, bbc_shade_vertices) */
  double light_gain;         /* with `lighting`: multiplies the shade (0 = 1);
                              * bbc_light_gain: as bright as a lit viewer shows it */
  int headlight;             /* with `lighting`: the light at the camera and the
                              * shade |n . v| (no floor), as viewers light a model */
  int ambient;               /* with `lighting`: adds X3D viewers' ambient light,
                              * 0.2 x mean over channels of (Ka / Kd) x Kd,
                              * untextured (Ka 0.2 when none; a grey Kd:
                              * OpenGL's 0.2 x Ka) */
} bbc_view;

/* The factor that makes a model lit by the directional light `light`
 * (unit, towards the light) with the renderer's shading 0.35 + 0.65 |n . l|
 * as bright, on average, as a lit viewer's headlight shows it (the light at
 * the camera, shade |n . v|: what model viewers and engine previews use).
 * Measured, not assumed: the model is rendered both ways (96 pixels, 8
 * azimuths around `up_axis` (0 = x, 1 = y, 2 = z), at 0 and 20 degrees of
 * elevation in turn: a viewer near the ground; occlusion included; one
 * pass per view) and *gain = the ratio of the covered
 * pixels' summed luminance. Prelit clouds are baked with it (plus the
 * fixed-function ambient, bbc_view.ambient), so that shown unlit they look
 * as bright as the original in a lit viewer; the sun only adds relief.
 * 1 for point clouds. Deterministic with any number of threads. */
bbc_result bbc_light_gain(const bbc_mesh *mesh, const double light[3], int up_axis, double *gain,
                          bbc_error *err);

/* Renders `mesh` into `image` (already allocated; its size is the
 * resolution) with a depth buffer, diffuse textures (nearest texel, repeat)
 * times the base colour, and an alpha test at 0.5. Both faces of every
 * triangle are drawn, except for materials marked single_sided. Lighting
 * (Lambert, two-sided) multiplies the colour by 0.35 + 0.65 |n . l|. A pixel is covered when its
 * centre is inside a triangle (top-left rule on shared edges). Deterministic. */
bbc_result bbc_render_ortho(const bbc_mesh *mesh, const bbc_view *view, bbc_image *image,
                            bbc_error *err);

/* Where model point p lands in a width x height image rendered with `view`:
 * out = (x right, y down) in pixels. Returns 0 when the view is invalid. */
int bbc_view_project(const bbc_view *view, int width, int height, const double p[3], double out[2]);

/* Fills `view` to look at the whole mesh along `direction` with `up`,
 * framing its bounding sphere with a small margin. */
void bbc_view_frame_mesh(const bbc_mesh *mesh, const double direction[3], const double up[3],
                         bbc_view *view);

/* ------------------------------------------------------------------------ */
/* Baselines: what a user would otherwise pick for a far LOD                 */
/* ------------------------------------------------------------------------ */

/* Crossed billboards: `planes` vertical planes (1..16) through the centre of
 * the model's bounding box, at equal angles around the up axis (`upaxis`),
 * plus a horizontal one when `horizontal`; each billboard the whole model's
 * projection onto its plane, baked by the step-3 baker (every face, front and
 * back images as `backimages`, `quality`, `prelight`, ...) at the power-of-two
 * texture resolution whose texel count comes closest to `texel_budget`. */
bbc_result bbc_baseline_crossed(const bbc_mesh *mesh, int planes, int horizontal,
                                const bbc_params *params, size_t texel_budget,
                                const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);

/* meshoptimizer's simplification (Debian libmeshoptimizer, 0.18) towards
 * `target_triangles`, each material and group on its own in proportion:
 * meshopt_simplify (edge collapses that keep attribute seams and borders,
 * so separate leaf cards cannot go below about one quad each) or, with
 * `sloppy`, meshopt_simplifySloppy (vertex clustering, reaches any target).
 * UVs, normals, materials and textures are kept; unused vertices dropped. */
bbc_result bbc_baseline_simplify(const bbc_mesh *mesh, size_t target_triangles, int sloppy,
                                 bbc_mesh *out, bbc_error *err);

/* ------------------------------------------------------------------------ */
/* Fidelity: how close a simplified model looks to its original              */
/* ------------------------------------------------------------------------ */

typedef struct bbc_eval_options {
  int views;                 /* directions evenly over the sphere (Fibonacci lattice), 64 */
  int size;                  /* pixels per side of each view, 256 */
  int up_axis;               /* 0 = x, 1 = y, 2 = z: side views, image up */
  double side_elevation_deg; /* side views: |elevation| <= this, 30 */
  int lighting;              /* 0 = unlit (default); 1 = both lit alike by `light`,
                              * as prelight bakes (bbc_light_gain) */
  double light[3];           /* towards the light, model frame */
  int ambient;               /* with lighting: bbc_view.ambient (prelight's `ambient`) */
  const double *directions;  /* not NULL: direction_count explicit directions (camera
                              * towards the model, 3 per view) instead of `views` */
  size_t direction_count;
  int threads;      /* 0 = all cores; results never depend on it */
  bbc_image *sheet; /* not NULL: receives a PNG-ready sheet, one row per
                     * shown view: original | other | coverage difference
                     * (grey both, red original only, blue other only),
                     * labelled with the view's coverage ratio over its
                     * block IoU */
  int sheet_views;  /* rows of the sheet, spread over the views (0 = 8) */
  /* A point cloud as the original is splatted as step 3 splats it: pointsize
   * pixels of a 256-pixel picture of its bounding sphere, round with
   * pointsmooth (defaults 3.5, 1). */
  double point_size;
  int point_smooth;
} bbc_eval_options;

void bbc_eval_options_default(bbc_eval_options *options);

typedef struct bbc_eval_view {
  double direction[3];                   /* camera towards the model */
  double elevation_deg;                  /* of the camera above the horizon */
  int side;                              /* |elevation| <= side_elevation_deg */
  size_t original_px, other_px, both_px; /* covered pixels */
  double iou;                            /* both / either */
  double recall;                         /* both / original: the original's coverage reproduced */
  double false_coverage;                 /* (other - both) / other: coverage the original lacks */
  double psnr; /* dB, RGB over the union of both masks (uncovered = black),
                * 99 for identical images */
  double mae;  /* mean absolute RGB difference over the intersection, 0..255 */
  double original_rgb[3], other_rgb[3]; /* mean colour of each one's covered pixels */
  double coverage_ratio;                /* density: other_px / original_px (1 = as dense; 0 when the
                                         * original covers nothing) */
  double block_iou;                     /* density seen 8x farther: the image cut in 32 x 32 blocks,
                                         * each block's covered fraction per model, sum of min / sum
                                         * of max (1 when neither covers anything) */
} bbc_eval_view;

typedef struct bbc_eval_result {
  size_t view_count;
  bbc_eval_view *views;
  size_t side_count;
  double iou_mean, iou_min, iou_side_mean, iou_side_min;
  double recall_mean, recall_side_mean;
  double false_mean;
  double psnr_mean, psnr_min, psnr_side_mean;
  double mae_mean;
  double coverage_ratio_mean, coverage_ratio_side_mean; /* of the views' coverage_ratio */
  double block_iou_mean, block_iou_side_mean;           /* of the views' block_iou */
  double brightness_ratio[3]; /* per channel: the other's mean colour over its covered
                               * pixels / the original's, over all views (1 = as bright) */
} bbc_eval_result;

/* Renders `original` and `other` (a cloud, a baseline) with the software
 * rasterizer, orthographic, from the same views framing both models' joint
 * bounds in the original's coordinates (an offset model scores worse), and
 * compares coverage and colour. Alpha-tested textures count as coverage;
 * single-sided materials are culled. Deterministic with any thread count. */
bbc_result bbc_eval(const bbc_mesh *original, const bbc_mesh *other,
                    const bbc_eval_options *options, bbc_eval_result *result, bbc_error *err);
void bbc_eval_result_free(bbc_eval_result *result);
/* Direction k of n used by bbc_eval (camera towards the model). */
void bbc_eval_direction(int k, int n, int up_axis, double dir[3]);

/* ------------------------------------------------------------------------ */
/* Built-in tree generator                                                   */
/* ------------------------------------------------------------------------ */

typedef enum bbc_tree_species {
  BBC_TREE_OAK = 0, /* broad, spreading crown */
  BBC_TREE_PINE,    /* conifer: straight stem, whorls of branches */
  BBC_TREE_BIRCH,   /* slender, upright, drooping twigs */
  BBC_TREE_BUSH,    /* several stems from the ground, dense */
  /* Airy species: sparse crowns and thin parts. */
  BBC_TREE_LARCH,   /* conifer: needle tufts on long thin twigs */
  BBC_TREE_WEEPING, /* weeping birch: thin twigs hanging in curtains */
  BBC_TREE_WINTER,  /* leafless oak: branches and twigs only */
  BBC_TREE_PALM,    /* palm: a bare leaning stem and a crown of arching pinnate fronds */
  BBC_TREE_SPECIES_COUNT
} bbc_tree_species;

/* "oak", "pine", ...; NULL for an invalid value. */
const char *bbc_tree_species_name(bbc_tree_species species);
/* -1 when `name` names no species. */
int bbc_tree_species_from_name(const char *name);

typedef struct bbc_tree_options {
  uint64_t seed; /* same seed and options -> identical mesh */
  size_t leaves; /* number of leaf quads; 0 = species default */
  bbc_tree_species species;
  int texture_size; /* leaf texture edge in texels, power of 2 */
  bbc_callbacks callbacks;
} bbc_tree_options;

void bbc_tree_options_default(bbc_tree_options *options);

/* Generates a tree in metres, Y up, base at the origin: group "trunk"
 * (material "bark", tapered tubes) and group "leaves" (material "leaf",
 * quads with a generated RGBA leaf texture whose alpha is 0 or 255). */
bbc_result bbc_tree_generate(const bbc_tree_options *options, bbc_mesh *mesh, bbc_error *err);

#ifdef __cplusplus
}
#endif

#endif /* BBC_H */
