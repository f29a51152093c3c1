/* sniff.c — what an input is before a reader sees it. Compressed files, LAS
 * point clouds, images, material libraries and forest maps given as a model
 * are named as such; an OBJ or XYZ whose last line was cut short is refused
 * (a partial model is worse than none); a glTF whose accessors claim more
 * than its buffers hold is refused before Assimp allocates for them. */
#include "io.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#define SNIFF_HEAD 65536

static int starts(const unsigned char *p, size_t n, const char *magic, size_t m) {
  return n >= m && !memcmp(p, magic, m);
}

static int ext_in(const char *ext, const char *const *list) {
  for (; *list; list++)
    if (!strcmp(ext, *list)) return 1;
  return 0;
}

/* Compressed or archived: which kind and how to unpack it. */
static bbc_result check_compressed(const char *name, const char *ext, const unsigned char *h,
                                   size_t n, bbc_error *err) {
  static const struct {
    const char *magic;
    size_t len;
    const char *ext, *kind, *how;
  } kinds[] = {
      {"\x1f\x8b", 2, "gz", "gzip", "gunzip -k"},
      {"\xfd"
       "7zXZ\0",
       6, "xz", "xz", "unxz -k"},
      {"BZh", 3, "bz2", "bzip2", "bunzip2 -k"},
      {"\x28\xb5\x2f\xfd", 4, "zst", "zstd", "unzstd"},
      {"PK\x03\x04", 4, "zip", "zip", "unzip"},
      {"7z\xbc\xaf\x27\x1c", 6, "7z", "7-Zip", "7z x"},
  };
  for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
    if (starts(h, n, kinds[i].magic, kinds[i].len) || !strcmp(ext, kinds[i].ext)) {
      /* a .zip-shaped 3MF or .usdz is not the user's archive; Assimp reads 3MF */
      if (!strcmp(kinds[i].ext, "zip") && (!strcmp(ext, "3mf") || !strcmp(ext, "usdz"))) continue;
      return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                       "%s: a %s-compressed file: decompress it first (%s '%s') and give the "
                       "model inside",
                       name, kinds[i].kind, kinds[i].how, name);
    }
  return BBC_OK;
}

/* A forest map or model description file (Appendix B): its first command. */
static const char *forest_file_kind(const unsigned char *h, size_t n) {
  static const char *const map_words[] = {
      "hmap",   "hmapfilter",  "colmap",  "heightscale", "stretch", "farclip",  "roetger",
      "skymap", "waterheight", "numobjs", "object2d",    "rndtree", "rndtree2", NULL};
  static const char *const model_words[] = {"fade", "shadowrad", "shadowcutoff", "lod", NULL};
  size_t i = 0;
  while (i < n) {
    while (i < n && isspace(h[i])) i++;
    if (i < n && h[i] == '\'') { /* a comment to the end of the line */
      while (i < n && h[i] != '\n') i++;
      continue;
    }
    break;
  }
  char word[16];
  size_t k = 0;
  while (i < n && k + 1 < sizeof word && isalnum(h[i])) word[k++] = (char)tolower(h[i++]);
  word[k] = 0;
  if (k == 0 || (i < n && !isspace(h[i]) && h[i] != '(')) return NULL;
  for (const char *const *w = map_words; *w; w++)
    if (!strcmp(word, *w)) return "a forest map file";
  for (const char *const *w = model_words; *w; w++)
    if (!strcmp(word, *w)) return "a forest model description file";
  return NULL;
}

