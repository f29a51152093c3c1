/* bench_planes — steps 1 and 2 (plane selection) on a model.
 *   bench_planes MODEL RUNS [NAME=VALUE ...]
 * Prints one JSON object: triangles, parts, planes, median step 1 and
 * step 2 seconds (summed over the parts), peak memory. */
#include "bbc.h"
#include "bench_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: bench_planes MODEL RUNS [NAME=VALUE ...]\n");
    return 1;
  }
  int runs = atoi(argv[2]);
  if (runs < 1 || runs > 99) runs = 3;
  bbc_planes_options o;
  bbc_planes_options_default(&o);
  bbc_error err;
  char params[512] = "";
  for (int i = 3; i < argc; i++) {
    if (bbc_params_set_assignment(&o.params, argv[i], &err) != BBC_OK) {
      fprintf(stderr, "bench_planes: %s\n", err.message);
      return 1;
    }
    size_t l = strlen(params);
    snprintf(params + l, sizeof params - l, "%s%s", l ? " " : "", argv[i]);
  }
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.skip_textures = 1;
  bbc_mesh m;
  if (bbc_mesh_load(argv[1], &lo, &m, &err) != BBC_OK) {
    fprintf(stderr, "bench_planes: %s\n", err.message);
    return 1;
  }
  double s1[99], s2[99], total[99];
  size_t planes = 0, parts = 0, part_planes[2] = {0, 0};
  for (int r = 0; r < runs; r++) {
    bbc_planeset s;
    double t0 = bench_now();
    if (bbc_planes_find(&m, &o, &s, &err) != BBC_OK) {
      fprintf(stderr, "bench_planes: %s\n", err.message);
      return 1;
    }
    total[r] = bench_now() - t0;
    s1[r] = s2[r] = 0;
    for (size_t p = 0; p < s.part_count; p++) {
      s1[r] += s.parts[p].step1_s;
      s2[r] += s.parts[p].step2_s;
      if (p < 2) part_planes[p] = s.parts[p].plane_count;
    }
    planes = s.plane_count;
    parts = s.part_count;
    bbc_planeset_free(&s);
  }
  printf("{\"bench\": \"planes\", \"model\": \"%s\", \"params\": \"%s\", \"triangles\": %zu, "
         "\"parts\": %zu, \"planes\": %zu, \"planes_part0\": %zu, \"planes_part1\": %zu, "
         "\"runs\": %d, \"step1_s\": %.3f, \"step2_s\": %.3f, \"median_s\": %.3f, "
         "\"peak_mib\": %.1f}\n",
         argv[1], params, m.triangle_count, parts, planes, part_planes[0], part_planes[1], runs,
         bench_median(s1, runs), bench_median(s2, runs), bench_median(total, runs),
         bench_peak_rss_mib());
  bbc_mesh_free(&m);
  return 0;
}
