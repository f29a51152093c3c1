/* params.c — the thesis's parameters (Appendix A, "Parameter Reference"):
 * names, ranges, defaults, and parsing with range checks. */
#include "base.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The table stores every field as an int or a double: the mode enums
 * (bbc_clustering, bbc_pure, ...) have an int's size. */
_Static_assert(sizeof(bbc_clustering) == sizeof(int) && sizeof(bbc_pure) == sizeof(int) &&
                   sizeof(bbc_quality) == sizeof(int) && sizeof(bbc_unlit_mode) == sizeof(int) &&
                   sizeof(bbc_vrml_format) == sizeof(int) && sizeof(bbc_axis) == sizeof(int),
               "a parameter's enum is stored as an int");

/* One table row: the public info plus where the value lives in bbc_params. */
typedef struct param_row {
  bbc_param_info info;
  size_t offset;
  int is_double; /* field is double (else int) */
} param_row;

#define F1           BBC_PARAM_KEEPS_STEP1
#define F3           BBC_PARAM_STEP3_ONLY
#define INT_FIELD(f) offsetof(bbc_params, f), 0
#define DBL_FIELD(f) offsetof(bbc_params, f), 1

static const param_row k_rows[] = {
    {{"break", BBC_PARAM_INT, 5, 1e9, 100, F1, "performance", "steps",
      "stop the recursive greedy select after n steps"},
     INT_FIELD(break_steps)},
    {{"breaknum", BBC_PARAM_INT, 10, 1e9, 2000, F1, "performance", "faces",
      "... but only if more than n primitives are simply valid for the subcell"},
     INT_FIELD(break_num)},
    {{"debug", BBC_PARAM_INT, 0, 3, 0, F1, "performance", "",
      "graphical debug level (0 silent ... 3)"},
     INT_FIELD(debug)},
    {{"res", BBC_PARAM_INT, 1, 180, 9, 0, "performance", "deg",
      "dual grid theta/phi resolution, degrees per cell; 180 mod res = 0"},
     INT_FIELD(res_deg)},
    {{"vn", BBC_PARAM_BOOL, 0, 1, 1, 0, "performance", "",
      "compute smooth vertex normals on load where the model has none"},
     INT_FIELD(vertex_normals)},
    {{"acceptunused", BBC_PARAM_BOOL, 0, 1, 0, 0, "extension", "",
      "load an OBJ whose vertices run on after its last face, unused (else refused as a file "
      "cut short, exit 4)"},
     INT_FIELD(accept_unused)},
    {{"cardboard", BBC_PARAM_BOOL, 0, 1, 0, F1, "plane", "",
      "cardboard plane finding (thesis 2.3.7)"},
     INT_FIELD(cardboard)},
    {{"cbcoverage", BBC_PARAM_REAL, 0, 99.9, 50, F3, "plane", "%",
      "minimum cardboard coverage, % of the mother plane"},
     DBL_FIELD(cb_coverage_pct)},
    {{"clustering", BBC_PARAM_INT, 0, 2, 0, 0, "plane", "",
      "face clustering: 0 off, 1 simple, 2 pre-clustering (2.3.10; thesis default 2)"},
     INT_FIELD(clustering)},
    {{"epsilon", BBC_PARAM_REAL, 0.001, 99, 6, 0, "plane", "%",
      "error threshold, % of the bounding-sphere radius (thesis default 5)"},
     DBL_FIELD(epsilon_pct)},
    {{"posttweak", BBC_PARAM_BOOL, 0, 1, 1, F1, "plane", "", "post-plane tweaking (2.3.3)"},
     INT_FIELD(post_tweak)},
    {{"punishval", BBC_PARAM_REAL, 0, 0.95, 0, F1, "plane", "",
      "view-dependent penalty maximum (2.3.8)"},
     DBL_FIELD(punish_value)},
    {{"punishcutoff", BBC_PARAM_REAL, 0, 90, 30, F1, "plane", "deg",
      "view-dependent penalty cutoff angle (2.3.8)"},
     DBL_FIELD(punish_cutoff_deg)},
    {{"subpenalty", BBC_PARAM_REAL, 0, 1e6, 5, F1, "plane", "",
      "penalty factor for subcell densities"},
     DBL_FIELD(sub_penalty)},
    {{"supergreedy", BBC_PARAM_BOOL, 0, 1, 0, F1, "plane", "", "supergreedy select (2.3.6)"},
     INT_FIELD(super_greedy)},
    {{"backface", BBC_PARAM_BOOL, 0, 1, 0, F3, "billboard", "", "backface culling when texturing"},
     INT_FIELD(backface)},
    {{"nm", BBC_PARAM_BOOL, 0, 1, 1, F3, "billboard", "",
      "normal maps (2.3.1): the surface's normal per texel, so engines light the cloud "
      "(thesis default 0)"},
     INT_FIELD(normal_maps)},
    {{"pointsize", BBC_PARAM_REAL, 0, 1e6, 3.5, F3, "billboard", "px",
      "point size for rendering point clouds"},
     DBL_FIELD(point_size)},
    {{"pointsmooth", BBC_PARAM_BOOL, 0, 1, 1, F3, "billboard", "", "smooth (round) points"},
     INT_FIELD(point_smooth)},
    {{"pointskip", BBC_PARAM_INT, 0, 1e9, 0, F3, "billboard", "points",
      "skip planes with fewer than n points"},
     INT_FIELD(point_skip)},
    {{"pointnormals", BBC_PARAM_BOOL, 0, 1, 1, 0, "extension", "",
      "point clouds: a point counts for a plane as its normal (from the file, else from its "
      "neighbours) meets it, as a triangle by its projected area; 0 = every point counts 1 "
      "(thesis 2.4.3)"},
     INT_FIELD(point_normals)},
    {{"pointsample", BBC_PARAM_INT, 0, 1e9, 16384, 0, "extension", "points",
      "point clouds of more than 4n points: planes chosen on a sample of about n points "
      "(1 in k), every point then given to the first plane it is valid for, else to planes "
      "found for the few left (every point within epsilon); 0 = every point in steps 1 and 2"},
     INT_FIELD(point_sample)},
    {{"facesample", BBC_PARAM_INT, 0, 1e9, 16384, 0, "extension", "faces",
      "meshes whose part has more than 4n faces (a triangle, or two coplanar ones): planes "
      "chosen on a sample of about n faces (1 in k), every face then given to the first plane "
      "it is valid for, else to planes found for the few left (every face within epsilon); "
      "0 = every face in steps 1 and 2"},
     INT_FIELD(face_sample)},
    {{"polyskip", BBC_PARAM_REAL, 0, 99, 0, F3, "billboard", "%",
      "skip planes whose coverage is below n% of the largest plane's (2.3.5)"},
     DBL_FIELD(poly_skip_pct)},
    {{"prelight", BBC_PARAM_BOOL, 0, 1, 0, F3, "billboard", "",
      "lighting while generating textures: a fixed light baked into the colours (thesis "
      "default 1; 0 = the albedo, for engines that light the cloud)"},
     INT_FIELD(prelight)},
    {{"pure", BBC_PARAM_INT, 0, 2, 0, F3, "billboard", "",
      "1 = render only the faces a plane simplifies into its texture (2.2.5); 2 = every face "
      "crossing the slab, its coverage split between the slabs it crosses (quality 2, dither)"},
     INT_FIELD(pure)},
    {{"quality", BBC_PARAM_INT, 0, 3, 2, F3, "billboard", "",
      "texture quality: 0 fast, 2 supersampling + squashing, 3 supersampling only (1 = 0; "
      "thesis default 0)"},
     INT_FIELD(quality)},
    {{"texres", BBC_PARAM_POW2, 4, 16384, 256, F3, "billboard", "texels",
      "maximum texture resolution, a power of two"},
     INT_FIELD(texres)},
    {{"format", BBC_PARAM_INT, 0, 1, 0, 0, "output", "",
      "VRML output: 0 VRML2.0/Open Inventor mix, 1 pure VRML97"},
     INT_FIELD(format)},
    {{"upaxis", BBC_PARAM_INT, 0, 2, 1, 0, "extension", "",
      "the model's up axis: 0 = x, 1 = y, 2 = z (also x, y, z)"},
     INT_FIELD(up_axis)},
    {{"threads", BBC_PARAM_INT, 0, 1024, 0, F1, "extension", "",
      "worker threads, 0 = all cores (results never depend on it)"},
     INT_FIELD(threads)},
    {{"merge", BBC_PARAM_BOOL, 0, 1, 1, F1, "extension", "",
      "dissolve planes whose faces all fit other planes (after step 2)"},
     INT_FIELD(merge)},
    {{"candidates", BBC_PARAM_INT, 1, 4, 1, F1, "extension", "",
      "densest cells refined per plane; the one simplifying most area wins (1 = thesis)"},
     INT_FIELD(candidates)},
    {{"backimages", BBC_PARAM_BOOL, 0, 1, 1, F3, "extension", "",
      "1 = front and back image per billboard (two one-sided quads), 0 = front only"},
     INT_FIELD(back_images)},
    {{"unlit", BBC_PARAM_INT, 0, 2, 2, F3, "extension", "",
      "material: 0 lit, 1 unlit (KHR_materials_unlit; VRML without Material), 2 = unlit "
      "when prelight"},
     INT_FIELD(unlit)},
    {{"ambient", BBC_PARAM_BOOL, 0, 1, 1, F3, "extension", "",
      "prelight: add the ambient light OpenGL/X3D viewers add to the original (0.2 x its "
      "Ka); 0 for engines that ignore Ka"},
     INT_FIELD(viewer_ambient)},
    {{"lightelev", BBC_PARAM_REAL, -90, 90, 60, F3, "extension", "deg",
      "prelight: the light's elevation above the horizon (model frame)"},
     DBL_FIELD(light_elev_deg)},
    {{"lightazim", BBC_PARAM_REAL, -360, 360, 30, F3, "extension", "deg",
      "prelight: the light's azimuth around the up axis"},
     DBL_FIELD(light_azim_deg)},
    {{"shade", BBC_PARAM_INT, 0, 512, 0, F3, "extension", "voxels",
      "voxel shadowing (2.3.11): voxels per axis, 0 = off (40-150 suit trees)"},
     INT_FIELD(shade_voxels)},
    {{"occlusion", BBC_PARAM_INT, 0, 512, 64, F3, "extension", "voxels",
      "an occlusion map (glTF occlusionTexture) from voxel shadowing (2.3.11) with n voxels "
      "per axis: how much ambient light each texel gets inside the crown; the colour stays "
      "unshadowed and `shade` is not used (0 = none)"},
     INT_FIELD(occlusion)},
    {{"occlusionmin", BBC_PARAM_REAL, 0, 1, 0.75, F3, "extension", "",
      "the occlusion map's value for the most shadowed voxel (1 = no occlusion)"},
     DBL_FIELD(occlusion_min)},
    {{"nmbend", BBC_PARAM_REAL, 0, 10, 0, F3, "extension", "",
      "normal maps: each texel's normal plus n times the unit vector from the crown's centre "
      "(0 = the surface's own): the crown lights like a ball, brighter towards the sun "
      "(docs/lighting.md)"},
     DBL_FIELD(nm_bend)},
    {{"nmflat", BBC_PARAM_REAL, 0, 10, 0, F3, "extension", "",
      "normal maps: each texel's normal plus n times the billboard's own normal (0 = the "
      "surface's own): keeps texels from facing away from a viewer at a slant "
      "(docs/lighting.md)"},
     DBL_FIELD(nm_flat)},
    {{"nmup", BBC_PARAM_REAL, 0, 10, 0.5, F3, "extension", "",
      "normal maps: a two-sided surface shows the side of its face that turns to its "
      "billboard's viewer tilted n towards up (tan of the tilt; 0 = the viewer's): the side "
      "a viewer above the horizon sees of leaves the billboard sees edge-on (docs/lighting.md)"},
     DBL_FIELD(nm_up)},
    {{"roughmin", BBC_PARAM_REAL, 0, 1, 0, F3, "extension", "",
      "the billboards' roughness (glTF roughnessFactor) at least this, the source's mean when "
      "higher: a flat billboard mirrors a low sun where the leaves it shows scattered it "
      "(docs/lighting.md)"},
     DBL_FIELD(rough_min)},
    {{"shadeambient", BBC_PARAM_REAL, 0, 1, 0.4, F3, "extension", "",
      "voxel shadowing (shade, occlusion): brightness of the darkest voxel (ambient light)"},
     DBL_FIELD(shade_ambient)},
    {{"dither", BBC_PARAM_BOOL, 0, 1, 1, F3, "extension", "",
      "quality 2: texel opacity by error diffusion of its samples' coverage, keeping the "
      "original's density (0 = growing: opaque when >= growmin samples are)"},
     INT_FIELD(dither)},
    {{"softalpha", BBC_PARAM_BOOL, 0, 1, 1, F3, "extension", "",
      "the atlas's alpha softened next to each edge between opaque and transparent texels "
      "(opaque stays >= 128, transparent < 128), so that a viewer's bilinear alpha test keeps "
      "each texel's area, as nearest sampling does (0 = alpha 0 or 255); bbcgen: on for glTF "
      "outputs (alpha mode MASK), off for OBJ, VRML and FBX, whose readers may blend it "
      "(docs/lighting.md)"},
     INT_FIELD(soft_alpha)},
    {{"limbs", BBC_PARAM_INT, 0, 100000, 512, 0, "extension", "triangles",
      "the trunk part (stem and limbs) kept as a mesh of at most n triangles inside the "
      "cloud instead of billboards, when there is a foliage part; its branches too thin "
      "for 2n go on billboards (0 = off)"},
     INT_FIELD(limbs)},
    {{"stem", BBC_PARAM_INT, 0, 8, 3, F3, "extension", "planes",
      "billboards through the trunk part's axis, 180/n degrees apart, each showing the whole "
      "stem, so it holds from every side (0 = off)"},
     INT_FIELD(stem)},
    {{"refine", BBC_PARAM_INT, 0, 1024, 16, F3, "extension", "views",
      "quality 2: texels whose opacity adds more false than true coverage of the original, "
      "over this many views, are cleared, and the reverse (0 = off)"},
     INT_FIELD(refine)},
    {{"refinesize", BBC_PARAM_INT, 16, 4096, 256, F3, "extension", "pixels",
      "refine: the size of the original's renders the alpha is judged against, the screen size "
      "the cloud is made for (a --lod-pixels chain: each level its own, at most 256)"},
     INT_FIELD(refine_size)},
    {{"growmin", BBC_PARAM_INT, 1, 16, 1, F3, "extension", "samples",
      "quality 2: opaque texel when >= n of its samples are (1 = thesis 2.3.9)"},
     INT_FIELD(grow_min)},
    {{"samples", BBC_PARAM_INT, 0, 4, 0, F3, "extension", "samples",
      "quality 2: samples per texel side; 0 = 2 from texres 128 up (4 a texel, each colour "
      "the mean of 4 texture points, about 1/3 of the bake's time), else 4 (16 a texel)"},
     INT_FIELD(samples)},
    {{"maxplanes", BBC_PARAM_INT, 0, 100000, 32, F1, "extension", "planes",
      "at most n planes: epsilon grows until steps 1-2 give no more, then narrows back "
      "toward n (0 = off, as the thesis); a sampled model's leftovers' planes come on top"},
     INT_FIELD(max_planes)},
    {{"minplanes", BBC_PARAM_INT, 0, 100000, 24, F1, "extension", "planes",
      "fewer planes: epsilon shrinks (to 1/5 at most) while within maxplanes (0 = off)"},
     INT_FIELD(min_planes)},
    {{"atlasmax", BBC_PARAM_INT, 0, 16384, 1024, F3, "extension", "texels",
      "atlas side: texres becomes the largest that fits one such atlas (0 = texres as set; "
      "at least 64)"},
     INT_FIELD(atlas_max)},
    {{"dds", BBC_PARAM_BOOL, 0, 1, 1, 0, "extension", "",
      "VRML output: the atlas also as DDS with binary-alpha mip levels that keep its coverage, "
      "named first in each url (readers without DDS take the PNG)"},
     INT_FIELD(dds)},
    {{"outline", BBC_PARAM_INT, -1, 10, -1, F3, "extension", "corners",
      "each billboard's outline: the convex hull of its opaque texels (grown by a texel), cut "
      "to at most n corners (3-10), so that a GPU shades fewer empty fragments; 0 = the "
      "rectangle clipped to its faces' bounds (the thesis); -1 = 8 for a --lod-pixels level "
      "of 384 px or more, else 0 (smaller trees shade more fragments with the extra corners)"},
     INT_FIELD(outline)},
    {{"maxtris", BBC_PARAM_INT, 0, 10000000, 0, F3, "extension", "triangles",
      "the outlines get fewer corners so that the cloud's triangles stay within n, quads at "
      "least (0 = off; a --lod-pixels level of P pixels: max(32, P^2/64))"},
     INT_FIELD(max_tris)},
};

