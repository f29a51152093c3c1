/* sample.c — point clouds from models: points on a triangle mesh's surface,
 * uniform by area, coloured as the surface (material colour times texture),
 * deterministic for a seed. The binary PLY writer for them (doubles, so
 * georeferenced coordinates keep their precision) is io/write_ply.c. */
#include "base.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The surface colour at barycentric (u, v) of triangle t. */
static void surface_colour(const bbc_mesh *m, size_t t, double u, double v, uint8_t out[4]) {
  float c[4] = {0.8f, 0.8f, 0.8f, 1};
  uint32_t mi = m->face_material ? m->face_material[t] : 0;
  if (m->material_count && mi < m->material_count) {
    const bbc_material *ma = &m->materials[mi];
    memcpy(c, ma->base_color, sizeof c);
    if (ma->texture >= 0 && (size_t)ma->texture < m->texture_count && m->uvs &&
        m->textures[ma->texture].image.rgba) {
      const bbc_image *im = &m->textures[ma->texture].image;
      const uint32_t *ix = m->indices + 3 * t;
      double w = 1 - u - v, s = 0, q = 0;
      const float *a = m->uvs + 2 * ix[0], *b = m->uvs + 2 * ix[1], *d = m->uvs + 2 * ix[2];
      s = w * a[0] + u * b[0] + v * d[0];
      q = w * a[1] + u * b[1] + v * d[1];
      s -= floor(s);
      q -= floor(q);
      int x = (int)(s * im->width), y = (int)((1 - q) * im->height);
      x = x < 0 ? 0 : x >= im->width ? im->width - 1 : x;
      y = y < 0 ? 0 : y >= im->height ? im->height - 1 : y;
      const uint8_t *px = im->rgba + 4 * ((size_t)y * im->width + x);
      for (int k = 0; k < 4; k++) c[k] *= px[k] / 255.0f;
    }
  }
  for (int k = 0; k < 4; k++) {
    float x = c[k] < 0 ? 0 : c[k] > 1 ? 1 : c[k];
    out[k] = (uint8_t)lrintf(x * 255);
  }
}

bbc_result bbc_mesh_sample_points(const bbc_mesh *m, size_t count, uint64_t seed, bbc_mesh *out,
                                  bbc_error *err) {
  assert(m && out);
  memset(out, 0, sizeof *out);
  if (m->kind != BBC_MESH_TRIANGLES || !m->triangle_count)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "sampling needs a triangle mesh");
  if (!count) return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "sampling: no points asked");
  size_t nt = m->triangle_count;
  double *cum = malloc(nt * sizeof *cum);
  out->positions = malloc(3 * count * sizeof *out->positions);
  out->colors = malloc(4 * count * sizeof *out->colors);
  out->normals = malloc(3 * count * sizeof *out->normals);
  if (!cum || !out->positions || !out->colors || !out->normals) {
    free(cum);
    bbc_mesh_free(out);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "sampling: out of memory for %zu points", count);
  }
  double total = 0;
  for (size_t t = 0; t < nt; t++) {
    total += bbc__triangle_area(m, t);
    cum[t] = total;
  }
  bbc__rng rng = {seed};
  for (size_t i = 0; i < count; i++) {
    double x = bbc__rng_uniform(&rng) * total;
    size_t lo = 0, hi = nt - 1; /* the first triangle whose running area passes x */
    while (lo < hi) {
      size_t mid = lo + (hi - lo) / 2;
      if (cum[mid] <= x)
        lo = mid + 1;
      else
        hi = mid;
    }
    double u = bbc__rng_uniform(&rng), v = bbc__rng_uniform(&rng);
    if (u + v > 1) { /* fold into the triangle: uniform by area */
      u = 1 - u;
      v = 1 - v;
    }
    const uint32_t *ix = m->indices + 3 * lo;
    for (int k = 0; k < 3; k++)
      out->positions[3 * i + k] = (1 - u - v) * m->positions[3 * ix[0] + k] +
                                  u * m->positions[3 * ix[1] + k] + v * m->positions[3 * ix[2] + k];
    surface_colour(m, lo, u, v, out->colors + 4 * i);
    /* the triangle's normal, as a scanner's estimate would give it */
    const double *a = m->positions + 3 * ix[0], *b = m->positions + 3 * ix[1],
                 *c = m->positions + 3 * ix[2];
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
           f[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double nn[3] = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2],
                    e[0] * f[1] - e[1] * f[0]};
    double len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    for (int k = 0; k < 3; k++) out->normals[3 * i + k] = len > 0 ? (float)(nn[k] / len) : 0.0f;
  }
  free(cum);
  out->kind = BBC_MESH_POINTS;
  out->vertex_count = count;
  return bbc_mesh_finalize(out, 0, "sampled points", err);
}
