/* bbcgl.h — the drawing layer (OpenGL 4.5 core) that `forest` and the
 * viewer share. The only GL code in the project lives in src/gl/; the
 * library (libbbc) stays GL-free. Functions here never print or exit:
 * failures return 0 / NULL with a message in `err` (a caller's buffer of
 * BBCGL_ERR bytes). */
#ifndef BBCGL_H
#define BBCGL_H

#include <stddef.h>
#include <stdint.h>

#include "app.h"
#include "bbc_forest.h"

#define BBCGL_ERR 512

/* ---- context (context.c) ------------------------------------------------ */
typedef struct bbcgl_context bbcgl_context;

/* A context without a display (EGL, surfaceless platform: Mesa's llvmpipe
 * or a GPU driver) drawing into an offscreen width x height framebuffer. */
bbcgl_context *bbcgl_context_headless(int width, int height, char *err);
/* A window (GLFW) of width x height; `title` in its bar. */
bbcgl_context *bbcgl_context_window(int width, int height, const char *title, char *err);
void bbcgl_context_free(bbcgl_context *ctx);
/* The window (a GLFWwindow *), NULL when headless. */
void *bbcgl_context_window_handle(bbcgl_context *ctx);
/* Framebuffer size now (a window may be resized). */
void bbcgl_context_size(bbcgl_context *ctx, int *width, int *height);
/* Binds the context's framebuffer for drawing. */
void bbcgl_context_begin(bbcgl_context *ctx);
/* Shows the frame (window) or waits for it to finish (headless). */
void bbcgl_context_end(bbcgl_context *ctx);
/* The last frame's pixels, rows top first. */
int bbcgl_context_read(bbcgl_context *ctx, bbc_image *out, char *err);
/* "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe ..." */
const char *bbcgl_context_describe(bbcgl_context *ctx);
/* What the GPU did between counters_begin and counters_end, from pipeline
 * statistics queries (OpenGL 4.6 or ARB_pipeline_statistics_query; Mesa's
 * llvmpipe answers them): vertices and primitives submitted, fragment
 * shader invocations (alpha-tested fragments included). `available` 0 where
 * the driver has none. counters_end waits for the results. */
typedef struct bbcgl_counters {
  int available;
  unsigned long long vertices, primitives, fragments;
} bbcgl_counters;
void bbcgl_context_counters_begin(bbcgl_context *ctx);
void bbcgl_context_counters_end(bbcgl_context *ctx, bbcgl_counters *out);

/* ---- the forest renderer (forest.c, forest_*.c) -------------------------- */
typedef struct bbcgl_forest bbcgl_forest;

typedef struct bbcgl_scene {
  const bbc_forest_world *world;
  const bbc_image *terrain_colour; /* (width - 1) x (depth - 1): its colours and the
                                    * objects' soft shadows; the sun lights it per pixel */
  bbc_forest_wind wind;            /* the map's wind (strength 0: still) */
  int has_water;
  double water_height;
  double fog_start, fog_end; /* world units; fog_end <= fog_start = no fog */
  const bbc_image *sky[6];   /* FR, BK, LF, RT, UP, DN; NULLs = a gradient */
  size_t bucket_count;       /* (model, level) buckets of the culling */
  /* 1: textures as RGBA8 even where BC1 would do (comparisons); 0: images
   * whose alpha is binary (cloud atlases) or opaque, and their mip levels,
   * as BC1 (S3TC, an eighth of RGBA8) where the driver samples it */
  int uncompressed;
} bbcgl_scene;
/* Bytes the GPU holds for `image` (with its mip levels where `mipmap`):
 * what bbcgl_forest_add_part uploaded, 0 for an image it has not. */
size_t bbcgl_forest_texture_bytes(const bbcgl_forest *f, const bbc_image *image, int mipmap);

bbcgl_forest *bbcgl_forest_create(const bbcgl_scene *scene, char *err);
void bbcgl_forest_free(bbcgl_forest *f);

/* How a component is drawn (bbcgl_forest_add_part). */
typedef struct bbcgl_part_options {
  int lit;                      /* its materials that are not unlit are lit by the frame's sun as
                                 * bbc_forest_sun_shade says: normal maps bend the normal, the
                                 * occlusion map darkens the ambient light; unlit ones (clouds with
                                 * a baked light) are drawn as they are */
  int mipmap;                   /* mip levels that keep alpha binary */
  size_t billboards;            /* what the statistics count for it per tree (0: a polygon model) */
  float sway_height;            /* the height the wind bends the model over (model units, the same
                                 * for every level of a model); 0 = it does not sway */
  const float *occlusion;       /* per vertex, the ambient light's share where no occlusion map
                                 * says (bbc_shade_vertices, as bbcgen bakes its clouds'
                                 * occlusion maps); NULL = 1 */
  const bbc_impostor *impostor; /* not NULL: `mesh` is its quad (corners +-1, bbcgen
                                 * impostor's .json read by forest), drawn facing the eye
                                 * with the frames' blend (docs/impostors.md); it must
                                 * outlive the renderer */
} bbcgl_part_options;

/* Adds `mesh` as a component of bucket `bucket` (one level of one model):
 * its triangles by material, each image uploaded once (colour maps as BC1
 * where their alpha is binary, normal and occlusion maps as BC1 where the
 * driver samples S3TC; see bbcgl_scene.uncompressed). */
int bbcgl_forest_add_part(bbcgl_forest *f, size_t bucket, const bbc_mesh *mesh,
                          const bbcgl_part_options *options, char *err);