/* Files that are not models at all. */
static bbc_result check_not_a_model(const char *name, const char *ext, const unsigned char *h,
                                    size_t n, bbc_error *err) {
  if (starts(h, n, "LASF", 4) || !strcmp(ext, "las") || !strcmp(ext, "laz"))
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: a LAS/LAZ point cloud, which bbcgen does not read: convert it to PLY "
                     "or XYZ first (PDAL: pdal translate '%s' points.ply)",
                     name, name);
  static const char *const image_exts[] = {"png", "jpg",  "jpeg", "bmp", "tga", "gif",
                                           "tif", "tiff", "dds",  "hdr", "exr", "webp",
                                           "ktx", "ktx2", "psd",  NULL};
  int image = starts(h, n, "\x89PNG", 4) || starts(h, n, "\xff\xd8\xff", 3) ||
              starts(h, n, "GIF8", 4) || starts(h, n, "DDS ", 4) || starts(h, n, "II*\0", 4) ||
              starts(h, n, "MM\0*", 4) || starts(h, n, "\xabKTX", 4) ||
              (starts(h, n, "BM", 2) && !strcmp(ext, "bmp")) || ext_in(ext, image_exts);
  if (image)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: an image (a texture or a map), not a model: give the model file "
                     "that uses it",
                     name);
  const char *forest = forest_file_kind(h, n);
  if (forest)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: %s (Appendix B), not a model: open it with forest '%s'", name, forest,
                     name);
  int mtl = !strcmp(ext, "mtl");
  for (size_t i = 0; !mtl && i + 7 < n && i < 4096; i++) /* its first statement */
    if (h[i] == '#') {
      while (i < n && h[i] != '\n') i++;
    } else if (!isspace(h[i])) {
      mtl = !memcmp(h + i, "newmtl", 6) && isspace(h[i + 6]);
      break;
    }
  if (mtl)
    return bbc__fail(err, BBC_ERROR_UNSUPPORTED_FORMAT,
                     "%s: a material library (MTL), not a model: give the .obj that names it "
                     "(mtllib)",
                     name);
  return BBC_OK;
}

/* ---- a last line cut short ------------------------------------------------ */

/* The words of a line, at most `max`: each [start, end). */
static int split_words(const char *s, const char *e, const char **ws, const char **we, int max) {
  int n = 0;
  while (s < e && n < max) { /* XYZ files also separate with ',' or ';' */
    while (s < e && (*s == ' ' || *s == '\t' || *s == ',' || *s == ';')) s++;
    if (s >= e) break;
    ws[n] = s;
    while (s < e && *s != ' ' && *s != '\t' && *s != ',' && *s != ';') s++;
    we[n++] = s;
  }
  return n;
}

/* Digits after the decimal point of a number word; -1 when it has none. */
static int fraction_digits(const char *s, const char *e) {
  const char *dot = memchr(s, '.', (size_t)(e - s));
  if (!dot) return -1;
  int n = 0;
  for (const char *p = dot + 1; p < e && isdigit((unsigned char)*p); p++) n++;
  return n;
}

/* A word no writer ends a number or index with: "1.", "1e", "-", "3/". */
static int word_unfinished(const char *e) {
  char c = e[-1];
  return c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+' || c == '/';
}

/* The shape of an OBJ face corner: the number of '/' and whether "//". */
static int corner_shape(const char *s, const char *e) {
  int slashes = 0, empty = 0;
  for (const char *p = s; p < e; p++)
    if (*p == '/') {
      slashes++;
      if (p + 1 < e && p[1] == '/') empty = 1;
    }
  return slashes * 2 + empty;
}

/* 1 when `last` (a line without its line end, the file's last bytes) is an
 * incomplete version of `prev`, the line before it with the same keyword:
 * fewer words, a word cut mid-number, a face corner of another shape, or
 * (from a writer of fixed precision, every number of `prev` with the same
 * digits after the point) a last number with fewer digits. */
static int line_cut_short(const char *ls, const char *le, const char *ps, const char *pe, int obj) {
  const char *w[32], *we[32], *pw[32], *pwe[32];
  int n = split_words(ls, le, w, we, 32), pn = split_words(ps, pe, pw, pwe, 32);
  if (n == 0) return 0;
  if (word_unfinished(we[n - 1])) return 1;
  if (obj && we[0] - w[0] == 1 && *w[0] == 'f' && n < 4) return 1; /* a face of < 3 corners */
  if (obj && we[0] - w[0] == 1 && *w[0] == 'v' && n < 4) return 1; /* v x y z */
  if (pn == 0 || n < pn) return pn > 0;
  if (obj && we[0] - w[0] == 1 && *w[0] == 'f') {
    if (pn < 2) return 0;
    for (int i = 1; i < n; i++)
      if (corner_shape(w[i], we[i]) != corner_shape(pw[1], pwe[1])) return 1;
    return 0;
  }
  int first = obj ? 1 : 0, digits = -2;
  for (int i = first; i < pn; i++) {
    int d = fraction_digits(pw[i], pwe[i]);
    if (digits == -2) digits = d;
    if (d != digits) return 0; /* not a fixed-precision writer */
  }
  return digits > 0 && n == pn && fraction_digits(w[n - 1], we[n - 1]) < digits;
}

