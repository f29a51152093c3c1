/* raster.c — a small software rasterizer: orthographic, depth-buffered,
 * textured with an alpha test. Used for previews, step 3's texture baking
 * (thesis 2.1.9) and alpha refinement, and the fidelity metrics (src/eval),
 * all by the same rules.
 *
 * Conventions: pixel (x, y) has its centre at (x + 0.5, y + 0.5) in screen
 * units, y down. A pixel is covered when its centre lies inside the
 * triangle; on an edge shared by two triangles the top-left rule gives it to
 * exactly one of them. */
#include "raster.h"
#include "vec3.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef bbc__camera camera;

int bbc__camera_setup(bbc__camera *cam, const bbc_view *v, int w, int h) {
  memcpy(cam->f, v->direction, sizeof cam->f);
  vstore(cam->f, vnormalize(vload(cam->f)));
  vstore(cam->r, vcross(vload(cam->f), vload(v->up)));
  double l = vlen(vload(cam->r));
  if (!(l > 1e-9)) return 0;
  vstore(cam->r, vnormalize(vload(cam->r)));
  vstore(cam->u, vcross(vload(cam->r), vload(cam->f)));
  memcpy(cam->c, v->center, sizeof cam->c);
  int side = w < h ? w : h;
  cam->scale = 0.5 * side / v->half_extent;
  cam->scale_y = cam->scale;
  if (v->half_extent_y > 0) { /* independent scales: the rectangle fills the image */
    cam->scale = 0.5 * w / v->half_extent;
    cam->scale_y = 0.5 * h / v->half_extent_y;
  }
  cam->w2 = 0.5 * w;
  cam->h2 = 0.5 * h;
  return 1;
}

/* Top-left rule for edge a->b of a triangle with positive orientation in
 * y-down screen space (clockwise on screen): top edges are horizontal with
 * b to the right... expressed through the edge vector. */
static int is_top_left(double ax, double ay, double bx, double by) {
  double ex = bx - ax, ey = by - ay;
  return (ey == 0 && ex > 0) || ey < 0;
}

/* The texel (x, y) that texture coordinate (u, v) samples (wrapped,
 * nearest). */
static inline void texel_at(const bbc_image *img, float u, float v, int *tx, int *ty) {
  double fu = u - floor(u), fv = v - floor(v);
  int x = (int)(fu * img->width);
  int y = (int)((1.0 - fv) * img->height);
  if (x >= img->width) x = img->width - 1;
  if (y >= img->height) y = img->height - 1;
  if (x < 0) x = 0;
  if (y < 0) y = 0;
  *tx = x;
  *ty = y;
}

static const uint8_t *sample(const bbc_image *img, float u, float v) {
  int x, y;
  texel_at(img, u, v, &x, &y);
  return img->rgba + 4 * ((size_t)y * img->width + x);
}

/* The alpha test of a material of opacity 1 at (u, v), from its texture's
 * bits: what base_color[3] x alpha / 255 >= 0.5 answers from the texel. */
static inline int alpha_bit(const bbc_image *img, const bbc__alpha_bits *ab, float u, float v) {
  int x, y;
  texel_at(img, u, v, &x, &y);
  return (int)((ab->bits[(size_t)(y >> 3) * ab->tiles_x + (x >> 3)] >> (((y & 7) << 3) | (x & 7))) &
               1);
}

/* k / 255.0 for every byte k, folded by the compiler (correctly rounded,
 * as the division at run time): a lookup instead of a division per
 * fragment, the same doubles. */
#define UNIT1(k)  ((k) / 255.0)
#define UNIT4(k)  UNIT1(k), UNIT1(k + 1), UNIT1(k + 2), UNIT1(k + 3)
#define UNIT16(k) UNIT4(k), UNIT4(k + 4), UNIT4(k + 8), UNIT4(k + 12)
#define UNIT64(k) UNIT16(k), UNIT16(k + 16), UNIT16(k + 32), UNIT16(k + 48)
static const double k_unit[256] = {UNIT64(0), UNIT64(64), UNIT64(128), UNIT64(192)};

static uint8_t to_byte(double v) {
  if (!(v > 0)) return 0;
  if (v >= 1) return 255;
  return (uint8_t)(v * 255.0 + 0.5);
}

/* Everything a triangle needs besides its index. */
typedef struct target {
  const camera *cam;
  const bbc_view *view;
  double light[3];
  int width, height;
  uint8_t *rgba; /* front (or the only) image */
  float *depth;  /* nearest depth so far (smaller = nearer the camera) */
  /* Baking only: */
  const bbc__bake *bake;
  float *depth_back; /* farthest depth so far (nearest from behind) */
  /* bbc_light_gain_measure only: the luminance each visible pixel would have lit by
   * the directional light `sun` instead (same pass, same visibility). */
  float *sun_lum;
  double sun[3];
  /* bbc__render_coverage only: 1 where a fragment passes (no colour, no
   * depth: what bbc_render_ortho's alpha would show). */
  uint8_t *cover;
  /* Optional: every vertex already projected (x, y, depth), for renders
   * of the whole mesh (each vertex serves about six triangles). */
  const double *proj;
  /* bbc__render_coverage, optional: per texture, its alpha test as bits */
  const bbc__alpha_bits *cover_bits;
} target;

/* A vector in an image's frame: x right, y up, z towards the image's
 * viewer (toward = 1 for the front image, -1 for the back). */
static inline vec3 in_image(const double *w, const camera *cam, double toward) {
  return v3(vdot(vload(w), vload(cam->r)), vdot(vload(w), vload(cam->u)),
            -toward * vdot(vload(w), vload(cam->f)));
}

/* Whether face `face` (unit, model space) turns away from the viewer of
 * the image `toward` (1 front, -1 back) tilted `up_tilt` towards up: the
 * side a viewer above the horizon sees of a face seen edge-on. */
static int face_away(const double *face, const target *tg, double toward) {
  const bbc__bake *bk = tg->bake;
  vec3 look = vadd(v3(0, 0, 1), vscale(in_image(bk->up, tg->cam, toward), bk->up_tilt));
  return vdot(in_image(face, tg->cam, toward), look) < 0;
}

/* Writes normal n (model space, unit) of a pixel of face `face` into a
 * normal map. Two-sided surfaces show a client the side whose face turns
 * to its viewer (gl_FrontFacing), with the normal on that side: so n is
 * turned to the face's side (a normal against its own face, the two
 * sides of a sheet, counts as the face's), then to the side of the face
 * this image shows (`away`: face_away); with `out` (in the image's frame)
 * it is then bent by it. */
