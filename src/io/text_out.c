/* text_out.c — the writers' one way to write text (glTF's JSON and binary
 * chunk, VRML, OBJ and MTL): a growing buffer whose appends never fail
 * loudly (a failed growth sets `oom` and later appends are ignored, so a
 * writer checks once), numbers through bbc__number_text (the C locale's
 * spelling whatever the process's), and a flush for files written as they
 * go. */
#include "io.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void bbc__text_append(bbc__text *t, const void *data, size_t n) {
  if (t->oom || n == 0) return;
  if (t->size + n < t->size) {
    t->oom = 1;
    return;
  }
  if (t->size + n > t->cap) {
    size_t cap = t->cap ? t->cap : 4096;
    while (cap < t->size + n) {
      if (cap > SIZE_MAX / 2) {
        cap = t->size + n;
        break;
      }
      cap *= 2;
    }
    unsigned char *p = realloc(t->data, cap);
    if (!p) {
      t->oom = 1;
      return;
    }
    t->data = p;
    t->cap = cap;
  }
  memcpy(t->data + t->size, data, n);
  t->size += n;
}

void bbc__text_puts(bbc__text *t, const char *s) {
  bbc__text_append(t, s, strlen(s));
}

void bbc__text_printf(bbc__text *t, const char *fmt, ...) {
  char small[256];
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(small, sizeof small, fmt, ap);
  va_end(ap);
  if (n < 0) {
    t->oom = 1;
    return;
  }
  if ((size_t)n < sizeof small) {
    bbc__text_append(t, small, (size_t)n);
    return;
  }
  char *big = malloc((size_t)n + 1);
  if (!big) {
    t->oom = 1;
    return;
  }
  va_start(ap, fmt);
  vsnprintf(big, (size_t)n + 1, fmt, ap);
  va_end(ap);
  bbc__text_append(t, big, (size_t)n);
  free(big);
}

void bbc__text_number(bbc__text *t, int digits, double v) {
  char s[BBC__NUMBER_TEXT];
  bbc__number_text(s, sizeof s, digits, v);
  bbc__text_puts(t, s);
}

int bbc__text_flush(bbc__text *t, FILE *f) {
  if (t->oom) return 0;
  int ok = t->size == 0 || fwrite(t->data, 1, t->size, f) == t->size;
  t->size = 0;
  return ok;
}

void bbc__text_free(bbc__text *t) {
  free(t->data);
  memset(t, 0, sizeof *t);
}
