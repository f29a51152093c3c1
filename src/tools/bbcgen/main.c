/* bbcgen — the Billboard Cloud generator's command-line tool.
 * One flat dispatch: each command parses its own options into the shared
 * `cli` state and calls the library (and its application layer). */
#include "cli.h"

#include <locale.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* --help, in parts: the cloud command; the commands on a model; the prompt,
 * the batch files, the viewer and setup; the options every command takes;
 * the parameters; the exit codes. `bbcgen COMMAND --help` cuts its part out
 * of the whole (print_command_help). */
static void help_cloud(FILE *out) {
  fprintf(out,
          "bbcgen %s — Billboard Cloud generator\n"
          "\n"
          "Usage:\n"
          "  bbcgen MODEL -o OUT.glb|OUT.gltf|OUT.obj|OUT.wrl|OUT.fbx [PARAMETER OPTIONS]\n"
          "               [--lod E1,E2,... | --lod-pixels P1,P2,...] [--lod-files]\n"
          "               [--report OUT.json] [--preview OUT.png] [--preview-size PX]\n"
          "               [--lighting material|baked]\n"
          "      The Billboard Cloud of a model: steps 1 to 3, written as glTF (one atlas,\n"
          "      alphaMode MASK), OBJ+MTL+PNG, VRML (--format 0|1) + PNG, or binary FBX\n"
          "      7.4 + PNG (a LOD chain's levels as meshes <model>_LOD0, _LOD1, ... for\n"
          "      Unity's and Unreal's LOD groups; no occlusion map).\n"
          "      --lighting: material (glTF's default): the albedo, a normal map and an\n"
          "        occlusion map in a lit metallic-roughness material, for engines to\n"
          "        light under their own sun; baked (VRML's and OBJ's default, and\n"
          "        --thesis's): a fixed light baked into the colours, unlit materials,\n"
          "        for viewers without lights. The info line, the report (\"lighting\")\n"
          "        and the glTF's extras (\"bbcgen_lighting\") say which a file carries.\n"
          "      --lod: one cloud per epsilon (percent, increasing); in glTF each is a node\n"
          "        (MSFT_lod chain, finest first), OBJ/VRML get OUT_lod1.obj, ...;\n"
          "        minplanes and maxplanes are off for the chain unless set.\n"
          "      --lod-pixels: a level per screen size (the tree's height on screen in\n"
          "        pixels where the level starts, falling, e.g. 512,128,32): level 0 the\n"
          "        cloud the parameters make, each further one coarser and at most a\n"
          "        texel a pixel at its size; texels and triangles fall along any chain.\n"
          "      --lod-files: each level of a glTF chain also as OUT_LOD0.glb, ... (for\n"
          "        engines that ignore MSFT_lod); alone, the chain 512,128,32.\n"
          "      --report: parameters, per-stage times, planes, texels, atlas fill (JSON).\n"
          "      --preview: a PNG of 4 views (front, side, above, oblique) in 3 rows: the\n"
          "        original, the cloud (a row per level of a chain), the billboards'\n"
          "        outlines coloured by plane kind\n"
          "        (light blue standard, orange coplanar, pink post-tweaked, green\n"
          "        cardboard, cyan parachute, yellow stem); --preview-size: pixels per\n"
          "        view (256).\n",
          BBC_VERSION_STRING);
}

