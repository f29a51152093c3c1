/* run.c — flying through a loaded map: the frame loop (window or
 * headless), Appendix B's controls, scripted keys, camera paths,
 * screenshots, statistics and the benchmark line. */
#include "run.h"

#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>

#include <GLFW/glfw3.h>

#include "bbcgl.h"

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

/* ---- state and controls (Appendix B) ------------------------------------- */

typedef struct state {
  scene *s;
  const run_options *o;
  FILE *log;
  int gpu_failed; /* --gpu-cull could not run (said once) */
  bbc_forest_camera cam;
  double speed, strafe, lift; /* units per second */
  double unit;                /* speed step per key press */
  double detail;              /* roetger */
  int locked;                 /* terrain frustum locked (key 3) */
  float locked_viewproj[16];
  double locked_eye[3];
  int wireframe, no_terrain, no_objects, stats, help, quit;
  bbc_forest_camera *stored;
  size_t stored_count, stored_next;
  char save_path[4600];
  char message[600];
  double message_until;
  /* mouse */
  double mouse_x, mouse_y;
  int mouse_known;
  double sun_azimuth, sun_elevation; /* degrees (--sun, the map's light, the arrow keys) */
  int clock_started;                 /* the wind's clock: --time at the first frame */
  double clock_start;
} state;

__attribute__((format(printf, 3, 4))) static void say(state *st, double t, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(st->message, sizeof st->message, fmt, ap);
  va_end(ap);
  st->message_until = t + 3;
  if (st->log) {
    fprintf(st->log, "%s\n", st->message);
    fflush(st->log);
  }
}

static void store_position(state *st, double t) {
  char dir[4300];
  snprintf(dir, sizeof dir, "%s/save", st->s->folder);
  if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
    say(st, t, "cannot make the folder %s", dir);
    return;
  }
  bbc_error err;
  if (bbc_forest_positions_append(st->save_path, &st->cam, &err) != BBC_OK) {
    say(st, t, "%s", err.message);
    return;
  }
  free(st->stored);
  st->stored = NULL;
  st->stored_count = 0;
  bbc_forest_positions_read(st->save_path, &st->stored, &st->stored_count, &err);
  /* F2 goes to the position just stored first, then on round the file */
  st->stored_next = st->stored_count ? st->stored_count - 1 : 0;
  say(st, t, "position %zu stored in %s", st->stored_count, st->save_path);
}

static void load_position(state *st, double t) {
  bbc_error err;
  if (!st->stored_count) {
    free(st->stored);
    st->stored = NULL;
    if (bbc_forest_positions_read(st->save_path, &st->stored, &st->stored_count, &err) != BBC_OK) {
      say(st, t, "%s", err.message);
      return;
    }
  }
  if (!st->stored_count) {
    say(st, t, "no stored positions in %s (F3 stores one)", st->save_path);
    return;
  }
  double zoom = st->cam.zoom;
  st->cam = st->stored[st->stored_next++ % st->stored_count];
  st->cam.zoom = zoom;
  st->speed = st->strafe = st->lift = 0;
  say(st, t, "position %zu of %zu loaded", (st->stored_next - 1) % st->stored_count + 1,
      st->stored_count);
}

