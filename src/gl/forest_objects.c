/* forest_objects.c — drawing the forest's 3D objects (thesis 3.2.3): the
 * instance buffer (the culling's static records once, then each frame's),
 * per part and material one multi-draw of indirect commands, or the naive
 * way (thesis 3.3) a draw call per tree and billboard, or culling and levels
 * of detail in a compute shader (GPU culling) that fills the commands in. */
#include "forest_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

/* A material's uniforms of the model program. */
static void set_batch(const bbcgl_forest *f, const batch *ba) {
  glUniform1i(f->u_has, ba->tex[0] == 0 ? 0 : ba->premultiplied ? 2 : 1);
  glUniform1i(f->u_texel_alpha, ba->texel_alpha);
  glUniform4fv(f->u_base, 1, ba->base);
  glUniform1i(f->u_lit, ba->lit);
  glUniform2i(f->u_maps, ba->tex[1] != 0, ba->tex[2] != 0);
  glUniform1f(f->u_sway, ba->sway);
  const bbc_impostor *im = ba->imp;
  glUniform4i(f->u_imp, im ? im->frames : 0, im ? im->hemi : 0, im ? im->frame_size : 0, im != 0);
  if (im) {
    glUniform4f(f->u_imp_c, (float)im->center[0], (float)im->center[1], (float)im->center[2],
                (float)im->half_extent);
    glUniform1f(f->u_imp_r, (float)im->radius);
    GLint lv[2 * BBCGL_IMP_LEVELS];
    int n = bbc_impostor_level_count(im);
    for (int l = 0; l < BBCGL_IMP_LEVELS; l++) {
      int k = l < n ? l : n - 1; /* past the last: the last */
      lv[2 * l] = bbc_impostor_level_size(im, k);
      lv[2 * l + 1] = bbcgl__impostor_level_row(im, k);
    }
    glUniform2iv(f->u_imp_lv, BBCGL_IMP_LEVELS, lv);
  }
  if (ba->single_sided)
    glEnable(GL_CULL_FACE);
  else
    glDisable(GL_CULL_FACE);
}

/* A material's maps on units 0, 1, 2 where they are not bound already
 * (bound[3]: what is). */
static void bind_maps(const batch *ba, GLuint *bound, bbcgl_stats *st) {
  for (int k = 0; k < 3; k++)
    if (ba->tex[k] && ba->tex[k] != bound[k]) {
      glBindTextureUnit((GLuint)k, ba->tex[k]);
      bound[k] = ba->tex[k];
      st->texture_binds++;
    }
}

/* The thesis's way (3.3), for measuring against: per tree, level and
 * billboard its own draw call and texture bind (the culling's per-frame
 * records, after the static ones in the buffer). */
static void draw_objects_naive(bbcgl_forest *f, const bbc_forest_records *c, bbcgl_stats *st) {
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t first = c->static_count + c->bucket_start[pt->bucket],
           count = c->bucket_start[pt->bucket + 1] - c->bucket_start[pt->bucket];
    for (size_t tree = 0; tree < count; tree++) {
      glBindVertexArray(pt->vao);
      for (size_t b = 0; b < pt->batch_count; b++) {
        const batch *ba = &pt->batches[b];
        GLuint none[3] = {0, 0, 0}; /* the thesis's way: bound for every call */
        bind_maps(ba, none, st);
        set_batch(f, ba);
        if (!pt->billboards) { /* a polygon model: one call (its display list) */
          glDrawElementsInstancedBaseInstance(GL_TRIANGLES, (GLsizei)ba->count, GL_UNSIGNED_INT,
                                              (const void *)(ba->first * sizeof(uint32_t)), 1,
                                              (GLuint)(first + tree));
          st->draw_calls++;
        }
        for (size_t r = 0; pt->billboards && r < ba->run_count; r++) {
          glDrawElementsInstancedBaseInstance(
              GL_TRIANGLES, (GLsizei)ba->runs[2 * r + 1], GL_UNSIGNED_INT,
              (const void *)(ba->runs[2 * r] * sizeof(uint32_t)), 1, (GLuint)(first + tree));
          st->draw_calls++;
        }
        st->triangles += ba->count / 3;
      }
      st->billboards += pt->billboards;
    }
  }
}

/* The instance buffer holds the static records (uploaded once) and this
 * frame's records after them. */
