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
#include <locale.h>
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
  bbc_session *sess; /* the model, planes and cloud (the application layer's session) */
  bbc_mesh loaded;   /* bbcload's cloud */
  int show_loaded;   /* 1: show model shows `loaded` (bbcload came after bbc/bbc3) */
  int depth;         /* nested exec */
  int quit;
} batch;

static int exec_file(cli *c, batch *b, const char *file);

/* After bbc or bbc3: what save names the folder by, the computed cloud
 * shown again (not bbcload's), the info line. */
static void made_cloud(const cli *c, batch *b, int step3_only) {
  b->show_loaded = 0;
  session_info(c, b->sess, 0, step3_only);
}

static void help(const char *which) {
  const bbc_command_info *only = which && *which ? bbc_command_find(which) : NULL;
  for (size_t i = 0; i < bbc_command_count(); i++) {
    const bbc_command_info *k = bbc_command_at(i);
    if (!only || only == k) printf("  %-7s %-19s %s\n", k->name, k->args, k->what);
  }
}

/* The commands one by one: each gets the parsed command `k` (its first
 * argument a1, the rest a2: NULL when absent) and returns an exit code. */

/* A command that needs a model, before any load. */
static int before_load(const bbc_command *k) {
  for (size_t i = 0; i < bbc_command_count(); i++)
    if (bbc_command_at(i)->kind == k->kind) cli_error("%s before load", bbc_command_at(i)->name);
  return EXIT_USAGE;
}

static int do_load(cli *c, batch *b, const bbc_command *k, const char *a1) {
  /* Appendix A: load FILE [nocg] [nomip]. nocg (the model stays where it
   * is, not moved to its centre of gravity) is how models always load
   * here; nomip: the model's textures without mipmaps (baking, viewer). */
  bbc_load_options lo;
  cli_load_options(c, &lo);
  lo.no_mipmaps |= k->nomip;
  bbc_error e;
  if (bbc_session_load(b->sess, a1, &lo, &e) != BBC_OK) return cli_fail(&e, 0);
  snprintf(b->model, sizeof b->model, "%s", a1);
  return EXIT_OK;
}

/* set NAME VALUE: as --set NAME=VALUE on the command line. */
static int do_set(cli *c, const bbc_command *k, const char *a1, const char *a2) {
  if (!bbc_param_find(k->name)) {
    const char *near = cli_closest_param(k->name);
    cli_error("set: no parameter '%s'%s%s%s (setup lists them)", k->name,
              near ? " (did you mean " : "", near ? near : "", near ? "?)" : "");
    return EXIT_USAGE;
  }
  char assignment[2 * BBC_COMMAND_LINE_MAX + 2];
  snprintf(assignment, sizeof assignment, "%s=%s", a1, a2);
  char *fake[2] = {"--set", assignment};
  int i = 0;
  int r = cli_common_option(c, 2, fake, &i);
  if (r == 0) cli_error("bad set command");
  return r != 1 ? EXIT_USAGE : EXIT_OK;
}

/* split MODE, split trunk=PATTERNS, split foliage=PATTERNS: as --split,
 * --trunk and --foliage (the patterns kept in the batch: the option keeps
 * a pointer to them). */
static int do_split(cli *c, batch *b, const bbc_command *k) {
  static const char *const modes[] = {"auto", "none", "names", "geometry"};
  char *fake[2] = {"--split", (char *)""};
  if (k->split == BBC_SPLIT_PATTERNS) {
    int t = k->trunk_side;
    snprintf(b->pattern[t], sizeof b->pattern[t], "%s", k->rest);
    fake[0] = t ? "--trunk" : "--foliage";
    fake[1] = b->pattern[t];
  } else {
    fake[1] = (char *)modes[k->split];
  }
  int i = 0;
  if (cli_common_option(c, 2, fake, &i) != 1) {
    cli_error("bad split command");
    return EXIT_USAGE;
  }
  return EXIT_OK;
}

static int do_exec(cli *c, batch *b, const char *a1) {
  if (b->depth >= 8) {
    cli_error("exec %s: batch files nested more than 8 deep", a1);
    return EXIT_USAGE;
  }
  b->depth++;
  int rc = exec_file(c, b, a1);
  b->depth--;
  return rc;
}

/* bbc1: step 1, the grid kept for bbc2. */
static int do_bbc1(cli *c, batch *b) {
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  bbc_error e;
  double t0 = cli_now();
  if (bbc_session_build_grid(b->sess, &po, &e) != BBC_OK) return cli_fail_in(b->model, &e, 0);
  cli_info(c, "step 1: the grid in %.2f s (bbc2 finds the planes on it)", cli_now() - t0);
  return EXIT_OK;
}

