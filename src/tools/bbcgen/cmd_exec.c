/* cmd_exec.c — `bbcgen exec FILE`: batch files in the thesis's command
 * language (Appendix A), as far as the toolkit implements it today. One
 * command per line; '#' starts a comment line.
 *
 *   load PATH            the model for the following commands
 *   set NAME VALUE       a parameter (also PART.NAME: trunk, foliage, all)
 *   split MODE           auto | none | names | geometry
 *   split trunk=PATTERNS   or  split foliage=PATTERNS   (group/material globs)
 *   bbc1, bbc2           steps 1 and 2 (they run together at bbc2)
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
 *   q, quit              stop
 * Not implemented: show, bbcload (interactive viewing). */
#include "pipeline.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char *trim(char *s) {
  while (isspace((unsigned char)*s)) s++;
  size_t n = strlen(s);
  while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
  return s;
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
  char line[4096], model[4096] = "", pattern[2][4096];
  int lineno = 0, rc = EXIT_OK, want_steps = 0, have_job = 0, have_cloud = 0;
  int split_gen = 0, planned_split = 0; /* split commands so far, and at the planes */
  bbc_params planned;                   /* the parameters the planes were found with */
  job jb;
  memset(&jb, 0, sizeof jb);
  memset(&planned, 0, sizeof planned);
  while (rc == EXIT_OK && fgets(line, sizeof line, f)) {
    lineno++;
    char *s = trim(line);
    if (!*s || *s == '#') continue;
    char *cmd = strtok(s, " \t");
    char *a1 = strtok(NULL, " \t");
    char *a2 = strtok(NULL, "");
    if (a2) a2 = trim(a2);
    if (!strcmp(cmd, "q") || !strcmp(cmd, "quit")) break;
    if (!strcmp(cmd, "load")) {
      if (!a1) goto missing;
      snprintf(model, sizeof model, "%s", a1);
      want_steps = 0;
      if (have_job) job_free(&jb);
      have_job = have_cloud = 0;
    } else if (!strcmp(cmd, "set")) {
      if (!a1 || !a2) goto missing;
      char assignment[512];
      snprintf(assignment, sizeof assignment, "%s=%s", a1, a2);
      char *fake[2] = {"--set", assignment};
      int i = 0;
      if (cli_common_option(c, 2, fake, &i) != 1) {
        cli_error("%s:%d: bad set command", file, lineno);
        rc = EXIT_USAGE;
      }
    } else if (!strcmp(cmd, "split")) {
      if (!a1) goto missing;
      split_gen++;
      if (!strncmp(a1, "trunk=", 6) || !strncmp(a1, "foliage=", 8)) {
        int t = a1[0] == 't';
        snprintf(pattern[t], sizeof pattern[t], "%s", strchr(a1, '=') + 1);
        char opt[16];
        snprintf(opt, sizeof opt, "--%s", t ? "trunk" : "foliage");
        char *fake[2] = {opt, pattern[t]};
        int i = 0;
        if (!pattern[t][0]) {
          cli_error("%s:%d: split %s= needs patterns", file, lineno, t ? "trunk" : "foliage");
          rc = EXIT_USAGE;
        } else if (cli_common_option(c, 2, fake, &i) != 1) {
          cli_error("%s:%d: bad split command", file, lineno);
          rc = EXIT_USAGE;
        }
      } else {
        char *fake[2] = {"--split", a1};
        int i = 0;
        if (cli_common_option(c, 2, fake, &i) != 1) {
          cli_error("%s:%d: bad split command", file, lineno);
          rc = EXIT_USAGE;
        }
      }
    } else if (!strcmp(cmd, "setup")) {
      char *fake[1] = {"setup"};
      rc = cmd_setup(c, 1, fake);
    } else if (!strcmp(cmd, "bbc1")) {
      if (!model[0]) goto noload;
      want_steps = 1;
    } else if (!strcmp(cmd, "planes")) {
      if (!model[0]) goto noload;
      rc = run_planes(c, model, a1);
    } else if (!strcmp(cmd, "bbc2")) {
      if (!model[0]) goto noload;
      if (!want_steps) {
        cli_error("%s:%d: bbc2 needs bbc1 first", file, lineno);
        rc = EXIT_USAGE;
        break;
      }
      if (have_job) job_free(&jb);
      have_job = have_cloud = 0;
      rc = job_plan(c, model, &jb);
      have_job = rc == EXIT_OK;
      planned = c->params;
      planned_split = split_gen;
      want_steps = 0;
    } else if (!strcmp(cmd, "bbc3")) {
      if (!model[0]) goto noload;
      if (!have_job) {
        cli_error("%s:%d: bbc3 needs the planes of bbc2 (after bbc1) or bbc first", file, lineno);
        rc = EXIT_USAGE;
        break;
      }
      const char *which = NULL;
      int step = bbc_params_first_step(&planned, &c->params, &which);
      if (split_gen != planned_split) step = 1, which = "split";
      if (step == 1 || step == 2) {
        cli_error("%s:%d: bbc3: %s changed since the planes were found, and it needs step %d "
                  "again: run %s",
                  file, lineno, which, step,
                  step == 1 ? "bbc1 and bbc2 (or bbc)" : "bbc2 (or bbc)");
        rc = EXIT_USAGE;
        break;
      }
      rc = job_texture(c, &jb);
      have_cloud = rc == EXIT_OK;
    } else if (!strcmp(cmd, "bbc")) {
      if (!model[0]) goto noload;
      if (have_job) job_free(&jb);
      have_job = have_cloud = 0;
      rc = job_run(c, model, NULL, 0, &jb);
      have_job = have_cloud = rc == EXIT_OK;
      planned = c->params;
      planned_split = split_gen;
    } else if (!strcmp(cmd, "shade")) {
      if (!a1) goto missing;
      char *e1, *e2 = NULL;
      long n = strtol(a1, &e1, 10);
      double amb = a2 ? strtod(a2, &e2) : 0;
      if (*e1 || n < 0 || n > 512 || (a2 && (*e2 || !(amb >= 0 && amb <= 1)))) {
        cli_error("%s:%d: shade NUMVOXELS [AMBIENT]: voxels 0..512, ambient 0..1", file, lineno);
        rc = EXIT_USAGE;
        break;
      }
      c->params.shade_voxels = (int)n;
      c->params.shade_ambient = amb > 0 ? amb : 0.4;
    } else if (!strcmp(cmd, "save")) {
      if (!have_cloud) {
        cli_error("%s:%d: save needs a Billboard Cloud: run bbc or bbc3 first", file, lineno);
        rc = EXIT_USAGE;
        break;
      }
      rc = job_save_vrml(c, &jb, a1);
    } else {
      cli_error("%s:%d: '%s' is not a batch command (or not implemented yet)", file, lineno, cmd);
      rc = EXIT_USAGE;
    }
    continue;
  missing:
    cli_error("%s:%d: %s needs %s", file, lineno, cmd,
              !strcmp(cmd, "set") ? "NAME VALUE" : "an argument");
    rc = EXIT_USAGE;
    continue;
  noload:
    cli_error("%s:%d: %s before load", file, lineno, cmd);
    rc = EXIT_USAGE;
  }
  fclose(f);
  if (have_job) job_free(&jb);
  return rc;
}