/* The file's last line when the file does not end with a line end, and the
 * line before it that starts with the same keyword (OBJ) or holds data
 * (XYZ); refused when the last one is cut short. `tail` holds the file's
 * last `n` bytes. */
static bbc_result check_last_line(const char *name, const char *tail, size_t n, int whole, int obj,
                                  bbc_error *err) {
  if (n == 0 || tail[n - 1] == '\n' || tail[n - 1] == '\r') return BBC_OK;
  const char *le = tail + n, *ls = le;
  while (ls > tail && ls[-1] != '\n' && ls[-1] != '\r') ls--;
  const char *ks = ls;
  while (ks < le && (*ks == ' ' || *ks == '\t')) ks++;
  const char *ke = ks;
  while (ke < le && *ke != ' ' && *ke != '\t') ke++;
  if (ks == le || *ks == '#') return BBC_OK;
  if (obj && !((ke - ks == 1 && *ks && strchr("vfpl", *ks)) ||
               (ke - ks == 2 && (!memcmp(ks, "vt", 2) || !memcmp(ks, "vn", 2)))))
    return BBC_OK;
  /* the previous line of the same kind, within the tail (XYZ: and the one
   * before it, which must have as many words: a file of one layout) */
  const char *pe = ls, *ps = NULL, *first_ps = NULL, *first_pe = NULL;
  for (int found = 0; found < (obj ? 1 : 2); found++) {
    ps = NULL;
    while (pe > tail) {
      while (pe > tail && (pe[-1] == '\n' || pe[-1] == '\r')) pe--;
      const char *s = pe;
      while (s > tail && s[-1] != '\n' && s[-1] != '\r') s--;
      if (s == tail && !whole) break; /* may itself be cut at the tail's start */
      const char *q = s;
      while (q < pe && (*q == ' ' || *q == '\t')) q++;
      int same = obj ? (size_t)(pe - q) > (size_t)(ke - ks) && !memcmp(q, ks, (size_t)(ke - ks)) &&
                           (q[ke - ks] == ' ' || q[ke - ks] == '\t')
                     : q < pe && (isdigit((unsigned char)*q) || *q == '-' || *q == '.');
      if (same) {
        ps = s;
        break;
      }
      pe = s;
      if (s == tail) break;
    }
    if (!ps) break;
    if (found == 0) {
      first_ps = ps;
      first_pe = pe;
      pe = ps;
    }
  }
  if (!obj && first_ps) { /* XYZ: judged only against a steady layout */
    const char *a[32], *ae[32], *b[32], *be[32];
    if (!ps || split_words(first_ps, first_pe, a, ae, 32) != split_words(ps, pe, b, be, 32))
      first_ps = NULL;
  }
  if (first_ps) {
    ps = first_ps;
    pe = first_pe;
  }
  int cut = first_ps ? line_cut_short(ls, le, ps, pe, obj) : 0;
  if (!first_ps && obj) cut = line_cut_short(ls, le, ls, ls, obj);
  if (cut)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: cut short: its last line '%.*s' is incomplete (the file ends inside "
                     "it); the file is truncated",
                     name, (int)(le - ls > 60 ? 60 : le - ls), ls);
  return BBC_OK;
}

/* OBJ: vertices after the last one any face, line or point uses (relative
 * indices aside) while the last face uses about the highest vertex used:
 * the faces that used the rest were lost, as when a file is cut at a line
 * end. Said, not refused: some exporters leave stray vertices. */
