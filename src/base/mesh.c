/* mesh.c — the library's own mesh: validation, clean-up and the frame of
 * thesis 2.1.4 (area-weighted centre of gravity, bounding-sphere radius). */
#include "base.h"
#include "vec3.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Coordinates beyond this are treated as damage, not geometry (a shifted
 * binary record reads as 1e38). */
#define BBC_MAX_COORD 1e30

void bbc_mesh_free(bbc_mesh *mesh) {
  if (!mesh) return;
  free(mesh->positions);
  free(mesh->normals);
  free(mesh->uvs);
  free(mesh->colors);
  free(mesh->tangents);
  free(mesh->indices);
  free(mesh->face_material);
  free(mesh->face_group);
  for (size_t i = 0; i < mesh->material_count; i++) {
    free(mesh->materials[i].name);
    free(mesh->materials[i].texture_ref);
  }
  free(mesh->materials);
  for (size_t i = 0; i < mesh->texture_count; i++) {
    free(mesh->textures[i].path);
    bbc_image_free(&mesh->textures[i].image);
  }
  free(mesh->textures);
  for (size_t i = 0; i < mesh->group_count; i++) free(mesh->group_names[i]);
  free(mesh->group_names);
  memset(mesh, 0, sizeof *mesh);
}

void bbc_mesh_count_group_triangles(const bbc_mesh *mesh, size_t *counts) {
  assert(mesh && (counts || mesh->group_count == 0));
  memset(counts, 0, mesh->group_count * sizeof *counts);
  for (size_t t = 0; t < mesh->triangle_count; t++) counts[mesh->face_group[t]]++;
}

/* Twice the triangle's area vector (unnormalised normal). */
void bbc__triangle_cross(const bbc_mesh *m, size_t t, double *c) {
  const uint32_t *ix = m->indices + 3 * t;
  vec3 p0 = vload(m->positions + 3 * ix[0]);
  vec3 e1 = vsub(vload(m->positions + 3 * ix[1]), p0);
  vec3 e2 = vsub(vload(m->positions + 3 * ix[2]), p0);
  vstore(c, vcross(e1, e2));
}

