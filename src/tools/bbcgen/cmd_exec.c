/* cmd_exec.c — `bbcgen exec FILE`: batch files in the thesis's command
 * language (Appendix A), as far as the toolkit implements it today. One
 * command per line; '#' starts a comment line.
 *
 *   load PATH            the model for the following commands
 *   set NAME VALUE       a parameter (also PART.NAME: trunk, foliage, all)
 *   split MODE           auto | none | names | geometry
 *   split trunk=PATTERNS   or  split foliage=PATTERNS   (group/material globs)
 *   bbc1                 step 1: the dual grid and its density, kept
 *   bbc2                 step 2 on the kept grid: the planes, kept; after a
 *                        change of step-2 parameters only (Appendix A's '+');
 *                        any other change asks for bbc1 again, saying which
 *   planes [OUT.json]    steps 1 and 2, the planes as JSON
 *   bbc3                 step 3 on the planes of the last bbc2 or bbc, which are
 *                        kept: after a change of texturing parameters only
 *                        (Appendix A's '*': texres, quality, nm, prelight, ...);
 *                        any other change asks for bbc1/bbc2 again, saying which
 *   bbc                  steps 1 to 3
 *   shade N [AMBIENT]    voxel shadowing for the next step 3 (N = 0: off;
 *                        AMBIENT 0 or omitted = 0.4, as in the thesis)
 *   save [DIR]           the last cloud as VRML into
 *                        vrml97models/[DIR/]<model>/<model>_eX.XX_texN[_nm][_pl]/
 *   setup                print the parameters
 *   exec FILE            run another batch file (nested, 8 deep at most)
 *   help [COMMAND]       the commands, or one
 *   cls                  clear the screen (at the prompt)
 *   q, quit              stop
 *   show model [KEYS]    the viewer in a window (keys script it)
 *   show bbc [KEYS]      the algorithm's internals: a face's validity domain on
 *                        the grid (discretised, continuous, both), the grid's
 *                        density, the faces of its plane
 *   bbcload FILE         a saved cloud, shown by show model in place of the cloud
 *                        (until the next bbc or bbc3), to compare with the model
 *
 * The prompt (`bbcgen -i`, `bbcgen -x FILE`, `bbcgen` on a terminal) runs
 * the same commands line by line; an error is reported and the session
 * goes on. Line editing, history and completion come from libedit. */
#include "pipeline.h"

#include <ctype.h>
#include <dirent.h>
#include <signal.h>
#include <editline/readline.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *trim(char *s) {
  while (isspace((unsigned char)*s)) s++;
  size_t n = strlen(s);
  while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
  return s;
}

/* What a session of commands keeps between them. */
typedef struct batch {
  char model[4096];
  char pattern[2][4096];
  bbc_session *sess; /* the model, planes and cloud (the library's session) */
  bbc_mesh loaded;   /* bbcload's cloud */
  int show_loaded;   /* 1: show model shows `loaded` (bbcload came after bbc/bbc3) */
  int depth;         /* nested exec */
  int quit;
} batch;

static const struct {
  const char *name, *args, *what;
} k_commands[] = {
    {"load", "FILE [nocg] [nomip]",
     "the model (it stays where it is); nomip: its textures without mipmaps"},
    {"set", "NAME VALUE", "a parameter (PART.NAME for one part: trunk, foliage)"},
    {"split", "MODE",
     "trunk and foliage: auto, none, names, geometry, trunk=PATTERNS, foliage=..."},
    {"bbc1", "", "step 1: the dual grid and its density (kept for bbc2)"},
    {"bbc2", "", "step 2 on the kept grid: the planes (kept for bbc3)"},
    {"bbc3", "", "step 3 on the kept planes (after texturing changes only)"},
    {"bbc", "", "steps 1 to 3"},
    {"planes", "[OUT.json]", "steps 1 and 2, the planes as JSON"},
    {"shade", "N [AMBIENT]", "voxel shadowing for the next step 3 (0 = off)"},
    {"save", "[DIR]", "the cloud as VRML into vrml97models/[DIR/]MODEL/MODEL_eX.XX_texN.../"},
    {"setup", "", "print every parameter"},
    {"exec", "FILE", "run a batch file"},
    {"bbcload", "FILE", "a saved cloud, shown by show model to compare with the model"},
    {"show", "model|bbc [KEYS]",
     "a window: the model, rectangles, cloud; or the grid's domains, density, faces (Esc returns)"},
    {"help", "[COMMAND]", "the commands, or one"},
    {"cls", "", "clear the screen"},
    {"quit", "", "stop (also q)"},
};
#define COMMAND_COUNT (sizeof k_commands / sizeof k_commands[0])

