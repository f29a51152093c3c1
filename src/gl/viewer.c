/* viewer.c — BBCgen's viewer (thesis 2.2, Appendix A `show model`): the
 * input model, the Billboard Cloud and its billboards' rectangles coloured
 * by plane kind, orbited around the model's centre. The same drawing layer
 * as the forest; a window or headless. */
#include "bbcgl.h"
#include "shader.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vbatch {
  size_t first, count; /* indices */
  GLuint tex;          /* 0: untextured */
  GLuint ntex;         /* its normal map, 0: none */
  float base[4];
  int unlit;
} vbatch;

typedef struct vmesh {
  GLuint vao, vbo, ebo;
  vbatch *batches;
  size_t batch_count;
  GLuint *textures;
  size_t texture_count;
} vmesh;

/* Coloured triangles and lines (bbc_geometry) in one buffer. */
typedef struct vgeom {
  GLuint vao, vbo;
  size_t tri_vertices, line_vertices;
  double center[3], radius;
} vgeom;

struct bbcgl_viewer {
  GLuint p_mesh, p_line;
  vmesh model, cloud;
  vgeom geom[3]; /* show bbc: the view's, the mini-model; show model's overlay */
  bbcgl__text *text;
  GLuint l_vao, l_vbo; /* rectangles: 2 vertices per edge, position + colour */
  size_t l_count;
  double center[3], radius; /* of the model (else the cloud) */
};

static const char *const k_mode_names[BBCGL_VIEW_COUNT] = {
    "input", "rects", "cloud-rects", "cloud", "domain", "continuous", "both", "density", "faces"};

const char *bbcgl_view_mode_name(bbcgl_view_mode mode) {
  return (unsigned)mode < BBCGL_VIEW_COUNT ? k_mode_names[mode] : NULL;
}

int bbcgl_view_mode_from_name(const char *name) {
  for (int i = 0; i < BBCGL_VIEW_COUNT; i++)
    if (!strcmp(name, k_mode_names[i])) return i;
  return -1;
}

void bbcgl_view_default(bbcgl_view *v) {
  memset(v, 0, sizeof *v);
  v->yaw = 30;
  v->pitch = 10;
  v->zoom = 1;
  v->lighting = 1;
  v->up_axis = 1;
  v->background[0] = v->background[1] = v->background[2] = 1;
}

static void vmesh_free(vmesh *m) {
  if (m->vao) glDeleteVertexArrays(1, &m->vao);
  if (m->vbo) glDeleteBuffers(1, &m->vbo);
  if (m->ebo) glDeleteBuffers(1, &m->ebo);
  if (m->texture_count) glDeleteTextures((GLsizei)m->texture_count, m->textures);
  free(m->textures);
  free(m->batches);
  memset(m, 0, sizeof *m);
}