static void check_obj_unused_tail(const char *name, const char *buf, size_t n,
                                  const bbc_load_options *options) {
  size_t verts = 0, max_used = 0, last_face_max = 0;
  int relative = 0;
  const char *p = buf, *end = buf + n;
  while (p < end) {
    const char *q = p;
    while (q < end && (*q == ' ' || *q == '\t')) q++;
    const char *nl = memchr(q, '\n', (size_t)(end - q));
    const char *le = nl ? nl : end;
    if (le - q > 2 && q[0] == 'v' && (q[1] == ' ' || q[1] == '\t')) {
      verts++;
    } else if (le - q > 2 && strchr("fpl", q[0]) && (q[1] == ' ' || q[1] == '\t')) {
      last_face_max = 0;
      for (const char *s = q + 2; s < le;) {
        while (s < le && (*s == ' ' || *s == '\t')) s++;
        if (s >= le) break;
        if (*s == '-') relative = 1;
        size_t v = 0; /* bounded by the line: the bytes need not end in a NUL */
        for (const char *d = s; d < le && *d >= '0' && *d <= '9' && v < ((size_t)1 << 60); d++)
          v = v * 10 + (size_t)(*d - '0');
        if (v > max_used) max_used = v;
        if (v > last_face_max) last_face_max = v;
        while (s < le && *s != ' ' && *s != '\t') s++;
      }
    }
    p = le + 1;
  }
  /* a cut: the faces were still reaching new vertices when the file ended
   * (its last face near the highest vertex used); whole files from some
   * exporters (ez-tree's ash) carry unused vertices after faces that end
   * elsewhere */
  if (relative || max_used == 0 || max_used >= verts || last_face_max * 100 < max_used * 99) return;
  size_t unused = verts - max_used;
  if (unused >= 16 && unused * 100 >= verts)
    bbc__log(&options->callbacks, BBC_LOG_WARNING,
             "%s: its last %zu of %zu vertices are used by no face: faces may be missing (a "
             "file cut short at a line end looks like this)",
             name, unused, verts);
}

/* ---- glTF: what the accessors claim against what the buffers hold ---------- */

static double num(const cJSON *o, const char *key, double dflt) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(v) ? v->valuedouble : dflt;
}

static int component_size(int type) {
  switch (type) {
  case 5120:
  case 5121:
    return 1;
  case 5122:
  case 5123:
    return 2;
  case 5125:
  case 5126:
    return 4;
  }
  return 0;
}