/* Keys by name, the same for GLFW's callback and scripts. */
static int handle_key(state *st, const char *name, double t) {
  /* names as --help lists them, in any case; z is y (German keyboards) */
  static const char *const names[] = {"s", "x",  "a",   "d",    "y",     "c",  "space", "q", "e",
                                      "w", "F1", "F2",  "F3",   "F4",    "F5", "F10",   "1", "2",
                                      "3", "h",  "esc", "left", "right", "up", "down"};
  const char *k = NULL;
  for (size_t i = 0; i < sizeof names / sizeof names[0] && !k; i++)
    if (!strcasecmp(name, names[i])) k = names[i];
  if (!strcasecmp(name, "z")) k = "y";
  if (!k) return 0;
  if (!strcmp(k, "s")) {
    st->speed += st->unit;
  } else if (!strcmp(k, "x")) {
    st->speed -= st->unit;
  } else if (!strcmp(k, "a")) {
    st->strafe -= st->unit;
  } else if (!strcmp(k, "d")) {
    st->strafe += st->unit;
  } else if (!strcmp(k, "y")) {
    st->lift += st->unit;
  } else if (!strcmp(k, "c")) {
    st->lift -= st->unit;
  } else if (!strcmp(k, "space")) {
    st->speed = st->strafe = st->lift = 0;
  } else if (!strcmp(k, "q")) {
    st->cam.zoom /= 1.25;
  } else if (!strcmp(k, "e")) {
    st->cam.zoom *= 1.25;
  } else if (!strcmp(k, "w")) {
    st->cam.zoom = 1;
  } else if (!strcmp(k, "F1")) {
    st->wireframe = !st->wireframe;
  } else if (!strcmp(k, "F2")) {
    load_position(st, t);
  } else if (!strcmp(k, "F3")) {
    store_position(st, t);
  } else if (!strcmp(k, "F4")) {
    st->no_terrain = !st->no_terrain;
  } else if (!strcmp(k, "F5")) {
    st->no_objects = !st->no_objects;
  } else if (!strcmp(k, "F10")) {
    st->stats = !st->stats;
  } else if (!strcmp(k, "1") || !strcmp(k, "2")) {
    st->detail *= k[0] == '1' ? 1 / 1.25 : 1.25;
    say(st, t, "terrain detail (roetger) %.2f", st->detail);
  } else if (!strcmp(k, "3")) {
    st->locked = !st->locked;
    say(st, t, "terrain frustum %s", st->locked ? "locked" : "unlocked");
  } else if (!strcmp(k, "left") || !strcmp(k, "right")) {
    st->sun_azimuth = fmod(st->sun_azimuth + (k[0] == 'l' ? -15 : 15) + 360, 360);
    say(st, t, "sun: azimuth %.0f, elevation %.0f", st->sun_azimuth, st->sun_elevation);
  } else if (!strcmp(k, "up") || !strcmp(k, "down")) {
    st->sun_elevation += k[0] == 'u' ? 5 : -5;
    if (st->sun_elevation > 90) st->sun_elevation = 90;
    if (st->sun_elevation < -10) st->sun_elevation = -10;
    say(st, t, "sun: azimuth %.0f, elevation %.0f", st->sun_azimuth, st->sun_elevation);
  } else if (!strcmp(k, "h")) {
    st->help = !st->help;
  } else if (!strcmp(k, "esc")) {
    st->quit = 1;
  } else {
    return 0;
  }
  return 1;
}

static const char *glfw_key_name(int key) {
  static char one[2];
  if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
    one[0] = (char)('a' + key - GLFW_KEY_A);
    one[1] = 0;
    return one;
  }
  switch (key) {
  case GLFW_KEY_1:
    return "1";
  case GLFW_KEY_2:
    return "2";
  case GLFW_KEY_3:
    return "3";
  case GLFW_KEY_LEFT:
    return "left";
  case GLFW_KEY_RIGHT:
    return "right";
  case GLFW_KEY_UP:
    return "up";
  case GLFW_KEY_DOWN:
    return "down";
  case GLFW_KEY_SPACE:
    return "space";
  case GLFW_KEY_ESCAPE:
    return "esc";
  case GLFW_KEY_F1:
    return "F1";
  case GLFW_KEY_F2:
    return "F2";
  case GLFW_KEY_F3:
    return "F3";
  case GLFW_KEY_F4:
    return "F4";
  case GLFW_KEY_F5:
    return "F5";
  case GLFW_KEY_F10:
    return "F10";
  default:
    return NULL;
  }
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  if (action == GLFW_RELEASE) return;
  state *st = glfwGetWindowUserPointer(w);
  const char *k = glfw_key_name(key);
  /* z and y swap places on German keyboards (the thesis's): accept both */
  if (key == GLFW_KEY_Z) k = "y";
  if (k) handle_key(st, k, glfwGetTime());
}

static void on_mouse(GLFWwindow *w, double x, double y) {
  state *st = glfwGetWindowUserPointer(w);
  if (st->mouse_known) {
    st->cam.yaw += (x - st->mouse_x) * 0.15 / st->cam.zoom;
    st->cam.pitch -= (y - st->mouse_y) * 0.15 / st->cam.zoom;
    if (st->cam.pitch > 89) st->cam.pitch = 89;
    if (st->cam.pitch < -89) st->cam.pitch = -89;
  }
  st->mouse_x = x;
  st->mouse_y = y;
  st->mouse_known = 1;
}

/* Moves the camera by its speeds over dt seconds; never below the ground. */
static void move(state *st, double dt) {
  double f[3];
  bbc_forest_camera_get_forward(&st->cam, f);
  double yaw = st->cam.yaw * 3.14159265358979323846 / 180;
  double right[3] = {cos(yaw), 0, sin(yaw)};
  for (int k = 0; k < 3; k++) st->cam.pos[k] += (f[k] * st->speed + right[k] * st->strafe) * dt;
  st->cam.pos[1] += st->lift * dt;
  double ground = bbc_forest_world_get_height(&st->s->world, st->cam.pos[0], st->cam.pos[2]);
  /* eye height 1.7 units (a person, if a unit is a metre) */
  double floor_y = ground + 1.7;
  if (st->s->map.has_water && st->s->map.water_height + 0.5 > floor_y)
    floor_y = st->s->map.water_height + 0.5;
  if (st->cam.pos[1] < floor_y) st->cam.pos[1] = floor_y;
}

/* ---- one frame --------------------------------------------------------------- */

