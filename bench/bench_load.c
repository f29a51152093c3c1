/* bench_load — time of loading a model into the library's mesh.
 *   bench_load MODEL RUNS
 * Prints one JSON object: triangles, median/min/max seconds, peak memory. */
#include "bbc.h"
#include "bench_common.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: bench_load MODEL RUNS\n");
    return 1;
  }
  int runs = atoi(argv[2]);
  if (runs < 1 || runs > 99) runs = 3;
  double t[99];
  size_t tris = 0, verts = 0;
  int is_points = 0;
  for (int r = 0; r < runs; r++) {
    bbc_mesh m;
    bbc_error err;
    double t0 = bench_now();
    if (bbc_mesh_load(argv[1], NULL, &m, &err) != BBC_OK) {
      fprintf(stderr, "bench_load: %s\n", err.message);
      return 1;
    }
    t[r] = bench_now() - t0;
    tris = m.triangles_read;
    verts = m.vertex_count;
    is_points = m.kind == BBC_MESH_POINTS;
    bbc_mesh_free(&m);
  }
  double mn, mx;
  bench_min_max(t, runs, &mn, &mx);
  printf("{\"bench\": \"load\", \"model\": \"%s\", \"triangles\": %zu, \"vertices\": %zu, "
         "\"points\": %zu, "
         "\"runs\": %d, \"median_s\": %.4f, \"min_s\": %.4f, \"max_s\": %.4f, "
         "\"peak_mib\": %.1f}\n",
         argv[1], tris, verts, is_points ? verts : (size_t)0, runs, bench_median(t, runs), mn, mx,
         bench_peak_rss_mib());
  return 0;
}
