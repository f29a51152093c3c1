/* context.c — an OpenGL 4.5 core context: headless through EGL's
 * surfaceless platform (no display needed; Mesa's llvmpipe on a machine
 * without a GPU), or a window through GLFW. Either way the frame is drawn
 * into the framebuffer bbcgl_context_begin binds. */
#include "bbcgl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#ifndef EGL_PLATFORM_SURFACELESS_MESA
#define EGL_PLATFORM_SURFACELESS_MESA 0x31DD
#endif

struct bbcgl_context {
  int width, height;
  /* headless */
  EGLDisplay dpy;
  EGLContext egl;
  GLuint fbo, colour, depth;
  /* window */
  GLFWwindow *window;
  char describe[256];
  /* pipeline statistics: -1 not looked for yet, 0 none, 1 queries made */
  int counters;
  GLuint query[3];
};

static void describe(bbcgl_context *c) {
  snprintf(c->describe, sizeof c->describe, "OpenGL %s, %s", (const char *)glGetString(GL_VERSION),
           (const char *)glGetString(GL_RENDERER));
}

static int check_version(bbcgl_context *c, char *err) {
  if (epoxy_gl_version() < 45) {
    snprintf(err, BBCGL_ERR, "OpenGL 4.5 is needed; the driver gives %d.%d (%s)",
             epoxy_gl_version() / 10, epoxy_gl_version() % 10,
             (const char *)glGetString(GL_RENDERER));
    return 0;
  }
  describe(c);
  return 1;
}

bbcgl_context *bbcgl_context_headless(int width, int height, char *err) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    snprintf(err, BBCGL_ERR, "size %d x %d: each side must be 1 to 16384", width, height);
    return NULL;
  }
  bbcgl_context *c = calloc(1, sizeof *c);
  if (c) c->counters = -1;
  if (!c) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  c->width = width;
  c->height = height;
  c->dpy = EGL_NO_DISPLAY;
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    c->dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
  if (c->dpy == EGL_NO_DISPLAY) c->dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  EGLint major = 0, minor = 0;
  if (c->dpy == EGL_NO_DISPLAY || !eglInitialize(c->dpy, &major, &minor)) {
    snprintf(err, BBCGL_ERR,
             "no EGL display (EGL error 0x%x): is Mesa's EGL installed (Debian: libegl1 "
             "libegl-mesa0 libgl1-mesa-dri)?",
             eglGetError());
    free(c);
    return NULL;
  }
  /* No surface is drawn to: a pbuffer-capable configuration, or none at
   * all where EGL_KHR_no_config_context allows it. */
  static const EGLint cfg_attr[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                    EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig cfg = (EGLConfig)0;
  EGLint n = 0;
  int bound = eglBindAPI(EGL_OPENGL_API);
  if (bound && (!eglChooseConfig(c->dpy, cfg_attr, &cfg, 1, &n) || n < 1) &&
      epoxy_has_egl_extension(c->dpy, "EGL_KHR_no_config_context")) {
    cfg = (EGLConfig)0; /* EGL_NO_CONFIG_KHR */
    n = 1;
  }
  if (!bound || n < 1) {
    snprintf(err, BBCGL_ERR, "EGL has no OpenGL configuration (EGL error 0x%x)", eglGetError());
    eglTerminate(c->dpy);
    free(c);
    return NULL;
  }
  static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    4,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_NONE};
  c->egl = eglCreateContext(c->dpy, cfg, EGL_NO_CONTEXT, ctx_attr);
  if (c->egl == EGL_NO_CONTEXT || !eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->egl)) {
    snprintf(err, BBCGL_ERR, "EGL cannot make an OpenGL 4.5 core context (EGL error 0x%x)",
             eglGetError());
    if (c->egl != EGL_NO_CONTEXT) eglDestroyContext(c->dpy, c->egl);
    eglTerminate(c->dpy);
    free(c);
    return NULL;
  }
  if (!check_version(c, err)) {
    bbcgl_context_free(c);
    return NULL;
  }
  glCreateRenderbuffers(1, &c->colour);
  glNamedRenderbufferStorage(c->colour, GL_RGBA8, width, height);
  glCreateRenderbuffers(1, &c->depth);
  glNamedRenderbufferStorage(c->depth, GL_DEPTH_COMPONENT24, width, height);
  glCreateFramebuffers(1, &c->fbo);
  glNamedFramebufferRenderbuffer(c->fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->colour);
  glNamedFramebufferRenderbuffer(c->fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, c->depth);
  if (glCheckNamedFramebufferStatus(c->fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    snprintf(err, BBCGL_ERR, "offscreen framebuffer %d x %d incomplete", width, height);
    bbcgl_context_free(c);
    return NULL;
  }
  return c;
}

