/* impostor_file.c — an octahedral impostor on disk (docs/impostors.md): two
 * PNG atlases beside a small JSON descriptor (its frames, layout, bounds and
 * the atlases' names), written atomically; and read back. */
#include "io.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const k_axis[3] = {"x", "y", "z"};

/* `key`: value, the number spelt as in the C locale. */
static void put_number(FILE *fp, const char *key, double v, int last) {
  char t[BBC__NUMBER_TEXT];
  bbc__number_text(t, sizeof t, 17, v);
  fprintf(fp, "  \"%s\": %s%s\n", key, t, last ? "" : ",");
}

bbc_result bbc_impostor_write(const char *path, const bbc_impostor *imp, bbc_error *err) {
  if (!path || !imp || !imp->albedo.rgba || !imp->normal.rgba || imp->frames < 2)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor: nothing to write");
  char stem[2048], folder[4096], name[2][2100], full[4096 + 2100 + 8];
  bbc__side_file_stem(path, 1, stem, sizeof stem);
  bbc__path_folder(path, folder, sizeof folder);
  snprintf(name[0], sizeof name[0], "%s_albedo.png", stem);
  snprintf(name[1], sizeof name[1], "%s_normal.png", stem);
  const bbc_image *img[2] = {&imp->albedo, &imp->normal};
  for (int k = 0; k < 2; k++) {
    if (snprintf(full, sizeof full, "%s%s", folder, name[k]) >= (int)sizeof full)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor: path too long");
    bbc_result r = bbc_image_write_png(full, img[k], err);
    if (r != BBC_OK) return r;
  }
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, path, err);
  if (r != BBC_OK) return r;
  FILE *fp = af.fp;
  fprintf(fp, "{\n  \"format\": \"bbc-impostor\",\n  \"version\": 1,\n");
  fprintf(fp, "  \"layout\": \"%s\",\n", imp->hemi ? "hemi-octahedral" : "octahedral");
  fprintf(fp, "  \"frames\": %d,\n  \"frame_size\": %d,\n  \"padding\": %d,\n", imp->frames,
          imp->frame_size, imp->padding);
  fprintf(fp, "  \"up\": \"%s\",\n", k_axis[(int)imp->up >= 0 && imp->up <= 2 ? (int)imp->up : 1]);
  char c[3][BBC__NUMBER_TEXT];
  for (int k = 0; k < 3; k++) bbc__number_text(c[k], sizeof c[k], 17, imp->center[k]);
  fprintf(fp, "  \"center\": [%s, %s, %s],\n", c[0], c[1], c[2]);
  put_number(fp, "radius", imp->radius, 0);
  put_number(fp, "half_extent", imp->half_extent, 0);
  fprintf(fp, "  \"albedo\": \"%s\",\n  \"normal\": \"%s\",\n", name[0], name[1]);
  fprintf(fp, "  \"albedo_encoding\": \"sRGB colour, alpha 0 or 255\",\n");
  fprintf(
      fp,
      "  \"normal_encoding\": \"rgb = 255 (n + 1) / 2, n the mean of the texel's model-space unit "
      "normals (|n| <= 1, not renormalised); "
      "a = 255 (depth / radius + 1) / 2, depth along the view from the centre plane, "
      "nearer the viewer negative\"\n}\n");
  return bbc__atomic_commit(&af, err);
}

static int get_int(const cJSON *o, const char *key, int *out) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!cJSON_IsNumber(v) || v->valuedouble != floor(v->valuedouble) || fabs(v->valuedouble) > 1e6)
    return 0;
  *out = (int)v->valuedouble;
  return 1;
}

static int get_double(const cJSON *o, const char *key, double *out) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return 0;
  *out = v->valuedouble;
  return 1;
}

/* The descriptor's fields into imp (no images), 0 with *what set when one
 * is missing or wrong. */
