/*
 * bbc.h — libbbc, the Billboard Cloud generator.
 *
 * A Billboard Cloud stands in for a heavy model (a tree above all) far from
 * the viewer: a few dozen planes, each carrying an alpha-textured image of
 * the faces near it, that look like the original from any side. The library
 * implements BBCgen of the diploma thesis "Billboard Clouds for rendering
 * huge forests" (2004; "the thesis" below, chapter 2 and Appendix A) and the
 * extensions measured beyond it. This header is its manual, in the order of
 * the pipeline.
 *
 * Start here — a model to its Billboard Cloud with the toolkit's defaults
 * (every call returns BBC_OK or an error with a message in err.message):
 *
 *   bbc_mesh mesh;              bbc_planes_options options;
 *   bbc_planeset planes;        bbc_cloud cloud;          bbc_error err;
 *   bbc_mesh_load("tree.obj", NULL, &mesh, &err);             // 1. the model
 *   bbc_planes_options_default(&options);                     // 2. parameters
 *   bbc_planes_find(&mesh, &options, &planes, &err);          // 3. steps 1, 2
 *   bbc_cloud_build(&mesh, &planes, &options.params, NULL, &cloud, &err);
 *                                                             // 4. step 3
 *   bbc_gltf_options out = {.unlit = bbc_params_is_unlit(&options.params)};
 *   bbc_mesh_write_gltf("tree.glb", &cloud.mesh, &out, &err); // 5. write it
 *   bbc_cloud_free(&cloud); bbc_planeset_free(&planes); bbc_mesh_free(&mesh);
 *
 * Sections: 1 results, errors and callbacks; 2 images; 3 meshes and point
 * clouds; 4 parameters; 5 steps 1 and 2: parts and planes; 6 step 3:
 * billboards and the cloud; 7 writers; 8 software rendering; 9 evaluation
 * and baselines; 10 generators; 11 the algorithm's internals as geometry
 * for viewers. The forest engine's runtime has its own header, bbc_forest.h.
 *
 * Conventions, stated once:
 *   - Errors: a function that can fail on bad data or bad parameters
 *     returns a bbc_result and, when `err` is not NULL, writes a one-line
 *     message naming the file and the problem into err->message. Programmer
 *     errors (NULL where a pointer is required, an index out of range) are
 *     assert()ions.
 *   - The library never prints and never exits: warnings and progress go
 *     through the optional callbacks of bbc_callbacks.
 *   - No global state: functions may run on different objects from several
 *     threads at once. Threads inside a function never change its result.
 *   - Options: a zeroed options struct (`= {0}`) means the defaults, as does
 *     a NULL options pointer; the `*_options_default()` functions write
 *     exactly that. bbc_params is the parameter table, not an options
 *     struct: it is filled by bbc_params_default() or bbc_params_thesis().
 *     The one exception follows from it: bbc_planes_options holds a
 *     bbc_params, so a zeroed one is not the defaults; fill it with
 *     bbc_planes_options_default() (a NULL pointer still means them).
 *   - Ownership: what a `*_load()`, `*_build()`, `*_find()` or
 *     `*_generate()` fills in belongs to the caller and is released by the
 *     matching `*_free()`; `*_free(NULL)` and freeing a zeroed struct are
 *     safe. On failure the output is left zeroed.
 *   - Units: geometry in the model's own units and frame, double precision;
 *     angles in degrees (`_deg`); `_pct` in percent of the model's bounding
 *     radius; `_s` in seconds; sizes of images in texels or pixels.
 *   - Texture coordinates follow OpenGL: v = 0 is the bottom row of an image.
 *     Images are RGBA8, straight (not premultiplied) alpha, rows top first.
 */
#ifndef BBC_H
#define BBC_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* printf-style format checking of the functions that take a format. */
#if defined(__GNUC__) || defined(__clang__)
#define BBC_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define BBC_PRINTF(fmt, args)
#endif

#define BBC_VERSION_MAJOR  0
#define BBC_VERSION_MINOR  1
#define BBC_VERSION_PATCH  0
#define BBC_VERSION_STRING "0.1.0"

/* ======================================================================== */
/* 1. Results, errors and callbacks                                          */
/* ======================================================================== */

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

/* Returns a short English name of `result` ("corrupt or truncated file");
 * never NULL. */
const char *bbc_result_string(bbc_result result);

/* What a failing function writes: the code and a one-line message. */
typedef struct bbc_error {
  bbc_result code;
  char message[512];
} bbc_error;

typedef enum bbc_log_level { BBC_LOG_INFO = 0, BBC_LOG_WARNING = 1 } bbc_log_level;

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

/* Optional reporting hooks; every member may be NULL (zeroed: none). */
typedef struct bbc_callbacks {
  /* A message for the user (a missing texture, dropped faces). */
  void (*log)(void *user, bbc_log_level level, const char *message);
  /* Progress of a long stage: `stage` names it in plain words, `fraction`
   * in [0, 1], non-decreasing within a stage, 1 exactly once at its end.
   * Called from one thread at a time. */
  void (*progress)(void *user, const char *stage, double fraction);
  void *user; /* passed to every hook */
  /* Asked now and then during steps 1 to 3: non-zero stops the step, which
   * frees what it made and returns BBC_ERROR_CANCELLED. */
  int (*cancel)(void *user);
  /* Step 2's internals at parameter `debug` >= the event's level; the step
   * waits for it to return and its result does not depend on it. The
   * event's arrays are valid during the call only. */
  void (*debug)(void *user, const bbc_debug_event *event);
} bbc_callbacks;

/* For callers that report their own failures and progress the library's
 * way (bbcgen's session does): */
/* Writes `code` and a message formatted as printf's into err (NULL:
 * nothing; cut at sizeof err->message); returns `code`. */
bbc_result bbc_error_set(bbc_error *err, bbc_result code, const char *fmt, ...) BBC_PRINTF(3, 4);
/* Calls cb's log hook with a message formatted as printf's (cut at 1,023
 * bytes); nothing when cb or its hook is NULL. */
void bbc_callbacks_log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...)
    BBC_PRINTF(3, 4);
/* Callbacks that name what they report on, for a stage that repeats (per
 * part, per level of detail): progress stages come out as "<label>:
 * <stage>" and log messages as "<label>: <message>" through the callbacks
 * `in` (may be NULL), the debug hook's events with `where` the label, the
 * cancel hook as it is. `out` is valid while `label` is; calls through it
 * must not overlap (the library reports progress from one thread at a
 * time). The label is cut at 95 bytes. */
typedef struct bbc_label {
  bbc_callbacks outer;
  char label[96];
  char text[1200];
} bbc_label;
void bbc_callbacks_label(const bbc_callbacks *in, bbc_label *label, bbc_callbacks *out,
                         const char *fmt, ...) BBC_PRINTF(4, 5);

/* An axis of the model's frame: the up axis of a model (parameter
 * `upaxis`), the axis of a view. */
typedef enum bbc_axis { BBC_AXIS_X = 0, BBC_AXIS_Y = 1, BBC_AXIS_Z = 2 } bbc_axis;

/* An up axis in an options struct, where zero means the default. */
typedef enum bbc_up {
  BBC_UP_DEFAULT = 0, /* y */
  BBC_UP_X,
  BBC_UP_Y,
  BBC_UP_Z
} bbc_up;

/* Returns the axis `up` names (BBC_UP_DEFAULT: y). */
static inline bbc_axis bbc_up_axis(bbc_up up) {
  return up == BBC_UP_X ? BBC_AXIS_X : up == BBC_UP_Z ? BBC_AXIS_Z : BBC_AXIS_Y;
}
/* Returns the bbc_up that names `axis`. */
static inline bbc_up bbc_up_from_axis(bbc_axis axis) {
  return axis == BBC_AXIS_X ? BBC_UP_X : axis == BBC_AXIS_Z ? BBC_UP_Z : BBC_UP_Y;
}

/* ======================================================================== */
/* 2. Images                                                                 */
/* ======================================================================== */

typedef struct bbc_image {
  int width;     /* texels, >= 0 */
  int height;    /* texels, >= 0 */
  uint8_t *rgba; /* width * height * 4 bytes, rows top first; NULL when empty */
} bbc_image;

/* Allocates a width x height image, every texel (0, 0, 0, 0). width and
 * height > 0, else BBC_ERROR_INVALID_ARGUMENT; on failure (that or
 * BBC_ERROR_OUT_OF_MEMORY) `image` is left zeroed. No message: no `err`. */
bbc_result bbc_image_alloc(bbc_image *image, int width, int height);
/* Releases the texels and zeroes `image` (NULL: nothing). */
void bbc_image_free(bbc_image *image);
/* Decodes a PNG, JPEG, BMP (run-length encoded too), TGA, GIF, PSD, HDR or
 * PNM file into RGBA8 (opaque alpha when the file has none). Images of more
 * than 2^27 texels are refused (BBC_ERROR_OUT_OF_RANGE) before decoding. */
bbc_result bbc_image_load(const char *path, bbc_image *image, bbc_error *err);
/* The same for `size` bytes of an image file held in memory. */
bbc_result bbc_image_load_memory(const void *data, size_t size, bbc_image *image, bbc_error *err);
/* Writes `image` as PNG, atomically (a temporary file renamed over `path`:
 * a failed write leaves no partial file). */
bbc_result bbc_image_write_png(const char *path, const bbc_image *image, bbc_error *err);
/* Returns 1 when at least one texel has alpha < 255, else 0. */
int bbc_image_has_transparency(const bbc_image *image);
/* Builds the mip chain of `base` below level 0, halving down to 1 x 1:
 * *count levels in a malloc'd array at *levels (free each level with
 * bbc_image_free, then the array with free()). An image with transparency
 * gets alpha-tested levels: colours averaged weighted by alpha, alpha
 * binary (0 or 255): as many opaque texels as the level's mean alpha sums
 * to, shared down a quadtree in proportion to each quarter's sum, and in
 * each block of 4 x 4 texels its most covered ones (coverage-preserving
 * alpha mipmaps, after Castano 2010, kept by every part of a level: thin
 * sparse leaves keep theirs beside a dense crown, a solid leaf stays
 * solid); an opaque image gets box-filtered levels. */
