/* bench_treegen — time of the built-in tree generator.
 *   bench_treegen SPECIES LEAVES RUNS
 * Prints one JSON object: triangles, median/min/max seconds, peak memory. */
#include "bbc.h"
#include "bench_common.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: bench_treegen SPECIES LEAVES RUNS\n");
    return 1;
  }
  bbc_tree_options opt;
  bbc_tree_options_default(&opt);
  opt.seed = 1; /* the tree these checks were written for */
  int sp = bbc_tree_species_from_name(argv[1]);
  if (sp < 0) {
    fprintf(stderr, "bench_treegen: unknown species %s\n", argv[1]);
    return 1;
  }
  opt.species = (bbc_tree_species)sp;
  opt.leaves = (size_t)strtoull(argv[2], NULL, 10);
  int runs = atoi(argv[3]);
  if (runs < 1 || runs > 99) runs = 5;
  double t[99];
  size_t tris = 0;
  for (int r = 0; r < runs; r++) {
    bbc_mesh m;
    bbc_error err;
    opt.seed = 1;
    double t0 = bench_now();
    if (bbc_tree_generate(&opt, &m, &err) != BBC_OK) {
      fprintf(stderr, "bench_treegen: %s\n", err.message);
      return 1;
    }
    t[r] = bench_now() - t0;
    tris = m.triangle_count;
    bbc_mesh_free(&m);
  }
  double mn, mx;
  bench_min_max(t, runs, &mn, &mx);
  printf("{\"bench\": \"treegen\", \"species\": \"%s\", \"leaves\": %zu, \"triangles\": %zu, "
         "\"runs\": %d, \"median_s\": %.4f, \"min_s\": %.4f, \"max_s\": %.4f, "
         "\"peak_mib\": %.1f}\n",
         argv[1], opt.leaves, tris, runs, bench_median(t, runs), mn, mx, bench_peak_rss_mib());
  return 0;
}
