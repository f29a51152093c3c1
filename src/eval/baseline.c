/* baseline.c — what a user would otherwise use for a far LOD, made by the
 * same code paths so `eval` judges everything alike: crossed billboards
 * (k vertical planes through the centre, optionally a horizontal one) baked
 * by our baker, and meshoptimizer's simplification keeping UVs and textures. */
#include "cloud.h"

#include <assert.h>
#include <math.h>
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

/* One part ("all") of n planes, every face in every slab: a slab far wider
 * than the model (c: the model's centre). */
static void crossed_set(const bbc_mesh *m, size_t n, const double c[3], bbc_planeset *set) {
  size_t nf = m->triangle_count;
  double eps = 4 * m->radius + 1;
  set->radius = m->radius;
  set->epsilon_abs = eps;
  set->plane_count = n;
  set->face_count = nf;
  set->part_count = 1;
  snprintf(set->parts[0].name, sizeof set->parts[0].name, "all");
  set->parts[0].epsilon_abs = eps;
  set->parts[0].face_count = nf;
  set->parts[0].plane_count = n;
  memcpy(set->parts[0].center, c, 3 * sizeof *c);
  set->parts[0].radius = m->radius;
  snprintf(set->split_why, sizeof set->split_why, "crossed billboards: one part");
}

/* Plane i through the centre c (the first `planes` vertical, 180 / planes
 * degrees apart, then the horizontal one) and its rectangle rb: the whole
 * model projected onto it. */
static void crossed_plane(const bbc_mesh *m, size_t i, int planes, int up, const double c[3],
                          bbc_plane *p, bbc_billboard *rb) {
  int a = (up + 1) % 3, b = (up + 2) % 3;
  double nrm[3] = {0, 0, 0}, u[3] = {0, 0, 0}, w[3] = {0, 0, 0};
  if (i < (size_t)planes) { /* vertical: u horizontal, w = up */
    double th = 3.14159265358979323846 * (double)i / planes;
    nrm[a] = cos(th);
    nrm[b] = sin(th);
    w[up] = 1;
    /* u = w x n, so that u x w = n */
    u[0] = w[1] * nrm[2] - w[2] * nrm[1];
    u[1] = w[2] * nrm[0] - w[0] * nrm[2];
    u[2] = w[0] * nrm[1] - w[1] * nrm[0];
  } else { /* horizontal: normal = up, (u, w) = (a, b) */
    nrm[up] = 1;
    u[a] = 1;
    w[b] = 1;
  }
  memcpy(p->normal, nrm, sizeof nrm);
  p->d = nrm[0] * c[0] + nrm[1] * c[1] + nrm[2] * c[2];
  p->kind = BBC_PLANE_STANDARD;
  p->mother = -1;
  p->coverage_pct = 100;
  p->area = 1;
  p->face_count = i == 0 ? m->triangle_count : 0;
  /* The rectangle: the whole model projected onto the plane. */
  double smin = INFINITY, smax = -INFINITY, tmin = INFINITY, tmax = -INFINITY;
  for (size_t v = 0; v < m->vertex_count; v++) {
    const double *x = m->positions + 3 * v;
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    double s = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
    double t = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
    smin = fmin(smin, s);
    smax = fmax(smax, s);
    tmin = fmin(tmin, t);
    tmax = fmax(tmax, t);
  }
  rb->plane = (uint32_t)i;
  memcpy(rb->u, u, sizeof u);
  memcpy(rb->w, w, sizeof w);
  for (int k = 0; k < 3; k++) rb->origin[k] = c[k] + smin * u[k] + tmin * w[k];
  rb->width = smax - smin;
  rb->height = tmax - tmin;
}

/* The texture resolution whose texels come closest to the budget. */
static int crossed_texres(const bbc_billboard *rects, size_t n, int sides, size_t texel_budget) {
  int best = 4;
  double best_d = INFINITY;
  for (int t = 4; t <= 8192; t *= 2) {
    size_t tx = bbc__cloud_texels(NULL, rects, n, t, sides);
    double d = fabs(log((double)tx / (double)(texel_budget ? texel_budget : 1)));
    if (d < best_d - 1e-12) {
      best_d = d;
      best = t;
    }
  }
  return best;
}