static void help_model_commands(FILE *out) {
  fputs("  bbcgen info MODEL [--json] [--no-textures]\n"
        "      Triangles, vertices, materials (texture, alpha), groups, bounding box,\n"
        "      centre of gravity and bounding radius of a model or point cloud.\n"
        "  bbcgen sample MODEL -o OUT.ply [--points N] [--seed S] [--normals]\n"
        "      A point cloud of N points (default 1,000,000) on the model's surface,\n"
        "      uniform by area, coloured as the surface: binary PLY with doubles;\n"
        "      --normals adds each point's surface normal (a scan with normals).\n"
        "  bbcgen tree [--seed S] [--leaves N] [--species NAME] [--texture-size N]\n"
        "              -o OUT.obj [--preview OUT.png]\n"
        "      Generate the built-in procedural tree as OBJ + MTL + PNG textures.\n"
        "      Species: oak (default), pine, birch, bush; airy ones: larch (sparse\n"
        "      needles on thin twigs), weeping (hanging twigs), winter (leafless oak);\n"
        "      and palm (a leaning stem and arching fronds).\n"
        "      Leaves: number of leaf quads (0: the species' default).\n"
        "  bbcgen render MODEL -o OUT.png [--size PX] [--up y|z] [--unlit]\n"
        "      Software render (no GPU) from the front, the side and above.\n"
        "  bbcgen planes MODEL [PARAMETER OPTIONS] [--json OUT.json]\n"
        "      Steps 1 and 2: the planes (n . x = d) and which plane simplifies each\n"
        "      triangle. Trunk and foliage are simplified apart (--split).\n"
        "  bbcgen eval ORIGINAL OTHER [--views N] [--size PX] [--json OUT.json]\n"
        "              [--png SHEET.png] [--lit|--no-lit] [--side-elevation DEG]\n"
        "              [--sun AZ,EL|sweep] [--upper]\n"
        "      How close OTHER (a cloud, a baseline, an impostor's .json) looks to\n"
        "      ORIGINAL: both rendered from N directions over the sphere (64; --upper:\n"
        "      the upper hemisphere only, seen from above or level),\n"
        "      coverage IoU, recall, false coverage, PSNR, colour error, brightness,\n"
        "      density (coverage ratio, block IoU at 1/8 resolution); also over side\n"
        "      views (elevation within --side-elevation, 30 degrees). Lit when OTHER\n"
        "      is prelit (all its materials unlit), else unlit; --lit / --no-lit\n"
        "      choose. A chain: each level alone at its own screen size, a line (and a\n"
        "      JSON 'levels' entry) each.\n"
        "  bbcgen baseline MODEL -o OUT.glb --method crossed [--planes K] [--horizontal]\n"
        "              [--texels N]\n"
        "  bbcgen baseline MODEL -o OUT.glb --method simplify|sloppy --triangles N\n"
        "  bbcgen baseline MODEL -o OUT.json --method impostor [--texels N]\n"
        "      Far-LOD alternatives to compare with `eval`: K crossed billboards (3)\n"
        "      baked by our baker at about N texels, meshoptimizer's simplification,\n"
        "      or an octahedral impostor of about N texels (bbcgen impostor).\n"
        "  bbcgen impostor MODEL -o OUT.json [--frames N] [--texels N] [--full]\n"
        "              [--samples K] [--check]\n"
        "      The octahedral impostor engines bake for far trees: the model rendered\n"
        "      from N x N directions (8) over the upper half of the sphere (--full:\n"
        "      the whole sphere) into an albedo atlas and a normal + depth atlas of\n"
        "      about N texels each (1,048,576), K x K samples a texel (4), beside the\n"
        "      descriptor OUT.json (docs/impostors.md). `eval` judges it (OTHER.json);\n"
        "      --check prints how well each frame shows the model (block IoU on the\n"
        "      frame's texels against the model drawn 4 x finer).\n",
        out);
}

static void help_session_commands(FILE *out) {
  fputs("  bbcgen -i [OPTIONS]   or   bbcgen -x BATCHFILE [OPTIONS]   or   bbcgen\n"
        "      The prompt (bbcgen alone on a terminal): the batch commands one line at\n"
        "      a time, with line editing, history and completion (Tab); an error is\n"
        "      reported and the session goes on. -x runs BATCHFILE first and stays at\n"
        "      the prompt unless the file ends with quit. `help` lists the commands.\n"
        "  bbcgen exec BATCHFILE\n"
        "      Run a batch file of commands (load, set, split, bbc1, bbc2, bbc3, bbc,\n"
        "      planes, shade, save, setup); see docs/cli.md. The planes are kept:\n"
        "      after texturing parameters only (texres, quality, nm, prelight, ...)\n"
        "      bbc3 runs step 3 alone; other changes ask for bbc2 or bbc1 again.\n"
        "  bbcgen view MODEL --mode VIEW --screenshot OUT.png [--size PX] [--yaw DEG]\n"
        "              [--pitch DEG] [--part P] [--face N] [--vertex 1|2|3|all] [--volume]\n"
        "              [--no-mini] [PARAMETER OPTIONS]\n"
        "      The viewer's nine views without a window (the prompt's `show model` and\n"
        "      `show bbc` open one). show model's: input (the model), rects (with the\n"
        "      billboards' rectangles coloured by plane kind: light blue standard,\n"
        "      orange coplanar, pink post-tweaked, green cardboard, cyan parachute,\n"
        "      yellow stem), cloud-rects, cloud. show bbc's, for a face (--part: trunk,\n"
        "      foliage or an index; --face: its index in the part, default the largest\n"
        "      face of the largest part): domain (its discretised validity domain on\n"
        "      the (theta, phi, rho) grid: theta red, rho green, phi blue), continuous\n"
        "      (the exact domain's lower and upper sheets; --vertex one vertex's\n"
        "      domain, --volume lines across it), both, density (the grid's density,\n"
        "      blue to red), faces (the model as wireframe, the faces of the selected\n"
        "      face's plane blue, the face yellow); a mini-model top left unless\n"
        "      --no-mini. all: the nine as a 3 x 3 sheet. The model runs through the\n"
        "      steps each view needs, with the parameters given.\n"
        "  bbcgen setup [PARAMETER OPTIONS]\n"
        "      Print every parameter's current value (the thesis's `setup`).\n"
        "  bbcgen --help | --version\n"
        "\n",
        out);
}

