/* test_forest_files.c — the forest engine's map and model description files
 * (thesis Appendix B): every keyword read as the manual defines it, the
 * manual's own example, and every mistake refused with file:line and what
 * was expected. Run under ASan/UBSan by `make test`. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bbc_forest.h"

/* The model description file of Appendix B, as printed. */
static const char k_thesis_model[] =
    "fade 250\n"
    "' we want a shadow with radius 5.2 units, and cutoff at 2.0 units\n"
    "shadowrad 5.2\n"
    "shadowcutoff 2.0\n"
    "' first LOD: render 3ds tree, with creating displaylists and lighting on\n"
    "LOD\n"
    "(\n"
    "    file1 tree.3ds displaylist lighting\n"
    "    min 0\n"
    "    max 1000\n"
    ")\n"
    "' second LOD: draw Billboard Clouds with displaylists\n"
    "LOD\n"
    "(\n"
    "    file1 treefoliage.wrl displaylist\n"
    "    file2 treetrunk.wrl displaylist\n"
    "    min 1000\n"
    "    max 5000\n"
    ")\n"
    "' third LOD is simplest Billboard Cloud\n"
    "LOD\n"
    "(\n"
    "    file1 tree.wrl displaylist mipmap\n"
    "    min 5000\n"
    "    max 15000\n"
    ")\n"
    "' an object further away is not rendered at all\n";

static void test_thesis_model(void **state) {
  (void)state;
  bbc_forest_model m;
  bbc_error err;
  if (bbc_forest_model_parse(k_thesis_model, strlen(k_thesis_model), "tree.txt", &m, &err) !=
      BBC_OK)
    fail_msg("%s", err.message);
  assert_true(m.fade == 250 && m.shadow_radius == 5.2 && m.shadow_cutoff == 2.0);
  assert_int_equal(m.lod_count, 3);
  assert_int_equal(m.lods[0].part_count, 1);
  assert_string_equal(m.lods[0].part[0].file, "tree.3ds");
  assert_true(m.lods[0].part[0].displaylist && m.lods[0].part[0].lighting &&
              !m.lods[0].part[0].mipmap);
  assert_true(m.lods[0].min_dist == 0 && m.lods[0].max_dist == 1000);
  assert_int_equal(m.lods[0].line, 6);
  assert_int_equal(m.lods[1].part_count, 2);
  assert_string_equal(m.lods[1].part[0].file, "treefoliage.wrl");
  assert_string_equal(m.lods[1].part[1].file, "treetrunk.wrl");
  assert_true(m.lods[1].part[1].displaylist && !m.lods[1].part[1].lighting);
  assert_true(m.lods[1].min_dist == 1000 && m.lods[1].max_dist == 5000);
  assert_string_equal(m.lods[2].part[0].file, "tree.wrl");
  assert_true(m.lods[2].part[0].mipmap && m.lods[2].max_dist == 15000);
  bbc_forest_model_free(&m);
}