static void put_normal(uint8_t *o, const double *n, const double *face, int away, const target *tg,
                       double toward, const double *out) {
  vec3 ni = in_image(n, tg->cam, toward);
  int against = vdot(vload(n), vload(face)) < 0;
  double x = ni.x, y = ni.y, z = ni.z, flat = tg->bake->flat;
  if (against != away) {
    x = -x;
    y = -y;
    z = -z;
  }
  if (out || flat > 0) {
    if (out) {
      x += out[0];
      y += out[1];
      z += out[2];
    }
    z += flat;
    double l = sqrt(x * x + y * y + z * z);
    if (l > 1e-12) {
      x /= l;
      y /= l;
      z /= l;
    } else {
      x = y = 0;
      z = 1;
    }
  }
  o[0] = to_byte(0.5 * x + 0.5);
  o[1] = to_byte(0.5 * y + 0.5);
  o[2] = to_byte(0.5 * z + 0.5);
  o[3] = 255;
}

/* Screen bounds of the part of triangle abc (x, y, depth) whose depth lies
 * in [lo, hi] (depth is linear on the triangle, so that part is the
 * triangle clipped by two planes). Returns 0 when the part is empty. The
 * per-pixel slab test stays exact; this only skips pixels that cannot pass,
 * which matters for large faces crossing a thin slab. */
static int slab_bounds(const double *a, const double *b, const double *c, double lo, double hi,
                       double *minx, double *maxx, double *miny, double *maxy) {
  double p[8][3], q[8][3];
  memcpy(p[0], a, sizeof p[0]);
  memcpy(p[1], b, sizeof p[1]);
  memcpy(p[2], c, sizeof p[2]);
  int n = 3;
  for (int side = 0; side < 2; side++) {
    int m = 0;
    for (int i = 0; i < n; i++) {
      const double *P = p[i], *Q = p[(i + 1) % n];
      double fp = side ? P[2] - hi : lo - P[2], fq = side ? Q[2] - hi : lo - Q[2];
      if (fp <= 0) memcpy(q[m++], P, sizeof q[0]);
      if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) {
        double t = fp / (fp - fq);
        for (int k = 0; k < 3; k++) q[m][k] = P[k] + t * (Q[k] - P[k]);
        m++;
      }
    }
    n = m;
    memcpy(p, q, (size_t)n * sizeof p[0]);
    if (n == 0) return 0;
  }
  /* A pixel whose centre passes the exact test lies within the clipped
   * polygon; pad by a texel for the rounding of the interpolated depth. */
  *minx = *maxx = p[0][0];
  *miny = *maxy = p[0][1];
  for (int i = 1; i < n; i++) {
    *minx = fmin(*minx, p[i][0]);
    *maxx = fmax(*maxx, p[i][0]);
    *miny = fmin(*miny, p[i][1]);
    *maxy = fmax(*maxy, p[i][1]);
  }
  *minx -= 1;
  *miny -= 1;
  *maxx += 1;
  *maxy += 1;
  return 1;
}

