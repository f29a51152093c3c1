/* bench_cloud — step 3 (baking, atlas) and the whole pipeline on a model.
 *   bench_cloud MODEL RUNS OUT.glb [NAME=VALUE ...]
 * Steps 1 and 2 run once; step 3 RUNS times (median); then the whole
 * pipeline from the file (load, steps 1-3, write OUT.glb) RUNS times
 * (median). Prints one JSON object. */
#include "bbc.h"
#include "bench_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(const bbc_error *err) {
  fprintf(stderr, "bench_cloud: %s\n", err->message);
  return 1;
}

int main(int argc, char **argv) {
  if (argc < 4) {
    fprintf(stderr, "usage: bench_cloud MODEL RUNS OUT.glb [NAME=VALUE ...]\n");
    return 1;
  }
  int runs = atoi(argv[2]);
  if (runs < 1 || runs > 99) runs = 3;
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_error err;
  char params[512] = "";
  for (int i = 4; i < argc; i++) {
    if (bbc_params_set_assignment(&o.params, argv[i], &err) != BBC_OK) return fail(&err);
    size_t l = strlen(params);
    snprintf(params + l, sizeof params - l, "%s%s", l ? " " : "", argv[i]);
  }
  bbc_mesh m;
  if (bbc_mesh_load(argv[1], NULL, &m, &err) != BBC_OK) return fail(&err);
  bbc_planeset s;
  if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) return fail(&err);
  double step3[99], whole[99];
  size_t billboards = 0, texels = 0;
  int aw = 0, ah = 0;
  for (int r = 0; r < runs; r++) {
    bbc_cloud c;
    double t0 = bench_now();
    if (bbc_cloud_build(&m, &s, &o.params, NULL, &c, &err) != BBC_OK) return fail(&err);
    step3[r] = bench_now() - t0;
    billboards = c.billboard_count;
    texels = c.texels;
    aw = c.mesh.textures[0].image.width;
    ah = c.mesh.textures[0].image.height;
    bbc_cloud_free(&c);
  }
  for (int r = 0; r < runs; r++) {
    double t0 = bench_now();
    bbc_mesh m2;
    bbc_planeset s2;
    bbc_cloud c;
    if (bbc_mesh_load(argv[1], NULL, &m2, &err) != BBC_OK ||
        bbc_planes_find(&m2, &o, &s2, &err) != BBC_OK ||
        bbc_cloud_build(&m2, &s2, &o.params, NULL, &c, &err) != BBC_OK ||
        bbc_mesh_write_gltf(argv[3], &c.mesh, NULL, &err) != BBC_OK)
      return fail(&err);
    whole[r] = bench_now() - t0;
    bbc_cloud_free(&c);
    bbc_planeset_free(&s2);
    bbc_mesh_free(&m2);
  }
  printf("{\"bench\": \"cloud\", \"model\": \"%s\", \"params\": \"%s\", \"triangles\": %zu, "
         "\"billboards\": %zu, \"texels\": %zu, \"atlas\": \"%dx%d\", \"runs\": %d, "
         "\"step3_s\": %.3f, \"obj_to_glb_s\": %.3f, \"peak_mib\": %.1f}\n",
         argv[1], params, m.triangle_count, billboards, texels, aw, ah, runs,
         bench_median(step3, runs), bench_median(whole, runs), bench_peak_rss_mib());
  bbc_planeset_free(&s);
  bbc_mesh_free(&m);
  return 0;
}
