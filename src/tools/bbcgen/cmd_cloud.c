/* cmd_cloud.c — `bbcgen MODEL -o OUT.glb|.gltf|.obj|.wrl|.fbx [options]`: the whole
 * pipeline, steps 1 to 3, with levels of detail, a report and a preview. */
#include "pipeline.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A chain's list: "5,10,15" (--lod: epsilons in percent, increasing) or
 * "512,128,32" (--lod-pixels: whole pixels, falling); -1 on error (printed). */
typedef struct lod_list {
  const char *option, *what, *example;
  double min, max;
  int falls, whole;
} lod_list;

static int parse_list(const lod_list *l, const char *text, double *v, size_t max, size_t *count) {
  *count = 0;
  for (const char *p = text; *p;) {
    char *end;
    double x = strtod(p, &end);
    if (end == p || !(x >= l->min && x <= l->max) || (l->whole && x != floor(x)) ||
        (*end && *end != ',')) {
      cli_error("%s: '%s' is not a list of %s in %g..%g, e.g. %s", l->option, text, l->what, l->min,
                l->max, l->example);
      return -1;
    }
    if (*count == max) {
      cli_error("%s: at most %zu levels", l->option, max);
      return -1;
    }
    if (*count && (l->falls ? x >= v[*count - 1] : x <= v[*count - 1])) {
      cli_error("%s: the values must %s (the finest level first): '%s'", l->option,
                l->falls ? "fall" : "increase", text);
      return -1;
    }
    v[(*count)++] = x;
    p = *end ? end + 1 : end;
  }
  if (!*count) {
    cli_error("%s needs at least one level", l->option);
    return -1;
  }
  return 0;
}

/* The chain's levels from screen sizes: level k starts where the tree is
 * px[k] pixels high. Level 0 is the single cloud the parameters make (the
 * plane and atlas budgets), at most a texel a pixel at px[0]; each further
 * level takes the epsilon used before it times (px[k-1] / px[k])^(1/8), at
 * most a texel a pixel and half the texres before it, refined at its size
 * (bbc_session_run_chain). Coverage falls as epsilon grows (few planes,
 * seen edge-on): on the Scopia palm's 32-pixel level, x1.41 a level kept
 * 0.85 of the original's side coverage, x1.19 0.89 (bench/results/lod_chain.md). */
static void levels_from_pixels(const double *px, size_t n, bbc_lod_level *lv) {
  for (size_t k = 0; k < n; k++) lv[k] = (bbc_lod_level){0, px[k], 0};
}