static void test_every_map_keyword(void **state) {
  (void)state;
  const char *text = "' a map with every command of Appendix B\n"
                     "hmap terrain.png\n"
                     "hmapfilter 2 3\n"
                     "colmap colour.png\n"
                     "heightscale 10.0\n"
                     "stretch 2.0\n"
                     "light 1 -2 0.5\n"
                     "farclip 400\n"
                     "roetger 12.5\n"
                     "skymap sky/clouds\n"
                     "waterheight 15.5\n"
                     "fog 100 900\n"
                     "numobjs 38001\n"
                     "object2d house.txt 1.5 1 100 200 0 90 0 -0.5\n"
                     "rndtree tupelo.txt 1.0 20000 1 1 0 0 0 0\n"
                     "rndtree2 foliage.wrl \"stem file.wrl\" 0.8 18000 0 1 -90 0 0 0.25\n"
                     "wind 1.5 0 -3\n";
  bbc_forest_map m;
  bbc_error err;
  if (bbc_forest_map_parse(text, strlen(text), "mixed.txt", &m, &err) != BBC_OK)
    fail_msg("%s", err.message);
  assert_string_equal(m.hmap, "terrain.png");
  assert_true(m.hmap_filter_radius == 2 && m.hmap_filter_passes == 3);
  assert_string_equal(m.colmap, "colour.png");
  assert_true(m.wind.strength == 1.5 && m.wind.dir[0] == 0 && m.wind.dir[1] == -1);
  { /* the direction is optional: a number on the next line belongs to its own command */
    const char *t2 = "hmap h.png\nwind 2\nfog 10 20\n";
    bbc_forest_map m2;
    if (bbc_forest_map_parse(t2, strlen(t2), "w.txt", &m2, &err) != BBC_OK)
      fail_msg("%s", err.message);
    assert_true(m2.wind.strength == 2 && m2.wind.dir[0] == 1 && m2.wind.dir[1] == 0);
    assert_true(m2.has_fog && m2.fog_start == 10 && m2.fog_end == 20);
    bbc_forest_map_free(&m2);
  }
  assert_true(m.heightscale == 10 && m.stretch == 2);
  assert_true(m.light[0] == 1 && m.light[1] == -2 && m.light[2] == 0.5);
  assert_true(m.farclip == 400 && m.roetger == 12.5);
  assert_string_equal(m.skymap, "sky/clouds");
  assert_true(m.has_water && m.water_height == 15.5);
  assert_true(m.has_fog && m.fog_start == 100 && m.fog_end == 900);
  assert_true(m.has_numobjs && m.numobjs == 38001);
  assert_int_equal(m.placement_count, 3);
  const bbc_forest_placement *o = &m.placements[0];
  assert_int_equal(o->kind, BBC_FOREST_OBJECT2D);
  assert_string_equal(o->file, "house.txt");
  assert_true(o->scale == 1.5 && o->mipmap == 1 && o->x == 100 && o->y == 200 && o->count == 1);
  assert_true(o->rotation_deg[1] == 90 && o->altitude == -0.5 && o->line == 14);
  const bbc_forest_placement *r = &m.placements[1];
  assert_int_equal(r->kind, BBC_FOREST_RNDTREE);
  assert_true(r->count == 20000 && r->mipmap == 1 && r->random == 1 && r->file2 == NULL);
  const bbc_forest_placement *r2 = &m.placements[2];
  assert_int_equal(r2->kind, BBC_FOREST_RNDTREE2);
  assert_string_equal(r2->file, "foliage.wrl");
  assert_string_equal(r2->file2, "stem file.wrl");
  assert_true(r2->scale == 0.8 && r2->count == 18000 && r2->mipmap == 0 && r2->random == 1);
  assert_true(r2->rotation_deg[0] == -90 && r2->altitude == 0.25);
  bbc_forest_map_free(&m);
  /* Defaults when a command is not given; keywords in any case; arguments
   * across line breaks. */
  const char *small = "HMAP h.png\nRNDTREE t.txt\n  2 10 0 0\n 0 0 0 0\n";
  if (bbc_forest_map_parse(small, strlen(small), "small.txt", &m, &err) != BBC_OK)
    fail_msg("%s", err.message);
  assert_true(m.heightscale == 1 && m.stretch == 1 && !m.has_water && !m.has_fog && !m.colmap);
  assert_true(m.placement_count == 1 && m.placements[0].count == 10 && m.placements[0].scale == 2);
  bbc_forest_map_free(&m);
}

/* Each mistake: refused, and the message holds every needle (model 1:
 * a model description file, else a map). */
static void expect_error(int model, const char *text, const char *n1, const char *n2) {
  bbc_forest_map mp;
  bbc_forest_model mo;
  bbc_error err;
  memset(&err, 0, sizeof err);
  bbc_result r = model ? bbc_forest_model_parse(text, strlen(text), "bad.txt", &mo, &err)
                       : bbc_forest_map_parse(text, strlen(text), "bad.txt", &mp, &err);
  if (r == BBC_OK) fail_msg("accepted: %s", text);
  assert_int_equal(r, BBC_ERROR_CORRUPT);
  if (!strstr(err.message, n1) || (n2 && !strstr(err.message, n2)))
    fail_msg("'%s' lacks '%s'/'%s'", err.message, n1, n2 ? n2 : "");
  if (model) {
    assert_null(mo.lods);
  } else {
    assert_null(mp.placements);
    assert_null(mp.hmap);
  }
}

