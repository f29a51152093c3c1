/* forest — the forest engine of the thesis (Perfect Motion, Appendix B):
 * command line, `--check`, and the log; loading is scene.c, the frame loop
 * and the controls run.c, the drawing src/gl/. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <math.h>
#include <time.h>
#include <unistd.h>

#include "bbc_forest.h"
#include "closest.h"
#include "run.h"

static void usage(FILE *f) {
  fprintf(f,
          "forest %s — the forest engine (thesis 3.2, Appendix B: Perfect Motion)\n"
          "\n"
          "Usage:\n"
          "  forest MAP [options]\n"
          "      Loads MAP (a map file as Appendix B defines it) and flies through it in a\n"
          "      window (OpenGL 4.5). Keys: mouse look; s/x faster/slower; a/d strafe;\n"
          "      y/c (or z/c) up/down; Space stop; q/e zoom out/in, w reset; F3 store and\n"
          "      F2 load positions (save/MAPNAME.txt beside the map); F1 wireframe;\n"
          "      F4 terrain; F5 objects; 1/2 terrain detail; 3 lock the terrain's\n"
          "      frustum; Left/Right turn the sun, Up/Down raise and lower it; F10\n"
          "      statistics; h key help; Esc quits.\n"
          "  forest MAP --size WxH [options]\n"
          "      The same drawing without a display (EGL), for screenshots and benchmarks.\n"
          "  forest --check MAP\n"
          "      Reads MAP and every model description file it names, builds the map's\n"
          "      world and checks that every file it needs is there and reads (each 3D\n"
          "      model once, with its textures). Prints a summary; every problem as\n"
          "      FILE:LINE: what is wrong.\n"
          "      Exit status 0 when the map is whole, 1 when something is wrong.\n"
          "  forest --demo-terrain DIR [--terrain-size N] [--seed S]\n"
          "                       [--terrain-kind hills|islands]\n"
          "      Writes a procedural landscape (hills: hills, a ridge, a lake, meadows,\n"
          "      forest floor, rock; islands: green islands with beaches in a sea) as\n"
          "      DIR/heightmap.png ((N+1)^2, default N 512) and DIR/colmap.png (N^2),\n"
          "      and prints the water level in heightmap units (0..255; a map's\n"
          "      waterheight is that times its heightscale): what `make demo` builds\n"
          "      its forest maps on.\n"
          "  forest --help | --version\n"
          "\n"
          "Options:\n"
          "  --size WxH           headless framebuffer size (with --window: the window's)\n"
          "  --window             a window even with --size (e.g. under xvfb-run)\n"
          "  --camera X,Y,Z,YAW,PITCH   start there (degrees; yaw 0 looks along -z, 90 along +x)\n"
          "  --path FILE          camera positions (lines: x y z yaw pitch) flown through over\n"
          "                       the frames, linearly\n"
          "  --frames N           frames to draw headless (default 1; 30 per --path position)\n"
          "  --screenshot PNG     write the last frame\n"
          "  --bench              print timings; the last line is\n"
          "                       frame_ms_median=… frame_ms_p95=… cpu_ms_median=…\n"
          "                       cull_ms_median=… cull_ms_p95=… terrain_ms_median=…\n"
          "                       trees_drawn=… billboards_drawn=… draw_calls=…\n"
          "                       draw_commands=… (frame: until the GPU is done; cpu:\n"
          "                       until the last GL call returns; cull: the CPU's culling\n"
          "                       and levels of the objects, 0 with --gpu-cull; draw calls:\n"
          "                       every draw, a multi-draw counting once; draw_commands:\n"
          "                       the commands of the objects' multi-draws)\n"
          "  --keys \"K K 30f shot:A.png K\"  scripted keys (names as in the list above:\n"
          "                       s x a d y c space q e w F1 F2 F3 F4 F5 F10 1 2 3 h esc\n"
          "                       left right up down, any\n"
          "                       case, z for y), Nf runs N frames of 1/30 s, shot:FILE writes\n"
          "                       a screenshot (shot:'FILE' for a name with blanks or commas);\n"
          "                       the program ends after the script (or at esc)\n"
          "  --sun AZ,EL          the sun's azimuth (degrees around the vertical: 0 towards\n"
          "                       +z, 90 towards +x) and elevation (above the horizon, -90\n"
          "                       to 90); default: the map's light. Lit models (polygon\n"
          "                       levels, clouds made with bbcgen's default --lighting\n"
          "                       material) and the terrain follow it; clouds with a baked\n"
          "                       light do not\n"
          "  --time SECONDS       the wind's clock at the first frame (default 0): the same\n"
          "                       time, the same picture (frames after it 1/30 s apart)\n"
          "  --stats              the statistics overlay (F10) from the start\n"
          "  --print-camera       print the final camera as --camera takes it\n"
          "  --uncompressed       textures as RGBA8 (by default cloud atlases with binary\n"
          "                       alpha and opaque images are BC1, an eighth of the memory)\n"
          "  --naive              draw the way the thesis did, to measure against: every tree\n"
          "                       tested and given its level one by one (no grid), and per\n"
          "                       tree, level and billboard its own draw call and texture bind\n"
          "  --gpu-cull           culling and levels of detail in a compute shader over every\n"
          "                       tree, drawn by indirect draws it fills in (off by default:\n"
          "                       on llvmpipe the CPU's cell culling is faster; docs/forest.md)\n"
          "  --reference          every tree at its own level, nothing left out but what\n"
          "                       is outside the view (no occlusion by the terrain): the\n"
          "                       picture to compare the default's with\n"
          "  --coverage           per frame, print how many pixels the objects cover\n"
          "                       (drawn again white on black: LOD transition checks)\n"
          "  --log FILE           the log (default: log.txt beside the map)\n"
          "\n"
          "Exit status: 0 done, 1 a file or the drawing failed, 2 bad usage.\n",
          BBC_VERSION_STRING);
}

static double clock_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

/* Models already read (each is read once however often it is placed). */
static char **g_seen;
static size_t g_seen_count;

