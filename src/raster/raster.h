/*
 * raster.h — the software rasterizer's internal interface (src/raster):
 * baking, coverage, point splats, texture mipmaps and
 * the orthographic camera. Not installed.
 */
#ifndef BBC_RASTER_H
#define BBC_RASTER_H

#include "base.h"

/* ---- baking, coverage, splats (src/raster/raster.c) ----------------------- */
/* A texture's mipmaps (src/raster/mips.c) as a GPU makes them
 * (glGenerateMipmap: each level the 2x2 box average of the one before, every
 * channel on its own, so the colour of transparent texels bleeds into their
 * opaque neighbours, as on screen). Only a baked light reads them. */
typedef struct bbc__mips {
  int levels;       /* levels after the base image */
  bbc_image *level; /* level[k - 1]: level k, half of level k - 1 (at least 1) */
} bbc__mips;

/* mips[t] for each of the mesh's textures (a texture without an image gets
 * none); free with bbc__mips_free. */
bbc_result bbc__mips_build(const bbc_mesh *mesh, bbc__mips **mips, bbc_error *err);
void bbc__mips_free(bbc__mips *mips, size_t count);

/* A texture's alpha test as bits (src/raster/mips.c): bit set where the
 * texel's alpha is at least 128, the test a material of opacity 1 makes
 * (base_color[3] x alpha / 255 >= 0.5), in tiles of 8 x 8 texels a word
 * (tile (x / 8, y / 8) at word y / 8 x tiles_x + x / 8, bit (y % 8) x 8 +
 * x % 8): the same answers as the texels' alpha bytes from 1/32 of their
 * memory, so that the alpha tests of a bake's many small leaves stay in
 * the cache. */
typedef struct bbc__alpha_bits {
  uint64_t *bits; /* NULL: the texture has none (no image) */
  int tiles_x;
} bbc__alpha_bits;

/* bits[t] for each of the mesh's textures (NULL when it has none); free
 * with bbc__alpha_bits_free. */
bbc_result bbc__alpha_bits_build(const bbc_mesh *mesh, bbc__alpha_bits **bits, bbc_error *err);
void bbc__alpha_bits_free(bbc__alpha_bits *bits, size_t count);

typedef struct bbc__bake {
  int width, height;
  uint8_t *front, *back;       /* RGBA */
  uint8_t *front_nm, *back_nm; /* RGBA, may be NULL */
  float *front_depth;          /* may be NULL: receives the front image's depth a pixel
                                * (along the view from its centre; FLT_MAX: none) */
  double outward;              /* > 0: normal maps turn two-sided surfaces to the side
                                * facing their viewer plus `outward` times away from
                                * `center` (0: their viewer's) */
  double center[3];
  double flat;                 /* >= 0: each normal plus `flat` times the image's own
                                * normal (z), renormalised (nmflat) */
  double up[3];                /* the model's up axis (unit) */
  double up_tilt;              /* >= 0: a two-sided surface's normal is turned to the
                                * side of its face that turns to the image's viewer
                                * plus this times up (nmup) */
  uint8_t *front_ao, *back_ao; /* RGBA, may be NULL: the view's vertex_shade goes
                                * here (grey) instead of into the colour */
  int backface;
  /* Optional, per texture of the mesh: colours are read from the mip level
   * matching each triangle's texel footprint on the image (as a GPU shows
   * the texture from that distance), alpha from the base image (coverage
   * is the supersampling's business). */
  const bbc__mips *mips;
  /* Optional, per texture of the mesh: its alpha test as bits (the same
   * answers, faster). */
  const bbc__alpha_bits *alpha_bits;
  int mip_bias; /* levels added: log2 of the samples per cloud texel side (4:
                 * 2), so that colours are those of one texel */
  /* Colours without mipmaps (a material's albedo), fewer samples than 4 a
   * texel side: each sample's colour the mean of the texels at 4 points
   * +-1/4 of a sample from its centre (those inside the triangle whose
   * alpha test passes; at 2 samples a side, the points of 4 x 4 samples a
   * texel), so that a texel's colour averages as many points as before. */
  int colour_taps;
  /* With colour_taps, per sample of the front and back images (zeroed by
   * the caller; taps[1] NULL without a back image): 1 when a face passing
   * its alpha test at the sample's centre drew it. A face passing at one of
   * the sample's taps only draws it too (a thin face, under 2 pixels
   * across, also where only a tap lies in it), where no face passing at the
   * centre has, so that a texel whose coverage lies between its samples'
   * centres (a larch's needles) is a candidate with a colour: the dithering
   * can put there the coverage of the samples' centres around it (the
   * coverage alpha_mask counts: samples marked here). */
  uint8_t *taps[2];
  /* Optional, per triangle of the mesh: the alpha its samples get (255 when
   * NULL): `pure 2` gives a face crossing n slabs 255 / n in each. */
  const uint8_t *face_alpha;
} bbc__bake;

