/*
 * internal.h — helpers shared by the library's source files. Not installed.
 * Every non-static symbol here starts with `bbc__` (two underscores) so it
 * never collides with a user's names or with the public API.
 */
#ifndef BBC_INTERNAL_H
#define BBC_INTERNAL_H

#ifdef _OPENMP
#include <omp.h>
#endif
#include "bbc.h"

#include <stdarg.h>
#include <stdio.h>

#if defined(__GNUC__)
#define BBC__PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define BBC__PRINTF(fmt, args)
#endif

/* The innermost loops of steps 1-3 compiled twice, for AVX2 and for any
 * x86-64, the one the processor supports chosen at load time (GCC's
 * function multi-versioning). The same results either way: C11 mode
 * contracts no multiply-add into FMA, and vectorising reorders no sum. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__) &&       \
    !defined(__SANITIZE_ADDRESS__) /* glibc: the choice is an ifunc */
#define BBC__CLONES __attribute__((target_clones("avx2", "default")))
#else
#define BBC__CLONES
#endif

/* Sets err (when not NULL) to `code` and a formatted message; returns code. */
bbc_result bbc__fail(bbc_error *err, bbc_result code, const char *fmt, ...) BBC__PRINTF(3, 4);

/* Calls the log callback, if any, with a formatted message. */
void bbc__log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...) BBC__PRINTF(3, 4);

/* Calls the progress callback, if any. */
void bbc__progress(const bbc_callbacks *cb, const char *stage, double fraction);
/* Whether the caller's cancel callback asks to stop (see bbc_callbacks). */
int bbc__cancelled(const bbc_callbacks *cb);

/* Callbacks that name what they report on: progress stages come out as
 * "<label>: <stage>" and log messages as "<label>: <message>", through the
 * caller's callbacks. For a stage that repeats (per part, per run of
 * maxplanes/minplanes, per level of detail). Calls through `out` must not
 * overlap (the library reports progress from one thread at a time). */
typedef struct bbc__label {
  bbc_callbacks outer;
  char label[96];
  char text[1200];
} bbc__label;
void bbc__label_callbacks(const bbc_callbacks *in, bbc__label *l, bbc_callbacks *out,
                          const char *fmt, ...) BBC__PRINTF(4, 5);

/* A name safe in file names and OBJ statements: [A-Za-z0-9_.-], others
 * '_'; "unnamed" when empty. */
void bbc__safe_name(const char *in, char *out, size_t n);

/* Twice triangle t's area vector (its unnormalised normal) into c[3]. */
void bbc__triangle_cross(const bbc_mesh *m, size_t t, double *c);

/* strdup that returns NULL for a NULL input. */
char *bbc__strdup(const char *s);

/* Seconds from a monotonic clock (stage timings). */
double bbc__now_s(void);

/* A copy of planes options whose split pattern texts live in `text` (the
 * caller's may change); callbacks cleared. */
void bbc__planes_options_copy(bbc_planes_options *dst, char text[3][4096],
                              const bbc_planes_options *src);
/* The eigenvector of the smallest eigenvalue of a symmetric 3 x 3 matrix
 * (cyclic Jacobi; `a` is overwritten): the normal of least spread. */
void bbc__smallest_eigenvector(double a[3][3], double out[3]);
/* The unit eigenvector of the largest eigenvalue of a symmetric 3 x 3
 * matrix by 32 steps of power iteration from `start` (deterministic); `v`
 * keeps the last good step (`start` when the matrix is zero). */
void bbc__largest_eigenvector(const double a[3][3], const double start[3], double v[3]);
/* The options a grid's step 1 ran with. */
const bbc_planes_options *bbc__grid_options(const bbc_grid *grid);

/* Checks that `path` names a readable regular file; BBC_ERROR_NOT_FOUND,
 * BBC_ERROR_NOT_A_FILE or BBC_ERROR_IO with a message otherwise. */
bbc_result bbc__check_input_file(const char *path, bbc_error *err);

/* Lower-case extension of `path` without the dot, written to ext (at most
 * ext_size bytes); "" when none. */
void bbc__path_extension(const char *path, char *ext, size_t ext_size);

/* Folder part of `path` including the trailing '/', or "" when none. */
void bbc__path_folder(const char *path, char *folder, size_t folder_size);
/* 1 when `path` is a regular file. */
int bbc__file_exists(const char *path);

