/* cloud.c — step 3: billboards baked with the software rasterizer (front
 * and back images, normal maps, prelighting, voxel shadowing), packed into
 * one atlas and assembled as a mesh (thesis 2.1.9, 2.2.5, 2.3.1, 2.3.5,
 * 2.3.9, 2.3.11). */
#include "cloud.h"
#include "dual.h"
#include "planes.h"
#include "raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

static int floor_pow2(double x) {
  int p = 1;
  while (p * 2 <= x && p < (1 << 14)) p *= 2;
  return p;
}

/* The images of one billboard before packing. */
typedef struct baked {
  bbc_image front, back, front_nm, back_nm;
  uint8_t *mask[2], *cand[2]; /* quality 2: per texel opaque / has covered samples */
  bbc_error err;
  bbc_result r;
} baked;

/* quality 2: which texels of a k x k supersampled image end opaque (mask[texel] = 1).
 * Growing (thesis 2.3.9, `dither 0`): at least `min_opaque` of its k^2
 * samples are. Dithering (`dither 1`): coverage-preserving error diffusion
 * (Floyd-Steinberg, serpentine rows) of each texel's covered fraction, so
 * that over any small area the fraction of opaque texels is the fraction
 * the original covers, and a texel none of whose samples is covered never
 * turns opaque (its share of the error moves on to covered neighbours). */
static bbc_result alpha_mask(const bbc_image *img, int k, int dither, unsigned min_opaque,
                             uint8_t *mask, uint8_t *cand) {
  int w = img->width / k, h = img->height / k;
  float *err = dither ? calloc(2 * ((size_t)w + 2), sizeof *err) : NULL;
  if (dither && !err) return BBC_ERROR_OUT_OF_MEMORY;
  for (int y = 0; y < h; y++) {
    float *cur = err ? err + (y % 2) * ((size_t)w + 2) + 1 : NULL;
    float *nxt = err ? err + ((y + 1) % 2) * ((size_t)w + 2) + 1 : NULL;
    if (nxt) memset(nxt - 1, 0, ((size_t)w + 2) * sizeof *nxt);
    int dir = y % 2 ? -1 : 1;
    for (int i = 0; i < w; i++) {
      int x = dir > 0 ? i : w - 1 - i;
      unsigned n = 0, shares = 0; /* covered samples, their alphas (pure 2: shares) */
      for (int j = 0; j < k; j++)
        for (int q = 0; q < k; q++) {
          unsigned a = img->rgba[4 * ((size_t)(y * k + j) * img->width + (x * k + q)) + 3];
          n += a > 0;
          shares += a;
        }
      uint8_t on;
      if (!dither) {
        on = n > 0 && n >= min_opaque;
      } else {
        float v = (float)shares / (float)(255 * k * k) + cur[x];
        on = n > 0 && v >= 0.5f;
        /* The error goes to the neighbours inside the image, the weights
         * renormalised, so that none leaves over an edge. */
        float e = v - on;
        int right = x + dir >= 0 && x + dir < w, below = y + 1 < h;
        int left_below = below && x - dir >= 0 && x - dir < w;
        float wr = right ? 7.0f : 0, wlb = left_below ? 3.0f : 0, wb = below ? 5.0f : 0;
        float wrb = right && below ? 1.0f : 0, sum = wr + wlb + wb + wrb;
        if (sum > 0) {
          e /= sum;
          cur[x + dir] += e * wr;
          nxt[x - dir] += e * wlb;
          nxt[x] += e * wb;
          nxt[x + dir] += e * wrb;
        }
      }
      mask[(size_t)y * w + x] = on;
      cand[(size_t)y * w + x] = n > 0;
    }
  }
  free(err);
  return BBC_OK;
}

/* Downsamples a k x k supersampled image to its texels: a texel with
 * covered samples gets their mean (normals renormalised), opaque when
 * `mask` says so, else with alpha 0 (the colour kept for refinement;
 * clear_masked removes it). */
static bbc_result downsample_masked(bbc_image *img, int k, int is_normal, const uint8_t *mask) {
  bbc_image dst;
  bbc_result r = bbc_image_alloc(&dst, img->width / k, img->height / k);
  if (r != BBC_OK) return r;
  for (int y = 0; y < dst.height; y++)
    for (int x = 0; x < dst.width; x++) {
      unsigned sum[3] = {0, 0, 0}, n = 0;
      for (int j = 0; j < k; j++)
        for (int i = 0; i < k; i++) {
          const uint8_t *s = img->rgba + 4 * ((size_t)(y * k + j) * img->width + (x * k + i));
          if (!s[3]) continue;
          for (int c = 0; c < 3; c++) sum[c] += s[c];
          n++;
        }
      uint8_t *d = dst.rgba + 4 * ((size_t)y * dst.width + x);
      if (!n) continue;
      if (is_normal) {
        double v[3], len = 0;
        for (int c = 0; c < 3; c++) {
          v[c] = (double)sum[c] / n / 127.5 - 1.0;
          len += v[c] * v[c];
        }
        len = sqrt(len);
        for (int c = 0; c < 3; c++) {
          double e = len > 1e-9 ? 127.5 * (v[c] / len + 1.0) : (c == 2 ? 255 : 127.5);
          d[c] = (uint8_t)(e > 255 ? 255 : e < 0 ? 0 : e + 0.5 > 255 ? 255 : e + 0.5);
        }
      } else {
        for (int c = 0; c < 3; c++) d[c] = (uint8_t)((sum[c] + n / 2) / n);
      }
      d[3] = mask[(size_t)y * dst.width + x] ? 255 : 0;
    }
  bbc_image_free(img);
  *img = dst;
  return BBC_OK;
}