static void help_options(FILE *out) {
  fputs("Point clouds (PLY without faces, XYZ, VRML PointSet) go through the same\n"
        "steps: points splatted onto the billboards (pointsize, pointsmooth,\n"
        "pointskip, pointnormals; docs/cli.md, Point clouds).\n"
        "\n"
        "Options for every command:\n"
        "  --set NAME=VALUE   set a parameter (repeatable), e.g. --set epsilon=6\n"
        "  --set PART.NAME=VALUE  a parameter for one part only: trunk, foliage or all,\n"
        "                     e.g. --set trunk.cardboard=1 --set foliage.epsilon=8\n"
        "  --split MODE       parts: auto (default: by names, else by geometry), none,\n"
        "                     names, geometry\n"
        "  --trunk PATTERNS   trunk = faces whose group or material matches a pattern\n"
        "                     (comma-separated, * and ?), the rest foliage\n"
        "  --foliage PATTERNS foliage = faces matching, the rest trunk\n"
        "  --branches foliage|trunk  the trunk part keeps only the stem and the branches\n"
        "                     go with the foliage (default, thesis 2.2.4), or keep them\n"
        "  --NAME VALUE       the same, e.g. --epsilon 6 (percent of the bounding radius)\n"
        "  --thesis           the thesis's Appendix A defaults (clustering 2, epsilon 5,\n"
        "                     quality 0, no maxplanes, no atlasmax) for what is not set\n"
        "  -q, --quiet        no progress bar and no info lines (warnings and errors stay)\n"
        "  Progress bars are drawn only when stderr is a terminal.\n"
        "\n",
        out);
}

static void print_help(FILE *out) {
  help_cloud(out);
  help_model_commands(out);
  help_session_commands(out);
  help_options(out);
  print_parameter_help(out);
  fprintf(out, "\n"
               "Exit codes:\n"
               "  0 success                      1 bad command line or parameter value\n"
               "  2 input missing or unreadable  3 input format not supported\n"
               "  4 input damaged, invalid or empty (NaN coordinates, bad indices, truncated)\n"
               "  5 output could not be written  6 out of memory\n"
               "  7 interrupted (Ctrl-C during a step at the prompt)\n"
               "  130 interrupted (Ctrl-C): the run stopped, no file half-written\n");
}

/* `bbcgen COMMAND --help`: that command's lines of the help (its usage
 * blocks), the options every command takes, the parameters for the commands
 * that run steps, and the exit codes; the whole help when COMMAND has no
 * block of its own (the cloud: `bbcgen MODEL -o OUT --help`). */
static void print_command_help(const char *cmd) {
  char *text = NULL;
  size_t size = 0;
  FILE *mem = open_memstream(&text, &size);
  if (!mem) {
    print_help(stdout);
    return;
  }
  print_help(mem);
  fclose(mem);
  char head[64];
  snprintf(head, sizeof head, "  bbcgen %s ", cmd);
  size_t hl = strlen(head);
  int found = 0;
  for (const char *p = text; *p;) {
    const char *nl = strchr(p, '\n');
    size_t n = nl ? (size_t)(nl - p) + 1 : strlen(p);
    if (!strncmp(p, head, hl) || (!strncmp(p, head, hl - 1) && p[hl - 1] == '\n')) {
      if (!found) printf("Usage:\n");
      found = 1;
      /* the block: its first line and the indented ones after it */
      const char *q = p;
      do {
        const char *e = strchr(q, '\n');
        size_t m = e ? (size_t)(e - q) + 1 : strlen(q);
        fwrite(q, 1, m, stdout);
        q += m;
      } while (*q && !strncmp(q, "   ", 3));
      p = q;
      continue;
    }
    p += n;
  }
  if (!found) {
    fputs(text, stdout);
  } else {
    const char *common = strstr(text, "\nOptions for every command:");
    const char *params = strstr(text, "\nParameters");
    const char *codes = strstr(text, "\nExit codes:");
    int steps = !strcmp(cmd, "planes") || !strcmp(cmd, "view") || !strcmp(cmd, "setup") ||
                !strcmp(cmd, "baseline");
    if (common) fwrite(common, 1, (size_t)((params ? params : codes) - common), stdout);
    if (steps && params && codes) fwrite(params, 1, (size_t)(codes - params), stdout);
    if (codes) fputs(codes, stdout);
  }
  free(text);
}

