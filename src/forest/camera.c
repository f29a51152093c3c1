/* camera.c — the forest's camera (Appendix B: airplane-like flight,
 * zoom) as a view-projection matrix, and the stored positions of F3/F2,
 * GL-free. */
#include "bbc_forest.h"
#include "io.h"
#include "vec3.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

void bbc_forest_camera_get_forward(const bbc_forest_camera *c, double f[3]) {
  assert(c && f);
  double cp = cos(c->pitch * DEG);
  f[0] = sin(c->yaw * DEG) * cp;
  f[1] = sin(c->pitch * DEG);
  f[2] = -cos(c->yaw * DEG) * cp;
}

void bbc_forest_camera_get_viewproj(const bbc_forest_camera *c, double aspect, double n, double far,
                                    float out[16]) {
  assert(c && out);
  double zoom = c->zoom > 0 ? c->zoom : 1;
  double fovy = 60.0 * DEG, t = tan(fovy / 2) / zoom;
  double P[16] = {0};
  P[0] = 1 / (t * aspect);
  P[5] = 1 / t;
  P[10] = -(far + n) / (far - n);
  P[11] = -1;
  P[14] = -2 * far * n / (far - n);
  double fa[3];
  bbc_forest_camera_get_forward(c, fa);
  /* Side (normalised by division) and up vectors of a look-at view. */
  vec3 f = vload(fa), pos = vload(c->pos);
  vec3 s = vcross(f, v3(0, 1, 0));
  s = vdiv(s, vlen(s));
  vec3 u = vcross(s, f);
  double V[16] = {s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, 0, 0, 0, 1};
  V[12] = -vdot(s, pos);
  V[13] = -vdot(u, pos);
  V[14] = vdot(f, pos);
  for (int col = 0; col < 4; col++)
    for (int row = 0; row < 4; row++) {
      double v = 0;
      for (int k = 0; k < 4; k++) v += P[k * 4 + row] * V[col * 4 + k];
      out[col * 4 + row] = (float)v;
    }
}

bbc_result bbc_forest_positions_append(const char *path, const bbc_forest_camera *c,
                                       bbc_error *err) {
  assert(path && c);
  FILE *f = fopen(path, "a");
  if (!f) return bbc__fail(err, BBC_ERROR_IO, "%s: %s", path, strerror(errno));
  fprintf(f, "%.4f %.4f %.4f %.3f %.3f\n", c->pos[0], c->pos[1], c->pos[2], c->yaw, c->pitch);
  if (fclose(f) != 0) return bbc__fail(err, BBC_ERROR_IO, "%s: %s", path, strerror(errno));
  return BBC_OK;
}

bbc_result bbc_forest_positions_read(const char *path, bbc_forest_camera **cams, size_t *count,
                                     bbc_error *err) {
  assert(path && cams && count);
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