/* The renderer's directional shading: two-sided Lambert with 0.35 ambient. */
static double sun_shade(const double *n, const double *l) {
  return 0.35 + 0.65 * fabs(n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
}

static inline double min2(double a, double b) {
  return a < b ? a : b;
}
static inline double max2(double a, double b) {
  return a > b ? a : b;
}
static inline double min3(double a, double b, double c) {
  return min2(a, min2(b, c));
}
static inline double max3(double a, double b, double c) {
  return max2(a, max2(b, c));
}

/* floor(0.5 log2(r) + 0.5) for r > 0, as libm's log2 gives it, from r's
 * binary exponent: r = m 2^e (m in [0.5, 1)) has log2(r) in [e - 1, e),
 * which decides the level unless r lies just below a power of 2 with an odd
 * exponent, where log2 may round up to it: libm there. */
static int mip_level_of(double r) {
  int e;
  double m = frexp(r, &e);
  if (!isfinite(r) || (e % 2 != 0 && m >= 0.999999)) return (int)floor(0.5 * log2(r) + 0.5);
  return e % 2 == 0 ? e / 2 : (e - 1) / 2;
}

/* The pixels whose centres (x + 0.5) can lie within [minx, maxx] x [miny,
 * maxy], clipped to a w x h image; 0 when there are none. The margin, far
 * above the rounding of the edge functions at these sizes, keeps every
 * pixel the exact test would take. Bounds are finite (a face's area is).
 * Most faces of a detailed model cover no pixel centre at all. */
#define PIXEL_MARGIN 1e-6

static int pixel_bounds(double minx, double maxx, double miny, double maxy, int w, int h, int *x0,
                        int *x1, int *y0, int *y1) {
  const double margin = PIXEL_MARGIN;
  double bx0 = ceil(minx - 0.5 - margin), bx1 = floor(maxx - 0.5 + margin);
  double by0 = ceil(miny - 0.5 - margin), by1 = floor(maxy - 0.5 + margin);
  if (!(bx0 <= bx1 && by0 <= by1) || bx1 < 0 || by1 < 0 || bx0 > w - 1 || by0 > h - 1) return 0;
  *x0 = bx0 < 0 ? 0 : (int)bx0;
  *x1 = bx1 > w - 1 ? w - 1 : (int)bx1;
  *y0 = by0 < 0 ? 0 : (int)by0;
  *y1 = by1 > h - 1 ? h - 1 : (int)by1;
  assert(0 <= *x0 && *x0 <= *x1 && *x1 < w && 0 <= *y0 && *y0 <= *y1 && *y1 < h);
  return 1;
}

/* 1 when every pixel of [x0, x1] x [y0, y1] is covered. */
static int all_covered(const uint8_t *cover, int w, int x0, int x1, int y0, int y1) {
  for (int y = y0; y <= y1; y++)
    for (int x = x0; x <= x1; x++)
      if (!cover[(size_t)y * w + x]) return 0;
  return 1;
}

/* draw_triangle's set-up stages, always inlined into it: no call per
 * triangle, and each of its compiled versions (BBC__CLONES) gets them
 * compiled for its instruction set. */
#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

/* A triangle on the screen, set up for drawing. */
typedef struct tri {
  int order[3];              /* the corners in the order a, b, c */
  const double *a, *b, *c;   /* oriented: the edge functions are positive inside */
  double area;               /* twice its screen area, > 0 */
  int x0, x1, y0, y1;        /* the pixels it may cover */
  int want_front, want_back; /* the images it may draw into */
  int slab, need_normal;     /* the view has a slab; the pixels need the normal */
  int wide;                  /* bbc__bake.taps: the pixels a tap of which it covers */
  int faces_camera;          /* its front (counter-clockwise side) faces the camera */
  double face[3];            /* baking normal maps: its unit normal (model space) */
  int away[2];               /* ... and face_away for the front and the back image */
  const bbc_material *mat;
} tri;

/* Projects triangle t (its corners into s: x, y, depth) and decides
 * whether it can draw anything: 0 when it is culled, degenerate, outside
 * the slab or covers no pixel centre. The corners stay apart from tr, so
 * that tr's fields can live in registers. */
static ALWAYS_INLINE int triangle_setup(const bbc_mesh *m, size_t t, const target *tg,
                                        double s[3][3], tri *tr) {
  const camera *cam = tg->cam;
  const bbc_view *view = tg->view;
  const uint32_t *ix = m->indices + 3 * t;
  if (tg->proj)
    for (int k = 0; k < 3; k++) memcpy(s[k], tg->proj + 3 * (size_t)ix[k], sizeof s[k]);
  else
    for (int k = 0; k < 3; k++) bbc__camera_project(cam, m->positions + 3 * ix[k], s[k]);
  /* Bounds first (the same whatever the vertices' order). */
  double minx = min3(s[0][0], s[1][0], s[2][0]), maxx = max3(s[0][0], s[1][0], s[2][0]);
  double miny = min3(s[0][1], s[1][1], s[2][1]), maxy = max3(s[0][1], s[1][1], s[2][1]);
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
  /* Renders of a whole detailed model (no slab: the bounds are the
   * vertices'): most faces cover no pixel centre, and the bounds test ends
   * them before any other work. */
  int whole = !tg->bake && !(view->depth_max > view->depth_min);
  if (whole) {
    if (!pixel_bounds(minx, maxx, miny, maxy, tg->width, tg->height, &x0, &x1, &y0, &y1)) return 0;
    /* Coverage only grows: a face whose every candidate pixel is covered
     * already changes nothing (inside a dense crown, most). */
    if (tg->cover && all_covered(tg->cover, tg->width, x0, x1, y0, y1)) return 0;
  }
  double area =
      (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[1][1] - s[0][1]) * (s[2][0] - s[0][0]);
  if (area == 0 || !isfinite(area)) return 0;
  /* Counter-clockwise seen by the camera turns clockwise on the y-down
   * screen: area < 0 means the triangle's front faces the camera. */
  int faces_camera = area < 0;
  const bbc_material *mat = &m->materials[m->face_material[t]];
  int want_front = 1, want_back = tg->bake && tg->bake->back;
  if (tg->bake ? tg->bake->backface : mat->single_sided) {
    want_front = faces_camera;
    want_back = want_back && !faces_camera;
  }
  if (!want_front && !want_back) return 0;
  /* Orient so that the edge functions are positive inside. */
  int *order = tr->order;
  order[0] = 0;
  order[1] = 1;
  order[2] = 2;
  if (area < 0) {
    order[1] = 2;
    order[2] = 1;
    area = -area;
  }
  const double *a = s[order[0]], *b = s[order[1]], *c = s[order[2]];
  int inside = a[2] >= view->depth_min && a[2] <= view->depth_max && b[2] >= view->depth_min &&
               b[2] <= view->depth_max && c[2] >= view->depth_min && c[2] <= view->depth_max;
  if (view->depth_max > view->depth_min && !inside &&
      !slab_bounds(a, b, c, view->depth_min, view->depth_max, &minx, &maxx, &miny, &maxy))
    return 0; /* no part of it inside the slab */
  /* bbc__bake.taps: a thin face (under 2 pixels across) draws the pixels
   * a tap of which (+-1/4 pixel) can lie in it too, not only those whose
   * centre does (a thicker one's neighbours have those) */
  tr->wide = 0;
  if (tg->bake && tg->bake->colour_taps) {
    double e2 = 0;
    for (int k = 0; k < 3; k++) {
      const double *p = s[k], *q = s[(k + 1) % 3];
      double dx = q[0] - p[0], dy = q[1] - p[1];
      e2 = fmax(e2, dx * dx + dy * dy);
    }
    tr->wide = area * area < 4.0 * e2; /* area / longest edge: its least height */
  }
  double tm = tr->wide ? 0.25 : 0.0;
  if (!whole && !pixel_bounds(minx - tm, maxx + tm, miny - tm, maxy + tm, tg->width, tg->height,
                              &x0, &x1, &y0, &y1))
    return 0;
  tr->a = a;
  tr->b = b;
  tr->c = c;
  assert(area > 0); /* oriented: the edge functions are positive inside */
  tr->area = area;
  tr->x0 = x0;
  tr->x1 = x1;
  tr->y0 = y0;
  tr->y1 = y1;
  tr->want_front = want_front;
  tr->want_back = want_back;
  tr->slab = view->depth_max > view->depth_min;
  tr->need_normal = view->lighting || (tg->bake && (tg->bake->front_nm || tg->bake->back_nm));
  tr->faces_camera = faces_camera;
  if (tg->bake && (tg->bake->front_nm || tg->bake->back_nm)) {
    bbc__triangle_cross(m, t, tr->face);
    vstore(tr->face, vnorm_or(vload(tr->face), v3(0, 0, 1)));
    tr->away[0] = face_away(tr->face, tg, 1);
    tr->away[1] = face_away(tr->face, tg, -1);
  }
  tr->mat = mat;
  return 1;
}

/* What a triangle's pixels interpolate and how they are shaded: alpha from
 * *tex, colour from *tex_rgb (a mip level); the corners' texture
 * coordinates, normals and voxel shadowing; the light's gain and the
 * ambient light. The arrays come initialised (no texture coordinates or
 * normals, no shadow, no ambient light). */
static ALWAYS_INLINE void triangle_shading(const bbc_mesh *m, size_t t, const target *tg,
                                           const tri *tr, const bbc_image **tex_out,
                                           const bbc_image **tex_rgb_out, const float *uv[3],
                                           const float *nv[3], float sh[3], double *gain,
                                           double amb[3]) {
  const bbc_view *view = tg->view;
  const uint32_t *ix = m->indices + 3 * t;
  const int *order = tr->order;
  const bbc_material *mat = tr->mat;
  double area = tr->area;
  const bbc_image *tex = NULL, *tex_rgb = NULL;
  if (mat->texture >= 0 && m->uvs && m->textures[mat->texture].image.rgba)
    tex = tex_rgb = &m->textures[mat->texture].image;
  for (int k = 0; k < 3; k++) {
    uint32_t vi = ix[order[k]];
    if (m->uvs) uv[k] = m->uvs + 2 * vi;
    nv[k] = m->normals + 3 * vi;
    if (view->vertex_shade) sh[k] = view->vertex_shade[vi];
  }
  if (tex && tg->bake && tg->bake->mips) {
    /* The mip level: log2 of texels per pixel (the square root of the
     * triangle's texel area over its pixel area), rounded. */
    const bbc__mips *mp = &tg->bake->mips[mat->texture];
    double du1 = uv[1][0] - uv[0][0], dv1 = uv[1][1] - uv[0][1];
    double du2 = uv[2][0] - uv[0][0], dv2 = uv[2][1] - uv[0][1];
    double texels = fabs(du1 * dv2 - dv1 * du2) * tex->width * tex->height;
    int level = texels > 0 ? mip_level_of(texels / area) + tg->bake->mip_bias : 0;
    if (level > mp->levels) level = mp->levels;
    if (level > 0) tex_rgb = &mp->level[level - 1];
  }
  *tex_out = tex;
  *tex_rgb_out = tex_rgb;
  *gain = view->light_gain > 0 ? view->light_gain : 1.0;
  /* The ambient light of X3D viewers: 0.2 x ambientIntensity x the diffuse
   * colour, untextured, with ambientIntensity the mean over the channels of
   * Ka / Kd, as view3dscene maps an MTL (measured on flat quads of coloured
   * Kd and Ka; Ka 0.2 when the material gives none); for a grey Kd this is
   * OpenGL's fixed-function 0.2 x Ka. */
  if (view->lighting && view->ambient && !mat->unlit) {
    int given = mat->ambient[0] > 0 || mat->ambient[1] > 0 || mat->ambient[2] > 0;
    double ai = 0;
    int n = 0;
    for (int k = 0; k < 3; k++)
      if (mat->base_color[k] > 0) {
        ai += (given ? mat->ambient[k] : 0.2) / mat->base_color[k];
        n++;
      }
    if (n)
      for (int k = 0; k < 3; k++) amb[k] = 0.2 * ai / n * mat->base_color[k];
  }
}

/* A triangle's edge functions: edge k from E0 to E1, its function along a
 * row ea x + eb(row), ea and the reciprocal fixed for the triangle; tl:
 * whether it is a top or left edge (the pixels on it are the triangle's). */
typedef struct edges {
  const double *E0[3], *E1[3];
  double edx[3], ea[3], inv_ea[3], t2[3];
  int tl[3];
} edges;

static ALWAYS_INLINE void edge_setup(const tri *tr, edges *ed) {
  const double *a = tr->a, *b = tr->b, *c = tr->c;
  ed->tl[0] = is_top_left(b[0], b[1], c[0], c[1]);
  ed->tl[1] = is_top_left(c[0], c[1], a[0], a[1]);
  ed->tl[2] = is_top_left(a[0], a[1], b[0], b[1]);
  ed->E0[0] = b;
  ed->E0[1] = c;
  ed->E0[2] = a;
  ed->E1[0] = c;
  ed->E1[1] = a;
  ed->E1[2] = b;
  const double *const *E0 = ed->E0, *const *E1 = ed->E1;
  for (int k = 0; k < 3; k++) {
    ed->edx[k] = E1[k][0] - E0[k][0];
    ed->ea[k] = -(E1[k][1] - E0[k][1]);
    ed->t2[k] = (E1[k][1] - E0[k][1]) * E0[k][0];
    ed->inv_ea[k] = ed->ea[k] > 1e-12 || ed->ea[k] < -1e-12 ? 1.0 / ed->ea[k] : 0;
  }
}

/* The row's span where every edge function can be >= 0, widened for
 * rounding (PIXEL_MARGIN, and the error of eb over the slope: a nearly
 * horizontal edge) and by `grow` pixels to either side; the exact test
 * decides each pixel. 0 when empty. */
static ALWAYS_INLINE int row_span(const edges *ed, double py, double grow, int x0, int x1, int *xs,
                                  int *xe) {
  const double *const *E0 = ed->E0;
  const double *edx = ed->edx, *ea = ed->ea, *inv_ea = ed->inv_ea, *t2 = ed->t2;
  double lo = x0, hi = x1;
  for (int k = 0; k < 3; k++) {
    double t1 = edx[k] * (py - E0[k][1]), eb = t1 + t2[k];
    double err = 1e-13 * (fabs(t1) + fabs(t2[k])) * inv_ea[k];
    if (ea[k] > 1e-12)
      lo = max2(lo, ceil(-eb * inv_ea[k] - 0.5 - grow - PIXEL_MARGIN - err));
    else if (ea[k] < -1e-12)
      hi = min2(hi, floor(-eb * inv_ea[k] - 0.5 + grow + PIXEL_MARGIN - err));
  }
  if (!(lo <= hi)) return 0;
  *xs = (int)lo;
  *xe = (int)hi;
  return 1;
}

/* One triangle: its set-up by stage, then every pixel whose centre it
 * covers (the top-left rule on its edges) within the view's slab, with the
 * depth tests, the alpha test, the colour, the shading and the normal, into
 * the front and back images (or only the coverage). */
/* A material's map (1 + texture index, 0 = none: normal_map,
 * occlusion_map) as an image, or NULL. */
static const bbc_image *material_map(const bbc_mesh *m, int map) {
  return map > 0 && (size_t)map <= m->texture_count ? &m->textures[map - 1].image : NULL;
}

/* An engine's lighting (bbc_view.sun), as glTF viewers light a lit
 * material: the normal n (interpolated, unit) bent by the material's normal
 * map through the corners' tangents (weights w, at texture coordinate (u, v);
 * u < 0: none), turned to the side seen (a double-sided face seen from behind
 * shows its back), lit by the ambient light times the occlusion map's red
 * channel and by the sun (Lambert), over ambient + sun so that a surface
 * facing the sun keeps its colour. */
static double engine_light(const bbc_mesh *m, size_t t, const target *tg, const tri *tr,
                           const double w[3], float u, float v, const double n[3]) {
  const bbc_material *mat = tr->mat;
  const uint32_t *ix = m->indices + 3 * t;
  vec3 nn = vload(n);
  const bbc_image *nmap = material_map(m, mat->normal_map);
  if (nmap && nmap->rgba && m->tangents && u >= 0) {
    double tg3[3] = {0, 0, 0}, hand = 0;
    for (int k = 0; k < 3; k++) {
      const float *tk = m->tangents + 4 * (size_t)ix[tr->order[k]];
      for (int c = 0; c < 3; c++) tg3[c] += w[k] * tk[c];
      hand += w[k] * tk[3];
    }
    vec3 T = vload(tg3);
    T = vnormalize(vsub(T, vscale(nn, vdot(nn, T))));
    vec3 B = vscale(vcross(nn, T), hand < 0 ? -1.0 : 1.0);
    const uint8_t *c = sample(nmap, u, v);
    double x = c[0] / 127.5 - 1, y = c[1] / 127.5 - 1, z = c[2] / 127.5 - 1;
    vec3 bent = vadd(vadd(vscale(T, x), vscale(B, y)), vscale(nn, z));
    if (vdot(bent, bent) > 1e-12) nn = vnormalize(bent);
  }
  if (!tr->faces_camera) nn = vscale(nn, -1.0);
  double ao = 1.0;
  const bbc_image *omap = material_map(m, mat->occlusion_map);
  if (omap && omap->rgba && u >= 0) ao = k_unit[sample(omap, u, v)[0]];
  double ndl = vdot(nn, vload(tg->light));
  double amb = tg->view->sun_ambient;
  return (amb * ao + (ndl > 0 ? ndl : 0)) / (amb + 1.0);
}

/* Baking with `outward`: the direction a two-sided surface's normal is
 * turned to, in the image's frame (x right, y up, z towards the image's
 * viewer): the viewer's z plus `outward` times the unit direction from the
 * bake's centre to the surface point (l: its barycentric weights). */
static const double *outward_dir(const bbc_mesh *m, size_t t, const tri *tr, double l0, double l1,
                                 double l2, const target *tg, double toward, double *d) {
  const uint32_t *ix = m->indices + 3 * t;
  const double *p0 = m->positions + 3 * (size_t)ix[tr->order[0]];
  const double *p1 = m->positions + 3 * (size_t)ix[tr->order[1]];
  const double *p2 = m->positions + 3 * (size_t)ix[tr->order[2]];
  double r[3];
  for (int k = 0; k < 3; k++) r[k] = l0 * p0[k] + l1 * p1[k] + l2 * p2[k] - tg->bake->center[k];
  vec3 u = vnorm_or(vload(r), v3(0, 0, 0));
  const camera *cam = tg->cam;
  double w = tg->bake->outward;
  d[0] = w * vdot(u, vload(cam->r));
  d[1] = w * vdot(u, vload(cam->u));
  d[2] = -toward * w * vdot(u, vload(cam->f));
  return d;
}

/* The alpha test at (u, v) of a textured material: from the texture's
 * bits when given (a material of opacity 1), else from its texel. */
static inline int alpha_passes(const bbc_image *tex, const bbc__alpha_bits *bits,
                               const bbc_material *mat, float u, float v) {
  if (bits) return alpha_bit(tex, bits, u, v);
  return mat->base_color[3] * k_unit[sample(tex, u, v)[3]] >= 0.5;
}

/* bbc__bake.colour_taps: how the edge functions and the texture
 * coordinates change along the screen's x and y. */
typedef struct taps_grad {
  double wx[3], wy[3]; /* edge function k (w0 opposite a, ...) */
  double ux, uy, vx, vy;
} taps_grad;

static ALWAYS_INLINE void taps_setup(const tri *tr, const float *uv[3], double inv_area,
                                     taps_grad *g) {
  const double *a = tr->a, *b = tr->b, *c = tr->c;
  g->wx[0] = -(c[1] - b[1]);
  g->wy[0] = c[0] - b[0];
  g->wx[1] = -(a[1] - c[1]);
  g->wy[1] = a[0] - c[0];
  g->wx[2] = -(b[1] - a[1]);
  g->wy[2] = b[0] - a[0];
  g->ux = g->uy = g->vx = g->vy = 0;
  for (int k = 0; k < 3 && uv[0]; k++) {
    g->ux += g->wx[k] * inv_area * uv[k][0];
    g->uy += g->wy[k] * inv_area * uv[k][0];
    g->vx += g->wx[k] * inv_area * uv[k][1];
    g->vy += g->wy[k] * inv_area * uv[k][1];
  }
}

/* The taps of bbc__bake.colour_taps around the pixel (its edge functions
 * w, its texture coordinate (u0, v0)) that fall inside the triangle and
 * pass its alpha test (an untextured material's: its opacity), as bits
 * 0-3. */
static ALWAYS_INLINE unsigned tap_bits(const bbc_image *tex, const bbc__alpha_bits *bits,
                                       const bbc_material *mat, const taps_grad *g, double w0,
                                       double w1, double w2, double u0, double v0) {
  if (!tex && mat->base_color[3] < 0.5) return 0;
  unsigned mask = 0;
  for (int k = 0; k < 4; k++) {
    double ox = k & 1 ? 0.25 : -0.25, oy = k & 2 ? 0.25 : -0.25;
    if (w0 + g->wx[0] * ox + g->wy[0] * oy < 0 || w1 + g->wx[1] * ox + g->wy[1] * oy < 0 ||
        w2 + g->wx[2] * ox + g->wy[2] * oy < 0)
      continue;
    if (tex) {
      float tu = (float)(u0 + g->ux * ox + g->uy * oy), tv = (float)(v0 + g->vx * ox + g->vy * oy);
      if (!alpha_passes(tex, bits, mat, tu, tv)) continue;
    }
    mask |= 1u << k;
  }
  return mask;
}

/* col[0..2] times the mean texel colour at the taps `mask` (not 0). */
static void tap_colour(const bbc_image *tex_rgb, const taps_grad *g, unsigned mask, double u0,
                       double v0, double col[4]) {
  unsigned sum[3] = {0, 0, 0}, n = 0;
  for (int k = 0; k < 4; k++) {
    if (!(mask >> k & 1u)) continue;
    double ox = k & 1 ? 0.25 : -0.25, oy = k & 2 ? 0.25 : -0.25;
    float tu = (float)(u0 + g->ux * ox + g->uy * oy), tv = (float)(v0 + g->vx * ox + g->vy * oy);
    const uint8_t *t = sample(tex_rgb, tu, tv);
    for (int c = 0; c < 3; c++) sum[c] += t[c];
    n++;
  }
  for (int c = 0; c < 3; c++) col[c] *= (double)sum[c] / (255.0 * n);
}

/* bbc__bake.taps: whether the pixel (edge functions w, texture coordinate
 * (u0, v0), its centre in the triangle, passing the alpha test there,
 * winning the front and back depth tests) draws into the front image
 * (*front; tf its taps byte, NULL when it may not) and the back (tb), and
 * col times its texture colour. A face passing at the centre draws over one
 * that passes at taps only whatever their depths; one passing at taps only
 * draws where none passing at the centre has. */
static ALWAYS_INLINE int taps_draw(const bbc_image *tex, const bbc_image *tex_rgb,
                                   const bbc__alpha_bits *bits, const bbc_material *mat,
                                   const taps_grad *g, double w0, double w1, double w2, double u0,
                                   double v0, int in, int centre, int df, int db, uint8_t *tf,
                                   uint8_t *tb, int *front, int *back, double col[4]) {
  *front = tf && (centre ? df || !*tf : df && !*tf);
  *back = tb && (centre ? db || !*tb : db && !*tb);
  if (!*front && !*back) return 0;
  unsigned mask = tex || !in ? tap_bits(tex, bits, mat, g, w0, w1, w2, u0, v0) : 0;
  if (!mask && !centre) return 0;
  if (centre && *front) *tf = 1;
  if (centre && *back) *tb = 1;
  if (tex && mask) {
    tap_colour(tex_rgb, g, mask, u0, v0, col);
  } else if (tex) { /* no tap passes: the centre's texel */
    const uint8_t *t = sample(tex_rgb, (float)u0, (float)v0);
    for (int c = 0; c < 3; c++) col[c] *= k_unit[t[c]];
  }
  return 1;
}

/* The pixels of row py the triangle may draw: those whose centre it may
 * cover, and when tr->wide those a tap of which (rows py +- 1/4, 1/4 pixel
 * to either side) it may cover. 0 when none. */
static ALWAYS_INLINE int draw_span(const edges *ed, const tri *tr, double py, int *xs, int *xe) {
  if (!tr->wide) return row_span(ed, py, 0.0, tr->x0, tr->x1, xs, xe);
  int s0, s1, any = 0;
  *xs = tr->x1, *xe = tr->x0;
  for (int k = -1; k <= 1; k++)
    if (row_span(ed, py + 0.25 * k, k ? 0.25 : 0.0, tr->x0, tr->x1, &s0, &s1)) {
      *xs = s0 < *xs ? s0 : *xs;
      *xe = s1 > *xe ? s1 : *xe;
      any = 1;
    }
  return any;
}

static BBC__CLONES void draw_triangle(const bbc_mesh *m, size_t t, const target *tg) {
  const bbc_view *view = tg->view;
  double s[3][3];
  tri tr;
  if (!triangle_setup(m, t, tg, s, &tr)) return;
  const bbc_image *tex, *tex_rgb;
  const float *uv[3] = {NULL, NULL, NULL}, *nv[3] = {NULL, NULL, NULL};
  float sh[3] = {1, 1, 1};
  double gain, amb[3] = {0, 0, 0}, inv_area = 1.0 / tr.area;
  triangle_shading(m, t, tg, &tr, &tex, &tex_rgb, uv, nv, sh, &gain, amb);
  edges ed;
  edge_setup(&tr, &ed);
  const double *a = tr.a, *b = tr.b, *c = tr.c;
  const bbc_material *mat = tr.mat;
  int want_front = tr.want_front, want_back = tr.want_back, slab = tr.slab;
  int tl0 = ed.tl[0], tl1 = ed.tl[1], tl2 = ed.tl[2], need_normal = tr.need_normal;
  /* The alpha test from the texture's bits where they answer it: a
   * material of opacity 1. */
  const bbc__alpha_bits *bits = NULL, *all = tg->bake ? tg->bake->alpha_bits : tg->cover_bits;
  if (tex && all && mat->base_color[3] == 1.0f && all[mat->texture].bits) bits = &all[mat->texture];
  uint8_t *tap_f = tg->bake && tg->bake->colour_taps ? tg->bake->taps[0] : NULL;
  uint8_t *tap_b = tap_f ? tg->bake->taps[1] : NULL;
  taps_grad tp;
  if (tap_f) taps_setup(&tr, uv, inv_area, &tp);
  double odir[3];
  for (int y = tr.y0; y <= tr.y1; y++) {
    double py = y + 0.5;
    int xs, xe;
    if (!draw_span(&ed, &tr, py, &xs, &xe)) continue;
    for (int x = xs; x <= xe; x++) {
      double px = x + 0.5;
      /* Edge functions: w0 opposite a, etc. */
      double w0 = (c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]);
      double w1 = (a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]);
      double w2 = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
      /* in: the triangle covers the pixel's centre (with taps, a pixel only
       * a tap of which it covers is drawn too) */
      int in = !(w0 < 0 || w1 < 0 || w2 < 0) &&
               !((w0 == 0 && !tl0) || (w1 == 0 && !tl1) || (w2 == 0 && !tl2));
      if (!in && !tr.wide) continue;
      double l0 = w0 * inv_area, l1 = w1 * inv_area, l2 = w2 * inv_area;
      float z = (float)(l0 * a[2] + l1 * b[2] + l2 * c[2]);
      size_t pi = (size_t)y * tg->width + x;
      if (tg->cover) { /* coverage: the depth test against the far plane only */
        if (tg->cover[pi] || !want_front || !(z < FLT_MAX)) continue;
        if (slab && (z < view->depth_min || z > view->depth_max)) continue;
        if (tex) {
          float u = (float)(l0 * uv[0][0] + l1 * uv[1][0] + l2 * uv[2][0]);
          float v = (float)(l0 * uv[0][1] + l1 * uv[1][1] + l2 * uv[2][1]);
          if (!alpha_passes(tex, bits, mat, u, v)) continue;
        } else if (mat->base_color[3] < 0.5) {
          continue;
        }
        tg->cover[pi] = 1;
        continue;
      }
      int df = want_front && z < tg->depth[pi];
      int db = want_back && z > tg->depth_back[pi];
      /* bbc__bake.taps: !sf, !sb: no face passing at its centre drew the sample */
      uint8_t *tf = tap_f ? tap_f + pi : NULL, *tbk = tap_b ? tap_b + pi : NULL;
      int sf = !tf || *tf, sb = !tbk || *tbk;
      if (!df && !db && (!want_front || sf) && (!want_back || sb)) continue;
      if (slab && (z < view->depth_min || z > view->depth_max))
        continue; /* outside the slab: the triangle is clipped there */
      double col[4] = {mat->base_color[0], mat->base_color[1], mat->base_color[2],
                       mat->base_color[3]};
      double ud = 0, vd = 0;
      if (uv[0]) {
        ud = l0 * uv[0][0] + l1 * uv[1][0] + l2 * uv[2][0];
        vd = l0 * uv[0][1] + l1 * uv[1][1] + l2 * uv[2][1];
      }
      float u = (float)ud, v = (float)vd;
      /* centre: the pixel's centre is in the triangle and passes the alpha
       * test (the base level's), before the colour */
      int centre = in && (tex ? alpha_passes(tex, bits, mat, u, v) : col[3] >= 0.5);
      int front, back;
      if (tf) {
        if (!taps_draw(tex, tex_rgb, bits, mat, &tp, w0, w1, w2, ud, vd, in, centre, df, db,
                       want_front ? tf : NULL, want_back ? tbk : NULL, &front, &back, col))
          continue;
      } else {
        front = df;
        back = db;
        if (!front && !back) continue;
        if (!centre) continue;
        if (tex) {
          const uint8_t *tx = sample(tex_rgb, u, v);
          for (int k = 0; k < 3; k++) col[k] *= k_unit[tx[k]];
        }
      }
      double n[3] = {0, 0, 1};
      if (need_normal) {
        for (int k = 0; k < 3; k++) n[k] = l0 * nv[0][k] + l1 * nv[1][k] + l2 * nv[2][k];
        vstore(n, vnormalize(vload(n)));
      }
      double shade = 1.0, occl = 1.0;
      if (view->vertex_shade) occl = l0 * sh[0] + l1 * sh[1] + l2 * sh[2];
      /* Baking an occlusion map: the shadowing goes there, not into the colour. */
      int ao_image = tg->bake && tg->bake->front_ao;
      double occl_col = ao_image ? 1.0 : occl;
      if (view->lighting && !mat->unlit) { /* unlit materials carry their light */
        double lw[3] = {l0, l1, l2};
        if (view->sun)
          shade = engine_light(m, t, tg, &tr, lw, uv[0] ? u : -1, v, n) * occl_col;
        else
          shade =
              gain * (view->headlight
                          ? fabs(n[0] * tg->light[0] + n[1] * tg->light[1] + n[2] * tg->light[2])
                          : sun_shade(n, tg->light));
      }
      if (!view->sun) shade *= occl_col;
      uint8_t px4[4] = {to_byte(col[0] * shade + amb[0] * occl_col),
                        to_byte(col[1] * shade + amb[1] * occl_col),
                        to_byte(col[2] * shade + amb[2] * occl_col),
                        tg->bake && tg->bake->face_alpha ? tg->bake->face_alpha[t] : 255};
      if (tg->sun_lum && front) {
        double s2 = 1.0;
        if (view->lighting && !mat->unlit) s2 = gain * sun_shade(n, tg->sun);
        s2 *= occl;
        tg->sun_lum[pi] = (float)(0.2126 * to_byte(col[0] * s2 + amb[0] * occl) +
                                  0.7152 * to_byte(col[1] * s2 + amb[1] * occl) +
                                  0.0722 * to_byte(col[2] * s2 + amb[2] * occl));
      }
      if (ao_image) {
        uint8_t g = to_byte(occl), grey[4] = {g, g, g, 255};
        if (front) memcpy(tg->bake->front_ao + 4 * pi, grey, 4);
        if (back && tg->bake->back_ao) memcpy(tg->bake->back_ao + 4 * pi, grey, 4);
      }
      if (front) {
        tg->depth[pi] = z;
        memcpy(tg->rgba + 4 * pi, px4, 4);
        if (tg->bake && tg->bake->front_nm)
          put_normal(tg->bake->front_nm + 4 * pi, n, tr.face, tr.away[0], tg, 1,
                     tg->bake->outward > 0 ? outward_dir(m, t, &tr, l0, l1, l2, tg, 1, odir)
                                           : NULL);
      }
      if (back) {
        tg->depth_back[pi] = z;
        memcpy(tg->bake->back + 4 * pi, px4, 4);
        if (tg->bake->back_nm)
          put_normal(tg->bake->back_nm + 4 * pi, n, tr.face, tr.away[1], tg, -1,
                     tg->bake->outward > 0 ? outward_dir(m, t, &tr, l0, l1, l2, tg, -1, odir)
                                           : NULL);
      }
    }
  }
}

