/* texture_path.c — where the texture a model names is: one search for every
 * reader (the formats Assimp reads, PLY, VRML). Artists' files name their
 * textures in many ways: absolute paths from the machine they were made on,
 * Windows paths, names relative to the model, bare names of files kept in a
 * textures folder beside it. */
#include "io.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

/* The folders, relative to the model's, where models keep their textures
 * (searched by the reference's base name). */
static const char *const k_texture_folders[] = {"textures/", "Textures/", "../textures/",
                                                "../Textures/"};

/* out = the model's folder (the first dir_len bytes of model_path), then a,
 * then b; 1 when that fits in n bytes and names a regular file. */
static int try_path(const char *model_path, int dir_len, const char *a, const char *b, char *out,
                    size_t n) {
  int w = snprintf(out, n, "%.*s%s%s", dir_len, model_path, a, b);
  return w > 0 && (size_t)w < n && bbc__file_exists(out);
}

/* out = the model's folder, then `sub`, then the one entry of that folder
 * whose name equals `base` but for case (a model made on Windows or macOS,
 * whose file systems ignore case, naming "Leaf.PNG" for leaf.png); 1 when
 * there is exactly one such regular file. */
static int try_any_case(const char *model_path, int dir_len, const char *sub, const char *base,
                        char *out, size_t n) {
  char folder[4096];
  int w = snprintf(folder, sizeof folder, "%.*s%s", dir_len, model_path, sub);
  if (w < 0 || (size_t)w >= sizeof folder) return 0;
  DIR *d = opendir(folder[0] ? folder : ".");
  if (!d) return 0;
  int found = 0;
  char match[4096];
  struct dirent *e;
  while ((e = readdir(d)) != NULL)
    if (!strcasecmp(e->d_name, base)) {
      char cand[4096];
      int c = snprintf(cand, sizeof cand, "%s%s", folder, e->d_name);
      if (c > 0 && (size_t)c < sizeof cand && bbc__file_exists(cand)) {
        found++;
        snprintf(match, sizeof match, "%s", e->d_name);
      }
    }
  closedir(d);
  return found == 1 && try_path(model_path, dir_len, sub, match, out, n);
}

/* The search bbc__texture_resolve describes; 0 when nothing is found (out
 * then holds the last candidate tried, or is untouched). */
static int search(const char *model_path, int dir_len, const char *ref,
                  bbc__texture_spelling spelling, char *out, size_t n) {
  char r[4096];
  int w = snprintf(r, sizeof r, "%s", ref);
  if (w < 0 || (size_t)w >= sizeof r) return 0;
  /* Blanks after the name (a line "map_Kd leaf.png \r"): no texture file
   * ends in one, and viewers drop them. */
  while (w > 0 && (r[w - 1] == ' ' || r[w - 1] == '\t' || r[w - 1] == '\r')) r[--w] = 0;
  if (spelling != BBC__TEXTURE_URL)
    for (char *c = r; *c; c++)
      if (*c == '\\') *c = '/';
  const char *base = strrchr(r, '/') ? strrchr(r, '/') + 1 : r;
  if (r[0] == '/' && try_path(model_path, 0, r, "", out, n)) return 1;
  const char *rel = r[0] == '/' ? NULL : r;
  if (spelling == BBC__TEXTURE_ASSIMP) {
    rel = r;
    while (rel[0] == '.' && rel[1] == '/') rel += 2;
  }
  if (rel && rel[0] && try_path(model_path, dir_len, rel, "", out, n)) return 1;
  if (!base[0]) return 0;
  if (try_path(model_path, dir_len, base, "", out, n)) return 1;
  for (size_t i = 0; i < sizeof k_texture_folders / sizeof k_texture_folders[0]; i++)
    if (try_path(model_path, dir_len, k_texture_folders[i], base, out, n)) return 1;
  /* The same places, the name's case ignored (its folders' too, for
   * textures/ and Textures/ are both tried). */
  if (rel && rel != base && strrchr(rel, '/')) {
    char sub[4096];
    int sl = (int)(strrchr(rel, '/') - rel + 1);
    snprintf(sub, sizeof sub, "%.*s", sl, rel);
    if (try_any_case(model_path, dir_len, sub, base, out, n)) return 1;
  }
  if (try_any_case(model_path, dir_len, "", base, out, n)) return 1;
  for (size_t i = 0; i < sizeof k_texture_folders / sizeof k_texture_folders[0]; i++)
    if (try_any_case(model_path, dir_len, k_texture_folders[i], base, out, n)) return 1;
  return 0;
}

int bbc__texture_resolve(const char *model_path, const char *ref, bbc__texture_spelling spelling,
                         char *out, size_t n) {
  const char *slash = strrchr(model_path, '/');
  int dir_len = slash ? (int)(slash - model_path + 1) : 0;
  if (search(model_path, dir_len, ref, spelling, out, n)) return 1;
  snprintf(out, n, "%.*s%s", ref[0] == '/' ? 0 : dir_len, model_path, ref);
  return 0;
}