bbc_result bbc_image_mipmaps(const bbc_image *base, bbc_image **levels, int *count, bbc_error *err);
/* The same chain for an opaque texture whose texels that count are marked
 * (mask[y * width + x] non-zero: those a model's triangles show, from
 * bbc_mesh_texture_padded): each level's colour the mean of the marked
 * texels under it where there are any (else of all), every level opaque;
 * so a far level of an atlas shows its leaves' colour, not their padding's
 * or their background's. */
bbc_result bbc_image_mipmaps_masked(const bbc_image *base, const uint8_t *mask, bbc_image **levels,
                                    int *count, bbc_error *err);
/* BC1 (S3TC DXT1, 4 bits a texel) for GPUs that sample it: the bytes a
 * width x height image takes (8 a 4 x 4 block, partial blocks whole). */
size_t bbc_bc1_size(int width, int height);
/* Encodes `image` into bbc_bc1_size bytes at `out`: opaque blocks in BC1's
 * four-colour mode (stb_dxt), blocks with a texel of alpha < 128 in its
 * three-colour mode with those texels transparent, so a binary alpha is kept
 * exactly. Deterministic. */
bbc_result bbc_image_encode_bc1(const bbc_image *image, uint8_t *out, bbc_error *err);
/* Decodes BC1 blocks into a new RGBA8 image (free with bbc_image_free), as a
 * GPU samples them. */
bbc_result bbc_bc1_decode(const uint8_t *blocks, int width, int height, bbc_image *out,
                          bbc_error *err);
/* 1 when every texel's alpha is 0 or 255 (BC1 keeps such an alpha). */
int bbc_image_alpha_is_binary(const bbc_image *image);
/* 1 when the alpha is a mask with softened edges, as bbcgen's `softalpha`
 * writes atlases: every texel's alpha at most 64 or at least 192, and some
 * neither 0 nor 255. bbc_image_alpha_binarise makes it 0 (< 128) or 255. */
int bbc_image_alpha_is_soft_mask(const bbc_image *image);
/* Sets every texel's alpha to 0 (below 128) or 255, in place. */
void bbc_image_alpha_binarise(bbc_image *image);
/* Writes `image` with its bbc_image_mipmaps chain as an uncompressed RGBA8
 * DDS (Microsoft's DirectDraw Surface layout, every level down to 1 x 1),
 * atomically. */
bbc_result bbc_image_write_dds(const char *path, const bbc_image *image, bbc_error *err);

/* ======================================================================== */
/* 3. Meshes and point clouds                                                */
/* ======================================================================== */

typedef struct bbc_texture {
  char *path;      /* resolved file path; NULL for generated or embedded images */
  bbc_image image; /* decoded texels (empty when not loaded) */
  int has_alpha;   /* 1 when some texel is not fully opaque */
} bbc_texture;

typedef struct bbc_material {
  char *name;          /* never NULL ("" when the file has none) */
  float base_color[4]; /* RGBA in [0, 1]; alpha is the material's opacity. RGB
                        * multiplies the texture's stored (sRGB) values, as an
                        * MTL's Kd does; glTF's linear baseColorFactor is
                        * converted on reading and writing */
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
                        * none), in [0, 1] */
  int occlusion_map;   /* ambient occlusion in the red channel (glTF
                        * occlusionTexture): 1 + index into mesh->textures, 0 = none */
  float roughness;     /* glTF roughness in (0, 1] (MTL Pr, or from Ns); 0 = not
                        * given (written as 1) */
} bbc_material;

/* Returns 1 when `material` is the one a cloud's limbs get (the trunk part
 * kept as a mesh, parameter `limbs`): named "limbs" or "limbs_LOD<k>". */
int bbc_material_is_limbs(const bbc_material *material);

typedef enum bbc_mesh_kind {
  BBC_MESH_TRIANGLES = 0, /* a polygon model, triangulated */
  BBC_MESH_POINTS = 1     /* a point cloud: vertices only (thesis 2.4) */
} bbc_mesh_kind;

/* A triangle mesh or a point cloud, with its materials and textures. Every
 * array is malloc'd and owned by the mesh (bbc_mesh_free). */
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
                              * rounded to whole units); 0 0 0 when nothing was */
  int no_mipmaps;            /* its textures are sampled at full resolution
                              * (Appendix A's `load ... nomip`) */

  /* The frame (thesis 2.1.4): the area-weighted centre of gravity of the
   * triangles (the mean of the points for a point cloud), the radius of the
   * bounding sphere around it, and the bounds of the used vertices. */
  double center[3];
  double radius;
  double bbox_min[3];
  double bbox_max[3];
} bbc_mesh;

/* How a model is loaded. Zeroed: the defaults. */
typedef struct bbc_load_options {
  /* Where the file has no normals: 0 = smooth vertex normals, area-weighted
   * (thesis parameter vn 1), 1 = flat face normals (vn 0). Normals in the
   * file are always kept. */
  int flat_normals;
  /* 1 = record texture paths without decoding the images (faster). */
  int skip_textures;
  /* 0 = every node; k + 1 = only level of detail k: the nodes (and their
   * subtrees) named "<anything>_LOD<k>" (formats read through Assimp;
   * BBC_ERROR_NOT_FOUND when the file has none). */
  int lod_node;
  /* 1 = mark the mesh no_mipmaps. */
  int no_mipmaps;
  /* 0 = an OBJ whose vertices run on after its last face, at least 100 of
   * them and 1 % of its vertices, none used by a face, is refused as cut
   * short (BBC_ERROR_CORRUPT); 1 = loaded (the unused vertices dropped). */
  int accept_unused;
  bbc_callbacks callbacks;
} bbc_load_options;

/* Writes the defaults (all zero) into `options`. */
void bbc_load_options_default(bbc_load_options *options);

/* Loads a model or a point cloud from `path`. The reader follows the
 * extension: the library's own for PLY (a mesh when it has faces, a point
 * cloud otherwise), XYZ/PTS/TXT point lists and VRML (.wrl: IndexedFaceSet
 * and PointSet); Assimp for the rest (OBJ + MTL, glTF/GLB, 3DS, FBX,
 * COLLADA, AC3D, ...). Node transforms are applied (the file's world
 * frame); texture paths are resolved against the model's folder and its
 * texture folders; a texture that cannot be found or decoded is a warning
 * and its material keeps the base colour. The mesh is finished with
 * bbc_mesh_finalize. options: NULL = defaults. On failure `mesh` is left
 * zeroed and `err` names the file and what is wrong. */
bbc_result bbc_mesh_load(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                         bbc_error *err);
/* The same from `size` bytes in memory; `name` chooses the reader by its
 * extension and names the input in messages. No other file is read (an
 * OBJ's MTL or a .gltf's buffers are not found; a .glb is whole). */