static int type_components(const char *t) {
  static const struct {
    const char *name;
    int n;
  } types[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
               {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
  for (size_t i = 0; t && i < sizeof types / sizeof types[0]; i++)
    if (!strcmp(t, types[i].name)) return types[i].n;
  return 0;
}

/* The bytes buffer i holds: the GLB's BIN chunk, a data: URI's, or the file
 * beside the .gltf; -1 when it cannot be told (left to the reader). */
static double buffer_holds(const cJSON *buf, size_t i, const char *folder, double bin_chunk) {
  const cJSON *uri = cJSON_GetObjectItemCaseSensitive(buf, "uri");
  if (!cJSON_IsString(uri)) return i == 0 ? bin_chunk : -1;
  const char *u = uri->valuestring;
  if (!strncmp(u, "data:", 5)) {
    const char *comma = strchr(u, ',');
    if (!comma || !strstr(u, ";base64")) return -1;
    return floor((double)strlen(comma + 1) * 3 / 4);
  }
  if (!folder || strstr(u, "%") || strstr(u, "..")) return -1;
  char path[4600];
  snprintf(path, sizeof path, "%s%s", folder, u);
  struct stat st;
  return stat(path, &st) == 0 && S_ISREG(st.st_mode) ? (double)st.st_size : -1;
}

static uint32_t le32(const unsigned char *p);

/* Every index of every primitive below its POSITION count (Assimp reads
 * out-of-range indices unchecked and crashes in its post-processing). The
 * ranges were checked; `bin`: a GLB's binary chunk; external buffers are
 * read from `folder`; data: URIs are left to the reader. */
static bbc_result check_indices(const char *name, const cJSON *j, const unsigned char *bin,
                                size_t bin_len, const char *folder, bbc_error *err) {
  const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(j, "buffers");
  const cJSON *views = cJSON_GetObjectItemCaseSensitive(j, "bufferViews");
  const cJSON *accessors = cJSON_GetObjectItemCaseSensitive(j, "accessors");
  const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(j, "meshes"), *mesh;
  int nb = cJSON_GetArraySize(buffers);
  char *files[8] = {0};
  size_t sizes[8] = {0};
  bbc_result r = BBC_OK;
  int mi = 0;
  cJSON_ArrayForEach(mesh, meshes) {
    const cJSON *prim;
    cJSON_ArrayForEach(prim, cJSON_GetObjectItemCaseSensitive(mesh, "primitives")) {
      double mode = num(prim, "mode", 4);
      if (!(mode >= 0 && mode <= 6)) { /* Assimp crashes past 6 */
        r = bbc__fail(err, BBC_ERROR_CORRUPT,
                      "%s: mesh %d: primitive mode %g (glTF's are 0 to 6): the file is damaged",
                      name, mi, mode);
        break;
      }
      int ii = (int)num(prim, "indices", -1);
      int pi = (int)num(cJSON_GetObjectItemCaseSensitive(prim, "attributes"), "POSITION", -1);
      const cJSON *ia = cJSON_GetArrayItem(accessors, ii), *pa = cJSON_GetArrayItem(accessors, pi);
      if (ii < 0 || !ia || !pa) continue;
      const cJSON *v = cJSON_GetArrayItem(views, (int)num(ia, "bufferView", -1));
      int b = v ? (int)num(v, "buffer", -1) : -1;
      int cs = component_size((int)num(ia, "componentType", 0));
      if (b < 0 || b >= nb || cs < 1) continue;
      const unsigned char *data = NULL;
      size_t size = 0;
      const cJSON *uri = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(buffers, b), "uri");
      if (!uri && b == 0) {
        data = bin;
        size = bin_len;
      } else if (cJSON_IsString(uri) && strncmp(uri->valuestring, "data:", 5) && folder && b < 8 &&
                 !strstr(uri->valuestring, "..")) {
        if (!files[b]) {
          char path[4600];
          snprintf(path, sizeof path, "%s%s", folder, uri->valuestring);
          bbc_error quiet;
          if (bbc__read_whole_file(path, &files[b], &sizes[b], &quiet) != BBC_OK) files[b] = NULL;
        }
        data = (const unsigned char *)files[b];
        size = sizes[b];
      }
      if (!data) continue;
      double count = num(ia, "count", 0), verts = num(pa, "count", 0);
      double at = num(v, "byteOffset", 0) + num(ia, "byteOffset", 0);
      double stride = num(v, "byteStride", cs);
      for (double e = 0; e < count; e++) {
        double o = at + e * stride;
        if (o < 0 || o + cs > (double)size) break; /* past what is there: the reader's */
        const unsigned char *q = data + (size_t)o;
        uint32_t x = cs == 1 ? q[0] : cs == 2 ? (uint32_t)(q[0] | q[1] << 8) : le32(q);
        if ((double)x >= verts) {
          r = bbc__fail(err, BBC_ERROR_CORRUPT,
                        "%s: mesh %d: index %.0f is %u, past its %.0f vertices: the file is "
                        "damaged",
                        name, mi, e, (unsigned)x, verts);
          break;
        }
      }
      if (r != BBC_OK) break;
    }
    if (r != BBC_OK) break;
    mi++;
  }
  for (int b = 0; b < 8; b++) free(files[b]);
  return r;
}

static bbc_result check_gltf_json(const char *name, const char *json, size_t len,
                                  const char *folder, const unsigned char *bin, size_t bin_len,
                                  bbc_error *err) {
  double bin_chunk = bin ? (double)bin_len : 0;
  cJSON *j = cJSON_ParseWithLength(json, len);
  if (!j) return BBC_OK; /* the reader says what is wrong with it */
  bbc_result r = BBC_OK;
  const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(j, "buffers");
  const cJSON *views = cJSON_GetObjectItemCaseSensitive(j, "bufferViews");
  const cJSON *accessors = cJSON_GetObjectItemCaseSensitive(j, "accessors");
  int nb = cJSON_GetArraySize(buffers), nv = cJSON_GetArraySize(views);
  for (int i = 0; i < nb && r == BBC_OK; i++) {
    const cJSON *b = cJSON_GetArrayItem(buffers, i);
    double claims = num(b, "byteLength", 0), holds = buffer_holds(b, (size_t)i, folder, bin_chunk);
    if (holds >= 0 && claims > holds + 3) /* a GLB chunk's padding aside */
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: buffer %d claims %.0f bytes but holds %.0f: the file is cut short or "
                    "damaged",
                    name, i, claims, holds);
  }
  for (int i = 0; i < nv && r == BBC_OK; i++) {
    const cJSON *v = cJSON_GetArrayItem(views, i);
    int b = (int)num(v, "buffer", -1);
    double end = num(v, "byteOffset", 0) + num(v, "byteLength", 0);
    double size = b >= 0 && b < nb ? num(cJSON_GetArrayItem(buffers, b), "byteLength", 0) : -1;
    if (size < 0 || end > size)
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: bufferView %d reaches byte %.0f of buffer %d, which has %.0f: the file "
                    "is damaged",
                    name, i, end, b, size < 0 ? 0 : size);
  }
  for (int i = 0; i < cJSON_GetArraySize(accessors) && r == BBC_OK; i++) {
    const cJSON *a = cJSON_GetArrayItem(accessors, i);
    double count = num(a, "count", 0);
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(a, "type");
    int cs = component_size((int)num(a, "componentType", 0)),
        nc = type_components(cJSON_IsString(type) ? type->valuestring : NULL);
    int vi = (int)num(a, "bufferView", -1);
    if (!cs || !nc) { /* Assimp compares the type's name unchecked */
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: accessor %d: type '%s', componentType %g: not glTF's; the file is "
                    "damaged",
                    name, i, cJSON_IsString(type) ? type->valuestring : "(none)",
                    num(a, "componentType", 0));
      break;
    }
    if (vi < 0) {
      if (count > 1e9) /* a sparse or zero accessor still gets count elements */
        r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: accessor %d claims %.0f elements", name, i,
                      count);
      continue;
    }
    if (vi >= nv) {
      r = bbc__fail(err, BBC_ERROR_CORRUPT, "%s: accessor %d names bufferView %d of %d", name, i,
                    vi, nv);
      break;
    }
    const cJSON *v = cJSON_GetArrayItem(views, vi);
    double elem = (double)cs * nc, stride = num(v, "byteStride", elem);
    double need = count > 0 ? num(a, "byteOffset", 0) + (count - 1) * stride + elem : 0;
    double have = num(v, "byteLength", 0);
    if (need > have)
      r = bbc__fail(err, BBC_ERROR_CORRUPT,
                    "%s: accessor %d claims %.0f elements (%.0f bytes) but its bufferView %d "
                    "holds %.0f bytes: the file is damaged",
                    name, i, count, need, vi, have);
  }
  const cJSON *image;
  cJSON_ArrayForEach(image, cJSON_GetObjectItemCaseSensitive(j, "images")) {
    const cJSON *mime = cJSON_GetObjectItemCaseSensitive(image, "mimeType");
    if (r == BBC_OK && mime && (!cJSON_IsString(mime) || !strchr(mime->valuestring, '/')))
      r = bbc__fail(err, BBC_ERROR_CORRUPT, /* Assimp reads past a '/' it does not find */
                    "%s: an image's mimeType '%s' is no MIME type: the file is damaged", name,
                    cJSON_IsString(mime) ? mime->valuestring : "(not text)");
  }
  if (r == BBC_OK) r = check_indices(name, j, bin, bin_len, folder, err);
  cJSON_Delete(j);
  return r;
}