static int exec_file(cli *c, batch *b, const char *file);

/* After bbc or bbc3: what save names the folder by, the computed cloud
 * shown again (not bbcload's), the info line. */
static void made_cloud(const cli *c, batch *b, int step3_only) {
  b->show_loaded = 0;
  session_info(c, b->sess, 0, step3_only);
}

static void help(const char *which) {
  for (size_t i = 0; i < COMMAND_COUNT; i++)
    if (!which || !strcmp(which, k_commands[i].name))
      printf("  %-7s %-19s %s\n", k_commands[i].name, k_commands[i].args, k_commands[i].what);
}

/* One command line (already trimmed, not empty). In a batch file every
 * error names file:line (cli_location, set by exec_file). */
static int exec_command(cli *c, batch *b, char *s) {
  char *cmd = strtok(s, " \t");
  char *a1 = strtok(NULL, " \t");
  char *a2 = strtok(NULL, "");
  if (a2) a2 = trim(a2);
  int rc = EXIT_OK;
  if (!strcmp(cmd, "q") || !strcmp(cmd, "quit")) {
    b->quit = 1;
  } else if (!strcmp(cmd, "load")) {
    if (!a1) goto missing;
    /* Appendix A: load FILE [nocg] [nomip]. nocg (the model stays where it
     * is, not moved to its centre of gravity) is how models always load
     * here; nomip: the model's textures without mipmaps (baking, viewer). */
    bbc_load_options lo;
    cli_load_options(c, &lo);
    for (char *w = a2 ? strtok(a2, " \t") : NULL; w; w = strtok(NULL, " \t")) {
      if (!strcmp(w, "nomip")) {
        lo.no_mipmaps = 1;
      } else if (strcmp(w, "nocg")) {
        cli_error("load: '%s' is not a flag (load FILE [nocg] [nomip])", w);
        return EXIT_USAGE;
      }
    }
    bbc_error e;
    if (bbc_session_load(b->sess, a1, &lo, &e) != BBC_OK) return cli_fail(&e, 0);
    snprintf(b->model, sizeof b->model, "%s", a1);
  } else if (!strcmp(cmd, "set")) {
    if (!a1 || !a2) goto missing;
    const char *dot = strchr(a1, '.'), *name = dot ? dot + 1 : a1;
    if (!bbc_param_find(name)) {
      const char *list[128];
      size_t n = 0;
      for (size_t i = 0; i < bbc_param_count() && n < 127; i++) list[n++] = bbc_param_at(i)->name;
      list[n] = NULL;
      const char *near = cli_closest(name, list);
      cli_error("set: no parameter '%s'%s%s%s (setup lists them)", name,
                near ? " (did you mean " : "", near ? near : "", near ? "?)" : "");
      return EXIT_USAGE;
    }
    char assignment[512];
    snprintf(assignment, sizeof assignment, "%s=%s", a1, a2);
    char *fake[2] = {"--set", assignment};
    int i = 0;
    int k = cli_common_option(c, 2, fake, &i);
    if (k == 0) cli_error("bad set command");
    if (k != 1) rc = EXIT_USAGE;
  } else if (!strcmp(cmd, "split")) {
    if (!a1) goto missing;
    if (!strncmp(a1, "trunk=", 6) || !strncmp(a1, "foliage=", 8)) {
      int t = a1[0] == 't';
      snprintf(b->pattern[t], sizeof b->pattern[t], "%s", strchr(a1, '=') + 1);
      char opt[16];
      snprintf(opt, sizeof opt, "--%s", t ? "trunk" : "foliage");
      char *fake[2] = {opt, b->pattern[t]};
      int i = 0;
      if (!b->pattern[t][0]) {
        cli_error("split %s= needs patterns", t ? "trunk" : "foliage");
        rc = EXIT_USAGE;
      } else if (cli_common_option(c, 2, fake, &i) != 1) {
        cli_error("bad split command");
        rc = EXIT_USAGE;
      }
    } else {
      char *fake[2] = {"--split", a1};
      int i = 0;
      if (cli_common_option(c, 2, fake, &i) != 1) {
        cli_error("bad split command");
        rc = EXIT_USAGE;
      }
    }
  } else if (!strcmp(cmd, "setup")) {
    char *fake[1] = {"setup"};
    rc = cmd_setup(c, 1, fake);
  } else if (!strcmp(cmd, "help")) {
    if (a1 && !strcmp(a1, "q")) a1 = "quit";
    int known = !a1;
    for (size_t i = 0; a1 && i < COMMAND_COUNT; i++) known |= !strcmp(a1, k_commands[i].name);
    if (!known) {
      cli_error("help: no command '%s' (help lists them)", a1);
      rc = EXIT_USAGE;
    } else {
      help(a1);
    }
  } else if (!strcmp(cmd, "cls")) {
    if (isatty(1)) fputs("\033[H\033[2J", stdout);
  } else if (!strcmp(cmd, "exec")) {
    if (!a1) goto missing;
    if (b->depth >= 8) {
      cli_error("exec %s: batch files nested more than 8 deep", a1);
      rc = EXIT_USAGE;
    } else {
      b->depth++;
      rc = exec_file(c, b, a1);
      b->depth--;
    }
  } else if (!strcmp(cmd, "bbc1")) {
    if (!b->model[0]) goto noload;
    bbc_planes_options po;
    if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
    bbc_error e;
    double t0 = cli_now();
    if (bbc_session_grid(b->sess, &po, &e) != BBC_OK) return cli_fail_in(b->model, &e, 0);
    cli_info(c, "step 1: the grid in %.2f s (bbc2 finds the planes on it)", cli_now() - t0);
  } else if (!strcmp(cmd, "planes")) {
    if (!b->model[0]) goto noload;
    rc = run_planes(c, b->model, a1);
  } else if (!strcmp(cmd, "bbc2")) {
    if (!b->model[0]) goto noload;
    bbc_planes_options po;
    if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
    const char *which = NULL;
    int stale = bbc_session_grid_stale(b->sess, &po, &which);
    if (stale < 0) {
      cli_error("bbc2 needs the grid of bbc1 first (or run bbc)");
      return EXIT_USAGE;
    }
    if (stale) {
      cli_error("bbc2: %s changed since bbc1, and it needs step 1 again: run bbc1 (or bbc)", which);
      return EXIT_USAGE;
    }
    bbc_error e;
    debug_views_begin(c, bbc_session_model(b->sess), &po);
    bbc_result r = bbc_session_planes(b->sess, &po, &e);
    debug_views_end();
    if (r != BBC_OK) return cli_fail_in(b->model, &e, 0);
    session_info(c, b->sess, 0, 1);
  } else if (!strcmp(cmd, "bbc3")) {
    if (!b->model[0]) goto noload;
    bbc_planes_options po;
    if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
    const char *which = NULL;
    int step = bbc_session_stale(b->sess, &po, &which);
    if (step < 0) {
      cli_error("bbc3 needs the planes of bbc2 (after bbc1) or bbc first");
      return EXIT_USAGE;
    }
    if (step == 1 || step == 2) {
      cli_error("bbc3: %s changed since the planes were found, and it needs step %d again: "
                "run %s",
                which, step, step == 1 ? "bbc1 and bbc2 (or bbc)" : "bbc2 (or bbc)");
      return EXIT_USAGE;
    }
    bbc_error e;
    if (bbc_session_cloud(b->sess, &po, &e) != BBC_OK) return cli_fail_in(b->model, &e, 0);
    made_cloud(c, b, 1);
  } else if (!strcmp(cmd, "bbc")) {
    if (!b->model[0]) goto noload;
    bbc_planes_options po;
    if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
    bbc_error e;
    debug_views_begin(c, bbc_session_model(b->sess), &po);
    bbc_result r = bbc_session_run(b->sess, &po, &e);
    debug_views_end();
    if (r != BBC_OK) return cli_fail_in(b->model, &e, 0);
    made_cloud(c, b, 0);
  } else if (!strcmp(cmd, "shade")) {
    if (!a1) goto missing;
    char *e1, *e2 = NULL;
    long n = strtol(a1, &e1, 10);
    double amb = a2 ? strtod(a2, &e2) : 0;
    if (*e1 || n < 0 || n > 512 || (a2 && (*e2 || !(amb >= 0 && amb <= 1)))) {
      cli_error("shade NUMVOXELS [AMBIENT]: voxels 0..512, ambient 0..1");
      return EXIT_USAGE;
    }
    c->params.shade_voxels = (int)n;
    c->params.shade_ambient = amb > 0 ? amb : 0.4;
  } else if (!strcmp(cmd, "save")) {
    const bbc_cloud *cloud = bbc_session_result(b->sess);
    if (!cloud) {
      cli_error("save needs a Billboard Cloud: run bbc or bbc3 first");
      return EXIT_USAGE;
    }
    rc = session_save(c, b->sess, a1);
  } else if (!strcmp(cmd, "show")) {
    /* show model|bbc [KEYS...]: the window; keys script it (tests) */
    if (!a1 || (strcmp(a1, "model") && strcmp(a1, "bbc"))) {
      cli_error("show %s: expected show model or show bbc", a1 ? a1 : "needs model or bbc:");
      return EXIT_USAGE;
    }
    if (!b->model[0]) goto noload;
    bbc_cloud wrap; /* a loaded cloud: its mesh, no rectangles */
    memset(&wrap, 0, sizeof wrap);
    wrap.mesh = b->loaded;
    const bbc_cloud *cl = b->show_loaded ? &wrap : bbc_session_result(b->sess);
    rc = show_window(c, b->sess, cl, a1[0] == 'b', a2);
  } else if (!strcmp(cmd, "bbcload")) {
    if (!a1) goto missing;
    bbc_load_options lo;
    cli_load_options(c, &lo);
    bbc_mesh m;
    bbc_error e;
    if (bbc_mesh_load(a1, &lo, &m, &e) != BBC_OK) return cli_fail(&e, 0);
    bbc_mesh_free(&b->loaded);
    b->loaded = m;
    b->show_loaded = 1;
    cli_info(c, "bbcload %s: %zu triangles; show model shows it as the cloud", a1,
             m.triangle_count);
  } else {
    cli_error("'%s' is not a command (help lists them)", cmd);
    rc = EXIT_USAGE;
  }
  return rc;
missing:
  cli_error("%s needs %s", cmd, !strcmp(cmd, "set") ? "NAME VALUE" : "an argument");
  return EXIT_USAGE;
noload:
  cli_error("%s before load", cmd);
  return EXIT_USAGE;
}

