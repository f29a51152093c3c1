/* progress.c — the progress bar: drawn on stderr when it is a terminal,
 * silent otherwise (pipes, CI logs) and with --quiet. */
#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

void cli_progress(void *user, const char *stage, double fraction) {
  const cli *c = user;
  if (c->quiet || !isatty(STDERR_FILENO)) return;
  static int last_permille = -1;
  static const char *last_stage = NULL;
  int permille = (int)(fraction * 1000.0);
  if (stage == last_stage && permille == last_permille) return;
  last_stage = stage;
  last_permille = permille;
  enum { WIDTH = 30 };
  int filled = (int)(fraction * WIDTH + 0.5);
  char bar[WIDTH + 1];
  for (int i = 0; i < WIDTH; i++) bar[i] = i < filled ? '#' : '.';
  bar[WIDTH] = 0;
  fprintf(stderr, "\r  %-8s [%s] %5.1f%%", stage, bar, 100.0 * fraction);
  if (fraction >= 1.0) {
    fputc('\n', stderr);
    last_permille = -1;
    last_stage = NULL;
  }
  fflush(stderr);
}
