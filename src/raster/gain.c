/* gain.c — the prelit light's gain (bbc_light_gain_measure): how bright a
 * headlight shows a model against the light bbcgen bakes with, over side
 * views, so that a prelit cloud is as bright as a lit viewer shows the
 * original. */
#include "raster.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

/* Luminance (Rec. 709) summed over the covered pixels of an image whose
 * background alpha is 0. */
static double covered_luminance(const bbc_image *img) {
  double sum = 0;
  size_t n = (size_t)img->width * img->height;
  for (size_t i = 0; i < n; i++) {
    const uint8_t *p = img->rgba + 4 * i;
    if (p[3]) sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  }
  return sum;
}

/* The views that stand for "seen from the side": 8 azimuths around up_axis,
 * 45 degrees apart, at elevations 0 and 20 degrees in turn (unit vectors,
 * towards the model). */
enum { SIDE_VIEWS = 8 };
static void side_views(int up, double views[SIDE_VIEWS][3]) {
  int ea = (up + 1) % 3, eb = (up + 2) % 3;
  for (int v = 0; v < SIDE_VIEWS; v++) {
    double el = 20.0 * (v % 2) * M_PI / 180.0, az = 2.0 * M_PI * v / SIDE_VIEWS;
    views[v][up] = -sin(el);
    views[v][ea] = -cos(el) * cos(az);
    views[v][eb] = -cos(el) * sin(az);
  }
}

bbc_result bbc_light_gain_measure(const bbc_mesh *m, const double light[3], bbc_axis up_axis,
                                  double *gain, bbc_error *err) {
  assert(m && light && gain);
  *gain = 1.0;
  if (m->kind != BBC_MESH_TRIANGLES || !m->indices || !m->triangle_count) return BBC_OK;
  /* Views: side_views (a viewer near the ground, 10 degrees on average);
   * 96 pixels. */
  enum { NV = SIDE_VIEWS, SIZE = 96 };
  int up = up_axis >= 0 && up_axis <= 2 ? up_axis : 1;
  double views[NV][3], head[NV], sun[NV];
  side_views(up, views);
  int failed = 0;
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < NV; v++) {
    double upv[3] = {0, 0, 0};
    upv[up] = 1;
    const double *dir = views[v];
    bbc_view view;
    bbc_view_frame_mesh(m, dir, upv, &view);
    view.lighting = 1;
    view.background[3] = 0;
    bbc_image img = {0};
    float *lum = malloc((size_t)SIZE * SIZE * sizeof *lum);
    head[v] = sun[v] = 0;
    if (!lum || bbc_image_alloc(&img, SIZE, SIZE) != BBC_OK) {
      free(lum);
#pragma omp atomic write
      failed = 1;
      continue;
    }
    /* One pass: the headlight into the image, the sun into lum. */
    view.headlight = 1;
    int ok = bbc__render_lit(m, &view, &img, light, lum, NULL) == BBC_OK;
    head[v] = covered_luminance(&img);
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
      if (img.rgba[4 * i + 3]) sun[v] += lum[i];
    free(lum);
    bbc_image_free(&img);
    if (!ok) {
#pragma omp atomic write
      failed = 1;
    }
  }
  if (failed) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "light gain: out of memory");
  double h = 0, s = 0;
  for (int v = 0; v < NV; v++) {
    h += head[v];
    s += sun[v];
  }
  if (s > 0 && h > 0) *gain = h / s;
  return BBC_OK;
}
