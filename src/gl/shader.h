/* shader.h — the drawing layer's GLSL programs (src/gl only). Failures
 * return 0 with the compiler's or linker's message in err (BBCGL_ERR). */
#ifndef BBCGL_SHADER_H
#define BBCGL_SHADER_H

#include <epoxy/gl.h>

#include "bbcgl.h"

/* A program of a vertex and a fragment shader; `name` names it in messages. */
GLuint bbcgl__program(const char *vs, const char *fs, const char *name, char *err);
/* A program of one compute shader. */
GLuint bbcgl__compute_program(const char *cs, const char *name, char *err);

#endif