/* Whether the 3D model at `path` reads; prints why not. */
static int model_reads(const char *where, int line, const char *name, const char *path) {
  for (size_t i = 0; i < g_seen_count; i++)
    if (!strcmp(g_seen[i], path)) return 1;
  if (!scene_file_exists(path)) {
    fprintf(stderr, "%s:%d: model '%s' not found (%s)\n", where, line, name, path);
    return 0;
  }
  size_t pl = strlen(path);
  if (pl >= 5 && !strcasecmp(path + pl - 5, ".json")) { /* an impostor (bbcgen impostor) */
    bbc_impostor imp;
    bbc_error err;
    if (bbc_impostor_read(path, &imp, &err) != BBC_OK) {
      fprintf(stderr, "%s:%d: impostor '%s': %s\n", where, line, name, err.message);
      return 0;
    }
    int y_up = imp.up == BBC_AXIS_Y;
    if (y_up)
      printf("    %s: an impostor, %d x %d %s frames of %d texels\n", name, imp.frames, imp.frames,
             imp.hemi ? "hemi-octahedral" : "octahedral", imp.frame_size);
    else
      fprintf(stderr, "%s:%d: impostor '%s': forest draws impostors of y-up models\n", where, line,
              name);
    bbc_impostor_free(&imp);
    return y_up;
  }
  bbc_load_options lo;
  bbc_load_options_default(&lo);
  scene_load_note note = {where, line, NULL, 0}; /* its textures are files it needs too */
  lo.callbacks.log = scene_load_warning;
  lo.callbacks.user = &note;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load(path, &lo, &m, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: model '%s': %s\n", where, line, name, err.message);
    return 0;
  }
  if (note.warnings) {
    bbc_mesh_free(&m);
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

/* Checks one placed file; prints problems, returns how many. */
static int check_file(const char *map_path, int line, const char *folder, const char *name) {
  char path[4096];
  scene_join(folder, name, path, sizeof path);
  if (scene_is_model_file(name)) return !model_reads(map_path, line, name, path);
  bbc_forest_model m;
  bbc_error err;
  if (bbc_forest_model_load(path, &m, &err) != BBC_OK) {
    fprintf(stderr, "%s:%d: model description '%s': %s\n", map_path, line, name, err.message);
    return 1;
  }
  char mfolder[4096];
  scene_folder_of(path, mfolder, sizeof mfolder);
  int bad = 0;
  for (size_t l = 0; l < m.lod_count; l++)
    for (int k = 0; k < m.lods[l].part_count; k++) {
      char p2[8192];
      scene_join(mfolder, m.lods[l].part[k].file, p2, sizeof p2);
      bad += !model_reads(path, m.lods[l].line, m.lods[l].part[k].file, p2);
    }
  if (!bad)
    printf("    %s: %zu LOD%s, %g to %g, fade %g%s\n", name, m.lod_count,
           m.lod_count == 1 ? "" : "s", m.lods[0].min_dist, m.lods[m.lod_count - 1].max_dist,
           m.fade, m.shadow_radius > 0 ? ", shadow" : "");
  bbc_forest_model_free(&m);
  return bad;
}

static int parse_size(const char *v, int *w, int *h) {
  char x, extra;
  return sscanf(v, "%d%c%d%c", w, &x, h, &extra) == 3 && (x == 'x' || x == 'X') && *w > 0 &&
         *h > 0 && *w <= 16384 && *h <= 16384;
}

static int draw_map(const char *map_path, run_options *o, const char *log_path) {
  char folder[4096], lp[4200];
  scene_folder_of(map_path, folder, sizeof folder);
  if (!log_path) {
    snprintf(lp, sizeof lp, "%s/log.txt", folder);
    log_path = lp;
  }
  if (!scene_file_exists(map_path)) { /* before the log, which goes beside it */
    fprintf(stderr, "forest: %s: no such map file\n", map_path);
    return 1;
  }
  FILE *log = fopen(log_path, "w");
  if (!log) fprintf(stderr, "forest: cannot write the log %s; going on without\n", log_path);
  if (log) fprintf(log, "forest %s: map %s\n", BBC_VERSION_STRING, map_path);
  scene s;
  double t0 = clock_s();
  if (!scene_load(&s, map_path, log, o->progress)) {
    if (log) {
      fprintf(log, "error: the map did not load (see the messages on stderr)\n");
      fclose(log);
    }
    scene_free(&s);
    return 1;
  }
  double load_s = clock_s() - t0;
  o->load_s = load_s;
  o->start_s = t0;
  if (log) {
    fprintf(log,
            "terrain %d x %d, %g units apart; %zu objects of %zu models; %zu triangles in %zu "
            "files; loaded in %.2f s\n",
            s.world.width, s.world.depth, s.world.spacing, s.world.instance_count, s.model_count,
            s.triangles_loaded, s.mesh_count, load_s);
    fflush(log);
  }
  if (o->progress)
    fprintf(stderr, "forest: %zu objects, %zu models, loaded in %.2f s\n", s.world.instance_count,
            s.model_count, load_s);
  for (size_t m = 0; o->gpu_cull && m < s.model_count; m++)
    if (s.models[m].lod_count > 8)
      fprintf(stderr,
              "forest: --gpu-cull: %s has %zu levels of detail; levels after the 8th are "
              "not drawn\n",
              s.models[m].name, s.models[m].lod_count);
  int status = run(&s, o, log);
  if (log) {
    fprintf(log, "done (exit status %d)\n", status);
    fclose(log);
  }
  scene_free(&s);
  return status;
}

static int demo_terrain(const char *dir, int size, uint32_t seed, bbc_forest_demo_kind kind) {
  bbc_image h, c;
  double water;
  bbc_error err;
  if (bbc_forest_demo_terrain(size, seed, kind, &h, &c, &water, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 1;
  }
  /* the folder itself when it is not there (its parent must be) */
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "forest: --demo-terrain %s: cannot create the folder: %s\n", dir,
            strerror(errno));
    bbc_image_free(&h);
    bbc_image_free(&c);
    return 1;
  }
  char p1[4200], p2[4200];
  snprintf(p1, sizeof p1, "%s/heightmap.png", dir);
  snprintf(p2, sizeof p2, "%s/colmap.png", dir);
  int ok =
      bbc_image_write_png(p1, &h, &err) == BBC_OK && bbc_image_write_png(p2, &c, &err) == BBC_OK;
  if (!ok)
    fprintf(stderr, "forest: %s\n", err.message);
  else
    printf("water_level=%.2f\n", water);
  bbc_image_free(&h);
  bbc_image_free(&c);
  return ok ? 0 : 1;
}

/* ---- --check ------------------------------------------------------------------- */

/* The six images of the sky box: each there and readable; the problems. */
static int check_sky(const bbc_forest_map *map, const char *map_path, const char *folder) {
  int bad = 0;
  static const char *const side[6] = {"FR", "BK", "LF", "RT", "UP", "DN"};
  for (int s = 0; s < 6; s++) {
    char name[4200], path[8400];
    snprintf(name, sizeof name, "%s_%s.tga", map->skymap, side[s]);
    scene_join(folder, name, path, sizeof path);
    bbc_image img;
    bbc_error e;
    if (!scene_file_exists(path)) {
      fprintf(stderr, "forest: %s:%d: skymap: sky image '%s' not found\n", map_path,
              map->skymap_line, name);
      bad++;
    } else if (bbc_image_load(path, &img, &e) != BBC_OK) {
      fprintf(stderr, "forest: %s:%d: skymap: %s\n", map_path, map->skymap_line, e.message);
      bad++;
    } else {
      bbc_image_free(&img);
    }
  }
  return bad;
}

/* The summary of the map's world: terrain, colour, sky, water, fog. */
static void print_world(const bbc_forest_map *map, const bbc_forest_world *w,
                        const char *map_path) {
  float lo = w->height[0], hi = w->height[0];
  for (size_t i = 0; i < (size_t)w->width * w->depth; i++) {
    if (w->height[i] < lo) lo = w->height[i];
    if (w->height[i] > hi) hi = w->height[i];
  }
  printf("map: %s\n", map_path);
  printf("terrain: %d x %d vertices (%d-bit heightmap), %g units apart, heights %.2f to %.2f\n",
         w->width, w->depth, w->heightmap_bits, w->spacing, lo, hi);
  if (w->note[0]) printf("note: %s\n", w->note);
  if (w->colour.rgba) printf("colour map: %d x %d\n", w->colour.width, w->colour.height);
  if (map->skymap) printf("sky: %s_FR/_BK/_LF/_RT/_UP/_DN\n", map->skymap);
  if (map->has_water) printf("water at %g\n", map->water_height);
  if (map->has_fog) printf("fog from %g to %g\n", map->fog_start, map->fog_end);
}

/* The objects placed and asked for, the green ground, then each placement
 * line with the files it needs checked; the problems. */
static int check_placements(const bbc_forest_map *map, const bbc_forest_world *w,
                            const char *map_path, const char *folder) {
  int bad = 0;
  size_t asked = 0;
  for (size_t i = 0; i < map->placement_count; i++) asked += map->placements[i].count;
  printf("objects: %zu placed of %zu asked, %zu line%s", w->instance_count, asked,
         map->placement_count, map->placement_count == 1 ? "" : "s");
  if (map->has_numobjs) printf(" (numobjs %zu)", map->numobjs);
  printf("\n");
  if (w->colour.rgba)
    printf("green ground (Appendix B: G > 70 and R < 2/3 G): %.1f %% of the colour map\n",
           100.0 * w->green_fraction);
  if (w->placements_short)
    printf("note: %zu rndtree line%s found too little green ground for all their objects\n",
           w->placements_short, w->placements_short == 1 ? "" : "s");
  for (size_t i = 0; i < map->placement_count; i++) {
    const bbc_forest_placement *p = &map->placements[i];
    static const char *const kind[3] = {"object2d", "rndtree", "rndtree2"};
    printf("  line %d %s %s%s%s: %zu\n", p->line, kind[p->kind], p->file, p->file2 ? " + " : "",
           p->file2 ? p->file2 : "", p->count);
    bad += check_file(map_path, p->line, folder, p->file);
    if (p->file2) bad += check_file(map_path, p->line, folder, p->file2);
  }
  return bad;
}

/* forest --check MAP: the exit status. */
static int check_map(const char *map_path) {
  bbc_forest_map map;
  bbc_error err;
  if (bbc_forest_map_load(map_path, &map, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    return 1;
  }
  char folder[4096];
  scene_folder_of(map_path, folder, sizeof folder);
  bbc_forest_world w;
  if (bbc_forest_world_build(&map, folder, &w, &err) != BBC_OK) {
    fprintf(stderr, "forest: %s\n", err.message);
    bbc_forest_map_free(&map);
    return 1;
  }
  print_world(&map, &w, map_path);
  int bad = 0;
  if (map.skymap) bad += check_sky(&map, map_path, folder);
  bad += check_placements(&map, &w, map_path, folder);
  if (bad) fprintf(stderr, "forest: %s: %d problem%s\n", map_path, bad, bad == 1 ? "" : "s");
  bbc_forest_world_free(&w);
  bbc_forest_map_free(&map);
  for (size_t i = 0; i < g_seen_count; i++) free(g_seen[i]);
  free(g_seen);
  return bad ? 1 : 0;
}

/* ---- the command line ------------------------------------------------------------ */

/* What the command line asks for. */
typedef struct settings {
  const char *map_path, *log_path, *demo_dir;
  int check, window, size_given, terrain_size;
  bbc_forest_demo_kind terrain_kind;
  unsigned long seed;
  run_options o;
} settings;

static int takes_value(const char *a) {
  return !strcmp(a, "--size") || !strcmp(a, "--camera") || !strcmp(a, "--path") ||
         !strcmp(a, "--frames") || !strcmp(a, "--screenshot") || !strcmp(a, "--keys") ||
         !strcmp(a, "--log") || !strcmp(a, "--demo-terrain") || !strcmp(a, "--terrain-size") ||
         !strcmp(a, "--seed") || !strcmp(a, "--terrain-kind") || !strcmp(a, "--sun") ||
         !strcmp(a, "--time");
}

/* The options without a value; 0 when `a` is none of them. */
static int set_flag(settings *st, const char *a) {
  run_options *o = &st->o;
  if (!strcmp(a, "--check"))
    st->check = 1;
  else if (!strcmp(a, "--window"))
    st->window = 1;
  else if (!strcmp(a, "--bench"))
    o->bench = 1;
  else if (!strcmp(a, "--stats"))
    o->stats = 1;
  else if (!strcmp(a, "--naive"))
    o->naive = 1;
  else if (!strcmp(a, "--uncompressed"))
    o->uncompressed = 1;
  else if (!strcmp(a, "--gpu-cull"))
    o->gpu_cull = 1;
  else if (!strcmp(a, "--reference"))
    o->reference = 1;
  else if (!strcmp(a, "--coverage"))
    o->coverage = 1;
  else if (!strcmp(a, "--print-camera"))
    o->print_camera = 1;
  else
    return 0;
  return 1;
}

/* --camera X,Y,Z,YAW,PITCH; 0 with a message when it is not one. */
static int parse_camera(const char *v, bbc_forest_camera *c) {
  char extra;
  int good = sscanf(v, "%lf,%lf,%lf,%lf,%lf%c", &c->pos[0], &c->pos[1], &c->pos[2], &c->yaw,
                    &c->pitch, &extra) == 5;
  for (int k = 0; k < 3 && good; k++) good = fabs(c->pos[k]) <= 1e7; /* false for NaN */
  good = good && fabs(c->yaw) <= 36000 && fabs(c->pitch) <= 89;
  if (!good)
    fprintf(stderr,
            "forest: --camera %s: expected X,Y,Z,YAW,PITCH (numbers; coordinates within "
            "+-1e7, pitch within +-89)\n",
            v);
  return good;
}

/* The options that check their value as a number or a kind: 1 when `a` is
 * one of them and its value `v` is good, -1 when it is bad (said), 0 when
 * `a` is none of them. */
static int set_checked_value(settings *st, const char *a, const char *v) {
  run_options *o = &st->o;
  if (!strcmp(a, "--size")) {
    if (!parse_size(v, &o->width, &o->height)) {
      fprintf(stderr, "forest: --size %s: expected WxH, e.g. 640x480\n", v);
      return -1;
    }
    st->size_given = 1;
  } else if (!strcmp(a, "--camera")) {
    if (!parse_camera(v, &o->camera)) return -1;
    o->has_camera = 1;
  } else if (!strcmp(a, "--frames")) {
    char *end;
    long n = strtol(v, &end, 10);
    if (*end || n < 1 || n > 10000000) {
      fprintf(stderr, "forest: --frames %s: expected a number of frames (1 to 10,000,000)\n", v);
      return -1;
    }
    o->frames = (int)n;
  } else if (!strcmp(a, "--sun")) {
    char extra;
    double az, el;
    if (sscanf(v, "%lf,%lf%c", &az, &el, &extra) != 2 || !(fabs(az) <= 3600) || !(fabs(el) <= 90)) {
      fprintf(stderr,
              "forest: --sun %s: expected AZIMUTH,ELEVATION in degrees (e.g. 135,30; "
              "elevation -90 to 90)\n",
              v);
      return -1;
    }
    o->has_sun = 1;
    o->sun_azimuth = az;
    o->sun_elevation = el;
  } else if (!strcmp(a, "--time")) {
    char *end;
    double t = strtod(v, &end);
    if (*end || end == v || !(t >= 0 && t <= 1e6)) {
      fprintf(stderr, "forest: --time %s: expected seconds, 0 to 1,000,000\n", v);
      return -1;
    }
    o->time = t;
  } else if (!strcmp(a, "--terrain-kind")) {
    if (!strcmp(v, "hills"))
      st->terrain_kind = BBC_FOREST_DEMO_HILLS;
    else if (!strcmp(v, "islands"))
      st->terrain_kind = BBC_FOREST_DEMO_ISLANDS;
    else {
      fprintf(stderr, "forest: --terrain-kind %s: expected hills or islands\n", v);
      return -1;
    }
  } else if (!strcmp(a, "--terrain-size") || !strcmp(a, "--seed")) {
    char *end;
    unsigned long n = strtoul(v, &end, 10);
    if (*end || !*v || n > 0xFFFFFFFFul) {
      fprintf(stderr, "forest: %s %s: expected a whole number\n", a, v);
      return -1;
    }
    if (a[2] == 't')
      st->terrain_size = (int)(n > 65536 ? 65536 : n);
    else
      st->seed = n;
  } else {
    return 0;
  }
  return 1;
}

/* The options with a value: as set_checked_value. */
static int set_value(settings *st, const char *a, const char *v) {
  run_options *o = &st->o;
  if (!strcmp(a, "--path")) {
    o->path = v;
  } else if (!strcmp(a, "--screenshot")) {
    size_t vl = strlen(v);
    if (vl < 4 || strcasecmp(v + vl - 4, ".png")) {
      fprintf(stderr, "forest: --screenshot %s: screenshots are written as .png\n", v);
      return -1;
    }
    o->screenshot = v;
  } else if (!strcmp(a, "--keys")) {
    o->keys = v;
  } else if (!strcmp(a, "--demo-terrain")) {
    st->demo_dir = v;
  } else if (!strcmp(a, "--log")) {
    st->log_path = v;
  } else {
    return set_checked_value(st, a, v);
  }
  return 1;
}

static void unknown_option(const char *a) {
  static const char *const known[] = {
      "--help",      "--version",      "--check",        "--window",
      "--stats",     "--naive",        "--uncompressed", "--gpu-cull",
      "--reference", "--coverage",     "--print-camera", "--size",
      "--camera",    "--frames",       "--path",         "--screenshot",
      "--keys",      "--demo-terrain", "--terrain-kind", "--terrain-size",
      "--seed",      "--log",          "--bench",        NULL};
  const char *near = cli_closest(a, known);
  if (near)
    fprintf(stderr, "forest: unknown option '%s' (did you mean %s?)\n", a, near);
  else
    fprintf(stderr, "forest: unknown option '%s' (try forest --help)\n", a);
}

/* Reads the command line into `st`: -1 to go on, else the exit status
 * (0 after --help or --version, 2 for bad usage, said). */
static int parse_options(int argc, char **argv, settings *st) {
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    const char *v = i + 1 < argc ? argv[i + 1] : NULL;
    int takes = takes_value(a);
    if (takes && !v) {
      fprintf(stderr, "forest: %s needs a value (try forest --help)\n", a);
      return 2;
    }
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "--version")) {
      printf("forest %s\n", BBC_VERSION_STRING);
      return 0;
    } else if (set_flag(st, a)) {
      continue;
    } else if (takes) {
      if (set_value(st, a, v) < 0) return 2;
      i++;
    } else if (a[0] == '-' && a[1]) {
      unknown_option(a);
      return 2;
    } else if (!st->map_path) {
      st->map_path = a;
    } else {
      fprintf(stderr, "forest: one map at a time ('%s' is a second one)\n", a);
      return 2;
    }
  }
  return -1;
}

