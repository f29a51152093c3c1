/* linalg.c — the principal axes of a symmetric 3 x 3 matrix (a covariance):
 * the normal of least spread (point normals, fitted planes) and the axis of
 * most spread (a stem's axis, a limb's direction). */
#include "base.h"

#include <math.h>
#include <string.h>

void bbc__smallest_eigenvector(double a[3][3], double v_out[3]) {
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 50; sweep++) {
    double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
    if (off < 1e-300) break;
    /* A sweep that changes no bit of a and v would change none again: the
     * result of all 50 (converged covariances get there after 10-12; their
     * off-diagonal rounding residue never reaches 1e-300). */
    double a0[3][3], v0[3][3];
    memcpy(a0, a, sizeof a0);
    memcpy(v0, v, sizeof v0);
    for (int p = 0; p < 2; p++)
      for (int q = p + 1; q < 3; q++) {
        if (a[p][q] == 0) continue;
        double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        double t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
        double c = 1 / sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; k++) { /* A = J^T A J */
          double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; k++) {
          double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; k++) {
          double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    if (!memcmp(a0, a, sizeof a0) && !memcmp(v0, v, sizeof v0)) break;
  }
  int m = 0;
  for (int i = 1; i < 3; i++)
    if (a[i][i] < a[m][m]) m = i;
  for (int k = 0; k < 3; k++) v_out[k] = v[k][m];
}

void bbc__largest_eigenvector(const double a[3][3], const double start[3], double v[3]) {
  memcpy(v, start, 3 * sizeof *v);
  for (int k = 0; k < 32; k++) {
    double nv[3];
    for (int i = 0; i < 3; i++) nv[i] = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
    double l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    if (!(l > 0)) break;
    for (int i = 0; i < 3; i++) v[i] = nv[i] / l;
  }
}