#define ROW_COUNT (sizeof k_rows / sizeof k_rows[0])

void bbc_params_thesis(bbc_params *p) {
  assert(p);
  bbc_params_default(p);
  p->clustering = 2;
  p->epsilon_pct = 5;
  p->quality = 0;
  p->max_planes = 0;
  p->min_planes = 0;
  p->atlas_max = 0;
  p->dither = 0; /* quality 2 grows (2.3.9) */
  p->refine = 0;
  p->stem = 0;
  p->limbs = 0;
  p->point_normals = 0;
  p->point_sample = 0; /* every point, as the thesis */
  p->face_sample = 0;  /* every face, as the thesis */
  p->prelight = 1;     /* the thesis bakes its light (2.1.9) */
  p->normal_maps = 0;
  p->occlusion = 0;
  p->outline = 0; /* the thesis's rectangles */
}

int bbc_params_stale_step(const bbc_params *a, const bbc_params *b, const char **which) {
  assert(a && b);
  int first = 0;
  if (which) *which = NULL;
  for (size_t i = 0; i < ROW_COUNT; i++) {
    const param_row *r = &k_rows[i];
    const char *pa = (const char *)a + r->offset, *pb = (const char *)b + r->offset;
    if (!memcmp(pa, pb, r->is_double ? sizeof(double) : sizeof(int))) continue;
    /* results never depend on these: worker threads, the debug views, the
     * VRML dialect the cloud is written in and whether a DDS goes with it */
    const char *name = r->info.name;
    if (!strcmp(name, "threads") || !strcmp(name, "debug") || !strcmp(name, "format") ||
        !strcmp(name, "dds"))
      continue;
    int step = r->info.flags & BBC_PARAM_STEP3_ONLY    ? 3
               : r->info.flags & BBC_PARAM_KEEPS_STEP1 ? 2
                                                       : 1;
    if (!first || step < first) {
      first = step;
      if (which) *which = name;
    }
  }
  return first;
}