/* ---- atomic output files -------------------------------------------------
 * Writes go to a temporary file in the destination folder; commit renames it
 * over the destination, abort removes it. A crash or a failed write never
 * leaves a half-written file under the final name. */
typedef struct bbc__atomic_file {
  FILE *fp;
  char *final_path;
  char *temp_path;
} bbc__atomic_file;

bbc_result bbc__atomic_open(bbc__atomic_file *af, const char *path, bbc_error *err);
/* Flushes, checks for write errors, renames. Closes in every case. */
bbc_result bbc__atomic_commit(bbc__atomic_file *af, bbc_error *err);

void bbc__atomic_abort(bbc__atomic_file *af);

/* A PNG file of the image in memory (image.c): *out from malloc. */
bbc_result bbc__png_encode(const bbc_image *image, uint8_t **out, size_t *out_size);

/* ---- deterministic random numbers (splitmix64) --------------------------- */
typedef struct bbc__rng {
  uint64_t state;
} bbc__rng;

static inline uint64_t bbc__rng_next(bbc__rng *r) {
  uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
/* Uniform in [0, 1). */
static inline double bbc__rng_uniform(bbc__rng *r) {
  return (double)(bbc__rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}
/* Uniform in [lo, hi). */
static inline double bbc__rng_range(bbc__rng *r, double lo, double hi) {
  return lo + (hi - lo) * bbc__rng_uniform(r);
}

/* ---- loaders (src/io) ---------------------------------------------------- */
bbc_result bbc__load_assimp(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                            bbc_error *err);
/* PLY (src/io/load_points.c), every .ply file: a triangle mesh when the
 * header declares `face` or `tristrips` records (polygons triangulated as
 * fans, one material "default", one group named after the file's stem), a
 * point cloud otherwise. Finishes the mesh with bbc_mesh_finalize and frees
 * it on failure; `options` may be NULL (defaults). */
/* Reads a whole file into a NUL-terminated buffer (*size bytes without
 * the NUL); free with free() (src/io/load_points.c). */
bbc_result bbc__read_whole_file(const char *path, char **data, size_t *size, bbc_error *err);

/* Run-length encoded BMP (BI_RLE8, BI_RLE4), which stb_image does not
 * read (src/io/bmp_rle.c): whether the bytes are one, and decoding. */
int bbc__is_bmp_rle(const uint8_t *data, size_t size);
bbc_result bbc__bmp_rle_decode(const uint8_t *data, size_t size, const char *name, bbc_image *image,
                               bbc_error *err);
/* The readers we own (src/io/load_vrml.c, load_ply.c, load_xyz.c), on a
 * file's bytes in memory: `buf` holds `size` bytes and a NUL after them and
 * is taken over (freed) by the call; `path` names the input in messages
 * (and, for PLY, where its textures are). PLY and XYZ finish the mesh
 * themselves; the caller finalizes a VRML mesh (bbc_mesh_load does). */
bbc_result bbc__parse_vrml(const char *path, char *buf, size_t size,
                           const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);
bbc_result bbc__parse_ply(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err);
bbc_result bbc__parse_xyz(const char *path, char *buf, size_t size, const bbc_load_options *options,
                          bbc_mesh *mesh, bbc_error *err);
/* A model Assimp reads, from memory (`name`'s extension is its format hint;
 * no other files: an OBJ's MTL, a glTF's buffers are not found). */
bbc_result bbc__load_assimp_memory(const char *name, const void *data, size_t size,
                                   const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

/* What every load ends with (src/io/load.c): the mesh finalized (when
 * `finalize`: the readers other than PLY and XYZ), freed when `r` or the
 * finishing fails, else moved near 0. Returns the result. */
bbc_result bbc__load_finish(const char *name, bbc_result r, int finalize,
                            const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);
/* Our code after Assimp on a scene the caller built (the fuzzer of our mesh
 * building, fuzz/fuzz_scene.c): materials, textures (embedded ones decoded
 * from memory), nodes, meshes, then bbc__load_finish; the scene stays the
 * caller's; `options` may not be NULL. */
struct aiScene;
bbc_result bbc__load_assimp_scene(const char *name, const struct aiScene *scene,
                                  const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err);

/* ---- baking (src/core/raster.c) ------------------------------------------
 * One rasterization of `faces` (indices into mesh triangles; all when NULL)
 * for a billboard seen along view->direction (= minus the plane's normal),
 * filling the front image (the nearest surface seen from the front, along
 * +direction) and, when `back` is not NULL, the back image (the nearest
 * seen from behind) at once, with two depth buffers. Both images are laid out
 * in the plane's frame (texel x along the camera's right, rows top first), so
 * the same texel shows the same point of the plane. The view's slab, lighting,
 * light and vertex_shade apply. Normal maps (when not NULL) receive the
 * interpolated vertex normal in the billboard's tangent space (x = right,
 * y = up, z = towards that image's viewer, flipped to face it), encoded as
 * rgb = 255 (n + 1) / 2, alpha as the colour image. `backface`: each image
 * shows only faces whose winding faces its viewer. Images must be allocated
 * width x height and cleared by the caller. */
/* A texture's mipmaps as a GPU makes them (glGenerateMipmap: each level
 * the 2x2 box average of the one before, every channel on its own, so the
 * colour of transparent texels bleeds into their opaque neighbours). */
typedef struct bbc__mips {
  int levels;       /* levels after the base image */
  bbc_image *level; /* level[k - 1]: level k, half of level k - 1 (at least 1) */
} bbc__mips;

/* mips[t] for each of the mesh's textures (a texture without an image gets
 * none); free with bbc__mips_free. */
bbc_result bbc__mips_build(const bbc_mesh *mesh, bbc__mips **mips, bbc_error *err);
void bbc__mips_free(bbc__mips *mips, size_t count);

typedef struct bbc__bake {
  int width, height;
  uint8_t *front, *back;       /* RGBA */
  uint8_t *front_nm, *back_nm; /* RGBA, may be NULL */
  int backface;
  /* Optional, per texture of the mesh: colours are read from the mip level
   * matching each triangle's texel footprint on the image (as a GPU shows
   * the texture from that distance), alpha from the base image (coverage
   * is the supersampling's business). */
  const bbc__mips *mips;
  int mip_bias; /* levels added: log2 of the pixels per cloud texel (4 samples
                 * per side: 2), so that colours are those of one texel */
  /* Optional, per triangle of the mesh: the alpha its samples get (255 when
   * NULL): `pure 2` gives a face crossing n slabs 255 / n in each. */
  const uint8_t *face_alpha;
} bbc__bake;

/* What bbc_render_ortho's alpha would show (alpha >= 128) on a size x
 * size image, 0 or 1 a pixel, without colours or depths: faster. */
bbc_result bbc__render_coverage(const bbc_mesh *mesh, const bbc_view *view, int size,
                                uint8_t *cover, bbc_error *err);
bbc_result bbc__render_bake(const bbc_mesh *mesh, const uint32_t *faces, size_t face_count,
                            const bbc_view *view, bbc__bake *bake, bbc_error *err);
/* The same for a point cloud's points (NULL: all), splatted `size_px`
 * pixels wide, round when `smooth`, coloured as scanned (else light grey);
 * the front image keeps the nearest point, the back image the farthest. */
bbc_result bbc__render_splats(const bbc_mesh *mesh, const uint32_t *points, size_t count,
                              const bbc_view *view, bbc__bake *bake, double size_px, int smooth,
                              bbc_error *err);

/* The orthographic camera of a bbc_view on a w x h image (src/core/raster.c). */
typedef struct bbc__camera {
  double r[3], u[3], f[3]; /* right, up, forward (unit) */
  double c[3];
  double scale;   /* pixels per model unit, x */
  double scale_y; /* pixels per model unit, y */
  double w2, h2;
} bbc__camera;

/* 0 when the view's up is parallel to its direction. */
int bbc__camera_setup(bbc__camera *cam, const bbc_view *view, int w, int h);

/* Screen position (x right, y down, pixels) and depth (model units along f). */
static inline void bbc__camera_project(const bbc__camera *cam, const double *p, double *s) {
  double d[3] = {p[0] - cam->c[0], p[1] - cam->c[1], p[2] - cam->c[2]};
  s[0] = cam->w2 + cam->scale * (d[0] * cam->r[0] + d[1] * cam->r[1] + d[2] * cam->r[2]);
  s[1] = cam->h2 - cam->scale_y * (d[0] * cam->u[0] + d[1] * cam->u[1] + d[2] * cam->u[2]);
  s[2] = d[0] * cam->f[0] + d[1] * cam->f[1] + d[2] * cam->f[2];
}

/* A view along `direction` (up hint `up`) centred on the box lo..hi and
 * framing its corners times `margin`; everything else zero. */
void bbc__view_frame_box(const double lo[3], const double hi[3], const double direction[3],
                         const double up[3], double margin, bbc_view *view);

/* The `threads` parameter for the parallel loops that name no thread count
 * (library functions without the parameter, called by steps 1 and 3):
 * OpenMP's default team size of the calling thread set to `threads` when
 * it is > 0, and put back by bbc__threads_restore. */
static inline int bbc__threads_use(int threads) {
#ifdef _OPENMP
  int old = omp_get_max_threads();
  if (threads > 0) omp_set_num_threads(threads);
  return old;
#else
  (void)threads;
  return 1;
#endif
}
static inline void bbc__threads_restore(int old) {
#ifdef _OPENMP
  omp_set_num_threads(old);
#else
  (void)old;
#endif
}

/* ---- step 3 internals (src/core/cloud.c) ----------------------------------- */
/* bbc_cloud_build with the billboards' rectangles given (one per plane of
 * `set`, NULL = computed as usual): baselines use it. */
bbc_result bbc__cloud_build_rects(const bbc_mesh *mesh, const bbc_planeset *set,
                                  const bbc_billboard *rects, const bbc_params *params,
                                  const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err);
/* Texels of all images for rectangles rects[n] at resolution texres. */
size_t bbc__cloud_texels(const bbc_billboard *rects, size_t n, int texres, int sides);

/* ---- the stem's billboards (src/core/stem.c) -------------------------------- */
#define BBC__STEM_MAX 8
typedef struct bbc__stem {
  size_t count;                       /* planes; 0 = no stem (no trunk part, or none found) */
  bbc_plane planes[BBC__STEM_MAX];    /* kind BBC_PLANE_STEM, part = the trunk part */
  bbc_billboard rects[BBC__STEM_MAX]; /* the stem faces' bounds on each (plane UINT32_MAX) */
  double slab[BBC__STEM_MAX];         /* half the thickness of each one's slab: all the
                                       * stem faces lie inside */
  uint8_t *face_mask;                 /* per triangle: 1 = a stem face */
  size_t face_count;
  double axis[3], base[3], base_radius; /* the axis (unit, up), base centre, radius */
} bbc__stem;

/* The trunk part's stem (the part named "trunk"): base = its faces in the
 * lowest 5 % of its height, axis = principal direction of its faces within
 * 2.5 base radii of the axis (refined twice from the up axis), and
 * `planes` planes through the axis. out->count = 0 when there is no trunk
 * part or it leans more than 60 degrees. Free with bbc__stem_free. */
bbc_result bbc__stem_find(const bbc_mesh *mesh, const bbc_planeset *set, int planes, int up_axis,
                          bbc__stem *out, bbc_error *err);
void bbc__stem_free(bbc__stem *stem);

/* ---- the trunk part as a mesh (src/core/limbs.c) ------------------------------ */
/* The faces no plane simplifies (set->face_plane BBC_NO_PLANE: the trunk
 * part with `limbs`), welded and simplified to at most `target` triangles,
 * with smooth normals, one material and one group; an empty mesh (all
 * zero) when there are none. Free with bbc_mesh_free. */
bbc_result bbc__limbs_build(const bbc_mesh *mesh, const bbc_planeset *set, int target,
                            bbc_mesh *out, bbc_error *err);

/* ---- alpha refinement (src/core/refine.c) ------------------------------------ */
/* One billboard's texels: alpha[side] nonzero = opaque (side 1 NULL: the
 * front image is seen from both sides), cand[side] nonzero = may turn
 * opaque (some sample of the original covered it; NULL = none may). */
typedef struct bbc__refine_image {
  uint8_t *alpha[2];
  const uint8_t *cand[2];
  int width, height;
} bbc__refine_image;

typedef struct bbc__refine_options {
  int views;             /* views over the sphere (0 = off) */
  int size;              /* pixels per side of each view */
  int rounds;            /* at most this many rounds (fewer when nothing changes) */
  int up_axis;           /* 0 = x, 1 = y, 2 = z */
  int threads;           /* 0 = all cores; never changes the result */
  const bbc_mesh *solid; /* opaque geometry drawn with the cloud (the limbs), or NULL */
} bbc__refine_options;

/* Refines the alpha of the billboards cb[n] (images im[n]) of a cloud of
 * `mesh` against renders of the mesh (src/core/refine.c). */
bbc_result bbc__refine_alpha(const bbc_mesh *mesh, const bbc_cloud_billboard *cb,
                             bbc__refine_image *im, size_t n, const bbc__refine_options *options,
                             bbc_error *err);

#endif /* BBC_INTERNAL_H */