static void expect_map_error(const char *text, const char *n1, const char *n2) {
  expect_error(0, text, n1, n2);
}

static void expect_model_error(const char *text, const char *n1, const char *n2) {
  expect_error(1, text, n1, n2);
}

static void test_mistakes_named(void **state) {
  (void)state;
  expect_map_error("hmap h.png\nheightscale ten\n", "bad.txt:2:", "heightscale");
  expect_map_error("hmap h.png\nheightscale -1\n", "bad.txt:2:", "> 0");
  expect_map_error("hmap h.png\n\nfog 900 100\n", "bad.txt:3:", "fog");
  expect_map_error("hmap h.png\nlight 0 0 0\n", "bad.txt:2:", "light");
  expect_map_error("hmap h.png\nwind -1\n", "bad.txt:2:", "wind");
  expect_map_error("hmap h.png\nwind 1 0 0\n", "bad.txt:2:", "direction");
  expect_map_error("hmap h.png\nwind 1 2\nfog 1 2\n", "bad.txt:3:", "direction's z");
  expect_map_error("hmap h.png\nforest 3\n", "bad.txt:2:", "unknown command 'forest'");
  /* a terminal's escape sequence in a binary file is shown, not sent */
  expect_map_error("hmap h.png\n\033[31mRED 1\n", "bad.txt:2:", "unknown command '\\x1b[31mRED'");
  expect_map_error("hmap h.png\nrndtree t.txt 1 100 2 1 0 0 0 0\n", "bad.txt:2:", "mipmap");
  expect_map_error("hmap h.png\nrndtree t.txt 1 -5 1 1 0 0 0 0\n", "bad.txt:2:", "number of");
  expect_map_error("hmap h.png\nobject2d a.txt 1 1 10 20 0 0 0\n", "end of the file",
                   "additional altitude");
  expect_map_error("hmap h.png\nobject2d a.txt 0 1 10 20 0 0 0 0\n", "bad.txt:2:", "scale");
  expect_map_error("hmap h.png\nhmapfilter 2\n", "bad.txt:2: hmapfilter", "end of the file");
  expect_map_error("hmap \"h.png\n", "bad.txt:1:", "quoted");
  expect_map_error("colmap c.png\n", "no heightmap", NULL);
  expect_map_error("hmap h.png\nnumobjs 1e12\n", "bad.txt:2:", "numobjs");
  /* too few values: the next line's word is named, and the line the command begins on */
  expect_map_error("hmap h.png\nrndtree t.txt 1 100 1\nobject2d a.txt 1 1 5 5 0 0 0 0\n",
                   "bad.txt:3:", "begins on line 2");
  /* one too many: a number taken for a command */
  expect_map_error("hmap h.png\nstretch 4 5\n", "bad.txt:2:", "one value too many");
  expect_model_error("LOD ( file1 a.wrl min 0 max 100 )\nfade fast\n", "bad.txt:2:", "fade");
  expect_model_error("LOD file1 a.wrl min 0 max 100 )\n", "bad.txt:1:", "'('");
  expect_model_error("LOD (\n file1 a.wrl\n min 0\n", "end of the file", "LOD");
  expect_model_error("LOD ( min 0 max 10 )\n", "bad.txt:1:", "no file");
  expect_model_error("LOD ( file1 a.wrl min 0 )\n", "bad.txt:1:", "max");
  expect_model_error("LOD ( file1 a.wrl min 50 max 10 )\n", "bad.txt:1:", "min < max");
  expect_model_error("LOD ( file2 a.wrl min 0 max 10 )\n", "bad.txt:1:", "file2");
  expect_model_error("LOD ( displaylist file1 a.wrl min 0 max 10 )\n", "bad.txt:1:", "option");
  expect_model_error("LOD ( file1 a.wrl smooth min 0 max 10 )\n", "bad.txt:1:", "'smooth'");
  expect_model_error("\n\nlod2 ( file1 a.wrl min 0 max 10 )\n", "bad.txt:3:", "unknown command");
  expect_model_error("fade 10\n", "no LOD block", NULL);
  expect_model_error("shadowrad 2\nshadowcutoff 3\nLOD ( file1 a min 0 max 1 )\n", "shadowcutoff",
                     NULL);
}