size_t bbc_param_count(void) {
  return ROW_COUNT;
}

const bbc_param_info *bbc_param_at(size_t i) {
  assert(i < bbc_param_count());
  return i < ROW_COUNT ? &k_rows[i].info : NULL;
}

static const param_row *find_row(const char *name) {
  for (size_t i = 0; i < ROW_COUNT; i++)
    if (!strcasecmp(k_rows[i].info.name, name)) return &k_rows[i];
  return NULL;
}

const bbc_param_info *bbc_param_find(const char *name) {
  const param_row *r = name ? find_row(name) : NULL;
  return r ? &r->info : NULL;
}

static const param_row *row_of(const bbc_param_info *info) {
  return (const param_row *)(const void *)info; /* info is the first member */
}

static void store(bbc_params *p, const param_row *row, double v) {
  char *base = (char *)p + row->offset;
  if (row->is_double)
    memcpy(base, &v, sizeof v);
  else {
    int iv = (int)v;
    memcpy(base, &iv, sizeof iv);
  }
}

double bbc_params_get(const bbc_params *p, const bbc_param_info *info) {
  assert(p && info);
  const param_row *row = row_of(info);
  const char *base = (const char *)p + row->offset;
  if (row->is_double) {
    double v;
    memcpy(&v, base, sizeof v);
    return v;
  }
  int iv;
  memcpy(&iv, base, sizeof iv);
  return iv;
}