static void draw_point(const bbc_mesh *m, size_t v, const camera *cam, const bbc_view *view,
                       bbc_image *img, float *depth) {
  double s[3];
  bbc__camera_project(cam, m->positions + 3 * v, s);
  double half = 0.5 * (view->point_size_px >= 1 ? view->point_size_px : 1);
  int x0 = (int)floor(s[0] - half + 0.5), x1 = (int)floor(s[0] + half - 0.5);
  int y0 = (int)floor(s[1] - half + 0.5), y1 = (int)floor(s[1] + half - 0.5);
  if (x1 < x0) x1 = x0;
  if (y1 < y0) y1 = y0;
  uint8_t rgb[3] = {200, 200, 200};
  if (m->colors) memcpy(rgb, m->colors + 4 * v, 3);
  for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < img->height; y++)
    for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < img->width; x++) {
      double dx = x + 0.5 - s[0], dy = y + 0.5 - s[1];
      int under = x == (int)floor(s[0]) && y == (int)floor(s[1]);
      if (view->point_round && !under && dx * dx + dy * dy > half * half) continue;
      size_t pi = (size_t)y * img->width + x;
      if ((float)s[2] >= depth[pi]) continue;
      depth[pi] = (float)s[2];
      uint8_t *o = img->rgba + 4 * pi;
      o[0] = rgb[0];
      o[1] = rgb[1];
      o[2] = rgb[2];
      o[3] = 255;
    }
}

