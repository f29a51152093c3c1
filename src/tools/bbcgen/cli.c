/* cli.c — shared command-line machinery of bbcgen. */
#include "cli.h"

#include <ctype.h>

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <strings.h>
#include <time.h>

volatile int cli_interrupted;

static int cli_cancel(void *user) {
  (void)user;
  return cli_interrupted != 0;
}

void cli_init(cli *c) {
  memset(c, 0, sizeof *c);
  bbc_params_default(&c->params);
  c->callbacks.progress = cli_progress;
  c->callbacks.log = cli_log;
  c->callbacks.cancel = cli_cancel;
  c->callbacks.user = c;
}

const char *cli_location;

void cli_error(const char *fmt, ...) {
  char buf[8192];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  /* in a batch file every message names file:line (once) */
  size_t n = cli_location ? strlen(cli_location) : 0;
  if (n && strncmp(buf, cli_location, n))
    fprintf(stderr, "bbcgen: %s%s\n", cli_location, buf);
  else
    fprintf(stderr, "bbcgen: %s\n", buf);
}

void cli_info(const cli *c, const char *fmt, ...) {
  if (c->quiet) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
}

int cli_exit_code(bbc_result r, int output) {
  switch (r) {
  case BBC_OK:
    return EXIT_OK;
  case BBC_ERROR_INVALID_ARGUMENT:
  case BBC_ERROR_OUT_OF_RANGE:
    return EXIT_USAGE;
  case BBC_ERROR_NOT_FOUND:
  case BBC_ERROR_NOT_A_FILE:
    return EXIT_INPUT;
  case BBC_ERROR_IO:
    return output ? EXIT_OUTPUT : EXIT_INPUT;
  case BBC_ERROR_UNSUPPORTED_FORMAT:
    return EXIT_FORMAT;
  case BBC_ERROR_CORRUPT:
  case BBC_ERROR_INVALID_GEOMETRY:
  case BBC_ERROR_EMPTY:
    return EXIT_DAMAGED;
  case BBC_ERROR_CANCELLED:
    return EXIT_INTERRUPTED;
  case BBC_ERROR_OUT_OF_MEMORY:
  case BBC_RESULT_COUNT:
    break;
  }
  return EXIT_RESOURCES;
}

int cli_fail(const bbc_error *err, int output) {
  /* Ctrl-C: the caller says "interrupted" once */
  if (err->code == BBC_ERROR_CANCELLED && cli_interrupted) return EXIT_INTERRUPTED;
  cli_error("%s", err->message[0] ? err->message : bbc_result_string(err->code));
  return cli_exit_code(err->code, output);
}

const char *cli_option_value(int argc, char **argv, int *i) {
  if (*i + 1 >= argc) {
    cli_error("option %s needs a value", argv[*i]);
    return NULL;
  }
  return argv[++*i];
}

long long cli_parse_count(const char *opt, const char *text, long long max) {
  char *end;
  errno = 0;
  long long v = strtoll(text, &end, 10);
  if (end == text || *end || errno || v < 0 || v > max) {
    cli_error("option %s: '%s' is not a whole number from 0 to %lld", opt, text, max);
    return -1;
  }
  return v;
}

/* A value set by hand is meant (the application layer's rules,
 * bbc_params_note_hand). */
static void note_explicit(cli *c, const char *name_or_assignment) {
  char name[64];
  snprintf(name, sizeof name, "%.*s", (int)strcspn(name_or_assignment, "="), name_or_assignment);
  bbc_params_note_hand(&c->params, &c->hand, name);
}