double bbc__srgb_to_linear(double c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return 1;
  return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

double bbc__linear_to_srgb(double c) {
  if (!(c > 0)) return 0;
  if (c >= 1) return 1;
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

double bbc__triangle_area(const bbc_mesh *m, size_t t) {
  double c[3];
  bbc__triangle_cross(m, t, c);
  return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

static int coord_ok(double v) {
  return isfinite(v) && fabs(v) <= BBC_MAX_COORD;
}

static bbc_result check_vertex(const bbc_mesh *m, size_t v, const char *source, bbc_error *err) {
  const double *p = m->positions + 3 * v;
  for (int k = 0; k < 3; k++)
    if (!coord_ok(p[k]))
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: vertex %zu has a non-finite or absurd coordinate (%g %g %g)", source, v,
                       p[0], p[1], p[2]);
  return BBC_OK;
}

/* Each vertex's first vertex (lowest index) at the same position (equal
 * bits), through a hash table of positions. */
static uint64_t position_hash(const double *p) {
  uint64_t h = 0x9E3779B97F4A7C15ull, b;
  for (int k = 0; k < 3; k++) {
    memcpy(&b, &p[k], sizeof b);
    h = (h ^ b) * 0xff51afd7ed558ccdull;
    h ^= h >> 29;
  }
  return h;
}

static int same_position_first(const bbc_mesh *m, uint32_t *first) {
  size_t nv = m->vertex_count, cap = 16;
  while (cap < 2 * nv) cap *= 2;
  uint32_t *slot = calloc(cap, sizeof *slot); /* vertex + 1; 0 = empty */
  if (!slot) return 0;
  for (size_t v = 0; v < nv; v++) {
    const double *p = m->positions + 3 * v;
    size_t h = (size_t)position_hash(p) & (cap - 1);
    for (;;) {
      uint32_t s = slot[h];
      if (!s) {
        slot[h] = (uint32_t)v + 1;
        first[v] = (uint32_t)v;
        break;
      }
      if (!memcmp(m->positions + 3 * (size_t)(s - 1), p, 3 * sizeof *p)) {
        first[v] = s - 1;
        break;
      }
      h = (h + 1) & (cap - 1);
    }
  }
  free(slot);
  return 1;
}

/* Computes unit normals for vertices whose normal is missing or unusable.
 * smooth = 1 accumulates area-weighted face normals over all vertices that
 * share a position (files often split vertices at UV seams); smooth = 0 only
 * over the vertex index itself. Faces nearly back to back with a vertex's
 * largest face (the two sides of a thin sheet, a two-sided leaf or needle
 * made of two faces on the same corners) are added turned over: summed as
 * they are, the two sides cancel, and the normal left is noise. */
static int normal_usable(const float *n) {
  double l2 = (double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2];
  return isfinite(l2) && l2 > 1e-12;
}

/* cos of the angle between two faces' normals below which the second is
 * the other side of the first's sheet: 150 degrees apart or more. */
#define BBC_SHEET_COS (-0.866)

static bbc_result compute_normals(bbc_mesh *m, int smooth, int only_missing) {
  size_t nv = m->vertex_count;
  if (only_missing) {
    /* The usual case: the file has every normal. Skip the welding sort. */
    size_t missing = 0;
    for (size_t v = 0; v < nv; v++) missing += !normal_usable(m->normals + 3 * v);
    if (missing == 0) {
      for (size_t v = 0; v < nv; v++) {
        float *n = m->normals + 3 * v;
        double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        for (int k = 0; k < 3; k++) n[k] = (float)(n[k] / l);
      }
      return BBC_OK;
    }
  }
  /* first[v]: the vertex whose sum v shares (the lowest index at v's
   * position with smooth, else v); ref: per such vertex, its largest
   * face's cross product (the lowest face index among equals). */
  size_t nv1 = nv ? nv : 1;
  double *acc = calloc(nv1 * 3, sizeof *acc), *ref = calloc(nv1 * 4, sizeof *ref);
  uint32_t *first = malloc(nv1 * sizeof *first);
  if (!acc || !ref || !first || (smooth && nv > 1 && !same_position_first(m, first))) {
    free(acc);
    free(ref);
    free(first);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  if (!(smooth && nv > 1))
    for (size_t v = 0; v < nv; v++) first[v] = (uint32_t)v;
  for (size_t t = 0; t < m->triangle_count; t++) {
    double c[3];
    bbc__triangle_cross(m, t, c);
    double q = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    for (int k = 0; k < 3; k++) {
      double *r = ref + 4 * (size_t)first[m->indices[3 * t + k]];
      if (q > r[3]) {
        memcpy(r, c, 3 * sizeof *c);
        r[3] = q;
      }
    }
  }
  for (size_t t = 0; t < m->triangle_count; t++) {
    double c[3];
    bbc__triangle_cross(m, t, c);
    double q = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    for (int k = 0; k < 3; k++) {
      size_t g = first[m->indices[3 * t + k]];
      const double *r = ref + 4 * g;
      double d = c[0] * r[0] + c[1] * r[1] + c[2] * r[2];
      double sign = d < BBC_SHEET_COS * sqrt(q * r[3]) ? -1.0 : 1.0;
      for (int j = 0; j < 3; j++) acc[3 * g + j] += sign * c[j];
    }
  }
  for (size_t v = 0; v < nv; v++)
    if (first[v] != v) memcpy(acc + 3 * v, acc + 3 * (size_t)first[v], 3 * sizeof *acc);
  free(first);
  free(ref);
  if (!m->normals) {
    m->normals = malloc(nv * 3 * sizeof *m->normals);
    if (!m->normals) {
      free(acc);
      return BBC_ERROR_OUT_OF_MEMORY;
    }
    only_missing = 0;
  }
  for (size_t v = 0; v < nv; v++) {
    float *n = m->normals + 3 * v;
    if (only_missing && normal_usable(n)) {
      double l = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
      for (int k = 0; k < 3; k++) n[k] = (float)(n[k] / l);
      continue;
    }
    double *a = acc + 3 * v;
    double l = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (l > 0) {
      for (int k = 0; k < 3; k++) n[k] = (float)(a[k] / l);
    } else {
      n[0] = 0.0f;
      n[1] = 1.0f;
      n[2] = 0.0f;
    }
  }
  free(acc);
  return BBC_OK;
}

static bbc_result finalize_points(bbc_mesh *m, const char *source, bbc_error *err) {
  if (m->vertex_count == 0) return bbc__fail(err, BBC_ERROR_EMPTY, "%s: no points", source);
  long double s[3] = {0, 0, 0};
  for (int k = 0; k < 3; k++) {
    m->bbox_min[k] = INFINITY;
    m->bbox_max[k] = -INFINITY;
  }
  for (size_t v = 0; v < m->vertex_count; v++) {
    bbc_result r = check_vertex(m, v, source, err);
    if (r != BBC_OK) return r;
    const double *p = m->positions + 3 * v;
    for (int k = 0; k < 3; k++) {
      s[k] += p[k];
      if (p[k] < m->bbox_min[k]) m->bbox_min[k] = p[k];
      if (p[k] > m->bbox_max[k]) m->bbox_max[k] = p[k];
    }
  }
  for (int k = 0; k < 3; k++) m->center[k] = (double)(s[k] / (long double)m->vertex_count);
  double r2 = 0;
  for (size_t v = 0; v < m->vertex_count; v++) {
    vec3 d = vsub(vload(m->positions + 3 * v), vload(m->center));
    double q = vdot(d, d);
    if (q > r2) r2 = q;
  }
  m->radius = sqrt(r2);
  return BBC_OK;
}

/* Indices and per-face tables first (everything after reads through them),
 * then the coordinates of every vertex a triangle uses: finite. */
static bbc_result check_triangles(const bbc_mesh *m, const char *source, bbc_error *err) {
  for (size_t t = 0; t < m->triangle_count; t++) {
    for (int k = 0; k < 3; k++)
      if (m->indices[3 * t + k] >= m->vertex_count)
        return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                         "%s: triangle %zu refers to vertex %u, but there are only %zu vertices",
                         source, t, m->indices[3 * t + k], m->vertex_count);
    if (m->face_material[t] >= m->material_count)
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: triangle %zu refers to material %u of %zu", source, t,
                       m->face_material[t], m->material_count);
    if (m->face_group[t] >= m->group_count)
      return bbc__fail(err, BBC_ERROR_INVALID_GEOMETRY,
                       "%s: triangle %zu refers to group %u of %zu", source, t, m->face_group[t],
                       m->group_count);
  }
  for (size_t t = 0; t < m->triangle_count; t++)
    for (int k = 0; k < 3; k++) {
      bbc_result r = check_vertex(m, m->indices[3 * t + k], source, err);
      if (r != BBC_OK) return r;
    }
  return BBC_OK;
}

/* Bounds of the vertices the triangles use. */
static void used_bounds(bbc_mesh *m) {
  for (int k = 0; k < 3; k++) {
    m->bbox_min[k] = INFINITY;
    m->bbox_max[k] = -INFINITY;
  }
  for (size_t i = 0; i < 3 * m->triangle_count; i++) {
    const double *p = m->positions + 3 * m->indices[i];
    for (int k = 0; k < 3; k++) {
      if (p[k] < m->bbox_min[k]) m->bbox_min[k] = p[k];
      if (p[k] > m->bbox_max[k]) m->bbox_max[k] = p[k];
    }
  }
}

/* Drops zero-area triangles (repeated indices, collinear or coincident
 * corners): they carry no surface, and their normal is undefined. "Zero"
 * is relative to the model's size (the bounds' diagonal) so that tiny real
 * leaves survive. The kept ones move to the front, in order. */
static void drop_degenerate(bbc_mesh *m) {
  vec3 ext = vsub(vload(m->bbox_max), vload(m->bbox_min));
  double diag2 = vdot(ext, ext);
  double min_cross = diag2 * 1e-14;
  m->triangles_read = m->triangle_count;
  size_t kept = 0;
  for (size_t t = 0; t < m->triangle_count; t++) {
    double c[3];
    bbc__triangle_cross(m, t, c);
    double len = vlen(vload(c));
    if (!(len > min_cross)) {
      m->dropped_degenerate++;
      continue;
    }
    if (kept != t) {
      memcpy(m->indices + 3 * kept, m->indices + 3 * t, 3 * sizeof *m->indices);
      m->face_material[kept] = m->face_material[t];
      m->face_group[kept] = m->face_group[t];
    }
    kept++;
  }
  m->triangle_count = kept;
}

/* Centre of gravity of the surface (thesis 2.1.4): area-weighted triangle
 * centroids, accumulated in long double, in triangle order, so the result
 * does not depend on anything but the input; and the radius of the sphere
 * around it through the farthest used vertex. */
static void centre_and_radius(bbc_mesh *m) {
  size_t kept = m->triangle_count;
  long double cs[3] = {0, 0, 0}, area_sum = 0;
  for (size_t t = 0; t < kept; t++) {
    double c[3];
    bbc__triangle_cross(m, t, c);
    double a = 0.5 * vlen(vload(c));
    const uint32_t *ix = m->indices + 3 * t;
    for (int k = 0; k < 3; k++) {
      double centroid = (m->positions[3 * ix[0] + k] + m->positions[3 * ix[1] + k] +
                         m->positions[3 * ix[2] + k]) /
                        3.0;
      cs[k] += (long double)a * centroid;
    }
    area_sum += a;
  }
  for (int k = 0; k < 3; k++) m->center[k] = (double)(cs[k] / area_sum);
  double r2 = 0;
  for (size_t i = 0; i < 3 * kept; i++) {
    vec3 d = vsub(vload(m->positions + 3 * m->indices[i]), vload(m->center));
    double q = vdot(d, d);
    if (q > r2) r2 = q;
  }
  m->radius = sqrt(r2);
}

bbc_result bbc_mesh_finalize(bbc_mesh *m, int smooth_normals, const char *source, bbc_error *err) {
  assert(m);
  if (!source) source = "mesh";
  if (m->kind == BBC_MESH_POINTS) return finalize_points(m, source, err);
  bbc_result r = check_triangles(m, source, err);
  if (r != BBC_OK) return r;
  /* Bounds of the used vertices: also the scale for "zero" area. */
  used_bounds(m);
  drop_degenerate(m);
  if (m->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_EMPTY, "%s: no triangles with non-zero area%s", source,
                     m->dropped_degenerate ? " (all were degenerate)" : "");
  /* Bounds again: dropped triangles may have held the extreme vertices. */
  used_bounds(m);

  /* Normals: keep the file's, fill missing or unusable ones. */
  int had_normals = m->normals != NULL;
  if (compute_normals(m, smooth_normals, had_normals) != BBC_OK)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory computing normals", source);
  if (!had_normals) m->normals_generated = 1;
  centre_and_radius(m);
  return BBC_OK;
}

int bbc_material_is_limbs(const bbc_material *mat) {
  assert(mat);
  const char *n = mat && mat->name ? mat->name : "";
  if (strncmp(n, "limbs", 5)) return 0;
  if (!n[5]) return 1;
  if (strncmp(n + 5, "_LOD", 4) || !n[9]) return 0;
  for (const char *p = n + 9; *p; p++)
    if (*p < '0' || *p > '9') return 0;
  return 1;
}
