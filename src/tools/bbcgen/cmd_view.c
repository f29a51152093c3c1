/* cmd_view.c — the viewer (thesis Appendix A `show model`, `show bbc`):
 * `bbcgen view` renders its nine views headless; `show model` and `show
 * bbc` at the prompt open a window. The geometry of show bbc's views comes
 * from the library (bbc_grid_view_build, bbc_faces_view_build:
 * src/cloud/views.c), the drawing is src/gl/viewer.c; the model, grid,
 * planes and cloud from the session. */
#include "pipeline.h"

#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "bbcgl.h"

static int write_png(bbcgl_context *ctx, const char *path) {
  bbc_image im;
  char err[BBCGL_ERR];
  if (!bbcgl_context_read(ctx, &im, err)) {
    cli_error("%s", err);
    return EXIT_OUTPUT;
  }
  bbc_error e;
  int ok = bbc_image_write_png(path, &im, &e) == BBC_OK;
  if (!ok) cli_error("%s", e.message);
  bbc_image_free(&im);
  return ok ? EXIT_OK : EXIT_OUTPUT;
}

/* The viewer over a model and (may be NULL) a cloud. */
static bbcgl_viewer *viewer_for(const bbc_mesh *model, const bbc_cloud *cloud) {
  char err[BBCGL_ERR];
  bbcgl_viewer *v = bbcgl_viewer_new(err);
  if (!v || !bbcgl_viewer_set_model(v, model, err) ||
      (cloud && !bbcgl_viewer_set_cloud(v, cloud, err))) {
    cli_error("viewer: %s", err);
    bbcgl_viewer_free(v);
    return NULL;
  }
  return v;
}

/* show bbc's selection: the part, its face, the vertex (F6), the volume (F7). */
typedef struct bbc_pick {
  size_t part, face;
  int vertex, volume;
} bbc_pick;

/* The first selection: the largest face of the part with most faces. */
static void pick_default(const bbc_grid *g, bbc_pick *p) {
  memset(p, 0, sizeof *p);
  p->vertex = -1;
  for (size_t i = 1; i < bbc_grid_get_part_count(g); i++)
    if (bbc_grid_get_part_faces(g, i) > bbc_grid_get_part_faces(g, p->part)) p->part = i;
  p->face = bbc_grid_get_largest_face(g, p->part);
}

/* Uploads the geometry of a show bbc view for the selection, and the
 * mini-model (the wireframe model, the selected face yellow). */
static int bbc_geometry_for(bbcgl_viewer *v, const bbc_session *s, int mode, const bbc_pick *p) {
  const bbc_grid *g = bbc_session_get_grid(s);
  const bbc_mesh *m = bbc_session_get_model(s);
  int64_t tri = bbc_grid_get_face_triangle(g, p->part, p->face);
  bbc_geometry geo, mini;
  bbc_error e;
  char err[BBCGL_ERR];
  uint8_t *state = NULL;
  bbc_result r;
  if (mode == BBCGL_VIEW_FACES) {
    state = malloc(m->triangle_count);
    if (!state) {
      cli_error("out of memory");
      return EXIT_RESOURCES;
    }
    bbc_faces_get_state(bbc_session_get_planes(s), (size_t)tri, state, m->triangle_count);
    r = bbc_faces_view_build(m, state, (size_t)tri, &geo, &e);
    free(state);
  } else {
    bbc_grid_view_options o = {(bbc_grid_view_kind)(mode - BBCGL_VIEW_DOMAIN), p->part, p->face,
                               p->vertex, p->volume};
    r = bbc_grid_view_build(g, &o, &geo, &e);
  }
  if (r != BBC_OK) return cli_fail(&e, 0);
  int ok = bbcgl_viewer_set_geometry(v, 0, &geo, err);
  bbc_geometry_free(&geo);
  if (ok && mode != BBCGL_VIEW_FACES) {
    if (bbc_faces_view_build(m, NULL, (size_t)tri, &mini, &e) != BBC_OK) return cli_fail(&e, 0);
    ok = bbcgl_viewer_set_geometry(v, 1, &mini, err);
    bbc_geometry_free(&mini);
  }
  if (!ok) {
    cli_error("viewer: %s", err);
    return EXIT_RESOURCES;
  }
  return EXIT_OK;
}

/* "1".."3" or "all" (F6's choices) -> -1..2; -2 on error. */
static int parse_vertex(const char *t) {
  if (!strcmp(t, "all")) return -1;
  if (t[0] >= '1' && t[0] <= '4' && !t[1]) return t[0] - '1';
  return -2;
}

/* What `bbcgen view` is asked for. */
typedef struct view_args {
  const char *model, *shot, *mode_name, *part;
  double size, yaw, pitch;
  long long face;
  int vertex, volume, mini;
  int all, mode; /* --mode all; the view mode otherwise */
} view_args;