bbc_result bbc_mesh_load_memory(const char *name, const void *data, size_t size,
                                const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

/* Releases everything the mesh owns and zeroes it (NULL: nothing). */
void bbc_mesh_free(bbc_mesh *mesh);
/* A copy of texture `texture` of `mesh` whose texels that no triangle's
 * texture coordinates reach (nor a texel next to one) take the colour of
 * the nearest texel that is reached (breadth first), alpha kept: mip levels
 * of it do not mix in what the model never shows (an atlas's background
 * between its leaves; a triangle that repeats it, wrapped). A plain copy
 * where the mesh has no coordinates or a triangle's box covers the texture
 * more than 16 times. *levels (NULL: not asked): how many mip levels past
 * level 0 keep the used texels' islands (4-connected, each of at least 2 %
 * of them) apart, a texel at most a quarter of the smallest side of their
 * boxes (an atlas's two leaves and its bark; every level where one island
 * covers the texture). *used (NULL: not asked): a malloc'd mask of width x
 * height bytes, 1 where a triangle's texture coordinates reach, else 0
 * (for bbc_image_mipmaps_masked; NULL where the whole texture counts).
 * Allocated here (free with bbc_image_free and free); zeroed on failure. */
bbc_result bbc_mesh_texture_padded(const bbc_mesh *mesh, int texture, bbc_image *out, int *levels,
                                   uint8_t **used, bbc_error *err);

/* Checks and completes a mesh whose arrays the caller filled in (loaders
 * and generators end with it): refuses non-finite coordinates and indices
 * out of range (BBC_ERROR_INVALID_GEOMETRY), drops zero-area triangles
 * (counted in dropped_degenerate), computes missing normals (smooth when
 * `smooth_normals` is 1, flat when 0), the bounds, centre and radius.
 * BBC_ERROR_EMPTY when nothing usable remains. `source` (may be NULL)
 * names the input in messages. */
bbc_result bbc_mesh_finalize(bbc_mesh *mesh, int smooth_normals, const char *source,
                             bbc_error *err);

/* Counts the triangles of each group into counts[mesh->group_count]. */
void bbc_mesh_count_group_triangles(const bbc_mesh *mesh, size_t *counts);

/* ======================================================================== */
/* 4. Parameters (thesis Appendix A, "Parameter Reference")                  */
/* ======================================================================== */

/* The values of the parameters that choose among modes. */
typedef enum bbc_clustering {
  BBC_CLUSTERING_OFF = 0,    /* faces are not clustered */
  BBC_CLUSTERING_SIMPLE = 1, /* the densest cell's faces split by isolation (2.3.10) */
  BBC_CLUSTERING_PRE = 2     /* pre-clustering: the cells' faces clustered before
                              * the densest is chosen (2.3.10; the thesis's default) */
} bbc_clustering;

typedef enum bbc_pure {
  BBC_PURE_SLAB = 0,  /* every face within a plane's +-epsilon slab is drawn into
                       * its texture, clipped to the slab */
  BBC_PURE_OWN = 1,   /* only the faces the plane simplifies (2.2.5) */
  BBC_PURE_SHARED = 2 /* every face crossing the slab, its coverage shared between
                       * the slabs it crosses (with quality 2 and dither) */
} bbc_pure;

typedef enum bbc_quality {
  BBC_QUALITY_FAST = 0,        /* one sample a texel (the thesis's default) */
  BBC_QUALITY_FAST_ALT = 1,    /* the same as 0 (Appendix A's value 1) */
  BBC_QUALITY_SQUASHED = 2,    /* 4 x 4 samples a texel, squashed to binary alpha
                                * (2.3.9) */
  BBC_QUALITY_SUPERSAMPLED = 3 /* 4 x 4 samples a texel, the images kept at the
                                * sampling resolution */
} bbc_quality;

typedef enum bbc_unlit_mode {
  BBC_UNLIT_NO = 0,         /* lit materials: viewers light the billboards */
  BBC_UNLIT_YES = 1,        /* unlit materials (KHR_materials_unlit, MTL illum 0,
                             * VRML without Material): colours shown as baked */
  BBC_UNLIT_WHEN_PRELIT = 2 /* unlit when `prelight` is on, else lit */
} bbc_unlit_mode;

typedef enum bbc_vrml_format {
  BBC_VRML_EXTENDED = 0, /* the thesis's VRML 2.0 with Open Inventor-style
                          * extensions (normal maps) */
  BBC_VRML_97 = 1        /* pure VRML97 (ISO/IEC 14772-1) */
} bbc_vrml_format;

typedef enum bbc_param_type {
  BBC_PARAM_BOOL = 0, /* 0 or 1 */
  BBC_PARAM_INT,      /* integer in [min, max] */
  BBC_PARAM_REAL,     /* real in [min, max] */
  BBC_PARAM_POW2      /* power of two in [min, max] */
} bbc_param_type;

/* The parameter classes of Appendix A (bbc_param_info.flags). */
#define BBC_PARAM_STEP3_ONLY  1u /* '*': used only by step 3 (texturing) */
#define BBC_PARAM_KEEPS_STEP1 2u /* '+': may change before step 2 without redoing step 1 */

/* Every parameter: each field names its Appendix A parameter, and
 * docs/parameters.md (generated from the table) gives ranges, units and
 * both defaults. Fill with bbc_params_default or bbc_params_thesis; change
 * by field or with bbc_params_set (range-checked). */
typedef struct bbc_params {
  /* performance */
  int break_steps;    /* break: stop the recursive greedy select after n steps */
  int break_num;      /* breaknum: ... only if more than n primitives are valid */
  int debug;          /* debug: debug events up to this level, 0..3 */
  int res_deg;        /* res: dual grid theta/phi resolution, degrees a cell */
  int vertex_normals; /* vn: smooth vertex normals on load where the file has none */
  int accept_unused;  /* acceptunused: load an OBJ that looks cut short (bbc_load_options) */
  /* plane */
  int cardboard;             /* cardboard: cardboard plane finding (2.3.7) */
  double cb_coverage_pct;    /* cbcoverage: minimum cardboard coverage, % of the mother */
  bbc_clustering clustering; /* clustering (2.3.10) */
  double epsilon_pct;        /* epsilon: error threshold, % of the bounding radius */
  int post_tweak;            /* posttweak: post-plane tweaking (2.3.3) */
  double punish_value;       /* punishval: view-dependent penalty maximum (2.3.8) */
  double punish_cutoff_deg;  /* punishcutoff: penalty cutoff angle */
  double sub_penalty;        /* subpenalty: penalty factor for subcells */
  int super_greedy;          /* supergreedy: supergreedy select (2.3.6) */
  /* billboard */
  int backface;         /* backface: backface culling when texturing */
  int normal_maps;      /* nm: normal maps (2.3.1) */
  double point_size;    /* pointsize: splat size for point clouds, pixels of a
                         * 256-pixel picture of the model */
  int point_smooth;     /* pointsmooth: round splats */
  int point_skip;       /* pointskip: drop planes with fewer points */
  int point_normals;    /* pointnormals: weigh points by their normals */
  int point_sample;     /* pointsample: steps 1 and 2 on about this many points */
  int face_sample;      /* facesample: steps 1 and 2 on about this many faces of a large mesh */
  double poly_skip_pct; /* polyskip: drop planes below n % of the largest's area (2.3.5) */
  int prelight;         /* prelight: lighting baked while texturing */
  bbc_pure pure;        /* pure: which faces a texture shows (2.2.5) */
  bbc_quality quality;  /* quality: sampling of the textures (2.3.9) */
  int texres;           /* texres: texels along a billboard's longest side, a power of 2 */
  /* output */
  bbc_vrml_format format; /* format: VRML output */
  int dds;                /* dds: VRML output also carries the atlas as DDS with mip levels */
  /* extensions beyond Appendix A */
  bbc_axis up_axis;      /* upaxis: the model's up axis (view-dependent penalty,
                          * stem, shading, previews) */
  int threads;           /* threads: worker threads, 0 = all cores; never changes results */
  int merge;             /* merge: after step 2, dissolve planes whose faces all fit
                          * other planes (smallest first) */
  int candidates;        /* candidates: densest cells refined per plane, the plane
                          * simplifying the largest projected area wins (1 = thesis) */
  int back_images;       /* backimages: 1 = each billboard is two one-sided quads,
                          * front and back image; 0 = one double-sided quad */
  bbc_unlit_mode unlit;  /* unlit: the cloud's material */
  int viewer_ambient;    /* ambient: prelight adds the ambient light X3D/OpenGL
                          * viewers give the original (bbc_view.ambient) */
  double light_elev_deg; /* lightelev: prelight direction above the horizon */
  double light_azim_deg; /* lightazim: ... around the up axis */
  int shade_voxels;      /* shade: voxel shadowing grid, voxels per axis, 0 off (2.3.11) */
  int occlusion;         /* occlusion: > 0: an occlusion map (glTF occlusionTexture) from
                          * voxel shadowing with this many voxels, the colour left
                          * unshadowed (in place of `shade`); 0 = none */
  double occlusion_min;  /* occlusionmin: the occlusion map's darkest value */
  double nm_bend;        /* nmbend: normal maps: each texel's normal plus this times the
                          * unit direction from the crown's centre, renormalised */
  double nm_flat;        /* nmflat: normal maps: each texel's normal plus this times the
                          * billboard's own normal, renormalised */
  double nm_up;          /* nmup: normal maps: a two-sided face shows the side that turns
                          * to its billboard's viewer tilted this much towards up */
  double rough_min;      /* roughmin: the billboards' material roughness at least this
                          * (the source's mean when higher) */
  double shade_ambient;  /* shadeambient: ambient share of voxel shadowing, 0..1 */
  int dither;            /* dither: quality 2: texel opacity by coverage-preserving
                          * error diffusion (1) or by growing (0) */
  int soft_alpha;        /* softalpha: the colour atlas's alpha softened next to the
                          * opaque/transparent edge (still >= 128 where opaque, < 128
                          * where not) so that a client's bilinear alpha test keeps
                          * each texel's area (1), or alpha 0/255 only (0) */
  int stem;              /* stem: billboards through the trunk part's axis, 180/n
                          * degrees apart, each showing the whole stem (0 = off) */
  int limbs;             /* limbs: > 0: the trunk part kept as a mesh of at most this
                          * many triangles inside the cloud (0 = billboards) */
  int refine;            /* refine: quality 2: views of the original each billboard's
                          * alpha is refined against (0 = off) */
  int refine_size;       /* refinesize: pixels across the renders refine judges
                          * against (the screen size the cloud is made for) */
  int grow_min;          /* growmin: quality 2: a texel is opaque when at least this
                          * many of its samples are (1 = the thesis's growing) */
  int max_planes;        /* maxplanes: > 0: more planes than this runs steps 1-2
                          * again with every epsilon 1.25-2x larger */
  int min_planes;        /* minplanes: > 0: fewer (and never too many) runs them again
                          * with epsilon 1.25-2x smaller, down to 1/5 */
  int atlas_max;         /* atlasmax: > 0: texres becomes the largest power of two
                          * whose cloud fits one atlas_max x atlas_max atlas */
  int samples;           /* samples: quality 2: samples per texel side, 1-4 (0: 2
                          * from texres 128 up, each colour the mean of 4 texture
                          * points; else 4) */
  int outline;           /* outline: 3-10: each billboard's outline the convex hull of
                          * its opaque texels grown by a texel, at most this many
                          * corners; 0: the rectangle clipped to its faces' bounds;
                          * -1 (auto): 8 for a chain's level made for 384 pixels or
                          * more (bbc_session_run_chain), else 0 */
  int max_tris;          /* maxtris: > 0: outlines get fewer corners (4 at least) so
                          * that the cloud's triangles stay within this */
} bbc_params;

/* One row of the parameter table. */
typedef struct bbc_param_info {
  const char *name; /* Appendix A name, e.g. "epsilon" */
  bbc_param_type type;
  double min, max;         /* inclusive range */
  double default_value;    /* the toolkit's default (bbc_params_default) */
  unsigned flags;          /* BBC_PARAM_STEP3_ONLY | BBC_PARAM_KEEPS_STEP1 */
  const char *group;       /* "performance", "plane", "billboard", "output",
                            * "extension" (not in Appendix A) */
  const char *unit;        /* "%", "deg", "texels", "" */
  const char *description; /* one line */
} bbc_param_info;

/* Writes the toolkit's defaults: Appendix A's except where the fidelity
 * benchmark found better far LODs (docs/parameters.md lists both). */
void bbc_params_default(bbc_params *params);
/* Writes Appendix A's defaults exactly (the extensions off). */
void bbc_params_thesis(bbc_params *params);

/* Returns the number of parameters. */
size_t bbc_param_count(void);
/* Returns row i of the table, in Appendix A's order; i < bbc_param_count(). */
const bbc_param_info *bbc_param_at(size_t i);
/* Returns the row named `name` (case-insensitive), NULL when none is. */
const bbc_param_info *bbc_param_find(const char *name);
/* Parses `text` (a number; "on"/"off"/"true"/"false" for switches; x/y/z
 * for upaxis) and stores it in parameter `name` after the range check. On
 * error (BBC_ERROR_INVALID_ARGUMENT, BBC_ERROR_OUT_OF_RANGE) the parameter
 * is unchanged and the message names it and its allowed range. */
bbc_result bbc_params_set(bbc_params *params, const char *name, const char *text, bbc_error *err);
/* The same for "name=value". */
bbc_result bbc_params_set_assignment(bbc_params *params, const char *assignment, bbc_error *err);
/* Copies one parameter's value from `src` to `dst`. */
void bbc_params_copy(bbc_params *dst, const bbc_params *src, const bbc_param_info *info);
/* Returns a parameter's value as a double. */
double bbc_params_get(const bbc_params *params, const bbc_param_info *info);
/* Returns the first step that must run again when the parameters change
 * from `before` to `after` (Appendix A's classes): 3 when only texturing
 * ('*') parameters changed, 2 when step-2 ('+') ones did too, 1 for any
 * other, 0 when nothing that changes a result did (threads, debug and the
 * VRML format never do). `which` (may be NULL) gets the name of a
 * parameter that forces that step. */
int bbc_params_stale_step(const bbc_params *before, const bbc_params *after, const char **which);
/* Returns 1 when a cloud baked with `params` gets unlit materials (the
 * `unlit` parameter; BBC_UNLIT_WHEN_PRELIT follows `prelight`), else 0. */
int bbc_params_is_unlit(const bbc_params *params);
/* Writes the unit direction towards the prelight light (lightelev,
 * lightazim around upaxis) in the model's frame into light[3]. */
void bbc_params_get_light_direction(const bbc_params *params, double light[3]);

/* ======================================================================== */
/* 5. Steps 1 and 2: parts and planes (thesis 2.1.3-2.1.8, 2.2.4, 2.3)       */
/* ======================================================================== */

/* How faces are split into parts simplified on their own (thesis 2.2.4). */
typedef enum bbc_split_mode {
  BBC_SPLIT_AUTO = 0, /* by names where they tell, else by geometry */
  BBC_SPLIT_NONE,     /* one part, "all" */
  BBC_SPLIT_NAMES,    /* by group and material names only (trunk, bark, stem, ...
                       * against leaf, leaves, twig, foliage, needle, ...) */
  BBC_SPLIT_GEOMETRY, /* the few large connected pieces are the trunk */
  BBC_SPLIT_PATTERNS  /* the caller's patterns below */
} bbc_split_mode;

/* How bbc_split_parts splits. Zeroed: the defaults (auto, the trunk part
 * keeps only the stem, y up). */
typedef struct bbc_split_options {
  bbc_split_mode mode;
  /* BBC_SPLIT_PATTERNS: comma-separated, case-insensitive glob patterns
   * ('*', '?') matched against each face's group and material names: a
   * face matching trunk_patterns is trunk, else one matching
   * foliage_patterns is foliage, else it goes to `rest` ("trunk" or
   * "foliage"; NULL: "foliage"). */
  const char *trunk_patterns;
  const char *foliage_patterns;
  const char *rest;
  /* 0 = the trunk part keeps only the stem, followed up the up axis from
   * the trunk's base, and the branches join the foliage among whose leaves
   * they lie (the thesis's "separate the stem and the foliage plus
   * branches"); 1 = the trunk part keeps every trunk face. */
  int branches_with_trunk;
  bbc_up up; /* the up axis, for the stem */
  /* BBC_SPLIT_AUTO: 1 = a model whose names make every face trunk (a
   * leafless tree) is split by geometry instead of kept as one part. */
  int all_trunk_by_geometry;
  /* > 0: the trunk part becomes a mesh of at most this many triangles
   * (parameter `limbs`): of a trunk of several pieces the thickest that fit
   * twice that stay, the thinner join the foliage; the stem rule is not
   * applied. */
  int limbs;
} bbc_split_options;

/* Splits the faces of `mesh` into at most two parts, "trunk" then
 * "foliage", or one part "all": writes their names into names[], each
 * triangle's part into face_part[mesh->triangle_count] (may be NULL for a
 * point cloud) and their number (1 or 2) into *part_count. `why` (may be
 * NULL) receives why_size bytes at most of explanation ("names: material
 * Leaves / Trunk"). options: NULL = defaults. BBC_ERROR_INVALID_ARGUMENT
 * for a bad mode or `rest`. */
bbc_result bbc_split_parts(const bbc_mesh *mesh, const bbc_split_options *options,
                           uint32_t *face_part, size_t *part_count, char names[2][32], char *why,
                           size_t why_size, bbc_error *err);

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

/* Returns the kind's name: "standard", "coplanar", "posttweaked",
 * "cardboard", "parachute", "stem"; "unknown" for an invalid kind. */
const char *bbc_plane_kind_name(bbc_plane_kind kind);

typedef struct bbc_plane {
  double normal[3]; /* unit normal n; the plane is n . x = d */
  double d;         /* model units, in the model's own frame */
  bbc_plane_kind kind;
  uint32_t part;       /* index into bbc_planeset.parts */
  size_t face_count;   /* faces it simplifies (cardboard: the mother's faces
                        * valid for it, which stay assigned to the mother) */
  double area;         /* the sum of those faces' areas projected onto it */
  int32_t mother;      /* cardboard: index of the mother plane, else -1 */
  double coverage_pct; /* cardboard: area / the mother's area * 100, else 100 */
  int leftover;        /* 1: a plane of a sampled part's leftovers (the faces or points
                        * its sample's planes missed): its billboard draws only its
                        * own faces, whatever `pure` says */
} bbc_plane;

/* A part of a model simplified on its own (thesis 2.2.4, 3.1.1). */
typedef struct bbc_part_result {
  char name[32];      /* "trunk", "foliage", "all" or a user's name */
  double epsilon_abs; /* its error threshold, model units */
  double center[3];   /* centre of its dual grid (its centre of gravity) */
  double radius;      /* its bounding radius around that centre */
  size_t face_count;
  size_t plane_count;
  double step1_s;    /* wall-clock seconds of step 1 (grid and density) */
  double step2_s;    /* ... of step 2 (greedy select) */
  size_t grid_cells; /* cells of its dual grid */
  int limbs;         /* > 0: no planes; step 3 keeps its faces as a mesh of at most
                      * this many triangles (the trunk part with `limbs`) */
} bbc_part_result;

#define BBC_NO_PLANE UINT32_MAX /* face_plane of a face no plane simplifies */

/* The planes of a model: the result of steps 1 and 2. */
typedef struct bbc_planeset {
  double radius;      /* the whole model's bounding radius */
  double epsilon_abs; /* the largest epsilon used by any part, model units */
  size_t plane_count;
  bbc_plane *planes;    /* the parts' planes, one part after another */
  size_t face_count;    /* = the mesh's triangles (points for a point cloud) */
  uint32_t *face_plane; /* per face, in the mesh's order: the plane that
                         * simplifies it, never a cardboard plane;
                         * BBC_NO_PLANE for the faces of a part kept as a
                         * mesh (`limbs`) */
  size_t part_count;
  bbc_part_result *parts;
  uint32_t *face_part;  /* per face: index into parts */
  char split_why[320];  /* how the parts were chosen, for people */
  double epsilon_scale; /* maxplanes/minplanes: the factor every part's epsilon was
                         * multiplied by (1 = as asked) */
  int attempts;         /* runs of steps 1 and 2 (> 1 when the plane budget moved
                         * epsilon) */
  double retry_s;       /* wall-clock seconds of the discarded runs and the probes */
  int probe_runs;       /* the epsilon search's runs on a sample of the faces (1 in
                         * probe_stride): it predicts the plane count at a scale */
  int probe_stride;     /* the probes' sample: one face or point in this many of each
                         * part (0 when there were no probes) */
  double probe_s;       /* their wall-clock seconds (part of retry_s) */
  /* `pointsample`/`facesample`: steps 1 and 2 ran on one face or point in
   * sample_stride (1: every one); beyond_count faces or points were valid
   * for none of the sample's planes (the farthest beyond_max epsilon from
   * its nearest) and got leftover_planes planes of their own, the greedy
   * select's on them alone: every face or point lies within epsilon of its
   * plane, sampled or not */
  size_t sample_stride;
  size_t beyond_count;
  double beyond_max;
  size_t leftover_planes;
} bbc_planeset;

/* Releases what the set owns and zeroes it (NULL: nothing). */
void bbc_planeset_free(bbc_planeset *set);

/* What steps 1 and 2 run with. Fill with bbc_planes_options_default and
 * change from there (it holds a bbc_params: the conventions' exception);
 * NULL options mean the defaults. */
typedef struct bbc_planes_options {
  bbc_params params;          /* for every part unless overridden */
  size_t part_override_count; /* parameters per part, at most 4: */
  struct {
    char part[32]; /* "trunk", "foliage" or "all" */
    bbc_params params;
  } part_overrides[4];
  bbc_split_options split;
  bbc_callbacks callbacks;
} bbc_planes_options;

/* Writes the defaults: bbc_params_default's parameters, no overrides, the
 * default split. */
void bbc_planes_options_default(bbc_planes_options *options);
/* bbc_params_stale_step over whole options: the parameters, the per-part
 * overrides (`which` then names e.g. "trunk.epsilon", in a buffer of the
 * calling thread's own, valid until that thread's next call) and the split
 * (`which` = "split": step 1). */
int bbc_planes_options_stale_step(const bbc_planes_options *before, const bbc_planes_options *after,
                                  const char **which);

/* Steps 1 and 2: finds planes such that every face of `mesh` is simplified
 * by exactly one plane and each of its vertices lies within its part's
 * epsilon of it (epsilon in percent of the whole model's radius for every
 * part). Splits the model into parts, builds each part's dual grid with
 * the faces' density, then picks planes by the recursive greedy select
 * and its extensions (2.1.3-2.1.8, 2.3). `set` is filled (bbc_planeset_free).
 * The same input and options give identical results with any thread
 * count. BBC_ERROR_CANCELLED when the cancel callback stops it. */
bbc_result bbc_planes_find(const bbc_mesh *mesh, const bbc_planes_options *options,
                           bbc_planeset *set, bbc_error *err);

/* bbc_planes_find as two calls, so that step 2 can run again on the same
 * step 1 (Appendix A's bbc1 and bbc2), with identical results. */
typedef struct bbc_grid bbc_grid;
/* Step 1: the model split into parts, each part's faces in dual form and
 * its dual grid of plane space with the faces' density (2.1.4-2.1.7). The
 * grid keeps a copy of `options` and what it needs of the mesh; *grid is
 * freed with bbc_grid_free. */
bbc_result bbc_grid_build(const bbc_mesh *mesh, const bbc_planes_options *options, bbc_grid **grid,
                          bbc_error *err);
/* bbc_grid_build for bbc_planes_select straight after: each epsilon's
 * density is built when a whole run of step 2 needs it (a search that
 * probes and lands on another epsilon never builds the asked one's). The
 * grid views (bbc_grid_view_build) need bbc_grid_build's grid. */
bbc_result bbc_grid_build_for_select(const bbc_mesh *mesh, const bbc_planes_options *options,
                                     bbc_grid **grid, bbc_error *err);
/* The options a grid's step 1 ran with (its copy, callbacks cleared). */
const bbc_planes_options *bbc_grid_get_options(const bbc_grid *grid);
/* Copies planes options so that the copy stays valid when the caller's
 * change: the split's pattern texts into `text` (cut at 4,095 bytes), the
 * callbacks cleared. */
void bbc_planes_options_copy(bbc_planes_options *dst, char text[3][4096],
                             const bbc_planes_options *src);
/* Releases a grid (NULL: nothing). */
void bbc_grid_free(bbc_grid *grid);
/* Step 2 on a grid of step 1 (the greedy select and what follows it, on a
 * copy of the density: the grid stays whole for the next call). `options`
 * may differ from the grid's only in step-2 and step-3 parameters
 * (bbc_planes_options_stale_step != 1), else BBC_ERROR_INVALID_ARGUMENT
 * naming the parameter. When the plane budget moves epsilon, the grids at
 * the other epsilons are built into `grid` and kept too; on large models
 * the budget's tries run on a probe of one face in 4-16 (set->probe_runs)
 * and the planes returned are always a whole run's at set->epsilon_scale. */
bbc_result bbc_planes_select(bbc_grid *grid, const bbc_planes_options *options, bbc_planeset *set,
                             bbc_error *err);

/* ======================================================================== */
/* 6. Step 3: billboards and the cloud (thesis 2.1.9, 2.2.5, 2.3)            */
/* ======================================================================== */

/* The billboard of a plane (thesis 2.1.9): the minimum-area rectangle, on
 * the plane, around its faces' projected vertices (convex hull and rotating
 * calipers); a cardboard plane's surrounds its mother's faces valid for it.
 * Its points are origin + s * width * u + t * height * w, s and t in [0, 1]. */
typedef struct bbc_billboard {
  uint32_t plane;       /* index into bbc_planeset.planes */
  double origin[3];     /* corner, model coordinates */
  double u[3], w[3];    /* unit in-plane axes, u x w = the plane's normal */
  double width, height; /* extents along u and w, model units (width >= height) */
} bbc_billboard;

/* Computes one billboard per plane of `set` into
 * billboards[set->plane_count]. BBC_ERROR_INVALID_ARGUMENT when `set` was
 * not made for `mesh`. */
bbc_result bbc_billboards_compute(const bbc_mesh *mesh, const bbc_planeset *set,
                                  bbc_billboard *billboards, bbc_error *err);

/* Where an image lies in an atlas. */
typedef struct bbc_atlas_rect {
  int x, y;          /* top-left texel of the image inside the atlas */
  int width, height; /* = the image's size */
} bbc_atlas_rect;

/* Packs `count` images into one power-of-two RGBA atlas (square or 2:1)
 * with `padding` texels around each image, and dilates the colour of
 * opaque texels into the transparent ones around them (alpha stays 0) so
 * that filtering and mipmaps bleed no dark fringes. rects[count] receives
 * where each image went; `atlas` is allocated (bbc_image_free).
 * Deterministic. BBC_ERROR_OUT_OF_RANGE when the images do not fit into
 * max_size x max_size; BBC_ERROR_INVALID_ARGUMENT for missing images or
 * rects, an empty image, a negative padding, a max_size that is not a
 * power of two; count 0 gives a 1 x 1
 * transparent atlas (rects may then be NULL). */
bbc_result bbc_atlas_pack(const bbc_image *images, size_t count, int padding, int max_size,
                          bbc_image *atlas, bbc_atlas_rect *rects, bbc_error *err);

/* One billboard of a cloud. */
typedef struct bbc_cloud_billboard {
  bbc_billboard rect;         /* its plane's rectangle (2.1.9) */
  bbc_plane_kind kind;        /* its plane's kind */
  uint32_t part;              /* its plane's part */
  double normal[3];           /* the front side's normal (the plane's) */
  double d;                   /* the plane: normal . x = d */
  int tex_width, tex_height;  /* texels of each of its images */
  bbc_atlas_rect front, back; /* where its images lie in the atlas (back: all 0
                               * without back images) */
  size_t face_count;          /* faces drawn into its images */
  int corner_count;           /* its outline, 3..10 corners: the rectangle
                               * clipped to the bounds (+- epsilon) of the faces
                               * drawn, inside the model's bounding box grown by
                               * epsilon */
  double corners[10][2];      /* (s, t) in [0, 1] on the rectangle, counter-
                               * clockwise seen from the front */
} bbc_cloud_billboard;

/* A Billboard Cloud. */
typedef struct bbc_cloud {
  /* The cloud as a mesh, in the original model's frame: per billboard its
   * outline fan-triangulated, facing the front with the front image, and
   * (back images) a second copy facing the back with the back image;
   * material 0 "billboards" (single-sided with back images, else
   * double-sided), whose texture 0 is the colour atlas; with normal maps
   * its normal_map is the next texture, the normal atlas (same layout), and
   * the mesh has tangents; with `occlusion` its occlusion_map the next, the
   * occlusion atlas (same layout, grey). Transparent texels carry the
   * colour of their nearest opaque ones (alpha 0). Groups are the parts. */
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

/* Step 3: bakes the billboard of every kept plane of `set` and builds the
 * cloud. Kept: planes whose projected area is at least `polyskip` % of
 * their part's largest (2.3.5), cardboard planes with coverage of at least
 * `cbcoverage`, point-cloud planes with at least `pointskip` points. The
 * longest billboard side gets `texres` texels (or what `atlasmax`
 * chooses), the others the same texel size in a power of two (2.1.9).
 * Each image shows the faces within +-epsilon of its plane, clipped to
 * that slab (`pure` chooses which, 2.2.5), the front image as seen from
 * the front and the back image from behind (`backimages`), with `backface`
 * culling; `quality` chooses the sampling (2.3.9), `prelight` bakes the
 * light `lightelev`/`lightazim`, `shade` voxel shadowing (2.3.11), `nm`
 * normal maps in the billboard's tangent space (2.3.1, bent by `nmbend`),
 * `occlusion` an occlusion map from voxel shadowing, `stem` stem
 * billboards, `limbs` the trunk part's mesh, `refine` the alpha refined
 * against views of the original. The images are packed into one atlas.
 * `set` must have been made for `mesh`; callbacks may be NULL. The result
 * does not depend on the thread count (`threads`). */
bbc_result bbc_cloud_build(const bbc_mesh *mesh, const bbc_planeset *set, const bbc_params *params,
                           const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
/* Releases what the cloud owns and zeroes it (NULL: nothing). */
void bbc_cloud_free(bbc_cloud *cloud);

/* Puts the levels of detail of one model (clouds[count], finest first)
 * into one atlas when all their images fit into max_size x max_size:
 * every cloud's colour (and normal and occlusion) atlas becomes that atlas
 * and its texture coordinates and image rectangles move with it,
 * *shared = 1. Otherwise (or when the clouds differ in which maps they
 * carry) nothing changes and *shared = 0 (not an error). */
bbc_result bbc_clouds_share_atlas(bbc_cloud *clouds, size_t count, int max_size, int *shared,
                                  bbc_error *err);

/* Voxel shadowing (thesis 2.3.11): a grid of `voxels` cubes (1..512) along
 * the model's longest axis counts the vertices in each voxel; each voxel's
 * shadow is the count of the voxels above it (along `up`) within 40 % of
 * the bounding radius, weighted down linearly with the distance; the 95th
 * percentile of the shadowed vertices' shadows maps to `ambient`, no shadow
 * to 1. Writes one factor in [ambient, 1] per vertex into
 * shade[mesh->vertex_count]. */
bbc_result bbc_shade_vertices(const bbc_mesh *mesh, int voxels, double ambient, bbc_axis up,
                              float *shade, bbc_error *err);
/* The occupied voxels of that grid: 4 floats a voxel (its centre and its
 * light, ambient..1) in a malloc'd array at *boxes (free()), *count
 * voxels. */
bbc_result bbc_shade_voxels(const bbc_mesh *mesh, int voxels, double ambient, bbc_axis up,
                            float **boxes, size_t *count, bbc_error *err);
/* Returns the side of a voxel of that grid, model units. */
double bbc_shade_get_voxel_size(const bbc_mesh *mesh, int voxels);

/* ======================================================================== */
/* 7. Writers                                                                */
/* ======================================================================== */
/* Every writer is atomic: each file goes to a temporary file renamed over
 * its name at the end, and a failure removes what it began, so no file is
 * ever half-written. Texture files beside an output are named by
 * bbc_texture_file_name. */

/* How glTF is written: .glb (one file) or .gltf with .bin and PNG files. */
typedef enum bbc_gltf_format {
  BBC_GLTF_BY_EXTENSION = 0, /* .glb binary, else .gltf + side files */
  BBC_GLTF_BINARY,           /* .glb */
  BBC_GLTF_SEPARATE          /* .gltf + <stem>.bin + PNG textures */
} bbc_gltf_format;

/* glTF options. Zeroed: the defaults. */
typedef struct bbc_gltf_options {
  bbc_gltf_format format;
  const char *extras_json;       /* NULL, or exactly one JSON object, stored verbatim as
                                  * the asset's "extras" (anything else is
                                  * BBC_ERROR_INVALID_ARGUMENT; nothing is written) */
  int lod_chain;                 /* bbc_scene_write_gltf: 1 = the nodes are levels of
                                  * detail of one object, finest first, children of one
                                  * group node (the scene's root, named lod_group_name),
                                  * and node 0 names the coarser ones (MSFT_lod) */
  const char *lod_group_name;    /* lod_chain: the group node's name (may be NULL) */
  const double *screen_coverage; /* lod_chain: node_count decreasing values in (0, 1],
                                  * node 0's MSFT_screencoverage: level k is drawn while
                                  * the object covers more than screen_coverage[k] of
                                  * the screen's height (may be NULL) */
  int unlit;                     /* 1 = every material KHR_materials_unlit: colours shown
                                  * as they are (prelit textures) */
} bbc_gltf_options;

/* Writes `mesh` as glTF 2.0: one node, one mesh, a primitive per material
 * (baseColorFactor = base_color made linear, baseColorTexture = its texture as PNG,
 * normalTexture for a normal_map when the mesh has tangents, alphaMode MASK
 * with alphaCutoff 0.5, doubleSided unless single_sided); POSITION (float,
 * with min/max), NORMAL (renormalised) and TANGENT when present,
 * TEXCOORD_0 (v flipped to glTF's top-left origin), indices (uint16 when
 * they fit). options: NULL = defaults. */
bbc_result bbc_mesh_write_gltf(const char *path, const bbc_mesh *mesh,
                               const bbc_gltf_options *options, bbc_error *err);

/* A node of bbc_scene_write_gltf: a mesh, its name and extras (a JSON
 * object), each optional but the mesh. */
typedef struct bbc_gltf_node {
  const bbc_mesh *mesh;
  const char *name;
  const char *extras_json;
} bbc_gltf_node;

/* Writes several meshes into one glTF file, nodes[node_count], each as
 * bbc_mesh_write_gltf writes one; identical textures are stored once. */
bbc_result bbc_scene_write_gltf(const char *path, const bbc_gltf_node *nodes, size_t node_count,
                                const bbc_gltf_options *options, bbc_error *err);

/* A mesh of bbc_scene_write_fbx and its name (may be NULL). */
typedef struct bbc_fbx_node {
  const bbc_mesh *mesh;
  const char *name;
} bbc_fbx_node;

/* Writes meshes as binary FBX 7.4 (`path` ends in .fbx), for engines that
 * build LOD groups from FBX files (Unity and Unreal: meshes named
 * "<model>_LOD0", "_LOD1", ...): one Model per node with its name, its
 * Geometry (triangles; normals and texture coordinates per corner; a
 * material per triangle) and a Phong Material per material of the mesh
 * (DiffuseColor = base colour, Opacity, Shininess from the roughness as
 * Blender's importer reads it back), the colour texture linked as
 * DiffuseColor and a normal map (when the mesh has tangents) as NormalMap,
 * each a PNG beside the FBX (<stem>_fbx_<name>.png; identical images once).
 * Y up, one unit a metre. No occlusion map: FBX's materials have no slot
 * for one. Deterministic: the same meshes give the same bytes. */
bbc_result bbc_scene_write_fbx(const char *path, const bbc_fbx_node *nodes, size_t node_count,
                               bbc_error *err);

/* OBJ options. Zeroed: the defaults. */
typedef struct bbc_obj_options {
  const char *comment; /* NULL, or lines written as # comments at the top */
  int unlit;           /* 1 = every material `illum 0` (colour without lighting) */
} bbc_obj_options;

/* Writes `mesh` as Wavefront OBJ (`obj_path` ends in .obj) with an MTL of
 * the same stem and a PNG per texture; groups become `g`, materials
 * `usemtl`. options: NULL = defaults. */
bbc_result bbc_mesh_write_obj(const char *obj_path, const bbc_mesh *mesh,
                              const bbc_obj_options *options, bbc_error *err);

/* VRML options. Zeroed: the defaults. */
typedef struct bbc_vrml_options {
  bbc_vrml_format format; /* the thesis's extended VRML 2.0 (default) or VRML97 */
  int unlit;              /* 1 = no Material in any Appearance: viewers draw the
                           * textures unlit (VRML97 6.4), for prelit clouds */
  int dds;                /* 1 = an alpha-tested colour atlas is also written as
                           * <stem>_<material>.dds (bbc_image_write_dds) and named
                           * first in each url, the PNG second (VRML97 4.5.2) */
  const char *comment;    /* NULL, or lines written as # comments in the header */
} bbc_vrml_options;

/* Writes a cloud as VRML (Appendix A's "save"): `wrl_path` (ends in .wrl)
 * and beside it the colour atlas (PNG with alpha) and, with normal maps,
 * the normal atlas. One Shape per billboard side (front, and back with back
 * images): ImageTexture of the atlas, IndexedFaceSet with its outline as
 * one polygon and texture coordinates into the atlas, `solid TRUE` for
 * one-sided copies, FALSE for a double-sided one; the limbs' mesh as a last
 * Shape. BBC_VRML_EXTENDED adds, with normal maps, a `NormalMap { url
 * "<stem>_nm.png" }` node beside each Shape (declared by a no-op PROTO, so
 * VRML97 readers still parse the file). options: NULL = defaults. */
bbc_result bbc_cloud_write_vrml(const char *wrl_path, const bbc_cloud *cloud,
                                const bbc_vrml_options *options, bbc_error *err);

/* Writes a point cloud as binary little-endian PLY: x y z as doubles, red
 * green blue when it has colours. */
bbc_result bbc_points_write_ply(const char *path, const bbc_mesh *points, bbc_error *err);

/* Writes `size` bytes to `path` atomically (reports and other text outputs). */
bbc_result bbc_write_file_atomic(const char *path, const void *data, size_t size, bbc_error *err);

/* Writes the name of texture `t` of `mesh`'s files into out[out_size]:
 * "<material>" for a colour texture, "<material>_nm" for a normal map and
 * "<material>_ao" for an occlusion map, the material being the first that
 * uses it, with characters outside
 * [A-Za-z0-9_.-] replaced by '_' ("unnamed" when empty). The writers name
 * the file <stem>_<that>.png. */
void bbc_texture_file_name(const bbc_mesh *mesh, size_t t, char *out, size_t out_size);

/* ======================================================================== */
/* 8. Software rendering (no GPU): previews, baking and evaluation           */
/* ======================================================================== */

/* An orthographic camera and how it draws. The image shows the square of
 * side 2 * half_extent around `center`, seen along `direction`. Zeroed
 * optional fields are off. */
typedef struct bbc_view {
  double direction[3];   /* viewing direction, camera towards the model */
  double up[3];          /* up hint; not parallel to direction */
  double center[3];      /* model point at the image centre */
  double half_extent;    /* half the image side, model units, > 0 */
  int lighting;          /* 1 = Lambert shading, two-sided, 0.35 + 0.65 |n . l|,
                          * from `light` (else a light over the viewer's left
                          * shoulder); 0 = unlit colours */
  float point_size_px;   /* point clouds: splat width in pixels (>= 1) */
  int point_round;       /* point clouds: round splats, else squares */
  uint8_t background[4]; /* RGBA written where nothing covers a pixel */
  /* Baking (optional): */
  double half_extent_y;        /* > 0: the image shows 2 half_extent x 2 half_extent_y
                                * (independent scales in x and y) */
  double depth_min, depth_max; /* depth_max > depth_min: only surface points whose
                                * depth along `direction` from `center` lies in
                                * [depth_min, depth_max] are drawn (a slab) */
  const uint8_t *face_mask;    /* not NULL: triangle t drawn only if mask[t] */
  /* Lighting (optional): */
  double light[3];           /* not zero: with `lighting`, the direction towards a
                              * directional light, model frame */
  const float *vertex_shade; /* not NULL: a factor in [0, 1] per vertex multiplying
                              * the colour (bbc_shade_vertices) */
  double light_gain;         /* with `lighting`: multiplies the shade (0 = 1) */
  int headlight;             /* with `lighting`: the light at the camera and the
                              * shade |n . v| (no floor), as model viewers light */
  int ambient;               /* with `lighting`: adds X3D viewers' ambient light,
                              * 0.2 x mean over channels of (Ka / Kd) x Kd,
                              * untextured (Ka 0.2 when none) */
  int sun;                   /* with `lighting`: 1 = as an engine lights a lit glTF
                              * material instead: colour x (sun_ambient x occlusion
                              * + max(0, n . light)) / (sun_ambient + 1), n bent by
                              * normal maps and turned to the side seen, occlusion
                              * from occlusion maps (and vertex_shade) */
  double sun_ambient;        /* with `sun`: the ambient light, the sun's being 1 */
} bbc_view;

/* Renders `mesh` into `image`, whose size (allocated by the caller) is the
 * resolution: depth-buffered, diffuse textures (nearest texel, repeat)
 * times the base colour, alpha test at 0.5; both faces of every triangle
 * unless its material is single_sided. A pixel is covered when its centre
 * is inside a triangle (top-left rule on shared edges). Deterministic. */
bbc_result bbc_render_ortho(const bbc_mesh *mesh, const bbc_view *view, bbc_image *image,
                            bbc_error *err);
/* Writes where model point p lands in a width x height image rendered with
 * `view` into out (x right, y down, pixels). Returns 0 when the view is
 * invalid (up parallel to direction, half_extent <= 0), else 1. */
int bbc_view_project(const bbc_view *view, int width, int height, const double p[3], double out[2]);
/* Fills `view` to look at the whole mesh along `direction` with `up`:
 * its bounding box framed with a 4 % margin, lighting on, 2-pixel splats,
 * an opaque white background, the other fields zero. */
void bbc_view_frame_mesh(const bbc_mesh *mesh, const double direction[3], const double up[3],
                         bbc_view *view);

/* Measures the factor that makes `mesh`, lit by the directional light
 * `light` (unit, towards the light) with the renderer's shading
 * 0.35 + 0.65 |n . l|, as bright on average as a viewer's headlight shows
 * it (the light at the camera, shade |n . v|): the model is rendered both
 * ways at 96 pixels from 8 azimuths around `up`, at 0 and 20 degrees of
 * elevation, and *gain is the ratio of the covered pixels' summed
 * luminance. 1 for point clouds. Deterministic with any thread count. */
bbc_result bbc_light_gain_measure(const bbc_mesh *mesh, const double light[3], bbc_axis up,
                                  double *gain, bbc_error *err);

/* ======================================================================== */
/* 9. Evaluation and baselines                                               */
/* ======================================================================== */

/* How bbc_eval looks. Zeroed: the defaults. */
typedef struct bbc_eval_options {
  int views;                 /* directions evenly over the sphere (Fibonacci
                              * lattice); 0 = 64 */
  int upper;                 /* 1 = those `views` over the upper hemisphere only (seen
                              * from above or level, as people see trees; a
                              * hemi-octahedral impostor's domain) */
  int size;                  /* pixels along each view's side; 0 = 256 */
  bbc_up up;                 /* the up axis: side views, image up */
  double side_elevation_deg; /* side views: |elevation| <= this; 0 = 30 */
  int lighting;              /* 0 = unlit; 1 = both lit alike by `light`, as
                              * prelight bakes */
  double light[3];           /* towards the light, model frame; zero = +y */
  int no_ambient;            /* with lighting: 1 = without bbc_view.ambient */
  int sun;                   /* with lighting: 1 = as an engine lights a lit material
                              * (bbc_view.sun: normal and occlusion maps, ambient
                              * sun_ambient + the sun `light`), both models alike */
  double sun_ambient;        /* with sun: the ambient light, the sun's being 1; 0 = 0.4 */
  const double *directions;  /* not NULL: direction_count explicit directions (camera
                              * towards the model, 3 per view) instead of `views` */
  size_t direction_count;
  int threads;      /* 0 = all cores; results never depend on it */
  bbc_image *sheet; /* not NULL: receives (allocated) a sheet with one row
                     * per shown view: original | other | coverage
                     * difference (grey both, red original only, blue
                     * other only), labelled with the view's coverage
                     * ratio over its block IoU */
  int sheet_views;  /* rows of the sheet, spread over the views; 0 = 8 */
  /* A point cloud original is splatted as step 3 splats it: */
  double point_size;                   /* pixels of a 256-pixel picture of its bounding
                                        * sphere; 0 = 3.5 */
  int point_square;                    /* 1 = square splats; 0 = round */
  const struct bbc_impostor *impostor; /* not NULL: drawn (bbc_impostor_render) in
                                        * place of `other`, which may be NULL */
} bbc_eval_options;

/* Writes the defaults (all zero) into `options`. */
void bbc_eval_options_default(bbc_eval_options *options);

/* One view's comparison. */
typedef struct bbc_eval_view {
  double direction[3];                   /* camera towards the model */
  double elevation_deg;                  /* of the camera above the horizon */
  int side;                              /* |elevation| <= side_elevation_deg */
  size_t original_px, other_px, both_px; /* covered pixels */
  double iou;                            /* both / either */
  double recall;                         /* both / original: the original's coverage reproduced */
  double false_coverage;                 /* (other - both) / other: coverage the original lacks */
  double psnr;                           /* dB, RGB over the union of both masks (uncovered =
                                          * black), 99 for identical images */
  double mae; /* mean absolute RGB difference over the intersection, 0..255 */
  double original_rgb[3], other_rgb[3]; /* mean colour of each one's covered pixels */
  double coverage_ratio;                /* density: other_px / original_px (1 = as dense; 0 when
                                         * the original covers nothing) */
  double block_iou;                     /* density seen 8x farther: the image cut in 32 x 32
                                         * blocks, each block's covered fraction per model,
                                         * sum of min / sum of max (1 when neither covers
                                         * anything) */
  double block_luminance_error;         /* brightness seen 8x farther: per 32 x 32 block the
                                         * summed luminance of the covered pixels over the
                                         * block's area; sum |other - original| / sum original
                                         * (0 = alike) */
} bbc_eval_view;

/* All views' comparisons and their summaries (means over all views, and
 * over the side views). */
typedef struct bbc_eval_result {
  size_t view_count;
  bbc_eval_view *views; /* view_count of them, in the order of the directions */
  size_t side_count;    /* the views that are side views (bbc_eval_view.side) */
  /* Each bbc_eval_view figure of the same name: `_mean` its mean over all
   * views, `_min` its least, `_side_mean`/`_side_min` the same over the
   * side views only (0 when there are none). */
  double iou_mean, iou_min, iou_side_mean, iou_side_min;
  double recall_mean, recall_side_mean;
  double false_mean; /* of false_coverage */
  double psnr_mean, psnr_min, psnr_side_mean;
  double mae_mean;
  double coverage_ratio_mean, coverage_ratio_side_mean;
  double block_iou_mean, block_iou_side_mean;
  double brightness_ratio[3]; /* per channel: the other's mean colour over its covered
                               * pixels / the original's, over all views (1 = as bright) */
  double luminance_ratio;     /* the same for the luminance (Rec. 709 weights) */
  double block_luminance_error_mean;
} bbc_eval_result;

/* Compares how `other` (a cloud, a baseline) looks against `original`:
 * both rendered by the software rasterizer, orthographic, from the same
 * views framing both models' joint bounds in the original's frame (an
 * offset model scores worse); alpha-tested textures count as coverage,
 * single-sided materials are culled. `result` is filled
 * (bbc_eval_result_free). options: NULL = defaults. Deterministic with any
 * thread count. */
bbc_result bbc_eval(const bbc_mesh *original, const bbc_mesh *other,
                    const bbc_eval_options *options, bbc_eval_result *result, bbc_error *err);
/* Releases what the result owns and zeroes it (NULL: nothing). */
void bbc_eval_result_free(bbc_eval_result *result);
/* How well an impostor's frames show their model (issue 49): along each
 * frame's own direction, the impostor drawn on the frame's own texels
 * (bbc_impostor_render, a frame_size square) against `mesh` drawn 4 x finer
 * (bbc_render_ortho), block IoU over blocks of 8 x 8 texels (per block the
 * covered fractions, sum min / sum max; the mean over the block grid's 8
 * phases, moved 0..7 texels across and down). Per frame into per_frame[j n + i]
 * (NULL: not kept), the worst and the mean over the frames. Frames of at
 * least 8 texels. Deterministic. */
bbc_result bbc_impostor_check(const bbc_mesh *mesh, const struct bbc_impostor *impostor,
                              double *per_frame, double *worst, double *mean, bbc_error *err);
/* Writes direction k of n that bbc_eval uses (camera towards the model)
 * into dir[3]; k < n. */
void bbc_eval_get_direction(int k, int n, bbc_axis up, double dir[3]);

/* Crossed billboards, what a user would otherwise pick for a far LOD:
 * `planes` vertical planes (1..16) through the centre of the model's
 * bounding box at equal angles around the up axis (`upaxis` of `params`),
 * and a horizontal one when `horizontal`; each billboard the whole model's
 * projection onto its plane, baked by step 3's baker (`params`: back
 * images, quality, prelight, ...) at the power-of-two resolution whose
 * texel count comes closest to `texel_budget`. */
bbc_result bbc_baseline_crossed(const bbc_mesh *mesh, int planes, int horizontal,
                                const bbc_params *params, size_t texel_budget,
                                const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
/* meshoptimizer's simplification towards `target_triangles`, each material
 * and group on its own in proportion: edge collapses that keep attribute
 * seams and borders (separate leaf cards cannot go below about one quad
 * each) or, with `sloppy`, vertex clustering (reaches any target). UVs,
 * normals, materials and textures are kept, unused vertices dropped. */
bbc_result bbc_baseline_simplify(const bbc_mesh *mesh, size_t target_triangles, int sloppy,
                                 bbc_mesh *out, bbc_error *err);

/* ======================================================================== */
/* 10. Generators: a built-in tree, points on a surface, point normals       */
/* ======================================================================== */

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

/* Returns the species' name ("oak", "pine", ...), NULL for an invalid value. */
const char *bbc_tree_species_name(bbc_tree_species species);
/* Returns the species `name` names, -1 when none. */
int bbc_tree_species_from_name(const char *name);

/* What tree to grow. Zeroed: the defaults (an oak, seed 0). */
typedef struct bbc_tree_options {
  uint64_t seed;            /* the same seed and options give the same mesh */
  size_t leaves;            /* number of leaf quads; 0 = the species' default */
  bbc_tree_species species; /* BBC_TREE_OAK = 0 */
  int texture_size;         /* leaf texture edge in texels, a power of 2; 0 = 128 */
  bbc_callbacks callbacks;
} bbc_tree_options;

/* Writes the defaults (all zero) into `options`. */
void bbc_tree_options_default(bbc_tree_options *options);

/* Generates a tree in metres, y up, its base at the origin: group "trunk"
 * (material "bark", tapered tubes) and group "leaves" (material "leaf",
 * quads with a generated RGBA leaf texture whose alpha is 0 or 255).
 * options: NULL = defaults. */
bbc_result bbc_tree_generate(const bbc_tree_options *options, bbc_mesh *mesh, bbc_error *err);

/* Samples `count` points on a triangle mesh's surface, uniform by area,
 * coloured as the surface there (material colour times texture), with its
 * triangle's unit normal, the same for the same seed: a point cloud into
 * `out` (bbc_mesh_free). */
bbc_result bbc_mesh_sample_points(const bbc_mesh *mesh, size_t count, uint64_t seed, bbc_mesh *out,
                                  bbc_error *err);

/* Estimates a normal for each point of a point cloud into
 * normals[3 * mesh->vertex_count] (unit, or zero where a point has fewer
 * than 3 neighbours): the direction of least spread of the points around
 * it (principal components within a cell of a grid holding about 12
 * points). threads: 0 = all cores; the result does not depend on it. */
bbc_result bbc_points_estimate_normals(const bbc_mesh *mesh, int threads, float *normals,
                                       bbc_error *err);

/* ---- Octahedral impostors' mapping (docs/impostors.md) ----------------------
 * A unit direction (up = +y) and its place on the square [0, 1]^2 of an
 * octahedral impostor (the whole sphere) or, with `hemi`, a hemi-octahedral
 * one (the upper half; a direction below the horizon goes onto it); frames
 * on an n x n grid of the square's points, frame (i, j) at (i, j) / (n - 1). */
void bbc_octahedral_encode(const double dir[3], int hemi, double uv[2]);
/* The unit direction at uv (the inverse of bbc_octahedral_encode). */
void bbc_octahedral_decode(const double uv[2], int hemi, double dir[3]);
/* The direction frame (i, j) of an n x n grid shows (n >= 2). */
void bbc_octahedral_frame_dir(int n, int i, int j, int hemi, double dir[3]);
/* The three frames a view along `dir` blends (frame[k] = {i, j}: the grid
 * square's corners on either side of its diagonal) and their weights
 * (barycentric: >= 0, summing to 1; 1 on a frame seen along its own
 * direction). */
void bbc_octahedral_blend(const double dir[3], int n, int hemi, int frame[3][2], double weight[3]);

/* ---- Octahedral impostors (docs/impostors.md) ------------------------------
 * A model rendered from the n x n frame directions of an octahedral (or
 * hemi-octahedral) grid into two atlases, drawn as one camera-facing quad
 * that blends the three frames nearest the view. */
typedef struct bbc_impostor_options {
  int frames;       /* frames a side of the grid, 2..64; 0 = 8 */
  int full;         /* 1 = octahedral (the whole sphere); 0 = hemi-octahedral
                     * (views from above the horizon, as trees are seen) */
  long long texels; /* texels of each atlas at most, >= 4 a frame; 0 = 1,048,576 */
  int samples;      /* samples a texel side, 1..4 (coverage and colour averaged
                     * over them); 0 = 4 */
  bbc_up up;        /* the model's up axis */
  int threads;      /* 0 = all cores; never changes the result */
} bbc_impostor_options;

/* Writes the defaults (all zero) into `options`. */
void bbc_impostor_options_default(bbc_impostor_options *options);

typedef struct bbc_impostor {
  int frames;       /* n: frame (i, j) shows the model seen from
                     * bbc_impostor_frame_dir(i, j), i, j in 0..n - 1 */
  int hemi;         /* 1 = hemi-octahedral */
  int frame_size;   /* texels a frame side; frame (i, j) is the square of the
                     * atlases at column i x frame_size, row j x frame_size
                     * (rows from the top of the image) */
  int padding;      /* texels at each frame's border that the model never
                     * covers (the sphere's projection stays inside) */
  bbc_axis up;      /* the model's up axis: the mapping's +y */
  double center[3]; /* the model's bounding sphere */
  double radius;
  double half_extent; /* each frame is the square of side 2 half_extent around
                       * center, seen orthographically (radius x frame_size /
                       * (frame_size - 2 padding)) */
  bbc_image albedo;   /* RGBA: unlit colour, alpha 0 or 255 (coverage-keeping:
                       * the fraction of opaque texels that of the covered
                       * samples); transparent texels carry their frame's
                       * nearest opaque colour (for mip levels) */
  bbc_image normal;   /* RGB: the model-space unit normal n as 255 (n + 1) / 2,
                       * turned to the frame's viewer; A: the depth d of the
                       * surface along the view from the sphere's centre plane
                       * (d in [-radius, radius], nearer the viewer negative)
                       * as 255 (d / radius + 1) / 2 */
} bbc_impostor;

/* Renders `mesh` into an impostor (free with bbc_impostor_free; zeroed on
 * failure). Deterministic with any thread count. */
bbc_result bbc_impostor_build(const bbc_mesh *mesh, const bbc_impostor_options *options,
                              bbc_impostor *impostor, bbc_error *err);
/* Releases what the impostor owns and zeroes it (NULL: nothing). */
void bbc_impostor_free(bbc_impostor *impostor);
/* The unit direction from the model towards the viewer of frame (i, j),
 * in the model's frame (the mapping's +y is the impostor's up axis), and the
 * frame's image axes: right and up (unit, orthogonal to dir). */
void bbc_impostor_frame_basis(const bbc_impostor *impostor, int i, int j, double dir[3],
                              double right[3], double up[3]);
/* Frame (i, j)'s own camera: the orthographic view along -dir, up its
 * image's up, centred on the impostor's centre, half_extent its frame's
 * (the rest of `view` zero). */
void bbc_impostor_frame_view(const bbc_impostor *impostor, int i, int j, bbc_view *view);
/* Draws the impostor into `image` (allocated by the caller) as a GPU would
 * draw its quad seen with `view` (orthographic): each pixel the blend of
 * the three frames nearest the view (bbc_octahedral_blend), each frame's
 * texel where the view's ray meets the surface the frame saw (marched
 * through its depths a texel at a time, relief mapping), nearest texels of
 * the atlases (level 0: alpha tested at the base level, as bbc_render_ortho
 * tests a cloud's textures), the blended alpha tested against a 4 x 4 ordered dither (as alpha to
 * coverage; 0 or 1 along a frame's own direction), lit from the normal
 * atlas as bbc_render_ortho lights a mesh (lighting, light, light_gain,
 * headlight, sun, sun_ambient; `ambient` adds 0.2 x the colour); the
 * background where nothing covers a pixel. Deterministic. */
bbc_result bbc_impostor_render(const bbc_impostor *impostor, const bbc_view *view, bbc_image *image,
                               bbc_error *err);
/* The same from the atlases' mip level `level` (bbc_impostor_level; past
 * the last: the last), or with level -1 the level whose texels are nearest
 * a pixel's size, round(log2(frame texels a pixel)), as forest's shader
 * picks it. */
bbc_result bbc_impostor_render_level(const bbc_impostor *impostor, const bbc_view *view, int level,
                                     bbc_image *image, bbc_error *err);
/* Mip levels of an impostor, each frame filtered within its own square:
 * level l has frames of bbc_impostor_level_size(l) = max(1, frame_size >>
 * l) texels (frame (i, j) at column i x size, row j x size, as level 0), a
 * texel (x, y) standing for the level-0 texels [x S / s, (x + 1) S / s) of
 * its frame across and down (S the frame size, s the level's). Albedo: the
 * covered texels' mean colour; alpha binary, each frame's covered shares
 * kept whole down a quadtree (as many opaque texels as the shares sum to,
 * shared between quarters by their sums); normal: the covered texels' mean
 * normal (its length kept) and mean depth; where none is covered, the texels' mean colour and a
 * zero normal. Level 0 is the atlases themselves. forest uploads them all and draws the level
 * bbc_impostor_render_level(-1) picks. */
int bbc_impostor_level_count(const bbc_impostor *impostor);
int bbc_impostor_level_size(const bbc_impostor *impostor, int level);
/* Level `level` (0 .. count - 1) of the impostor's two atlases into albedo
 * and normal (allocated here; free with bbc_image_free; zeroed on failure). */
bbc_result bbc_impostor_level(const bbc_impostor *impostor, int level, bbc_image *albedo,
                              bbc_image *normal, bbc_error *err);
/* Writes the impostor's descriptor to `path` (JSON: its frames, layout,
 * bounds and the atlases' names) and its atlases beside it as
 * <stem>_albedo.png and <stem>_normal.png (the stem as for other outputs'
 * side files: "tree.json" -> "tree_json"), each atomically. */
bbc_result bbc_impostor_write(const char *path, const bbc_impostor *impostor, bbc_error *err);
/* Reads what bbc_impostor_write wrote (free with bbc_impostor_free). */
bbc_result bbc_impostor_read(const char *path, bbc_impostor *impostor, bbc_error *err);

/* ======================================================================== */
/* 11. The algorithm's internals as geometry (Appendix A `show bbc`)         */
/* ======================================================================== */

/* Coloured geometry for a viewer to draw as it is (bbcgen's viewer):
 * triangles and line segments, 6 floats a vertex (x y z r g b). */
typedef struct bbc_geometry {
  float *tris; /* 3 vertices a triangle */
  size_t tri_count;
  float *lines; /* 2 vertices a segment */
  size_t line_count;
  double center[3], radius; /* what frames it */
} bbc_geometry;
/* Releases what the geometry owns and zeroes it (NULL: nothing). */
void bbc_geometry_free(bbc_geometry *geometry);

/* The four grid views. They are drawn in a box: theta (-180..180 deg) along
 * x in [-2, 2], rho (the grid's range, from just below 0 to the part's
 * radius + epsilon) along y in [0, 2], phi (-90..90 deg) along z in
 * [1, -1]; the box's edges grey, its theta edge red, rho green, phi blue. */
typedef enum bbc_grid_view_kind {
  BBC_GRID_VIEW_DOMAIN = 0, /* the face's discretised validity domain: the cells
                             * step 1 counts it in (simple validity), light blue */
  BBC_GRID_VIEW_CONTINUOUS, /* its continuous validity domain: the exact range
                             * of rho per direction, lower sheet orange, upper
                             * sheet yellow */
  BBC_GRID_VIEW_BOTH,       /* the cells as blue edges with the sheets */
  BBC_GRID_VIEW_DENSITY     /* the grid's density (contribution minus penalty)
                             * as cubes sized and coloured by it, blue to red */
} bbc_grid_view_kind;

typedef struct bbc_grid_view_options {
  bbc_grid_view_kind kind;
  size_t part; /* index of the part (bbc_grid_get_part_count) */
  size_t face; /* the selected face: an index within the part */
  int vertex;  /* continuous views: -1 the face's domain, 0-2 (0-3 for a face of four
                * vertices) one vertex's (F6) */
  int volume;  /* continuous views: lines across the domain between its sheets (F7) */
} bbc_grid_view_options;
/* The grid at the epsilon of the planes step 2 returned last (else as
 * asked). */
bbc_result bbc_grid_view_build(const bbc_grid *grid, const bbc_grid_view_options *options,
                               bbc_geometry *out, bbc_error *err);
/* The grid's parts (as step 1 split the model), a part's name and its
 * faces' count (0 for no such part). */
size_t bbc_grid_get_part_count(const bbc_grid *grid);
const char *bbc_grid_get_part_name(const bbc_grid *grid, size_t part); /* NULL: no such part */
size_t bbc_grid_get_part_faces(const bbc_grid *grid, size_t part);
/* The mesh triangle of a part's face, -1 when there is none (a face of
 * four vertices, two coplanar triangles sharing an edge: the first). */
int64_t bbc_grid_get_face_triangle(const bbc_grid *grid, size_t part, size_t face);
/* Its vertices: 3, or 4 for two triangles taken as one face; 0 when none. */
int bbc_grid_get_face_vertex_count(const bbc_grid *grid, size_t part, size_t face);
/* The part's face of the largest area (the views' first selection). */
size_t bbc_grid_get_largest_face(const bbc_grid *grid, size_t part);
/* The part's epsilon in model units in the views' grid. */
double bbc_grid_get_epsilon(const bbc_grid *grid, size_t part);

/* The faces view: per triangle of the mesh one state, */
enum {
  BBC_FACE_DONE = 0,      /* simplified already: not drawn */
  BBC_FACE_REMAINING = 1, /* wireframe, grey */
  BBC_FACE_VALID = 2      /* valid for the current plane: solid blue */
};
/* and the selected triangle solid yellow (state NULL: all remaining). */
bbc_result bbc_faces_view_build(const bbc_mesh *mesh, const uint8_t *state, size_t selected,
                                bbc_geometry *out, bbc_error *err);
/* show model's overlays: every vertex's validity domain in model space (an
 * octahedron of radius eps: the planes valid for the vertex meet its
 * eps-ball; at most 200,000 vertices, every k-th of larger models), and
 * the shadow voxels of 2.3.11 (the occupied voxels, grey by their light). */
bbc_result bbc_vertex_domains_view_build(const bbc_mesh *mesh, double eps, bbc_geometry *out,
                                         bbc_error *err);
/* The shadow voxels of bbc_shade_voxels as boxes, grey by their light. */
bbc_result bbc_shade_view_build(const bbc_mesh *mesh, int voxels, double ambient, bbc_axis up_axis,
                                bbc_geometry *out, bbc_error *err);
/* States after step 2: the faces of the selected triangle's plane valid,
 * the others remaining (set NULL: all remaining). */
void bbc_faces_get_state(const bbc_planeset *set, size_t selected, uint8_t *state, size_t count);

#ifdef __cplusplus
}
#endif

#endif /* BBC_H */