/* Ctrl-C outside the prompt: the first asks the running step to stop (the
 * library cleans up, no file is left half-written) and the run ends with
 * "interrupted" and exit 130; a second stops at once. */
static void on_sigint(int sig) {
  (void)sig;
  if (cli_interrupted) {
    static const char msg[] = "\nbbcgen: interrupted\n";
    ssize_t w = write(2, msg, sizeof msg - 1);
    (void)w;
    _exit(EXIT_SIGINT);
  }
  cli_interrupted = 1;
}

static int run_command(cli *c, const char *cmd, int argc, char **argv);

int main(int argc, char **argv) {
  /* Numbers in text formats and JSON must never get a decimal comma. */
  setlocale(LC_ALL, "C");
  cli c;
  cli_init(&c);
  /* The prompt: `bbcgen` alone on a terminal, `bbcgen -i`, `bbcgen -x FILE`. */
  if (argc < 2 && isatty(0) && isatty(1)) return cmd_prompt(&c, NULL);
  if (argc < 2) {
    print_help(stderr);
    return EXIT_USAGE;
  }
  const char *cmd = argv[1];
  if (!strcmp(cmd, "-i") || !strcmp(cmd, "-x")) {
    int i = 2;
    const char *file = NULL;
    if (cmd[1] == 'x') {
      if (argc < 3) {
        cli_error("-x needs a batch file: bbcgen -x FILE");
        return EXIT_USAGE;
      }
      file = argv[2];
      i = 3;
    }
    for (; i < argc; i++) {
      int k = cli_common_option(&c, argc, argv, &i);
      if (k < 0) return EXIT_USAGE;
      if (!k) {
        cli_error("%s: '%s' is not an option here (bbcgen -i [OPTIONS], bbcgen -x FILE "
                  "[OPTIONS])",
                  cmd, argv[i]);
        return EXIT_USAGE;
      }
    }
    return cmd_prompt(&c, file);
  }
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
    print_help(stdout);
    return EXIT_OK;
  }
  if (!strcmp(cmd, "--version") || !strcmp(cmd, "-V")) {
    printf("bbcgen %s\n", BBC_VERSION_STRING);
    return EXIT_OK;
  }
  /* `bbcgen COMMAND --help` answers too, with that command's part. */
  for (int i = 2; i < argc; i++)
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      print_command_help(cmd);
      return EXIT_OK;
    }
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  int rc = run_command(&c, cmd, argc, argv);
  if (cli_interrupted) {
    cli_error("interrupted (Ctrl-C): stopped; no file is left half-written");
    return EXIT_SIGINT;
  }
  return rc;
}

static int run_command(cli *c, const char *cmd, int argc, char **argv) {
  if (!strcmp(cmd, "info")) return cmd_info(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "tree")) return cmd_tree(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "sample")) return cmd_sample(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "render")) return cmd_render(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "setup")) return cmd_setup(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "planes")) return cmd_planes(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "eval")) return cmd_eval(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "baseline")) return cmd_baseline(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "impostor")) return cmd_impostor(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "exec")) return cmd_exec(c, argc - 1, argv + 1);
  if (!strcmp(cmd, "view")) return cmd_view(c, argc - 1, argv + 1);
  static const char *const commands[] = {"info",     "sample", "tree", "render",
                                         "setup",    "planes", "eval", "baseline",
                                         "impostor", "exec",   "view", NULL};
  if (cmd[0] == '-') {
    static const char *const own[] = {"--help", "--version", NULL};
    return cli_unknown_option(NULL, cmd, own);
  }
  /* Not a command: a model, unless no such file exists and the word looks
   * like a command (a typo, or a command we do not have). */
  struct stat st;
  if (stat(cmd, &st) != 0 && !strchr(cmd, '/') && !strchr(cmd, '.')) {
    const char *near = cli_closest(cmd, commands);
    if (near)
      cli_error("unknown command '%s' (did you mean bbcgen %s?)", cmd, near);
    else
      cli_error(
          "unknown command '%s', and no model file of that name (commands: info, sample, tree, "
          "render, planes, eval, baseline, impostor, exec, view, setup; try bbcgen --help)",
          cmd);
    return EXIT_USAGE;
  }
  /* Anything else is a model: the whole pipeline. */
  return cmd_cloud(c, argc - 1, argv + 1);
}