/* The command line into `va`: -1 to go on, else an exit code (said). */
static int parse_view_args(cli *c, int argc, char **argv, view_args *va) {
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has = i + 1 < argc;
    if (!strcmp(a, "--mode") && has) {
      va->mode_name = argv[++i];
    } else if (!strcmp(a, "--screenshot") && has) {
      va->shot = argv[++i];
    } else if (!strcmp(a, "--part") && has) {
      va->part = argv[++i];
    } else if (!strcmp(a, "--face") && has) {
      if ((va->face = cli_parse_count("--face", argv[++i], 1LL << 40)) < 0) return EXIT_USAGE;
    } else if (!strcmp(a, "--vertex") && has) {
      if ((va->vertex = parse_vertex(argv[++i])) < -1) {
        cli_error("view: --vertex %s: expected 1, 2, 3, 4 (a face of four vertices) or all",
                  argv[i]);
        return EXIT_USAGE;
      }
    } else if (!strcmp(a, "--volume")) {
      va->volume = 1;
    } else if (!strcmp(a, "--no-mini")) {
      va->mini = 0;
    } else if ((!strcmp(a, "--size") || !strcmp(a, "--yaw") || !strcmp(a, "--pitch")) && has) {
      char *end;
      double v = strtod(argv[++i], &end);
      if (*end || !isfinite(v) || (a[2] == 's' && (v < 16 || v > 4096))) {
        cli_error("view: %s %s: expected a number%s", a, argv[i],
                  a[2] == 's' ? " of pixels from 16 to 4096" : " (degrees)");
        return EXIT_USAGE;
      }
      *(a[2] == 's' ? &va->size : a[2] == 'y' ? &va->yaw : &va->pitch) = v;
    } else {
      int k = cli_common_option(c, argc, argv, &i);
      if (k < 0) return EXIT_USAGE;
      if (k) continue;
      if (a[0] != '-' && !va->model) {
        va->model = a;
      } else if (a[0] == '-') {
        static const char *const own[] = {"--mode",   "--screenshot", "--size", "--yaw",
                                          "--pitch",  "--part",       "--face", "--vertex",
                                          "--volume", "--no-mini",    NULL};
        return cli_unknown_option("view", a, own);
      } else {
        cli_error("view: one model at a time ('%s' is a second one)", a);
        return EXIT_USAGE;
      }
    }
  }
  return -1;
}

/* The mode, the model and the screenshot's name: an exit code. */
static int check_view_args(view_args *va) {
  va->all = !strcmp(va->mode_name, "all");
  va->mode = va->all ? 0 : bbcgl_view_mode_from_name(va->mode_name);
  if (va->mode < 0) {
    cli_error("view: --mode %s: expected input, rects, cloud-rects, cloud, domain, continuous, "
              "both, density, faces or all",
              va->mode_name);
    return EXIT_USAGE;
  }
  if (!va->model || !va->shot) {
    cli_error("view: usage: bbcgen view MODEL --screenshot OUT.png [--mode "
              "input|rects|cloud-rects|cloud|domain|continuous|both|density|faces|all] [--size "
              "PX] [--yaw DEG] [--pitch DEG] [--part P] [--face N] [--vertex 1|2|3|all] "
              "[--volume] [--no-mini]");
    return EXIT_USAGE;
  }
  size_t sl = strlen(va->shot);
  if (sl < 4 || strcasecmp(va->shot + sl - 4, ".png")) {
    cli_error("view: --screenshot %s: the picture is written as .png", va->shot);
    return EXIT_USAGE;
  }
  return EXIT_OK;
}

/* show bbc's views: the face --part and --face choose (else the default),
 * --vertex and --volume; an exit code. */
static int pick_from_args(const view_args *va, const bbc_grid *g, bbc_pick *pick) {
  pick_default(g, pick);
  pick->vertex = va->vertex;
  pick->volume = va->volume;
  const char *part = va->part;
  if (part) {
    size_t n = bbc_grid_get_part_count(g), k;
    for (k = 0; k < n; k++)
      if (!strcasecmp(part, bbc_grid_get_part_name(g, k)) ||
          (part[0] >= '0' && part[0] <= '9' && !part[1] && (size_t)(part[0] - '0') == k))
        break;
    if (k == n) {
      cli_error("view: --part %s: the model's parts are %s%s%s", part, bbc_grid_get_part_name(g, 0),
                n > 1 ? " and " : "", n > 1 ? bbc_grid_get_part_name(g, 1) : "");
      return EXIT_USAGE;
    } else if (!bbc_grid_get_part_faces(g, k)) {
      cli_error("view: --part %s: it is kept as a mesh (limbs), not on planes; --limbs 0 puts "
                "it on planes",
                part);
      return EXIT_USAGE;
    } else {
      pick->part = k;
      pick->face = bbc_grid_get_largest_face(g, k);
    }
  }
  if (va->face >= 0) {
    if ((size_t)va->face >= bbc_grid_get_part_faces(g, pick->part)) {
      cli_error("view: --face %lld: part %s has %zu faces (0 to %zu)", va->face,
                bbc_grid_get_part_name(g, pick->part), bbc_grid_get_part_faces(g, pick->part),
                bbc_grid_get_part_faces(g, pick->part) - 1);
      return EXIT_USAGE;
    } else {
      pick->face = (size_t)va->face;
    }
  }
  return EXIT_OK;
}

