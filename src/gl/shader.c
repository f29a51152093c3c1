/* shader.c — compiling and linking the GLSL programs of the drawing layer. */
#include "shader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

int bbcgl__mesh_upload(const bbc_mesh *m, const float *occlusion, GLuint *vao, GLuint *vbo,
                       GLuint *ebo, size_t *first, size_t *count, float **keep_vertices,
                       uint32_t **keep_indices, char *err) {
  size_t nv = m->vertex_count, groups = m->material_count ? m->material_count : 1;
  float *v = malloc((nv ? nv : 1) * BBCGL_VERTEX_FLOATS * sizeof *v);
  uint32_t *idx = malloc((m->triangle_count ? m->triangle_count * 3 : 1) * sizeof *idx);
  if (!v || !idx) {
    free(v);
    free(idx);
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  for (size_t i = 0; i < nv; i++) {
    float *o = v + BBCGL_VERTEX_FLOATS * i;
    for (int k = 0; k < 3; k++) o[k] = (float)m->positions[3 * i + k];
    for (int k = 0; k < 3; k++) o[3 + k] = m->normals ? m->normals[3 * i + k] : (k == 1);
    o[6] = m->uvs ? m->uvs[2 * i] : 0;
    o[7] = m->uvs ? m->uvs[2 * i + 1] : 0;
    for (int k = 0; k < 4; k++)
      o[8 + k] = m->tangents ? m->tangents[4 * i + k] : (k == 0 || k == 3);
    o[12] = occlusion ? occlusion[i] : 1;
  }
  size_t k = 0;
  for (size_t mat = 0; mat < groups; mat++) {
    first[mat] = k;
    for (size_t t = 0; t < m->triangle_count; t++)
      if ((m->face_material ? m->face_material[t] : 0) == mat) {
        memcpy(idx + k, m->indices + 3 * t, 3 * sizeof *idx);
        k += 3;
      }
    count[mat] = k - first[mat];
  }
  glCreateVertexArrays(1, vao);
  glCreateBuffers(1, vbo);
  glCreateBuffers(1, ebo);
  glNamedBufferStorage(*vbo, (GLsizeiptr)((nv ? nv : 1) * BBCGL_VERTEX_FLOATS * sizeof *v), v, 0);
  glNamedBufferStorage(*ebo, (GLsizeiptr)((k ? k : 1) * sizeof *idx), idx, 0);
  glVertexArrayVertexBuffer(*vao, 0, *vbo, 0, BBCGL_VERTEX_FLOATS * sizeof(float));
  glVertexArrayElementBuffer(*vao, *ebo);
  static const int loc[5] = {0, 1, 2, 5, 6}, size[5] = {3, 3, 2, 4, 1}, off[5] = {0, 3, 6, 8, 12};
  for (int i = 0; i < 5; i++) {
    glEnableVertexArrayAttrib(*vao, (GLuint)loc[i]);
    glVertexArrayAttribFormat(*vao, (GLuint)loc[i], size[i], GL_FLOAT, GL_FALSE,
                              (GLuint)(off[i] * sizeof(float)));
    glVertexArrayAttribBinding(*vao, (GLuint)loc[i], 0);
  }
  if (keep_vertices)
    *keep_vertices = v;
  else
    free(v);
  if (keep_indices)
    *keep_indices = idx;
  else
    free(idx);
  return 1;
}