bbc_result bbc_baseline_crossed(const bbc_mesh *m, int planes, int horizontal,
                                const bbc_params *params, size_t texel_budget,
                                const bbc_callbacks *callbacks, bbc_cloud *cloud, bbc_error *err) {
  assert(m && params && cloud);
  memset(cloud, 0, sizeof *cloud);
  if (m->kind != BBC_MESH_TRIANGLES || m->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "crossed billboards need triangles (point clouds are not supported yet)");
  if (planes < 1 || planes > 16)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "crossed billboards: 1 to 16 vertical planes, not %d", planes);
  int up = params->up_axis >= 0 && params->up_axis <= 2 ? params->up_axis : 1;
  size_t n = (size_t)planes + (horizontal ? 1 : 0), nf = m->triangle_count;
  bbc_planeset set;
  memset(&set, 0, sizeof set);
  bbc_billboard *rects = calloc(n, sizeof *rects);
  set.planes = calloc(n, sizeof *set.planes);
  set.face_plane = calloc(nf, sizeof *set.face_plane);
  set.face_part = calloc(nf, sizeof *set.face_part);
  set.parts = calloc(1, sizeof *set.parts);
  bbc_result r = BBC_OK;
  if (!rects || !set.planes || !set.face_plane || !set.face_part || !set.parts)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "crossed billboards: out of memory");
  if (r == BBC_OK) {
    double c[3];
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (m->bbox_min[k] + m->bbox_max[k]);
    crossed_set(m, n, c, &set);
    for (size_t i = 0; i < n; i++) crossed_plane(m, i, planes, up, c, &set.planes[i], &rects[i]);
    bbc_params prm = *params;
    prm.pure = 0;
    prm.poly_skip_pct = 0;
    prm.texres = crossed_texres(rects, n, prm.back_images ? 2 : 1, texel_budget);
    prm.atlas_max = 0; /* the texel budget decides */
    prm.outline = 0;   /* whole quads, as engines make crossed billboards */
    r = bbc__cloud_build_rects(m, &set, rects, &prm, callbacks, cloud, err);
  }
  free(rects);
  bbc_planeset_free(&set);
  return r;
}

/* ---- simplification ---------------------------------------------------------- */

static bbc_result copy_materials(const bbc_mesh *m, bbc_mesh *o, bbc_error *err) {
  o->materials = calloc(m->material_count, sizeof *o->materials);
  o->textures = calloc(m->texture_count ? m->texture_count : 1, sizeof *o->textures);
  o->group_names = calloc(m->group_count ? m->group_count : 1, sizeof *o->group_names);
  if (!o->materials || !o->textures || !o->group_names)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "simplify: out of memory");
  o->material_count = m->material_count;
  for (size_t i = 0; i < m->material_count; i++) {
    o->materials[i] = m->materials[i];
    o->materials[i].name = bbc__strdup(m->materials[i].name ? m->materials[i].name : "");
    o->materials[i].texture_ref =
        m->materials[i].texture_ref ? bbc__strdup(m->materials[i].texture_ref) : NULL;
    if (!o->materials[i].name)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "simplify: out of memory");
  }
  o->texture_count = m->texture_count;
  for (size_t t = 0; t < m->texture_count; t++) {
    const bbc_texture *s = &m->textures[t];
    bbc_texture *d = &o->textures[t];
    d->has_alpha = s->has_alpha;
    d->path = s->path ? bbc__strdup(s->path) : NULL;
    if (s->image.rgba) {
      if (bbc_image_alloc(&d->image, s->image.width, s->image.height) != BBC_OK)
        return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "simplify: out of memory");
      memcpy(d->image.rgba, s->image.rgba, (size_t)s->image.width * s->image.height * 4);
    }
  }
  o->group_count = m->group_count;
  for (size_t g = 0; g < m->group_count; g++) {
    o->group_names[g] = bbc__strdup(m->group_names[g]);
    if (!o->group_names[g]) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  return BBC_OK;
}