/* What bbc_render_ortho's alpha would show (alpha >= 128) on a size x
 * size image, 0 or 1 a pixel, without colours or depths: faster.
 * alpha_bits (or NULL): the mesh's textures' alpha tests as bits
 * (bbc__alpha_bits_build), the same answers from less memory. */
bbc_result bbc__render_coverage(const bbc_mesh *mesh, const bbc_view *view, int size,
                                uint8_t *cover, const bbc__alpha_bits *alpha_bits, bbc_error *err);
/* bbc_render_ortho, and with `sun` (or NULL) the luminance a sun from
 * there gives each pixel into sun_lum (width x height, or NULL), in the
 * same pass. */
bbc_result bbc__render_lit(const bbc_mesh *mesh, const bbc_view *view, bbc_image *img,
                           const double *sun, float *sun_lum, bbc_error *err);
/* One rasterization of `faces` (indices into mesh triangles; all when NULL)
 * for a billboard seen along view->direction (= minus the plane's normal),
 * filling the front image (the nearest surface seen from the front, along
 * +direction) and, when `back` is not NULL, the back image (the nearest
 * seen from behind) at once, with two depth buffers. Both images are laid out
 * in the plane's frame (texel x along the camera's right, rows top first), so
 * the same texel shows the same point of the plane. The view's slab, lighting,
 * light and vertex_shade apply. Normal maps (when not NULL) receive the
 * interpolated vertex normal in the billboard's tangent space (x = right,
 * y = up, z = towards that image's viewer, flipped to face it), encoded as
 * rgb = 255 (n + 1) / 2, alpha as the colour image. `backface`: each image
 * shows only faces whose winding faces its viewer. Images must be allocated
 * width x height and cleared by the caller. */
bbc_result bbc__render_bake(const bbc_mesh *mesh, const uint32_t *faces, size_t face_count,
                            const bbc_view *view, bbc__bake *bake, bbc_error *err);
/* The same for a point cloud's points (NULL: all), splatted `size_px`
 * pixels wide, round when `smooth`, coloured as scanned (else light grey);
 * the front image keeps the nearest point, the back image the farthest
 * (front_depth: its depth, as bbc__render_bake gives it). */
bbc_result bbc__render_splats(const bbc_mesh *mesh, const uint32_t *points, size_t count,
                              const bbc_view *view, bbc__bake *bake, double size_px, int smooth,
                              bbc_error *err);

/* The orthographic camera of a bbc_view on a w x h image. */
typedef struct bbc__camera {
  double r[3], u[3], f[3]; /* right, up, forward (unit) */
  double c[3];
  double scale;   /* pixels per model unit, x */
  double scale_y; /* pixels per model unit, y */
  double w2, h2;
} bbc__camera;

/* 0 when the view's up is parallel to its direction. */
int bbc__camera_setup(bbc__camera *cam, const bbc_view *view, int w, int h);
/* Depth buffers of n pixels for a front and a back image: the nearest
 * (FLT_MAX, cleared) then the farthest (-FLT_MAX); NULL when out of
 * memory. */
float *bbc__depth_front_back(size_t n);
/* bbc__camera_setup for a w x h image, with the error said (no image, a
 * zero extent, up along the view). */
bbc_result bbc__check_view(const bbc_view *view, int w, int h, bbc__camera *cam, bbc_error *err);

/* Screen position (x right, y down, pixels) and depth (model units along f). */
static inline void bbc__camera_project(const bbc__camera *cam, const double *p, double *s) {
  double d[3] = {p[0] - cam->c[0], p[1] - cam->c[1], p[2] - cam->c[2]};
  s[0] = cam->w2 + cam->scale * (d[0] * cam->r[0] + d[1] * cam->r[1] + d[2] * cam->r[2]);
  s[1] = cam->h2 - cam->scale_y * (d[0] * cam->u[0] + d[1] * cam->u[1] + d[2] * cam->u[2]);
  s[2] = d[0] * cam->f[0] + d[1] * cam->f[1] + d[2] * cam->f[2];
}

/* A view along `direction` (up hint `up`) centred on the box lo..hi and
 * framing its corners times `margin`; everything else zero. */
void bbc__view_frame_box(const double lo[3], const double hi[3], const double direction[3],
                         const double up[3], double margin, bbc_view *view);
#endif /* BBC_RASTER_H */
