/* bench_fidelity — one far-LOD method on one model: generation time (median
 * of RUNS), peak memory, size, and fidelity (bbc_eval, 64 views, 256 px,
 * unlit; textures baked unlit).
 *   bench_fidelity MODEL RUNS OUT.glb cloud [NAME=VALUE ...]
 *   bench_fidelity MODEL RUNS OUT.glb crossed K H TEXELS [NAME=VALUE ...]
 *   bench_fidelity MODEL RUNS OUT.glb simplify|sloppy TRIANGLES
 *   bench_fidelity MODEL RUNS OTHER.glb file LABEL   (evaluate an existing file)
 * Prints one JSON object. */
#include "bbc.h"
#include "bench_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(const bbc_error *err) {
  fprintf(stderr, "bench_fidelity: %s\n", err->message);
  return 1;
}

int main(int argc, char **argv) {
  if (argc < 5) {
    fprintf(stderr, "usage: see bench/bench_fidelity.c\n");
    return 1;
  }
  const char *model = argv[1], *out = argv[3], *method = argv[4];
  int runs = atoi(argv[2]);
  if (runs < 1 || runs > 99) runs = 3;
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  o.params.prelight = 0; /* unlit textures for an unlit comparison */
  int first_param = 5, k = 3, horizontal = 0;
  size_t texels = 0, triangles = 0;
  if (!strcmp(method, "crossed")) {
    if (argc < 8) return 1;
    k = atoi(argv[5]);
    horizontal = atoi(argv[6]);
    texels = (size_t)atoll(argv[7]);
    first_param = 8;
  } else if (!strcmp(method, "simplify") || !strcmp(method, "sloppy")) {
    if (argc < 6) return 1;
    triangles = (size_t)atoll(argv[5]);
    first_param = 6;
  } else if (!strcmp(method, "file")) {
    first_param = 6;
  }
  bbc_error err;
  char params[512] = "";
  for (int i = first_param; i < argc; i++) {
    if (bbc_params_set_assignment(&o.params, argv[i], &err) != BBC_OK) return fail(&err);
    size_t l = strlen(params);
    snprintf(params + l, sizeof params - l, "%s%s", l ? " " : "", argv[i]);
  }
  bbc_mesh m;
  if (bbc_mesh_load(model, NULL, &m, &err) != BBC_OK) return fail(&err);
  double times[99];
  size_t planes = 0, tris = 0, tex = 0;
  int aw = 0, ah = 0;
  char label[160];
  if (!strcmp(method, "file")) {
    snprintf(label, sizeof label, "%s", argc > 5 ? argv[5] : "file");
    runs = 0;
  }
  for (int r = 0; r < runs; r++) {
    double t0 = bench_now();
    bbc_cloud c;
    bbc_mesh s;
    memset(&c, 0, sizeof c);
    memset(&s, 0, sizeof s);
    const bbc_mesh *res = NULL;
    if (!strcmp(method, "cloud")) {
      bbc_planeset ps;
      if (bbc_planes_find(&m, &o, &ps, &err) != BBC_OK) return fail(&err);
      if (bbc_cloud_build(&m, &ps, &o.params, NULL, &c, &err) != BBC_OK) return fail(&err);
      planes = c.billboard_count;
      bbc_planeset_free(&ps);
      res = &c.mesh;
      snprintf(label, sizeof label, "cloud");
    } else if (!strcmp(method, "crossed")) {
      if (bbc_baseline_crossed(&m, k, horizontal, &o.params, texels, NULL, &c, &err) != BBC_OK)
        return fail(&err);
      planes = c.billboard_count;
      res = &c.mesh;
      snprintf(label, sizeof label, "crossed %d%s", k, horizontal ? "+h" : "");
    } else {
      int sloppy = !strcmp(method, "sloppy");
      if (bbc_baseline_simplify(&m, triangles, sloppy, &s, &err) != BBC_OK) return fail(&err);
      res = &s;
      snprintf(label, sizeof label, "%s %zu", sloppy ? "meshopt sloppy" : "meshopt simplify",
               triangles);
    }
    times[r] = bench_now() - t0;
    if (r == runs - 1) {
      if (bbc_mesh_write_gltf(out, res, NULL, &err) != BBC_OK) return fail(&err);
    }
    tris = res->triangle_count;
    tex = 0;
    for (size_t t = 0; t < res->texture_count; t++)
      tex += (size_t)res->textures[t].image.width * res->textures[t].image.height;
    if (res->texture_count) {
      aw = res->textures[0].image.width;
      ah = res->textures[0].image.height;
    }
    if (c.billboard_count) tex = c.texels;
    bbc_cloud_free(&c);
    bbc_mesh_free(&s);
  }
  double peak = bench_peak_rss_mib();
  /* Evaluate the written file as any user would load it. */
  bbc_mesh other;
  if (bbc_mesh_load(out, NULL, &other, &err) != BBC_OK) return fail(&err);
  if (runs == 0) {
    tris = other.triangle_count;
    for (size_t t = 0; t < other.texture_count; t++)
      tex += (size_t)other.textures[t].image.width * other.textures[t].image.height;
  }
  bbc_eval_options eo;
  bbc_eval_options_default(&eo);
  eo.up = bbc_up_from_axis(o.params.up_axis);
  bbc_eval_result e;
  if (bbc_eval(&m, &other, &eo, &e, &err) != BBC_OK) return fail(&err);
  printf("{\"bench\": \"fidelity\", \"model\": \"%s\", \"method\": \"%s\", \"params\": \"%s\", "
         "\"model_triangles\": %zu, \"planes\": %zu, \"triangles\": %zu, \"texels\": %zu, "
         "\"atlas\": \"%dx%d\", \"runs\": %d, \"median_s\": %.3f, \"peak_mib\": %.1f, "
         "\"iou\": %.4f, \"iou_side\": %.4f, \"recall\": %.4f, \"psnr\": %.2f, "
         "\"psnr_side\": %.2f, \"coverage\": %.4f, \"coverage_side\": %.4f, "
         "\"block_iou\": %.4f, \"block_iou_side\": %.4f}\n",
         model, label, params, m.triangle_count, planes, tris, tex, aw, ah, runs,
         runs ? bench_median(times, runs) : 0.0, runs ? peak : 0.0, e.iou_mean, e.iou_side_mean,
         e.recall_mean, e.psnr_mean, e.psnr_side_mean, e.coverage_ratio_mean,
         e.coverage_ratio_side_mean, e.block_iou_mean, e.block_iou_side_mean);
  bbc_eval_result_free(&e);
  bbc_mesh_free(&other);
  bbc_mesh_free(&m);
  return 0;
}