static int upload_instances(bbcgl_forest *f, const bbc_forest_records *c) {
  size_t s = c->static_count, n = c->bucket_start[c->bucket_count];
  if (s + n > f->instance_capacity) {
    size_t cap = s + n + n / 2 + 1024;
    glNamedBufferData(f->instances, (GLsizeiptr)(cap * sizeof(bbc_forest_draw)), NULL,
                      GL_DYNAMIC_DRAW);
    f->instance_capacity = cap;
    f->statics_uploaded = NULL;
    for (size_t i = 0; i < f->part_count; i++)
      glVertexArrayVertexBuffer(f->parts[i].vao, 1, f->instances, 0, sizeof(bbc_forest_draw));
    f->vao_source = f->instances;
  }
  if (f->statics_uploaded != (const void *)c->statics || f->statics_count != s) {
    if (s)
      glNamedBufferSubData(f->instances, 0, (GLsizeiptr)(s * sizeof(bbc_forest_draw)), c->statics);
    f->statics_uploaded = c->statics;
    f->statics_count = s;
  }
  if (n) {
    glInvalidateBufferSubData(f->instances, (GLintptr)(s * sizeof(bbc_forest_draw)),
                              (GLsizeiptr)(n * sizeof(bbc_forest_draw)));
    glNamedBufferSubData(f->instances, (GLintptr)(s * sizeof(bbc_forest_draw)),
                         (GLsizeiptr)(n * sizeof(bbc_forest_draw)), c->draws);
  }
  return 1;
}

/* One material of a part: its texture (when not bound already), its
 * uniforms, and `n` commands of the bound indirect buffer from `first`. */
static void multi_draw(bbcgl_forest *f, const batch *ba, size_t first, size_t n, GLuint *bound,
                       bbcgl_stats *st) {
  bind_maps(ba, bound, st);
  set_batch(f, ba);
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                              (const void *)(first * 5 * sizeof(uint32_t)), (GLsizei)n, 0);
  st->draw_calls++;
  st->draw_commands += n;
}

/* The parts' VAOs take their instance records from `buf`. */
static void vao_source(bbcgl_forest *f, GLuint buf) {
  if (f->vao_source == buf) return;
  for (size_t i = 0; i < f->part_count; i++)
    glVertexArrayVertexBuffer(f->parts[i].vao, 1, buf, 0, sizeof(bbc_forest_draw));
  f->vao_source = buf;
}

/* GPU culling's programs and buffers: per bucket a region of the output as
 * large as its model's records, the first-component bits, and one indirect
 * command per part and material (its instance count filled in each frame). */
static void gpu_build(bbcgl_forest *f, const bbc_forest_records *c) {
  f->gpu_state = -1;
  snprintf(f->gpu_err, sizeof f->gpu_err, "GPU culling: out of memory");
  if (!(f->p_cull = bbcgl__compute_program(bbcgl__glsl_forest_cull_comp, "cull", f->gpu_err)) ||
      !(f->p_cmdfill =
            bbcgl__compute_program(bbcgl__glsl_forest_cmdfill_comp, "cmdfill", f->gpu_err)))
    return;
  size_t nb = c->bucket_count, ncell = c->cell_count, total = 0;
  f->g_base = calloc(nb + 1, sizeof *f->g_base);
  size_t words = (c->static_count + 31) / 32 + 1;
  uint32_t *bits = calloc(words, sizeof *bits);
  size_t ncmd = 0;
  for (size_t i = 0; i < f->part_count; i++)
    if (f->parts[i].bucket < nb) ncmd += f->parts[i].batch_count;
  uint32_t(*cmd)[5] = calloc(ncmd + 1, sizeof *cmd);
  uint32_t *cmd_bucket = calloc(ncmd + 1, sizeof *cmd_bucket);
  if (!f->g_base || !bits || !cmd || !cmd_bucket) {
    free(bits);
    free(cmd);
    free(cmd_bucket);
    return;
  }
  for (size_t m = 0; m < c->model_count; m++) {
    const uint32_t *st = c->model_cell_start + m * (ncell + 1);
    for (size_t l = 0; l < c->models[m].lod_count; l++) {
      f->g_base[c->bucket_base[m] + l] = total;
      total += st[ncell] - st[0];
    }
  }
  for (size_t i = 0; i < c->static_count; i++)
    if (c->static_first[i]) bits[i >> 5] |= 1u << (i & 31);
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= nb) continue;
    for (size_t b = 0; b < pt->batch_count; b++, k++) {
      cmd[k][0] = (uint32_t)pt->batches[b].count;
      cmd[k][2] = (uint32_t)pt->batches[b].first;
      cmd[k][4] = (uint32_t)f->g_base[pt->bucket];
      cmd_bucket[k] = (uint32_t)pt->bucket;
    }
  }
  f->g_ncmd = ncmd;
  glCreateBuffers(1, &f->g_out);
  glCreateBuffers(1, &f->g_counters);
  glCreateBuffers(1, &f->g_first);
  glCreateBuffers(1, &f->g_cmds);
  glCreateBuffers(1, &f->g_cmd_bucket);
  glNamedBufferStorage(f->g_out, (GLsizeiptr)((total ? total : 1) * sizeof(bbc_forest_draw)), NULL,
                       0);
  glNamedBufferStorage(f->g_counters, (GLsizeiptr)((nb + 1) * sizeof(uint32_t)), NULL,
                       GL_DYNAMIC_STORAGE_BIT);
  glNamedBufferStorage(f->g_first, (GLsizeiptr)(words * sizeof *bits), bits, 0);
  glNamedBufferStorage(f->g_cmds, (GLsizeiptr)((ncmd + 1) * sizeof *cmd), cmd, 0);
  glNamedBufferStorage(f->g_cmd_bucket, (GLsizeiptr)((ncmd + 1) * sizeof *cmd_bucket), cmd_bucket,
                       0);
  free(bits);
  free(cmd);
  free(cmd_bucket);
  f->gpu_state = 1;
}

