/* shader.c — compiling and linking the GLSL programs of the drawing layer. */
#include "shader.h"

#include <stdio.h>

static GLuint compile(GLenum type, const char *src, const char *name, char *err) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, NULL);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[400];
    glGetShaderInfoLog(s, sizeof log, NULL, log);
    snprintf(err, BBCGL_ERR, "shader %s does not compile: %s", name, log);
    glDeleteShader(s);
    return 0;
  }
  return s;
}

/* Links the shaders (0 ends the list; each deleted after) into a program. */
static GLuint link(const GLuint *shaders, const char *name, char *err) {
  GLuint p = glCreateProgram();
  for (const GLuint *s = shaders; *s; s++) glAttachShader(p, *s);
  glLinkProgram(p);
  for (const GLuint *s = shaders; *s; s++) glDeleteShader(*s);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[400];
    glGetProgramInfoLog(p, sizeof log, NULL, log);
    snprintf(err, BBCGL_ERR, "shader %s does not link: %s", name, log);
    glDeleteProgram(p);
    return 0;
  }
  return p;
}

GLuint bbcgl__compute_program(const char *cs, const char *name, char *err) {
  GLuint c[2] = {compile(GL_COMPUTE_SHADER, cs, name, err), 0};
  return c[0] ? link(c, name, err) : 0;
}

GLuint bbcgl__program(const char *vs, const char *fs, const char *name, char *err) {
  GLuint v = compile(GL_VERTEX_SHADER, vs, name, err);
  if (!v) return 0;
  GLuint f = compile(GL_FRAGMENT_SHADER, fs, name, err);
  if (!f) {
    glDeleteShader(v);
    return 0;
  }
  GLuint sh[3] = {v, f, 0};
  return link(sh, name, err);
}