static int read_fields(const cJSON *root, bbc_impostor *imp, const char **what) {
  const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(root, "format");
  const cJSON *layout = cJSON_GetObjectItemCaseSensitive(root, "layout");
  const cJSON *up = cJSON_GetObjectItemCaseSensitive(root, "up");
  const cJSON *center = cJSON_GetObjectItemCaseSensitive(root, "center");
  *what = "format \"bbc-impostor\"";
  if (!cJSON_IsString(fmt) || strcmp(fmt->valuestring, "bbc-impostor") != 0) return 0;
  *what = "layout";
  if (!cJSON_IsString(layout)) return 0;
  if (!strcmp(layout->valuestring, "hemi-octahedral"))
    imp->hemi = 1;
  else if (strcmp(layout->valuestring, "octahedral") != 0)
    return 0;
  *what = "frames (2..64), frame_size (>= 8) and padding";
  if (!get_int(root, "frames", &imp->frames) || !get_int(root, "frame_size", &imp->frame_size) ||
      !get_int(root, "padding", &imp->padding) || imp->frames < 2 || imp->frames > 64 ||
      imp->frame_size < 8 || imp->frame_size > 16384 || imp->padding < 0 ||
      2 * imp->padding >= imp->frame_size)
    return 0;
  *what = "up (\"x\", \"y\" or \"z\")";
  if (!cJSON_IsString(up) || strlen(up->valuestring) != 1 || up->valuestring[0] < 'x' ||
      up->valuestring[0] > 'z')
    return 0;
  imp->up = (bbc_axis)(up->valuestring[0] - 'x');
  *what = "center (3 numbers)";
  if (!cJSON_IsArray(center) || cJSON_GetArraySize(center) != 3) return 0;
  for (int k = 0; k < 3; k++) {
    const cJSON *v = cJSON_GetArrayItem(center, k);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return 0;
    imp->center[k] = v->valuedouble;
  }
  *what = "radius and half_extent (> 0)";
  if (!get_double(root, "radius", &imp->radius) ||
      !get_double(root, "half_extent", &imp->half_extent) || !(imp->radius > 0) ||
      !(imp->half_extent > 0))
    return 0;
  return 1;
}

bbc_result bbc_impostor_read(const char *path, bbc_impostor *imp, bbc_error *err) {
  if (!path || !imp) return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT, "impostor: no path");
  memset(imp, 0, sizeof *imp);
  char *text = NULL;
  size_t size = 0;
  bbc_result r = bbc__read_whole_file(path, &text, &size, err);
  if (r != BBC_OK) return r;
  cJSON *root = cJSON_ParseWithLength(text, size);
  free(text);
  if (!root || !cJSON_IsObject(root)) {
    cJSON_Delete(root);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: not a JSON object", path);
  }
  const char *what = "";
  if (!read_fields(root, imp, &what)) {
    cJSON_Delete(root);
    memset(imp, 0, sizeof *imp);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: an impostor descriptor needs %s", path, what);
  }
  char folder[4096];
  bbc__path_folder(path, folder, sizeof folder);
  const char *key[2] = {"albedo", "normal"};
  bbc_image *img[2] = {&imp->albedo, &imp->normal};
  int side = imp->frames * imp->frame_size;
  for (int k = 0; k < 2 && r == BBC_OK; k++) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, key[k]);
    if (!cJSON_IsString(v) || !v->valuestring[0] || strchr(v->valuestring, '/')) {
      r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: \"%s\" must name a file beside it", path, key[k]);
      break;
    }
    size_t n = strlen(folder) + strlen(v->valuestring) + 1;
    char *full = malloc(n);
    if (!full) {
      r = bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "impostor: out of memory");
      break;
    }
    snprintf(full, n, "%s%s", folder, v->valuestring);
    r = bbc_image_load(full, img[k], err);
    if (r == BBC_OK && (img[k]->width != side || img[k]->height != side))
      r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: %d x %d, the descriptor says %d x %d", full,
                    img[k]->width, img[k]->height, side, side);
    free(full);
  }
  cJSON_Delete(root);
  if (r != BBC_OK) bbc_impostor_free(imp);
  return r;
}