/* A batch file: stops at its first error (or quit). */
static int exec_file(cli *c, batch *b, const char *file) {
  struct stat st;
  if (stat(file, &st) == 0 && S_ISDIR(st.st_mode)) {
    cli_error("%s: is a folder, not a batch file", file);
    return EXIT_INPUT;
  }
  FILE *f = fopen(file, "r");
  if (!f) {
    cli_error("%s: cannot open batch file", file);
    return EXIT_INPUT;
  }
  char line[4096];
  int lineno = 0, rc = EXIT_OK;
  while (rc == EXIT_OK && !b->quit && fgets(line, sizeof line, f)) {
    lineno++;
    char *s = trim(line);
    if (!*s || *s == '#') continue;
    char loc[4200];
    snprintf(loc, sizeof loc, "%s:%d: ", file, lineno);
    const char *outer = cli_location;
    cli_location = loc;
    rc = exec_command(c, b, s);
    cli_location = outer;
  }
  fclose(f);
  return rc;
}

int cmd_exec(cli *c, int argc, char **argv) {
  const char *file = NULL;
  for (int i = 1; i < argc; i++) {
    int k = cli_common_option(c, argc, argv, &i);
    if (k < 0) return EXIT_USAGE;
    if (k) continue;
    if (!file && argv[i][0] != '-')
      file = argv[i];
    else {
      cli_error("exec: usage: bbcgen exec BATCHFILE");
      return EXIT_USAGE;
    }
  }
  if (!file) {
    cli_error("exec: usage: bbcgen exec BATCHFILE");
    return EXIT_USAGE;
  }
  batch *b = calloc(1, sizeof *b);
  if (b) b->sess = bbc_session_new();
  if (!b || !b->sess) {
    free(b);
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  int rc = exec_file(c, b, file);
  bbc_session_free(b->sess);
  bbc_mesh_free(&b->loaded);
  free(b);
  return rc;
}

/* ---- the prompt ---------------------------------------------------------------- */

/* Completion: command names first on the line, parameter names after
 * `set`, command names after `help`, file names elsewhere. */
static char *complete_word(const char *text, int state, int params) {
  static size_t i;
  if (!state) i = 0;
  size_t n = strlen(text);
  if (params) {
    while (i < bbc_param_count()) {
      const char *name = bbc_param_at(i++)->name;
      if (!strncmp(name, text, n)) return strdup(name);
    }
  } else {
    while (i < COMMAND_COUNT) {
      const char *name = k_commands[i++].name;
      if (!strncmp(name, text, n)) return strdup(name);
    }
  }
  return NULL;
}
static char *complete_command(const char *text, int state) {
  return complete_word(text, state, 0);
}
static char *complete_param(const char *text, int state) {
  return complete_word(text, state, 1);
}

static char **complete(const char *text, int start, int end) {
  (void)end;
  int first = 1;
  for (int i = 0; i < start; i++) first &= isspace((unsigned char)rl_line_buffer[i]) != 0;
  if (first) return rl_completion_matches(text, complete_command);
  if (!strncmp(rl_line_buffer, "set ", 4) && start == 4)
    return rl_completion_matches(text, complete_param);
  if (!strncmp(rl_line_buffer, "help ", 5)) return rl_completion_matches(text, complete_command);
  return NULL; /* file names */
}

static void on_interrupt(int sig) {
  (void)sig;
  cli_interrupted = 1;
}

int cmd_prompt(cli *c, const char *batch_file) {
  batch *b = calloc(1, sizeof *b);
  if (b) b->sess = bbc_session_new();
  if (!b || !b->sess) {
    free(b);
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  int rc = EXIT_OK;
  if (batch_file) {
    rc = exec_file(c, b, batch_file);
    if (b->quit) {
      bbc_session_free(b->sess);
      bbc_mesh_free(&b->loaded);
      free(b);
      return rc;
    }
  }
  int tty = isatty(0) && isatty(1);
  if (tty) {
    rl_readline_name = "bbcgen";
    rl_attempted_completion_function = complete;
    using_history();
    printf("bbcgen %s: the thesis's commands (help lists them; quit ends)\n", BBC_VERSION_STRING);
  }
  char buf[4096];
  while (!b->quit) {
    char *line = NULL;
    if (tty) {
      line = readline("bbcgen> ");
      if (!line) break;
    } else {
      if (!fgets(buf, sizeof buf, stdin)) break;
      line = strdup(buf);
      if (!line) break;
    }
    char *s = trim(line);
    if (*s && *s != '#') {
      if (tty) add_history(s);
      /* at the prompt an error is reported and the session goes on; Ctrl-C
       * stops a long step and leaves the session as it was before it */
      struct sigaction sa, old;
      memset(&sa, 0, sizeof sa);
      sa.sa_handler = on_interrupt;
      sigemptyset(&sa.sa_mask);
      cli_interrupted = 0;
      sigaction(SIGINT, &sa, &old);
      int r = exec_command(c, b, s);
      if (r != EXIT_OK) rc = r; /* the status: the last command that failed (0: none) */
      sigaction(SIGINT, &old, NULL);
      if (cli_interrupted)
        cli_error("interrupted: the session is as it was before '%s'", strtok(s, " \t"));
      cli_interrupted = 0;
    }
    free(line);
    fflush(stdout);
  }
  if (tty && !b->quit) putchar('\n');
  bbc_session_free(b->sess);
  bbc_mesh_free(&b->loaded);
  free(b);
  return rc;
}