/* GPU culling, before the drawing: every static record of every model
 * through the cull shader, then the commands' instance counts. */
static int gpu_cull(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_records *c) {
  if (!f->gpu_state) gpu_build(f, c);
  if (f->gpu_state < 0 || !c->static_count) return 0;
  upload_instances(f, c);
  glClearNamedBufferData(f->g_counters, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
  GLuint p = f->p_cull;
  glUseProgram(p);
  double pl[6][4];
  bbc_forest_frustum_from_matrix(fr->viewproj, pl);
  float plf[24];
  for (int i = 0; i < 24; i++) plf[i] = (float)pl[i / 4][i % 4];
  glUniform4fv(glGetUniformLocation(p, "u_planes"), 6, plf);
  glUniform3f(glGetUniformLocation(p, "u_eye"), (float)fr->eye[0], (float)fr->eye[1],
              (float)fr->eye[2]);
  glUniform1f(glGetUniformLocation(p, "u_zoom"), (float)(fr->zoom > 0 ? fr->zoom : 1));
  glUniform1ui(glGetUniformLocation(p, "u_trees"), (GLuint)c->bucket_count);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, f->instances, 0,
                    (GLsizeiptr)(c->static_count * sizeof(bbc_forest_draw)));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, f->g_out);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, f->g_counters);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, f->g_first);
  GLint u_first = glGetUniformLocation(p, "u_first"), u_count = glGetUniformLocation(p, "u_count"),
        u_bucket0 = glGetUniformLocation(p, "u_bucket0"),
        u_radius = glGetUniformLocation(p, "u_radius"), u_fade = glGetUniformLocation(p, "u_fade"),
        u_lods = glGetUniformLocation(p, "u_lods"), u_range = glGetUniformLocation(p, "u_range"),
        u_base = glGetUniformLocation(p, "u_base");
  size_t ncell = c->cell_count;
  for (size_t m = 0; m < c->model_count; m++) {
    const uint32_t *st = c->model_cell_start + m * (ncell + 1);
    uint32_t first = st[0], count = st[ncell] - st[0];
    const bbc_forest_lod_model *mod = &c->models[m];
    if (!count || !mod->lod_count) continue;
    int lods = mod->lod_count > 8 ? 8 : (int)mod->lod_count;
    float range[16];
    GLuint base[8];
    for (int l = 0; l < lods; l++) {
      range[2 * l] = (float)mod->ranges[2 * l];
      range[2 * l + 1] = (float)mod->ranges[2 * l + 1];
      base[l] = (GLuint)f->g_base[c->bucket_base[m] + (size_t)l];
    }
    glUniform1ui(u_first, first);
    glUniform1ui(u_count, count);
    glUniform1ui(u_bucket0, (GLuint)c->bucket_base[m]);
    glUniform1f(u_radius, (float)mod->radius);
    glUniform1f(u_fade, (float)(mod->fade > 0 ? mod->fade : 0));
    glUniform1i(u_lods, lods);
    glUniform2fv(u_range, lods, range);
    glUniform1uiv(u_base, lods, base);
    glDispatchCompute((count + 255) / 256, 1, 1);
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(f->p_cmdfill);
  glUniform1ui(glGetUniformLocation(f->p_cmdfill, "u_ncmd"), (GLuint)f->g_ncmd);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, f->g_cmds);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, f->g_cmd_bucket);
  glDispatchCompute((GLuint)((f->g_ncmd + 63) / 64), 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
  return 1;
}

