/* camera.c — the forest's camera (Appendix B: airplane-like flight,
 * zoom) as a view-projection matrix, and the stored positions of F3/F2,
 * GL-free. */
#include "bbc_forest.h"
#include "io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

void bbc_forest_camera_forward(const bbc_forest_camera *c, double f[3]) {
  double cp = cos(c->pitch * DEG);
  f[0] = sin(c->yaw * DEG) * cp;
  f[1] = sin(c->pitch * DEG);
  f[2] = -cos(c->yaw * DEG) * cp;
}

void bbc_forest_camera_matrix(const bbc_forest_camera *c, double aspect, double n, double far,
                              float out[16]) {
  double zoom = c->zoom > 0 ? c->zoom : 1;
  double fovy = 60.0 * DEG, t = tan(fovy / 2) / zoom;
  double P[16] = {0};
  P[0] = 1 / (t * aspect);
  P[5] = 1 / t;
  P[10] = -(far + n) / (far - n);
  P[11] = -1;
  P[14] = -2 * far * n / (far - n);
  double f[3], up[3] = {0, 1, 0}, s[3], u[3];
  bbc_forest_camera_forward(c, f);
  s[0] = f[1] * up[2] - f[2] * up[1];
  s[1] = f[2] * up[0] - f[0] * up[2];
  s[2] = f[0] * up[1] - f[1] * up[0];
  double sl = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  for (int k = 0; k < 3; k++) s[k] /= sl;
  u[0] = s[1] * f[2] - s[2] * f[1];
  u[1] = s[2] * f[0] - s[0] * f[2];
  u[2] = s[0] * f[1] - s[1] * f[0];
  double V[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, 0, 0, 0, 1};
  V[12] = -(s[0] * c->pos[0] + s[1] * c->pos[1] + s[2] * c->pos[2]);
  V[13] = -(u[0] * c->pos[0] + u[1] * c->pos[1] + u[2] * c->pos[2]);
  V[14] = f[0] * c->pos[0] + f[1] * c->pos[1] + f[2] * c->pos[2];
  for (int col = 0; col < 4; col++)
    for (int row = 0; row < 4; row++) {
      double v = 0;
      for (int k = 0; k < 4; k++) v += P[k * 4 + row] * V[col * 4 + k];
      out[col * 4 + row] = (float)v;
    }
}

bbc_result bbc_forest_positions_append(const char *path, const bbc_forest_camera *c,
                                       bbc_error *err) {
  FILE *f = fopen(path, "a");
  if (!f) return bbc__fail(err, BBC_ERROR_IO, "%s: %s", path, strerror(errno));
  fprintf(f, "%.4f %.4f %.4f %.3f %.3f\n", c->pos[0], c->pos[1], c->pos[2], c->yaw, c->pitch);
  if (fclose(f) != 0) return bbc__fail(err, BBC_ERROR_IO, "%s: %s", path, strerror(errno));
  return BBC_OK;
}

bbc_result bbc_forest_positions_read(const char *path, bbc_forest_camera **cams, size_t *count,
                                     bbc_error *err) {
  *cams = NULL;
  *count = 0;
  FILE *probe = fopen(path, "r");
  if (!probe) return BBC_OK;
  fclose(probe);
  char *text = NULL;
  size_t size = 0;
  bbc_result r = bbc__read_whole_file(path, &text, &size, err);
  if (r != BBC_OK) return r;
  size_t lines = 1;
  for (size_t i = 0; i < size; i++) lines += text[i] == '\n';
  *cams = calloc(lines, sizeof **cams);
  if (!*cams) {
    free(text);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  char *p = text;
  int line = 0;
  while (p && *p) {
    line++;
    char *nl = strchr(p, '\n');
    if (nl) *nl = '\0';
    bbc_forest_camera c = {{0, 0, 0}, 0, 0, 1};
    char extra;
    int n = sscanf(p, "%lf %lf %lf %lf %lf %c", &c.pos[0], &c.pos[1], &c.pos[2], &c.yaw, &c.pitch,
                   &extra);
    const char *first = p + strspn(p, " \t");
    if (*first == '\'' || *first == '#') {
      /* a comment, as in map files (') or in shell-style files (#) */
    } else if (n == 5 && fabs(c.pos[0]) <= 1e7 && fabs(c.pos[1]) <= 1e7 && fabs(c.pos[2]) <= 1e7 &&
               fabs(c.yaw) <= 36000 && fabs(c.pitch) <= 89) {
      (*cams)[(*count)++] = c;
    } else if (strspn(p, " \t\r") != strlen(p)) {
      free(*cams);
      *cams = NULL;
      *count = 0;
      free(text);
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s:%d: expected x y z yaw pitch (numbers; coordinates within +-1e7, "
                       "pitch within +-89)",
                       path, line);
    }
    p = nl ? nl + 1 : NULL;
  }
  free(text);
  return BBC_OK;
}