void bbc_params_default(bbc_params *p) {
  assert(p);
  memset(p, 0, sizeof *p);
  for (size_t i = 0; i < ROW_COUNT; i++) store(p, &k_rows[i], k_rows[i].info.default_value);
}

static void describe_range(const bbc_param_info *in, char *buf, size_t n) {
  switch (in->type) {
  case BBC_PARAM_BOOL:
    snprintf(buf, n, "0 or 1 (also off/on, false/true, no/yes)");
    break;
  case BBC_PARAM_INT:
    if (!strcmp(in->name, "upaxis"))
      snprintf(buf, n, "x, y or z (or 0, 1, 2)");
    else if (in->max >= 1e9)
      snprintf(buf, n, "an integer >= %g", in->min);
    else
      snprintf(buf, n, "an integer from %g to %g", in->min, in->max);
    break;
  case BBC_PARAM_REAL:
    if (in->max >= 1e6)
      snprintf(buf, n, "a number >= %g", in->min);
    else
      snprintf(buf, n, "a number from %g to %g", in->min, in->max);
    break;
  case BBC_PARAM_POW2:
    snprintf(buf, n, "a power of two from %g to %g", in->min, in->max);
    break;
  }
}

bbc_result bbc_params_set(bbc_params *p, const char *name, const char *text, bbc_error *err) {
  assert(p && name && text);
  const param_row *row = name ? find_row(name) : NULL;
  if (!row)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "unknown parameter '%s' (bbcgen --help lists them)", name ? name : "");
  const bbc_param_info *in = &row->info;
  char range[96];
  describe_range(in, range, sizeof range);
  if (!text || !*text)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "parameter %s needs a value: %s", in->name,
                     range);
  double v;
  if (in->type == BBC_PARAM_BOOL &&
      (!strcasecmp(text, "on") || !strcasecmp(text, "true") || !strcasecmp(text, "yes")))
    v = 1;
  else if (in->type == BBC_PARAM_BOOL &&
           (!strcasecmp(text, "off") || !strcasecmp(text, "false") || !strcasecmp(text, "no")))
    v = 0;
  else if (!strcmp(in->name, "upaxis") && strlen(text) == 1 && strchr("xyzXYZ", text[0]))
    v = tolower((unsigned char)text[0]) - 'x';
  else {
    char *end = NULL;
    errno = 0;
    v = strtod(text, &end);
    while (end && isspace((unsigned char)*end)) end++;
    if (end == text || !end || *end || errno == ERANGE || !isfinite(v))
      return bbc__fail(
          err, BBC_ERROR_INVALID_ARGUMENT, "parameter %s: '%s' is not %s; allowed: %s", in->name,
          text, in->type == BBC_PARAM_BOOL || !strcmp(in->name, "upaxis") ? "accepted" : "a number",
          range);
  }
  if (v < in->min || v > in->max)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE, "parameter %s = %s is out of range; allowed: %s",
                     in->name, text, range);
  if (in->type != BBC_PARAM_REAL && v != floor(v))
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                     "parameter %s = %s must be a whole number; allowed: %s", in->name, text,
                     range);
  if (in->type == BBC_PARAM_POW2) {
    long iv = (long)v;
    if (iv & (iv - 1))
      return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                       "parameter %s = %s is not a power of two; allowed: %s", in->name, text,
                       range);
  }
  /* The dual grid has 360/res x 180/res cells: res must divide 180 (App. A). */
  if (!strcmp(in->name, "res") && 180 % (int)v != 0)
    return bbc__fail(err, BBC_ERROR_OUT_OF_RANGE,
                     "parameter res = %s must divide 180 (1, 2, 3, 4, 5, 6, 9, 10, 12, 15, 18, "
                     "20, 30, 36, 45, 60, 90, 180)",
                     text);
  store(p, row, v);
  return BBC_OK;
}