int cmd_cloud(cli *c, int argc, char **argv) {
  const char *path = argv[0], *out = NULL, *report = NULL, *preview = NULL;
  double eps[BBC_SESSION_MAX_LEVELS], px[BBC_SESSION_MAX_LEVELS];
  size_t lods = 0, pixels = 0;
  long long cell = 256;
  int lighting = -1; /* --lighting: -1 = by the output's format */
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    const char *v;
    if (!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) {
      if (!(out = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--report")) {
      if (!(report = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--preview")) {
      if (!(preview = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--preview-size")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if ((cell = cli_parse_count(argv[i - 1], v, 4096)) < 16) {
        if (cell >= 0) cli_error("--preview-size: at least 16 pixels");
        return EXIT_USAGE;
      }
    } else if (!strcmp(argv[i], "--lod")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      const bbc_param_info *e = bbc_param_find("epsilon");
      const lod_list l = {"--lod", "epsilons (percent)", "5,10,15", e->min, e->max, 0, 0};
      if (parse_list(&l, v, eps, BBC_SESSION_MAX_LEVELS, &lods) < 0) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--lod-pixels")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      const lod_list l = {"--lod-pixels",
                          "screen sizes in pixels (the tree's height on screen where each level "
                          "starts)",
                          "512,128,32",
                          4,
                          8192,
                          1,
                          1};
      if (parse_list(&l, v, px, BBC_SESSION_MAX_LEVELS, &pixels) < 0) return EXIT_USAGE;
    } else if (!strcmp(argv[i], "--lod-files")) {
      c->level_files = 1;
    } else if (!strcmp(argv[i], "--lighting")) {
      if (!(v = cli_option_value(argc, argv, &i))) return EXIT_USAGE;
      if (!strcmp(v, "material"))
        lighting = BBC_LIGHTING_MATERIAL;
      else if (!strcmp(v, "baked"))
        lighting = BBC_LIGHTING_BAKED;
      else {
        cli_error("--lighting: 'material' (albedo, normal and occlusion maps for engines to "
                  "light) or 'baked' (a fixed light in the colours, unlit), not '%s'",
                  v);
        return EXIT_USAGE;
      }
    } else {
      static const char *const own[] = {
          "-o",    "--output",     "--report",    "--preview",  "--preview-size",
          "--lod", "--lod-pixels", "--lod-files", "--lighting", NULL};
      return cli_unknown_option(NULL, argv[i], own);
    }
  }
  if (!out) {
    cli_error("usage: bbcgen MODEL -o OUT.glb|OUT.gltf|OUT.obj|OUT.wrl|OUT.fbx [options]");
    return EXIT_USAGE;
  }
  const char *ext = strrchr(out, '.');
  if (!ext || (strcasecmp(ext, ".glb") && strcasecmp(ext, ".gltf") && strcasecmp(ext, ".obj") &&
               strcasecmp(ext, ".wrl") && strcasecmp(ext, ".fbx"))) {
    cli_error("the output must end in .glb, .gltf, .obj, .wrl or .fbx, not '%s'", out);
    return EXIT_USAGE;
  }
  size_t pn = preview ? strlen(preview) : 0, rn = report ? strlen(report) : 0;
  if (preview && (pn < 4 || strcasecmp(preview + pn - 4, ".png"))) {
    cli_error("--preview: the file must end in .png, not '%s'", preview);
    return EXIT_USAGE;
  }
  if (report && (rn < 5 || strcasecmp(report + rn - 5, ".json"))) {
    cli_error("--report: the file must end in .json, not '%s'", report);
    return EXIT_USAGE;
  }
  if (!cli_output_ok("-o", out) || (preview && !cli_output_ok("--preview", preview)) ||
      (report && !cli_output_ok("--report", report)))
    return EXIT_OUTPUT;
  if (lods && pixels) {
    cli_error("--lod (epsilons) and --lod-pixels (screen sizes) choose the levels two ways: "
              "give one");
    return EXIT_USAGE;
  }
  /* --lod-files alone: the default chain, for 512, 128 and 32 pixels */
  if (c->level_files && !lods && !pixels) {
    const double dflt[3] = {512, 128, 32};
    memcpy(px, dflt, sizeof dflt);
    pixels = 3;
  }
  bbc_lod_level levels[BBC_SESSION_MAX_LEVELS];
  for (size_t k = 0; k < lods; k++) levels[k] = (bbc_lod_level){eps[k], 0, 0};
  if (pixels) levels_from_pixels(px, pixels, levels);
  size_t count = lods ? lods : pixels;
  /* A LOD chain of epsilons asks for them: neither minplanes nor maxplanes
   * moves them (unless set by hand), so the levels stay in order. */
  if (lods) bbc_params_lod_chain(&c->params, c->hand);
  /* glTF gets materials for engines to light; VRML and OBJ the thesis's
   * baked light, unless asked (parameters set by hand are kept). */
  if (lighting < 0) lighting = c->thesis ? BBC_LIGHTING_BAKED : (int)bbc_lighting_for_output(out);
  bbc_params_lighting(&c->params, c->hand, (bbc_lighting)lighting);
  /* FBX's materials have no occlusion slot: none baked unless asked. */
  if (!strcasecmp(ext, ".fbx") && !bbc_params_by_hand(c->hand, "occlusion"))
    c->params.occlusion = 0;
  /* Softened alpha edges for glTF, whose MASK mode makes every client
   * alpha-test; OBJ, VRML and FBX readers may blend such an alpha instead
   * (halos), so theirs stays 0 or 255 unless asked. */
  if (!bbc_params_by_hand(c->hand, "softalpha"))
    c->params.soft_alpha = !strcasecmp(ext, ".glb") || !strcasecmp(ext, ".gltf");
  cli_info(c, "lighting: %s", bbc_params_lighting_name(&c->params));
  bbc_session *sess = bbc_session_new();
  if (!sess) {
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  int rc = session_run(c, sess, path, count ? levels : NULL, count);
  if (rc == EXIT_OK) rc = session_write(c, sess, out);
  bbc_error err;
  if (rc == EXIT_OK && preview) {
    if (bbc_session_write_preview(sess, preview, (int)cell, &err) != BBC_OK)
      rc = cli_fail(&err, 1);
    else
      cli_info(c, "wrote %s", preview);
  }
  if (rc == EXIT_OK && report) {
    if (bbc_session_write_report(sess, report, out, &err) != BBC_OK)
      rc = cli_fail(&err, 1);
    else
      cli_info(c, "wrote %s", report);
  }
  bbc_session_free(sess);
  return rc;
}