int cli_common_option(cli *c, int argc, char **argv, int *i) {
  const char *a = argv[*i];
  if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) {
    c->quiet = 1;
    return 1;
  }
  if (!strcmp(a, "--thesis")) {
    /* Appendix A's defaults; parameters set by hand are kept. */
    bbc_params_thesis_merge(&c->params, c->hand);
    c->thesis = 1;
    return 1;
  }
  bbc_error err;
  if (!strcmp(a, "--split")) {
    const char *v = cli_option_value(argc, argv, i);
    if (!v) return -1;
    static const char *const modes[] = {"auto", "none", "names", "geometry"};
    for (int m = 0; m < 4; m++)
      if (!strcmp(v, modes[m])) {
        c->split.mode = (bbc_split_mode)m;
        return 1;
      }
    cli_error("--split must be auto, none, names or geometry, not '%s'", v);
    return -1;
  }
  if (!strcmp(a, "--branches")) {
    const char *v = cli_option_value(argc, argv, i);
    if (!v) return -1;
    if (strcmp(v, "trunk") && strcmp(v, "foliage")) {
      cli_error("--branches must be trunk or foliage, not '%s'", v);
      return -1;
    }
    c->branches_with_trunk = !strcmp(v, "trunk");
    return 1;
  }
  if (!strcmp(a, "--trunk") || !strcmp(a, "--foliage")) {
    const char *v = cli_option_value(argc, argv, i);
    if (!v) return -1;
    c->split.mode = BBC_SPLIT_PATTERNS;
    if (a[2] == 't') {
      c->split.trunk_patterns = v;
      if (!c->split.rest) c->split.rest = "foliage";
    } else {
      c->split.foliage_patterns = v;
      c->split.rest = "trunk";
    }
    return 1;
  }
  if (!strcmp(a, "--set")) {
    const char *v = cli_option_value(argc, argv, i);
    if (!v) return -1;
    const char *dot = strchr(v, '.'), *eq = strchr(v, '=');
    if (dot && eq && dot < eq) {
      /* A part's own parameter: check it now against a scratch copy. */
      bbc_params scratch = c->params;
      if (bbc_params_set_assignment(&scratch, dot + 1, &err) != BBC_OK) {
        cli_error("%.*s: %s", (int)(dot - v), v, err.message);
        return -1;
      }
      if (c->part_setting_count >= sizeof c->part_settings / sizeof c->part_settings[0] ||
          (size_t)(dot - v) >= sizeof c->part_settings[0].part ||
          strlen(dot + 1) >= sizeof c->part_settings[0].assignment) {
        cli_error("too many or too long part settings ('%s')", v);
        return -1;
      }
      if (!strncasecmp(dot + 1, "epsilon=", 8)) { /* kept too: the budgets go off */
        bbc_hand h = c->hand;
        bbc_params_note_hand(&c->params, &h, "epsilon");
      }
      cli_part_setting *ps = &c->part_settings[c->part_setting_count++];
      snprintf(ps->part, sizeof ps->part, "%.*s", (int)(dot - v), v);
      snprintf(ps->assignment, sizeof ps->assignment, "%s", dot + 1);
      return 1;
    }
    if (bbc_params_set_assignment(&c->params, v, &err) != BBC_OK) {
      char name[64];
      snprintf(name, sizeof name, "%.*s", (int)(eq ? (size_t)(eq - v) : strlen(v)), v);
      const char *near = bbc_param_find(name) ? NULL : cli_closest_param(name);
      cli_error("%s%s%s%s", err.message, near ? " (did you mean " : "", near ? near : "",
                near ? "?)" : "");
      return -1;
    }
    note_explicit(c, v);
    return 1;
  }
  if (!strncmp(a, "--", 2) && bbc_param_find(a + 2)) {
    const char *v = cli_option_value(argc, argv, i);
    if (!v) return -1;
    if (bbc_params_set(&c->params, a + 2, v, &err) != BBC_OK) {
      cli_error("%s", err.message);
      return -1;
    }
    note_explicit(c, a + 2);
    return 1;
  }
  return 0;
}

const char *cli_closest_param(const char *name) {
  const char *list[128];
  size_t n = 0;
  for (size_t i = 0; i < bbc_param_count() && n < 127; i++) list[n++] = bbc_param_at(i)->name;
  list[n] = NULL;
  return cli_closest(name, list);
}

int cli_unknown_option(const char *cmd, const char *arg, const char *const *own) {
  static const char *const common[] = {"--quiet",    "--set",    "--split", "--trunk", "--foliage",
                                       "--branches", "--thesis", "--help",  NULL};
  const char *list[256];
  size_t n = 0;
  for (size_t i = 0; own && own[i] && n < 64; i++) list[n++] = own[i];
  for (size_t i = 0; common[i]; i++) list[n++] = common[i];
  char names[128][40];
  for (size_t i = 0; i < bbc_param_count() && i < 128 && n < 255; i++) {
    snprintf(names[i], sizeof names[i], "--%s", bbc_param_at(i)->name);
    list[n++] = names[i];
  }
  list[n] = NULL;
  const char *near = arg[0] == '-' ? cli_closest(arg, list) : NULL;
  char pre[64] = "";
  if (cmd) snprintf(pre, sizeof pre, "%s: ", cmd);
  if (near)
    cli_error("%sunknown option '%s' (did you mean %s?)", pre, arg, near);
  else if (arg[0] == '-')
    cli_error("%sunknown option '%s' (try bbcgen --help)", pre, arg);
  else
    cli_error("%sunexpected argument '%s' (try bbcgen --help)", pre, arg);
  return EXIT_USAGE;
}

