/* sun_wind.c — the forest's sun (a direction from azimuth and elevation,
 * the shading a glTF viewer gives a lit material) and its wind (how far a
 * point of a tree sways). GL-free: forest_model.vert.glsl and
 * forest_model.frag.glsl do the same per vertex and per pixel, and the
 * tests check these. */
#include "bbc_forest.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void bbc_forest_sun_direction(double azimuth_deg, double elevation_deg, double dir[3]) {
  double az = azimuth_deg * M_PI / 180, el = elevation_deg * M_PI / 180;
  dir[0] = cos(el) * sin(az);
  dir[1] = sin(el);
  dir[2] = cos(el) * cos(az);
}

void bbc_forest_sun_angles(const double light[3], double *azimuth_deg, double *elevation_deg) {
  double h = sqrt(light[0] * light[0] + light[2] * light[2]);
  *elevation_deg = atan2(light[1], h) * 180 / M_PI;
  double az = h > 0 ? atan2(light[0], light[2]) * 180 / M_PI : 0;
  *azimuth_deg = az < 0 ? az + 360 : az;
}

double bbc_forest_sun_shade(double ambient, double occlusion, double n_dot_l) {
  return (ambient * occlusion + (n_dot_l > 0 ? n_dot_l : 0)) / (ambient + 1);
}

static double fract(double x) {
  return x - floor(x);
}

void bbc_forest_wind_offset(const bbc_forest_wind *wind, double time, const double base[3],
                            const double q[3], double height, double out[3]) {
  out[0] = out[1] = out[2] = 0;
  if (!wind || !(wind->strength > 0) || !(height > 0) || !(q[1] > 0)) return;
  double dx = wind->dir[0], dz = wind->dir[1];
  double a = 0.04 * wind->strength * height; /* the top's lean in a steady breeze */
  double h = q[1] / height;
  if (h > 2) h = 2;
  double phase = 2 * M_PI * fract(0.6180339 * base[0] + 0.4142136 * base[2]);
  /* slow gusts (about 16 s) travelling downwind at about 8 units a second */
  double gust = 0.5 + 0.5 * sin(0.4 * time - 0.05 * (base[0] * dx + base[2] * dz));
  double sway = (0.35 + 0.65 * gust) * (1 + 0.3 * sin(1.7 * time + phase));
  double bend = a * h * h * sway;
  /* leaves and twigs flutter, more the farther from the axis */
  double r = sqrt(q[0] * q[0] + q[2] * q[2]) / height;
  if (r > 1) r = 1;
  double flutter = 0.25 * a * r * h * (0.5 + gust) *
                   sin(5.0 * time + phase + 3.0 * (q[0] + q[1] + q[2]) / height);
  out[0] = dx * bend - dz * 0.8 * flutter;
  out[1] = 0.6 * flutter;
  out[2] = dz * bend + dx * 0.8 * flutter;
}
