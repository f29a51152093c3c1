/* test_cli_cloud.c — making clouds with the bbcgen tool as a user does:
 * outputs, epsilon by hand, suggestions, parts, the atlas budget, materials
 * and texture names, brightness, the sun. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cjson/cJSON.h>

#include "bbc.h"
#include "cli_util.h"
#include "test_util.h"

/* bbcgen MODEL -o OUT: option errors before any work; batch bbc/shade/save
 * write the thesis's VRML folder. */
static void test_cloud_command(void **state) {
  (void)state;
  char path[1024], args[4096], text[2048];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *out, *err;
  const char *bad[][3] = {
      {"--lod 10,5", "1", "must increase"},
      {"--lod 5,abc", "1", "not a list"},
      {"--preview p.jpg", "1", ".png"},
      {"--report r.txt", "1", ".json"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/t.glb' %s", path, tu_dir, bad[i][0]);
    assert_int_equal(cli_run(args, &out, &err), atoi(bad[i][1]));
    if (!strstr(err, bad[i][2])) fail_msg("%s: %s", bad[i][0], err);
    free(out);
    free(err);
  }
  snprintf(args, sizeof args, "'%s' -o '%s/no/such/t.glb'", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 5);
  assert_non_null(strstr(err, "does not exist"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "'%s' -o '%s/t.png'", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 1);
  free(out);
  free(err);
  /* Extensions in capitals are the same formats (a Windows user's T.GLB). */
  snprintf(args, sizeof args, "'%s' -o '%s/UP.GLB' --preview '%s/UP.PNG' -q", path, tu_dir, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "'%s' -o '%s/UP.OBJ' -q", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  /* A space in an OBJ's name stays out of the names mtllib and map_Kd
   * give: they split at spaces. */
  snprintf(args, sizeof args, "'%s' -o '%s/my tree.obj' -q", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(args, sizeof args, "%s/my tree.obj", tu_dir);
  char *obj = (char *)tu_read_file(args, NULL);
  assert_non_null(obj);
  assert_non_null(strstr(obj, "\nmtllib my_tree.mtl\n"));
  free(obj);
  snprintf(args, sizeof args, "%s/my_tree.mtl", tu_dir);
  char *mtl = (char *)tu_read_file(args, NULL);
  assert_non_null(mtl);
  assert_non_null(strstr(mtl, "\nmap_Kd my_tree_obj_billboards.png\n"));
  free(mtl);
  const char *made[] = {"UP.GLB",
                        "UP.PNG",
                        "UP.OBJ",
                        "UP.mtl",
                        "UP_OBJ_billboards.png",
                        "my_tree_obj_billboards.png"};
  for (size_t i = 0; i < sizeof made / sizeof made[0]; i++) {
    char f[1200];
    snprintf(f, sizeof f, "%s/%s", tu_dir, made[i]);
    if (!tu_have_file(f)) fail_msg("%s not written", made[i]);
  }
  /* An output that is a folder is refused before any work; a point cloud
   * makes a cloud (thesis 2.4) the Khronos validator passes; a folder is no
   * batch file (exit 2); an unknown baseline method is a usage error. */
  char folder[1200];
  snprintf(folder, sizeof folder, "%s/folder.glb", tu_dir);
  assert_int_equal(mkdir(folder, 0777), 0);
  snprintf(args, sizeof args, "'%s' -o '%s'", path, folder);
  assert_int_equal(cli_run(args, &out, &err), 5);
  rmdir(folder);
  assert_non_null(strstr(err, "is a folder"));
  free(out);
  free(err);
  char pts[1024];
  tu_data_path(pts, sizeof pts, "points/b9_training.ply");
  if (tu_have_file(pts)) {
    snprintf(args, sizeof args, "'%s' -o '%s/p.glb' -q", pts, tu_dir);
    if (cli_run(args, &out, &err)) fail_msg("%s", err);
    free(out);
    free(err);
    char glb[1200];
    snprintf(glb, sizeof glb, "%s/p.glb", tu_dir);
    int v = tu_gltf_validate(glb);
    if (v == 3 && getenv("CI")) fail_msg("the glTF validator is unavailable");
    if (v != 3) assert_int_equal(v, 0);
  }
  snprintf(args, sizeof args, "exec '%s'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 2);
  free(out);
  free(err);
  snprintf(args, sizeof args, "baseline '%s' -o '%s/b.glb' --method foo", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 1);
  assert_non_null(strstr(err, "foo"));
  free(out);
  free(err);
  /* eval: side-view figures are null when no view is a side view. */
  snprintf(args, sizeof args,
           "eval '%s' '%s' --views 2 --side-elevation 10 --size 16 --json '%s/e.json'", path, path,
           tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  assert_non_null(strstr(out, "side n/a"));
  free(out);
  free(err);
  char ej[1200];
  snprintf(ej, sizeof ej, "%s/e.json", tu_dir);
  char *etext = (char *)tu_read_file(ej, NULL);
  cJSON *e = cJSON_Parse(etext);
  assert_non_null(e);
  assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(e, "iou_side_mean")));
  assert_true(cJSON_GetObjectItemCaseSensitive(e, "iou_mean")->valuedouble == 1.0);
  cJSON_Delete(e);
  free(etext);
  /* eval --upper: every view from above or level (y up: the camera's
   * direction towards the model never rises) */
  snprintf(args, sizeof args, "eval '%s' '%s' --views 12 --size 16 --upper --json '%s/e.json'",
           path, path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  etext = (char *)tu_read_file(ej, NULL);
  e = cJSON_Parse(etext);
  assert_non_null(e);
  assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(e, "upper")));
  const cJSON *pv = cJSON_GetObjectItemCaseSensitive(e, "per_view"), *view;
  assert_int_equal(cJSON_GetArraySize(pv), 12);
  int level = 0;
  cJSON_ArrayForEach(view, pv) {
    double dy =
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(view, "direction"), 1)->valuedouble;
    assert_true(dy <= 1e-9);
    level += dy > -0.2;
  }
  assert_true(level > 0); /* down to the horizon */
  cJSON_Delete(e);
  free(etext);
  /* Batch: bbc3 needs bbc2; bbc then save writes the Appendix A folder. */
  snprintf(text, sizeof text, "load \"%s\"\nbbc3\n", path);
  char *bf = tu_write_file(tu_dir, "c3.bbc", text, strlen(text));
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(cli_run(args, &out, &err), 1);
  assert_non_null(strstr(err, "bbc3 needs the planes of bbc2"));
  free(out);
  free(err);
  free(bf);
  /* load reads the model at once: a missing one is named at its line */
  bf = tu_write_file(tu_dir, "nomodel.bbc", "load /no/such/x.obj\nbbc\n", 25);
  snprintf(args, sizeof args, "exec '%s'", bf);
  assert_int_equal(cli_run(args, &out, &err), 2);
  assert_non_null(strstr(err, "x.obj"));
  free(out);
  free(err);
  free(bf);
  snprintf(text, sizeof text, "load \"%s\"\nset texres 32\nshade 20 0.5\nbbc\nsave forest\n", path);
  bf = tu_write_file(tu_dir, "save.bbc", text, strlen(text));
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s/bbcgen' exec '%s' -q > /dev/null 2>&1", tu_dir,
           BBC_BIN_DIR, bf);
  int st = system(cmd);
  assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  char wrl[2048], png[2048];
  snprintf(wrl, sizeof wrl, "%s/vrml97models/forest/Tree_1/Tree_1_e6.00_tex32_pl/Tree_1.wrl",
           tu_dir);
  snprintf(png, sizeof png,
           "%s/vrml97models/forest/Tree_1/Tree_1_e6.00_tex32_pl/Tree_1_wrl_billboards.png", tu_dir);
  size_t n;
  unsigned char *w = tu_read_file(wrl, &n), *p = tu_read_file(png, NULL);
  assert_non_null(w);
  assert_non_null(p);
  assert_true(n > 100 && !memcmp(w, "#VRML V2.0 utf8", 15));
  free(w);
  free(p);
  free(bf);
}

/* An epsilon typed by hand is kept; maxplanes moves only the default, and
 * the report says when it did. A generated bush needs more than 8 planes at
 * epsilon 3. */
static void test_hand_epsilon_kept(void **state) {
  (void)state;
  char args[4096], *out, *err;
  snprintf(args, sizeof args, "tree --species bush --leaves 600 --seed 3 -o '%s/eb.obj'", tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  const char *cases[][3] = {
      /* options, epsilon used (0: more than asked), adjusted_by */
      {"--epsilon 3 --texres 32", "3", ""},
      {"--set epsilon=3 --texres 32", "3", ""},
      {"--epsilon 3 --maxplanes 8 --texres 32", "0", "maxplanes"},
      {"--maxplanes 8 --epsilon 3 --texres 32", "0", "maxplanes"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    snprintf(args, sizeof args, "'%s/eb.obj' -o '%s/eb.glb' --report '%s/eb.json' %s", tu_dir,
             tu_dir, tu_dir, cases[i][0]);
    assert_int_equal(cli_run(args, &out, &err), 0);
    free(out);
    char rp[1200];
    snprintf(rp, sizeof rp, "%s/eb.json", tu_dir);
    char *text = (char *)tu_read_file(rp, NULL);
    cJSON *r = cJSON_Parse(text);
    assert_non_null(r);
    const cJSON *lod = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(r, "lods"), 0);
    double used = cli_num(lod, "epsilon_pct_used");
    const cJSON *by = cJSON_GetObjectItemCaseSensitive(lod, "epsilon_adjusted_by");
    if (cases[i][2][0]) {
      assert_true(used > 3.0);
      assert_true(cJSON_IsString(by) && !strcmp(by->valuestring, cases[i][2]));
      assert_true(cli_num(lod, "planes") <= 8);
      /* The info line says what moved it. */
      if (!strstr(err, "raised from 3 % by maxplanes 8")) fail_msg("%s", err);
    } else {
      assert_true(used == 3.0);
      assert_true(cJSON_IsString(by) && !strcmp(by->valuestring, "none"));
      assert_true(cli_num(lod, "planes") > 8);
    }
    /* The glTF node's extras state the epsilon used. */
    snprintf(rp, sizeof rp, "%s/eb.glb", tu_dir);
    cJSON *g = cli_glb_json(rp);
    const cJSON *ex = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(g, "nodes"), 0), "extras");
    assert_true(cli_num(ex, "epsilon_pct_used") == used);
    cJSON_Delete(g);
    cJSON_Delete(r);
    free(text);
    free(err);
  }
  /* VRML: the header gives the epsilon used and why. */
  snprintf(args, sizeof args, "'%s/eb.obj' -o '%s/eb.wrl' --epsilon 3 --maxplanes 8 --texres 32",
           tu_dir, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  char wp[1200];
  snprintf(wp, sizeof wp, "%s/eb.wrl", tu_dir);
  char *w = (char *)tu_read_file(wp, NULL);
  assert_non_null(w);
  assert_non_null(strstr(w, "(raised from 3 % by maxplanes 8)"));
  assert_null(strstr(w, "# epsilon: 3 %"));
  free(w);
}

/* Unknown options and commands: named, with the nearest suggestion. */
static void test_suggestions(void **state) {
  (void)state;
  const char *cases[][3] = {
      {"x.obj -o x.glb --epslon 6", "did you mean --epsilon?", "1"},
      {"infoo x.obj", "unknown command 'infoo' (did you mean bbcgen info?)", "1"},
      {"plane x.obj", "did you mean bbcgen planes?", "1"},
      {"eval a.obj b.glb --jsn x", "eval: unknown option '--jsn' (did you mean --json?)", "1"},
      {"tree --specis oak -o t.obj", "did you mean --species?", "1"},
      {"x.obj -o x.glb --prev p.png", "did you mean --preview?", "1"},
      {"--verison", "did you mean --version?", "1"},
      {"x.obj -o x.glb --zzzzzz 1", "unknown option '--zzzzzz' (try bbcgen --help)", "1"},
      {"frobnicate", "unknown command 'frobnicate'", "1"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char *out, *err;
    assert_int_equal(cli_run(cases[i][0], &out, &err), atoi(cases[i][2]));
    if (!strstr(err, cases[i][1])) fail_msg("bbcgen %s: '%s'", cases[i][0], err);
    free(out);
    free(err);
  }
  /* Every command answers --help (it used to be "unknown option '--help'
   * (did you mean --help?)"). */
  /* Each with its own part of the help (the cloud: all of it). */
  const char *helps[][3] = {
      {"tree --help", "larch", "eval ORIGINAL"}, {"eval --help", "side-elevation", "larch"},
      {"info -h", "--no-textures", "larch"},     {"render --help", "Software render", "larch"},
      {"planes --help", "epsilon", "larch"},     {"baseline --help", "crossed", "larch"},
      {"x.obj -o x.glb --help", "larch", NULL}};
  for (size_t i = 0; i < sizeof helps / sizeof helps[0]; i++) {
    char *out, *err;
    assert_int_equal(cli_run(helps[i][0], &out, &err), 0);
    if (!strstr(out, "Usage:") || !strstr(out, helps[i][1]) || !strstr(out, "Exit codes") ||
        (helps[i][2] && strstr(out, helps[i][2])))
      fail_msg("bbcgen %s: '%s'", helps[i][0], out);
    free(out);
    free(err);
  }
}

/* Materials and texture files: prelit clouds are unlit in every format
 * (KHR_materials_unlit, VRML without Material, MTL illum 0), relightable
 * ones lit; texture files are <stem>_<material>[_nm].png in all three. */
/* atlasmax: the largest texres whose images the packer fits, not the one
 * that fills 70 % (the ez-tree oak at epsilon 5: 128 fills 79 % of one
 * 1024 x 1024 atlas, where the 70 % rule took 64). */
/* A part's parameters for a part the model does not have are said. */
static void test_unknown_part(void **state) {
  (void)state;
  char path[1024], args[4096];
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "planes '%s' --set bogus.epsilon=8", path);
  char *out, *err;
  assert_int_equal(cli_run(args, &out, &err), 0);
  if (!strstr(err, "parameters for part 'bogus' are not used")) fail_msg("%s", err);
  free(out);
  free(err);
}

static void test_atlas_budget(void **state) {
  (void)state;
  char path[1024], args[4096];
  tu_data_path(path, sizeof path, "trees/eztree/oak_medium.obj");
  if (!tu_have_file(path)) skip();
  snprintf(args, sizeof args, "'%s' -o '%s/ab.glb' --epsilon 5 --report '%s/ab.json' -q", path,
           tu_dir, tu_dir);
  char *out, *err;
  assert_int_equal(cli_run(args, &out, &err), 0);
  free(out);
  free(err);
  snprintf(path, sizeof path, "%s/ab.json", tu_dir);
  char *t = (char *)tu_read_file(path, NULL);
  assert_non_null(t);
  cJSON *j = cJSON_Parse(t);
  const cJSON *l = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "lods"), 0);
  int texres = cJSON_GetObjectItemCaseSensitive(l, "texres_used")->valueint;
  double fill = cJSON_GetObjectItemCaseSensitive(l, "atlas_fill")->valuedouble;
  double texels = cJSON_GetObjectItemCaseSensitive(l, "texels")->valuedouble;
  if (texres != 128 || fill < 0.7 || texels / fill > 1024.0 * 1024.0 + 0.5)
    fail_msg("texres %d, atlas fill %.3f, %.0f texels", texres, fill, texels);
  cJSON_Delete(j);
  free(t);
}