static void setup_light(const camera *cam, const bbc_view *view, double *light) {
  if (view->headlight) {
    for (int k = 0; k < 3; k++) light[k] = -cam->f[k];
  } else if (view->light[0] != 0 || view->light[1] != 0 || view->light[2] != 0) {
    memcpy(light, view->light, 3 * sizeof *light);
  } else { /* from over the viewer's left shoulder */
    for (int k = 0; k < 3; k++) light[k] = -0.6 * cam->f[k] + 0.6 * cam->u[k] - 0.45 * cam->r[k];
  }
  vstore(light, vnormalize(vload(light)));
}

bbc_result bbc__check_view(const bbc_view *view, int w, int h, camera *cam, bbc_error *err) {
  if (w <= 0 || h <= 0)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "render: image not allocated");
  if (!(view->half_extent > 0))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "render: half_extent must be > 0");
  if (!bbc__camera_setup(cam, view, w, h))
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "render: up vector is parallel to the view direction");
  return BBC_OK;
}

/* Every vertex of the mesh projected by cam (x, y, depth), or NULL when
 * out of memory (the rasterizer then projects per triangle). */
static double *project_all(const bbc_mesh *m, const camera *cam) {
  double *p = malloc((m->vertex_count ? m->vertex_count : 1) * 3 * sizeof *p);
  if (p)
    for (size_t v = 0; v < m->vertex_count; v++)
      bbc__camera_project(cam, m->positions + 3 * v, p + 3 * v);
  return p;
}

