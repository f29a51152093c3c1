/* cli.h — what the bbcgen commands share: exit codes, messages, parameter
 * options, progress. The library never prints; these do. */
#ifndef BBCGEN_CLI_H
#define BBCGEN_CLI_H

#include "app.h"
#include "closest.h"

#include <stdio.h>

/* Exit codes (documented in --help and docs/cli.md). */
enum {
  EXIT_OK = 0,
  EXIT_USAGE = 1,       /* bad command line, unknown or out-of-range parameter */
  EXIT_INPUT = 2,       /* input missing, a folder, or unreadable */
  EXIT_FORMAT = 3,      /* input in a format no reader knows */
  EXIT_DAMAGED = 4,     /* input damaged, truncated, invalid or empty */
  EXIT_OUTPUT = 5,      /* an output could not be written */
  EXIT_RESOURCES = 6,   /* out of memory */
  EXIT_INTERRUPTED = 7, /* interrupted (Ctrl-C at the prompt: the session goes on) */
  EXIT_SIGINT = 130     /* interrupted (Ctrl-C) outside the prompt: 128 + SIGINT */
};

/* "FILE:LINE: " while a batch command runs (cli_error then names it), else NULL. */
extern const char *cli_location;

/* Set by the prompt's Ctrl-C handler; the library's cancel callback reads it. */
extern volatile int cli_interrupted;

/* A parameter for one part only: `--set trunk.cardboard=1`. Applied on
 * top of the global parameters once all options are read, so the order of
 * options does not matter. */
typedef struct cli_part_setting {
  char part[32];
  char assignment[96]; /* name=value */
} cli_part_setting;

/* Shared state of one bbcgen run. */
typedef struct cli {
  int quiet;         /* --quiet: no progress bar, no info lines */
  bbc_params params; /* thesis parameters after --set/--NAME options */
  int thesis;        /* --thesis given: Appendix A's defaults (a baked light) */
  bbc_callbacks callbacks;
  size_t part_setting_count;
  cli_part_setting part_settings[32];
  bbc_split_options split;    /* --split, --trunk, --foliage */
  int branches_with_trunk;    /* --branches trunk (default: with the foliage) */
  bbc_hand hand;              /* parameters set by hand (bbc_params_note_hand's rules) */
  const char *progress_label; /* what progress bars belong to ("level 2 of 3") */
  int level_files;            /* --lod-files: a glTF chain's levels as files too */
} cli;

void cli_init(cli *c);
/* Prints "bbcgen: <msg>" to stderr. */
void cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints an info line to stderr unless quiet. */
void cli_info(const cli *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Exit code for a library result; `output` = the failing object was an output. */
int cli_exit_code(bbc_result r, int output);
/* Prints the error message and returns the exit code. */
int cli_fail(const bbc_error *err, int output);
/* The same, the message prefixed with `path` unless it names it already. */
int cli_fail_in(const char *path, const bbc_error *err, int output);

/* Tries the options every command accepts at argv[*i]: --quiet, --set
 * [PART.]NAME=VALUE, --NAME VALUE for any thesis parameter, and the part
 * options --split MODE, --trunk PATTERNS, --foliage PATTERNS. Returns 1 when
 * consumed (advancing *i past its value), 0 when not an option of these, and
 * -1 after printing an error (exit EXIT_USAGE). */
int cli_common_option(cli *c, int argc, char **argv, int *i);
/* The parameter whose name is closest to a misspelt one, or NULL. */
const char *cli_closest_param(const char *name);
/* Prints "<cmd>: unknown option 'X' (did you mean --Y?)": Y from the
 * command's own options (`own`, NULL-terminated, may be NULL), the options
 * every command takes and --<parameter>; "(try bbcgen --help)" when none is
 * close. `cmd` may be NULL (the cloud command). Returns EXIT_USAGE. */
int cli_unknown_option(const char *cmd, const char *arg, const char *const *own);

/* Value of the option at argv[*i]; prints an error and returns NULL when missing. */
const char *cli_option_value(int argc, char **argv, int *i);
/* Parses a non-negative integer option value; -1 on error (printed). */
long long cli_parse_count(const char *opt, const char *text, long long max);

/* Progress bar on a terminal (stderr), nothing otherwise or when quiet. */
void cli_progress(void *user, const char *stage, double fraction);
void cli_log(void *user, bbc_log_level level, const char *message);

/* Before any work: the output's folder exists and is writable, and the
 * output itself is not a folder. Prints why and returns 0 otherwise. */
int cli_output_ok(const char *option, const char *path);

/* Load options from the command line: vn and progress/log callbacks. */
void cli_load_options(const cli *c, bbc_load_options *o);

/* Seconds from a monotonic clock. */
double cli_now(void);

/* Fills planes options from the command line: global parameters, the
 * split, and per-part parameters. Prints and returns EXIT_USAGE on error. */
int cli_planes_options(const cli *c, bbc_planes_options *o);

/* Commands. */
int cmd_info(cli *c, int argc, char **argv);
int cmd_tree(cli *c, int argc, char **argv);
int cmd_sample(cli *c, int argc, char **argv);
int cmd_render(cli *c, int argc, char **argv);
int cmd_setup(cli *c, int argc, char **argv);
int cmd_planes(cli *c, int argc, char **argv);
int cmd_exec(cli *c, int argc, char **argv);
/* The prompt: the batch commands line by line (libedit on a terminal);
 * batch_file (may be NULL) runs first, and a `quit` in it ends there. */
int cmd_prompt(cli *c, const char *batch_file);
int cmd_view(cli *c, int argc, char **argv);
int cmd_cloud(cli *c, int argc, char **argv);
int cmd_eval(cli *c, int argc, char **argv);
int cmd_baseline(cli *c, int argc, char **argv);
int cmd_impostor(cli *c, int argc, char **argv);
/* The eval metrics as JSON text (cJSON_free it); a and b name the inputs. */
char *eval_json_text(const bbc_eval_result *r, const bbc_eval_options *o, const char *a,
                     const char *b);
/* Steps 1 and 2 on a model file; JSON to json_path when not NULL. */
int run_planes(const cli *c, const char *path, const char *json_path);
void print_parameter_help(FILE *out);
/* Front, side and top views side by side into a PNG; returns an exit code. */
int render_views_png(const bbc_mesh *m, int z_up, int size, int lighting, const char *out_path);

#endif
