/* view.c — framing an orthographic view: a box or a mesh seen along a
 * direction, and where a point lands on the image. */
#include "raster.h"
#include "vec3.h"

#include <assert.h>
#include <math.h>
#include <string.h>

typedef bbc__camera camera;

int bbc_view_project(const bbc_view *view, int width, int height, const double p[3],
                     double out[2]) {
  assert(view && p && out);
  camera cam;
  if (width <= 0 || height <= 0 || !(view->half_extent > 0) ||
      !bbc__camera_setup(&cam, view, width, height))
    return 0;
  double s[3];
  bbc__camera_project(&cam, p, s);
  out[0] = s[0];
  out[1] = s[1];
  return 1;
}

void bbc__view_frame_box(const double lo[3], const double hi[3], const double direction[3],
                         const double up[3], double margin, bbc_view *v) {
  memset(v, 0, sizeof *v);
  memcpy(v->direction, direction, sizeof v->direction);
  memcpy(v->up, up, sizeof v->up);
  /* Frame the box as seen along the view: the largest extent of its
   * corners on the image axes, times the margin. */
  for (int k = 0; k < 3; k++) v->center[k] = 0.5 * (lo[k] + hi[k]);
  double f[3] = {direction[0], direction[1], direction[2]}, r[3], u[3];
  vstore(f, vnormalize(vload(f)));
  vstore(r, vcross(vload(f), vload(up)));
  vstore(r, vnormalize(vload(r)));
  vstore(u, vcross(vload(r), vload(f)));
  double half = 0;
  for (int c = 0; c < 8; c++) {
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = ((c >> k) & 1 ? hi[k] : lo[k]) - v->center[k];
    double x = fabs(d[0] * r[0] + d[1] * r[1] + d[2] * r[2]);
    double y = fabs(d[0] * u[0] + d[1] * u[1] + d[2] * u[2]);
    half = fmax(half, fmax(x, y));
  }
  v->half_extent = half > 0 ? margin * half : 1.0;
}

void bbc_view_frame_mesh(const bbc_mesh *m, const double direction[3], const double up[3],
                         bbc_view *v) {
  assert(m && direction && up && v);
  bbc__view_frame_box(m->bbox_min, m->bbox_max, direction, up, 1.04, v);
  v->lighting = 1;
  v->point_size_px = 2.0f;
  v->background[0] = v->background[1] = v->background[2] = 255;
  v->background[3] = 255;
}