static void draw_objects_gpu(bbcgl_forest *f, const bbc_forest_records *c, bbcgl_stats *st) {
  vao_source(f, f->g_out);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f->g_cmds);
  GLuint bound[3] = {0, 0, 0};
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    glBindVertexArray(pt->vao);
    for (size_t bi = 0; bi < pt->batch_count; bi++, k++)
      multi_draw(f, &pt->batches[bi], k, 1, bound, st);
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  /* the statistics: the counters read back (waits for the culling) */
  uint32_t *n = calloc(c->bucket_count + 1, sizeof *n);
  if (!n) return;
  glGetNamedBufferSubData(f->g_counters, 0, (GLsizeiptr)((c->bucket_count + 1) * sizeof *n), n);
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    st->billboards += n[pt->bucket] * pt->billboards;
    for (size_t bi = 0; bi < pt->batch_count; bi++)
      st->triangles += n[pt->bucket] * pt->batches[bi].count / 3;
  }
  st->trees = n[c->bucket_count];
  free(n);
}

/* An indirect command: the batch's indices, `n` instances from `first`. */
static void set_command(uint32_t *cmd, const batch *ba, uint32_t n, uint32_t first) {
  cmd[0] = (uint32_t)ba->count;
  cmd[1] = n;
  cmd[2] = (uint32_t)ba->first;
  cmd[3] = 0;
  cmd[4] = first;
}

/* Bucket b's commands per material: whole ranges and per-frame records
 * (weights in the records), then blend ranges (weights from the distance). */
static size_t whole_commands(const bbc_forest_records *c, size_t b) {
  return c->range_blend[b] - c->range_start[b] + (c->bucket_start[b + 1] > c->bucket_start[b]);
}
static size_t blend_commands(const bbc_forest_records *c, size_t b) {
  return c->range_start[b + 1] - c->range_blend[b];
}

/* This frame's multi-draw commands in f->cmds (grown when needed): per part
 * and material a command per whole range of its bucket, one for the
 * bucket's per-frame records, then one per blend range. Their number; 0:
 * nothing to draw (or no memory for them). */
static size_t fill_commands(bbcgl_forest *f, const bbc_forest_records *c) {
  size_t ncmd = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    ncmd += (whole_commands(c, pt->bucket) + blend_commands(c, pt->bucket)) * pt->batch_count;
  }
  if (!ncmd) return 0;
  if (ncmd > f->cmd_capacity) {
    size_t cap = ncmd + ncmd / 2 + 64;
    uint32_t(*d)[5] = realloc(f->cmds, cap * sizeof *d);
    if (!d) return 0;
    f->cmds = d;
    f->cmd_capacity = cap;
    glNamedBufferData(f->indirect, (GLsizeiptr)(cap * sizeof *d), NULL, GL_DYNAMIC_DRAW);
  }
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t b = pt->bucket, dyn = c->bucket_start[b + 1] - c->bucket_start[b];
    for (size_t ba = 0; ba < pt->batch_count; ba++) {
      for (size_t r = c->range_start[b]; r < c->range_blend[b]; r++)
        set_command(f->cmds[k++], &pt->batches[ba], c->ranges[r][1], c->ranges[r][0]);
      if (dyn)
        set_command(f->cmds[k++], &pt->batches[ba], (uint32_t)dyn,
                    (uint32_t)(c->static_count + c->bucket_start[b]));
      for (size_t r = c->range_blend[b]; r < c->range_start[b + 1]; r++)
        set_command(f->cmds[k++], &pt->batches[ba], c->ranges[r][1], c->ranges[r][0]);
    }
  }
  return ncmd;
}

/* The levels of bucket b for the shader's weights of blend ranges: its
 * range's start and end, the model's fade, 1 / zoom (as
 * bbc_forest_lod_get_weight, distances divided by the zoom). */