/* bbc_render_ortho; with sun_lum, also the luminance lit by `sun`. */
bbc_result bbc__render_lit(const bbc_mesh *m, const bbc_view *view, bbc_image *img,
                           const double *sun, float *sun_lum, bbc_error *err) {
  if (!img->rgba) return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "render: image not allocated");
  camera cam;
  bbc_result r = bbc__check_view(view, img->width, img->height, &cam, err);
  if (r != BBC_OK) return r;
  size_t n = (size_t)img->width * img->height;
  float *depth = malloc(n * sizeof *depth);
  if (!depth) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "render: out of memory");
  for (size_t i = 0; i < n; i++) {
    depth[i] = FLT_MAX;
    memcpy(img->rgba + 4 * i, view->background, 4);
  }
  target tg = {&cam, view, {0, 0, 0}, img->width, img->height, img->rgba, depth,
               NULL, NULL, sun_lum,   {0, 0, 0},  NULL,        NULL,      NULL};
  if (sun) memcpy(tg.sun, sun, sizeof tg.sun);
  setup_light(&cam, view, tg.light);
  if (m->kind == BBC_MESH_POINTS) {
    for (size_t v = 0; v < m->vertex_count; v++) draw_point(m, v, &cam, view, img, depth);
  } else {
    double *proj = project_all(m, &cam);
    tg.proj = proj;
    for (size_t t = 0; t < m->triangle_count; t++)
      if (!view->face_mask || view->face_mask[t]) draw_triangle(m, t, &tg);
    free(proj);
  }
  free(depth);
  return BBC_OK;
}

