/* cmd_eval.c — `bbcgen eval ORIGINAL OTHER [--views N] [--size S] [--json OUT]
 * [--png SHEET] [--lit] [--sun AZ,EL|sweep]`: how close OTHER (a cloud, a
 * baseline) looks to ORIGINAL, through the library's bbc_eval; with --sun,
 * both lit alike by an engine's sun and ambient light. */
#include "cli.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The metrics as JSON: the summary at the top level, then per view. */
char *eval_json_text(const bbc_eval_result *r, const bbc_eval_options *o, const char *a,
                     const char *b) {
  cJSON *j = cJSON_CreateObject();
  if (a) cJSON_AddStringToObject(j, "original", a);
  if (b) cJSON_AddStringToObject(j, "other", b);
  cJSON_AddNumberToObject(j, "iou_mean", r->iou_mean);
  /* Side-view figures are null when no view is a side view. */
#define SIDE(name, v)                                                                              \
  (r->side_count ? cJSON_AddNumberToObject(j, name, v) : cJSON_AddNullToObject(j, name))
  SIDE("iou_side_mean", r->iou_side_mean);
  cJSON_AddNumberToObject(j, "iou_min", r->iou_min);
  SIDE("iou_side_min", r->iou_side_min);
  cJSON_AddNumberToObject(j, "recall_mean", r->recall_mean);
  SIDE("recall_side_mean", r->recall_side_mean);
  cJSON_AddNumberToObject(j, "false_coverage_mean", r->false_mean);
  cJSON_AddNumberToObject(j, "psnr_mean", r->psnr_mean);
  SIDE("psnr_side_mean", r->psnr_side_mean);
  cJSON_AddNumberToObject(j, "coverage_ratio_mean", r->coverage_ratio_mean);
  SIDE("coverage_ratio_side_mean", r->coverage_ratio_side_mean);
  cJSON_AddNumberToObject(j, "block_iou_mean", r->block_iou_mean);
  SIDE("block_iou_side_mean", r->block_iou_side_mean);
#undef SIDE
  cJSON_AddNumberToObject(j, "psnr_min", r->psnr_min);
  cJSON_AddNumberToObject(j, "mae_mean", r->mae_mean);
  cJSON_AddItemToObject(j, "brightness_ratio", cJSON_CreateDoubleArray(r->brightness_ratio, 3));
  cJSON_AddNumberToObject(j, "luminance_ratio", r->luminance_ratio);
  cJSON_AddNumberToObject(j, "block_luminance_error_mean", r->block_luminance_error_mean);
  cJSON_AddNumberToObject(j, "views", (double)r->view_count);
  cJSON_AddNumberToObject(j, "side_views", (double)r->side_count);
  cJSON_AddNumberToObject(j, "size", o->size);
  cJSON_AddBoolToObject(j, "lit", o->lighting);
  cJSON_AddBoolToObject(j, "upper", o->upper);
  cJSON *vs = cJSON_AddArrayToObject(j, "per_view");
  for (size_t k = 0; k < r->view_count; k++) {
    const bbc_eval_view *v = &r->views[k];
    cJSON *q = cJSON_CreateObject();
    cJSON_AddItemToObject(q, "direction", cJSON_CreateDoubleArray(v->direction, 3));
    cJSON_AddNumberToObject(q, "elevation_deg", v->elevation_deg);
    cJSON_AddBoolToObject(q, "side", v->side);
    cJSON_AddNumberToObject(q, "iou", v->iou);
    cJSON_AddNumberToObject(q, "recall", v->recall);
    cJSON_AddNumberToObject(q, "false_coverage", v->false_coverage);
    cJSON_AddNumberToObject(q, "psnr", v->psnr);
    cJSON_AddNumberToObject(q, "mae", v->mae);
    cJSON_AddNumberToObject(q, "coverage_ratio", v->coverage_ratio);
    cJSON_AddNumberToObject(q, "block_iou", v->block_iou);
    cJSON_AddNumberToObject(q, "block_luminance_error", v->block_luminance_error);
    cJSON_AddNumberToObject(q, "original_px", (double)v->original_px);
    cJSON_AddNumberToObject(q, "other_px", (double)v->other_px);
    cJSON_AddItemToArray(vs, q);
  }
  char *text = cJSON_Print(j);
  cJSON_Delete(j);
  return text;
}

