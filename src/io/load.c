/* load.c — bbc_mesh_load: picks the reader for a file and finishes the mesh. */
#include "io.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Georeferenced coordinates (a centre beyond 10,000 units, e.g. UTM metres)
 * are moved near 0: read as doubles, they would lose millimetres as floats
 * in the outputs. The offset, the centre rounded to whole units, is kept in
 * mesh->origin. */
static void recentre(bbc_mesh *m) {
  double o[3] = {0, 0, 0};
  int far = 0;
  for (int k = 0; k < 3; k++)
    if (fabs(m->center[k]) > 1e4) far = 1;
  if (!far) return;
  for (int k = 0; k < 3; k++) o[k] = round(m->center[k]);
  for (size_t v = 0; v < m->vertex_count; v++)
    for (int k = 0; k < 3; k++) m->positions[3 * v + k] -= o[k];
  for (int k = 0; k < 3; k++) {
    m->center[k] -= o[k];
    m->bbox_min[k] -= o[k];
    m->bbox_max[k] -= o[k];
    m->origin[k] = o[k];
  }
}

/* An OBJ whose `mtllib` names no file beside it loads with grey materials
 * (Assimp says nothing): said, as a missing map_Kd is. Only the first 64 KB
 * are looked at (exporters write mtllib at the top). */
static void check_mtllib(const char *path, const bbc_load_options *options) {
  FILE *f = fopen(path, "rb");
  if (!f) return;
  char buf[65537];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = 0;
  char folder[4096];
  bbc__path_folder(path, folder, sizeof folder);
  int line = 1;
  for (char *p = buf; p && *p; line++) {
    char *nl = strchr(p, '\n');
    if (nl) *nl = 0;
    char *q = p + strspn(p, " \t");
    if (!strncmp(q, "mtllib", 6) && (q[6] == ' ' || q[6] == '\t')) {
      char name[1024];
      snprintf(name, sizeof name, "%s", q + 6 + strspn(q + 6, " \t"));
      size_t len = strlen(name);
      while (len && (name[len - 1] == '\r' || name[len - 1] == ' ' || name[len - 1] == '\t'))
        name[--len] = 0;
      /* the whole rest of the line (names with spaces), else any of its words */
      char full[5200];
      snprintf(full, sizeof full, "%s%s", folder, name);
      int found = len && bbc__file_exists(full);
      for (char *w = strtok(name, " \t"); !found && w; w = strtok(NULL, " \t")) {
        snprintf(full, sizeof full, "%s%s", folder, w);
        found = bbc__file_exists(full);
      }
      if (len && !found)
        bbc__log(&options->callbacks, BBC_LOG_WARNING,
                 "%s:%d: material library '%s' not found beside the model; its materials get "
                 "a plain grey",
                 path, line, q + 6 + strspn(q + 6, " \t"));
    }
    p = nl ? nl + 1 : NULL;
  }
}

/* An OBJ's line at p (its start) begins with keyword c and a blank. */
static int obj_line_is(const char *p, const char *end, char c) {
  return p + 1 < end && p[0] == c && (p[1] == ' ' || p[1] == '\t');
}

/* An OBJ cut short where it held only vertices (a tree's leaves after its
 * trunk's faces) still parses, and gives a model without them: refused when
 * at least 100 vertex lines, and 1 % of the file's, follow its last face
 * (f, l or p line; a vertex is referred to after it is given, so none of
 * them is used). From the end backwards: a whole file is read only then. */
static bbc_result obj_cut_short(const char *name, const char *buf, size_t size, bbc_error *err) {
  const char *end = buf + size, *p = end;
  size_t trailing = 0;
  int face = 0;
  while (p > buf && !face) {
    const char *e = p; /* the line [start, e) */
    while (e > buf && (e[-1] == '\n' || e[-1] == '\r')) e--;
    const char *start = e;
    while (start > buf && start[-1] != '\n') start--;
    if (obj_line_is(start, e, 'v'))
      trailing++;
    else if (obj_line_is(start, e, 'f') || obj_line_is(start, e, 'l') || obj_line_is(start, e, 'p'))
      face = 1;
    p = start;
  }
  if (!face || trailing < 100) return BBC_OK;
  size_t all = 0;
  for (const char *q = buf; q < end;) {
    if (obj_line_is(q, end, 'v')) all++;
    const char *nl = memchr(q, '\n', (size_t)(end - q));
    q = nl ? nl + 1 : end;
  }
  if (trailing * 100 < all) return BBC_OK;
  return bbc__fail(err, BBC_ERROR_CORRUPT,
                   "%s: cut short? %zu of its %zu vertices follow its last face, which no face "
                   "uses (parameter acceptunused 1 loads it anyway)",
                   name, trailing, all);
}