bbc_result bbc_render_ortho(const bbc_mesh *m, const bbc_view *view, bbc_image *img,
                            bbc_error *err) {
  assert(m && view && img);
  return bbc__render_lit(m, view, img, NULL, NULL, err);
}

bbc_result bbc__render_coverage(const bbc_mesh *m, const bbc_view *view, int size, uint8_t *cover,
                                const bbc__alpha_bits *alpha_bits, bbc_error *err) {
  camera cam;
  bbc_result r = bbc__check_view(view, size, size, &cam, err);
  if (r != BBC_OK) return r;
  memset(cover, 0, (size_t)size * size);
  target tg;
  memset(&tg, 0, sizeof tg);
  tg.cam = &cam;
  tg.view = view;
  tg.width = tg.height = size;
  tg.cover = cover;
  tg.cover_bits = alpha_bits;
  setup_light(&cam, view, tg.light);
  if (m->kind == BBC_MESH_POINTS) { /* points: the full render's alpha */
    bbc_image img;
    if (bbc_image_alloc(&img, size, size) != BBC_OK)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "render: out of memory");
    r = bbc__render_lit(m, view, &img, NULL, NULL, err);
    for (size_t i = 0; r == BBC_OK && i < (size_t)size * size; i++)
      cover[i] = img.rgba[4 * i + 3] >= 128;
    bbc_image_free(&img);
    return r;
  }
  /* Each triangle projects its corners (no project_all): on a model of a
   * million triangles, writing and reading back every vertex's projection
   * costs more than projecting shared corners twice */
  for (size_t t = 0; t < m->triangle_count; t++)
    if (!view->face_mask || view->face_mask[t]) draw_triangle(m, t, &tg);
  return BBC_OK;
}