/* A mesh's triangles grouped by material, its textures with mip levels. */
static int vmesh_build(vmesh *g, const bbc_mesh *m, char *err) {
  vmesh_free(g);
  if (m->kind != BBC_MESH_TRIANGLES || !m->triangle_count) {
    snprintf(err, BBCGL_ERR, "the viewer draws triangle meshes (point clouds are not supported)");
    return 0;
  }
  size_t groups = m->material_count ? m->material_count : 1;
  size_t *first = malloc(groups * sizeof *first), *count = malloc(groups * sizeof *count);
  g->batches = calloc(groups, sizeof *g->batches);
  g->textures = calloc(m->texture_count ? m->texture_count : 1, sizeof *g->textures);
  if (!first || !count || !g->batches || !g->textures ||
      !bbcgl__mesh_upload(m, NULL, &g->vao, &g->vbo, &g->ebo, first, count, NULL, NULL, err)) {
    if (!first || !count || !g->batches || !g->textures) snprintf(err, BBCGL_ERR, "out of memory");
    free(first);
    free(count);
    vmesh_free(g);
    return 0;
  }
  g->texture_count = m->texture_count;
  if (m->texture_count) glCreateTextures(GL_TEXTURE_2D, (GLsizei)m->texture_count, g->textures);
  for (size_t t = 0; t < m->texture_count; t++) {
    const bbc_image *im = &m->textures[t].image;
    if (!im->rgba || im->width < 1 || im->height < 1) continue;
    int levels = 1;
    for (int s = im->width > im->height ? im->width : im->height; s > 1 && !m->no_mipmaps; s /= 2)
      levels++;
    glTextureStorage2D(g->textures[t], levels, GL_RGBA8, im->width, im->height);
    glTextureSubImage2D(g->textures[t], 0, 0, 0, im->width, im->height, GL_RGBA, GL_UNSIGNED_BYTE,
                        im->rgba);
    if (levels > 1) glGenerateTextureMipmap(g->textures[t]);
    glTextureParameteri(g->textures[t], GL_TEXTURE_MIN_FILTER,
                        levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(g->textures[t], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  }
  for (size_t mat = 0; mat < groups; mat++) {
    if (!count[mat]) continue;
    vbatch *b = &g->batches[g->batch_count++];
    b->first = first[mat];
    b->count = count[mat];
    b->base[0] = b->base[1] = b->base[2] = b->base[3] = 1;
    if (m->material_count) {
      const bbc_material *ma = &m->materials[mat];
      memcpy(b->base, ma->base_color, sizeof b->base);
      b->unlit = ma->unlit;
      if (ma->texture >= 0 && (size_t)ma->texture < m->texture_count &&
          m->textures[ma->texture].image.rgba)
        b->tex = g->textures[ma->texture];
      if (ma->normal_map > 0 && (size_t)ma->normal_map - 1 < m->texture_count &&
          m->textures[ma->normal_map - 1].image.rgba)
        b->ntex = g->textures[ma->normal_map - 1];
    }
  }
  free(first);
  free(count);
  return 1;
}

bbcgl_viewer *bbcgl_viewer_new(char *err) {
  bbcgl_viewer *v = calloc(1, sizeof *v);
  if (!v) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return NULL;
  }
  if (!(v->p_mesh = bbcgl__program(bbcgl__glsl_viewer_mesh_vert, bbcgl__glsl_viewer_mesh_frag,
                                   "viewer mesh", err)) ||
      !(v->p_line = bbcgl__program(bbcgl__glsl_viewer_line_vert, bbcgl__glsl_viewer_line_frag,
                                   "viewer lines", err))) {
    bbcgl_viewer_free(v);
    return NULL;
  }
  glCreateVertexArrays(1, &v->l_vao);
  glCreateBuffers(1, &v->l_vbo);
  v->radius = 1;
  if (!(v->text = bbcgl__text_new(err))) {
    bbcgl_viewer_free(v);
    return NULL;
  }
  return v;
}

static void vgeom_free(vgeom *g) {
  if (g->vao) glDeleteVertexArrays(1, &g->vao);
  if (g->vbo) glDeleteBuffers(1, &g->vbo);
  memset(g, 0, sizeof *g);
}

int bbcgl_viewer_set_geometry(bbcgl_viewer *v, int slot, const bbc_geometry *geometry, char *err) {
  vgeom *g = &v->geom[slot < 0 ? 0 : slot > 2 ? 2 : slot];
  vgeom_free(g);
  if (!geometry) return 1;
  size_t nt = 3 * geometry->tri_count, nl = 2 * geometry->line_count, n = nt + nl;
  glCreateVertexArrays(1, &g->vao);
  glCreateBuffers(1, &g->vbo);
  glNamedBufferStorage(g->vbo, (GLsizeiptr)((n ? n : 1) * 6 * sizeof(float)), NULL,
                       GL_DYNAMIC_STORAGE_BIT);
  if (nt) glNamedBufferSubData(g->vbo, 0, (GLsizeiptr)(nt * 6 * sizeof(float)), geometry->tris);
  if (nl)
    glNamedBufferSubData(g->vbo, (GLintptr)(nt * 6 * sizeof(float)),
                         (GLsizeiptr)(nl * 6 * sizeof(float)), geometry->lines);
  if (glGetError() == GL_OUT_OF_MEMORY) {
    vgeom_free(g);
    snprintf(err, BBCGL_ERR, "out of GPU memory for the view's geometry");
    return 0;
  }
  glVertexArrayVertexBuffer(g->vao, 0, g->vbo, 0, 6 * sizeof(float));
  for (GLuint i = 0; i < 2; i++) {
    glEnableVertexArrayAttrib(g->vao, i);
    glVertexArrayAttribFormat(g->vao, i, 3, GL_FLOAT, GL_FALSE, i * 3 * sizeof(float));
    glVertexArrayAttribBinding(g->vao, i, 0);
  }
  g->tri_vertices = nt;
  g->line_vertices = nl;
  memcpy(g->center, geometry->center, sizeof g->center);
  g->radius = geometry->radius > 0 ? geometry->radius : 1;
  return 1;
}

void bbcgl_viewer_free(bbcgl_viewer *v) {
  if (!v) return;
  for (int i = 0; i < 3; i++) vgeom_free(&v->geom[i]);
  bbcgl__text_free(v->text);
  vmesh_free(&v->model);
  vmesh_free(&v->cloud);
  if (v->p_mesh) glDeleteProgram(v->p_mesh);
  if (v->p_line) glDeleteProgram(v->p_line);
  if (v->l_vao) glDeleteVertexArrays(1, &v->l_vao);
  if (v->l_vbo) glDeleteBuffers(1, &v->l_vbo);
  free(v);
}

int bbcgl_viewer_set_model(bbcgl_viewer *v, const bbc_mesh *model, char *err) {
  if (!vmesh_build(&v->model, model, err)) return 0;
  memcpy(v->center, model->center, sizeof v->center);
  v->radius = model->radius > 0 ? model->radius : 1;
  return 1;
}

/* Plane kinds' colours, as the preview draws them. */
static const float k_kind_colour[BBC_PLANE_KIND_COUNT][3] = {
    {0.45f, 0.75f, 1.0f}, /* standard: light blue */
    {1.0f, 0.55f, 0.1f},  /* coplanar: orange */
    {1.0f, 0.45f, 0.75f}, /* post-tweaked: pink */
    {0.25f, 0.85f, 0.3f}, /* cardboard: green */
    {0.0f, 0.9f, 0.9f},   /* parachute: cyan */
    {0.95f, 0.9f, 0.15f}, /* stem: yellow */
};

int bbcgl_viewer_set_cloud(bbcgl_viewer *v, const bbc_cloud *cloud, char *err) {
  if (!cloud) {
    vmesh_free(&v->cloud);
    v->l_count = 0;
    return 1;
  }
  if (!vmesh_build(&v->cloud, &cloud->mesh, err)) return 0;
  if (!v->model.vao) {
    memcpy(v->center, cloud->mesh.center, sizeof v->center);
    v->radius = cloud->mesh.radius > 0 ? cloud->mesh.radius : 1;
  }
  size_t n = cloud->billboard_count * 8;
  float *l = malloc((n ? n : 1) * 6 * sizeof *l);
  if (!l) {
    snprintf(err, BBCGL_ERR, "out of memory");
    return 0;
  }
  for (size_t i = 0; i < cloud->billboard_count; i++) {
    const bbc_billboard *r = &cloud->billboards[i].rect;
    double c[4][3];
    for (int k = 0; k < 3; k++) {
      c[0][k] = r->origin[k];
      c[1][k] = r->origin[k] + r->u[k] * r->width;
      c[2][k] = c[1][k] + r->w[k] * r->height;
      c[3][k] = r->origin[k] + r->w[k] * r->height;
    }
    unsigned kind = (unsigned)cloud->billboards[i].kind;
    const float *col = k_kind_colour[kind < BBC_PLANE_KIND_COUNT ? kind : 0];
    for (int e = 0; e < 4; e++)
      for (int end = 0; end < 2; end++) {
        float *o = l + 6 * (8 * i + 2 * (size_t)e + (size_t)end);
        for (int k = 0; k < 3; k++) o[k] = (float)c[(e + end) % 4][k];
        memcpy(o + 3, col, 3 * sizeof *col);
      }
  }
  glDeleteBuffers(1, &v->l_vbo);
  glCreateBuffers(1, &v->l_vbo);
  glNamedBufferStorage(v->l_vbo, (GLsizeiptr)((n ? n : 1) * 6 * sizeof *l), l, 0);
  free(l);
  v->l_count = n;
  glVertexArrayVertexBuffer(v->l_vao, 0, v->l_vbo, 0, 6 * sizeof(float));
  for (GLuint i = 0; i < 2; i++) {
    glEnableVertexArrayAttrib(v->l_vao, i);
    glVertexArrayAttribFormat(v->l_vao, i, 3, GL_FLOAT, GL_FALSE, i * 3 * sizeof(float));
    glVertexArrayAttribBinding(v->l_vao, i, 0);
  }
  return 1;
}

/* Column-major 4 x 4: out = a b. */
static void mul4(const double a[16], const double b[16], double out[16]) {
  double r[16];
  for (int c = 0; c < 4; c++)
    for (int rr = 0; rr < 4; rr++) {
      double s = 0;
      for (int k = 0; k < 4; k++) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
  memcpy(out, r, sizeof r);
}

/* The model-view-projection of an orbit around the model's centre (its up
 * axis up), and the headlight's direction in model coordinates. */
static void orbit(const double center[3], double radius, const bbcgl_view *view, int w, int h,
                  float mvp[16], float light[3]) {
  const double pi = 3.14159265358979323846, fov = 35 * pi / 180;
  double zoom = view->zoom > 0 ? view->zoom : 1;
  double dist = radius / sin(fov / 2) * 1.05 / zoom;
  double near = dist - 2 * radius > dist * 0.01 ? dist - 2 * radius : dist * 0.01;
  double far = dist + 2 * radius;
  double f = 1 / tan(fov / 2), aspect = h > 0 ? (double)w / h : 1;
  double proj[16] = {f / aspect,
                     0,
                     0,
                     0,
                     0,
                     f,
                     0,
                     0,
                     0,
                     0,
                     (far + near) / (near - far),
                     -1,
                     0,
                     0,
                     2 * far * near / (near - far),
                     0};
  /* model: centre to the origin; a z-up model turned so that z is up on screen */
  double model[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -center[0], -center[1], -center[2], 1};
  if (view->up_axis == 2) {
    double zup[16] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
    mul4(zup, model, model);
  } else if (view->up_axis == 0) {
    double xup[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    mul4(xup, model, model);
  }
  double ya = view->yaw * pi / 180, pa = view->pitch * pi / 180;
  double ry[16] = {cos(ya), 0, sin(ya), 0, 0, 1, 0, 0, -sin(ya), 0, cos(ya), 0, 0, 0, 0, 1};
  double rx[16] = {1, 0, 0, 0, 0, cos(pa), -sin(pa), 0, 0, sin(pa), cos(pa), 0, 0, 0, 0, 1};
  double tr[16] = {
      1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, view->pan[0] * radius, -view->pan[1] * radius, -dist, 1};
  double rot[16], viewm[16], m[16];
  mul4(rx, ry, rot);
  mul4(tr, rot, viewm);
  mul4(viewm, model, m);
  mul4(proj, m, m);
  for (int i = 0; i < 16; i++) mvp[i] = (float)m[i];
  /* the headlight (towards the eye) in model coordinates: the inverse of
   * the rotation part of viewm * model applied to +z */
  double rm[16];
  mul4(rot, model, rm);
  double d[3] = {rm[2], rm[6], rm[10]}; /* row 2 of the rotation = its inverse's column */
  double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int k = 0; k < 3; k++) light[k] = (float)(l > 0 ? d[k] / l : k == 1);
}

static void draw_mesh(const bbcgl_viewer *v, const vmesh *g, const bbcgl_view *view) {
  if (!g->vao) return;
  GLuint p = v->p_mesh;
  glUniform1i(glGetUniformLocation(p, "u_lighting"), view->lighting);
  glBindVertexArray(g->vao);
  for (size_t i = 0; i < g->batch_count; i++) {
    const vbatch *b = &g->batches[i];
    glUniform4fv(glGetUniformLocation(p, "u_base"), 1, b->base);
    GLuint tex = view->normal_maps && b->ntex ? b->ntex : b->tex;
    glUniform1i(glGetUniformLocation(p, "u_has_tex"), tex != 0);
    glUniform1i(glGetUniformLocation(p, "u_unlit"), b->unlit || tex != b->tex);
    if (tex) glBindTextureUnit(0, tex);
    glDrawElements(GL_TRIANGLES, (GLsizei)b->count, GL_UNSIGNED_INT,
                   (const void *)(b->first * sizeof(uint32_t)));
  }
}

static void clear_rect(const bbcgl_view *view, int x, int y, int width, int height) {
  glViewport(x, y, width, height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, y, width, height);
  glClearColor(view->background[0], view->background[1], view->background[2], 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
}

/* show bbc's geometry: grid views with y up, the faces in the model's frame. */
static void draw_geometry(const bbcgl_viewer *v, const vgeom *g, const bbcgl_view *view, int grid,
                          int width, int height) {
  if (!g->vao) return;
  bbcgl_view gv = *view;
  if (grid == 1) gv.up_axis = 1; /* 2: in the model's frame, depth-tested like the grid */
  float mvp[16], light[3];
  orbit(g->center, g->radius, &gv, width, height, mvp, light);
  glUseProgram(v->p_line);
  glUniformMatrix4fv(glGetUniformLocation(v->p_line, "u_mvp"), 1, GL_FALSE, mvp);
  glBindVertexArray(g->vao);
  if (!grid) { /* the faces: the wireframe, then the solid faces over it */
    if (g->line_vertices) glDrawArrays(GL_LINES, (GLint)g->tri_vertices, (GLsizei)g->line_vertices);
    glDepthFunc(GL_ALWAYS);
  }
  glPolygonMode(GL_FRONT_AND_BACK, view->wireframe ? GL_LINE : GL_FILL);
  if (g->tri_vertices) glDrawArrays(GL_TRIANGLES, 0, (GLsizei)g->tri_vertices);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDepthFunc(GL_LEQUAL);
  if (grid && g->line_vertices)
    glDrawArrays(GL_LINES, (GLint)g->tri_vertices, (GLsizei)g->line_vertices);
}

void bbcgl_viewer_draw(bbcgl_viewer *v, bbcgl_view_mode mode, const bbcgl_view *view, int x, int y,
                       int width, int height) {
  clear_rect(view, x, y, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  if (mode >= BBCGL_VIEW_DOMAIN) {
    draw_geometry(v, &v->geom[0], view, mode != BBCGL_VIEW_FACES, width, height);
    if (view->mini && mode != BBCGL_VIEW_FACES && v->geom[1].vao) {
      /* the mini-model: a quarter of the height in the top left corner, framed */
      int s = height / 4 > 32 ? height / 4 : 32;
      bbcgl_view mv = *view;
      mv.background[0] = mv.background[1] = mv.background[2] =
          view->background[0] > 0.5f ? 0.92f : 0.12f;
      mv.wireframe = 0;
      clear_rect(&mv, x, y + height - s, s, s);
      draw_geometry(v, &v->geom[1], &mv, 0, s, s);
    }
    return;
  }
  float mvp[16], light[3];
  orbit(v->center, v->radius, view, width, height, mvp, light);
  glPolygonMode(GL_FRONT_AND_BACK, view->wireframe ? GL_LINE : GL_FILL);
  glUseProgram(v->p_mesh);
  glUniformMatrix4fv(glGetUniformLocation(v->p_mesh, "u_mvp"), 1, GL_FALSE, mvp);
  glUniform3fv(glGetUniformLocation(v->p_mesh, "u_light"), 1, light);
  glUniform1i(glGetUniformLocation(v->p_mesh, "u_tex"), 0);
  if (mode == BBCGL_VIEW_INPUT || mode == BBCGL_VIEW_RECTS) draw_mesh(v, &v->model, view);
  if ((mode == BBCGL_VIEW_INPUT || mode == BBCGL_VIEW_RECTS) && v->geom[2].vao) {
    draw_geometry(v, &v->geom[2], view, 2, width, height);
    glUseProgram(v->p_mesh);
  }
  if (mode == BBCGL_VIEW_CLOUD || mode == BBCGL_VIEW_CLOUD_RECTS) draw_mesh(v, &v->cloud, view);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  if ((mode == BBCGL_VIEW_RECTS || mode == BBCGL_VIEW_CLOUD_RECTS) && v->l_count) {
    glUseProgram(v->p_line);
    glUniformMatrix4fv(glGetUniformLocation(v->p_line, "u_mvp"), 1, GL_FALSE, mvp);
    glBindVertexArray(v->l_vao);
    glDrawArrays(GL_LINES, 0, (GLsizei)v->l_count);
  }
}

void bbcgl_viewer_text(bbcgl_viewer *v, int width, int height, const char *const *lines,
                       size_t count) {
  glViewport(0, 0, width, height);
  bbcgl__text_draw(v->text, width, height, lines, count, width >= 1100 ? 2 : 1, 1);
}