/* The readers we own (PLY, XYZ/PTS/TXT, VRML) parse a NUL-terminated buffer
 * (the whole file read at once, or a copy of the caller's bytes); the rest
 * goes to Assimp. Either way the mesh is then finished alike. */
static bbc_result load_any(const char *name, const void *data, size_t size, int from_memory,
                           const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  bbc_load_options defaults;
  if (!options) {
    bbc_load_options_default(&defaults);
    options = &defaults;
  }
  memset(mesh, 0, sizeof *mesh);
  if (err) {
    err->code = BBC_OK;
    err->message[0] = 0;
  }
  bbc_result r = from_memory ? BBC_OK : bbc__check_input_file(name, err);
  if (r != BBC_OK) return r;
  char ext[16];
  bbc__path_extension(name, ext, sizeof ext);
  /* An OBJ file for our reader is read once, for the sniffing too */
  char *obj = NULL;
  size_t obj_size = 0;
  if (!from_memory && !strcmp(ext, "obj") && options->lod_node <= 0 &&
      (r = bbc__read_whole_file(name, &obj, &obj_size, err)) != BBC_OK)
    return r;
  r = obj ? bbc__sniff_input(name, obj, obj_size, 1, options, err)
          : bbc__sniff_input(name, data, size, from_memory, options, err);
  if (r == BBC_OK && !strcmp(ext, "obj") && !options->accept_unused && (obj || from_memory))
    r = obj ? obj_cut_short(name, obj, obj_size, err)
            : obj_cut_short(name, (const char *)data, size, err);
  if (r != BBC_OK) {
    free(obj);
    return r;
  }
  /* Every .ply goes to our reader, mesh or point cloud: Assimp would drop
   * the points, accept damaged binary bodies without complaint, read
   * out-of-range face indices from uninitialised memory, and it never
   * returns on a header without end_header. VRML: Debian's Assimp has no
   * VRML importer. */
  int ply = !strcmp(ext, "ply"), wrl = !strcmp(ext, "wrl") || !strcmp(ext, "vrml"),
      xyz = !strcmp(ext, "xyz") || !strcmp(ext, "pts") || !strcmp(ext, "txt");
  if (ply || wrl || xyz) {
    char *buf = NULL;
    size_t n = size;
    if (from_memory) {
      buf = malloc(size + 1);
      if (!buf) return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
      if (size) memcpy(buf, data, size);
      buf[size] = 0;
    } else if ((r = bbc__read_whole_file(name, &buf, &n, err)) != BBC_OK) {
      return r;
    }
    /* the PLY and XYZ parsers finish the mesh themselves */
    r = ply   ? bbc__parse_ply(name, buf, n, options, mesh, err)
        : xyz ? bbc__parse_xyz(name, buf, n, options, mesh, err)
              : bbc__parse_vrml(name, buf, n, options, mesh, err);
  } else {
    /* OBJ files: our reader, which gives Assimp's mesh (load_obj.c), or
     * Assimp for what it leaves to it */
    int deferred = 1;
    if (obj) {
      r = bbc__parse_obj(name, obj, obj_size, options, mesh, &deferred, err);
      free(obj);
    }
    if (deferred)
      r = from_memory ? bbc__load_assimp_memory(name, data, size, options, mesh, err)
                      : bbc__load_assimp(name, options, mesh, err);
    if (r == BBC_OK && !from_memory && !strcmp(ext, "obj")) check_mtllib(name, options);
  }
  return bbc__load_finish(name, r, !ply && !xyz, options, mesh, err);
}

bbc_result bbc__load_finish(const char *name, bbc_result r, int finalize,
                            const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  if (finalize) {
    if (r == BBC_OK) r = bbc_mesh_finalize(mesh, !options->flat_normals, name, err);
    if (r == BBC_OK && mesh->dropped_degenerate)
      bbc__log(&options->callbacks, BBC_LOG_WARNING, "%s: dropped %zu zero-area triangles", name,
               mesh->dropped_degenerate);
    bbc__progress(&options->callbacks, "load", 1.0);
  }
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  mesh->no_mipmaps = options->no_mipmaps;
  recentre(mesh);
  return BBC_OK;
}

bbc_result bbc_mesh_load(const char *path, const bbc_load_options *options, bbc_mesh *mesh,
                         bbc_error *err) {
  assert(path && mesh);
  return load_any(path, NULL, 0, 0, options, mesh, err);
}

bbc_result bbc_mesh_load_memory(const char *name, const void *data, size_t size,
                                const bbc_load_options *options, bbc_mesh *mesh, bbc_error *err) {
  assert((data || size == 0) && mesh);
  return load_any(name ? name : "(memory)", data, size, 1, options, mesh, err);
}

void bbc_load_options_default(bbc_load_options *options) {
  assert(options);
  memset(options, 0, sizeof *options);
}
