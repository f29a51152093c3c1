/* shader.h — what the drawing layer's renderers share (src/gl only): GLSL
 * programs and mesh upload. Failures return 0 with a message in err
 * (BBCGL_ERR). */
#ifndef BBCGL_SHADER_H
#define BBCGL_SHADER_H

#include <epoxy/gl.h>

#include "bbcgl.h"

/* The GLSL sources, src/gl/shaders/NAME.STAGE.glsl as bbcgl__glsl_NAME_STAGE:
 * NUL-terminated text (includes expanded, // comments left out) that the
 * build writes into a C file (cmake/embed_shaders.cmake). */
extern const char bbcgl__glsl_forest_terrain_vert[], bbcgl__glsl_forest_terrain_frag[];
extern const char bbcgl__glsl_forest_model_vert[], bbcgl__glsl_forest_model_frag[];
extern const char bbcgl__glsl_forest_sky_vert[], bbcgl__glsl_forest_sky_frag[];
extern const char bbcgl__glsl_forest_water_vert[], bbcgl__glsl_forest_water_frag[];
extern const char bbcgl__glsl_forest_cull_comp[], bbcgl__glsl_forest_cmdfill_comp[];
extern const char bbcgl__glsl_text_vert[], bbcgl__glsl_text_frag[];
extern const char bbcgl__glsl_viewer_mesh_vert[], bbcgl__glsl_viewer_mesh_frag[];
extern const char bbcgl__glsl_viewer_line_vert[], bbcgl__glsl_viewer_line_frag[];

/* A program of a vertex and a fragment shader; `name` names it in messages. */
GLuint bbcgl__program(const char *vs, const char *fs, const char *name, char *err);
/* A program of one compute shader. */
GLuint bbcgl__compute_program(const char *cs, const char *name, char *err);

/* A mesh on the GPU: its vertices (position, normal, uv, tangent with its
 * handedness, occlusion: BBCGL_VERTEX_FLOATS floats; a mesh without
 * tangents gets (1, 0, 0, 1), without `occlusion` (one per vertex, may be
 * NULL) 1) and its triangles grouped by material, materials in order, in
 * new buffers vbo and ebo with a VAO whose attributes 0, 1, 2, 5 and 6 read
 * them from binding 0.
 * first[g], count[g]: each material's indices (one group when the mesh has
 * no materials; arrays of that many). keep_vertices / keep_indices (may be
 * NULL) get the packed arrays, the caller's to free. */
#define BBCGL_VERTEX_FLOATS 13
int bbcgl__mesh_upload(const bbc_mesh *mesh, const float *occlusion, GLuint *vao, GLuint *vbo,
                       GLuint *ebo, size_t *first, size_t *count, float **keep_vertices,
                       uint32_t **keep_indices, char *err);

/* A text overlay (text.c): lines in a 5 x 7 font on a dark panel, at the
 * top left of a width x height framebuffer (bottom: at the bottom left),
 * `scale` pixels a font pixel. Lower case is drawn upper case; characters
 * outside the font are left out. */
typedef struct bbcgl__text bbcgl__text;
bbcgl__text *bbcgl__text_new(char *err);
void bbcgl__text_free(bbcgl__text *text);
void bbcgl__text_draw(bbcgl__text *text, int width, int height, const char *const *lines,
                      size_t line_count, int scale, int bottom);

#endif