typedef struct bbcgl_frame {
  float viewproj[16]; /* column-major */
  double eye[3];
  int width, height;
  int wireframe;   /* F1 */
  int no_terrain;  /* F4 */
  int no_objects;  /* F5 */
  int fill_colour; /* 1: only the objects, white on black (coverage measurements) */
  int naive;       /* 1: the thesis's way, per tree, level and billboard a draw call
                    * and a texture bind (forest --naive, to measure against) */
  int gpu_cull;    /* 1: culling and levels of detail in a compute shader over every
                    * static record, drawn by indirect draws the shader fills in (the
                    * CPU's bbc_forest_cull_run is then not needed) */
  double zoom;     /* with gpu_cull: distances are divided by it (0 = 1) */
  double sun[3];   /* towards the sun (unit; bbc_forest_sun_direction): lights lit
                    * models and the terrain */
  double time;     /* seconds: the wind's clock */
} bbcgl_frame;

typedef struct bbcgl_stats {
  size_t draw_calls;    /* calls into GL that draw (a multi-draw counts once) */
  size_t draw_commands; /* the multi-draws' commands (each an instanced draw) */
  size_t texture_binds;
  size_t trees, billboards, triangles, terrain_nodes;
} bbcgl_stats;

/* Draws one frame: sky, terrain nodes, water, every bucket's instances
 * (one multi-draw per bucket, component and material: a command per static
 * range of the culling and one for its per-frame records). */
void bbcgl_forest_draw(bbcgl_forest *f, const bbcgl_frame *frame, const bbc_forest_terrain *terrain,
                       const bbc_forest_cull *cull, bbcgl_stats *stats);

/* After a frame drawn with gpu_cull: NULL when it works, else why not
 * (its shaders did not build; the objects were then not drawn). */
const char *bbcgl_forest_gpu_cull_error(const bbcgl_forest *f);

/* Lines of text over the frame (statistics, key help), top left, in a
 * built-in 5 x 7 pixel font scaled by `scale`. */
void bbcgl_forest_text(bbcgl_forest *f, int width, int height, const char *const *lines,
                       size_t line_count, int scale);

/* ---- BBCgen's viewer (viewer.c) ------------------------------------------ */
typedef struct bbcgl_viewer bbcgl_viewer;

/* Appendix A's `show model` views: the input; the input with the
 * billboards' rectangles; the cloud with them; the cloud alone. Rectangles
 * are coloured by plane kind: light blue standard, orange coplanar, pink
 * post-tweaked, green cardboard, cyan parachute, yellow stem. Then `show
 * bbc`'s five: the selected face's discretised validity domain on the
 * grid, its continuous domain, both, the grid's density, the model's faces
 * (geometry built by the library: bbc_grid_view_build, bbc_faces_view_build). */
typedef enum bbcgl_view_mode {
  BBCGL_VIEW_INPUT = 0,
  BBCGL_VIEW_RECTS,
  BBCGL_VIEW_CLOUD_RECTS,
  BBCGL_VIEW_CLOUD,
  BBCGL_VIEW_DOMAIN, /* first of show bbc's */
  BBCGL_VIEW_CONTINUOUS,
  BBCGL_VIEW_BOTH,
  BBCGL_VIEW_DENSITY,
  BBCGL_VIEW_FACES,
  BBCGL_VIEW_COUNT
} bbcgl_view_mode;
#define BBCGL_VIEW_MODEL_COUNT 4 /* show model's views come first */

typedef struct bbcgl_view {
  double yaw, pitch; /* degrees: the orbit around the model's centre */
  double zoom;       /* 1: the whole model fills the view */
  int wireframe;     /* F1 */
  int lighting;      /* F5: polygon models lit by a headlight (prelit clouds never) */
  int up_axis;       /* the model's up axis: 0 x, 1 y, 2 z */
  int mini;          /* show bbc: the mini-model in the top left corner (F3) */
  int normal_maps;   /* show model: the cloud's normal maps as colours (F3) */
  double pan[2];     /* the orbit's centre moved across the screen, in model radii */
  float background[3];
} bbcgl_view;

void bbcgl_view_default(bbcgl_view *view);
/* "input", "rects", "cloud-rects", "cloud", "domain", "continuous", "both",
 * "density", "faces"; from_name: -1 when unknown. */
const char *bbcgl_view_mode_name(bbcgl_view_mode mode);
int bbcgl_view_mode_from_name(const char *name);

/* Needs a current context (bbcgl_context_*). */
bbcgl_viewer *bbcgl_viewer_new(char *err);
void bbcgl_viewer_free(bbcgl_viewer *viewer);
/* The input model (its centre and radius frame the views). */
int bbcgl_viewer_set_model(bbcgl_viewer *viewer, const bbc_mesh *model, char *err);
/* The cloud and its rectangles (NULL: none). */
int bbcgl_viewer_set_cloud(bbcgl_viewer *viewer, const bbc_cloud *cloud, char *err);
/* show bbc's geometry: slot 0 the view's, slot 1 the mini-model; slot 2
 * show model's overlay in the model's frame (vertex domains, shadow voxels),
 * drawn with the input views (NULL: none). */
int bbcgl_viewer_set_geometry(bbcgl_viewer *viewer, int slot, const bbc_geometry *geometry,
                              char *err);
/* Lines of text on a panel at the bottom left of a width x height
 * framebuffer (the window's key help). */
void bbcgl_viewer_text(bbcgl_viewer *viewer, int width, int height, const char *const *lines,
                       size_t count);
/* Draws into the framebuffer's rectangle from (x, y) (bottom left) of
 * width x height, cleared to the view's background first. */
void bbcgl_viewer_draw(bbcgl_viewer *viewer, bbcgl_view_mode mode, const bbcgl_view *view, int x,
                       int y, int width, int height);

#endif /* BBCGL_H */
