/* bake.c — step 3, baking one billboard (thesis 2.1.9, 2.2.5, 2.3.9): the
 * faces in its plane's +-epsilon slab (or a point cloud's points), its
 * outline, its images from the software rasterizer (front and back, normal
 * maps, prelit, voxel-shadowed) and, with quality 2, their alpha by the
 * coverage of their supersamples. Also what every billboard's bake shares,
 * and all of them baked in parallel. */
#include "cloud.h"
#include "raster.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

typedef bbc__baked baked;

/* Sutherland-Hodgman: keeps the part of polygon p (n corners, (s, t)) where
 * a s + b t <= c. Returns the new corner count (<= n + 1). */
static int clip_half(double p[][2], int n, double a, double b, double c) {
  double out[12][2];
  int m = 0;
  for (int i = 0; i < n; i++) {
    const double *P = p[i], *Q = p[(i + 1) % n];
    double fp = a * P[0] + b * P[1] - c, fq = a * Q[0] + b * Q[1] - c;
    if (fp <= 0 && m < 12) {
      out[m][0] = P[0];
      out[m][1] = P[1];
      m++;
    }
    if (((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) && m < 12) {
      double t = fp / (fp - fq);
      out[m][0] = P[0] + t * (Q[0] - P[0]);
      out[m][1] = P[1] + t * (Q[1] - P[1]);
      m++;
    }
  }
  memcpy(p, out, (size_t)m * sizeof out[0]);
  return m;
}

static double polygon_area(double p[][2], int n) { /* an outline: at most 10 corners */
  bbc__pt2 q[10];
  assert(n >= 0 && n <= 10);
  for (int i = 0; i < n; i++) q[i] = (bbc__pt2){p[i][0], p[i][1]};
  return bbc__polygon_area_2d(q, (size_t)n);
}

/* The rectangle clipped to the box lo..hi (model units): in (s, t) of the
 * rectangle, s, t in [0, 1]. Falls back to the whole rectangle when the
 * clip leaves (almost) nothing, which only rounding can cause. */
static void outline(const bbc_billboard *b, const double lo[3], const double hi[3],
                    bbc_cloud_billboard *cb) {
  double p[12][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  int n = 4;
  double W = b->width, H = b->height;
  for (int k = 0; k < 3 && n >= 3; k++) {
    /* x_k = origin_k + s W u_k + t H w_k */
    double a = W * b->u[k], c = H * b->w[k];
    n = clip_half(p, n, a, c, hi[k] - b->origin[k]);
    if (n >= 3) n = clip_half(p, n, -a, -c, b->origin[k] - lo[k]);
  }
  /* Corners on a line with their neighbours (or on them) would give the
   * fan zero-area triangles, which a mesh drops: removed. */
  for (int i = 0; n > 3 && i < n;) {
    const double *A = p[(i + n - 1) % n], *B = p[i], *C = p[(i + 1) % n];
    double cr = (B[0] - A[0]) * (C[1] - B[1]) - (B[1] - A[1]) * (C[0] - B[0]);
    if (fabs(cr) <= 1e-9) {
      memmove(p[i], p[i + 1], (size_t)(n - 1 - i) * sizeof p[0]);
      n--;
      i = 0;
    } else {
      i++;
    }
  }
  if (n < 3 || n > 10 || polygon_area(p, n) < 1e-9) {
    double r[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    memcpy(p, r, sizeof r);
    n = 4;
  }
  cb->corner_count = n;
  memcpy(cb->corners, p, (size_t)n * sizeof p[0]);
}

/* Whether triangle t crosses plane p's +-eps slab. */
static int crosses_slab(const bbc_mesh *m, size_t t, const bbc_plane *p, double eps) {
  const uint32_t *ix = m->indices + 3 * t;
  double dmin = INFINITY, dmax = -INFINITY;
  for (int c = 0; c < 3; c++) {
    const double *x = m->positions + 3 * ix[c];
    double d = p->normal[0] * x[0] + p->normal[1] * x[1] + p->normal[2] * x[2] - p->d;
    dmin = d < dmin ? d : dmin; /* finite positions (the loader checks): no fmin call */
    dmax = d > dmax ? d : dmax;
  }
  return !(dmin > eps || dmax < -eps);
}

/* Faces drawn into a billboard: those crossing the +-eps slab (or, pure,
 * its plane's own), or with `mask` those it marks (a stem billboard), and
 * their bounds. Returns the count. */
static size_t slab_faces(const bbc_mesh *m, const bbc_planeset *set, const bbc_plane *p,
                         uint32_t owner, double eps, bbc_pure pure, const uint8_t *mask,
                         uint32_t *faces, double lo[3], double hi[3]) {
  size_t n = 0;
  for (int k = 0; k < 3; k++) {
    lo[k] = INFINITY;
    hi[k] = -INFINITY;
  }
  for (size_t t = 0; t < m->triangle_count; t++) {
    const uint32_t *ix = m->indices + 3 * t;
    if (mask) {
      if (!mask[t]) continue;
    } else {
      if (set->face_plane[t] == BBC_NO_PLANE) continue; /* in the limbs' mesh */
      if (pure == BBC_PURE_OWN && set->face_plane[t] != owner) continue;
      if (!crosses_slab(m, t, p, eps)) continue;
    }
    faces[n++] = (uint32_t)t;
    for (int c = 0; c < 3; c++)
      for (int k = 0; k < 3; k++) {
        double x = m->positions[3 * ix[c] + k];
        lo[k] = x < lo[k] ? x : lo[k];
        hi[k] = x > hi[k] ? x : hi[k];
      }
  }
  return n;
}

/* A point cloud's points within the plane's +-eps slab (pure: those of
 * plane `owner`), and their bounds. */
static size_t slab_points(const bbc_mesh *m, const bbc_planeset *set, const bbc_plane *p,
                          uint32_t owner, double eps, bbc_pure pure, uint32_t *out, double lo[3],
                          double hi[3]) {
  size_t n = 0;
  for (int k = 0; k < 3; k++) {
    lo[k] = INFINITY;
    hi[k] = -INFINITY;
  }
  for (size_t v = 0; v < m->vertex_count; v++) {
    if (pure == BBC_PURE_OWN && set->face_plane[v] != owner) continue;
    const double *x = m->positions + 3 * v;
    double d = p->normal[0] * x[0] + p->normal[1] * x[1] + p->normal[2] * x[2] - p->d;
    if (d > eps || d < -eps) continue;
    out[n++] = (uint32_t)v;
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(lo[k], x[k]);
      hi[k] = fmax(hi[k], x[k]);
    }
  }
  return n;
}

/* pure 2: the alpha each triangle's samples get, 255 / n for a triangle
 * crossing the slabs of n kept planes, so that its coverage reaches the
 * images once in all (quality 2's dithering sums the shares). NULL when out
 * of memory. */
static uint8_t *face_shares(const bbc_mesh *m, const bbc_planeset *set, const size_t *order,
                            size_t nk) {
  uint8_t *share = malloc(m->triangle_count ? m->triangle_count : 1);
  if (!share) return NULL;
  for (size_t t = 0; t < m->triangle_count; t++) {
    unsigned n = 0;
    for (size_t k = 0; k < nk; k++) {
      const bbc_plane *p = &set->planes[order[k]];
      n += (unsigned)crosses_slab(m, t, p, set->parts[p->part].epsilon_abs);
    }
    share[t] = (uint8_t)(n > 1 ? (255 + n / 2) / n : 255);
  }
  return share;
}

/* One billboard to bake: plane p's faces crossing its +-eps slab (pure:
 * those of plane `owner`), or with `mask` the faces it marks (a stem
 * billboard, eps its slab); `share` as bbc__bake_inputs's (NULL for a stem
 * billboard). */
typedef struct bake_job {
  const bbc_plane *p;
  uint32_t owner;
  double eps;
  const uint8_t *mask;
  const uint8_t *share;
} bake_job;

/* The faces (or points) drawn into billboard cb, listed in faces[] (their
 * count in cb->face_count), and its outline: its rectangle clipped to their
 * bounds. */
static void bake_faces(const bbc__bake_inputs *in, const bake_job *job, bbc_cloud_billboard *cb,
                       uint32_t *faces) {
  const bbc_mesh *m = in->mesh;
  const bbc_params *prm = in->params;
  const bbc_plane *p = job->p;
  double eps = job->eps;
  const uint8_t *mask = job->mask;
  const bbc_billboard *b = &cb->rect;
  double lo[3], hi[3];
  int points = m->kind == BBC_MESH_POINTS;
  /* A leftovers' plane: its own faces only (its slab crosses the crown
   * where other planes' billboards show the faces already). */
  bbc_pure pure = p->leftover && !mask ? BBC_PURE_OWN : prm->pure;
  cb->face_count = points ? slab_points(m, in->set, p, job->owner, eps, pure, faces, lo, hi)
                          : slab_faces(m, in->set, p, job->owner, eps, pure, mask, faces, lo, hi);
  if (cb->face_count) {
    /* Never beyond the model's own bounds (+- epsilon; a stem billboard,
     * whose slab may be thicker, within its faces' bounds). */
    double grow = mask ? 0 : eps;
    for (int k = 0; k < 3; k++) {
      lo[k] = fmax(lo[k], m->bbox_min[k]) - grow;
      hi[k] = fmin(hi[k], m->bbox_max[k]) + grow;
    }
    outline(b, lo, hi, cb);
  } else {
    for (int k = 0; k < 3; k++) {
      lo[k] = m->bbox_min[k] - eps;
      hi[k] = m->bbox_max[k] + eps;
    }
    outline(b, lo, hi, cb);
  }
}

/* The w x h images a billboard's bake fills: front, back with back images,
 * their normal maps with normal maps (2.3.1), their occlusion images with
 * `occlusion`. */
static bbc_result bake_images(const bbc_params *prm, int points, int w, int h, baked *out) {
  bbc_result r = bbc_image_alloc(&out->front, w, h);
  if (r == BBC_OK && prm->back_images) r = bbc_image_alloc(&out->back, w, h);
  int want_nm = prm->normal_maps && !points; /* 2.4.4: no normal maps for points */
  if (r == BBC_OK && want_nm) r = bbc_image_alloc(&out->front_nm, w, h);
  if (r == BBC_OK && want_nm && prm->back_images) r = bbc_image_alloc(&out->back_nm, w, h);
  int want_ao = prm->occlusion > 0 && !points;
  if (r == BBC_OK && want_ao) r = bbc_image_alloc(&out->front_ao, w, h);
  if (r == BBC_OK && want_ao && prm->back_images) r = bbc_image_alloc(&out->back_ao, w, h);
  return r;
}

/* The view of billboard cb: along minus its plane's normal, framing its
 * rectangle, its slab the depth range, lit as the parameters say. */
static void bake_view(const bbc__bake_inputs *in, const bake_job *job,
                      const bbc_cloud_billboard *cb, bbc_view *v) {
  const bbc_params *prm = in->params;
  const bbc_plane *p = job->p;
  const bbc_billboard *b = &cb->rect;
  double eps = job->eps;
  memset(v, 0, sizeof *v);
  for (int k = 0; k < 3; k++) {
    v->direction[k] = -p->normal[k];
    v->up[k] = b->w[k];
    v->center[k] = b->origin[k] + 0.5 * b->width * b->u[k] + 0.5 * b->height * b->w[k];
  }
  /* Degenerate (single-point or single-line) rectangles still get texels. */
  v->half_extent = 0.5 * (b->width > 0 ? b->width : eps);
  v->half_extent_y = 0.5 * (b->height > 0 ? b->height : eps);
  v->depth_min = -eps;
  v->depth_max = eps;
  v->lighting = prm->prelight;
  memcpy(v->light, in->light, sizeof v->light);
  v->light_gain = in->light_gain;
  if (job->mask) {
    /* A stem billboard is seen from the side, within 30 degrees of its
     * normal (three around the axis): lit as a viewer's headlight shows the
     * stem from there (bright in the middle, dark at the edges), where the
     * sun at `lightelev` would darken a vertical stem against the crown. */
    v->headlight = 1;
    v->light_gain = 1;
  }
  v->ambient = prm->viewer_ambient;
  v->vertex_shade = in->vshade;
}

/* The rasterizer's target: the images of `out`, w x h (ss samples a texel
 * side), the mipmaps and the faces' alpha shares. */
static void bake_target(const bbc__bake_inputs *in, const bake_job *job, int w, int h, int ss,
                        const baked *out, bbc__bake *bk) {
  memset(bk, 0, sizeof *bk);
  bk->width = w;
  bk->height = h;
  bk->front = out->front.rgba;
  bk->back = out->back.rgba;
  bk->front_nm = out->front_nm.rgba;
  bk->back_nm = out->back_nm.rgba;
  bk->front_ao = out->front_ao.rgba;
  bk->outward = job->mask ? 0 : in->params->nm_bend; /* the stem's: its own normals */
  memcpy(bk->center, in->crown_center, sizeof bk->center);
  bk->flat = job->mask ? 0 : in->params->nm_flat;
  bk->up[in->params->up_axis >= 0 && in->params->up_axis <= 2 ? in->params->up_axis : 1] = 1;
  bk->up_tilt = in->params->nm_up;
  bk->back_ao = out->back_ao.rgba;
  bk->backface = in->params->backface;
  bk->mips = in->mips;
  bk->alpha_bits = in->alpha_bits;
  bk->mip_bias = ss >= 4 ? 2 : ss >= 2 ? 1 : 0;
  bk->colour_taps = !in->mips && in->params->quality == BBC_QUALITY_SQUASHED && ss < 4;
  bk->face_alpha = job->mask ? NULL : job->share; /* a stem billboard draws its faces whole */
}

/* quality 2 (thesis 2.3.9): the supersampled images down to their texels,
 * opaque by their samples' coverage. One mask per side, shared by its
 * colour and normal images; kept until refinement (bbc__refine_alpha) has
 * used it. */
static bbc_result coverage_alpha(const bbc_params *prm, const bbc_cloud_billboard *cb, int ss,
                                 uint8_t *const taps[2], baked *out) {
  bbc_result r = BBC_OK;
  size_t nx = (size_t)cb->tex_width * cb->tex_height;
  bbc_image *col[2] = {&out->front, &out->back}, *nm[2] = {&out->front_nm, &out->back_nm};
  bbc_image *ao[2] = {&out->front_ao, &out->back_ao};
  unsigned grow = (unsigned)(prm->grow_min > 0 ? prm->grow_min : 1);
  if (grow > (unsigned)(ss * ss)) grow = (unsigned)(ss * ss); /* every sample at most */
  for (int i = 0; i < 2 && r == BBC_OK; i++) {
    if (!col[i]->rgba) continue;
    out->mask[i] = malloc(nx);
    out->cand[i] = malloc(nx);
    if (!out->mask[i] || !out->cand[i]) r = BBC_ERROR_OUT_OF_MEMORY;
    if (r == BBC_OK)
      r = bbc__alpha_mask(col[i], taps[i], ss, prm->dither, grow, out->mask[i], out->cand[i]);
    if (r == BBC_OK && nm[i]->rgba) r = bbc__downsample_masked(nm[i], ss, 1, out->mask[i]);
    if (r == BBC_OK && ao[i]->rgba) r = bbc__downsample_masked(ao[i], ss, 0, out->mask[i]);
    if (r == BBC_OK) r = bbc__downsample_masked(col[i], ss, 0, out->mask[i]);
  }
  if (r != BBC_OK) r = bbc__fail(&out->err, r, "step 3: out of memory");
  return r;
}

/* Bakes billboard cb (`job`) into `out` (its result in out->r); faces: room
 * for every face (or point) of the mesh. */
static void bake_one(const bbc__bake_inputs *in, const bake_job *job, bbc_cloud_billboard *cb,
                     uint32_t *faces, baked *out) {
  const bbc_mesh *m = in->mesh;
  const bbc_params *prm = in->params;
  const bbc_billboard *b = &cb->rect;
  int points = m->kind == BBC_MESH_POINTS;
  bake_faces(in, job, cb, faces);
  int ss = bbc__bake_samples(prm);
  int w = cb->tex_width * ss, h = cb->tex_height * ss;
  bbc_result r = bake_images(prm, points, w, h, out);
  if (r != BBC_OK) {
    out->r = bbc__fail(&out->err, r, "step 3: out of memory for a %dx%d texture", w, h);
    return;
  }
  bbc_view v;
  bake_view(in, job, cb, &v);
  bbc__bake bk;
  bake_target(in, job, w, h, ss, out, &bk);
  if (bk.colour_taps && !points) {
    bk.taps[0] = calloc((size_t)w * h, 1);
    bk.taps[1] = bk.back ? calloc((size_t)w * h, 1) : NULL;
    if (!bk.taps[0] || (bk.back && !bk.taps[1])) {
      free(bk.taps[0]);
      free(bk.taps[1]);
      out->r = bbc__fail(&out->err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
      return;
    }
  }
  if (points) {
    /* 2.4: splats `pointsize` pixels wide on a 256-pixel picture of the
     * whole model (its bounding sphere), in this billboard's texels (adapted
     * to the texture: the cover does not change with the resolution), ss
     * samples a texel */
    double texel = cb->tex_width > 0 ? b->width / cb->tex_width : 1;
    double size = prm->point_size * (2 * m->radius / 256.0) / (texel > 0 ? texel : 1) * ss;
    r = bbc__render_splats(m, faces, cb->face_count, &v, &bk, size, prm->point_smooth, &out->err);
  } else {
    r = bbc__render_bake(m, faces, cb->face_count, &v, &bk, &out->err);
  }
  if (r == BBC_OK && prm->quality == BBC_QUALITY_SQUASHED)
    r = coverage_alpha(prm, cb, ss, bk.taps, out);
  free(bk.taps[0]);
  free(bk.taps[1]);
  out->r = r;
}

int bbc__bake_samples(const bbc_params *prm) {
  if (prm->quality == BBC_QUALITY_SUPERSAMPLED) return 4;
  if (prm->quality != BBC_QUALITY_SQUASHED) return 1;
  if (prm->samples >= 1 && prm->samples <= 4) return prm->samples;
  /* auto: a small texture's coverage needs every sample (a far level's few
   * texels a leaf), a large one's bake the time */
  return prm->texres >= 128 ? 2 : 4;
}

void bbc__baked_clear_transparent(baked *b) {
  bbc__clear_masked(&b->front, b->mask[0]);
  bbc__clear_masked(&b->front_nm, b->mask[0]);
  bbc__clear_masked(&b->front_ao, b->mask[0]);
  if (b->mask[1]) {
    bbc__clear_masked(&b->back, b->mask[1]);
    bbc__clear_masked(&b->back_nm, b->mask[1]);
    bbc__clear_masked(&b->back_ao, b->mask[1]);
  }
}

bbc_result bbc__baked_fill_transparent(baked *b) {
  bbc_image *all[6] = {&b->front, &b->back, &b->front_nm, &b->back_nm, &b->front_ao, &b->back_ao};
  bbc_result r = BBC_OK;
  for (int i = 0; i < 6 && r == BBC_OK; i++) r = bbc__fill_transparent(all[i]);
  return r;
}

void bbc__baked_free(baked *b) {
  for (int i = 0; i < 2; i++) {
    free(b->mask[i]);
    free(b->cand[i]);
  }
  bbc_image_free(&b->front);
  bbc_image_free(&b->back);
  bbc_image_free(&b->front_nm);
  bbc_image_free(&b->back_nm);
  bbc_image_free(&b->front_ao);
  bbc_image_free(&b->back_ao);
}

/* The crown's centre (nmbend): the middle of the bounds of the faces not
 * in a part named "trunk" (all faces when every one is). */
static void crown_center(bbc__bake_inputs *in) {
  const bbc_mesh *m = in->mesh;
  const bbc_planeset *set = in->set;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int pass = 0; pass < 2 && !(lo[0] <= hi[0]); pass++)
    for (size_t t = 0; t < m->triangle_count && m->kind == BBC_MESH_TRIANGLES; t++) {
      uint32_t part = set->face_part ? set->face_part[t] : 0;
      if (!pass && part < set->part_count && !strcmp(set->parts[part].name, "trunk")) continue;
      for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) {
          double x = m->positions[3 * (size_t)m->indices[3 * t + c] + k];
          lo[k] = x < lo[k] ? x : lo[k];
          hi[k] = x > hi[k] ? x : hi[k];
        }
    }
  for (int k = 0; k < 3; k++)
    in->crown_center[k] =
        lo[0] <= hi[0] ? 0.5 * (lo[k] + hi[k]) : 0.5 * (m->bbox_min[k] + m->bbox_max[k]);
}

bbc_result bbc__bake_shading(bbc__bake_inputs *in, bbc_error *err) {
  const bbc_mesh *m = in->mesh;
  const bbc_params *prm = in->params;
  bbc_result r = BBC_OK;
  /* `occlusion` takes the voxel shadowing to the occlusion images (the
   * colour stays the albedo), in place of `shade`. */
  int voxels = prm->occlusion > 0 ? prm->occlusion : prm->shade_voxels;
  if (voxels > 0 && m->kind != BBC_MESH_POINTS) {
    in->vshade = malloc((m->vertex_count ? m->vertex_count : 1) * sizeof *in->vshade);
    if (!in->vshade)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
    else
      r = bbc_shade_vertices(m, voxels,
                             prm->occlusion > 0 ? prm->occlusion_min : prm->shade_ambient,
                             prm->up_axis, in->vshade, err);
  }
  crown_center(in);
  return r;
}

bbc_result bbc__bake_lighting(bbc__bake_inputs *in, const size_t *order, size_t kept_planes,
                              bbc_error *err) {
  const bbc_mesh *m = in->mesh;
  const bbc_params *prm = in->params;
  int points = m->kind == BBC_MESH_POINTS;
  bbc_result r = BBC_OK;
  bbc_params_get_light_direction(prm, in->light);
  /* Prelight gives the brightness a lit viewer shows the original with
   * (the sun adds relief, not darkness): shown unlit, the cloud looks as
   * the original does in a viewer. */
  in->light_gain = 1.0;
  if (prm->prelight && !points)
    r = bbc_light_gain_measure(m, in->light, prm->up_axis, &in->light_gain, err);
  /* A baked light: colours as a GPU shows the textures from the
   * billboards' distance (mipmaps). A material: the albedo, the texels
   * themselves (the samples average them), so that no mip level mixes in
   * the colours of other parts of a texture atlas. */
  if (r == BBC_OK && prm->prelight && !m->no_mipmaps && !points)
    r = bbc__mips_build(m, &in->mips, err);
  if (r == BBC_OK && !points) r = bbc__alpha_bits_build(m, &in->alpha_bits, err);
  /* pure 2: each face's coverage split between the slabs it crosses (only
   * dithering sums shares; otherwise it acts as pure 0). */
  if (r == BBC_OK && prm->pure == BBC_PURE_SHARED && prm->quality == BBC_QUALITY_SQUASHED &&
      prm->dither && !points && !(in->share = face_shares(m, in->set, order, kept_planes)))
    r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  return r;
}

void bbc__bake_inputs_free(bbc__bake_inputs *in) {
  free(in->vshade);
  free(in->share);
  bbc__mips_free(in->mips, in->mesh->texture_count);
  bbc__alpha_bits_free(in->alpha_bits, in->mesh->texture_count);
}

/* Billboard k's job: a kept plane's (order[k]) below kept_planes, else the
 * stem's billboard k - kept_planes. */
static bake_job job_of(const bbc__bake_inputs *in, const size_t *order, size_t kept_planes,
                       const bbc__stem *stem, size_t k) {
  bake_job job;
  if (k < kept_planes) {
    const bbc_plane *p = &in->set->planes[order[k]];
    job.p = p;
    job.owner = p->kind == BBC_PLANE_CARDBOARD ? (uint32_t)p->mother : (uint32_t)order[k];
    job.eps = in->set->parts[p->part].epsilon_abs;
    job.mask = NULL;
    job.share = in->share;
  } else {
    size_t i = k - kept_planes;
    job.p = &stem->planes[i];
    job.owner = 0;
    job.eps = stem->slab[i];
    job.mask = stem->face_mask;
    job.share = NULL;
  }
  return job;
}

bbc_result bbc__bake_all(const bbc__bake_inputs *in, const size_t *order, size_t kept_planes,
                         const bbc__stem *stem, const bbc_callbacks *cbk, bbc_cloud *cl, baked *bk,
                         bbc_error *err) {
  const bbc_mesh *m = in->mesh;
  size_t nf = m->kind == BBC_MESH_POINTS ? m->vertex_count : m->triangle_count;
  size_t nk = cl->billboard_count;
  bbc_result r = BBC_OK;
  int nt = bbc__thread_count(in->params->threads);
  size_t done = 0;
  int stop = 0; /* the cancel callback asked: the remaining billboards are skipped */
  const bbc_callbacks *cbp = cbk;
#pragma omp parallel num_threads(nt)
  {
    uint32_t *faces = malloc((nf ? nf : 1) * sizeof *faces);
#pragma omp for schedule(dynamic, 1)
    for (size_t k = 0; k < nk; k++) {
      if (!faces) {
        bk[k].r = bbc__fail(&bk[k].err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
        continue;
      }
      int stopped;
#pragma omp atomic read
      stopped = stop;
      if (stopped) {
        bk[k].r = bbc__fail(&bk[k].err, BBC_ERROR_CANCELLED, "step 3: cancelled");
        continue;
      }
      bake_job job = job_of(in, order, kept_planes, stem, k);
      bake_one(in, &job, &cl->billboards[k], faces, &bk[k]);
#pragma omp critical(bbc_cloud_progress)
      {
        done++;
        if (cbp) bbc__progress(cbp, "baking", (double)done / (double)nk);
        if (bbc__cancelled(cbp)) {
#pragma omp atomic write
          stop = 1;
        }
      }
    }
    free(faces);
  }
  for (size_t k = 0; k < nk && r == BBC_OK; k++)
    if (bk[k].r != BBC_OK) {
      r = bk[k].r;
      if (err) *err = bk[k].err;
    }
  return r;
}