/* Draws the view (or the nine as a sheet) headless into the screenshot and
 * says what it wrote; an exit code. */
static int draw_views(const cli *c, const view_args *va, const bbc_session *sess,
                      const bbc_pick *pick, int need_grid) {
  char err[BBCGL_ERR];
  int all = va->all, mode = va->mode;
  int px = (int)va->size, w = all ? 3 * px : px, h = all ? 3 * px : px;
  bbcgl_context *ctx = bbcgl_context_headless(w, h, err);
  if (!ctx) {
    cli_error("view: %s", err);
    return EXIT_RESOURCES;
  }
  bbcgl_viewer *v = viewer_for(bbc_session_get_model(sess), bbc_session_get_cloud(sess));
  if (!v) {
    bbcgl_context_free(ctx);
    return EXIT_RESOURCES;
  }
  bbcgl_view view;
  bbcgl_view_default(&view);
  view.yaw = va->yaw;
  view.pitch = va->pitch;
  view.up_axis = c->params.up_axis;
  view.mini = va->mini;
  int rc = EXIT_OK;
  bbcgl_context_begin(ctx);
  for (int m = all ? 0 : mode; rc == EXIT_OK && m < (all ? BBCGL_VIEW_COUNT : mode + 1); m++) {
    if (m >= BBCGL_VIEW_DOMAIN) rc = bbc_geometry_for(v, sess, m, pick);
    if (rc != EXIT_OK) break;
    bbcgl_view mv = view;
    if (m >= BBCGL_VIEW_DOMAIN && m != BBCGL_VIEW_FACES && va->yaw == 30 && va->pitch == 10) {
      mv.yaw = 25; /* the grid's box from above its front corner */
      mv.pitch = 25;
    }
    if (all) /* a 3 x 3 sheet: show model's four, then show bbc's five */
      bbcgl_viewer_draw(v, (bbcgl_view_mode)m, &mv, (m % 3) * px, (2 - m / 3) * px, px, px);
    else
      bbcgl_viewer_draw(v, (bbcgl_view_mode)m, &mv, 0, 0, w, h);
  }
  bbcgl_context_end(ctx);
  if (rc == EXIT_OK) rc = write_png(ctx, va->shot);
  if (rc == EXIT_OK) {
    if (need_grid)
      cli_info(c, "wrote %s: %s; part %s, face %zu (triangle %lld of the model)", va->shot,
               all ? "the nine views" : va->mode_name,
               bbc_grid_get_part_name(bbc_session_get_grid(sess), pick->part), pick->face,
               (long long)bbc_grid_get_face_triangle(bbc_session_get_grid(sess), pick->part,
                                                     pick->face));
    else
      cli_info(c, "wrote %s: %s", va->shot, va->mode_name);
  }
  bbcgl_viewer_free(v);
  bbcgl_context_free(ctx);
  return rc;
}

/* bbcgen view MODEL --mode M --screenshot PNG [--size PX] [--yaw D] [--pitch D]
 *   [--part P] [--face N] [--vertex 1|2|3|all] [--volume] [--no-mini] */
