/* forest_sky.c — the forest's sky (a cube map from the map's six images,
 * else a gradient) and its water (one plane at the water height, reaching a
 * map's width beyond the terrain on every side). */
#include "forest_internal.h"

#include <epoxy/gl.h>

void bbcgl__forest_build_water(bbcgl_forest *f) {
  const bbc_forest_world *w = f->world;
  float e = (float)((w->width - 1) * w->spacing), h = (float)f->scene.water_height;
  float v[18] = {-e, h, -e, -e,    h, 2 * e, 2 * e, h, 2 * e,
                 -e, h, -e, 2 * e, h, 2 * e, 2 * e, h, -e};
  glCreateVertexArrays(1, &f->w_vao);
  glCreateBuffers(1, &f->w_vbo);
  glNamedBufferStorage(f->w_vbo, sizeof v, v, 0);
  glVertexArrayVertexBuffer(f->w_vao, 0, f->w_vbo, 0, 3 * sizeof(float));
  glEnableVertexArrayAttrib(f->w_vao, 0);
  glVertexArrayAttribFormat(f->w_vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->w_vao, 0, 0);
}

void bbcgl__forest_build_sky(bbcgl_forest *f) {
  glCreateVertexArrays(1, &f->sky_vao);
  if (!f->scene.sky[0]) return;
  /* FR, BK, LF, RT, UP, DN onto the cube's faces: front = -z (the
   * direction a GL camera looks by default), right = +x, up = +y. */
  static const int face_of[6] = {5, 4, 1, 0, 2, 3}; /* +X=0 -X=1 +Y=2 -Y=3 +Z=4 -Z=5 */
  int size = f->scene.sky[0]->width;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &f->cube);
  glTextureStorage2D(f->cube, 1, GL_RGBA8, size, size);
  for (int s = 0; s < 6; s++) {
    const bbc_image *im = f->scene.sky[s];
    if (!im || im->width != size || im->height != size) continue;
    glTextureSubImage3D(f->cube, 0, 0, 0, face_of[s], size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                        im->rgba);
  }
  glTextureParameteri(f->cube, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(f->cube, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(f->cube, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

/* The inverse of a 4 x 4 matrix (0 when singular). */
static void inverse4(const float m[16], float out[16]) {
  /* cofactor expansion, double precision */
  double inv[16], a[16];
  for (int i = 0; i < 16; i++) a[i] = m[i];
  inv[0] = a[5] * a[10] * a[15] - a[5] * a[11] * a[14] - a[9] * a[6] * a[15] + a[9] * a[7] * a[14] +
           a[13] * a[6] * a[11] - a[13] * a[7] * a[10];
  inv[4] = -a[4] * a[10] * a[15] + a[4] * a[11] * a[14] + a[8] * a[6] * a[15] -
           a[8] * a[7] * a[14] - a[12] * a[6] * a[11] + a[12] * a[7] * a[10];
  inv[8] = a[4] * a[9] * a[15] - a[4] * a[11] * a[13] - a[8] * a[5] * a[15] + a[8] * a[7] * a[13] +
           a[12] * a[5] * a[11] - a[12] * a[7] * a[9];
  inv[12] = -a[4] * a[9] * a[14] + a[4] * a[10] * a[13] + a[8] * a[5] * a[14] -
            a[8] * a[6] * a[13] - a[12] * a[5] * a[10] + a[12] * a[6] * a[9];
  inv[1] = -a[1] * a[10] * a[15] + a[1] * a[11] * a[14] + a[9] * a[2] * a[15] -
           a[9] * a[3] * a[14] - a[13] * a[2] * a[11] + a[13] * a[3] * a[10];
  inv[5] = a[0] * a[10] * a[15] - a[0] * a[11] * a[14] - a[8] * a[2] * a[15] + a[8] * a[3] * a[14] +
           a[12] * a[2] * a[11] - a[12] * a[3] * a[10];
  inv[9] = -a[0] * a[9] * a[15] + a[0] * a[11] * a[13] + a[8] * a[1] * a[15] - a[8] * a[3] * a[13] -
           a[12] * a[1] * a[11] + a[12] * a[3] * a[9];
  inv[13] = a[0] * a[9] * a[14] - a[0] * a[10] * a[13] - a[8] * a[1] * a[14] + a[8] * a[2] * a[13] +
            a[12] * a[1] * a[10] - a[12] * a[2] * a[9];
  inv[2] = a[1] * a[6] * a[15] - a[1] * a[7] * a[14] - a[5] * a[2] * a[15] + a[5] * a[3] * a[14] +
           a[13] * a[2] * a[7] - a[13] * a[3] * a[6];
  inv[6] = -a[0] * a[6] * a[15] + a[0] * a[7] * a[14] + a[4] * a[2] * a[15] - a[4] * a[3] * a[14] -
           a[12] * a[2] * a[7] + a[12] * a[3] * a[6];
  inv[10] = a[0] * a[5] * a[15] - a[0] * a[7] * a[13] - a[4] * a[1] * a[15] + a[4] * a[3] * a[13] +
            a[12] * a[1] * a[7] - a[12] * a[3] * a[5];
  inv[14] = -a[0] * a[5] * a[14] + a[0] * a[6] * a[13] + a[4] * a[1] * a[14] - a[4] * a[2] * a[13] -
            a[12] * a[1] * a[6] + a[12] * a[2] * a[5];
  inv[3] = -a[1] * a[6] * a[11] + a[1] * a[7] * a[10] + a[5] * a[2] * a[11] - a[5] * a[3] * a[10] -
           a[9] * a[2] * a[7] + a[9] * a[3] * a[6];
  inv[7] = a[0] * a[6] * a[11] - a[0] * a[7] * a[10] - a[4] * a[2] * a[11] + a[4] * a[3] * a[10] +
           a[8] * a[2] * a[7] - a[8] * a[3] * a[6];
  inv[11] = -a[0] * a[5] * a[11] + a[0] * a[7] * a[9] + a[4] * a[1] * a[11] - a[4] * a[3] * a[9] -
            a[8] * a[1] * a[7] + a[8] * a[3] * a[5];
  inv[15] = a[0] * a[5] * a[10] - a[0] * a[6] * a[9] - a[4] * a[1] * a[10] + a[4] * a[2] * a[9] +
            a[8] * a[1] * a[6] - a[8] * a[2] * a[5];
  double det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
  det = det != 0 ? 1.0 / det : 0;
  for (int i = 0; i < 16; i++) out[i] = (float)(inv[i] * det);
}

/* The sky at the far plane, behind everything: the view rays through the
 * inverse of the view-projection. */
void bbcgl__forest_draw_sky(bbcgl_forest *f, const bbcgl_frame *fr, bbcgl_stats *st) {
  glDisable(GL_DEPTH_TEST);
  glUseProgram(f->p_sky);
  float inv[16];
  inverse4(fr->viewproj, inv);
  glUniformMatrix4fv(glGetUniformLocation(f->p_sky, "u_inverse"), 1, GL_FALSE, inv);
  glUniform3fv(glGetUniformLocation(f->p_sky, "u_fog_colour"), 1, f->fog_colour);
  glUniform1i(glGetUniformLocation(f->p_sky, "u_has_cube"), f->cube != 0);
  glUniform1i(glGetUniformLocation(f->p_sky, "u_cube"), 2);
  if (f->cube) glBindTextureUnit(2, f->cube);
  glBindVertexArray(f->sky_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  st->draw_calls++;
}

/* The water, blended over what is drawn. */
void bbcgl__forest_draw_water(bbcgl_forest *f, const bbcgl_frame *fr, bbcgl_stats *st) {
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(f->p_water);
  glUniformMatrix4fv(glGetUniformLocation(f->p_water, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
  bbcgl__forest_set_fog(f->p_water, f, fr->eye);
  glBindVertexArray(f->w_vao);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  st->draw_calls++;
  glDisable(GL_BLEND);
}
