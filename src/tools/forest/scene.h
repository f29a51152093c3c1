/* scene.h — what `forest` loads for a map: the world, every model with its
 * levels of detail and components (each 3D file read once), the terrain's
 * colour with the objects' soft shadows, the culling grid and the terrain
 * quadtree. GL-free; the drawing layer gets the meshes afterwards. */
#ifndef FOREST_SCENE_H
#define FOREST_SCENE_H

#include <stdio.h>

#include "bbc_forest.h"

typedef struct scene_mesh {
  char *path;
  int lod_node; /* as bbc_load_options.lod_node */
  bbc_mesh mesh;
  size_t billboards;      /* planes of the mesh when it is a Billboard Cloud, else 0 */
  double radius;          /* farthest vertex from the model's origin */
  double height;          /* highest vertex above the model's origin (its base) */
  int relightable;        /* a material has a normal or occlusion map (a cloud made with
                           * bbcgen --lighting material): lit by the sun wherever placed */
  bbc_impostor *impostor; /* an octahedral impostor (a .json descriptor, bbcgen impostor):
                           * `mesh` its quad (corners at x, y = +-1), drawn facing the eye
                           * with the frames' blend; else NULL */
  float *occlusion;       /* per vertex, for a polygon model lit by the sun: the occlusion
                           * bbcgen bakes into its clouds' occlusion maps (occlusion 64,
                           * occlusionmin 0.75), so that the levels light alike; else NULL */
} scene_mesh;

typedef struct scene_part {
  size_t mesh; /* index into scene.meshes */
  int lit, mipmap;
} scene_part;

typedef struct scene_model {
  char *key; /* file + mipmap flag */
  char *name;
  size_t lod_count;
  double *ranges; /* 2 per level */
  double fade, shadow_radius, shadow_cutoff;
  scene_part (*parts)[2];
  int *part_count; /* per level: 1 or 2 */
  double radius;
  double height; /* level 0's first component's: what the wind bends every level over */
} scene_model;

typedef struct scene {
  char folder[4096];
  char map_name[256]; /* file name without folder and extension */
  bbc_forest_map map;
  bbc_forest_world world;
  scene_mesh *meshes;
  size_t mesh_count;
  scene_model *models;
  size_t model_count;
  uint32_t (*placement_models)[2];
  bbc_image terrain_colour;
  bbc_image sky[6];
  int has_sky;
  bbc_forest_cull *cull;
  bbc_forest_terrain terrain;
  bbc_forest_occluder occluder; /* the terrain's occlusion of cells of trees */
  double extent;                /* map size, world units */
  double far_clip;              /* world units */
  size_t triangles_loaded;
} scene;

/* Loads everything; messages (progress when `progress`, details to `log`)
 * as it goes. 0 with a message on stderr when something is wrong. */
int scene_load(scene *s, const char *map_path, FILE *log, int progress);
void scene_free(scene *s);

/* What loading a 3D file warns about (a texture missing or unreadable),
 * said with the map line that asked for the file: a bbc_callbacks.log. */
typedef struct scene_load_note {
  const char *where;
  int line;
  FILE *log; /* also written here when not NULL */
  int warnings;
} scene_load_note;
void scene_load_warning(void *user, bbc_log_level level, const char *message);

/* File names: `name` relative to `folder` (absolute names as they are;
 * "" when too long), the folder of a path ("." when none), whether a
 * regular file is there, whether a name is a 3D model by its extension
 * (else a model description file). */
void scene_join(const char *folder, const char *name, char *out, size_t n);
void scene_folder_of(const char *path, char *out, size_t n);
int scene_file_exists(const char *path);
int scene_is_model_file(const char *name);

#endif
