/* file_names.c — the names writers give the files beside an output: safe
 * names and the texture-file rule every writer shares. */
#include "io.h"

#include <assert.h>
#include <ctype.h>
#include <stdio.h>
#include <string.h>

void bbc__safe_name(const char *in, char *out, size_t n) {
  size_t i = 0;
  for (; in && in[i] && i + 1 < n; i++) {
    unsigned char c = (unsigned char)in[i];
    out[i] = (char)(isalnum(c) || c == '_' || c == '-' || c == '.' ? c : '_');
  }
  out[i] = 0;
  if (i == 0) snprintf(out, n, "unnamed");
}

void bbc__side_file_stem(const char *path, int safe, char *out, size_t n) {
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  char name[1024];
  snprintf(name, sizeof name, "%s", base);
  char *dot = strrchr(name, '.');
  if (dot) *dot = '_';
  if (safe)
    bbc__safe_name(name, out, n);
  else
    snprintf(out, n, "%s", name);
}

void bbc_texture_file_name(const bbc_mesh *m, size_t t, char *out, size_t n) {
  assert(m && out);
  /* The first material that uses it as colour, else as normal map, else
   * as occlusion map. */
  static const char *const suffix[3] = {"", "_nm", "_ao"};
  for (int pass = 0; pass < 3; pass++)
    for (size_t i = 0; i < m->material_count; i++) {
      const bbc_material *mat = &m->materials[i];
      int use = pass == 0   ? mat->texture == (int)t
                : pass == 1 ? mat->normal_map == (int)t + 1
                            : mat->occlusion_map == (int)t + 1;
      if (!use) continue;
      char safe[128];
      bbc__safe_name(mat->name, safe, sizeof safe);
      snprintf(out, n, "%s%s", safe, suffix[pass]);
      return;
    }
  snprintf(out, n, "texture%zu", t);
}