/* What `bbcgen eval` is asked for. */
typedef struct eval_args {
  const char *paths[2], *json, *png;
  long long views, size;
  int lit; /* -1: lit when OTHER is prelit (all its materials unlit) */
  double side;
  int suns;           /* --sun: 0 none, 1 one (sun_deg), 16 the sweep */
  double sun_deg[2];  /* azimuth, elevation */
  double sun_ambient; /* 0 = the library's 0.4 */
  int upper;          /* --upper: views over the upper hemisphere only */
} eval_args;

/* The sweep: 8 azimuths x 2 elevations. */
#define SWEEP_SUNS 16
static void sweep_sun(int k, double deg[2]) {
  deg[0] = 45.0 * (k % 8);
  deg[1] = k < 8 ? 15.0 : 50.0;
}

/* "AZ,EL" in degrees or "sweep". */
static int parse_sun(const char *v, eval_args *ea) {
  if (!strcmp(v, "sweep")) {
    ea->suns = SWEEP_SUNS;
    return 0;
  }
  char *end;
  double az = strtod(v, &end), el = 0;
  int ok = end != v && *end == ',';
  if (ok) {
    const char *p = end + 1;
    el = strtod(p, &end);
    ok = end != p && !*end && az >= -360 && az <= 360 && el >= -90 && el <= 90;
  }
  if (!ok) {
    cli_error("--sun: 'AZ,EL' (degrees: azimuth around the up axis, 0 = +z for y up, and "
              "elevation -90..90) or 'sweep', not '%s'",
              v);
    return -1;
  }
  ea->suns = 1;
  ea->sun_deg[0] = az;
  ea->sun_deg[1] = el;
  return 0;
}

