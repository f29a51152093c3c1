/* cmd_view.c — the viewer (thesis Appendix A `show model`): `bbcgen view`
 * renders its views headless; `show model` at the prompt opens a window.
 * The drawing is src/gl/viewer.c. */
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

/* bbcgen view MODEL --mode M --screenshot PNG [--size PX] [--yaw D] [--pitch D] */
int cmd_view(cli *c, int argc, char **argv) {
  const char *model = NULL, *shot = NULL, *mode_name = "input";
  double size = 512, yaw = 30, pitch = 10;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has = i + 1 < argc;
    if (!strcmp(a, "--mode") && has) {
      mode_name = argv[++i];
    } else if (!strcmp(a, "--screenshot") && has) {
      shot = argv[++i];
    } else if ((!strcmp(a, "--size") || !strcmp(a, "--yaw") || !strcmp(a, "--pitch")) && has) {
      char *end;
      double v = strtod(argv[++i], &end);
      if (*end || !isfinite(v) || (a[2] == 's' && (v < 16 || v > 4096))) {
        cli_error("view: %s %s: expected a number%s", a, argv[i],
                  a[2] == 's' ? " of pixels from 16 to 4096" : " (degrees)");
        return EXIT_USAGE;
      }
      *(a[2] == 's' ? &size : a[2] == 'y' ? &yaw : &pitch) = v;
    } else {
      int k = cli_common_option(c, argc, argv, &i);
      if (k < 0) return EXIT_USAGE;
      if (k) continue;
      if (a[0] != '-' && !model) {
        model = a;
      } else if (a[0] == '-') {
        static const char *const own[] = {"--mode", "--screenshot", "--size",
                                          "--yaw",  "--pitch",      NULL};
        return cli_unknown_option("view", a, own);
      } else {
        cli_error("view: one model at a time ('%s' is a second one)", a);
        return EXIT_USAGE;
      }
    }
  }
  int all = !strcmp(mode_name, "all");
  int mode = all ? 0 : bbcgl_view_mode_from_name(mode_name);
  if (mode < 0) {
    cli_error("view: --mode %s: expected input, rects, cloud-rects, cloud or all", mode_name);
    return EXIT_USAGE;
  }
  if (!model || !shot) {
    cli_error("view: usage: bbcgen view MODEL --screenshot OUT.png [--mode "
              "input|rects|cloud-rects|cloud|all] [--size PX] [--yaw DEG] [--pitch DEG]");
    return EXIT_USAGE;
  }
  size_t sl = strlen(shot);
  if (sl < 4 || strcmp(shot + sl - 4, ".png")) {
    cli_error("view: --screenshot %s: the picture is written as .png", shot);
    return EXIT_USAGE;
  }
  int need_cloud = all || mode != BBCGL_VIEW_INPUT;
  job j;
  int rc = need_cloud ? job_run(c, model, NULL, 0, &j) : job_load(c, model, &j);
  if (rc != EXIT_OK) return rc;
  char err[BBCGL_ERR];
  int px = (int)size, w = all ? 2 * px : px, h = all ? 2 * px : px;
  bbcgl_context *ctx = bbcgl_context_headless(w, h, err);
  if (!ctx) {
    cli_error("view: %s", err);
    job_free(&j);
    return EXIT_RESOURCES;
  }
  bbcgl_viewer *v = viewer_for(&j.mesh, need_cloud ? &j.lods[0].cloud : NULL);
  if (!v) {
    bbcgl_context_free(ctx);
    job_free(&j);
    return EXIT_RESOURCES;
  }
  bbcgl_view view;
  bbcgl_view_default(&view);
  view.yaw = yaw;
  view.pitch = pitch;
  view.up_axis = c->params.up_axis;
  bbcgl_context_begin(ctx);
  if (all) { /* a 2 x 2 sheet: input, rects / cloud-rects, cloud */
    for (int m = 0; m < BBCGL_VIEW_COUNT; m++)
      bbcgl_viewer_draw(v, (bbcgl_view_mode)m, &view, (m % 2) * px, (1 - m / 2) * px, px, px);
  } else {
    bbcgl_viewer_draw(v, (bbcgl_view_mode)mode, &view, 0, 0, w, h);
  }
  bbcgl_context_end(ctx);
  rc = write_png(ctx, shot);
  if (rc == EXIT_OK) cli_info(c, "wrote %s: %s", shot, all ? "the four views" : mode_name);
  bbcgl_viewer_free(v);
  bbcgl_context_free(ctx);
  job_free(&j);
  return rc;
}

/* ---- show model: a window at the prompt -------------------------------------- */

typedef struct show_state {
  bbcgl_view view;
  int mode, quit, dragging;
  double mx, my;
} show_state;