/* bbc2: step 2 on bbc1's grid, when only step-2 parameters changed since. */
static int do_bbc2(cli *c, batch *b) {
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  const char *which = NULL;
  int stale = bbc_session_grid_stale_step(b->sess, &po, &which);
  if (stale < 0) {
    cli_error("bbc2 needs the grid of bbc1 first (or run bbc)");
    return EXIT_USAGE;
  }
  if (stale) {
    cli_error("bbc2: %s changed since bbc1, and it needs step 1 again: run bbc1 (or bbc)", which);
    return EXIT_USAGE;
  }
  bbc_error e;
  debug_views_begin(c, bbc_session_get_model(b->sess), &po);
  bbc_result r = bbc_session_select_planes(b->sess, &po, &e);
  debug_views_end();
  if (r != BBC_OK) return cli_fail_in(b->model, &e, 0);
  session_info(c, b->sess, 0, 1);
  return EXIT_OK;
}

/* bbc3: step 3 on the kept planes, when only texturing parameters changed. */
static int do_bbc3(cli *c, batch *b) {
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  const char *which = NULL;
  int step = bbc_session_stale_step(b->sess, &po, &which);
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
  if (bbc_session_build_cloud(b->sess, &po, &e) != BBC_OK) return cli_fail_in(b->model, &e, 0);
  made_cloud(c, b, 1);
  return EXIT_OK;
}

/* bbc: steps 1 to 3. */
static int do_bbc(cli *c, batch *b) {
  bbc_planes_options po;
  if (cli_planes_options(c, &po) != EXIT_OK) return EXIT_USAGE;
  bbc_error e;
  debug_views_begin(c, bbc_session_get_model(b->sess), &po);
  bbc_result r = bbc_session_run(b->sess, &po, &e);
  debug_views_end();
  if (r != BBC_OK) return cli_fail_in(b->model, &e, 0);
  made_cloud(c, b, 0);
  return EXIT_OK;
}

static int do_save(cli *c, batch *b, const char *a1) {
  if (!bbc_session_get_cloud(b->sess)) {
    cli_error("save needs a Billboard Cloud: run bbc or bbc3 first");
    return EXIT_USAGE;
  }
  return session_save(c, b->sess, a1);
}

/* show model|bbc [KEYS...]: the window; keys script it (tests). */
static int do_show(cli *c, batch *b, const bbc_command *k, const char *a2) {
  bbc_cloud wrap; /* a loaded cloud: its mesh, no rectangles */
  memset(&wrap, 0, sizeof wrap);
  wrap.mesh = b->loaded;
  const bbc_cloud *cl = b->show_loaded ? &wrap : bbc_session_get_cloud(b->sess);
  return show_window(c, b->sess, cl, k->show_bbc, a2);
}

static int do_bbcload(cli *c, batch *b, const char *a1) {
  bbc_load_options lo;
  cli_load_options(c, &lo);
  bbc_mesh m;
  bbc_error e;
  if (bbc_mesh_load(a1, &lo, &m, &e) != BBC_OK) return cli_fail(&e, 0);
  bbc_mesh_free(&b->loaded);
  b->loaded = m;
  b->show_loaded = 1;
  cli_info(c, "bbcload %s: %zu triangles; show model shows it as the cloud", a1, m.triangle_count);
  return EXIT_OK;
}

/* One parsed command (bbc_command_parse has checked its words). In a batch
 * file every error names file:line (cli_location, set by exec_file). */
static int run_command(cli *c, batch *b, bbc_command *k) {
  const char *a1 = k->arg[0] ? k->arg : NULL, *a2 = k->rest[0] ? k->rest : NULL;
  int needs_model = k->kind == BBC_COMMAND_BBC1 || k->kind == BBC_COMMAND_PLANES ||
                    k->kind == BBC_COMMAND_BBC2 || k->kind == BBC_COMMAND_BBC3 ||
                    k->kind == BBC_COMMAND_BBC || k->kind == BBC_COMMAND_SHOW;
  if (needs_model && !b->model[0]) return before_load(k);
  switch (k->kind) {
  case BBC_COMMAND_QUIT:
    b->quit = 1;
    return EXIT_OK;
  case BBC_COMMAND_LOAD:
    return do_load(c, b, k, a1);
  case BBC_COMMAND_SET:
    return do_set(c, k, a1, a2);
  case BBC_COMMAND_SPLIT:
    return do_split(c, b, k);
  case BBC_COMMAND_SETUP: {
    char *fake[1] = {"setup"};
    return cmd_setup(c, 1, fake);
  }
  case BBC_COMMAND_HELP:
    help(a1);
    return EXIT_OK;
  case BBC_COMMAND_CLS:
    if (isatty(1)) fputs("\033[H\033[2J", stdout);
    return EXIT_OK;
  case BBC_COMMAND_EXEC:
    return do_exec(c, b, a1);
  case BBC_COMMAND_BBC1:
    return do_bbc1(c, b);
  case BBC_COMMAND_PLANES:
    return run_planes(c, b->model, a1);
  case BBC_COMMAND_BBC2:
    return do_bbc2(c, b);
  case BBC_COMMAND_BBC3:
    return do_bbc3(c, b);
  case BBC_COMMAND_BBC:
    return do_bbc(c, b);
  case BBC_COMMAND_SHADE:
    c->params.shade_voxels = k->shade_voxels;
    c->params.shade_ambient = k->shade_ambient > 0 ? k->shade_ambient : 0.4;
    return EXIT_OK;
  case BBC_COMMAND_SAVE:
    return do_save(c, b, a1);
  case BBC_COMMAND_SHOW:
    return do_show(c, b, k, a2);
  case BBC_COMMAND_BBCLOAD:
    return do_bbcload(c, b, a1);
  case BBC_COMMAND_NONE:
  default:
    return EXIT_OK;
  }
}

