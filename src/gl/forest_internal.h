/* forest_internal.h — the forest renderer's state, shared by its files
 * (src/gl only): forest.c (creation, the frame), forest_terrain.c,
 * forest_sky.c (sky and water), forest_parts.c (the models' meshes and
 * textures) and forest_objects.c (drawing the objects, GPU culling). */
#ifndef BBCGL_FOREST_INTERNAL_H
#define BBCGL_FOREST_INTERNAL_H

/* An impostor's mip levels the shader knows (u_imp_lv): frames up to 32,768 texels */
#define BBCGL_IMP_LEVELS 16

#include "bbcgl.h"
#include "shader.h"

typedef struct batch {
  GLuint tex[3];     /* colour, normal and occlusion maps (units 0, 1, 2); 0 = none */
  int premultiplied; /* tex[0] is BC1: transparent texels black, colours divided by alpha */
  int texel_alpha;   /* alpha tested at the nearest texel of the nearest level: 1 a cloud's
                      * atlas, 2 a polygon model's texture past level 0; 0 filtered */
  float base[4];
  int lit;
  int single_sided;    /* the material's: back faces culled (a cloud's two sides are two quads) */
  float sway;          /* bbcgl_part_options.sway_height */
  size_t first, count; /* indices */
  int limbs;           /* bbcgen's material "limbs": a mesh, not billboards */
  uint32_t *runs;      /* naive mode: 2 per run of consecutive triangles in one
                        * plane (a billboard): first index, index count; the
                        * limbs one run */
  size_t run_count;
  const bbc_impostor *imp; /* an impostor's quad (tex: its albedo and normal atlases), or NULL */
} batch;

typedef struct part {
  size_t bucket;
  GLuint vao, vbo, ebo;
  batch *batches;
  size_t batch_count;
  size_t triangles, billboards;
} part;

typedef struct texture_entry {
  const uint8_t *key; /* the image's texels: one GL texture per image and use */
  int mipmap, map;    /* map: 0 a colour map, 1 a normal or occlusion map, 2 and 3 an
                       * impostor's albedo and normal atlases with their levels */
  GLuint tex;
  size_t bytes;      /* what the GPU holds, all levels */
  int premultiplied; /* BC1: transparent texels decode black (0, 0, 0, 0) */
  int alpha_tested;  /* the image has transparent texels */
} texture_entry;

struct bbcgl_forest {
  bbcgl_scene scene;
  const bbc_forest_world *world;
  float fog_colour[3];
  GLuint p_terrain, p_model, p_sky, p_water;
  GLint u_has, u_base, u_lit, u_maps, u_sway, u_texel_alpha; /* per-material uniforms */
  GLint u_blend, u_lod;                    /* weights from the distance (blend ranges) */
  GLint u_imp, u_imp_c, u_imp_r, u_imp_lv; /* an impostor's (impostor.glsl) */
  /* terrain */
  GLuint t_vao, t_vbo, t_ebo, t_nodes, t_height, t_colour;
  size_t t_first[5], t_count[5], t_node_capacity;
  float *t_node_data; /* 4 floats per node, grouped by quarter */
  int leaf, squares;
  /* sky, water */
  GLuint sky_vao, cube, w_vao, w_vbo;
  /* objects */
  part *parts;
  size_t part_count;
  texture_entry *textures;
  size_t texture_count;
  GLuint instances;             /* the culling's static records, then this frame's */
  size_t instance_capacity;     /* records */
  const void *statics_uploaded; /* the static records in `instances` (NULL = none yet) */
  size_t statics_count;
  GLuint indirect; /* this frame's multi-draw commands */
  uint32_t (*cmds)[5];
  size_t cmd_capacity;
  /* GPU culling (bbcgl_frame.gpu_cull), built at its first use */
  int gpu_state; /* 0 not built, 1 ready, -1 failed */
  char gpu_err[BBCGL_ERR];
  GLuint p_cull, p_cmdfill;
  GLuint g_out, g_counters, g_first, g_cmds, g_cmd_bucket;
  size_t *g_base;    /* per bucket: the first record of its region in g_out */
  size_t g_ncmd;     /* one command per part and material */
  GLuint vao_source; /* the buffer the parts' VAOs take their instances from */
  /* text */
  bbcgl__text *text;
};

/* forest.c: the fog's uniforms (fog.glsl) of program `p`. */
void bbcgl__forest_set_fog(GLuint p, const bbcgl_forest *f, const double eye[3]);

/* forest.c: the sun's uniforms (u_light towards it, u_ambient) of program `p`. */
void bbcgl__forest_set_sun(GLuint p, const bbcgl_frame *fr);

/* forest_terrain.c */
int bbcgl__forest_build_terrain(bbcgl_forest *f, char *err);
void bbcgl__forest_draw_terrain(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_terrain *t,
                                bbcgl_stats *st);

/* forest_sky.c */
void bbcgl__forest_build_water(bbcgl_forest *f);
void bbcgl__forest_build_sky(bbcgl_forest *f);
void bbcgl__forest_draw_sky(bbcgl_forest *f, const bbcgl_frame *fr, bbcgl_stats *st);
void bbcgl__forest_draw_water(bbcgl_forest *f, const bbcgl_frame *fr, bbcgl_stats *st);

/* forest_objects.c */
void bbcgl__forest_draw_objects(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_cull *c,
                                bbcgl_stats *st);

/* The first row of an impostor's level `level` in its packed atlases
 * (forest_parts.c); level = the count: their height. */
int bbcgl__impostor_level_row(const bbc_impostor *imp, int level);

#endif