static void bucket_lod(const bbc_forest_cull *cull, const bbc_forest_records *c, size_t b,
                       float lod[4]) {
  size_t l, m = bbc_forest_cull_get_bucket_model(cull, b, &l);
  const bbc_forest_lod_model *mod = &c->models[m];
  lod[0] = (float)mod->ranges[2 * l];
  lod[1] = (float)(mod->ranges[2 * l + 1] < 1e30 ? mod->ranges[2 * l + 1] : 1e30);
  lod[2] = (float)(mod->fade > 0 ? mod->fade : 0);
  lod[3] = (float)(1 / (c->zoom > 0 ? c->zoom : 1));
}

/* The CPU culling's objects: per part and material a multi-draw of whole
 * ranges and per-frame records, and one of blend ranges. */
static void draw_objects_indirect(bbcgl_forest *f, const bbc_forest_cull *cull,
                                  const bbc_forest_records *c, bbcgl_stats *st) {
  size_t ncmd = fill_commands(f, c);
  if (!ncmd) return;
  glInvalidateBufferData(f->indirect);
  glNamedBufferSubData(f->indirect, 0, (GLsizeiptr)(ncmd * sizeof *f->cmds), f->cmds);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f->indirect);
  GLuint bound[3] = {0, 0, 0};
  size_t k = 0;
  for (size_t i = 0; i < f->part_count; i++) {
    const part *pt = &f->parts[i];
    if (pt->bucket >= c->bucket_count) continue;
    size_t b = pt->bucket, count = bbc_forest_cull_get_bucket_size(cull, b);
    size_t whole = whole_commands(c, b), blend = blend_commands(c, b);
    if (!whole && !blend) continue;
    glBindVertexArray(pt->vao);
    float lod[4];
    bucket_lod(cull, c, b, lod);
    glUniform4fv(f->u_lod, 1, lod);
    for (size_t bi = 0; bi < pt->batch_count; bi++) {
      const batch *ba = &pt->batches[bi];
      if (whole) multi_draw(f, ba, k, whole, bound, st);
      k += whole;
      if (blend) {
        glUniform1i(f->u_blend, 1);
        multi_draw(f, ba, k, blend, bound, st);
        glUniform1i(f->u_blend, 0);
      }
      k += blend;
      st->triangles += count * ba->count / 3;
    }
    st->billboards += count * pt->billboards;
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

/* The objects of the frame: the model program's uniforms, then drawn the
 * naive way, by indirect multi-draws of the CPU culling's records, or
 * culled and drawn on the GPU. */
void bbcgl__forest_draw_objects(bbcgl_forest *f, const bbcgl_frame *fr, const bbc_forest_cull *cull,
                                bbcgl_stats *st) {
  bbc_forest_records rec;
  bbc_forest_cull_get_records(cull, &rec);
  const bbc_forest_records *c = &rec;
  st->trees = c->trees_visible;
  int gpu = 0;
  if (fr->gpu_cull && !fr->naive && c->bucket_count) {
    if (!gpu_cull(f, fr, c)) return;
    gpu = 1;
  } else if (!c->bucket_count || !upload_instances(f, c)) {
    return;
  }
  GLuint p = f->p_model;
  glUseProgram(p);
  glUniformMatrix4fv(glGetUniformLocation(p, "u_viewproj"), 1, GL_FALSE, fr->viewproj);
  bbcgl__forest_set_fog(p, f, fr->eye);
  bbcgl__forest_set_sun(p, fr);
  const bbc_forest_wind *w = &f->scene.wind;
  glUniform3f(glGetUniformLocation(p, "u_wind"), (float)w->strength, (float)w->dir[0],
              (float)w->dir[1]);
  glUniform1f(glGetUniformLocation(p, "u_time"), (float)fr->time);
  glUniform1i(f->u_blend, 0);
  glUniform1i(glGetUniformLocation(p, "u_tex"), 0);
  glUniform1i(glGetUniformLocation(p, "u_normal"), 1);
  glUniform1i(glGetUniformLocation(p, "u_occlusion"), 2);
  glUniform1i(glGetUniformLocation(p, "u_fill"), fr->fill_colour);
  if (gpu) {
    draw_objects_gpu(f, c, st);
    return;
  }
  vao_source(f, f->instances);
  if (fr->naive) {
    draw_objects_naive(f, c, st);
    return;
  }
  draw_objects_indirect(f, cull, c, st);
}

const char *bbcgl_forest_gpu_cull_error(const bbcgl_forest *f) {
  return f->gpu_state < 0 ? f->gpu_err : NULL;
}
