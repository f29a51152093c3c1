/* forest.c — the forest renderer (thesis 3.2 on OpenGL 4.5 core): its
 * creation and each frame: sky (forest_sky.c), terrain (forest_terrain.c:
 * CDLOD nodes from src/forest/terrain.c, heights read in the vertex shader,
 * odd vertices morphed to the coarser grid), the 3D objects the culling of
 * src/forest/cull.c chose (forest_objects.c: per (model, level, component,
 * material) one instanced draw with one texture, whatever the number of
 * trees; levels blended by screen-door dithering, so no sorting and depth
 * stays right), then water. Textures with alpha keep it binary in every mip
 * level (bbc_image_mipmaps). No allocation per frame once buffers have
 * grown. */
#include "forest_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

void bbcgl__forest_set_fog(GLuint p, const bbcgl_forest *f, const double eye[3]) {
  glProgramUniform3f(p, glGetUniformLocation(p, "u_eye"), (float)eye[0], (float)eye[1],
                     (float)eye[2]);
  glProgramUniform3fv(p, glGetUniformLocation(p, "u_fog_colour"), 1, f->fog_colour);
  glProgramUniform2f(p, glGetUniformLocation(p, "u_fog"), (float)f->scene.fog_start,
                     (float)f->scene.fog_end);
}

void bbcgl__forest_set_sun(GLuint p, const bbcgl_frame *fr) {
  double l = sqrt(fr->sun[0] * fr->sun[0] + fr->sun[1] * fr->sun[1] + fr->sun[2] * fr->sun[2]);
  double d[3] = {0, 1, 0}; /* no sun given: noon */
  for (int k = 0; k < 3 && l > 0; k++) d[k] = fr->sun[k] / l;
  glProgramUniform3f(p, glGetUniformLocation(p, "u_light"), (float)d[0], (float)d[1], (float)d[2]);
  glProgramUniform1f(p, glGetUniformLocation(p, "u_ambient"), (float)BBC_FOREST_SUN_AMBIENT);
}

bbcgl_forest *bbcgl_forest_create(const bbcgl_scene *scene, char *err) {
  bbcgl_forest *f = calloc(1, sizeof *f);
  if (!f) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  f->scene = *scene;
  f->world = scene->world;
  f->fog_colour[0] = 0.74f;
  f->fog_colour[1] = 0.81f;
  f->fog_colour[2] = 0.88f;
  if (!(f->p_terrain = bbcgl__program(bbcgl__glsl_forest_terrain_vert,
                                      bbcgl__glsl_forest_terrain_frag, "terrain", err)) ||
      !(f->p_model = bbcgl__program(bbcgl__glsl_forest_model_vert, bbcgl__glsl_forest_model_frag,
                                    "model", err)) ||
      !(f->p_sky =
            bbcgl__program(bbcgl__glsl_forest_sky_vert, bbcgl__glsl_forest_sky_frag, "sky", err)) ||
      !(f->p_water = bbcgl__program(bbcgl__glsl_forest_water_vert, bbcgl__glsl_forest_water_frag,
                                    "water", err)) ||
      !(f->text = bbcgl__text_new(err)) || !bbcgl__forest_build_terrain(f, err)) {
    bbcgl_forest_free(f);
    return NULL;
  }
  f->u_has = glGetUniformLocation(f->p_model, "u_has_tex");
  f->u_texel_alpha = glGetUniformLocation(f->p_model, "u_texel_alpha");
  f->u_base = glGetUniformLocation(f->p_model, "u_base");
  f->u_lit = glGetUniformLocation(f->p_model, "u_lit");
  f->u_maps = glGetUniformLocation(f->p_model, "u_maps");
  f->u_sway = glGetUniformLocation(f->p_model, "u_sway");
  f->u_imp = glGetUniformLocation(f->p_model, "u_imp");
  f->u_imp_c = glGetUniformLocation(f->p_model, "u_imp_c");
  f->u_imp_r = glGetUniformLocation(f->p_model, "u_imp_r");
  f->u_imp_lv = glGetUniformLocation(f->p_model, "u_imp_lv");
  f->u_blend = glGetUniformLocation(f->p_model, "u_blend");
  f->u_lod = glGetUniformLocation(f->p_model, "u_lod");
  bbcgl__forest_build_water(f);
  bbcgl__forest_build_sky(f);
  glCreateBuffers(1, &f->instances);
  glCreateBuffers(1, &f->indirect);
  return f;
}

void bbcgl_forest_free(bbcgl_forest *f) {
  if (!f) return;
  for (size_t i = 0; i < f->part_count; i++) {
    glDeleteVertexArrays(1, &f->parts[i].vao);
    glDeleteBuffers(1, &f->parts[i].vbo);
    glDeleteBuffers(1, &f->parts[i].ebo);
    for (size_t b = 0; b < f->parts[i].batch_count; b++) free(f->parts[i].batches[b].runs);
    free(f->parts[i].batches);
  }
  free(f->parts);
  for (size_t i = 0; i < f->texture_count; i++) glDeleteTextures(1, &f->textures[i].tex);
  free(f->textures);
  GLuint progs[4] = {f->p_terrain, f->p_model, f->p_sky, f->p_water};
  for (int i = 0; i < 4; i++)
    if (progs[i]) glDeleteProgram(progs[i]);
  GLuint bufs[6] = {f->t_vbo, f->t_ebo, f->t_nodes, f->w_vbo, f->instances, f->indirect};
  glDeleteBuffers(6, bufs);
  GLuint vaos[3] = {f->t_vao, f->sky_vao, f->w_vao};
  glDeleteVertexArrays(3, vaos);
  GLuint texs[3] = {f->t_height, f->t_colour, f->cube};
  glDeleteTextures(3, texs);
  free(f->t_node_data);
  bbcgl__text_free(f->text);
  free(f->cmds);
  if (f->p_cull) glDeleteProgram(f->p_cull);
  if (f->p_cmdfill) glDeleteProgram(f->p_cmdfill);
  GLuint gbufs[5] = {f->g_out, f->g_counters, f->g_first, f->g_cmds, f->g_cmd_bucket};
  for (int i = 0; i < 5; i++)
    if (gbufs[i]) glDeleteBuffers(1, &gbufs[i]);
  free(f->g_base);
  free(f);
}

void bbcgl_forest_draw(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_terrain *t,
                       const bbc_forest_cull *c, bbcgl_stats *st) {
  memset(st, 0, sizeof *st);
  glViewport(0, 0, fr->width, fr->height);
  if (fr->fill_colour)
    glClearColor(0, 0, 0, 1);
  else
    glClearColor(f->fog_colour[0], f->fog_colour[1], f->fog_colour[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  /* sky at the far plane, behind everything */
  if (!fr->wireframe && !fr->fill_colour) bbcgl__forest_draw_sky(f, fr, st);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glPolygonMode(GL_FRONT_AND_BACK, fr->wireframe ? GL_LINE : GL_FILL);
  if (!fr->no_terrain && !fr->fill_colour) bbcgl__forest_draw_terrain(f, fr, t, st);
  if (!fr->no_objects && c) bbcgl__forest_draw_objects(f, fr, c, st);
  glDisable(GL_CULL_FACE); /* single-sided materials turn it on */
  if (f->scene.has_water && !fr->no_terrain && !fr->fill_colour)
    bbcgl__forest_draw_water(f, fr, st);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

void bbcgl_forest_text(bbcgl_forest *f, int width, int height, const char *const *lines,
                       size_t line_count, int scale) {
  bbcgl__text_draw(f->text, width, height, lines, line_count, scale, 0);
}
