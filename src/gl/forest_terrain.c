/* forest_terrain.c — the forest's terrain (thesis 3.2): the CDLOD nodes
 * src/forest/terrain.c chose each frame, each an instance of one leaf grid
 * (or a quarter of it) whose heights the vertex shader reads from a float
 * texture, odd vertices morphed to the coarser grid with distance; the
 * colour texture has the lighting baked in. */
#include "forest_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

/* The leaf grid (its index ranges: the whole grid, then each quarter), the
 * node buffer, and the height and colour textures. */
int bbcgl__forest_build_terrain(bbcgl_forest *f, char *err) {
  const bbc_forest_world *w = f->world;
  f->squares = w->width - 1;
  f->leaf = f->squares < BBC_FOREST_TERRAIN_LEAF ? f->squares : BBC_FOREST_TERRAIN_LEAF;
  int n = f->leaf, verts = (n + 1) * (n + 1);
  float *grid = malloc((size_t)verts * 2 * sizeof *grid);
  uint32_t *idx = malloc((size_t)n * n * 6 * 2 * sizeof *idx);
  if (!grid || !idx) {
    free(grid);
    free(idx);
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  for (int z = 0; z <= n; z++)
    for (int x = 0; x <= n; x++) {
      grid[2 * (z * (n + 1) + x)] = (float)x;
      grid[2 * (z * (n + 1) + x) + 1] = (float)z;
    }
  /* index ranges: the whole grid, then its four quarters */
  size_t k = 0;
  for (int r = -1; r < 4; r++) {
    int x0 = 0, z0 = 0, len = n;
    if (r >= 0) {
      len = n / 2 ? n / 2 : 1;
      x0 = (r & 1) * len;
      z0 = (r >> 1) * len;
    }
    f->t_first[r + 1] = k;
    for (int z = z0; z < z0 + len && z < n; z++)
      for (int x = x0; x < x0 + len && x < n; x++) {
        uint32_t a = (uint32_t)(z * (n + 1) + x), b = a + 1, c = a + (uint32_t)(n + 1), d = c + 1;
        /* alternate diagonals so the mesh has no direction */
        if ((x + z) & 1) {
          uint32_t t[6] = {a, c, b, b, c, d};
          memcpy(idx + k, t, sizeof t);
        } else {
          uint32_t t[6] = {a, c, d, a, d, b};
          memcpy(idx + k, t, sizeof t);
        }
        k += 6;
      }
    f->t_count[r + 1] = k - f->t_first[r + 1];
  }
  glCreateVertexArrays(1, &f->t_vao);
  glCreateBuffers(1, &f->t_vbo);
  glCreateBuffers(1, &f->t_ebo);
  glCreateBuffers(1, &f->t_nodes);
  glNamedBufferStorage(f->t_vbo, (GLsizeiptr)verts * 2 * sizeof *grid, grid, 0);
  glNamedBufferStorage(f->t_ebo, (GLsizeiptr)k * sizeof *idx, idx, 0);
  free(grid);
  free(idx);
  glVertexArrayVertexBuffer(f->t_vao, 0, f->t_vbo, 0, 2 * sizeof(float));
  glVertexArrayElementBuffer(f->t_vao, f->t_ebo);
  glEnableVertexArrayAttrib(f->t_vao, 0);
  glVertexArrayAttribFormat(f->t_vao, 0, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->t_vao, 0, 0);
  glEnableVertexArrayAttrib(f->t_vao, 1);
  glVertexArrayAttribFormat(f->t_vao, 1, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->t_vao, 1, 1);
  glVertexArrayBindingDivisor(f->t_vao, 1, 1);
  /* heights, 32-bit float, filtered */
  glCreateTextures(GL_TEXTURE_2D, 1, &f->t_height);
  glTextureStorage2D(f->t_height, 1, GL_R32F, w->width, w->depth);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(f->t_height, 0, 0, 0, w->width, w->depth, GL_RED, GL_FLOAT, w->height);
  glTextureParameteri(f->t_height, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_height, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_height, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->t_height, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  /* colour, with the lighting baked in, mipmapped */
  const bbc_image *c = f->scene.terrain_colour;
  int levels = 1;
  while ((c->width >> levels) > 0 || (c->height >> levels) > 0) levels++;
  glCreateTextures(GL_TEXTURE_2D, 1, &f->t_colour);
  glTextureStorage2D(f->t_colour, levels, GL_RGBA8, c->width, c->height);
  glTextureSubImage2D(f->t_colour, 0, 0, 0, c->width, c->height, GL_RGBA, GL_UNSIGNED_BYTE,
                      c->rgba);
  glGenerateTextureMipmap(f->t_colour);
  glTextureParameteri(f->t_colour, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(f->t_colour, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->t_colour, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->t_colour, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  /* Anisotropic filtering keeps the ground sharp at grazing angles; not on
   * Mesa's llvmpipe (software), which can take minutes for a frame with it. */
  const char *renderer = (const char *)glGetString(GL_RENDERER);
  if (!renderer || !strstr(renderer, "llvmpipe"))
    glTextureParameterf(f->t_colour, GL_TEXTURE_MAX_ANISOTROPY, 4.0f);
  return 1;
}

/* The frame's CDLOD nodes: one instanced draw per index range. */
void bbcgl__forest_draw_terrain(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_terrain *t,
                                bbcgl_stats *st) {
  if (!t || !t->node_count) return;
  if (t->node_count > f->t_node_capacity) {
    size_t cap = t->node_count * 2;
    float *d = realloc(f->t_node_data, cap * 4 * sizeof *d);
    if (!d) return;
    f->t_node_data = d;
    f->t_node_capacity = cap;
    glNamedBufferData(f->t_nodes, (GLsizeiptr)(cap * 4 * sizeof(float)), NULL, GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(f->t_vao, 1, f->t_nodes, 0, 4 * sizeof(float));
  }
  /* grouped by index range: whole grids, then each quarter */
  size_t start[6] = {0}, fill[5];
  for (size_t i = 0; i < t->node_count; i++) start[t->nodes[i].quarter + 2]++;
  for (int r = 0; r < 5; r++) start[r + 1] += start[r];
  memcpy(fill, start, sizeof fill);
  for (size_t i = 0; i < t->node_count; i++) {
    const bbc_forest_terrain_node *n = &t->nodes[i];
    float *d = f->t_node_data + 4 * fill[n->quarter + 1]++;
    int full = n->quarter < 0 ? n->size : 2 * n->size;
    d[0] = (float)(n->x - (n->quarter < 0 ? 0 : (n->quarter & 1) * n->size));
    d[1] = (float)(n->z - (n->quarter < 0 ? 0 : (n->quarter >> 1) * n->size));
    d[2] = (float)full / (float)f->leaf;
    d[3] = (float)n->level;
  }
  glNamedBufferSubData(f->t_nodes, 0, (GLsizeiptr)(t->node_count * 4 * sizeof(float)),
                       f->t_node_data);
  GLuint p = f->p_terrain;
  glUseProgram(p);
  glUniformMatrix4fv(glGetUniformLocation(p, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
  bbcgl__forest_set_fog(p, f, fr->eye);
  glUniform1f(glGetUniformLocation(p, "u_spacing"), (float)f->world->spacing);
  glUniform1f(glGetUniformLocation(p, "u_squares"), (float)f->squares);
  float morph[48];
  for (int l = 0; l < 24; l++) {
    morph[2 * l] = (float)(l < t->levels ? t->morph_start[l] : 1e30);
    morph[2 * l + 1] = (float)(l < t->levels ? t->range[l] : 2e30);
  }
  glUniform2fv(glGetUniformLocation(p, "u_morph"), 24, morph);
  glUniform1i(glGetUniformLocation(p, "u_height"), 0);
  glUniform1i(glGetUniformLocation(p, "u_colour"), 1);
  glUniform1i(glGetUniformLocation(p, "u_flat"), fr->wireframe);
  bbcgl__forest_set_sun(p, fr);
  glBindTextureUnit(0, f->t_height);
  glBindTextureUnit(1, f->t_colour);
  st->texture_binds += 2;
  glBindVertexArray(f->t_vao);
  for (int r = 0; r < 5; r++) {
    size_t n = start[r + 1] - start[r];
    if (!n) continue;
    glDrawElementsInstancedBaseInstance(GL_TRIANGLES, (GLsizei)f->t_count[r], GL_UNSIGNED_INT,
                                        (const void *)(f->t_first[r] * sizeof(uint32_t)),
                                        (GLsizei)n, (GLuint)start[r]);
    st->draw_calls++;
    st->triangles += n * f->t_count[r] / 3;
  }
  st->terrain_nodes = t->node_count;
}