bbcgl_context *bbcgl_context_window(int width, int height, const char *title, char *err) {
  if (!glfwInit()) {
    const char *why = NULL;
    glfwGetError(&why);
    snprintf(err, BBCGL_ERR, "no window system (%s)", why ? why : "GLFW cannot start");
    return NULL;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow *w = glfwCreateWindow(width, height, title, NULL, NULL);
  if (!w) {
    const char *why = NULL;
    glfwGetError(&why);
    snprintf(err, BBCGL_ERR, "cannot open an OpenGL 4.5 core window (%s)", why ? why : "?");
    glfwTerminate();
    return NULL;
  }
  glfwMakeContextCurrent(w);
  glfwSwapInterval(0);
  bbcgl_context *c = calloc(1, sizeof *c);
  if (c) c->counters = -1;
  if (!c) {
    glfwDestroyWindow(w);
    glfwTerminate();
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  c->window = w;
  c->dpy = EGL_NO_DISPLAY;
  glfwGetFramebufferSize(w, &c->width, &c->height);
  if (!check_version(c, err)) {
    bbcgl_context_free(c);
    return NULL;
  }
  return c;
}

void bbcgl_context_free(bbcgl_context *c) {
  if (!c) return;
  if (c->counters > 0) glDeleteQueries(3, c->query);
  if (c->window) {
    /* No glfwTerminate, for the reason given below for eglTerminate: it
     * unloads the driver; the connection closes when the process ends. */
    glfwDestroyWindow(c->window);
  } else if (c->dpy != EGL_NO_DISPLAY) {
    if (c->fbo) glDeleteFramebuffers(1, &c->fbo);
    if (c->colour) glDeleteRenderbuffers(1, &c->colour);
    if (c->depth) glDeleteRenderbuffers(1, &c->depth);
    eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(c->dpy, c->egl);
    /* No eglTerminate: it unloads the driver, and what the driver keeps for
     * the process (a few bytes) would then look leaked to LeakSanitizer
     * from an unknown module; the process ends soon after anyway. */
  }
  free(c);
}

void *bbcgl_context_window_handle(bbcgl_context *c) {
  return c->window;
}

void bbcgl_context_size(bbcgl_context *c, int *w, int *h) {
  if (c->window) glfwGetFramebufferSize(c->window, &c->width, &c->height);
  *w = c->width;
  *h = c->height;
}

void bbcgl_context_begin(bbcgl_context *c) {
  glBindFramebuffer(GL_FRAMEBUFFER, c->window ? 0 : c->fbo);
  int w, h;
  bbcgl_context_size(c, &w, &h);
  glViewport(0, 0, w, h);
}

void bbcgl_context_end(bbcgl_context *c) {
  if (c->window)
    glfwSwapBuffers(c->window);
  else
    glFinish();
}

static const GLenum k_counter_target[3] = {GL_VERTICES_SUBMITTED_ARB, GL_PRIMITIVES_SUBMITTED_ARB,
                                           GL_FRAGMENT_SHADER_INVOCATIONS_ARB};

void bbcgl_context_counters_begin(bbcgl_context *c) {
  if (c->counters < 0) {
    c->counters =
        epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    if (c->counters) glGenQueries(3, c->query);
  }
  for (int i = 0; c->counters && i < 3; i++) glBeginQuery(k_counter_target[i], c->query[i]);
}

void bbcgl_context_counters_end(bbcgl_context *c, bbcgl_counters *out) {
  memset(out, 0, sizeof *out);
  if (c->counters <= 0) return;
  GLuint64 v[3] = {0, 0, 0};
  for (int i = 0; i < 3; i++) glEndQuery(k_counter_target[i]);
  for (int i = 0; i < 3; i++) glGetQueryObjectui64v(c->query[i], GL_QUERY_RESULT, &v[i]);
  out->available = 1;
  out->vertices = v[0];
  out->primitives = v[1];
  out->fragments = v[2];
}

int bbcgl_context_read(bbcgl_context *c, bbc_image *out, char *err) {
  int w, h;
  bbcgl_context_size(c, &w, &h);
  if (bbc_image_alloc(out, w, h) != BBC_OK) {
    snprintf(err, BBCGL_ERR, "out of memory for a %d x %d screenshot", w, h);
    return 0;
  }
  if (c->window) glReadBuffer(GL_BACK);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, c->window ? 0 : c->fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, out->rgba);
  /* GL's rows start at the bottom */
  size_t row = (size_t)w * 4;
  uint8_t *tmp = malloc(row);
  if (!tmp) {
    bbc_image_free(out);
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  for (int y = 0; y < h / 2; y++) {
    memcpy(tmp, out->rgba + y * row, row);
    memcpy(out->rgba + y * row, out->rgba + (h - 1 - y) * row, row);
    memcpy(out->rgba + (h - 1 - y) * row, tmp, row);
  }
  free(tmp);
  for (size_t i = 0; i < (size_t)w * h; i++) out->rgba[4 * i + 3] = 255;
  return 1;
}

const char *bbcgl_context_describe(bbcgl_context *c) {
  return c->describe;
}