bbc_result bbc_params_set_assignment(bbc_params *p, const char *assignment, bbc_error *err) {
  assert(p && assignment);
  const char *eq = assignment ? strchr(assignment, '=') : NULL;
  if (!eq || eq == assignment)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "expected name=value, got '%s'",
                     assignment ? assignment : "");
  char name[64];
  size_t n = (size_t)(eq - assignment);
  if (n >= sizeof name)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "unknown parameter '%.*s'", (int)n,
                     assignment);
  memcpy(name, assignment, n);
  name[n] = 0;
  return bbc_params_set(p, name, eq + 1, err);
}

int bbc_params_is_unlit(const bbc_params *p) {
  assert(p);
  return p->unlit == BBC_UNLIT_WHEN_PRELIT ? p->prelight != 0 : p->unlit == BBC_UNLIT_YES;
}

void bbc_params_copy(bbc_params *dst, const bbc_params *src, const bbc_param_info *info) {
  assert(dst && src && info);
  const param_row *r = row_of(info);
  memcpy((char *)dst + r->offset, (const char *)src + r->offset,
         r->is_double ? sizeof(double) : sizeof(int));
}

void bbc_params_get_light_direction(const bbc_params *prm, double light[3]) {
  assert(prm && light);
  int up = prm->up_axis >= 0 && prm->up_axis <= 2 ? prm->up_axis : 1;
  int a = (up + 1) % 3, b = (up + 2) % 3; /* (a, b, up) is right-handed */
  double el = prm->light_elev_deg * M_PI / 180, az = prm->light_azim_deg * M_PI / 180;
  light[up] = sin(el);
  light[a] = cos(el) * cos(az);
  light[b] = cos(el) * sin(az);
}