float *bbc__depth_front_back(size_t n) {
  float *depth = malloc(2 * n * sizeof *depth);
  if (depth)
    for (size_t i = 0; i < n; i++) {
      depth[i] = FLT_MAX;
      depth[n + i] = -FLT_MAX;
    }
  return depth;
}

bbc_result bbc__render_bake(const bbc_mesh *m, const uint32_t *faces, size_t face_count,
                            const bbc_view *view, bbc__bake *bake, bbc_error *err) {
  if (m->kind != BBC_MESH_TRIANGLES || !bake->front)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "bake: needs triangles and a front image");
  camera cam;
  bbc_result r = bbc__check_view(view, bake->width, bake->height, &cam, err);
  if (r != BBC_OK) return r;
  size_t n = (size_t)bake->width * bake->height;
  float *depth = bbc__depth_front_back(n);
  if (!depth) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "bake: out of memory");
  target tg = {&cam, view,      {0, 0, 0}, bake->width, bake->height, bake->front, depth,
               bake, depth + n, NULL,      {0, 0, 0},   NULL,         NULL,        NULL};
  setup_light(&cam, view, tg.light);
  size_t count = faces ? face_count : m->triangle_count;
  for (size_t i = 0; i < count; i++) draw_triangle(m, faces ? faces[i] : i, &tg);
  if (bake->front_depth) memcpy(bake->front_depth, depth, n * sizeof *depth);
  free(depth);
  return BBC_OK;
}
