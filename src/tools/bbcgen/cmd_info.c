/* cmd_info.c — `bbcgen info MODEL [--json]` and `bbcgen setup`. */
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

static cJSON *vec3(const double *v) {
  return cJSON_CreateDoubleArray(v, 3);
}

static char *info_json(const char *path, const bbc_mesh *m, const size_t *group_tris) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "file", path);
  cJSON_AddStringToObject(root, "kind", m->kind == BBC_MESH_POINTS ? "points" : "triangles");
  /* triangles: as read (after triangulation); the zero-area ones among them
   * are dropped and counted; groups count the triangles kept. */
  cJSON_AddNumberToObject(root, "triangles", (double)m->triangles_read);
  cJSON_AddNumberToObject(root, "triangles_used", (double)m->triangle_count);
  cJSON_AddNumberToObject(root, "vertices", (double)m->vertex_count);
  if (m->kind == BBC_MESH_POINTS) cJSON_AddNumberToObject(root, "points", (double)m->vertex_count);
  cJSON_AddNumberToObject(root, "dropped_degenerate", (double)m->dropped_degenerate);
  cJSON_AddBoolToObject(root, "normals_generated", m->normals_generated);
  cJSON *mats = cJSON_AddArrayToObject(root, "materials");
  for (size_t i = 0; i < m->material_count; i++) {
    const bbc_material *mat = &m->materials[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", mat->name);
    const bbc_texture *t = mat->texture >= 0 ? &m->textures[mat->texture] : NULL;
    if (t && t->path)
      cJSON_AddStringToObject(o, "texture", t->path);
    else
      cJSON_AddNullToObject(o, "texture");
    cJSON_AddBoolToObject(o, "texture_has_alpha", t ? t->has_alpha : 0);
    if (mat->texture_ref && !t) cJSON_AddStringToObject(o, "texture_missing", mat->texture_ref);
    double c[4] = {mat->base_color[0], mat->base_color[1], mat->base_color[2], mat->base_color[3]};
    cJSON_AddItemToObject(o, "base_color", cJSON_CreateDoubleArray(c, 4));
    cJSON_AddBoolToObject(o, "unlit", mat->unlit);
    cJSON_AddItemToArray(mats, o);
  }
  cJSON *groups = cJSON_AddArrayToObject(root, "groups");
  for (size_t g = 0; g < m->group_count; g++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", m->group_names[g]);
    cJSON_AddNumberToObject(o, "triangles", (double)group_tris[g]);
    cJSON_AddItemToArray(groups, o);
  }
  cJSON *bbox = cJSON_AddObjectToObject(root, "bbox");
  cJSON_AddItemToObject(bbox, "min", vec3(m->bbox_min));
  cJSON_AddItemToObject(bbox, "max", vec3(m->bbox_max));
  cJSON_AddItemToObject(root, "origin", vec3(m->origin));
  cJSON_AddItemToObject(root, "center", vec3(m->center));
  cJSON_AddNumberToObject(root, "radius", m->radius);
  char *s = cJSON_Print(root);
  cJSON_Delete(root);
  return s;
}

static void info_text(const char *path, const bbc_mesh *m, const size_t *group_tris) {
  printf("%s\n", path);
  if (m->kind == BBC_MESH_POINTS)
    printf("  point cloud: %zu points%s%s\n", m->vertex_count, m->colors ? ", colours" : "",
           m->normals ? ", normals" : "");
  else
    printf("  %zu triangles, %zu vertices%s%s\n", m->triangles_read, m->vertex_count,
           m->uvs ? ", UVs" : "", m->normals_generated ? ", normals computed" : "");
  if (m->dropped_degenerate)
    printf("  dropped %zu zero-area triangles, %zu used\n", m->dropped_degenerate,
           m->triangle_count);
  if (m->material_count) printf("  materials (%zu):\n", m->material_count);
  for (size_t i = 0; i < m->material_count; i++) {
    const bbc_material *mat = &m->materials[i];
    const bbc_texture *t = mat->texture >= 0 ? &m->textures[mat->texture] : NULL;
    printf("    %-24s colour %.2f %.2f %.2f %.2f", mat->name[0] ? mat->name : "(unnamed)",
           mat->base_color[0], mat->base_color[1], mat->base_color[2], mat->base_color[3]);
    if (t)
      printf("  texture %s (%dx%d%s)", t->path ? t->path : "(generated)", t->image.width,
             t->image.height, t->has_alpha ? ", alpha" : "");
    else if (mat->texture_ref)
      printf("  texture %s MISSING", mat->texture_ref);
    printf("\n");
  }
  if (m->group_count) printf("  groups (%zu):\n", m->group_count);
  for (size_t g = 0; g < m->group_count; g++)
    printf("    %-24s %zu triangles\n", m->group_names[g][0] ? m->group_names[g] : "(unnamed)",
           group_tris[g]);
  printf("  bbox   [%g %g %g] .. [%g %g %g]\n", m->bbox_min[0], m->bbox_min[1], m->bbox_min[2],
         m->bbox_max[0], m->bbox_max[1], m->bbox_max[2]);
  printf("  centre [%g %g %g] (centre of gravity)\n", m->center[0], m->center[1], m->center[2]);
  printf("  radius %g (bounding sphere around the centre)\n", m->radius);
  if (m->origin[0] != 0 || m->origin[1] != 0 || m->origin[2] != 0)
    printf("  origin [%.3f %.3f %.3f] subtracted from the file's coordinates (they lie far\n"
           "         from 0: positions above and in outputs are relative to it)\n",
           m->origin[0], m->origin[1], m->origin[2]);
}

int cmd_info(cli *c, int argc, char **argv) {
  const char *path = NULL;
  int json = 0, textures = 1;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    if (!strcmp(argv[i], "--json"))
      json = 1;
    else if (!strcmp(argv[i], "--no-textures"))
      textures = 0;
    else if (argv[i][0] == '-' && argv[i][1]) {
      static const char *const own[] = {"--json", "--no-textures", NULL};
      return cli_unknown_option("info", argv[i], own);
    } else if (!path)
      path = argv[i];
    else {
      cli_error("info: one model at a time ('%s' and '%s')", path, argv[i]);
      return EXIT_USAGE;
    }
  }
  if (!path) {
    cli_error("info: which model? usage: bbcgen info MODEL [--json]");
    return EXIT_USAGE;
  }
  bbc_load_options opt;
  cli_load_options(c, &opt);
  opt.skip_textures = !textures;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &opt, &m, &err) != BBC_OK) return cli_fail(&err, 0);
  size_t *counts = calloc(m.group_count ? m.group_count : 1, sizeof *counts);
  if (!counts) {
    bbc_mesh_free(&m);
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  bbc_mesh_count_group_triangles(&m, counts);
  int rc = EXIT_OK;
  if (json) {
    char *s = info_json(path, &m, counts);
    if (s) {
      printf("%s\n", s);
      free(s);
    } else {
      cli_error("out of memory");
      rc = EXIT_RESOURCES;
    }
  } else {
    info_text(path, &m, counts);
  }
  free(counts);
  bbc_mesh_free(&m);
  return rc;
}

int cmd_setup(cli *c, int argc, char **argv) {
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (!k) {
      return cli_unknown_option("setup", argv[i], NULL);
    }
  }
  for (size_t i = 0; i < bbc_param_count(); i++) {
    const bbc_param_info *p = bbc_param_at(i);
    printf("%-14s %g\n", p->name, bbc_params_get(&c->params, p));
  }
  return EXIT_OK;
}
