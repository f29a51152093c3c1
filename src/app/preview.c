/* preview.c — the preview sheet of bbcgen --preview: the original lit as
 * the textures were baked, the cloud (a row per level of a chain), and the
 * billboards' outlines over the faded original, from four sides. */
#include "session.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef app_level job_lod;

static void put_px(bbc_image *im, int x, int y, const uint8_t *rgb) {
  if (x < 0 || y < 0 || x >= im->width || y >= im->height) return;
  uint8_t *p = im->rgba + 4 * ((size_t)y * im->width + x);
  memcpy(p, rgb, 3);
  p[3] = 255;
}

static void draw_line(bbc_image *im, double x0, double y0, double x1, double y1,
                      const uint8_t *rgb) {
  double dx = x1 - x0, dy = y1 - y0;
  int steps = (int)ceil(fmax(fabs(dx), fabs(dy)));
  if (steps > 100000) steps = 100000;
  for (int i = 0; i <= steps; i++) {
    double t = steps ? (double)i / steps : 0;
    int x = (int)floor(x0 + t * dx), y = (int)floor(y0 + t * dy);
    put_px(im, x, y, rgb);
    put_px(im, x + 1, y, rgb);
    put_px(im, x, y + 1, rgb);
  }
}

/* The thesis's colour code (Fig. 2-33 ff.). */
static const uint8_t k_kind_rgb[BBC_PLANE_KIND_COUNT][3] = {
    {120, 190, 255}, /* standard: light blue */
    {255, 150, 20},  /* coplanar: orange */
    {255, 120, 200}, /* post-tweaked: pink */
    {40, 220, 60},   /* cardboard: green */
    {0, 255, 255},   /* parachute: cyan */
    {255, 230, 40},  /* stem: yellow */
};

bbc_result bbc_session_write_preview(const bbc_session *s, const char *out, int cell,
                                     bbc_error *err) {
  if (!s->have_cloud)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "no Billboard Cloud to preview: run step 3");
  if (cell < 16 || cell > 4096)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT,
                         "preview cells of 16 to 4096 pixels, not %d", cell);
  const bbc_mesh *m = &s->model;
  const job_lod *L = &s->level0;
  int up = L->params.up_axis;
  /* Front, side, above, and from 35 degrees up between front and side. */
  double dirs[4][3], ups[4][3];
  int a = (up + 1) % 3, b = (up + 2) % 3; /* (a, b, up) right-handed */
  for (int v = 0; v < 4; v++)
    for (int k = 0; k < 3; k++) dirs[v][k] = ups[v][k] = 0;
  dirs[0][b] = -1;
  dirs[1][a] = -1;
  dirs[2][up] = -1;
  double e = 35 * 3.14159265358979323846 / 180;
  dirs[3][a] = -cos(e) * sqrt(0.5);
  dirs[3][b] = -cos(e) * sqrt(0.5);
  dirs[3][up] = -sin(e);
  ups[0][up] = ups[1][up] = ups[3][up] = 1;
  ups[2][b] = -1;
  /* rows: the original, each level's cloud, level 0's outlines */
  size_t levels = bbc_session_get_level_count(s);
  int rows = 2 + (int)levels, outline_row = rows - 1;
  bbc_image sheet, img;
  if (bbc_image_alloc(&sheet, 4 * cell, rows * cell) != BBC_OK ||
      bbc_image_alloc(&img, cell, cell) != BBC_OK) {
    bbc_image_free(&sheet);
    return bbc_error_set(err, BBC_ERROR_OUT_OF_MEMORY, "preview: out of memory");
  }
  float *shade = NULL;
  if (L->params.shade_voxels > 0) {
    shade = malloc(m->vertex_count * sizeof *shade);
    bbc_error ignored;
    if (shade && bbc_shade_vertices(m, L->params.shade_voxels, L->params.shade_ambient, up, shade,
                                    &ignored) != BBC_OK) {
      free(shade);
      shade = NULL;
    }
  }
  double light[3], gain = 1.0;
  bbc_params_get_light_direction(&L->params, light);
  bbc_result rc = BBC_OK;
  if (L->params.prelight) rc = bbc_light_gain_measure(m, light, L->params.up_axis, &gain, err);
  for (int v = 0; v < 4 && rc == BBC_OK; v++) {
    for (int row = 0; row < rows && rc == BBC_OK; row++) {
      int cloud_row = row >= 1 && row < outline_row;
      const job_lod *lv = cloud_row ? app_session_level((bbc_session *)s, (size_t)row - 1) : L;
      bbc_view view;
      bbc_view_frame_mesh(m, dirs[v], ups[v], &view);
      /* The original lit as the textures were baked; the cloud unlit (its
       * textures carry the light). A material (no baked light): both lit
       * alike by the lightelev/lightazim sun, as an engine lights them. */
      int material = !L->params.prelight && !bbc_params_is_unlit(&L->params);
      view.lighting = material || (!cloud_row && L->params.prelight);
      view.sun = material;
      view.sun_ambient = 0.4;
      view.light_gain = gain;
      view.ambient = L->params.viewer_ambient;
      memcpy(view.light, light, sizeof light);
      view.vertex_shade = cloud_row ? NULL : shade;
      if (row == outline_row) view.background[0] = view.background[1] = view.background[2] = 40;
      const bbc_mesh *what = cloud_row ? &lv->cloud.mesh : m;
      if ((rc = bbc_render_ortho(what, &view, &img, err)) != BBC_OK) break;
      if (row == outline_row) {
        /* The original faded into the background, the billboards' outlines
         * on top, coloured by kind. */
        for (size_t i = 0; i < (size_t)cell * cell; i++)
          for (int k = 0; k < 3; k++)
            img.rgba[4 * i + k] = (uint8_t)(40 + (img.rgba[4 * i + k] - 40) * 45 / 100);
        for (size_t q = 0; q < L->cloud.billboard_count; q++) {
          const bbc_cloud_billboard *cb = &L->cloud.billboards[q];
          const uint8_t *rgb = k_kind_rgb[cb->kind < BBC_PLANE_KIND_COUNT ? cb->kind : 0];
          double prev[2] = {0, 0}, first[2] = {0, 0};
          for (int cc = 0; cc <= cb->corner_count; cc++) {
            const double *st = cb->corners[cc % cb->corner_count];
            double p[3], sc[2];
            for (int k = 0; k < 3; k++)
              p[k] = cb->rect.origin[k] + st[0] * cb->rect.width * cb->rect.u[k] +
                     st[1] * cb->rect.height * cb->rect.w[k];
            bbc_view_project(&view, cell, cell, p, sc);
            if (cc == 0)
              memcpy(first, sc, sizeof sc);
            else
              draw_line(&img, prev[0], prev[1], sc[0], sc[1], rgb);
            memcpy(prev, sc, sizeof sc);
          }
          (void)first;
        }
      }
      for (int y = 0; y < cell; y++)
        memcpy(sheet.rgba + 4 * ((size_t)(row * cell + y) * sheet.width + (size_t)v * cell),
               img.rgba + 4 * (size_t)y * cell, 4 * (size_t)cell);
    }
  }
  free(shade);
  bbc_image_free(&img);
  if (rc == BBC_OK) rc = bbc_image_write_png(out, &sheet, err);
  bbc_image_free(&sheet);
  return rc;
}