/* One line typed at the prompt (trimmed, not empty). */
static int exec_command(cli *c, batch *b, const char *s) {
  bbc_command *k = malloc(sizeof *k);
  if (!k) {
    cli_error("out of memory");
    return EXIT_RESOURCES;
  }
  bbc_error e;
  k->line = 0;
  int rc;
  if (bbc_command_parse(s, strlen(s), k, &e) != BBC_OK) {
    cli_error("%s", e.message);
    rc = EXIT_USAGE;
  } else {
    rc = run_command(c, b, k);
  }
  free(k);
  return rc;
}

/* A batch file: stops at its first error (or quit). */
static int exec_file(cli *c, batch *b, const char *file) {
  struct stat st;
  if (stat(file, &st) == 0 && S_ISDIR(st.st_mode)) {
    cli_error("%s: is a folder, not a batch file", file);
    return EXIT_INPUT;
  }
  FILE *f = fopen(file, "rb");
  if (!f) {
    cli_error("%s: cannot open batch file", file);
    return EXIT_INPUT;
  }
  /* the whole file (batch files are small: 64 MiB at most) */
  size_t size = 0, cap = 0;
  char *text = NULL;
  int rc = EXIT_OK;
  for (;;) {
    if (size == cap) {
      size_t ncap = cap ? cap * 2 : 65536;
      char *t = ncap <= ((size_t)64 << 20) ? realloc(text, ncap) : NULL;
      if (!t) {
        cli_error("%s: %s", file,
                  ncap > ((size_t)64 << 20) ? "not a batch file (over 64 MiB)" : "out of memory");
        rc = ncap > ((size_t)64 << 20) ? EXIT_INPUT : EXIT_RESOURCES;
        break;
      }
      text = t;
      cap = ncap;
    }
    size_t got = fread(text + size, 1, cap - size, f);
    size += got;
    if (!got) break;
  }
  if (rc == EXIT_OK && ferror(f)) {
    cli_error("%s: cannot read batch file", file);
    rc = EXIT_INPUT;
  }
  fclose(f);
  bbc_command *k = rc == EXIT_OK ? malloc(sizeof *k) : NULL;
  if (rc == EXIT_OK && !k) {
    cli_error("out of memory");
    rc = EXIT_RESOURCES;
  }
  size_t pos = 0;
  int lineno = 0;
  while (rc == EXIT_OK && !b->quit) {
    bbc_error e;
    if (bbc_script_next(text, size, file, &pos, &lineno, k, &e) != BBC_OK) {
      const char *outer = cli_location;
      cli_location = NULL; /* the message names file:line */
      cli_error("%s", e.message);
      cli_location = outer;
      rc = EXIT_USAGE;
      break;
    }
    if (k->kind == BBC_COMMAND_NONE) break;
    char loc[4200];
    snprintf(loc, sizeof loc, "%s:%d: ", file, lineno);
    const char *outer = cli_location;
    cli_location = loc;
    rc = run_command(c, b, k);
    cli_location = outer;
  }
  free(k);
  free(text);
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
  bbc_params_lighting(&c->params, c->hand, BBC_LIGHTING_BAKED);            /* as cmd_prompt */
  if (!bbc_params_by_hand(c->hand, "softalpha")) c->params.soft_alpha = 0; /* VRML */
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
    while (i < bbc_command_count()) {
      const char *name = bbc_command_at(i++)->name;
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
  /* The thesis's workflow, whose `save` writes VRML: a baked light, alpha
   * 0 or 255 (VRML readers may blend a softened one). */
  bbc_params_lighting(&c->params, c->hand, BBC_LIGHTING_BAKED);
  if (!bbc_params_by_hand(c->hand, "softalpha")) c->params.soft_alpha = 0;
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
    /* The line editor keeps only the characters its LC_CTYPE knows: the
     * user's, else UTF-8 (main sets "C" for every category, which would
     * drop a path's non-ASCII letters); numbers stay LC_NUMERIC "C". */
    const char *ct = setlocale(LC_CTYPE, "");
    if (!ct || !strcmp(ct, "C") || !strcmp(ct, "POSIX")) setlocale(LC_CTYPE, "C.UTF-8");
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