typedef struct frame_result {
  double frame_ms;   /* CPU time of the frame up to its last GL call (no waiting for the GPU) */
  double cull_ms;    /* object culling and levels of detail */
  double terrain_ms; /* the terrain's node selection */
  bbcgl_stats stats;
  size_t per_level[8];
  bbcgl_counters counters; /* --bench: what the GPU did (pipeline statistics) */
} frame_result;

static void draw_frame(state *st, bbcgl_context *ctx, bbcgl_forest *r, double fps,
                       frame_result *res, double t) {
  int w, h;
  bbcgl_context_size(ctx, &w, &h);
  if (w < 1 || h < 1) return;
  double t0 = now_s();
  bbcgl_frame fr;
  memset(&fr, 0, sizeof fr);
  double near_clip = st->s->world.spacing * 0.05 > 0.05 ? st->s->world.spacing * 0.05 : 0.05;
  bbc_forest_camera_get_viewproj(&st->cam, (double)w / h, near_clip, st->s->far_clip, fr.viewproj);
  memcpy(fr.eye, st->cam.pos, sizeof fr.eye);
  fr.width = w;
  fr.height = h;
  fr.wireframe = st->wireframe;
  fr.no_terrain = st->no_terrain;
  fr.no_objects = st->no_objects;
  bbc_forest_sun_direction(st->sun_azimuth, st->sun_elevation, fr.sun);
  if (!st->clock_started) {
    st->clock_started = 1;
    st->clock_start = t;
  }
  fr.time = st->o->time + (t - st->clock_start);
  if (!st->locked) {
    memcpy(st->locked_viewproj, fr.viewproj, sizeof fr.viewproj);
    memcpy(st->locked_eye, fr.eye, sizeof fr.eye);
  }
  double c0 = now_s();
  bbc_forest_terrain_select(&st->s->terrain, &st->s->world, st->locked_viewproj, st->locked_eye,
                            st->detail);
  res->terrain_ms = (now_s() - c0) * 1000;
  c0 = now_s();
  /* occlusion by the terrain where it is drawn, solid, for this eye */
  int occlude = !st->o->reference && !st->no_terrain && !st->wireframe && !st->locked;
  bbc_forest_cull_set_occluder(st->s->cull, occlude ? &st->s->occluder : NULL,
                               occlude ? &st->s->terrain : NULL);
  if (st->o->naive)
    bbc_forest_cull_run_flat(st->s->cull, fr.viewproj, fr.eye, st->cam.zoom);
  else if (!st->o->gpu_cull)
    bbc_forest_cull_run(st->s->cull, fr.viewproj, fr.eye, st->cam.zoom);
  fr.naive = st->o->naive;
  fr.gpu_cull = st->o->gpu_cull && !st->o->naive;
  fr.zoom = st->cam.zoom;
  /* with --gpu-cull the CPU culls nothing: the work is in the frame's GPU time */
  res->cull_ms = fr.gpu_cull ? 0 : (now_s() - c0) * 1000;
  bbcgl_context_begin(ctx);
  if (st->o->bench) bbcgl_context_counters_begin(ctx);
  bbcgl_forest_draw(r, &fr, &st->s->terrain, st->s->cull, &res->stats);
  if (fr.gpu_cull && !st->gpu_failed && bbcgl_forest_gpu_cull_error(r)) {
    fprintf(stderr, "forest: --gpu-cull: %s\n", bbcgl_forest_gpu_cull_error(r));
    st->gpu_failed = 1;
    st->quit = 1;
  }
  memset(res->per_level, 0, sizeof res->per_level);
  bbc_forest_records rec;
  bbc_forest_cull_get_records(st->s->cull, &rec);
  for (size_t m = 0; m < st->s->model_count && !st->no_objects; m++)
    for (size_t l = 0; l < st->s->models[m].lod_count; l++) {
      size_t b = rec.bucket_base[m] + l;
      res->per_level[l < 7 ? l : 7] += bbc_forest_cull_get_bucket_size(st->s->cull, b);
    }
  const char *lines[24];
  char buf[8][160];
  size_t n = 0;
  if (st->stats) {
    snprintf(buf[0], sizeof buf[0], "FPS %.1f  frame %.1f ms  cull %.2f ms", fps,
             fps > 0 ? 1000 / fps : 0, res->cull_ms);
    int len = snprintf(buf[1], sizeof buf[1], "trees %zu  per LOD:", res->stats.trees);
    for (int l = 0; l < 8 && len < 150; l++)
      if (res->per_level[l])
        len += snprintf(buf[1] + len, sizeof buf[1] - (size_t)len, " %d=%zu", l, res->per_level[l]);
    snprintf(buf[2], sizeof buf[2], "billboards %zu  triangles %zu", res->stats.billboards,
             res->stats.triangles);
    snprintf(buf[3], sizeof buf[3], "draw calls %zu  texture binds %zu  terrain nodes %zu",
             res->stats.draw_calls, res->stats.texture_binds, res->stats.terrain_nodes);
    snprintf(buf[4], sizeof buf[4], "detail %.2f%s  zoom %.2f  pos %.0f %.0f %.0f", st->detail,
             st->locked ? " (locked)" : "", st->cam.zoom, st->cam.pos[0], st->cam.pos[1],
             st->cam.pos[2]);
    for (int i = 0; i < 5; i++) lines[n++] = buf[i];
  }
  if (st->help) {
    static const char *const help[] = {
        "mouse: look   s/x: faster/slower   a/d: strafe   y/c: up/down",
        "space: stop   q/e: zoom out/in   w: zoom reset",
        "F3: store position   F2: next stored position",
        "F1: wireframe   F4: terrain   F5: objects   F10: statistics",
        "1/2: terrain detail   3: lock terrain frustum   h: this help   esc: quit",
        "left/right: turn the sun   up/down: raise/lower the sun"};
    for (size_t i = 0; i < sizeof help / sizeof help[0]; i++) lines[n++] = help[i];
  }
  if (st->message[0] && t < st->message_until) lines[n++] = st->message;
  if (n) bbcgl_forest_text(r, w, h, lines, n, h >= 600 ? 2 : 1);
  res->frame_ms = (now_s() - t0) * 1000;
  if (st->o->bench) bbcgl_context_counters_end(ctx, &res->counters);
  if (st->o->coverage) { /* the same frame again: objects only, white on black */
    fr.fill_colour = 1;
    bbcgl_stats dummy;
    bbcgl_forest_draw(r, &fr, &st->s->terrain, st->s->cull, &dummy);
    bbc_image im;
    char err[BBCGL_ERR];
    size_t covered = 0;
    if (bbcgl_context_read(ctx, &im, err)) {
      for (size_t i = 0; i < (size_t)im.width * im.height; i++) covered += im.rgba[4 * i] > 127;
      if (getenv("FOREST_DEBUG_FILL")) bbc_image_write_png(getenv("FOREST_DEBUG_FILL"), &im, NULL);
      bbc_image_free(&im);
    }
    printf("coverage=%zu pos=%.3f,%.3f,%.3f\n", covered, st->cam.pos[0], st->cam.pos[1],
           st->cam.pos[2]);
    fr.fill_colour = 0;
    bbcgl_forest_draw(r, &fr, &st->s->terrain, st->s->cull, &dummy); /* what is shown */
  }
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static int screenshot(bbcgl_context *ctx, const char *path) {
  bbc_image im;
  char err[BBCGL_ERR];
  if (!bbcgl_context_read(ctx, &im, err)) {
    fprintf(stderr, "forest: %s\n", err);
    return 0;
  }
  bbc_error e;
  int ok = bbc_image_write_png(path, &im, &e) == BBC_OK;
  if (!ok) fprintf(stderr, "forest: %s\n", e.message);
  bbc_image_free(&im);
  return ok;
}

/* ---- set-up ------------------------------------------------------------------ */

/* The GL context: a window, or headless with --size. */
static bbcgl_context *open_context(const run_options *o, FILE *log) {
  char err[BBCGL_ERR];
  bbcgl_context *ctx = o->headless ? bbcgl_context_headless(o->width, o->height, err)
                                   : bbcgl_context_window(o->width, o->height, "forest", err);
  if (!ctx) {
    fprintf(stderr, "forest: %s%s\n", err,
            o->headless ? "" : "; headless drawing needs --size WxH");
    if (log) fprintf(log, "error: %s\n", err);
    return NULL;
  }
  if (log) fprintf(log, "%s\n", bbcgl_context_describe(ctx));
  return ctx;
}

/* The drawing side of the scene: terrain, water, fog, sky and one bucket
 * per model and level, each with its parts' meshes. */
static bbcgl_forest *create_forest(scene *s, const run_options *o) {
  char err[BBCGL_ERR];
  bbcgl_scene sc;
  memset(&sc, 0, sizeof sc);
  sc.world = &s->world;
  sc.terrain_colour = &s->terrain_colour;
  sc.wind = s->map.wind;
  sc.has_water = s->map.has_water;
  sc.water_height = s->map.water_height;
  if (s->map.has_fog) {
    sc.fog_start = s->map.fog_start;
    sc.fog_end = s->map.fog_end;
  } else { /* a light haze that ends at the far clip, so the clip is not seen */
    sc.fog_start = s->far_clip * 0.6;
    sc.fog_end = s->far_clip;
  }
  for (int i = 0; i < 6 && s->has_sky; i++) sc.sky[i] = &s->sky[i];
  bbc_forest_records rec;
  bbc_forest_cull_get_records(s->cull, &rec);
  sc.bucket_count = rec.bucket_count;
  sc.uncompressed = o->uncompressed;
  bbcgl_forest *r = bbcgl_forest_create(&sc, err);
  if (!r) {
    fprintf(stderr, "forest: %s\n", err);
    return NULL;
  }
  for (size_t m = 0; m < s->model_count; m++)
    for (size_t l = 0; l < s->models[m].lod_count; l++)
      for (int k = 0; k < s->models[m].part_count[l]; k++) {
        const scene_part *p = &s->models[m].parts[l][k];
        const scene_mesh *me = &s->meshes[p->mesh];
        bbcgl_part_options po = {p->lit,         p->mipmap,
                                 me->billboards, (float)s->models[m].height,
                                 me->occlusion,  me->impostor};
        if (!bbcgl_forest_add_part(r, rec.bucket_base[m] + l, &me->mesh, &po, err)) {
          fprintf(stderr, "forest: %s: %s\n", me->path, err);
          bbcgl_forest_free(r);
          return NULL;
        }
      }
  return r;
}

/* The controls' state at the start: the camera where Appendix B puts it
 * (or --camera's), above the ground and the water. */
static void init_state(state *st, scene *s, const run_options *o, FILE *log) {
  memset(st, 0, sizeof *st);
  st->s = s;
  st->o = o;
  st->log = log;
  st->detail = s->map.roetger > 0 ? s->map.roetger : 10;
  st->unit = s->extent / 200;
  st->stats = o->stats;
  st->help = !o->headless && !o->keys ? 2 : 0; /* 2: shown at the start for 10 s */
  snprintf(st->save_path, sizeof st->save_path, "%s/save/%s.txt", s->folder, s->map_name);
  /* Appendix B: the viewer starts in the map's top left corner. */
  st->cam.zoom = 1;
  st->cam.pos[0] = s->extent * 0.02;
  st->cam.pos[2] = s->extent * 0.02;
  st->cam.pos[1] =
      bbc_forest_world_get_height(&s->world, st->cam.pos[0], st->cam.pos[2]) + s->extent * 0.04;
  st->cam.yaw = 135;
  st->cam.pitch = -8;
  if (o->has_camera) {
    st->cam = o->camera;
    st->cam.zoom = 1;
  }
  if (o->has_sun) {
    st->sun_azimuth = o->sun_azimuth;
    st->sun_elevation = o->sun_elevation;
  } else {
    bbc_forest_sun_angles(s->map.light, &st->sun_azimuth, &st->sun_elevation);
  }
  move(st, 0); /* never starts below the ground or the water */
}

/* --path's camera positions; 0 with a message when the file is missing or
 * holds none. */
static int read_path(const run_options *o, bbc_forest_camera **path, size_t *path_count) {
  bbc_error e;
  FILE *probe = fopen(o->path, "r");
  bbc_result pr = BBC_ERROR_NOT_FOUND;
  if (!probe) {
    snprintf(e.message, sizeof e.message, "--path %s: no such file", o->path);
  } else {
    fclose(probe);
    pr = bbc_forest_positions_read(o->path, path, path_count, &e);
    if (pr == BBC_OK && !*path_count)
      snprintf(e.message, sizeof e.message, "--path %s: no positions (lines: x y z yaw pitch)",
               o->path);
  }
  if (pr != BBC_OK || !*path_count) {
    fprintf(stderr, "forest: %s\n", e.message);
    free(*path); /* a file without positions still gave an array */
    *path = NULL;
    return 0;
  }
  return 1;
}

static void connect_window(GLFWwindow *win, state *st, const run_options *o) {
  glfwSetWindowUserPointer(win, st);
  glfwSetKeyCallback(win, on_key);
  /* scripted keys are the only input: the pointer's events (one arrives
   * when the window appears under it, at a moment that varies) would turn
   * the camera and make the run differ from one time to the next */
  if (!o->keys) glfwSetCursorPosCallback(win, on_mouse);
  if (!o->keys) glfwSetInputMode(win, GLFW_CURSOR, GLFW_CURSOR_DISABLED);
}

/* ---- the frames ------------------------------------------------------------------ */

/* What one run holds between its stages. */
typedef struct runner {
  state st;
  const run_options *o;
  bbcgl_context *ctx;
  bbcgl_forest *r;
  GLFWwindow *win;
  bbc_forest_camera *path; /* --path's positions */
  size_t path_count;
  frame_result res; /* the last frame's */
  double t, fps;    /* the scripted clock; the frame rate the overlay shows */
  double ready_s;   /* --bench: when the first frame was drawn */
} runner;

/* Per frame, for --bench: the whole frame (waiting for the GPU), its CPU
 * part up to the last GL call, object culling, terrain selection; and what
 * was drawn. */
typedef struct frame_records {
  double (*ms)[4];
  size_t *trees, *bills, *calls, *cmds;
  double (*gpu)[3]; /* vertices, primitives, fragments (pipeline statistics) */
  int gpu_counted;
} frame_records;

static int records_alloc(frame_records *rec, size_t frames) {
  rec->gpu = calloc(frames + 1, sizeof *rec->gpu);
  rec->ms = calloc(frames + 1, sizeof *rec->ms);
  rec->trees = calloc(frames + 1, sizeof *rec->trees);
  rec->bills = calloc(frames + 1, sizeof *rec->bills);
  rec->calls = calloc(frames + 1, sizeof *rec->calls);
  rec->cmds = calloc(frames + 1, sizeof *rec->cmds);
  return rec->ms && rec->trees && rec->bills && rec->calls && rec->cmds && rec->gpu;
}

static void records_free(frame_records *rec) {
  free(rec->gpu);
  free(rec->ms);
  free(rec->cmds);
  free(rec->trees);
  free(rec->bills);
  free(rec->calls);
}

/* The next step of a --keys script at *p (blanks and commas before it
 * skipped), cut in place; NULL at the end. shot:"FILE" or shot:'FILE' may
 * hold blanks and commas (the quotes dropped). */
static char *next_step(char **p) {
  char *s = *p;
  while (*s == ' ' || *s == ',') s++;
  if (!*s) return NULL;
  char *tok = s;
  if (!strncmp(s, "shot:", 5) && (s[5] == '"' || s[5] == '\'')) {
    char q = s[5];
    memmove(s + 5, s + 6, strlen(s + 6) + 1); /* the opening quote */
    char *e = strchr(s + 5, q);
    if (e) {
      *e = 0;
      *p = e + 1;
    } else {
      *p = s + strlen(s);
    }
    return tok;
  }
  while (*s && *s != ' ' && *s != ',') s++;
  if (*s) *s++ = 0;
  *p = s;
  return tok;
}

/* --keys: names, numbers of frames to run, shot:FILE. The exit status: 2
 * for a bad step (the script stops there), 1 when a screenshot failed. */
static int run_keys(runner *u) {
  const double script_dt = 1.0 / 30;
  int status = 0;
  char *copy = strdup(u->o->keys), *save = copy;
  for (char *tok = copy ? next_step(&save) : NULL; tok && !u->st.quit; tok = next_step(&save)) {
    char *end;
    long nframes = strtol(tok, &end, 10);
    if (!strncmp(tok, "shot:", 5) && !tok[5]) {
      fprintf(stderr, "forest: --keys: 'shot:' needs a file name (shot:FILE.png)\n");
      status = 2;
      break;
    } else if (!strncmp(tok, "shot:", 5)) {
      draw_frame(&u->st, u->ctx, u->r, u->fps, &u->res, u->t);
      if (!screenshot(u->ctx, tok + 5)) status = 1;
      bbcgl_context_end(u->ctx);
    } else if (end != tok && end[0] == 'f' && end[1] == '\0' &&
               (nframes < 1 || nframes > 10000000)) {
      fprintf(stderr, "forest: --keys: %s: frames from 1 to 10,000,000\n", tok);
      status = 2;
      break;
    } else if (end != tok && end[0] == 'f' && end[1] == '\0') {
      for (long i = 0; i < nframes && !u->st.quit; i++) {
        if (u->win) glfwPollEvents();
        move(&u->st, script_dt);
        u->t += script_dt;
        draw_frame(&u->st, u->ctx, u->r, u->fps, &u->res, u->t);
        bbcgl_context_end(u->ctx);
        u->fps = u->res.frame_ms > 0 ? 1000 / u->res.frame_ms : 0;
      }
    } else if (!handle_key(&u->st, tok, u->t)) {
      fprintf(stderr,
              "forest: --keys: unknown key or step '%s' (keys: s x a d y c space q e w "
              "F1 F2 F3 F4 F5 F10 1 2 3 h esc left right up down, any case, z for y; frames "
              "to run "
              "as Nf, e.g. 30f; shot:FILE.png)\n",
              tok);
      status = 2;
      break;
    }
  }
  free(copy);
  return status;
}

/* The window's loop: the mouse and keys fly until Esc or the window closes. */
static void run_window(runner *u) {
  double last = glfwGetTime(), fps_t = last;
  int fps_n = 0;
  while (!glfwWindowShouldClose(u->win) && !u->st.quit) {
    glfwPollEvents();
    double tn = glfwGetTime();
    move(&u->st, tn - last);
    last = tn;
    draw_frame(&u->st, u->ctx, u->r, u->fps, &u->res, tn);
    if (tn > 10 && u->st.help == 2) u->st.help = 0; /* the help shown at the start goes */
    bbcgl_context_end(u->ctx);
    fps_n++;
    if (tn - fps_t >= 0.5) {
      u->fps = fps_n / (tn - fps_t);
      fps_t = tn;
      fps_n = 0;
    }
  }
}

/* Frame i of `frames` along --path: positions and pitch linear, the yaw
 * the short way round. */
static void path_camera(runner *u, size_t i, size_t frames) {
  const bbc_forest_camera *path = u->path;
  size_t path_count = u->path_count;
  state *st = &u->st;
  double v = frames > 1 ? (double)i / (frames - 1) * (path_count - 1) : 0;
  size_t a = (size_t)v < path_count - 1 ? (size_t)v : path_count - 1;
  size_t b = a + 1 < path_count ? a + 1 : a;
  double f = v - a;
  double zoom = st->cam.zoom;
  for (int k = 0; k < 3; k++) st->cam.pos[k] = path[a].pos[k] * (1 - f) + path[b].pos[k] * f;
  double dy = path[b].yaw - path[a].yaw;
  while (dy > 180) dy -= 360;
  while (dy < -180) dy += 360;
  st->cam.yaw = path[a].yaw + dy * f;
  st->cam.pitch = path[a].pitch * (1 - f) + path[b].pitch * f;
  st->cam.zoom = zoom;
  move(st, 0); /* above the ground */
}

/* The frames without a window (or after a key script): along --path, or
 * flying on at the speeds the keys left; --screenshot of the last one.
 * *frames becomes 0 when the key script ended with esc. The exit status:
 * 1 when the screenshot failed. */
static int run_frames(runner *u, size_t *frames_io, frame_records *rec) {
  const double script_dt = 1.0 / 30;
  const run_options *o = u->o;
  size_t frames = *frames_io;
  int status = 0;
  if (o->bench) { /* one frame not counted: shaders are compiled at their first use */
    draw_frame(&u->st, u->ctx, u->r, u->fps, &u->res, u->t);
    bbcgl_context_end(u->ctx);
    u->ready_s = now_s() - o->start_s;
  }
  if (u->st.quit) frames = 0; /* esc in a key script ends the run there */
  for (size_t i = 0; i < frames; i++) {
    if (u->path_count)
      path_camera(u, i, frames);
    else if (i)
      move(&u->st, script_dt);
    u->t += script_dt;
    double f0 = now_s();
    draw_frame(&u->st, u->ctx, u->r, u->fps, &u->res, u->t);
    if (i + 1 == frames && o->screenshot && !screenshot(u->ctx, o->screenshot)) status = 1;
    bbcgl_context_end(u->ctx);
    rec->ms[i][0] = (now_s() - f0) * 1000;
    rec->ms[i][1] = u->res.frame_ms;
    rec->ms[i][2] = u->res.cull_ms;
    rec->ms[i][3] = u->res.terrain_ms;
    rec->trees[i] = u->res.stats.trees;
    rec->bills[i] = u->res.stats.billboards;
    rec->calls[i] = u->res.stats.draw_calls;
    rec->cmds[i] = u->res.stats.draw_commands;
    rec->gpu[i][0] = (double)u->res.counters.vertices;
    rec->gpu[i][1] = (double)u->res.counters.primitives;
    rec->gpu[i][2] = (double)u->res.counters.fragments;
    rec->gpu_counted = u->res.counters.available;
    u->fps = u->res.frame_ms > 0 ? 1000 / u->res.frame_ms : 0;
    if (o->progress && frames > 1) fprintf(stderr, "\rforest: frame %zu of %zu", i + 1, frames);
  }
  if (o->progress && frames > 1) fprintf(stderr, "\n");
  *frames_io = frames;
  return status;
}

/* ---- --bench's lines ----------------------------------------------------------- */

/* Each model's textures in MiB as the GPU holds them (BC1 or RGBA8, with
 * the mip levels), each image once. */
static void print_texture_memory(const scene *s, const bbcgl_forest *r) {
  for (size_t m = 0; m < s->model_count; m++) {
    const uint8_t *seen[64];
    size_t nseen = 0;
    double bytes = 0;
    for (size_t l = 0; l < s->models[m].lod_count; l++)
      for (int k = 0; k < s->models[m].part_count[l]; k++) {
        const bbc_mesh *me = &s->meshes[s->models[m].parts[l][k].mesh].mesh;
        for (size_t ti = 0; ti < me->texture_count; ti++) {
          const bbc_image *im = &me->textures[ti].image;
          int dup = !im->rgba;
          for (size_t q = 0; q < nseen && !dup; q++) dup = seen[q] == im->rgba;
          if (dup) continue;
          if (nseen < 64) seen[nseen++] = im->rgba;
          bytes += (double)bbcgl_forest_texture_bytes(r, im, s->models[m].parts[l][k].mipmap);
        }
      }
    printf(" texture_mb[%s]=%.2f", s->models[m].name, bytes / (1024.0 * 1024.0));
  }
}

/* The medians and 95th percentiles of the frames' times, the means of what
 * they drew, the load time and the memory. */
static void print_bench(const runner *u, const scene *s, size_t frames, const frame_records *rec) {
  const run_options *o = u->o;
  double *sorted = malloc(frames * sizeof *sorted), med[4], p95[4];
  size_t k95 = (size_t)ceil(0.95 * frames) - 1;
  for (int q = 0; q < 4 && sorted; q++) {
    for (size_t i = 0; i < frames; i++) sorted[i] = rec->ms[i][q];
    qsort(sorted, frames, sizeof *sorted, cmp_double);
    med[q] = sorted[frames / 2];
    p95[q] = sorted[k95];
  }
  if (sorted) {
    size_t tsum = 0, bsum = 0, csum = 0, dsum = 0;
    for (size_t i = 0; i < frames; i++) {
      tsum += rec->trees[i];
      bsum += rec->bills[i];
      csum += rec->calls[i];
      dsum += rec->cmds[i];
    }
    printf("frames=%zu size=%dx%d renderer=\"%s\"\n", frames, o->width, o->height,
           bbcgl_context_describe(u->ctx));
    /* memory: the peak so far (ru_maxrss, kB on Linux), the instance
     * records, and each model's textures */
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("load_s=%.3f ready_s=%.3f peak_rss_mb=%.1f objects=%zu instance_bytes=%zu", o->load_s,
           u->ready_s, ru.ru_maxrss / 1024.0, s->world.instance_count, sizeof(bbc_forest_instance));
    print_texture_memory(s, u->r);
    printf("\n");
    printf("frame_ms_median=%.3f frame_ms_p95=%.3f cpu_ms_median=%.3f cull_ms_median=%.3f "
           "cull_ms_p95=%.3f terrain_ms_median=%.3f trees_drawn=%zu billboards_drawn=%zu "
           "draw_calls=%zu draw_commands=%zu\n",
           med[0], p95[0], med[1], med[2], p95[2], med[3], tsum / frames, bsum / frames,
           csum / frames, dsum / frames);
    /* what a GPU pays, from pipeline statistics: medians over the frames */
    if (rec->gpu_counted) {
      double gm[3];
      for (int q = 0; q < 3; q++) {
        for (size_t i = 0; i < frames; i++) sorted[i] = rec->gpu[i][q];
        qsort(sorted, frames, sizeof *sorted, cmp_double);
        gm[q] = sorted[frames / 2];
      }
      printf("vertices=%.0f primitives=%.0f fragments=%.0f fragments_per_pixel=%.3f\n", gm[0],
             gm[1], gm[2], gm[2] / ((double)o->width * o->height));
    } else {
      printf("counters=unavailable (no pipeline statistics queries)\n");
    }
  }
  free(sorted);
}

/* ---- the run ------------------------------------------------------------------- */

int run(scene *s, const run_options *o, FILE *log) {
  runner u;
  memset(&u, 0, sizeof u);
  u.o = o;
  u.ctx = open_context(o, log);
  if (!u.ctx) return 1;
  u.r = create_forest(s, o);
  if (!u.r) {
    bbcgl_context_free(u.ctx);
    return 1;
  }
  init_state(&u.st, s, o, log);
  if (o->path && !read_path(o, &u.path, &u.path_count)) {
    bbcgl_forest_free(u.r);
    bbcgl_context_free(u.ctx);
    return 1;
  }
  int status = 0;
  u.win = bbcgl_context_window_handle(u.ctx);
  if (u.win) connect_window(u.win, &u.st, o);
  size_t frames = o->frames > 0 ? (size_t)o->frames : (u.path_count > 1 ? u.path_count * 30 : 1);
  frame_records rec;
  if (!records_alloc(&rec, frames)) {
    fprintf(stderr, "forest: out of memory\n");
    status = 1;
    goto done;
  }
  if (o->keys) {
    status = run_keys(&u);
    if (status) goto done;
  }
  if (u.win && !o->keys) {
    run_window(&u);
  } else {
    status = run_frames(&u, &frames, &rec);
    if (o->bench && frames == 0)
      printf("frames=0 (esc in the key script)\n");
    else if (o->bench)
      print_bench(&u, s, frames, &rec);
  }
  if (o->keys && o->screenshot) {
    draw_frame(&u.st, u.ctx, u.r, u.fps, &u.res, u.t);
    if (!screenshot(u.ctx, o->screenshot)) status = 1;
    bbcgl_context_end(u.ctx);
  }
  if (o->print_camera)
    printf("camera=%.3f,%.3f,%.3f,%.2f,%.2f\n", u.st.cam.pos[0], u.st.cam.pos[1], u.st.cam.pos[2],
           u.st.cam.yaw, u.st.cam.pitch);
  if (u.st.gpu_failed) status = 1;
done:
  records_free(&rec);
  free(u.path);
  free(u.st.stored);
  bbcgl_forest_free(u.r);
  bbcgl_context_free(u.ctx);
  return status;
}
