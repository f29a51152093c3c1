/* forest — the forest engine of the thesis (Perfect Motion, Appendix B),
 * being rebuilt (issue 12). What exists: reading a map and every model
 * description file it names, building its world and checking that every
 * file is there (`--check`). Drawing does not exist yet. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "bbc.h"

static void usage(FILE *f) {
  fprintf(f,
          "forest %s — the forest engine (thesis 3.2, Appendix B), being rebuilt\n"
          "\n"
          "Usage:\n"
          "  forest --check MAP\n"
          "      Reads MAP (a map file as Appendix B defines it) and every model\n"
          "      description file it names, builds the map's world (terrain, colour map,\n"
          "      objects placed on the ground) and checks that every file it needs is\n"
          "      there and reads (every 3D model and LOD file is loaded once). Prints a\n"
          "      summary; every problem as FILE:LINE: what is wrong.\n"
          "      Exit status 0 when the map is whole, 1 when something is wrong or\n"
          "      missing.\n"
          "  forest --help | --version\n"
          "\n"
          "Not built yet: drawing the forest (a window, flying through it).\n",
          BBC_VERSION_STRING);
}

static int file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Models already read (each is read once however often it is placed). */
static char **g_seen;
static size_t g_seen_count;

/* Whether the 3D model at `path` reads; prints why not. */
static int model_reads(const char *where, int line, const char *name, const char *path) {
  for (size_t i = 0; i < g_seen_count; i++)
    if (!strcmp(g_seen[i], path)) return 1;
  if (!file_exists(path)) {
    fprintf(stderr, "%s:%d: model '%s' not found (%s)\n", where, line, name, path);
    return 0;
  }
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  lo.load_textures = 0;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: model '%s': %s\n", where, line, name, err.message);
    return 0;
  }
  printf("    %s: %zu triangles\n", name, m.triangle_count);
  bbc_mesh_free(&m);
  char **s2 = realloc(g_seen, (g_seen_count + 1) * sizeof *s2);
  if (s2) {
    g_seen = s2;
    g_seen[g_seen_count] = strdup(path);
    if (g_seen[g_seen_count]) g_seen_count++;
  }
  return 1;
}

