/* closest.h — the nearest known word to a misspelt one (tools only). */
#ifndef BBC_TOOLS_CLOSEST_H
#define BBC_TOOLS_CLOSEST_H

/* The closest of `candidates` (NULL-terminated) to `word`, ignoring case
 * and leading dashes, when it is close enough to be a typo; else NULL. */
const char *cli_closest(const char *word, const char *const *candidates);

#endif
