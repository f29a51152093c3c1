/* number.c — numbers as text for the writers (glTF, VRML, OBJ): "%.*g"
 * spelt as in the C locale whatever the process's locale, so that a library
 * caller who calls setlocale (a decimal comma: de_DE, fr_FR, ...) still
 * gets files every reader reads. */
#include "io.h"

#include <stdio.h>

void bbc__number_text(char *out, size_t n, int digits, double v) {
  char s[BBC__NUMBER_TEXT];
  snprintf(s, sizeof s, "%.*g", digits, v);
  size_t o = 0;
  /* digits, signs and exponents kept; any other run (the decimal separator,
   * one byte or several) becomes one '.' */
  for (size_t i = 0; s[i] && o + 1 < n; i++) {
    char c = s[i];
    int plain = (c >= '0' && c <= '9') || c == '-' || c == '+' || c == 'e' || c == 'E' ||
                c == 'i' || c == 'n' || c == 'f' || c == 'a' || c == 'N' || c == 'I' || c == 'F' ||
                c == 'A';
    if (plain)
      out[o++] = c;
    else if (o == 0 || out[o - 1] != '.')
      out[o++] = '.';
  }
  if (n) out[o < n ? o : n - 1] = 0;
}