static void show_key(show_state *s, int key) {
  switch (key) {
  case GLFW_KEY_RIGHT:
  case GLFW_KEY_DOWN:
    s->mode = (s->mode + 1) % BBCGL_VIEW_COUNT;
    break;
  case GLFW_KEY_LEFT:
  case GLFW_KEY_UP:
    s->mode = (s->mode + BBCGL_VIEW_COUNT - 1) % BBCGL_VIEW_COUNT;
    break;
  case GLFW_KEY_TAB: {
    int up = s->view.up_axis;
    float bg[3];
    memcpy(bg, s->view.background, sizeof bg);
    bbcgl_view_default(&s->view);
    s->view.up_axis = up;
    memcpy(s->view.background, bg, sizeof bg);
    break;
  }
  case GLFW_KEY_F1:
    s->view.wireframe = !s->view.wireframe;
    break;
  case GLFW_KEY_F5:
    s->view.lighting = !s->view.lighting;
    break;
  case GLFW_KEY_F12: {
    float b = s->view.background[0] > 0.5f ? 0.0f : 1.0f;
    s->view.background[0] = s->view.background[1] = s->view.background[2] = b;
    break;
  }
  case GLFW_KEY_ESCAPE:
    s->quit = 1;
    break;
  default:
    break;
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
  if (button == GLFW_MOUSE_BUTTON_LEFT) s->dragging = action == GLFW_PRESS;
  glfwGetCursorPos(w, &s->mx, &s->my);
}

static void on_cursor(GLFWwindow *w, double x, double y) {
  show_state *s = glfwGetWindowUserPointer(w);
  if (s->dragging) {
    s->view.yaw += (x - s->mx) * 0.4;
    s->view.pitch += (y - s->my) * 0.4;
    if (s->view.pitch > 89) s->view.pitch = 89;
    if (s->view.pitch < -89) s->view.pitch = -89;
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

static int key_from_name(const char *n) {
  static const struct {
    const char *name;
    int key;
  } keys[] = {{"right", GLFW_KEY_RIGHT}, {"left", GLFW_KEY_LEFT}, {"up", GLFW_KEY_UP},
              {"down", GLFW_KEY_DOWN},   {"tab", GLFW_KEY_TAB},   {"f1", GLFW_KEY_F1},
              {"f5", GLFW_KEY_F5},       {"f12", GLFW_KEY_F12},   {"esc", GLFW_KEY_ESCAPE}};
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
    if (!strcasecmp(n, keys[i].name)) return keys[i].key;
  return -1;
}

int show_model(const cli *c, const bbc_mesh *model, const bbc_cloud *cloud, const char *keys) {
  int have_cloud = cloud != NULL;
  char err[BBCGL_ERR];
  if (!getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
    cli_error("show: no display to open a window on (for pictures without one: bbcgen view "
              "MODEL --mode ... --screenshot OUT.png)");
    return EXIT_USAGE;
  }
  bbcgl_context *ctx = bbcgl_context_window(800, 600, "bbcgen: show model", err);
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
  s.mode = have_cloud ? BBCGL_VIEW_RECTS : BBCGL_VIEW_INPUT;
  GLFWwindow *win = bbcgl_context_window_handle(ctx);
  glfwSetWindowUserPointer(win, &s);
  glfwSetKeyCallback(win, on_key);
  if (!keys) { /* scripted keys are the only input of a scripted run */
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetScrollCallback(win, on_scroll);
  }
  cli_info(c, "show: arrow keys change the view (input, rectangles, cloud with rectangles, "
              "cloud), mouse drag turns, wheel zooms, Tab resets, F1 wireframe, F5 lighting, "
              "F12 background, Esc back to the prompt");
  int rc = EXIT_OK;
  char *script = keys ? strdup(keys) : NULL, *save = NULL;
  char *tok = script ? strtok_r(script, " ,", &save) : NULL;
  while (!s.quit && !glfwWindowShouldClose(win)) {
    glfwPollEvents();
    if (!have_cloud && s.mode != BBCGL_VIEW_INPUT) s.mode = BBCGL_VIEW_INPUT;
    int w, h;
    bbcgl_context_size(ctx, &w, &h);
    bbcgl_context_begin(ctx);
    bbcgl_viewer_draw(v, (bbcgl_view_mode)s.mode, &s.view, 0, 0, w, h);
    if (script) { /* scripted keys: names, shot:FILE.png; the window closes after them */
      if (!tok) break;
      if (!strncmp(tok, "shot:", 5)) {
        if (write_png(ctx, tok + 5) != EXIT_OK) rc = EXIT_OUTPUT;
      } else if (key_from_name(tok) >= 0) {
        show_key(&s, key_from_name(tok));
      } else {
        cli_error("show: unknown key '%s' (right left up down tab f1 f5 f12 esc, shot:FILE)", tok);
        rc = EXIT_USAGE;
        break;
      }
      tok = strtok_r(NULL, " ,", &save);
    }
    bbcgl_context_end(ctx);
  }
  free(script);
  bbcgl_viewer_free(v);
  bbcgl_context_free(ctx);
  return rc;
}