static void folder_of(const char *path, char *out, size_t n) {
  snprintf(out, n, "%s", path);
  char *slash = strrchr(out, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(out, n, ".");
}

static void join(const char *folder, const char *name, char *out, size_t n) {
  if (name[0] == '/')
    snprintf(out, n, "%s", name);
  else
    snprintf(out, n, "%s/%s", folder, name);
}

/* A 3D model by its extension; anything else is a model description file. */
static int is_model_file(const char *name) {
  const char *dot = strrchr(name, '.');
  static const char *const ext[] = {".wrl", ".glb", ".gltf", ".obj",
                                    ".3ds", ".ply", ".dae",  ".fbx"};
  for (size_t i = 0; dot && i < sizeof ext / sizeof ext[0]; i++)
    if (!strcasecmp(dot, ext[i])) return 1;
  return 0;
}

/* Checks one placed file; prints problems, returns how many. */
static int check_file(const char *map_path, int line, const char *folder, const char *name) {
  char path[4096];
  join(folder, name, path, sizeof path);
  if (is_model_file(name)) return !model_reads(map_path, line, name, path);
  bbc_forest_model m;
  bbc_error err;
  if (bbc_forest_model_load(path, &m, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: model description '%s': %s\n", map_path, line, name, err.message);
    return 1;
  }
  char mfolder[4096];
  folder_of(path, mfolder, sizeof mfolder);
  int bad = 0;
  for (size_t l = 0; l < m.lod_count; l++)
    for (int k = 0; k < m.lods[l].part_count; k++) {
      char p2[8192];
      join(mfolder, m.lods[l].part[k].file, p2, sizeof p2);
      bad += !model_reads(path, m.lods[l].line, m.lods[l].part[k].file, p2);
    }
  if (!bad)
    printf("    %s: %zu LOD%s, %g to %g, fade %g%s\n", name, m.lod_count,
           m.lod_count == 1 ? "" : "s", m.lods[0].min_dist, m.lods[m.lod_count - 1].max_dist,
           m.fade, m.shadow_radius > 0 ? ", shadow" : "");
  bbc_forest_model_free(&m);
  return bad;
}

int main(int argc, char **argv) {
  const char *map_path = NULL;
  int check = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    }
    if (!strcmp(argv[i], "--version")) {
      printf("forest %s\n", BBC_VERSION_STRING);
      return 0;
    }
    if (!strcmp(argv[i], "--check")) {
      check = 1;
    } else if (argv[i][0] == '-' && argv[i][1]) {
      fprintf(stderr, "forest: unknown option '%s' (try forest --help)\n", argv[i]);
      return 2;
    } else if (!map_path) {
      map_path = argv[i];
    } else {
      fprintf(stderr, "forest: one map at a time ('%s' is a second one)\n", argv[i]);
      return 2;
    }
  }
  if (!map_path) {
    usage(stderr);
    return 2;
  }
  if (!check) {
    fprintf(stderr,
            "forest: drawing a forest is not built yet (issue 12); `forest --check %s` reads "
            "and checks the map\n",
            map_path);
    return 2;
  }
  bbc_forest_map map;
  bbc_error err;
  if (bbc_forest_map_load(map_path, &map, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 1;
  }
  char folder[4096];
  folder_of(map_path, folder, sizeof folder);
  bbc_forest_world w;
  if (bbc_forest_world_build(&map, folder, &w, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    bbc_forest_map_free(&map);
    return 1;
  }
  float lo = w.height[0], hi = w.height[0];
  for (size_t i = 0; i < (size_t)w.width * w.depth; i++) {
    if (w.height[i] < lo) lo = w.height[i];
    if (w.height[i] > hi) hi = w.height[i];
  }
  printf("map: %s\n", map_path);
  printf("terrain: %d x %d vertices (%d-bit heightmap), %g units apart, heights %g to %g\n",
         w.width, w.depth, w.heightmap_bits, w.spacing, lo, hi);
  if (w.note[0]) printf("note: %s\n", w.note);
  if (w.colour.rgba) printf("colour map: %d x %d\n", w.colour.width, w.colour.height);
  if (map.skymap) printf("sky: %s_FR/_BK/_LF/_RT/_UP/_DN\n", map.skymap);
  if (map.has_water) printf("water at %g\n", map.water_height);
  if (map.has_fog) printf("fog from %g to %g\n", map.fog_start, map.fog_end);
  int bad = 0;
  if (map.skymap) {
    static const char *const side[6] = {"FR", "BK", "LF", "RT", "UP", "DN"};
    for (int s = 0; s < 6; s++) {
      char name[4200], path[8400];
      snprintf(name, sizeof name, "%s_%s.tga", map.skymap, side[s]);
      join(folder, name, path, sizeof path);
      if (!file_exists(path)) {
        fprintf(stderr, "%s: sky image '%s' not found\n", map_path, name);
        bad++;
      }
    }
  }
  size_t asked = 0;
  for (size_t i = 0; i < map.placement_count; i++) asked += map.placements[i].count;
  printf("objects: %zu placed of %zu asked, %zu line%s", w.instance_count, asked,
         map.placement_count, map.placement_count == 1 ? "" : "s");
  if (map.has_numobjs) printf(" (numobjs %zu)", map.numobjs);
  printf("\n");
  if (w.colour.rgba)
    printf("green ground (Appendix B: G > 70 and R < 2/3 G): %.1f %% of the colour map\n",
           100.0 * w.green_fraction);
  if (w.placements_short)
    printf("note: %zu rndtree line%s found too little green ground for all their objects\n",
           w.placements_short, w.placements_short == 1 ? "" : "s");
  for (size_t i = 0; i < map.placement_count; i++) {
    const bbc_forest_placement *p = &map.placements[i];
    static const char *const kind[3] = {"object2d", "rndtree", "rndtree2"};
    printf("  line %d %s %s%s%s: %zu\n", p->line, kind[p->kind], p->file, p->file2 ? " + " : "",
           p->file2 ? p->file2 : "", p->count);
    bad += check_file(map_path, p->line, folder, p->file);
    if (p->file2) bad += check_file(map_path, p->line, folder, p->file2);
  }
  if (bad) fprintf(stderr, "forest: %s: %d problem%s\n", map_path, bad, bad == 1 ? "" : "s");
  bbc_forest_world_free(&w);
  bbc_forest_map_free(&map);
  for (size_t i = 0; i < g_seen_count; i++) free(g_seen[i]);
  free(g_seen);
  return bad ? 1 : 0;
}