double cli_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_log(void *user, bbc_log_level level, const char *message) {
  const cli *c = user;
  if (level == BBC_LOG_INFO && c->quiet) return;
  fprintf(stderr, "bbcgen: %s%s\n", level == BBC_LOG_WARNING ? "warning: " : "", message);
}

void print_parameter_help(FILE *out) {
  static const char *const groups[] = {"performance", "plane", "billboard", "output", "extension"};
  fprintf(out, "Parameters (thesis Appendix A; set with --set NAME=VALUE or --NAME VALUE;\n"
               "* = used by step 3 only, + = can change before step 2 without redoing step 1):\n");
  for (size_t g = 0; g < sizeof groups / sizeof groups[0]; g++) {
    fprintf(out, "  %s:\n", groups[g]);
    for (size_t i = 0; i < bbc_param_count(); i++) {
      const bbc_param_info *p = bbc_param_at(i);
      if (strcmp(p->group, groups[g])) continue;
      char range[64];
      switch (p->type) {
      case BBC_PARAM_BOOL:
        snprintf(range, sizeof range, "0|1");
        break;
      case BBC_PARAM_POW2:
        snprintf(range, sizeof range, "2^n %g..%g", p->min, p->max);
        break;
      default:
        if (p->max >= 1e6)
          snprintf(range, sizeof range, ">=%g", p->min);
        else
          snprintf(range, sizeof range, "%g..%g", p->min, p->max);
      }
      char name[32];
      snprintf(name, sizeof name, "%s%s", p->name,
               p->flags & BBC_PARAM_STEP3_ONLY ? "*"
                                               : (p->flags & BBC_PARAM_KEEPS_STEP1 ? "+" : ""));
      char def[32];
      snprintf(def, sizeof def, "%g%s", p->default_value, p->unit[0] == '%' ? "%" : "");
      fprintf(out, "    %-14s %-16s default %-7s %s\n", name, range, def, p->description);
    }
  }
}

int cli_planes_options(const cli *c, bbc_planes_options *o) {
  bbc_planes_options_default(o);
  o->params = c->params;
  o->split = c->split;
  o->split.branches_with_trunk = c->branches_with_trunk;
  o->callbacks = c->callbacks;
  for (size_t i = 0; i < c->part_setting_count; i++) {
    const cli_part_setting *ps = &c->part_settings[i];
    size_t k = 0;
    while (k < o->part_override_count && strcmp(o->part_overrides[k].part, ps->part)) k++;
    if (k == o->part_override_count) {
      if (k >= sizeof o->part_overrides / sizeof o->part_overrides[0]) {
        cli_error("parameters for at most %zu parts", k);
        return EXIT_USAGE;
      }
      snprintf(o->part_overrides[k].part, sizeof o->part_overrides[k].part, "%s", ps->part);
      o->part_overrides[k].params = c->params;
      o->part_override_count++;
    }
    bbc_error err;
    if (bbc_params_set_assignment(&o->part_overrides[k].params, ps->assignment, &err) != BBC_OK) {
      cli_error("%s: %s", ps->part, err.message);
      return EXIT_USAGE;
    }
  }
  return EXIT_OK;
}

int cli_output_ok(const char *option, const char *path) {
  const char *slash = strrchr(path, '/');
  char dir[4096];
  if (slash)
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path) + (slash == path), path);
  else
    snprintf(dir, sizeof dir, ".");
  struct stat st;
  if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
    cli_error("%s %s: the folder %s does not exist", option, path, dir);
    return 0;
  }
  if (access(dir, W_OK) != 0) {
    cli_error("%s %s: the folder %s is not writable", option, path, dir);
    return 0;
  }
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
    cli_error("%s %s: is a folder", option, path);
    return 0;
  }
  return 1;
}

int cli_fail_in(const char *path, const bbc_error *err, int output) {
  if (err->code == BBC_ERROR_CANCELLED && cli_interrupted) return EXIT_INTERRUPTED;
  if (!strncmp(err->message, path, strlen(path))) return cli_fail(err, output);
  cli_error("%s: %s", path, err->message);
  return cli_exit_code(err->code, output);
}

void cli_load_options(const cli *c, bbc_load_options *o) {
  bbc_load_options_default(o);
  o->flat_normals = !c->params.vertex_normals;
  o->accept_unused = c->params.accept_unused;
  o->callbacks = c->callbacks;
}
