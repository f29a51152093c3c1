/* obj_reader.h — our OBJ reader's model (load_obj.c parses the file into
 * it, obj_scene.c builds from it the scene Assimp would hand over);
 * internal to src/io. */
#ifndef BBC_OBJ_READER_H
#define BBC_OBJ_READER_H

#include <stddef.h>
#include <stdint.h>

#include "io.h"

enum { NO_MATERIAL = -1, NAME_MAX_LEN = 1000 };

typedef struct obj_material {
  char *name;
  float ambient[3], diffuse[3], alpha, shininess;
  int illum;
  char *texture; /* map_Kd */
} obj_material;

typedef struct obj_mesh {
  int material; /* NO_MATERIAL until a usemtl or the object's creation sets it */
  int has_normals;
  size_t uv_refs, faces, segments; /* faces: lines included; segments: the lines' */
} obj_mesh;

typedef struct obj_object {
  char *name;
  uint32_t *meshes;
  size_t n, cap;
} obj_object;

/* A growing array of `elem`-byte items. */
typedef struct vec {
  void *p;
  size_t n, cap, elem;
} vec;

typedef struct obj_reader {
  const char *path;
  vec v, vt, vn;    /* floats: 3 a position, 3 a texture coordinate (z 0 when 2D), 3 a normal */
  vec corners;      /* int32: v, vt, vn (-1: none) a corner, indices 0-based */
  vec face_mesh;    /* uint32 a face: its mesh */
  vec face_corners; /* uint8 a face: 3 or 4 corners; a line (`l`): 2 to 255 vertices */
  vec face_line;    /* uint8 a face: 1 for a line */
  vec meshes;       /* obj_mesh */
  vec objects;      /* obj_object */
  vec materials;    /* obj_material; [0] Assimp's DefaultMaterial */
  int current_object, current_mesh, current_material; /* -1: none */
  char *active_group;
  int defer; /* beyond the subset: Assimp reads the file */
  int oom;
} obj_reader;

struct aiScene;
/* The scene of the model read: a root node, a child node an object (its
 * meshes: lines, then triangles), the materials in the library's order.
 * NULL with R->defer (Assimp's to read) or R->oom. */
struct aiScene *bbc__obj_make_scene(obj_reader *R);
void bbc__obj_free_scene(struct aiScene *sc);

#endif
