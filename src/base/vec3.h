/*
 * vec3.h — 3-vectors of doubles passed by value, and the small operations on
 * them that the library's geometry keeps needing (src/base; internal, not
 * installed). One set for every layer: arrays of three doubles (a mesh's
 * positions, a plane's normal) come in through vload and go out through
 * vstore.
 *
 * Each operation is written out component by component in one fixed order
 * (a dot product is a.x * b.x + a.y * b.y + a.z * b.z, summed left to
 * right; C11 contracts nothing into FMA), so code that moves onto these
 * helpers computes bit for bit what its own spelled-out arithmetic did.
 * Normalising comes in two roundings that are not interchangeable: vnorm
 * multiplies by the reciprocal of the length, vdiv(a, vlen(a)) divides by
 * the length.
 */
#ifndef BBC_VEC3_H
#define BBC_VEC3_H

#include <math.h>

typedef struct vec3 {
  double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z) {
  vec3 r = {x, y, z};
  return r;
}
/* p[0..2] as a vector. */
static inline vec3 vload(const double *p) {
  return v3(p[0], p[1], p[2]);
}
/* a into p[0..2]. */
static inline void vstore(double *p, vec3 a) {
  p[0] = a.x;
  p[1] = a.y;
  p[2] = a.z;
}
static inline vec3 vadd(vec3 a, vec3 b) {
  return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline vec3 vsub(vec3 a, vec3 b) {
  return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline vec3 vscale(vec3 a, double s) {
  return v3(a.x * s, a.y * s, a.z * s);
}
/* Each component divided by s (rounds differently from vscale(a, 1 / s)). */
static inline vec3 vdiv(vec3 a, double s) {
  return v3(a.x / s, a.y / s, a.z / s);
}
/* a + b * s */
static inline vec3 vmadd(vec3 a, vec3 b, double s) {
  return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline double vdot(vec3 a, vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline vec3 vcross(vec3 a, vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double vlen(vec3 a) {
  return sqrt(vdot(a, a));
}
/* Unit vector along a (times the reciprocal of its length); `fallback` when
 * a is (nearly) zero. */
static inline vec3 vnorm_or(vec3 a, vec3 fallback) {
  double l = vlen(a);
  return l > 1e-12 ? vscale(a, 1.0 / l) : fallback;
}
/* a divided by its length (the rounding of a division); a zero vector
 * stays zero. */
static inline vec3 vnormalize(vec3 a) {
  double l = vlen(a);
  return l > 0 ? vdiv(a, l) : a;
}
/* Unit vector along a; +y when a is (nearly) zero. */
static inline vec3 vnorm(vec3 a) {
  return vnorm_or(a, v3(0, 1, 0));
}

#endif /* BBC_VEC3_H */