bbc_result bbc_baseline_simplify(const bbc_mesh *m, size_t target_triangles, int sloppy,
                                 bbc_mesh *out, bbc_error *err) {
  assert(m && out);
  memset(out, 0, sizeof *out);
  if (m->kind != BBC_MESH_TRIANGLES || m->triangle_count == 0)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "simplification needs triangles (point clouds are not supported)");
  size_t nv = m->vertex_count, nt = m->triangle_count, nm = m->material_count;
  float *pos = malloc(3 * nv * sizeof *pos);
  unsigned *in = malloc(3 * nt * sizeof *in), *res = malloc(3 * nt * sizeof *res);
  uint32_t *keep_tri = malloc(3 * nt * sizeof *keep_tri), *keep_mat = malloc(nt * sizeof *keep_mat);
  uint32_t *keep_grp = malloc(nt * sizeof *keep_grp);
  uint32_t *remap = malloc(nv * sizeof *remap);
  bbc_result r = BBC_OK;
  if (!pos || !in || !res || !keep_tri || !keep_mat || !keep_grp || !remap)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "simplify: out of memory");
  size_t kept = 0;
  for (size_t v = 0; r == BBC_OK && v < nv; v++)
    for (int k = 0; k < 3; k++) pos[3 * v + k] = (float)m->positions[3 * v + k];
  /* Each material (and group) on its own, targets in proportion. */
  for (size_t mi = 0; r == BBC_OK && mi < nm; mi++) {
    for (size_t g = 0; g < (m->group_count ? m->group_count : 1); g++) {
      size_t cnt = 0;
      for (size_t t = 0; t < nt; t++)
        if (m->face_material[t] == mi && m->face_group[t] == g) {
          memcpy(in + 3 * cnt, m->indices + 3 * t, 3 * sizeof *in);
          cnt++;
        }
      if (!cnt) continue;
      size_t target = (size_t)((double)target_triangles * (double)cnt / (double)nt + 0.5);
      if (target < 1) target = 1;
      size_t got =
          target >= cnt ? (memcpy(res, in, 3 * cnt * sizeof *res), 3 * cnt)
          : sloppy ? meshopt_simplifySloppy(res, in, 3 * cnt, pos, nv, 12, 3 * target, 1.0f, NULL)
                   : meshopt_simplify(res, in, 3 * cnt, pos, nv, 12, 3 * target, 1.0f, 0, NULL);
      for (size_t i = 0; i < got / 3; i++, kept++) {
        memcpy(keep_tri + 3 * kept, res + 3 * i, 3 * sizeof *keep_tri);
        keep_mat[kept] = (uint32_t)mi;
        keep_grp[kept] = (uint32_t)g;
      }
    }
  }
  if (r == BBC_OK && kept == 0)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "%s: nothing is left at %zu triangles; ask for more",
                  sloppy ? "sloppy simplification" : "simplification", target_triangles);
  /* Only the vertices still used, in their original order. */
  size_t nuse = 0;
  if (r == BBC_OK) {
    for (size_t v = 0; v < nv; v++) remap[v] = UINT32_MAX;
    for (size_t i = 0; i < 3 * kept; i++) remap[keep_tri[i]] = 0;
    for (size_t v = 0; v < nv; v++)
      if (remap[v] == 0) remap[v] = (uint32_t)nuse++;
    out->kind = BBC_MESH_TRIANGLES;
    out->vertex_count = nuse;
    out->triangle_count = kept;
    out->positions = malloc(3 * nuse * sizeof *out->positions);
    out->normals = m->normals ? malloc(3 * nuse * sizeof *out->normals) : NULL;
    out->uvs = m->uvs ? malloc(2 * nuse * sizeof *out->uvs) : NULL;
    out->indices = malloc(3 * kept * sizeof *out->indices);
    out->face_material = malloc(kept * sizeof *out->face_material);
    out->face_group = malloc(kept * sizeof *out->face_group);
    if (!out->positions || (m->normals && !out->normals) || (m->uvs && !out->uvs) ||
        !out->indices || !out->face_material || !out->face_group)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "simplify: out of memory");
  }
  if (r == BBC_OK) {
    for (size_t v = 0; v < nv; v++) {
      if (remap[v] == UINT32_MAX) continue;
      size_t o = remap[v];
      memcpy(out->positions + 3 * o, m->positions + 3 * v, 3 * sizeof *out->positions);
      if (out->normals) memcpy(out->normals + 3 * o, m->normals + 3 * v, 3 * sizeof(float));
      if (out->uvs) memcpy(out->uvs + 2 * o, m->uvs + 2 * v, 2 * sizeof(float));
    }
    for (size_t i = 0; i < 3 * kept; i++) out->indices[i] = remap[keep_tri[i]];
    memcpy(out->face_material, keep_mat, kept * sizeof *keep_mat);
    memcpy(out->face_group, keep_grp, kept * sizeof *keep_grp);
    r = copy_materials(m, out, err);
  }
  if (r == BBC_OK) r = bbc_mesh_finalize(out, 1, "simplified mesh", err);
  free(pos);
  free(in);
  free(res);
  free(keep_tri);
  free(keep_mat);
  free(keep_grp);
  free(remap);
  if (r != BBC_OK) bbc_mesh_free(out);
  return r;
}
