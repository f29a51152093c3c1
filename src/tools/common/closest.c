/* closest.c — the nearest known word to a misspelt one, for the tools'
 * "did you mean ...?" (bbcgen and forest). */
#include "closest.h"

#include <ctype.h>
#include <string.h>
#include <strings.h>

/* Edit distance (insertions, deletions, substitutions, and swaps of two
 * neighbours), case-insensitive, capped at 64 characters. */
static int edit_distance(const char *a, const char *b) {
  size_t n = strlen(a), m = strlen(b);
  if (n > 64 || m > 64) return 1000;
  int d[65][65];
  for (size_t i = 0; i <= n; i++) d[i][0] = (int)i;
  for (size_t j = 0; j <= m; j++) d[0][j] = (int)j;
  for (size_t i = 1; i <= n; i++)
    for (size_t j = 1; j <= m; j++) {
      int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
      int v = d[i - 1][j - 1] + cost;
      if (d[i - 1][j] + 1 < v) v = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < v) v = d[i][j - 1] + 1;
      if (i > 1 && j > 1 && tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 2]) &&
          tolower((unsigned char)a[i - 2]) == tolower((unsigned char)b[j - 1]) &&
          d[i - 2][j - 2] + 1 < v)
        v = d[i - 2][j - 2] + 1;
      d[i][j] = v;
    }
  return d[n][m];
}

const char *cli_closest(const char *word, const char *const *candidates) {
  while (*word == '-') word++;
  size_t len = strlen(word);
  if (!len) return NULL;
  /* A typo: at most 1 edit in short words, 2 from 6 letters, 3 from 12. */
  int limit = len < 6 ? 1 : len < 12 ? 2 : 3, best_d = limit + 1;
  const char *best = NULL;
  for (size_t i = 0; candidates[i]; i++) {
    const char *c = candidates[i];
    while (*c == '-') c++;
    int dist = edit_distance(word, c);
    if (len >= 3 && !strncasecmp(c, word, len) && dist > 1) dist = 1; /* a prefix */
    if (dist < best_d) {
      best_d = dist;
      best = candidates[i];
    }
  }
  return best;
}
