/* limbs.c — beyond the thesis: the trunk part kept as a small mesh inside
 * the cloud (`limbs`, issue 11). A stem and its limbs are thin cylinders: on
 * billboards they are lines from the sides those planes are seen edge-on
 * (a conifer's whorls lie on near-horizontal planes, so from the side its
 * limbs vanish) and up to epsilon off their place. As a mesh they hold from
 * every side at their place. The trunk part's faces (those no plane
 * simplifies, BBC_NO_PLANE) are welded by position and simplified with
 * meshoptimizer (edge collapses keeping the topology; where that stops
 * above the budget, clustering on the result) to at most `target`
 * triangles, with smooth normals. */
#include "cloud.h"

#include <math.h>
#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

bbc_result bbc__limbs_build(const bbc_mesh *m, const bbc_planeset *set, int target, bbc_mesh *out,
                            bbc_error *err) {
  memset(out, 0, sizeof *out);
  if (m->kind != BBC_MESH_TRIANGLES || target <= 0 || set->face_count != m->triangle_count)
    return BBC_OK;
  size_t n = 0;
  for (size_t t = 0; t < m->triangle_count; t++) n += set->face_plane[t] == BBC_NO_PLANE;
  if (!n) return BBC_OK;
  /* The part's triangles on their own vertices (float, as meshoptimizer
   * takes them), then one vertex per position. */
  size_t ni = 3 * n;
  unsigned *idx = malloc(ni * sizeof *idx), *welded = malloc(ni * sizeof *welded);
  unsigned *remap = malloc(ni * sizeof *remap), *res = malloc(ni * sizeof *res);
  float *pos = malloc(3 * ni * sizeof *pos), *upos = malloc(3 * ni * sizeof *upos);
  bbc_result r = BBC_OK;
  if (!idx || !welded || !remap || !res || !pos || !upos)
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "limbs: out of memory");
  size_t nu = 0, got = 0;
  if (r == BBC_OK) {
    size_t k = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
      if (set->face_plane[t] != BBC_NO_PLANE) continue;
      for (int c = 0; c < 3; c++, k++) {
        const double *p = m->positions + 3 * (size_t)m->indices[3 * t + c];
        for (int j = 0; j < 3; j++) pos[3 * k + j] = (float)p[j];
        idx[k] = (unsigned)k;
      }
    }
    nu = meshopt_generateVertexRemap(remap, idx, ni, pos, ni, 3 * sizeof *pos);
    meshopt_remapIndexBuffer(welded, idx, ni, remap);
    meshopt_remapVertexBuffer(upos, pos, ni, 3 * sizeof *pos, remap);
    size_t want = 3 * (size_t)target;
    if (ni <= want) {
      memcpy(res, welded, ni * sizeof *res);
      got = ni;
    } else {
      got = meshopt_simplify(res, welded, ni, upos, nu, 3 * sizeof *upos, want, 1.0f, 0, NULL);
      if (got > want) { /* the topology held it back: cluster what is left */
        memcpy(idx, res, got * sizeof *idx);
        got = meshopt_simplifySloppy(res, idx, got, upos, nu, 3 * sizeof *upos, want, 1.0f, NULL);
      }
    }
  }
  /* Only the vertices still used, in first-use order. */
  size_t nv = 0;
  if (r == BBC_OK) {
    for (size_t v = 0; v < nu; v++) remap[v] = UINT32_MAX;
    for (size_t i = 0; i < got; i++)
      if (remap[res[i]] == UINT32_MAX) remap[res[i]] = (unsigned)nv++;
    out->kind = BBC_MESH_TRIANGLES;
    out->vertex_count = nv;
    out->triangle_count = got / 3;
    out->positions = malloc((nv ? nv : 1) * 3 * sizeof *out->positions);
    out->indices = malloc((got ? got : 1) * sizeof *out->indices);
    out->face_material = calloc(got / 3 + 1, sizeof *out->face_material);
    out->face_group = malloc((got / 3 + 1) * sizeof *out->face_group);
    out->materials = calloc(1, sizeof *out->materials);
    out->group_names = calloc(1, sizeof *out->group_names);
    if (out->materials) out->materials[0].name = bbc__strdup("limbs");
    if (out->group_names) out->group_names[0] = bbc__strdup("trunk");
    if (!out->positions || !out->indices || !out->face_material || !out->face_group ||
        !out->materials || !out->group_names || !out->materials[0].name || !out->group_names[0])
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "limbs: out of memory");
  }
  if (r == BBC_OK) {
    out->material_count = 1;
    out->group_count = 1;
    out->materials[0].texture = -1;
    for (int c = 0; c < 4; c++) out->materials[0].base_color[c] = 1.0f;
    for (size_t v = 0; v < nu; v++)
      if (remap[v] != UINT32_MAX)
        for (int j = 0; j < 3; j++) out->positions[3 * (size_t)remap[v] + j] = upos[3 * v + j];
    for (size_t i = 0; i < got; i++) out->indices[i] = remap[res[i]];
    for (size_t t = 0; t < got / 3; t++) out->face_group[t] = 0;
    if (got) r = bbc_mesh_finalize(out, 1, "limbs", err);
  }
  free(idx);
  free(welded);
  free(remap);
  free(res);
  free(pos);
  free(upos);
  if (r != BBC_OK || !out->triangle_count) bbc_mesh_free(out);
  if (r != BBC_OK) memset(out, 0, sizeof *out);
  return r;
}