/* The command line into `ea`: -1 to go on, else an exit code (said). */
static int parse_eval_args(cli *c, int argc, char **argv, eval_args *ea) {
  int np = 0;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *v;
    if (!strcmp(argv[i], "--views")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((ea->views = cli_parse_count(argv[i - 1], v, 100000)) < 1) {
        if (ea->views == 0) cli_error("--views: at least 1");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--size")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((ea->size = cli_parse_count(argv[i - 1], v, 8192)) < 8) {
        if (ea->size >= 0) cli_error("--size: 8 to 8192 pixels");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--json")) {
      if (!(ea->json = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--png")) {
      if (!(ea->png = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--side-elevation")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      char *end;
      ea->side = strtod(v, &end);
      if (*end || !(ea->side >= 0 && ea->side <= 90)) {
        cli_error("--side-elevation: degrees from 0 to 90, not '%s'", v);
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--sun")) {
      if (!(v = cli_option_value(argc, argv, &i)) || parse_sun(v, ea) < 0) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--sun-ambient")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      char *end;
      ea->sun_ambient = strtod(v, &end);
      if (*end || !(ea->sun_ambient > 0 && ea->sun_ambient <= 10)) {
        cli_error("--sun-ambient: the ambient light against the sun's 1, in (0, 10], not '%s'", v);
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--upper")) {
      ea->upper = 1;
    } else if (!strcmp(argv[i], "--lit")) {
      ea->lit = 1;
    } else if (!strcmp(argv[i], "--no-lit")) {
      ea->lit = 0;
    } else if (argv[i][0] != '-' && np < 2) {
      ea->paths[np++] = argv[i];
    } else {
      static const char *const own[] = {
          "--views",       "--size",           "--json",   "--png",   "--lit", "--sun",
          "--sun-ambient", "--side-elevation", "--no-lit", "--upper", NULL};
      return cli_unknown_option("eval", argv[i], own);
    }
  }
  if (np != 2) {
    cli_error(
        "eval: usage: bbcgen eval ORIGINAL OTHER [--views N] [--size PX] [--json OUT] "
        "[--png SHEET] [--lit|--no-lit] [--sun AZ,EL|sweep] [--side-elevation DEG] [--upper]");
    return EXIT_USAGE;
  }
  return -1;
}

/* The evaluation's options from the arguments and the parameters. */
static void eval_options(const cli *c, const eval_args *ea, const bbc_mesh *other,
                         bbc_eval_options *o) {
  bbc_eval_options_default(o);
  o->views = (int)ea->views;
  o->upper = ea->upper;
  o->size = (int)ea->size;
  o->up = bbc_up_from_axis(c->params.up_axis);
  o->threads = c->params.threads;
  int lit = ea->lit;
  if (lit < 0) { /* a prelit cloud is meant to look like the lit original */
    int all_unlit = other->material_count > 0;
    for (size_t i = 0; i < other->material_count; i++) all_unlit &= other->materials[i].unlit != 0;
    lit = all_unlit;
  }
  o->lighting = lit;
  o->no_ambient = !c->params.viewer_ambient;
  o->point_size = c->params.point_size;
  o->point_square = !c->params.point_smooth;
  o->side_elevation_deg = ea->side > 0 ? ea->side : -1; /* -1: the horizon only */
  bbc_params_get_light_direction(&c->params, o->light);
  if (ea->suns) {
    o->lighting = 1;
    o->sun = 1;
    o->sun_ambient = ea->sun_ambient;
  }
}

/* The two summary lines; the side-view figures "n/a" when no view is one. */
static void print_eval(const bbc_eval_result *r, const bbc_eval_options *o, double t0) {
  char side_iou[32] = "n/a", side_psnr[32] = "n/a", side_cov[32] = "n/a", side_block[32] = "n/a";
  if (r->side_count) {
    snprintf(side_iou, sizeof side_iou, "%.4f", r->iou_side_mean);
    snprintf(side_psnr, sizeof side_psnr, "%.2f", r->psnr_side_mean);
    snprintf(side_cov, sizeof side_cov, "%.3f", r->coverage_ratio_side_mean);
    snprintf(side_block, sizeof side_block, "%.4f", r->block_iou_side_mean);
  }
  printf("iou %.4f (side %s, min %.4f)  recall %.4f  false coverage %.4f  psnr %.2f dB "
         "(side %s)  mae %.2f  brightness %.3f %.3f %.3f  [%zu views, %zu side, %d px, %s, "
         "%.2f s]\n",
         r->iou_mean, side_iou, r->iou_min, r->recall_mean, r->false_mean, r->psnr_mean, side_psnr,
         r->mae_mean, r->brightness_ratio[0], r->brightness_ratio[1], r->brightness_ratio[2],
         r->view_count, r->side_count, o->size, o->lighting ? "lit" : "unlit", cli_now() - t0);
  printf("density: coverage ratio %.3f (side %s)  block iou 1/8 %.4f (side %s)\n",
         r->coverage_ratio_mean, side_cov, r->block_iou_mean, side_block);
}

/* --sun: one bbc_eval per sun, a line each, the JSON with every sun's and
 * the range of their luminance ratios. */
static int eval_suns(const cli *c, const eval_args *ea, const bbc_mesh m[2], bbc_eval_options *o,
                     bbc_image *sheet) {
  int n = ea->suns, rc = EXIT_OK;
  double lo = 1e300, hi = -1e300, t0 = cli_now();
  cJSON *j = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(j, "suns");
  cJSON_AddStringToObject(j, "original", ea->paths[0]);
  cJSON_AddStringToObject(j, "other", ea->paths[1]);
  cJSON_AddNumberToObject(j, "ambient", ea->sun_ambient > 0 ? ea->sun_ambient : 0.4);
  cJSON_AddBoolToObject(j, "upper", o->upper);
  printf("sun (az, el)  luminance  r      g      b      block lum err  iou     block iou\n");
  for (int k = 0; k < n && rc == EXIT_OK; k++) {
    double deg[2] = {ea->sun_deg[0], ea->sun_deg[1]};
    if (n > 1) sweep_sun(k, deg);
    /* The sun as the prelight's light is set: azimuth around the up axis
     * (0 = +z for y up), elevation above the horizon. */
    bbc_params sun = c->params;
    sun.light_azim_deg = deg[0];
    sun.light_elev_deg = deg[1];
    bbc_params_get_light_direction(&sun, o->light);
    o->sheet = k == 0 ? sheet : NULL;
    bbc_eval_result r;
    bbc_error err;
    if (bbc_eval(&m[0], o->impostor ? NULL : &m[1], o, &r, &err) != BBC_OK) {
      rc = cli_fail(&err, 0);
      break;
    }
    printf("%5.0f %5.0f    %.3f      %.3f  %.3f  %.3f  %.3f          %.4f  %.4f\n", deg[0], deg[1],
           r.luminance_ratio, r.brightness_ratio[0], r.brightness_ratio[1], r.brightness_ratio[2],
           r.block_luminance_error_mean, r.iou_mean, r.block_iou_mean);
    lo = fmin(lo, r.luminance_ratio);
    hi = fmax(hi, r.luminance_ratio);
    cJSON *q = cJSON_CreateObject();
    cJSON_AddItemToObject(q, "sun_deg", cJSON_CreateDoubleArray(deg, 2));
    cJSON_AddItemToObject(q, "light", cJSON_CreateDoubleArray(o->light, 3));
    cJSON_AddNumberToObject(q, "luminance_ratio", r.luminance_ratio);
    cJSON_AddItemToObject(q, "brightness_ratio", cJSON_CreateDoubleArray(r.brightness_ratio, 3));
    cJSON_AddNumberToObject(q, "block_luminance_error", r.block_luminance_error_mean);
    cJSON_AddNumberToObject(q, "iou_mean", r.iou_mean);
    cJSON_AddNumberToObject(q, "block_iou_mean", r.block_iou_mean);
    cJSON_AddItemToArray(arr, q);
    bbc_eval_result_free(&r);
  }
  if (rc == EXIT_OK) {
    printf("luminance ratio over %d sun%s: %.3f .. %.3f  [%d views, %d px, ambient %.2g, %.2f s]\n",
           n, n > 1 ? "s" : "", lo, hi, o->views, o->size,
           o->sun_ambient > 0 ? o->sun_ambient : 0.4, cli_now() - t0);
    cJSON_AddNumberToObject(j, "luminance_ratio_min", lo);
    cJSON_AddNumberToObject(j, "luminance_ratio_max", hi);
    char *text = ea->json ? cJSON_Print(j) : NULL;
    bbc_error err;
    if (ea->json && (!text || bbc_write_file_atomic(ea->json, text, strlen(text), &err) != BBC_OK))
      rc = text ? cli_fail(&err, 1) : EXIT_RESOURCES;
    cJSON_free(text);
  }
  cJSON_Delete(j);
  return rc;
}

/* ---- chains: each level alone at its own screen size ----------------------- */

/* A whole file (NULL when it cannot be read, or beyond 1 GiB). */
static unsigned char *read_whole(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  unsigned char *d = NULL;
  long len = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
  if (len > 0 && len < (1L << 30) && fseek(f, 0, SEEK_SET) == 0 && (d = malloc((size_t)len)) &&
      fread(d, 1, (size_t)len, f) != (size_t)len) {
    free(d);
    d = NULL;
  }
  fclose(f);
  *n = d ? (size_t)len : 0;
  return d;
}

/* A glTF chain's levels (nodes "<model>_LOD<k>") and each one's screen size
 * from its extras ("screen_px", written for --lod-pixels chains; 0 when
 * absent). Returns the number of levels, 0 when OTHER is not a chain. */
static size_t chain_levels(const char *path, double *px, size_t max) {
  size_t n = 0, count = 0;
  unsigned char *d = read_whole(path, &n);
  if (!d) return 0;
  const char *json = (const char *)d;
  size_t jl = n;
  if (n >= 20 && !memcmp(d, "glTF", 4)) {
    jl = (size_t)d[12] | (size_t)d[13] << 8 | (size_t)d[14] << 16 | (size_t)d[15] << 24;
    json = (const char *)d + 20;
    if (jl > n - 20) jl = 0;
  }
  cJSON *j = cJSON_ParseWithLength(json, jl);
  free(d);
  const cJSON *nodes = cJSON_GetObjectItemCaseSensitive(j, "nodes"), *node;
  cJSON_ArrayForEach(node, nodes) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(node, "name");
    const char *lod = cJSON_IsString(name) ? strstr(name->valuestring, "_LOD") : NULL;
    if (!lod) continue;
    char *end;
    long k = strtol(lod + 4, &end, 10);
    if (end == lod + 4 || *end || k < 0 || (size_t)k >= max) continue;
    const cJSON *sp = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(node, "extras"), "screen_px");
    px[k] = cJSON_IsNumber(sp) ? sp->valuedouble : 0;
    if ((size_t)k + 1 > count) count = (size_t)k + 1;
  }
  cJSON_Delete(j);
  return count > 1 ? count : 0;
}

/* The sheets of the levels one under the other. */
static bbc_result stack_sheets(const bbc_image *rows, size_t n, bbc_image *out) {
  int w = 0, h = 0;
  for (size_t k = 0; k < n; k++) {
    if (rows[k].width > w) w = rows[k].width;
    h += rows[k].height;
  }
  bbc_result r = bbc_image_alloc(out, w ? w : 1, h ? h : 1);
  if (r != BBC_OK) return r;
  memset(out->rgba, 255, (size_t)out->width * out->height * 4);
  int y = 0;
  for (size_t k = 0; k < n; k++) {
    for (int row = 0; row < rows[k].height; row++)
      memcpy(out->rgba + ((size_t)(y + row) * out->width) * 4,
             rows[k].rgba + (size_t)row * rows[k].width * 4, (size_t)rows[k].width * 4);
    y += rows[k].height;
  }
  return BBC_OK;
}

/* `bbcgen eval ORIGINAL CHAIN`: each level loaded alone and judged at its
 * screen size (the eval's image size; --size where the chain has none), a
 * line per level, a "levels" array in the JSON, a row per level in the
 * sheet. */
static int eval_chain(const cli *c, const eval_args *ea, const bbc_mesh *orig, const double *px,
                      size_t count) {
  bbc_load_options lo;
  cli_load_options(c, &lo);
  cJSON *j = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(j, "levels");
  cJSON_AddStringToObject(j, "original", ea->paths[0]);
  cJSON_AddStringToObject(j, "other", ea->paths[1]);
  bbc_image sheets[16];
  memset(sheets, 0, sizeof sheets);
  int rc = EXIT_OK;
  for (size_t k = 0; k < count && rc == EXIT_OK; k++) {
    bbc_error err;
    bbc_mesh m;
    lo.lod_node = (int)k + 1;
    if (bbc_mesh_load(ea->paths[1], &lo, &m, &err) != BBC_OK) {
      rc = cli_fail(&err, 0);
      break;
    }
    eval_args one = *ea;
    if (px[k] > 0) one.size = (long long)(px[k] < 16 ? 16 : px[k] > 8192 ? 8192 : px[k]);
    bbc_eval_options o;
    eval_options(c, &one, &m, &o);
    if (ea->png && k < 16) o.sheet = &sheets[k];
    bbc_eval_result r;
    double t0 = cli_now();
    if (bbc_eval(orig, &m, &o, &r, &err) != BBC_OK) {
      rc = cli_fail(&err, 0);
      bbc_mesh_free(&m);
      break;
    }
    printf("level %zu (%s%lld px, %zu triangles):\n", k,
           px[k] > 0 ? "" : "no screen size: ", one.size, m.triangle_count);
    print_eval(&r, &o, t0);
    char *text = eval_json_text(&r, &o, NULL, NULL);
    cJSON *q = text ? cJSON_Parse(text) : NULL;
    cJSON_free(text);
    if (q) {
      cJSON_DeleteItemFromObjectCaseSensitive(q, "per_view");
      cJSON_AddNumberToObject(q, "level", (double)k);
      cJSON_AddNumberToObject(q, "screen_px", (double)one.size);
      cJSON_AddNumberToObject(q, "triangles", (double)m.triangle_count);
      cJSON_AddItemToArray(arr, q);
    }
    bbc_eval_result_free(&r);
    bbc_mesh_free(&m);
  }
  bbc_error err;
  if (rc == EXIT_OK && ea->json) {
    char *text = cJSON_Print(j);
    if (!text || bbc_write_file_atomic(ea->json, text, strlen(text), &err) != BBC_OK)
      rc = text ? cli_fail(&err, 1) : EXIT_RESOURCES;
    cJSON_free(text);
  }
  if (rc == EXIT_OK && ea->png) {
    bbc_image all = {0, 0, NULL};
    if (stack_sheets(sheets, count < 16 ? count : 16, &all) != BBC_OK)
      rc = EXIT_RESOURCES;
    else if (bbc_image_write_png(ea->png, &all, &err) != BBC_OK)
      rc = cli_fail(&err, 1);
    bbc_image_free(&all);
  }
  for (size_t k = 0; k < 16; k++) bbc_image_free(&sheets[k]);
  cJSON_Delete(j);
  return rc;
}

int cmd_eval(cli *c, int argc, char **argv) {
  eval_args ea = {{NULL, NULL}, NULL, NULL, 64, 256, -1, 30, 0, {0, 0}, 0, 0};
  int rc = parse_eval_args(c, argc, argv, &ea);
  if (rc >= 0) return rc;
  const char *json = ea.json, *png = ea.png;
  if ((json && !cli_output_ok("--json", json)) || (png && !cli_output_ok("--png", png)))
    return EXIT_OUTPUT;
  size_t pl = png ? strlen(png) : 0;
  if (png && (pl < 4 || strcasecmp(png + pl - 4, ".png"))) {
    cli_error("eval: --png: the file must end in .png, not '%s'", png);
    return EXIT_USAGE;
  }
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_mesh m[2];
  bbc_error err;
  if (bbc_mesh_load(ea.paths[0], &lo, &m[0], &err) != BBC_OK) return cli_fail(&err, 0);
  double px[BBC_SESSION_MAX_LEVELS] = {0};
  size_t levels = ea.suns ? 0 : chain_levels(ea.paths[1], px, BBC_SESSION_MAX_LEVELS);
  if (levels) {
    rc = eval_chain(c, &ea, &m[0], px, levels);
    bbc_mesh_free(&m[0]);
    return rc;
  }
  /* An impostor (its descriptor) is drawn in place of a model. */
  size_t ol = strlen(ea.paths[1]);
  int impostor = ol >= 5 && !strcasecmp(ea.paths[1] + ol - 5, ".json");
  bbc_impostor imp;
  memset(&imp, 0, sizeof imp);
  memset(&m[1], 0, sizeof m[1]);
  if (impostor ? bbc_impostor_read(ea.paths[1], &imp, &err) != BBC_OK
               : bbc_mesh_load(ea.paths[1], &lo, &m[1], &err) != BBC_OK) {
    bbc_mesh_free(&m[0]);
    return cli_fail(&err, 0);
  }
  bbc_eval_options o;
  eval_options(c, &ea, &m[1], &o);
  if (impostor) o.impostor = &imp;
  bbc_image sheet = {0, 0, NULL};
  if (png) o.sheet = &sheet;
  bbc_eval_result r;
  double t0 = cli_now();
  rc = EXIT_OK;
  if (ea.suns) {
    rc = eval_suns(c, &ea, m, &o, png ? &sheet : NULL);
    if (rc == EXIT_OK && png && bbc_image_write_png(png, &sheet, &err) != BBC_OK)
      rc = cli_fail(&err, 1);
  } else if (bbc_eval(&m[0], impostor ? NULL : &m[1], &o, &r, &err) != BBC_OK) {
    rc = cli_fail(&err, 0);
  } else {
    print_eval(&r, &o, t0);
    if (json) {
      char *text = eval_json_text(&r, &o, ea.paths[0], ea.paths[1]);
      if (!text || bbc_write_file_atomic(json, text, strlen(text), &err) != BBC_OK)
        rc = text ? cli_fail(&err, 1) : EXIT_RESOURCES;
      cJSON_free(text);
    }
    if (rc == EXIT_OK && png && bbc_image_write_png(png, &sheet, &err) != BBC_OK)
      rc = cli_fail(&err, 1);
    bbc_eval_result_free(&r);
  }
  bbc_image_free(&sheet);
  bbc_impostor_free(&imp);
  bbc_mesh_free(&m[0]);
  bbc_mesh_free(&m[1]);
  return rc;
}
