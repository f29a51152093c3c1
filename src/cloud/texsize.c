/* texsize.c — step 3, the billboards' texture sizes (thesis 2.1.9): the
 * longest side of all gets `texres` texels and every side the same texels
 * a model unit (a sampled part's leftovers' billboards left out of the
 * longest and given half as many), rounded down to a power of two (at
 * least 4); with
 * `atlasmax`, the largest texres whose images fit one atlas of that size. */
#include "cloud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bbc__floor_pow2(double x) {
  int p = 1;
  while (p * 2 <= x && p < (1 << 14)) p *= 2;
  return p;
}

/* A billboard's texture at `texel` model units a texel: powers of two, at
 * least 4 (the sizes bbc__cloud_billboards_init gives, which the atlas
 * budget predicts). */
double bbc__rect_density(const bbc_planeset *set, const bbc_billboard *r) {
  return set && r->plane < set->plane_count && set->planes[r->plane].leftover ? 0.5 : 1.0;
}

static void tex_size(const bbc_billboard *r, double texel, int *w, int *h) {
  *w = bbc__floor_pow2(texel > 0 ? r->width / texel : 1);
  *h = bbc__floor_pow2(texel > 0 ? r->height / texel : 1);
  if (*w < 4) *w = 4;
  if (*h < 4) *h = 4;
}

/* Model units a texel at `texres` for billboards `rects`: the longest side
 * gets texres texels. */
static double texel_of(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int texres) {
  double longest = 0;
  for (size_t i = 0; i < n; i++)
    if (bbc__rect_density(set, &rects[i]) == 1.0)
      longest = fmax(longest, fmax(rects[i].width, rects[i].height));
  for (size_t i = 0; longest == 0 && i < n; i++) /* leftovers' alone */
    longest = fmax(longest, fmax(rects[i].width, rects[i].height));
  return longest / texres;
}

size_t bbc__cloud_texels(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int texres,
                         int sides) {
  double texel = texel_of(set, rects, n, texres);
  size_t total = 0;
  for (size_t i = 0; i < n; i++) {
    int w, h;
    tex_size(&rects[i], texel / bbc__rect_density(set, &rects[i]), &w, &h);
    total += (size_t)w * (size_t)h;
  }
  return total * (size_t)sides;
}

/* Whether the images of billboards `rects` at `texres` (sized as
 * bbc__cloud_billboards_init sizes them: quality 3 keeps its samples,
 * `scale` 4) pack into one limit x limit atlas (1), do not (0), or out of
 * memory (-1); blank images stand in for them. */
static int atlas_fits(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int texres,
                      int sides, int scale, int limit) {
  double texel = texel_of(set, rects, n, texres);
  size_t count = (size_t)sides * n, biggest = 0;
  bbc_image *imgs = calloc(count ? count : 1, sizeof *imgs);
  bbc_atlas_rect *where = calloc(count ? count : 1, sizeof *where);
  int ok = imgs && where;
  for (size_t i = 0; ok && i < n; i++) {
    int w, h;
    tex_size(&rects[i], texel / bbc__rect_density(set, &rects[i]), &w, &h);
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
  bbc_result r =
      ok ? bbc_atlas_pack(imgs, count, 2, limit, &atlas, where, &quiet) : BBC_ERROR_OUT_OF_MEMORY;
  bbc_image_free(&atlas);
  free(blank);
  free(where);
  free(imgs);
  return r == BBC_OK ? 1 : r == BBC_ERROR_OUT_OF_MEMORY ? -1 : 0;
}

int bbc__texres_fitting(const bbc_planeset *set, const bbc_billboard *rects, size_t n, int sides,
                        int scale, int limit) {
  size_t per = (size_t)sides * (size_t)(scale * scale);
  for (int t = 8192; n && t > 4; t /= 2) {
    if ((double)bbc__cloud_texels(set, rects, n, t, 1) * (double)per > (double)limit * limit)
      continue;
    int fits = atlas_fits(set, rects, n, t, sides, scale, limit);
    if (fits) return fits > 0 ? t : -1;
  }
  return 4;
}

void bbc__cloud_billboards_init(bbc_cloud *cl, const bbc_planeset *set, const bbc_billboard *bb,
                                const size_t *order, size_t np_kept, const bbc__stem *stem,
                                size_t nk, double longest, int texres) {
  cl->billboard_count = nk;
  cl->epsilon_abs = set->epsilon_abs;
  cl->texres = texres;
  double texel = longest / texres;
  for (size_t k = 0; k < nk; k++) {
    bbc_cloud_billboard *cb = &cl->billboards[k];
    const bbc_plane *p = k < np_kept ? &set->planes[order[k]] : &stem->planes[k - np_kept];
    cb->rect = k < np_kept ? bb[order[k]] : stem->rects[k - np_kept];
    cb->kind = p->kind;
    cb->part = p->part;
    memcpy(cb->normal, p->normal, sizeof cb->normal);
    cb->d = p->d;
    tex_size(&cb->rect, texel / bbc__rect_density(set, &cb->rect), &cb->tex_width, &cb->tex_height);
  }
}