/* Texels that are not opaque in `mask` become (0, 0, 0, 0); opaque ones
 * alpha 255. */
static void clear_masked(bbc_image *img, const uint8_t *mask) {
  if (!img->rgba) return;
  size_t n = (size_t)img->width * img->height;
  for (size_t i = 0; i < n; i++)
    if (mask[i])
      img->rgba[4 * i + 3] = 255;
    else
      memset(img->rgba + 4 * i, 0, 4);
}

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

static double polygon_area(double p[][2], int n) {
  double a = 0;
  for (int i = 0; i < n; i++) a += p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1];
  return 0.5 * a;
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
                         uint32_t owner, double eps, int pure, const uint8_t *mask, uint32_t *faces,
                         double lo[3], double hi[3]) {
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
      if (pure == 1 && set->face_plane[t] != owner) continue;
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
                          uint32_t owner, double eps, int pure, uint32_t *out, double lo[3],
                          double hi[3]) {
  size_t n = 0;
  for (int k = 0; k < 3; k++) {
    lo[k] = INFINITY;
    hi[k] = -INFINITY;
  }
  for (size_t v = 0; v < m->vertex_count; v++) {
    if (pure == 1 && set->face_plane[v] != owner) continue;
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

/* Bakes billboard cb of plane p: the faces crossing its +-eps slab (pure:
 * those of plane `owner`), or with `mask` the faces it marks (a stem
 * billboard, eps its slab). */
static void bake_one(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                     const bbc__mips *mips, const float *vshade, const double *light,
                     double light_gain, const bbc_plane *p, uint32_t owner, double eps,
                     const uint8_t *mask, const uint8_t *share, bbc_cloud_billboard *cb,
                     uint32_t *faces, baked *out) {
  const bbc_billboard *b = &cb->rect;
  double lo[3], hi[3];
  int points = m->kind == BBC_MESH_POINTS;
  cb->face_count = points ? slab_points(m, set, p, owner, eps, prm->pure, faces, lo, hi)
                          : slab_faces(m, set, p, owner, eps, prm->pure, mask, faces, lo, hi);
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
  int ss = prm->quality >= 2 ? 4 : 1;
  int w = cb->tex_width * ss, h = cb->tex_height * ss;
  bbc_result r = bbc_image_alloc(&out->front, w, h);
  if (r == BBC_OK && prm->back_images) r = bbc_image_alloc(&out->back, w, h);
  int want_nm = prm->normal_maps && !points; /* 2.4.4: no normal maps for points */
  if (r == BBC_OK && want_nm) r = bbc_image_alloc(&out->front_nm, w, h);
  if (r == BBC_OK && want_nm && prm->back_images) r = bbc_image_alloc(&out->back_nm, w, h);
  if (r != BBC_OK) {
    out->r = bbc__fail(&out->err, r, "step 3: out of memory for a %dx%d texture", w, h);
    return;
  }
  bbc_view v;
  memset(&v, 0, sizeof v);
  for (int k = 0; k < 3; k++) {
    v.direction[k] = -p->normal[k];
    v.up[k] = b->w[k];
    v.center[k] = b->origin[k] + 0.5 * b->width * b->u[k] + 0.5 * b->height * b->w[k];
  }
  /* Degenerate (single-point or single-line) rectangles still get texels. */
  v.half_extent = 0.5 * (b->width > 0 ? b->width : eps);
  v.half_extent_y = 0.5 * (b->height > 0 ? b->height : eps);
  v.depth_min = -eps;
  v.depth_max = eps;
  v.lighting = prm->prelight;
  memcpy(v.light, light, sizeof v.light);
  v.light_gain = light_gain;
  if (mask) {
    /* A stem billboard is seen from the side, within 30 degrees of its
     * normal (three around the axis): lit as a viewer's headlight shows the
     * stem from there (bright in the middle, dark at the edges), where the
     * sun at `lightelev` would darken a vertical stem against the crown. */
    v.headlight = 1;
    v.light_gain = 1;
  }
  v.ambient = prm->viewer_ambient;
  v.vertex_shade = vshade;
  bbc__bake bk;
  memset(&bk, 0, sizeof bk);
  bk.width = w;
  bk.height = h;
  bk.front = out->front.rgba;
  bk.back = out->back.rgba;
  bk.front_nm = out->front_nm.rgba;
  bk.back_nm = out->back_nm.rgba;
  bk.backface = prm->backface;
  bk.mips = mips;
  bk.mip_bias = ss == 4 ? 2 : 0;
  bk.face_alpha = mask ? NULL : share; /* a stem billboard draws its faces whole */
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
  if (r == BBC_OK && prm->quality == 2) {
    /* One mask per side, shared by its colour and normal images; kept
     * until refinement (bbc__refine_alpha) has used it. */
    size_t nx = (size_t)cb->tex_width * cb->tex_height;
    bbc_image *col[2] = {&out->front, &out->back}, *nm[2] = {&out->front_nm, &out->back_nm};
    unsigned grow = (unsigned)(prm->grow_min > 0 ? prm->grow_min : 1);
    for (int i = 0; i < 2 && r == BBC_OK; i++) {
      if (!col[i]->rgba) continue;
      out->mask[i] = malloc(nx);
      out->cand[i] = malloc(nx);
      if (!out->mask[i] || !out->cand[i]) r = BBC_ERROR_OUT_OF_MEMORY;
      if (r == BBC_OK) r = alpha_mask(col[i], ss, prm->dither, grow, out->mask[i], out->cand[i]);
      if (r == BBC_OK && nm[i]->rgba) r = downsample_masked(nm[i], ss, 1, out->mask[i]);
      if (r == BBC_OK) r = downsample_masked(col[i], ss, 0, out->mask[i]);
    }
    if (r != BBC_OK) r = bbc__fail(&out->err, r, "step 3: out of memory");
  }
  out->r = r;
}

static void baked_free(baked *b) {
  for (int i = 0; i < 2; i++) {
    free(b->mask[i]);
    free(b->cand[i]);
  }
  bbc_image_free(&b->front);
  bbc_image_free(&b->back);
  bbc_image_free(&b->front_nm);
  bbc_image_free(&b->back_nm);
}

void bbc_cloud_free(bbc_cloud *cloud) {
  if (!cloud) return;
  bbc_mesh_free(&cloud->mesh);
  free(cloud->billboards);
  memset(cloud, 0, sizeof *cloud);
}

/* The part whose faces `limbs` keeps as a mesh: its triangle budget (0 =
 * none) and index. */
static int limbs_part(const bbc_planeset *set, uint32_t *part) {
  for (size_t pi = 0; pi < set->part_count; pi++)
    if (set->parts[pi].limbs > 0) {
      if (part) *part = (uint32_t)pi;
      return set->parts[pi].limbs;
    }
  return 0;
}

/* The limbs' colour: their original faces baked as the stem billboards
 * are (prelit by a headlight from the side, textures at the distance of a
 * 64-texel image), seen from two sides, averaged over what they cover. */
static void limb_colour(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                        const bbc__mips *mips, const float *vshade, uint8_t rgba[4]) {
  enum { SIDE = 64 };
  uint32_t *faces = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *faces);
  uint8_t *img = malloc(4 * SIDE * SIDE);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  size_t n = 0;
  for (size_t t = 0; faces && t < m->triangle_count; t++) {
    if (set->face_plane[t] != BBC_NO_PLANE) continue;
    faces[n++] = (uint32_t)t;
    for (int c = 0; c < 3; c++)
      for (int k = 0; k < 3; k++) {
        double x = m->positions[3 * (size_t)m->indices[3 * t + c] + k];
        lo[k] = fmin(lo[k], x);
        hi[k] = fmax(hi[k], x);
      }
  }
  double sum[3] = {0, 0, 0}, weight = 0;
  int up = prm->up_axis >= 0 && prm->up_axis <= 2 ? prm->up_axis : 1;
  for (int side = 0; n && img && side < 2; side++) {
    int ax = (up + 1 + side) % 3, across = (up + 2 - side) % 3;
    bbc_view v;
    memset(&v, 0, sizeof v);
    v.direction[ax] = -1;
    v.up[up] = 1;
    for (int k = 0; k < 3; k++) v.center[k] = 0.5 * (lo[k] + hi[k]);
    v.half_extent = fmax(0.5 * (hi[across] - lo[across]), 1e-9);
    v.half_extent_y = fmax(0.5 * (hi[up] - lo[up]), 1e-9);
    v.lighting = prm->prelight;
    v.headlight = 1;
    v.light_gain = 1;
    v.ambient = prm->viewer_ambient;
    v.vertex_shade = vshade;
    bbc__bake bk;
    memset(&bk, 0, sizeof bk);
    bk.width = bk.height = SIDE;
    bk.front = img;
    bk.mips = mips;
    memset(img, 0, 4 * SIDE * SIDE);
    bbc_error quiet;
    if (bbc__render_bake(m, faces, n, &v, &bk, &quiet) != BBC_OK) continue;
    for (size_t i = 0; i < (size_t)SIDE * SIDE; i++) {
      double a = img[4 * i + 3] / 255.0;
      for (int c = 0; c < 3; c++) sum[c] += a * img[4 * i + c];
      weight += a;
    }
  }
  for (int c = 0; c < 3; c++) rgba[c] = (uint8_t)(weight > 0 ? sum[c] / weight + 0.5 : 128);
  rgba[3] = 255;
  free(faces);
  free(img);
}

/* The cloud's mesh: each billboard's outline (twice with back images), then
 * the limbs' mesh (`limbs`, may be empty) textured by the swatch. */
static bbc_result build_mesh(const bbc_planeset *set, const bbc_params *prm, bbc_cloud *cl,
                             bbc_image *atlas, bbc_image *nm_atlas, const bbc_mesh *limbs,
                             const bbc_atlas_rect *swatch, uint32_t limbs_group, bbc_error *err) {
  bbc_mesh *me = &cl->mesh;
  int sides = prm->back_images ? 2 : 1;
  size_t nv = limbs->vertex_count, nt = limbs->triangle_count;
  for (size_t k = 0; k < cl->billboard_count; k++) {
    nv += (size_t)sides * cl->billboards[k].corner_count;
    nt += (size_t)sides * (cl->billboards[k].corner_count - 2);
  }
  me->kind = BBC_MESH_TRIANGLES;
  me->vertex_count = nv;
  me->triangle_count = nt;
  me->positions = malloc(3 * nv * sizeof *me->positions);
  me->normals = malloc(3 * nv * sizeof *me->normals);
  me->uvs = malloc(2 * nv * sizeof *me->uvs);
  if (nm_atlas) me->tangents = malloc(4 * nv * sizeof *me->tangents);
  me->indices = malloc(3 * nt * sizeof *me->indices);
  me->face_material = calloc(nt, sizeof *me->face_material);
  me->face_group = malloc(nt * sizeof *me->face_group);
  me->materials = calloc(2, sizeof *me->materials);
  me->textures = calloc(2, sizeof *me->textures);
  me->group_names = calloc(set->part_count, sizeof *me->group_names);
  if (!me->positions || !me->normals || !me->uvs || (nm_atlas && !me->tangents) || !me->indices ||
      !me->face_material || !me->face_group || !me->materials || !me->textures || !me->group_names)
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  me->material_count = 1;
  bbc_material *mat = &me->materials[0];
  mat->name = bbc__strdup("billboards");
  mat->texture = 0;
  mat->single_sided = prm->back_images;
  for (int c = 0; c < 4; c++) mat->base_color[c] = 1.0f;
  me->texture_count = nm_atlas ? 2 : 1;
  me->textures[0].image = *atlas;
  me->textures[0].has_alpha = bbc_image_has_transparency(atlas);
  memset(atlas, 0, sizeof *atlas);
  if (nm_atlas) {
    me->textures[1].image = *nm_atlas;
    memset(nm_atlas, 0, sizeof *nm_atlas);
    mat->normal_map = 2;
  }
  me->group_count = set->part_count;
  for (size_t g = 0; g < set->part_count; g++) {
    me->group_names[g] = bbc__strdup(set->parts[g].name);
    if (!me->group_names[g]) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  if (!mat->name) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  if (limbs->triangle_count) {
    /* The limbs: their own material "limbs" (the same atlas, both sides: a
     * simplified tube may open), so that readers tell them from billboards
     * (forest draws them in one call). */
    bbc_material *lm = &me->materials[1];
    *lm = *mat;
    lm->name = bbc__strdup("limbs");
    lm->single_sided = 0;
    me->material_count = 2;
    if (!lm->name) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  double aw = me->textures[0].image.width, ah = me->textures[0].image.height;
  size_t v = 0, t = 0;
  for (size_t k = 0; k < cl->billboard_count; k++) {
    const bbc_cloud_billboard *cb = &cl->billboards[k];
    const bbc_billboard *b = &cb->rect;
    int nc = cb->corner_count;
    for (int side = 0; side < sides; side++) {
      const bbc_atlas_rect *rc = side ? &cb->back : &cb->front;
      double sign = side ? -1.0 : 1.0;
      size_t base = v;
      for (int c = 0; c < nc; c++, v++) {
        double s = cb->corners[c][0], tt = cb->corners[c][1];
        for (int j = 0; j < 3; j++) {
          me->positions[3 * v + j] =
              b->origin[j] + s * b->width * b->u[j] + tt * b->height * b->w[j];
          me->normals[3 * v + j] = (float)(sign * cb->normal[j]);
          if (me->tangents) me->tangents[4 * v + j] = (float)b->u[j];
        }
        if (me->tangents) me->tangents[4 * v + 3] = (float)sign;
        /* Image rows run top first; v = 0 is the image's bottom row. */
        me->uvs[2 * v] = (float)((rc->x + s * rc->width) / aw);
        me->uvs[2 * v + 1] = (float)(1.0 - (rc->y + (1 - tt) * rc->height) / ah);
      }
      for (int c = 1; c + 1 < nc; c++, t++) {
        uint32_t a = (uint32_t)base, b1 = (uint32_t)(base + c), b2 = (uint32_t)(base + c + 1);
        me->indices[3 * t] = a;
        me->indices[3 * t + 1] = side ? b2 : b1;
        me->indices[3 * t + 2] = side ? b1 : b2;
        me->face_group[t] = cb->part;
      }
    }
  }
  /* The limbs: every vertex at the swatch's centre texel. */
  float su = swatch ? (float)((swatch->x + 0.5 * swatch->width) / aw) : 0;
  float sv = swatch ? (float)(1.0 - (swatch->y + 0.5 * swatch->height) / ah) : 0;
  size_t v0 = v;
  for (size_t i = 0; i < limbs->vertex_count; i++, v++) {
    const float *n = limbs->normals + 3 * i;
    for (int j = 0; j < 3; j++) {
      me->positions[3 * v + j] = limbs->positions[3 * i + j];
      me->normals[3 * v + j] = n[j];
    }
    me->uvs[2 * v] = su;
    me->uvs[2 * v + 1] = sv;
    if (me->tangents) { /* any unit tangent across the normal (the swatch is flat) */
      int a = fabsf(n[0]) < 0.6f ? 0 : fabsf(n[1]) < 0.6f ? 1 : 2;
      float e[3] = {0, 0, 0}, tg[3];
      e[a] = 1;
      float d = n[0] * e[0] + n[1] * e[1] + n[2] * e[2];
      for (int j = 0; j < 3; j++) tg[j] = e[j] - d * n[j];
      float l = sqrtf(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
      for (int j = 0; j < 3; j++) me->tangents[4 * v + j] = l > 0 ? tg[j] / l : (float)e[j];
      me->tangents[4 * v + 3] = 1;
    }
  }
  for (size_t i = 0; i < limbs->triangle_count; i++, t++) {
    for (int c = 0; c < 3; c++) me->indices[3 * t + c] = (uint32_t)(v0 + limbs->indices[3 * i + c]);
    me->face_group[t] = limbs_group;
    me->face_material[t] = 1;
  }
  cl->limb_triangles = limbs->triangle_count;
  if (swatch && limbs->triangle_count) cl->limb_swatch = *swatch;
  return BBC_OK;
}

/* Texels of all images of billboards rects[n] at texture resolution texres
 * (the sizing rule of bbc_cloud_build). */
/* A billboard's texture at `texel` model units a texel: powers of two, at
 * least 4 (build_inner's sizes, which the atlas budget predicts). */
static void tex_size(const bbc_billboard *r, double texel, int *w, int *h) {
  *w = floor_pow2(texel > 0 ? r->width / texel : 1);
  *h = floor_pow2(texel > 0 ? r->height / texel : 1);
  if (*w < 4) *w = 4;
  if (*h < 4) *h = 4;
}

/* Model units a texel at `texres` for billboards `rects`: the longest side
 * gets texres texels. */
static double texel_of(const bbc_billboard *rects, size_t n, int texres) {
  double longest = 0;
  for (size_t i = 0; i < n; i++) longest = fmax(longest, fmax(rects[i].width, rects[i].height));
  return longest / texres;
}

size_t bbc__cloud_texels(const bbc_billboard *rects, size_t n, int texres, int sides) {
  double texel = texel_of(rects, n, texres);
  size_t total = 0;
  for (size_t i = 0; i < n; i++) {
    int w, h;
    tex_size(&rects[i], texel, &w, &h);
    total += (size_t)w * (size_t)h;
  }
  return total * (size_t)sides;
}

bbc_result bbc_cloud_build(const bbc_mesh *m, const bbc_planeset *set, const bbc_params *prm,
                           const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  return bbc__cloud_build_rects(m, set, NULL, prm, cbk, cl, err);
}

/* Whether plane i gets a billboard (2.3.5, 2.3.7). */
static int plane_kept(const bbc_mesh *m, const bbc_planeset *set, size_t i, const bbc_params *prm) {
  const bbc_plane *p = &set->planes[i];
  if (p->kind == BBC_PLANE_CARDBOARD) return p->coverage_pct >= prm->cb_coverage_pct;
  /* 2.4.4: a point cloud's planes with fewer than pointskip points go */
  if (m->kind == BBC_MESH_POINTS) return p->face_count >= (size_t)prm->point_skip;
  double largest = 0;
  for (size_t j = 0; j < set->plane_count; j++)
    if (set->planes[j].part == p->part && set->planes[j].kind != BBC_PLANE_CARDBOARD &&
        set->planes[j].area > largest)
      largest = set->planes[j].area;
  return p->area >= prm->poly_skip_pct / 100.0 * largest;
}

static bbc_result build_inner(const bbc_mesh *m, const bbc_planeset *set,
                              const bbc_billboard *given, const bbc__stem *stem,
                              const bbc_params *prm, const bbc_callbacks *cbk, bbc_cloud *cl,
                              bbc_error *err, int atlas_limit);

/* Whether the images of billboards `rects` at `texres` (sized as build_inner
 * sizes them: quality 3 keeps its samples, `scale` 4) pack into one
 * limit x limit atlas; blank images stand in for them. */
static int atlas_fits(const bbc_billboard *rects, size_t n, int texres, int sides, int scale,
                      int limit) {
  double texel = texel_of(rects, n, texres);
  size_t count = (size_t)sides * n, biggest = 0;
  bbc_image *imgs = calloc(count ? count : 1, sizeof *imgs);
  bbc_atlas_rect *where = calloc(count ? count : 1, sizeof *where);
  int ok = imgs && where;
  for (size_t i = 0; ok && i < n; i++) {
    int w, h;
    tex_size(&rects[i], texel, &w, &h);
    w *= scale;
    h *= scale;
    for (int s = 0; s < sides; s++) {
      imgs[s * n + i].width = w;
      imgs[s * n + i].height = h;
    }
    if ((size_t)w * h > biggest) biggest = (size_t)w * h;
  }
  uint8_t *blank = ok ? calloc(biggest ? biggest * 4 : 4, 1) : NULL;
  ok = ok && blank;
  for (size_t i = 0; ok && i < count; i++) imgs[i].rgba = blank;
  bbc_image atlas = {0, 0, NULL};
  bbc_error quiet;
  ok = ok && bbc_atlas_pack(imgs, count, 2, limit, &atlas, where, &quiet) == BBC_OK;
  bbc_image_free(&atlas);
  free(blank);
  free(where);
  free(imgs);
  return ok;
}

static bbc_result cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                    const bbc_billboard *given, const bbc_params *prm,
                                    const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err);

bbc_result bbc__cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                  const bbc_billboard *given, const bbc_params *prm,
                                  const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  int saved = bbc__threads_use(prm->threads);
  bbc_result r = cloud_build_rects(m, set, given, prm, cbk, cl, err);
  bbc__threads_restore(saved);
  return r;
}

static bbc_result cloud_build_rects(const bbc_mesh *m, const bbc_planeset *set,
                                    const bbc_billboard *given, const bbc_params *prm,
                                    const bbc_callbacks *cbk, bbc_cloud *cl, bbc_error *err) {
  memset(cl, 0, sizeof *cl);
  bbc_params pts;
  if (m->kind == BBC_MESH_POINTS) { /* 2.4.4: no normal maps, no stem for points */
    pts = *prm;
    pts.normal_maps = 0;
    pts.stem = 0;
    prm = &pts;
  }
  bbc__stem stem;
  bbc_result r = BBC_OK;
  /* with limbs the trunk part is a mesh: no stem billboards */
  if (m->kind == BBC_MESH_TRIANGLES && !limbs_part(set, NULL))
    r = bbc__stem_find(m, set, prm->stem, prm->up_axis, &stem, err);
  else
    memset(&stem, 0, sizeof stem);
  if (r != BBC_OK) return r;
  if (prm->atlas_max <= 0) {
    r = build_inner(m, set, given, &stem, prm, cbk, cl, err, 16384);
    bbc__stem_free(&stem);
    return r;
  }
  /* atlasmax: the largest texres whose images the packer fits in one
   * limit x limit atlas (tried on blank images of their sizes before any
   * baking), then halved while the baked ones do not fit (they do). */
  int limit = floor_pow2(prm->atlas_max < 64 ? 64 : prm->atlas_max); /* below 64: 64 */
  size_t np = set->plane_count, nk = 0;
  bbc_billboard *bb = calloc(np ? np : 1, sizeof *bb);
  bbc_billboard *kept = calloc(np + stem.count + 1, sizeof *kept);
  if (!bb || !kept) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK && given)
    memcpy(bb, given, np * sizeof *bb);
  else if (r == BBC_OK)
    r = bbc_billboards_compute(m, set, bb, err);
  for (size_t i = 0; r == BBC_OK && i < np; i++)
    if (plane_kept(m, set, i, prm)) kept[nk++] = bb[i];
  for (size_t i = 0; r == BBC_OK && i < stem.count; i++) kept[nk++] = stem.rects[i];
  int texres = 4, sides = prm->back_images ? 2 : 1, scale = prm->quality == 3 ? 4 : 1;
  size_t per = (size_t)sides * (size_t)(scale * scale);
  for (int t = 8192; r == BBC_OK && nk && t > 4; t /= 2)
    if ((double)bbc__cloud_texels(kept, nk, t, 1) * (double)per <= (double)limit * limit &&
        atlas_fits(kept, nk, t, sides, scale, limit)) {
      texres = t;
      break;
    }
  bbc_params p2 = *prm;
  while (r == BBC_OK) {
    p2.texres = texres;
    r = build_inner(m, set, bb, &stem, &p2, cbk, cl, err, limit); /* billboards computed once */
    if (r != BBC_ERROR_OUT_OF_RANGE || texres <= 4) break;
    r = BBC_OK; /* did not fit: half the resolution */
    texres /= 2;
  }
  free(bb);
  free(kept);
  bbc__stem_free(&stem);
  return r;
}

static bbc_result build_inner(const bbc_mesh *m, const bbc_planeset *set,
                              const bbc_billboard *given, const bbc__stem *stem,
                              const bbc_params *prm, const bbc_callbacks *cbk, bbc_cloud *cl,
                              bbc_error *err, int atlas_limit) {
  memset(cl, 0, sizeof *cl);
  int points = m->kind == BBC_MESH_POINTS;
  size_t nf = points ? m->vertex_count : m->triangle_count;
  if (set->face_count != nf)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "step 3: the planes were found for another model (%zu %s, it has %zu)",
                     set->face_count, points ? "points" : "faces", nf);
  double t0 = bbc__now_s();
  size_t np = set->plane_count;
  bbc_billboard *bb = calloc(np ? np : 1, sizeof *bb);
  size_t *order = malloc((np ? np : 1) * sizeof *order);
  float *vshade = NULL;
  bbc__mips *mips = NULL;
  uint8_t *share = NULL; /* pure 2: per triangle, its alpha share */
  bbc_mesh limbs;        /* `limbs`: the trunk part as a mesh, and its colour's swatch */
  memset(&limbs, 0, sizeof limbs);
  bbc_image swatch[2] = {{0, 0, NULL}, {0, 0, NULL}};
  uint32_t limbs_group = 0;
  int limbs_target = points ? 0 : limbs_part(set, &limbs_group);
  bbc_result r = BBC_OK;
  if (!bb || !order) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  if (r == BBC_OK && given)
    memcpy(bb, given, np * sizeof *bb);
  else if (r == BBC_OK)
    r = bbc_billboards_compute(m, set, bb, err);
  if (r == BBC_OK && prm->shade_voxels > 0 && !points) {
    vshade = malloc((m->vertex_count ? m->vertex_count : 1) * sizeof *vshade);
    if (!vshade)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
    else
      r = bbc_shade_vertices(m, prm->shade_voxels, prm->shade_ambient, prm->up_axis, vshade, err);
  }
  /* Which planes get a billboard (2.3.5, 2.3.7). */
  size_t nk = 0;
  double longest = 0;
  for (size_t i = 0; r == BBC_OK && i < np; i++)
    if (plane_kept(m, set, i, prm)) {
      order[nk++] = i;
      longest = fmax(longest, fmax(bb[i].width, bb[i].height));
    }
  if (r == BBC_OK && nk == 0)
    r = bbc__fail(err, BBC_ERROR_EMPTY, "step 3: every plane was skipped");
  /* Billboards 0..np_kept-1: the kept planes'; then the stem's. */
  size_t np_kept = nk;
  for (size_t i = 0; r == BBC_OK && i < stem->count; i++) {
    longest = fmax(longest, fmax(stem->rects[i].width, stem->rects[i].height));
    nk++;
  }
  baked *bk = NULL;
  if (r == BBC_OK) {
    cl->billboards = calloc(nk, sizeof *cl->billboards);
    bk = calloc(nk, sizeof *bk);
    if (!cl->billboards || !bk)
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  }
  if (r == BBC_OK) {
    cl->billboard_count = nk;
    cl->epsilon_abs = set->epsilon_abs;
    cl->texres = prm->texres;
    double texel = longest / prm->texres;
    for (size_t k = 0; k < nk; k++) {
      bbc_cloud_billboard *cb = &cl->billboards[k];
      const bbc_plane *p = k < np_kept ? &set->planes[order[k]] : &stem->planes[k - np_kept];
      cb->rect = k < np_kept ? bb[order[k]] : stem->rects[k - np_kept];
      cb->kind = p->kind;
      cb->part = p->part;
      memcpy(cb->normal, p->normal, sizeof cb->normal);
      cb->d = p->d;
      tex_size(&cb->rect, texel, &cb->tex_width, &cb->tex_height);
    }
    double light[3];
    bbc_params_light_direction(prm, light);
    /* Prelight gives the brightness a lit viewer shows the original with
     * (the sun adds relief, not darkness): shown unlit, the cloud looks as
     * the original does in a viewer. */
    double light_gain = 1.0;
    if (prm->prelight && !points) r = bbc_light_gain(m, light, prm->up_axis, &light_gain, err);
    /* Colours as a GPU shows the textures from the billboards' distance. */
    if (r == BBC_OK && !m->no_mipmaps && !points) r = bbc__mips_build(m, &mips, err);
    /* pure 2: each face's coverage split between the slabs it crosses (only
     * dithering sums shares; otherwise it acts as pure 0). */
    if (r == BBC_OK && prm->pure == 2 && prm->quality == 2 && prm->dither && !points &&
        !(share = face_shares(m, set, order, np_kept)))
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
    int nt = prm->threads;
#ifdef _OPENMP
    if (nt <= 0) nt = omp_get_max_threads();
#else
    nt = 1;
#endif
    size_t done = 0;
    int stop = 0; /* the cancel callback asked: the remaining billboards are skipped */
    const bbc_callbacks *cbp = cbk;
#pragma omp parallel num_threads(nt)
    if (r == BBC_OK) {
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
        if (k < np_kept) {
          const bbc_plane *p = &set->planes[order[k]];
          uint32_t owner =
              p->kind == BBC_PLANE_CARDBOARD ? (uint32_t)p->mother : (uint32_t)order[k];
          bake_one(m, set, prm, mips, vshade, light, light_gain, p, owner,
                   set->parts[p->part].epsilon_abs, NULL, share, &cl->billboards[k], faces, &bk[k]);
        } else {
          size_t i = k - np_kept;
          bake_one(m, set, prm, mips, vshade, light, light_gain, &stem->planes[i], 0, stem->slab[i],
                   stem->face_mask, NULL, &cl->billboards[k], faces, &bk[k]);
        }
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
  }
  /* The limbs' mesh and the swatch of their colour (its normal flat). */
  if (r == BBC_OK && limbs_target > 0) {
    /* At most `limbs` triangles, and at most 4 times the billboards' (at
     * least 16): a coarse level of a chain keeps its weight. */
    size_t bt = 0;
    for (size_t k = 0; k < nk; k++)
      bt += (size_t)(prm->back_images ? 2 : 1) * (size_t)(cl->billboards[k].corner_count - 2);
    if ((size_t)limbs_target > 4 * bt) limbs_target = (int)(4 * bt < 16 ? 16 : 4 * bt);
    r = bbc__limbs_build(m, set, limbs_target, &limbs, err);
    if (r == BBC_OK && limbs.triangle_count) {
      uint8_t rgba[4];
      limb_colour(m, set, prm, mips, vshade, rgba);
      for (int i = 0; r == BBC_OK && i < (prm->normal_maps ? 2 : 1); i++)
        r = bbc_image_alloc(&swatch[i], 4, 4);
      if (r != BBC_OK) r = bbc__fail(err, r, "step 3: out of memory");
      static const uint8_t flat[4] = {128, 128, 255, 255};
      for (int i = 0; r == BBC_OK && i < 2; i++)
        for (size_t x = 0; swatch[i].rgba && x < 16; x++)
          memcpy(swatch[i].rgba + 4 * x, i ? flat : rgba, 4);
    }
  }
  /* quality 2: alpha refined against renders of the original, then the
   * colour of texels left transparent cleared. */
  if (r == BBC_OK && prm->quality == 2) {
    bbc__refine_image *ri = calloc(nk, sizeof *ri);
    if (!ri) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
    for (size_t k = 0; r == BBC_OK && k < nk; k++) {
      for (int i = 0; i < 2; i++) {
        ri[k].alpha[i] = bk[k].mask[i];
        ri[k].cand[i] = bk[k].cand[i];
      }
      ri[k].width = cl->billboards[k].tex_width;
      ri[k].height = cl->billboards[k].tex_height;
    }
    if (r == BBC_OK && prm->refine > 0 && !points) { /* renders of triangles */
      if (cbk) bbc__progress(cbk, "refining", 0.0);
      bbc__refine_options ro = {prm->refine, 256, 3, prm->up_axis, prm->threads, NULL};
      ro.solid = limbs.triangle_count ? &limbs : NULL;
      r = bbc__refine_alpha(m, cl->billboards, ri, nk, &ro, err);
      if (cbk) bbc__progress(cbk, "refining", 1.0);
    }
    for (size_t k = 0; r == BBC_OK && k < nk; k++) {
      clear_masked(&bk[k].front, bk[k].mask[0]);
      clear_masked(&bk[k].front_nm, bk[k].mask[0]);
      if (bk[k].mask[1]) {
        clear_masked(&bk[k].back, bk[k].mask[1]);
        clear_masked(&bk[k].back_nm, bk[k].mask[1]);
      }
    }
    free(ri);
  }
  double t1 = bbc__now_s();
  cl->bake_s = t1 - t0;
  /* The atlas: front images then back images; the normal atlas packs
   * images of the same sizes in the same order, so it has the same layout. */
  int sides = prm->back_images ? 2 : 1;
  size_t ni = (size_t)sides * nk + (swatch[0].rgba ? 1 : 0); /* the swatch last */
  bbc_image *imgs = NULL, atlas = {0, 0, NULL}, nm_atlas = {0, 0, NULL};
  bbc_atlas_rect *rects = NULL;
  if (r == BBC_OK) {
    imgs = calloc(ni, sizeof *imgs);
    rects = calloc(ni, sizeof *rects);
    if (!imgs || !rects) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
  }
  if (r == BBC_OK) {
    for (size_t k = 0; k < nk; k++) {
      imgs[k] = bk[k].front;
      if (sides == 2) imgs[nk + k] = bk[k].back;
    }
    if (swatch[0].rgba) imgs[ni - 1] = swatch[0];
    r = bbc_atlas_pack(imgs, ni, 2, atlas_limit, &atlas, rects, err);
  }
  if (r == BBC_OK) {
    for (size_t k = 0; k < nk; k++) {
      cl->billboards[k].front = rects[k];
      if (sides == 2) cl->billboards[k].back = rects[nk + k];
      cl->texels += (size_t)sides * bk[k].front.width * bk[k].front.height;
    }
    if (swatch[0].rgba) cl->texels += (size_t)swatch[0].width * swatch[0].height;
    cl->atlas_fill = (double)cl->texels / ((double)atlas.width * atlas.height);
  }
  if (r == BBC_OK && prm->normal_maps) {
    for (size_t k = 0; k < nk; k++) {
      imgs[k] = bk[k].front_nm;
      if (sides == 2) imgs[nk + k] = bk[k].back_nm;
    }
    if (swatch[0].rgba) imgs[ni - 1] = swatch[1];
    bbc_atlas_rect *r2 = calloc(ni, sizeof *r2);
    if (!r2) r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 3: out of memory");
    if (r == BBC_OK) r = bbc_atlas_pack(imgs, ni, 2, atlas_limit, &nm_atlas, r2, err);
    if (r == BBC_OK && (nm_atlas.width != atlas.width || nm_atlas.height != atlas.height ||
                        memcmp(r2, rects, ni * sizeof *r2)))
      r = bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "step 3: the normal atlas's layout differs");
    free(r2);
  }
  if (r == BBC_OK)
    r = build_mesh(set, prm, cl, &atlas, prm->normal_maps ? &nm_atlas : NULL, &limbs,
                   swatch[0].rgba ? &rects[ni - 1] : NULL, limbs_group, err);
  if (r == BBC_OK) r = bbc_mesh_finalize(&cl->mesh, 0, "billboard cloud", err);
  cl->atlas_s = bbc__now_s() - t1;
  for (size_t k = 0; bk && k < nk; k++) baked_free(&bk[k]);
  bbc_image_free(&atlas);
  bbc_image_free(&nm_atlas);
  free(bk);
  free(imgs);
  free(rects);
  free(bb);
  free(order);
  free(vshade);
  free(share);
  bbc_mesh_free(&limbs);
  bbc_image_free(&swatch[0]);
  bbc_image_free(&swatch[1]);
  bbc__mips_free(mips, m->texture_count);
  if (r != BBC_OK) bbc_cloud_free(cl);
  return r;
}