int cmd_view(cli *c, int argc, char **argv) {
  view_args va = {NULL, NULL, "input", NULL, 512, 30, 10, -1, -1, 0, 1, 0, 0};
  int rc = parse_view_args(c, argc, argv, &va);
  if (rc >= 0) return rc;
  if ((rc = check_view_args(&va)) != EXIT_OK) return rc;
  int all = va.all, mode = va.mode;
  /* the session: the model; the grid and planes for show bbc's views; the
   * cloud for show model's (all: everything) */
  bbc_session *sess = bbc_session_new();
  if (!sess) {
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_planes_options po;
  bbc_error e;
  rc = cli_planes_options(c, &po);
  int need_cloud = all || (mode != BBCGL_VIEW_INPUT && mode < BBCGL_VIEW_DOMAIN);
  int need_grid = all || mode >= BBCGL_VIEW_DOMAIN;
  if (rc == EXIT_OK && bbc_session_load(sess, va.model, &lo, &e) != BBC_OK) rc = cli_fail(&e, 0);
  if (rc == EXIT_OK && need_cloud && bbc_session_run(sess, &po, &e) != BBC_OK)
    rc = cli_fail_in(va.model, &e, 0);
  if (rc == EXIT_OK && need_grid && !need_cloud &&
      (bbc_session_build_grid(sess, &po, &e) != BBC_OK ||
       bbc_session_select_planes(sess, &po, &e) != BBC_OK))
    rc = cli_fail_in(va.model, &e, 0);
  bbc_pick pick;
  memset(&pick, 0, sizeof pick);
  if (rc == EXIT_OK && need_grid) rc = pick_from_args(&va, bbc_session_get_grid(sess), &pick);
  if (rc == EXIT_OK) rc = draw_views(c, &va, sess, &pick, need_grid);
  bbc_session_free(sess);
  return rc;
}

/* ---- show model / show bbc: a window at the prompt ----------------------------- */

typedef struct show_state {
  bbcgl_view view;
  int bbc;   /* show bbc (else show model) */
  int debug; /* a debug view during step 2: the faces only; End: no more of them */
  int have_cloud;
  int mode, quit, end, dragging, changed;
  int help;            /* the key help at the bottom (H) */
  int domains, voxels; /* show model: F2 vertex validity domains, F10 shadow voxels */
  int overlay_changed;
  const cli *c; /* its parameters: epsilon, shade */
  const bbc_mesh *model;
  const bbc_planeset *planes; /* the epsilon used, when there are planes */
  const bbc_grid *grid;
  bbc_pick pick;
  double mx, my;
} show_state;

/* Tab: the view as it starts, keeping the up axis, the mini-model and the
 * background. */
static void reset_view(bbcgl_view *view) {
  int up = view->up_axis, mini = view->mini;
  float bg[3];
  memcpy(bg, view->background, sizeof bg);
  bbcgl_view_default(view);
  view->up_axis = up;
  view->mini = mini;
  memcpy(view->background, bg, sizeof bg);
}

/* show bbc's selection: the next (+1) or previous (-1) face of the part,
 * the other part's largest face, the face's domain then each of its
 * vertices' (F6). */
static void next_face(show_state *s, int dir) {
  size_t n = bbc_grid_get_part_faces(s->grid, s->pick.part);
  s->pick.face = (s->pick.face + (dir > 0 ? 1 : n - 1)) % n;
  s->changed = 1;
}

static void other_part(show_state *s) {
  size_t parts = bbc_grid_get_part_count(s->grid);
  s->pick.part = (s->pick.part + 1) % parts;
  s->pick.face = bbc_grid_get_largest_face(s->grid, s->pick.part);
  s->changed = 1;
}

static void next_vertex(show_state *s) {
  int nv = bbc_grid_get_face_vertex_count(s->grid, s->pick.part, s->pick.face);
  s->pick.vertex = s->pick.vertex >= nv - 1 ? -1 : s->pick.vertex + 1;
  s->changed = 1;
}

/* Arrow keys: up/down cycle the views (show model: left/right too), in show
 * bbc left/right cycle the selected face. */
static void show_key(show_state *s, int key) {
  int first = s->bbc ? BBCGL_VIEW_DOMAIN : 0;
  int count = s->bbc ? BBCGL_VIEW_COUNT - BBCGL_VIEW_DOMAIN : BBCGL_VIEW_MODEL_COUNT;
  int step = 0;
  if (s->debug && (key == GLFW_KEY_UP || key == GLFW_KEY_DOWN || key == GLFW_KEY_LEFT ||
                   key == GLFW_KEY_RIGHT || key == GLFW_KEY_PAGE_UP || key == GLFW_KEY_PAGE_DOWN))
    return;
  switch (key) {
  case GLFW_KEY_DOWN:
    step = 1;
    break;
  case GLFW_KEY_UP:
    step = -1;
    break;
  case GLFW_KEY_RIGHT:
  case GLFW_KEY_LEFT:
    if (!s->bbc)
      step = key == GLFW_KEY_RIGHT ? 1 : -1;
    else
      next_face(s, key == GLFW_KEY_RIGHT ? 1 : -1);
    break;
  case GLFW_KEY_PAGE_UP:
  case GLFW_KEY_PAGE_DOWN:
    if (s->bbc) other_part(s);
    break;
  case GLFW_KEY_TAB:
    reset_view(&s->view);
    break;
  case GLFW_KEY_F1:
    s->view.wireframe = !s->view.wireframe;
    break;
  case GLFW_KEY_F2: /* show model: every vertex's validity domain */
    if (!s->bbc && !s->debug) {
      s->domains = !s->domains;
      s->overlay_changed = 1;
    }
    break;
  case GLFW_KEY_F3: /* show bbc: the mini-model; show model: the normal maps */
    if (s->bbc)
      s->view.mini = !s->view.mini;
    else
      s->view.normal_maps = !s->view.normal_maps;
    break;
  case GLFW_KEY_F10: /* show model: the shadow voxels (2.3.11) */
    if (!s->bbc && !s->debug) {
      s->voxels = !s->voxels;
      s->overlay_changed = 1;
    }
    break;
  case GLFW_KEY_H:
    s->help = !s->help;
    break;
  case GLFW_KEY_F5:
    s->view.lighting = !s->view.lighting;
    break;
  case GLFW_KEY_F6: /* the face's domain, then each of its vertices' */
    if (s->bbc) next_vertex(s);
    break;
  case GLFW_KEY_F7: /* sheets only, or the domain between them */
    if (s->bbc) {
      s->pick.volume = !s->pick.volume;
      s->changed = 1;
    }
    break;
  case GLFW_KEY_F12: {
    float b = s->view.background[0] > 0.5f ? 0.0f : 1.0f;
    s->view.background[0] = s->view.background[1] = s->view.background[2] = b;
    break;
  }
  case GLFW_KEY_ESCAPE:
    s->quit = 1;
    break;
  case GLFW_KEY_END:
    s->quit = s->end = 1;
    break;
  default:
    break;
  }
  if (step) {
    s->mode = first + ((s->mode - first) + step + count) % count;
    s->changed = 1;
  }
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  if (action == GLFW_PRESS || action == GLFW_REPEAT) show_key(glfwGetWindowUserPointer(w), key);
}

static void on_button(GLFWwindow *w, int button, int action, int mods) {
  (void)mods;
  show_state *s = glfwGetWindowUserPointer(w);
  /* Appendix A: left turns, middle pans, right zooms */
  int which = button == GLFW_MOUSE_BUTTON_LEFT     ? 1
              : button == GLFW_MOUSE_BUTTON_MIDDLE ? 2
              : button == GLFW_MOUSE_BUTTON_RIGHT  ? 3
                                                   : 0;
  if (which) s->dragging = action == GLFW_PRESS ? which : 0;
  glfwGetCursorPos(w, &s->mx, &s->my);
}

static void on_cursor(GLFWwindow *w, double x, double y) {
  show_state *s = glfwGetWindowUserPointer(w);
  double dx = x - s->mx, dy = y - s->my;
  if (s->dragging == 1) {
    s->view.yaw += dx * 0.4;
    s->view.pitch += dy * 0.4;
    if (s->view.pitch > 89) s->view.pitch = 89;
    if (s->view.pitch < -89) s->view.pitch = -89;
  } else if (s->dragging == 2) {
    s->view.pan[0] += dx * 0.005 / s->view.zoom;
    s->view.pan[1] += dy * 0.005 / s->view.zoom;
  } else if (s->dragging == 3) {
    s->view.zoom *= pow(1.01, -dy);
    if (s->view.zoom < 0.2) s->view.zoom = 0.2;
    if (s->view.zoom > 20) s->view.zoom = 20;
  }
  s->mx = x;
  s->my = y;
}

static void on_scroll(GLFWwindow *w, double dx, double dy) {
  (void)dx;
  show_state *s = glfwGetWindowUserPointer(w);
  s->view.zoom *= pow(1.15, dy);
  if (s->view.zoom < 0.2) s->view.zoom = 0.2;
  if (s->view.zoom > 20) s->view.zoom = 20;
}

static const struct {
  const char *name;
  int key;
} k_keys[] = {{"right", GLFW_KEY_RIGHT}, {"left", GLFW_KEY_LEFT},    {"up", GLFW_KEY_UP},
              {"down", GLFW_KEY_DOWN},   {"pgup", GLFW_KEY_PAGE_UP}, {"pgdn", GLFW_KEY_PAGE_DOWN},
              {"tab", GLFW_KEY_TAB},     {"f1", GLFW_KEY_F1},        {"f3", GLFW_KEY_F3},
              {"f5", GLFW_KEY_F5},       {"f6", GLFW_KEY_F6},        {"f7", GLFW_KEY_F7},
              {"f12", GLFW_KEY_F12},     {"esc", GLFW_KEY_ESCAPE},   {"end", GLFW_KEY_END},
              {"f2", GLFW_KEY_F2},       {"f10", GLFW_KEY_F10},      {"h", GLFW_KEY_H}};

static int key_from_name(const char *n) {
  for (size_t i = 0; i < sizeof k_keys / sizeof k_keys[0]; i++)
    if (!strcasecmp(n, k_keys[i].name)) return k_keys[i].key;
  return -1;
}

/* show model's overlay: F2 every vertex's validity domain (epsilon: the
 * planes' when there are planes, else the parameter's), F10 the shadow
 * voxels (the shade parameter's grid, else 60 voxels). */
static int model_overlay(bbcgl_viewer *v, const show_state *s) {
  char err[BBCGL_ERR];
  bbc_error e;
  bbc_geometry geo;
  int ok = 1;
  if (!s->domains && !s->voxels) {
    bbcgl_viewer_set_geometry(v, 2, NULL, err); /* clearing cannot fail */
    return EXIT_OK;
  }
  bbc_geometry a = {0}, b = {0};
  if (s->domains) {
    double eps =
        s->planes ? s->planes->epsilon_abs : s->c->params.epsilon_pct / 100.0 * s->model->radius;
    if (bbc_vertex_domains_view_build(s->model, eps, &a, &e) != BBC_OK) return cli_fail(&e, 0);
  }
  if (s->voxels) {
    int n = s->c->params.shade_voxels > 0 ? s->c->params.shade_voxels : 60;
    double amb = s->c->params.shade_voxels > 0 ? s->c->params.shade_ambient : 0.4;
    if (bbc_shade_view_build(s->model, n, amb, s->c->params.up_axis, &b, &e) != BBC_OK) {
      bbc_geometry_free(&a);
      return cli_fail(&e, 0);
    }
  }
  /* both: one geometry */
  memset(&geo, 0, sizeof geo);
  geo.tri_count = a.tri_count + b.tri_count;
  geo.tris = malloc((geo.tri_count ? geo.tri_count : 1) * 18 * sizeof *geo.tris);
  if (!geo.tris) {
    ok = 0;
    snprintf(err, sizeof err, "out of memory");
  } else {
    if (a.tri_count) memcpy(geo.tris, a.tris, a.tri_count * 18 * sizeof *geo.tris);
    if (b.tri_count)
      memcpy(geo.tris + 18 * a.tri_count, b.tris, b.tri_count * 18 * sizeof *geo.tris);
    memcpy(geo.center, s->model->center, sizeof geo.center);
    geo.radius = s->model->radius;
    ok = bbcgl_viewer_set_geometry(v, 2, &geo, err);
  }
  bbc_geometry_free(&a);
  bbc_geometry_free(&b);
  bbc_geometry_free(&geo);
  if (!ok) {
    cli_error("show: %s", err);
    return EXIT_RESOURCES;
  }
  return EXIT_OK;
}

/* The window's loop: draws, takes keys (or the script's) until Esc, End or
 * the script's end. */
static int run_window(const cli *c, bbcgl_context *ctx, bbcgl_viewer *v, const bbc_session *sess,
                      show_state *sp, const char *keys) {
  GLFWwindow *win = bbcgl_context_window_handle(ctx);
  glfwSetWindowUserPointer(win, sp);
  glfwSetKeyCallback(win, on_key);
  if (!keys) { /* scripted keys are the only input of a scripted run */
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetScrollCallback(win, on_scroll);
  }
  int rc = EXIT_OK;
  char *script = keys ? strdup(keys) : NULL, *save = NULL;
  char *tok = script ? strtok_r(script, " ,", &save) : NULL;
  while (!sp->quit && !glfwWindowShouldClose(win)) {
    glfwPollEvents();
    if (!sp->bbc && !sp->debug && !sp->have_cloud && sp->mode != BBCGL_VIEW_INPUT)
      sp->mode = BBCGL_VIEW_INPUT;
    if (sp->bbc && sp->changed) {
      if ((rc = bbc_geometry_for(v, sess, sp->mode, &sp->pick)) != EXIT_OK) break;
      const char *vn[3] = {"first", "second", "third"};
      int sheets = sp->pick.vertex >= 0 &&
                   (sp->mode == BBCGL_VIEW_CONTINUOUS || sp->mode == BBCGL_VIEW_BOTH);
      cli_info(c, "show bbc: %s, part %s, face %zu of %zu%s%s%s", bbcgl_view_mode_name(sp->mode),
               bbc_grid_get_part_name(sp->grid, sp->pick.part), sp->pick.face,
               bbc_grid_get_part_faces(sp->grid, sp->pick.part), sheets ? ", its " : "",
               sheets ? vn[sp->pick.vertex] : "", sheets ? " vertex's domain" : "");
    }
    sp->changed = 0;
    if (sp->overlay_changed && (rc = model_overlay(v, sp)) != EXIT_OK) break;
    sp->overlay_changed = 0;
    int w, h;
    bbcgl_context_size(ctx, &w, &h);
    bbcgl_context_begin(ctx);
    bbcgl_view dv = sp->view;
    if (sp->bbc && sp->mode != BBCGL_VIEW_FACES) {
      dv.yaw -= 5; /* the grid's box from above its front corner */
      dv.pitch += 15;
    }
    bbcgl_viewer_draw(v, (bbcgl_view_mode)sp->mode, &dv, 0, 0, w, h);
    if (sp->help) {
      static const char *const model_help[] = {
          "ARROWS VIEW  LEFT DRAG TURN  MIDDLE PAN  RIGHT/WHEEL ZOOM  TAB RESET",
          "F1 WIRE  F2 DOMAINS  F3 NORMAL MAPS  F5 LIGHT  F10 VOXELS  F12 BG  H HELP  ESC BACK"};
      static const char *const bbc_help[] = {
          "UP/DOWN VIEW  LEFT/RIGHT FACE  PGUP/PGDN PART  LEFT DRAG TURN  MIDDLE PAN  RIGHT ZOOM",
          "F1 WIRE  F3 MINI-MODEL  F6 VERTEX  F7 VOLUME  F12 BG  TAB RESET  H HELP  ESC BACK"};
      static const char *const debug_help[] = {
          "DRAG TURN  MIDDLE PAN  RIGHT/WHEEL ZOOM  F1 WIRE  F12 BG  H HELP",
          "ESC NEXT  END NO MORE DEBUG VIEWS IN THIS COMMAND"};
      char title[96];
      snprintf(title, sizeof title, "%s",
               sp->debug ? "DEBUG: THE FACES" : bbcgl_view_mode_name(sp->mode));
      const char *const *keys_help = sp->debug ? debug_help : sp->bbc ? bbc_help : model_help;
      const char *lines[3] = {title, keys_help[0], keys_help[1]};
      bbcgl_viewer_text(v, w, h, lines, 3);
    }
    if (script) { /* scripted keys: names, shot:FILE.png; the window closes after them */
      if (!tok) break;
      if (!strncmp(tok, "shot:", 5)) {
        if (write_png(ctx, tok + 5) != EXIT_OK) rc = EXIT_OUTPUT;
      } else if (key_from_name(tok) >= 0) {
        show_key(sp, key_from_name(tok));
      } else {
        cli_error("show: unknown key '%s' (right left up down pgup pgdn tab f1 f2 f3 f5 f6 f7 "
                  "f10 f12 h esc end, shot:FILE)",
                  tok);
        rc = EXIT_USAGE;
        break;
      }
      tok = strtok_r(NULL, " ,", &save);
    }
    bbcgl_context_end(ctx);
  }
  free(script);
  return rc;
}

int show_window(const cli *c, const bbc_session *sess, const bbc_cloud *cloud, int bbc,
                const char *keys) {
  char err[BBCGL_ERR];
  const bbc_mesh *model = bbc_session_get_model(sess);
  int have_cloud = cloud != NULL;
  if (bbc && !bbc_session_get_grid(sess)) {
    cli_error("show bbc needs the grid of step 1: run bbc1 (or bbc) first");
    return EXIT_USAGE;
  }
  if (!getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
    cli_error("show: no display to open a window on (for pictures without one: bbcgen view "
              "MODEL --mode ... --screenshot OUT.png)");
    return EXIT_USAGE;
  }
  bbcgl_context *ctx =
      bbcgl_context_window(800, 600, bbc ? "bbcgen: show bbc" : "bbcgen: show model", err);
  if (!ctx) {
    cli_error("show: %s (for pictures without a display: bbcgen view)", err);
    return EXIT_RESOURCES;
  }
  bbcgl_viewer *v = viewer_for(model, cloud);
  if (!v) {
    bbcgl_context_free(ctx);
    return EXIT_RESOURCES;
  }
  show_state s;
  memset(&s, 0, sizeof s);
  bbcgl_view_default(&s.view);
  s.view.up_axis = c->params.up_axis;
  s.view.mini = 1;
  s.bbc = bbc;
  s.have_cloud = have_cloud;
  s.help = 1;
  s.c = c;
  s.model = model;
  s.planes = bbc_session_get_planes(sess);
  s.grid = bbc_session_get_grid(sess);
  if (bbc) pick_default(s.grid, &s.pick);
  s.mode = bbc ? BBCGL_VIEW_DOMAIN : have_cloud ? BBCGL_VIEW_RECTS : BBCGL_VIEW_INPUT;
  s.changed = 1;
  if (bbc)
    cli_info(c, "show bbc: up/down change the view (validity domain on the grid: discretised, "
                "continuous, both; the grid's density; the faces), left/right the face, "
                "PgUp/PgDn the part, F3 mini-model, F6 the face's or one vertex's domain, F7 "
                "sheets or volume, mouse drag turns, wheel zooms, Tab resets, F1 wireframe, F12 "
                "background, Esc back to the prompt");
  else
    cli_info(c, "show model: arrow keys change the view (input, rectangles, cloud with "
                "rectangles, cloud), mouse drag turns, wheel zooms, Tab resets, F1 wireframe, F5 "
                "lighting, F12 background, Esc back to the prompt");
  int rc = run_window(c, ctx, v, sess, &s, keys);
  bbcgl_viewer_free(v);
  bbcgl_context_free(ctx);
  return rc;
}

/* ---- debug levels: step 2's internals in a window as they happen ------------ */

static struct {
  const cli *c;
  const bbc_mesh *model;
  bbcgl_context *ctx;
  bbcgl_viewer *v;
  show_state s;
  uint8_t *state;
  int count, off;
} g_dbg;

/* The faces view of one event: the faces earlier planes took hidden, the
 * event's faces blue (the first yellow), the rest as wireframe; Esc goes on,
 * End goes on without more debug views in this command. */
static void on_debug(void *user, const bbc_debug_event *ev) {
  (void)user;
  if (g_dbg.off || !g_dbg.model) return;
  const cli *c = g_dbg.c;
  g_dbg.count++;
  const char *what = ev->level == 1 ? "plane picked" : ev->level == 2 ? "greedy step" : "cluster";
  char step[32] = "";
  if (ev->level == 2) snprintf(step, sizeof step, " %d", ev->step);
  cli_info(c, "debug %d: %s%splane %zu, %s%s: %zu faces (view %d)", ev->level, ev->where,
           ev->where[0] ? ", " : "", ev->plane + (ev->level != 1), what, step, ev->face_count,
           g_dbg.count);
  char err[BBCGL_ERR];
  if (!g_dbg.ctx) {
    if (!getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
      cli_log((void *)c, BBC_LOG_WARNING, "debug: no display for the debug views (step 2 goes on)");
      g_dbg.off = 1;
      return;
    }
    g_dbg.state = malloc(g_dbg.model->triangle_count);
    g_dbg.ctx = bbcgl_context_window(800, 600, "bbcgen: debug", err);
    if (!g_dbg.state || !g_dbg.ctx || !(g_dbg.v = viewer_for(g_dbg.model, NULL))) {
      if (!g_dbg.ctx) cli_error("debug: %s", err);
      g_dbg.off = 1;
      return;
    }
    memset(&g_dbg.s, 0, sizeof g_dbg.s);
    bbcgl_view_default(&g_dbg.s.view);
    g_dbg.s.view.up_axis = c->params.up_axis;
    g_dbg.s.debug = 1;
    g_dbg.s.help = 1;
    g_dbg.s.mode = BBCGL_VIEW_FACES;
  }
  size_t nt = g_dbg.model->triangle_count;
  memset(g_dbg.state, BBC_FACE_REMAINING, nt);
  for (size_t i = 0; i < ev->done_count; i++) g_dbg.state[ev->done[i]] = BBC_FACE_DONE;
  for (size_t i = 0; i < ev->face_count; i++) g_dbg.state[ev->faces[i]] = BBC_FACE_VALID;
  bbc_geometry geo;
  bbc_error e;
  if (bbc_faces_view_build(g_dbg.model, g_dbg.state, ev->face_count ? ev->faces[0] : nt, &geo,
                           &e) != BBC_OK) {
    cli_error("debug: %s", e.message);
    g_dbg.off = 1;
    return;
  }
  int ok = bbcgl_viewer_set_geometry(g_dbg.v, 0, &geo, err);
  bbc_geometry_free(&geo);
  if (!ok) {
    cli_error("debug: %s", err);
    g_dbg.off = 1;
    return;
  }
  /* scripts and tests: BBCGEN_DEBUG_KEYS, %d the view's number */
  const char *keys = getenv("BBCGEN_DEBUG_KEYS");
  char script[1024];
  if (keys) {
    size_t o = 0;
    for (const char *k = keys; *k && o + 16 < sizeof script; k++) {
      if (k[0] == '%' && k[1] == 'd') {
        o += (size_t)snprintf(script + o, sizeof script - o, "%d", g_dbg.count);
        k++;
      } else {
        script[o++] = *k;
      }
    }
    script[o] = 0;
  }
  g_dbg.s.quit = 0;
  run_window(c, g_dbg.ctx, g_dbg.v, NULL, &g_dbg.s, keys ? script : NULL);
  if (g_dbg.s.end) g_dbg.off = 1;
}

void debug_views_begin(const cli *c, const bbc_mesh *model, bbc_planes_options *o) {
  memset(&g_dbg, 0, sizeof g_dbg);
  if (c->params.debug <= 0 || !model) return;
  g_dbg.c = c;
  g_dbg.model = model;
  o->callbacks.debug = on_debug;
}

void debug_views_end(void) {
  bbcgl_viewer_free(g_dbg.v);
  bbcgl_context_free(g_dbg.ctx);
  free(g_dbg.state);
  memset(&g_dbg, 0, sizeof g_dbg);
}