/* Every prefix of a valid file is refused or accepted cleanly (ASan). */
static void test_every_prefix(void **state) {
  (void)state;
  const char *map = "hmap h.png\ncolmap c.png\nfog 1 2\nrndtree2 a \"b c\" 1 2 1 0 0 0 0 0\n";
  for (size_t n = 0; n <= strlen(map); n++) {
    bbc_forest_map m;
    bbc_error err;
    if (bbc_forest_map_parse(map, n, "p.txt", &m, &err) == BBC_OK) bbc_forest_map_free(&m);
  }
  for (size_t n = 0; n <= strlen(k_thesis_model); n++) {
    bbc_forest_model m;
    bbc_error err;
    if (bbc_forest_model_parse(k_thesis_model, n, "p.txt", &m, &err) == BBC_OK)
      bbc_forest_model_free(&m);
  }
}

static void test_from_files(void **state) {
  (void)state;
  bbc_forest_map m;
  bbc_error err;
  assert_int_equal(bbc_forest_map_load("/nonexistent/forest/map.txt", &m, &err),
                   BBC_ERROR_NOT_FOUND);
  assert_non_null(strstr(err.message, "map.txt"));
  char path[] = "/tmp/bbc_forest_XXXXXX";
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  fputs(k_thesis_model, f);
  fclose(f);
  bbc_forest_model mo;
  if (bbc_forest_model_load(path, &mo, &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(mo.lod_count, 3);
  bbc_forest_model_free(&mo);
  assert_int_equal(bbc_forest_map_load(path, &m, &err), BBC_ERROR_CORRUPT); /* not a map */
  assert_non_null(strstr(err.message, "unknown command 'fade'"));
  remove(path);
}

/* Runs a shell command whose output goes to `out`; its status in *rc and
 * that output (malloc'd, NUL-terminated). */
static char *run_logged(const char *cmd, const char *out, int *rc) {
  *rc = system(cmd);
  char *log = calloc(1, 65536);
  assert_non_null(log);
  FILE *f = fopen(out, "r");
  if (f) {
    size_t n = fread(log, 1, 65535, f);
    log[n] = 0;
    fclose(f);
  }
  return log;
}

static void put_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

/* A world from a 20 x 12 ramp heightmap (resampled to 33 x 33) and a
 * colour map green on its left half, red on the right: heights scaled,
 * object2d on the ground where written, every rndtree object on green
 * ground, the same world twice. */
static void test_world(void **state) {
  (void)state;
  char dir[] = "/tmp/bbc_world_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char path[256];
  bbc_image hm, cm;
  bbc_error err;
  assert_int_equal(bbc_image_alloc(&hm, 20, 12), BBC_OK);
  for (int y = 0; y < 12; y++)
    for (int x = 0; x < 20; x++) {
      uint8_t *p = hm.rgba + 4 * ((size_t)y * 20 + x);
      p[0] = p[1] = p[2] = (uint8_t)(10 * x); /* 0..190 along x */
      p[3] = 255;
    }
  snprintf(path, sizeof path, "%s/h.png", dir);
  assert_int_equal(bbc_image_write_png(path, &hm, &err), BBC_OK);
  assert_int_equal(bbc_image_alloc(&cm, 64, 64), BBC_OK);
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) {
      uint8_t *p = cm.rgba + 4 * ((size_t)y * 64 + x);
      p[0] = x < 32 ? 40 : 200;
      p[1] = x < 32 ? 160 : 60;
      p[2] = 30;
      p[3] = 255;
    }
  snprintf(path, sizeof path, "%s/c.png", dir);
  assert_int_equal(bbc_image_write_png(path, &cm, &err), BBC_OK);
  const char *text = "hmap h.png\ncolmap c.png\nheightscale 2\nstretch 3\n"
                     "object2d house.txt 1 0 30 45 0 90 0 0.5\n"
                     "rndtree tree.txt 1.5 500 1 1 0 0 0 0\n";
  bbc_forest_map map;
  if (bbc_forest_map_parse(text, strlen(text), "w.txt", &map, &err) != BBC_OK)
    fail_msg("%s", err.message);
  bbc_forest_world w[2];
  for (int k = 0; k < 2; k++)
    if (bbc_forest_world_build(&map, dir, &w[k], &err) != BBC_OK) fail_msg("%s", err.message);
  assert_int_equal(w[0].width, 33);
  assert_int_equal(w[0].depth, 33);
  assert_non_null(strstr(w[0].note, "20 x 12 resampled to 33 x 33"));
  assert_non_null(strstr(w[0].note, "64 x 64 resampled to 32 x 32"));
  assert_true(w[0].spacing == 3 && w[0].heightmap_bits == 8);
  /* The ramp: 0 at x = 0, 190 x heightscale at the far edge. */
  assert_true(fabs(w[0].height[0]) < 1e-4);
  assert_true(fabs(w[0].height[32] - 380) < 1e-3);
  double mid = bbc_forest_world_get_height(&w[0], 16 * 3.0, 10);
  assert_true(fabs(mid - 190) < 1.0);
  assert_int_equal(w[0].instance_count, 501);
  const bbc_forest_instance *o = &w[0].instances[0];
  assert_true(o->x == 30 && o->z == 45 && o->yaw_deg == 90);
  assert_true(fabs(o->y - (bbc_forest_world_get_height(&w[0], 30, 45) + 0.5)) < 1e-3);
  double extent = 32 * 3.0;
  for (size_t i = 1; i < w[0].instance_count; i++) {
    const bbc_forest_instance *t = &w[0].instances[i];
    assert_true(t->x >= 0 && t->x < extent / 2 + 1e-9); /* the green half */
    assert_true(t->z >= 0 && t->z < extent);
    assert_true(t->scale == 1.5f && t->yaw_deg >= 0 && t->yaw_deg < 360);
    assert_true(fabs(t->y - bbc_forest_world_get_height(&w[0], t->x, t->z)) < 1e-3);
  }
  assert_int_equal(w[0].placements_short, 0);
  assert_true(fabs(w[0].green_fraction - 0.5) < 1e-9);
  assert_int_equal(w[1].instance_count, w[0].instance_count);
  assert_memory_equal(w[0].instances, w[1].instances, w[0].instance_count * sizeof *w[0].instances);
  assert_int_equal(sizeof(bbc_forest_instance) <= 32, 1);
  for (int k = 0; k < 2; k++) bbc_forest_world_free(&w[k]);
  /* The tool: `forest --check` reads the map and its model descriptions
   * and names what is missing. */
  char cmd[1024], out[512], model[256], house[256];
  snprintf(model, sizeof model, "%s/tree.txt", dir);
  put_file(model, "fade 10\nLOD ( file1 tree.obj mipmap min 0 max 500 )\n");
  snprintf(house, sizeof house, "%s/house.txt", dir);
  put_file(house, "LOD ( file1 tree.obj min 0 max 100 )\n");
  snprintf(path, sizeof path, "%s/tree.obj", dir);
  put_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  snprintf(path, sizeof path, "%s/map.txt", dir);
  put_file(path, text);
  snprintf(out, sizeof out, "%s/out.txt", dir);
  snprintf(cmd, sizeof cmd, "'%s/forest' --check '%s' > '%s' 2>&1", BBC_BIN_DIR, path, out);
  int rc;
  char *log = run_logged(cmd, out, &rc);
  if (rc != 0) fail_msg("forest --check: %s", log);
  assert_non_null(strstr(log, "objects: 501 placed of 501 asked"));
  assert_non_null(strstr(log, "green ground"));
  free(log);
  put_file(path, "hmap h.png\nrndtree tree.txt 1 5 0 1 0 0 0 0\n"
                 "rndtree2 tree.txt stem.wrl 1 5 0 1 0 0 0 0\n");
  log = run_logged(cmd, out, &rc);
  assert_true(rc != 0 && WEXITSTATUS(rc) == 1);
  assert_non_null(strstr(log, "map.txt:3: model 'stem.wrl' not found"));
  assert_non_null(strstr(log, "objects: 10 placed of 10 asked"));
  free(log);
  /* Drawing a map with a missing model: named, exit 1, nothing drawn. */
  snprintf(cmd, sizeof cmd, "'%s/forest' '%s' --size 32x32 --log '%s/log.txt' > '%s' 2>&1",
           BBC_BIN_DIR, path, dir, out);
  log = run_logged(cmd, out, &rc);
  assert_int_equal(WEXITSTATUS(rc), 1);
  assert_non_null(strstr(log, "stem.wrl"));
  free(log);
  /* A model whose texture is missing: named with the map's line, a problem. */
  char tex[256];
  snprintf(tex, sizeof tex, "%s/leafy.mtl", dir);
  put_file(tex, "newmtl leaf\nKd 1 1 1\nmap_Kd gone.png\n");
  snprintf(tex, sizeof tex, "%s/leafy.obj", dir);
  put_file(tex, "mtllib leafy.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl leaf\nf 1 2 3\n");
  put_file(path, "hmap h.png\nobject2d leafy.obj 1 1 8 8 0 0 0 0\n");
  snprintf(cmd, sizeof cmd, "'%s/forest' --check '%s' > '%s' 2>&1", BBC_BIN_DIR, path, out);
  log = run_logged(cmd, out, &rc);
  assert_true(rc != 0 && WEXITSTATUS(rc) == 1);
  if (!strstr(log, "map.txt:2: warning:") || !strstr(log, "gone.png")) fail_msg("%s", log);
  free(log);
  /* A map file a command names but that is not there: named with its line. */
  put_file(path, "' a heightmap that is not there\nhmap gone.png\n");
  log = run_logged(cmd, out, &rc);
  assert_true(rc != 0 && WEXITSTATUS(rc) == 1);
  if (!strstr(log, "map.txt:2: ") || !strstr(log, "gone.png")) fail_msg("%s", log);
  free(log);
  /* A misspelt option gets the nearest one; a word far from all, --help. */
  snprintf(cmd, sizeof cmd, "'%s/forest' --scrrenshot s.png '%s' > '%s' 2>&1", BBC_BIN_DIR, path,
           out);
  log = run_logged(cmd, out, &rc);
  assert_true(rc != 0 && WEXITSTATUS(rc) == 2);
  if (!strstr(log, "unknown option '--scrrenshot' (did you mean --screenshot?)"))
    fail_msg("%s", log);
  free(log);
  snprintf(cmd, sizeof cmd, "'%s/forest' --zzzzzz '%s' > '%s' 2>&1", BBC_BIN_DIR, path, out);
  log = run_logged(cmd, out, &rc);
  assert_true(rc != 0 && WEXITSTATUS(rc) == 2);
  if (!strstr(log, "unknown option '--zzzzzz' (try forest --help)")) fail_msg("%s", log);
  free(log);
  remove(tex);
  snprintf(tex, sizeof tex, "%s/leafy.mtl", dir);
  remove(tex);
  remove(model);
  remove(house);
  remove(path);
  remove(out);
  snprintf(path, sizeof path, "%s/tree.obj", dir);
  remove(path);
  /* A missing heightmap is named. */
  bbc_forest_map_free(&map);
  const char *bad = "hmap nothere.png\n";
  assert_int_equal(bbc_forest_map_parse(bad, strlen(bad), "b.txt", &map, &err), BBC_OK);
  bbc_forest_world nw;
  assert_int_equal(bbc_forest_world_build(&map, dir, &nw, &err), BBC_ERROR_NOT_FOUND);
  assert_non_null(strstr(err.message, "nothere.png"));
  bbc_forest_map_free(&map);
  bbc_image_free(&hm);
  bbc_image_free(&cm);
  snprintf(path, sizeof path, "%s/h.png", dir);
  remove(path);
  snprintf(path, sizeof path, "%s/c.png", dir);
  remove(path);
  rmdir(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_thesis_model),   cmocka_unit_test(test_every_map_keyword),
      cmocka_unit_test(test_mistakes_named), cmocka_unit_test(test_every_prefix),
      cmocka_unit_test(test_from_files),     cmocka_unit_test(test_world),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