int main(int argc, char **argv) {
  settings st;
  memset(&st, 0, sizeof st);
  st.terrain_size = 512;
  st.terrain_kind = BBC_FOREST_DEMO_HILLS;
  st.seed = 1;
  st.o.width = 1024;
  st.o.height = 768;
  st.o.progress = isatty(2);
  int rc = parse_options(argc, argv, &st);
  if (rc >= 0) return rc;
  if (st.demo_dir)
    return demo_terrain(st.demo_dir, st.terrain_size, (uint32_t)st.seed, st.terrain_kind);
  if (st.o.naive && st.o.gpu_cull) {
    fprintf(stderr, "forest: --naive and --gpu-cull do not go together (--naive draws the "
                    "thesis's way, culling on the CPU tree by tree)\n");
    return 2;
  }
  if (!st.map_path) {
    usage(stderr);
    return 2;
  }
  if (scene_is_model_file(st.map_path)) { /* a model where a map belongs */
    fprintf(stderr,
            "forest: %s is a 3D model, not a map: forest takes a map file (Appendix B, "
            "docs/forest.md) whose object2d and rndtree lines place models. To look at this "
            "one: bbcgen view %s\n",
            st.map_path, st.map_path);
    return 2;
  }
  if (!st.check) {
    st.o.headless = st.size_given && !st.window;
    return draw_map(st.map_path, &st.o, st.log_path);
  }
  return check_map(st.map_path);
}
