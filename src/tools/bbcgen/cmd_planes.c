/* cmd_planes.c — `bbcgen planes MODEL [...] --json OUT`: steps 1 and 2, the
 * planes and the face -> plane assignment as JSON. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

/* The JSON holds results only (no timings), so that the same input and
 * parameters give byte-identical files with any thread count. */
static cJSON *planes_json(const bbc_planeset *s) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddNumberToObject(root, "epsilon_abs", s->epsilon_abs);
  cJSON_AddNumberToObject(root, "radius", s->radius);
  cJSON_AddStringToObject(root, "split", s->split_why);
  cJSON *parts = cJSON_AddArrayToObject(root, "parts");
  for (size_t i = 0; i < s->part_count; i++) {
    const bbc_part_result *p = &s->parts[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", p->name);
    cJSON_AddNumberToObject(o, "epsilon_abs", p->epsilon_abs);
    cJSON_AddNumberToObject(o, "faces", (double)p->face_count);
    cJSON_AddNumberToObject(o, "planes", (double)p->plane_count);
    cJSON_AddItemToObject(o, "center", cJSON_CreateDoubleArray(p->center, 3));
    cJSON_AddNumberToObject(o, "radius", p->radius);
    cJSON_AddNumberToObject(o, "grid_cells", (double)p->grid_cells);
    cJSON_AddItemToArray(parts, o);
  }
  cJSON *planes = cJSON_AddArrayToObject(root, "planes");
  for (size_t i = 0; i < s->plane_count; i++) {
    const bbc_plane *p = &s->planes[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddItemToObject(o, "normal", cJSON_CreateDoubleArray(p->normal, 3));
    cJSON_AddNumberToObject(o, "d", p->d);
    cJSON_AddStringToObject(o, "kind", bbc_plane_kind_name(p->kind));
    cJSON_AddNumberToObject(o, "faces", (double)p->face_count);
    cJSON_AddNumberToObject(o, "area", p->area);
    cJSON_AddStringToObject(o, "part", s->parts[p->part].name);
    if (p->leftover) cJSON_AddBoolToObject(o, "leftover", 1);
    if (p->kind == BBC_PLANE_CARDBOARD) {
      cJSON_AddNumberToObject(o, "mother", p->mother);
      cJSON_AddNumberToObject(o, "coverage_pct", p->coverage_pct);
    }
    cJSON_AddItemToArray(planes, o);
  }
  cJSON *fp = cJSON_AddArrayToObject(root, "face_plane");
  for (size_t i = 0; i < s->face_count; i++)
    cJSON_AddItemToArray(fp, cJSON_CreateNumber(s->face_plane[i] == BBC_NO_PLANE
                                                    ? -1 /* limbs: kept as a mesh */
                                                    : (double)s->face_plane[i]));
  return root;
}

int cmd_planes(cli *c, int argc, char **argv) {
  const char *path = NULL, *json_path = NULL;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *a = argv[i];
    if (!strcmp(a, "--json")) {
      if (!(json_path = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (a[0] == '-' && a[1]) {
      static const char *const own[] = {"--json", NULL};
      return cli_unknown_option("planes", a, own);
    } else if (!path) {
      path = a;
    } else {
      cli_error("planes: one model at a time");
      return EXIT_USAGE;
    }
  }
  if (!path) {
    cli_error("planes: usage: bbcgen planes MODEL [--epsilon E] [--set NAME=VALUE ...] "
              "[--json OUT.json]");
    return EXIT_USAGE;
  }
  return run_planes(c, path, json_path);
}

int run_planes(const cli *c, const char *path, const char *json_path) {
  if (json_path && !cli_output_ok("--json", json_path)) return EXIT_OUTPUT;
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  bbc_load_options lo;
  cli_load_options(c, &lo);
  lo.skip_textures = 1; /* steps 1 and 2 need geometry only */
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  bbc_planeset set;
  double t0 = cli_now();
  if (bbc_planes_find(&m, &po, &set, &err) != BBC_OK) {
    bbc_mesh_free(&m);
    return cli_fail(&err, 0);
  }
  double t1 = cli_now();
  cli_info(c, "parts: %s", set.split_why);
  for (size_t i = 0; i < set.part_count; i++) {
    const bbc_part_result *p = &set.parts[i];
    cli_info(c, "%-8s %7zu faces  eps %-9.4g %3zu planes  step 1 %.2f s  step 2 %.2f s", p->name,
             p->face_count, p->epsilon_abs, p->plane_count, p->step1_s, p->step2_s);
  }
  size_t kinds[BBC_PLANE_KIND_COUNT] = {0};
  for (size_t i = 0; i < set.plane_count; i++) kinds[set.planes[i].kind]++;
  cli_info(c,
           "%zu planes (%zu standard, %zu coplanar, %zu posttweaked, %zu cardboard, %zu "
           "parachute) in %.2f s",
           set.plane_count, kinds[0], kinds[1], kinds[2], kinds[3], kinds[4], t1 - t0);
  int rc = EXIT_OK;
  if (json_path) {
    cJSON *j = planes_json(&set);
    char *text = j ? cJSON_PrintUnformatted(j) : NULL;
    cJSON_Delete(j);
    if (!text) {
      cli_error("out of memory");
      rc = EXIT_RESOURCES;
    } else {
      size_t n = strlen(text);
      text[n] = '\n';
      if (bbc_write_file_atomic(json_path, text, n + 1, &err) != BBC_OK) rc = cli_fail(&err, 1);
      free(text);
    }
  }
  bbc_planeset_free(&set);
  bbc_mesh_free(&m);
  return rc;
}