static void test_materials_and_texture_names(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_1.obj");
  if (!tu_have_file(path)) skip();
  char *dir = tu_make_temp_dir();
  /* glTF: lit materials by default, VRML and OBJ baked. */
  const char *runs[][2] = {{"u.glb", "--lighting baked"},
                           {"l.glb", ""},
                           {"f.glb", "--lighting baked --unlit 0"},
                           {"u.gltf", "--lighting baked --nm 1"},
                           {"u.wrl", "--nm 1"},
                           {"l.wrl", "--prelight 0"},
                           {"u.obj", ""},
                           {"l.obj", "--prelight 0"},
                           {"m.gltf", "--lighting material"}};
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/%s' --texres 32 -q %s", path, dir, runs[i][0],
             runs[i][1]);
    assert_int_equal(cli_run(args, &out, &err), 0);
    free(out);
    free(err);
  }
  char p[2048];
  for (int k = 0; k < 3; k++) {
    const char *names[3] = {"u.glb", "l.glb", "f.glb"};
    snprintf(p, sizeof p, "%s/%s", dir, names[k]);
    cJSON *g = cli_glb_json(p);
    const cJSON *mat = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(g, "materials"), 0);
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(mat, "extensions");
    int unlit = ext && cJSON_GetObjectItemCaseSensitive(ext, "KHR_materials_unlit");
    assert_int_equal(unlit, k == 0);
    if (k == 1) {
      assert_non_null(cJSON_GetObjectItemCaseSensitive(mat, "normalTexture"));
      assert_non_null(cJSON_GetObjectItemCaseSensitive(mat, "occlusionTexture"));
    } else {
      assert_null(cJSON_GetObjectItemCaseSensitive(mat, "occlusionTexture"));
    }
    cJSON_Delete(g);
    int v = tu_gltf_validate(p);
    if (v != 3) assert_int_equal(v, 0);
  }
  /* Each output its own side files, though u.gltf, u.wrl and u.obj share a
   * folder and a stem. */
  assert_true(cli_file_exists(dir, "u_gltf_billboards.png") &&
              cli_file_exists(dir, "u_obj_billboards.png"));
  assert_true(cli_file_exists(dir, "u_gltf_billboards_nm.png") &&
              cli_file_exists(dir, "u_wrl_billboards_nm.png"));
  assert_true(cli_file_exists(dir, "l_wrl_billboards.png") &&
              cli_file_exists(dir, "l_obj_billboards.png"));
  assert_false(cli_file_exists(dir, "u_billboards.png"));
  assert_true(cli_file_exists(dir, "u.mtl") && cli_file_exists(dir, "l.mtl"));
  snprintf(p, sizeof p, "%s/u.gltf", dir);
  char *t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "\"uri\":\"u_gltf_billboards.png\""));
  assert_non_null(strstr(t, "\"uri\":\"u_gltf_billboards_nm.png\""));
  free(t);
  assert_true(cli_file_exists(dir, "m_gltf_billboards_nm.png") &&
              cli_file_exists(dir, "m_gltf_billboards_ao.png"));
  snprintf(p, sizeof p, "%s/u.wrl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_null(strstr(t, "Material {"));
  /* the DDS with the atlas's mip levels first, the PNG for other readers */
  assert_non_null(strstr(t, "url [ \"u_wrl_billboards.dds\" \"u_wrl_billboards.png\" ]"));
  assert_true(cli_file_exists(dir, "u_wrl_billboards.dds"));
  free(t);
  snprintf(p, sizeof p, "%s/l.wrl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "Material { diffuseColor 1 1 1 }"));
  free(t);
  snprintf(p, sizeof p, "%s/u.mtl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_non_null(strstr(t, "illum 0"));
  assert_non_null(strstr(t, "map_Kd u_obj_billboards.png"));
  free(t);
  snprintf(p, sizeof p, "%s/l.mtl", dir);
  t = (char *)tu_read_file(p, NULL);
  assert_null(strstr(t, "illum 0"));
  free(t);
  /* Read back, the unlit flag survives (and eval --lit lights only the
   * original then). */
  snprintf(args, sizeof args, "info --json '%s/u.glb'", dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  assert_non_null(strstr(out, "\"unlit\":\ttrue"));
  free(out);
  free(err);
  snprintf(args, sizeof args, "info --json '%s/l.glb'", dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  assert_non_null(strstr(out, "\"unlit\":\tfalse"));
  free(out);
  free(err);
  tu_remove_dir(dir);
  free(dir);
}

/* Lit once: a baked (prelit, unlit material) cloud and a relightable one
 * look as bright
 * as the original, per channel within 10 %, lit (the original lit by the
 * same light; the prelit cloud shown as baked, its material being unlit)
 * and unlit. */
static void test_brightness(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_3.obj");
  if (!tu_have_file(path)) skip();
  const char *runs[][3] = {
      /* cloud options, eval options, 1 = must match */
      {"--lighting baked", "--lit", "1"},
      {"--lighting baked", "", "1"},
      /* A relightable cloud's one material has no Ka of its own: compared
       * lit, without the fixed-function ambient (Tree_3's MTL says Ka 1). */
      {"--prelight 0", "--lit --ambient 0", "1"},
      {"--prelight 0", "", "1"},
  };
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    snprintf(args, sizeof args, "'%s' -o '%s/br.glb' --texres 64 -q %s", path, tu_dir, runs[i][0]);
    assert_int_equal(cli_run(args, &out, &err), 0);
    free(out);
    free(err);
    snprintf(args, sizeof args,
             "eval '%s' '%s/br.glb' --views 16 --size 128 --json '%s/br.json' %s", path, tu_dir,
             tu_dir, runs[i][1]);
    assert_int_equal(cli_run(args, &out, &err), 0);
    free(out);
    free(err);
    char jp[1200];
    snprintf(jp, sizeof jp, "%s/br.json", tu_dir);
    char *text = (char *)tu_read_file(jp, NULL);
    cJSON *j = cJSON_Parse(text);
    assert_non_null(j);
    /* eval lights the original by itself when the cloud is prelit. */
    int want_lit = strstr(runs[i][1], "--lit") ||
                   (!strstr(runs[i][0], "--prelight 0") && !strstr(runs[i][1], "--no-lit"));
    assert_int_equal(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(j, "lit")), want_lit);
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(j, "brightness_ratio");
    assert_int_equal(cJSON_GetArraySize(b), 3);
    int within = 1;
    for (int c = 0; c < 3; c++) {
      double v = cJSON_GetArrayItem(b, c)->valuedouble;
      within &= v > 0.9 && v < 1.1;
    }
    if (within != atoi(runs[i][2]))
      fail_msg("cloud %s, eval %s: brightness %.3f %.3f %.3f", runs[i][0], runs[i][1],
               cJSON_GetArrayItem(b, 0)->valuedouble, cJSON_GetArrayItem(b, 1)->valuedouble,
               cJSON_GetArrayItem(b, 2)->valuedouble);
    cJSON_Delete(j);
    free(text);
  }
}

/* eval --sun: original and cloud lit alike by an engine's sun and ambient
 * light. The default (material) cloud follows the sun as the original
 * does; a baked cloud, drawn unlit, is far too bright under the same
 * lights (what three.js shows, docs/lighting.md). Bad values are said. */
static void test_sun(void **state) {
  (void)state;
  char path[1024], args[4096], *out, *err;
  tu_data_path(path, sizeof path, "trees/quaternius/OBJ/Tree_3.obj");
  if (!tu_have_file(path)) skip();
  const char *clouds[2] = {"", "--lighting baked"};
  double lum[2][2];
  for (int c = 0; c < 2; c++) {
    snprintf(args, sizeof args, "'%s' -o '%s/sun%d.glb' --texres 64 %s", path, tu_dir, c,
             clouds[c]);
    assert_int_equal(cli_run(args, &out, &err), 0);
    assert_non_null(strstr(err, c ? "lighting: baked" : "lighting: material"));
    free(out);
    free(err);
    for (int s = 0; s < 2; s++) {
      snprintf(args, sizeof args,
               "eval '%s' '%s/sun%d.glb' --views 8 --size 96 --sun %s --json '%s/sun.json'", path,
               tu_dir, c, s ? "180,15" : "0,50", tu_dir);
      assert_int_equal(cli_run(args, &out, &err), 0);
      assert_non_null(strstr(out, "luminance ratio over 1 sun:"));
      free(out);
      free(err);
      char jp[1200];
      snprintf(jp, sizeof jp, "%s/sun.json", tu_dir);
      char *text = (char *)tu_read_file(jp, NULL);
      cJSON *j = cJSON_Parse(text);
      const cJSON *s0 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "suns"), 0);
      lum[c][s] = cJSON_GetObjectItemCaseSensitive(s0, "luminance_ratio")->valuedouble;
      cJSON_Delete(j);
      free(text);
    }
  }
  for (int s = 0; s < 2; s++) {
    if (!(lum[0][s] > 0.85 && lum[0][s] < 1.15)) fail_msg("material cloud: %.3f", lum[0][s]);
    if (!(lum[1][s] > 1.3)) fail_msg("baked cloud, drawn unlit: %.3f", lum[1][s]);
  }
  /* The sweep: 16 suns, a line each and the range. */
  snprintf(args, sizeof args, "eval '%s' '%s/sun0.glb' --views 4 --size 64 --sun sweep", path,
           tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 0);
  int rows = 0;
  for (const char *p = out; (p = strstr(p, "\n")) != NULL; p++) rows += p[1] == ' ';
  assert_int_equal(rows, 16);
  assert_non_null(strstr(out, "luminance ratio over 16 suns:"));
  free(out);
  free(err);
  const char *bad[] = {"--sun 400,0", "--sun 30", "--sun north", "--sun-ambient 0 --sun 0,0"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(args, sizeof args, "eval '%s' '%s/sun0.glb' %s", path, tu_dir, bad[i]);
    assert_int_equal(cli_run(args, &out, &err), 1);
    assert_non_null(strstr(err, "--sun"));
    free(out);
    free(err);
  }
  snprintf(args, sizeof args, "'%s' -o '%s/x.glb' --lighting sunny", path, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 1);
  assert_non_null(strstr(err, "--lighting: 'material'"));
  free(out);
  free(err);
}

/* bbcgen impostor (issue 49): the descriptor and both atlases written, eval
 * judges the .json like a model, baseline --method impostor makes one too,
 * --check says how well its frames show the model;
 * its mistakes named: an output that is no .json, too few frames or
 * texels, a missing model. */
static void test_impostor_command(void **state) {
  (void)state;
  char args[4096], *out, *err;
  snprintf(args, sizeof args, "tree --leaves 500 --seed 4 -o '%s/it.obj'", tu_dir);
  if (cli_run(args, &out, &err)) fail_msg("%s", err);
  free(out);
  free(err);
  snprintf(args, sizeof args,
           "impostor '%s/it.obj' -o '%s/it.json' --frames 4 --texels 16384 --check", tu_dir,
           tu_dir);
  if (cli_run(args, &out, &err)) fail_msg("%s", err);
  assert_non_null(strstr(err, "4 x 4 frames of 32 texels"));
  /* --check: how well the frames show the model, on stdout */
  const char *ck = strstr(out, "frames against the model: block IoU worst ");
  assert_non_null(ck);
  double worst = atof(ck + strlen("frames against the model: block IoU worst "));
  print_message("%s", ck);
  assert_true(worst > 0.8 && worst <= 1.0);
  free(out);
  free(err);
  assert_true(cli_file_exists(tu_dir, "it.json"));
  assert_true(cli_file_exists(tu_dir, "it_json_albedo.png"));
  assert_true(cli_file_exists(tu_dir, "it_json_normal.png"));
  snprintf(args, sizeof args,
           "eval '%s/it.obj' '%s/it.json' --views 8 --size 64 --json '%s/ie.json'", tu_dir, tu_dir,
           tu_dir);
  if (cli_run(args, &out, &err)) fail_msg("%s", err);
  free(out);
  free(err);
  char p[1200];
  snprintf(p, sizeof p, "%s/ie.json", tu_dir);
  char *text = (char *)tu_read_file(p, NULL);
  cJSON *e = cJSON_Parse(text);
  assert_non_null(e);
  double cov = cli_num(e, "coverage_ratio_mean");
  print_message("impostor of 4 x 4 frames: iou %.3f, coverage %.3f\n", cli_num(e, "iou_mean"), cov);
  /* a coarse impostor (16 frames over the upper half), judged also from
   * below: the plumbing, not its quality (test_impostor) */
  assert_true(cli_num(e, "block_iou_mean") > 0.3);
  assert_true(cov > 0.6 && cov < 1.5);
  cJSON_Delete(e);
  free(text);
  snprintf(args, sizeof args,
           "baseline '%s/it.obj' -o '%s/ib.json' --method impostor --texels 16384 -q", tu_dir,
           tu_dir);
  if (cli_run(args, &out, &err)) fail_msg("%s", err);
  free(out);
  free(err);
  assert_true(cli_file_exists(tu_dir, "ib_json_albedo.png"));
  static const struct {
    const char *args, *says; /* after "-o DIR/" */
  } bad[] = {{"x.png", ".json"},
             {"x.json --frames 1", "--frames"},
             {"x.json --texels 100", "--texels"},
             {"x.json --frames 64 --texels 4096", "texels"},
             {"x.json --colours 3", "unknown option"}};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(args, sizeof args, "impostor '%s/it.obj' -o '%s/'%s", tu_dir, tu_dir, bad[i].args);
    assert_int_equal(cli_run(args, &out, &err), 1);
    if (!strstr(err, bad[i].says)) fail_msg("'%s': %s", bad[i].args, err);
    free(out);
    free(err);
  }
  snprintf(args, sizeof args, "impostor '%s/none.obj' -o '%s/x.json'", tu_dir, tu_dir);
  assert_int_equal(cli_run(args, &out, &err), 2);
  free(out);
  free(err);
  assert_false(cli_file_exists(tu_dir, "x.json"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cloud_command),
      cmocka_unit_test(test_hand_epsilon_kept),
      cmocka_unit_test(test_impostor_command),
      cmocka_unit_test(test_suggestions),
      cmocka_unit_test(test_materials_and_texture_names),
      cmocka_unit_test(test_atlas_budget),
      cmocka_unit_test(test_unknown_part),
      cmocka_unit_test(test_brightness),
      cmocka_unit_test(test_sun),
  };
  return cmocka_run_group_tests(tests, tu_group_setup, tu_group_teardown);
}
