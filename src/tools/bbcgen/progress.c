/* progress.c — the progress bar: drawn on stderr when it is a terminal,
 * silent otherwise (pipes, CI logs) and with --quiet. The library's stage
 * names ("grid", "select", ...) are shown in plain words, after what they
 * belong to when the library names it ("foliage, run 2 at epsilon 7.5 %:
 * grid" -> "foliage, run 2 at epsilon 7.5 %: step 1, plane density"). */
#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

static const char *plain_words(const char *stage) {
  static const char *const words[][2] = {
      {"load", "loading the model"},         {"grid", "step 1, plane density"},
      {"select", "step 2, choosing planes"}, {"baking", "step 3, baking images"},
      {"tree", "growing the tree"},
  };
  for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
    if (!strcmp(stage, words[i][0])) return words[i][1];
  return stage;
}

void cli_progress(void *user, const char *stage, double fraction) {
  const cli *c = user;
  if (c->quiet || !isatty(STDERR_FILENO)) return;
  static int last_permille = -1;
  static char last_stage[256];
  int permille = (int)(fraction * 1000.0);
  if (!strcmp(stage, last_stage) && permille == last_permille) return;
  snprintf(last_stage, sizeof last_stage, "%s", stage);
  last_permille = permille;
  /* "<what>: <stage>": the last part is the library's stage name. */
  char label[400];
  const char *colon = strrchr(stage, ':'), *pre = c->progress_label ? c->progress_label : "";
  const char *sep = *pre ? ", " : "";
  if (colon && colon[1] == ' ')
    snprintf(label, sizeof label, "%s%s%.*s: %s", pre, sep, (int)(colon - stage), stage,
             plain_words(colon + 2));
  else
    snprintf(label, sizeof label, "%s%s%s", pre, *pre ? ": " : "", plain_words(stage));
  enum { WIDTH = 24 };
  int filled = (int)(fraction * WIDTH + 0.5);
  char bar[WIDTH + 1];
  for (int i = 0; i < WIDTH; i++) bar[i] = i < filled ? '#' : '.';
  bar[WIDTH] = 0;
  /* \033[K clears what a longer label left on the line. */
  fprintf(stderr, "\r  [%s] %5.1f%%  %s\033[K", bar, 100.0 * fraction, label);
  if (fraction >= 1.0) {
    fputc('\n', stderr);
    last_permille = -1;
    last_stage[0] = 0;
  }
  fflush(stderr);
}