static uint32_t le32(const unsigned char *p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* A GLB's header and chunks against its size, then its JSON. */
static bbc_result check_glb(const char *name, const unsigned char *d, size_t n, bbc_error *err) {
  if (n < 20) return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: cut short: %zu bytes", name, n);
  uint32_t total = le32(d + 8), jl = le32(d + 12);
  if (total > n)
    return bbc__fail(err, BBC_ERROR_CORRUPT,
                     "%s: cut short: its header says %u bytes, the file has %zu", name, total, n);
  if ((size_t)jl + 20 > n || le32(d + 16) != 0x4E4F534Au)
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: a damaged GLB (its JSON chunk)", name);
  const unsigned char *bin = NULL;
  size_t bin_len = 0, at = 20 + (size_t)jl;
  if (at + 8 <= n && le32(d + at + 4) == 0x004E4942u) {
    uint32_t bl = le32(d + at);
    if (at + 8 + bl > n)
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: cut short: its binary chunk claims %u bytes, %zu are there", name, bl,
                       n - at - 8);
    bin = d + at + 8;
    bin_len = bl;
  }
  return check_gltf_json(name, (const char *)d + 20, jl, NULL, bin, bin_len, err);
}

/* ---- the entry ---------------------------------------------------------- */

bbc_result bbc__sniff_input(const char *name, const void *data, size_t size, int from_memory,
                            const bbc_load_options *options, bbc_error *err) {
  char ext[16];
  bbc__path_extension(name, ext, sizeof ext);
  unsigned char head[SNIFF_HEAD];
  size_t hn = 0;
  FILE *f = NULL;
  if (from_memory) {
    hn = size < SNIFF_HEAD ? size : SNIFF_HEAD;
    if (hn) memcpy(head, data, hn);
  } else {
    f = fopen(name, "rb");
    if (!f) return BBC_OK; /* the reader says why */
    hn = fread(head, 1, sizeof head, f);
    fclose(f);
  }
  bbc_result r = check_compressed(name, ext, head, hn, err);
  if (r == BBC_OK) r = check_not_a_model(name, ext, head, hn, err);
  if (r != BBC_OK) return r;
  int obj = !strcmp(ext, "obj"),
      xyz = !strcmp(ext, "xyz") || !strcmp(ext, "pts") || !strcmp(ext, "txt");
  int glb = starts(head, hn, "glTF", 4), gltf = !strcmp(ext, "gltf");
  if (!glb && (gltf || !strcmp(ext, "glb"))) { /* else Assimp guesses among all its formats */
    size_t i = starts(head, hn, "\xef\xbb\xbf", 3) ? 3 : 0; /* a UTF-8 byte order mark */
    while (i < hn && isspace(head[i])) i++;
    if (i >= hn || head[i] != '{')
      return bbc__fail(err, BBC_ERROR_CORRUPT,
                       "%s: not a glTF file: neither a GLB header ('glTF') nor JSON", name);
    gltf = 1;
  }
  if (!obj && !xyz && !glb && !gltf) return BBC_OK;
  char *buf = NULL;
  size_t n = size;
  if (from_memory) {
    buf = (char *)data;
  } else if (xyz) { /* the last line only: point files run to gigabytes */
    f = fopen(name, "rb");
    if (!f) return BBC_OK;
    char tail[SNIFF_HEAD];
    size_t tn = 0;
    if (fseek(f, 0, SEEK_END) == 0) {
      long end = ftell(f);
      long from = end > (long)sizeof tail ? end - (long)sizeof tail : 0;
      if (end > 0 && fseek(f, from, SEEK_SET) == 0) tn = fread(tail, 1, sizeof tail, f);
    }
    fclose(f);
    return check_last_line(name, tail, tn, tn < sizeof tail, 0, err);
  } else if (bbc__read_whole_file(name, &buf, &n, err) != BBC_OK) {
    return BBC_OK; /* the reader says why */
  }
  if (glb) {
    r = check_glb(name, (const unsigned char *)buf, n, err);
  } else if (gltf) {
    char folder[4096];
    bbc__path_folder(name, folder, sizeof folder);
    r = check_gltf_json(name, buf, n, from_memory ? NULL : folder, NULL, 0, err);
  } else {
    size_t tn = n < SNIFF_HEAD ? n : SNIFF_HEAD;
    r = check_last_line(name, buf + n - tn, tn, tn == n, obj, err);
    if (r == BBC_OK && obj) check_obj_unused_tail(name, buf, n, options);
  }
  if (!from_memory) free(buf);
  return r;
}
