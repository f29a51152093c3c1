/* text.c — a text overlay for the drawing layer's windows (the forest's
 * panel, the viewer's key help): a built-in 5 x 7 font, a dark panel behind
 * the lines. */
#include "shader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct bbcgl__text {
  GLuint p_text, x_vao, x_vbo, font;
  size_t x_capacity; /* vertices */
  float *x_data;
};

/* ---- the built-in 5 x 7 font ------------------------------------------- */

static const char font_chars[] = " %()+,-./0123456789:=<>ABCDEFGHIJKLMNOPQRSTUVWXYZ_[]|";
static const uint8_t font_rows[][7] = {
    {0, 0, 0, 0, 0, 0, 0},                      /* space */
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}, /* % */
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}, /* ( */
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}, /* ) */
    {0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0},       /* + */
    {0, 0, 0, 0, 0x0C, 0x04, 0x08},             /* , */
    {0, 0, 0, 0x1F, 0, 0, 0},                   /* - */
    {0, 0, 0, 0, 0, 0x0C, 0x0C},                /* . */
    {0x01, 0x01, 0x02, 0x04, 0x08, 0x10, 0x10}, /* / */
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, /* 0 */
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* 1 */
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, /* 2 */
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}, /* 3 */
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, /* 4 */
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}, /* 5 */
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, /* 6 */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}, /* 7 */
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, /* 8 */
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}, /* 9 */
    {0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0},          /* : */
    {0, 0, 0x1F, 0, 0x1F, 0, 0},                /* = */
    {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}, /* < */
    {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}, /* > */
    {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, /* A */
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}, /* B */
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}, /* C */
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}, /* D */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}, /* E */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}, /* F */
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}, /* G */
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, /* H */
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* I */
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}, /* J */
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}, /* K */
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}, /* L */
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}, /* M */
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}, /* N */
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* O */
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}, /* P */
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}, /* Q */
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}, /* R */
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}, /* S */
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* T */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* U */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}, /* V */
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}, /* W */
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}, /* X */
    {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}, /* Y */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}, /* Z */
    {0, 0, 0, 0, 0, 0, 0x1F},                   /* _ */
    {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}, /* [ */
    {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}, /* ] */
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* | */
};
#define FONT_COUNT ((int)(sizeof font_rows / sizeof font_rows[0]))

bbcgl__text *bbcgl__text_new(char *err) {
  bbcgl__text *f = calloc(1, sizeof *f);
  if (!f) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  if (!(f->p_text = bbcgl__program(bbcgl__glsl_text_vert, bbcgl__glsl_text_frag, "text", err))) {
    free(f);
    return NULL;
  }
  int w = FONT_COUNT * 6, h = 8;
  uint8_t *px = calloc((size_t)w * h, 1);
  if (px)
    for (int g = 0; g < FONT_COUNT; g++)
      for (int y = 0; y < 7; y++)
        for (int x = 0; x < 5; x++)
          if (font_rows[g][y] & (0x10 >> x)) px[y * w + g * 6 + x] = 255;
  glCreateTextures(GL_TEXTURE_2D, 1, &f->font);
  glTextureStorage2D(f->font, 1, GL_R8, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (px) glTextureSubImage2D(f->font, 0, 0, 0, w, h, GL_RED, GL_UNSIGNED_BYTE, px);
  free(px);
  glCreateVertexArrays(1, &f->x_vao);
  glCreateBuffers(1, &f->x_vbo);
  glEnableVertexArrayAttrib(f->x_vao, 0);
  glVertexArrayAttribFormat(f->x_vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(f->x_vao, 0, 0);
  return f;
}

void bbcgl__text_free(bbcgl__text *f) {
  if (!f) return;
  glDeleteProgram(f->p_text);
  glDeleteVertexArrays(1, &f->x_vao);
  glDeleteBuffers(1, &f->x_vbo);
  glDeleteTextures(1, &f->font);
  free(f->x_data);
  free(f);
}

void bbcgl__text_draw(bbcgl__text *f, int width, int height, const char *const *lines,
                      size_t line_count, int scale, int bottom) {
  if (!f || !line_count) return;
  if (scale < 1) scale = 1;
  size_t chars = 0, longest = 0;
  for (size_t i = 0; i < line_count; i++) {
    size_t l = strlen(lines[i]);
    chars += l;
    longest = l > longest ? l : longest;
  }
  size_t need = (chars + 1) * 6;
  if (need > f->x_capacity) {
    float *d = realloc(f->x_data, need * 2 * 4 * sizeof *d);
    if (!d) return;
    f->x_data = d;
    f->x_capacity = need * 2;
    glNamedBufferData(f->x_vbo, (GLsizeiptr)(f->x_capacity * 4 * sizeof(float)), NULL,
                      GL_STREAM_DRAW);
    glVertexArrayVertexBuffer(f->x_vao, 0, f->x_vbo, 0, 4 * sizeof(float));
  }
  float *v = f->x_data;
  size_t n = 0;
  float cw = 6.0f * scale, lh = 9.0f * scale, pad = 4.0f * scale;
  /* a dark panel behind the text (u < 0) */
  float bx = pad + longest * cw + pad, by = pad + line_count * lh + pad;
  float top = bottom ? (float)height - by : 0; /* the panel's top, pixels from the top */
  float panel[6][4] = {{0, top, -1, 0}, {bx, top, -1, 0},      {bx, top + by, -1, 0},
                       {0, top, -1, 0}, {bx, top + by, -1, 0}, {0, top + by, -1, 0}};
  memcpy(v, panel, sizeof panel);
  n = 6;
  for (size_t i = 0; i < line_count; i++)
    for (size_t j = 0; lines[i][j]; j++) {
      int ch = (unsigned char)lines[i][j];
      if (ch >= 'a' && ch <= 'z') ch -= 'a' - 'A';
      const char *at = ch ? strchr(font_chars, ch) : NULL;
      if (!at || ch == ' ') continue;
      int g = (int)(at - font_chars);
      float x0 = pad + j * cw, y0 = top + pad + i * lh, x1 = x0 + 6.0f * scale,
            y1 = y0 + 8.0f * scale;
      float u0 = g * 6.0f, u1 = u0 + 6.0f;
      float q[6][4] = {{x0, y0, u0, 0}, {x1, y0, u1, 0}, {x1, y1, u1, 8},
                       {x0, y0, u0, 0}, {x1, y1, u1, 8}, {x0, y1, u0, 8}};
      memcpy(v + 4 * n, q, sizeof q);
      n += 6;
    }
  glNamedBufferSubData(f->x_vbo, 0, (GLsizeiptr)(n * 4 * sizeof(float)), v);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glViewport(0, 0, width, height);
  glUseProgram(f->p_text);
  glUniform2f(glGetUniformLocation(f->p_text, "u_size"), (float)width, (float)height);
  glUniform4f(glGetUniformLocation(f->p_text, "u_colour"), 1, 1, 0.85f, 1);
  glUniform1i(glGetUniformLocation(f->p_text, "u_font"), 3);
  glBindTextureUnit(3, f->font);
  glBindVertexArray(f->x_vao);
  glDrawArrays(GL_TRIANGLES, 0, (GLsizei)n);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
}
