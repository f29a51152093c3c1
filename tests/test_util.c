/* test_util.c — see test_util.h. */
#include "test_util.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

char *mkdtemp(char *template_path);

const char *tu_data_path(char *buf, size_t size, const char *rel) {
  snprintf(buf, size, "%s/%s", BBC_DATA_DIR, rel);
  return buf;
}

int tu_have_file(const char *path) {
  struct stat st;
  if (stat(path, &st) == 0) return 1;
  printf("SKIP: data file %s is missing\n", path);
  return 0;
}

char *tu_make_temp_dir(void) {
  const char *base = getenv("TMPDIR");
  if (!base || !*base) base = "/tmp";
  mkdir(base, 0777);
  size_t n = strlen(base) + 32;
  char *p = malloc(n);
  if (!p) return NULL;
  snprintf(p, n, "%s/bbctest.XXXXXX", base);
  if (!mkdtemp(p)) {
    free(p);
    return NULL;
  }
  return p;
}

char *tu_write_file(const char *dir, const char *name, const void *data, size_t size) {
  size_t n = strlen(dir) + strlen(name) + 2;
  char *p = malloc(n);
  if (!p) return NULL;
  snprintf(p, n, "%s/%s", dir, name);
  FILE *f = fopen(p, "wb");
  if (!f) {
    free(p);
    return NULL;
  }
  if (size) fwrite(data, 1, size, f);
  fclose(f);
  return p;
}

unsigned char *tu_read_file(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *buf = malloc((size_t)n + 1);
  if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
    free(buf);
    buf = NULL;
  }
  fclose(f);
  if (buf) {
    buf[n] = 0;
    if (size) *size = (size_t)n;
  }
  return buf;
}

int tu_same_file(const char *a, const char *b) {
  size_t na = 0, nb = 0;
  unsigned char *ta = tu_read_file(a, &na), *tb = tu_read_file(b, &nb);
  int same = ta && tb && na == nb && (na == 0 || !memcmp(ta, tb, na));
  free(ta);
  free(tb);
  return same;
}

void tu_remove_dir(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    size_t n = strlen(dir) + strlen(e->d_name) + 2;
    char *p = malloc(n);
    if (!p) continue;
    snprintf(p, n, "%s/%s", dir, e->d_name);
    struct stat st;
    if (stat(p, &st) == 0 && S_ISDIR(st.st_mode))
      tu_remove_dir(p);
    else
      unlink(p);
    free(p);
  }
  closedir(d);
  rmdir(dir);
}

char *tu_dir;

int tu_group_setup(void **state) {
  (void)state;
  tu_dir = tu_make_temp_dir();
  return tu_dir ? 0 : -1;
}

int tu_group_teardown(void **state) {
  (void)state;
  tu_remove_dir(tu_dir);
  free(tu_dir);
  tu_dir = NULL;
  return 0;
}

int tu_gltf_validate(const char *path) {
  /* scripts/tools/gltf_validate.sh, found from this file's path (CMake compiles it
   * by absolute path). */
  char script[1024];
  snprintf(script, sizeof script, "%s", __FILE__);
  char *slash = strrchr(script, '/');
  if (slash) *slash = 0;
  size_t len = strlen(script);
  snprintf(script + len, sizeof script - len, "%s",
           slash ? "/../scripts/tools/gltf_validate.sh" : "../scripts/tools/gltf_validate.sh");
  struct stat st;
  if (stat(script, &st) != 0) return 2;
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "'%s' '%s'", script, path);
  fflush(stdout);
  int rc = system(cmd);
  if (rc == -1 || !WIFEXITED(rc)) return 2;
  return WEXITSTATUS(rc);
}

void tu_mesh_begin(bbc_mesh *m, size_t max_tris, size_t materials, const char *const *names,
                   const float (*colours)[4], const char *group) {
  memset(m, 0, sizeof *m);
  m->kind = BBC_MESH_TRIANGLES;
  m->positions = calloc(12 * max_tris, sizeof(double));
  m->indices = calloc(3 * max_tris, sizeof(uint32_t));
  m->face_material = calloc(max_tris, sizeof(uint32_t));
  m->face_group = calloc(max_tris, sizeof(uint32_t));
  m->materials = calloc(materials, sizeof(bbc_material));
  m->material_count = materials;
  for (size_t i = 0; i < materials; i++) {
    m->materials[i].name = strdup(names[i]);
    m->materials[i].texture = -1;
    for (int k = 0; k < 4; k++) m->materials[i].base_color[k] = colours ? colours[i][k] : 1.0f;
  }
  m->group_count = 1;
  m->group_names = calloc(1, sizeof(char *));
  m->group_names[0] = strdup(group);
}

/* Appends corners p[0..n-1] as vertices and triangles (0 k k+1) of them. */
static void append_fan(bbc_mesh *m, const double *const *p, int n, uint32_t material) {
  size_t v = m->vertex_count;
  for (int i = 0; i < n; i++) memcpy(m->positions + 3 * (v + i), p[i], 3 * sizeof(double));
  for (int k = 1; k + 1 < n; k++) {
    size_t t = m->triangle_count++;
    m->indices[3 * t] = (uint32_t)v;
    m->indices[3 * t + 1] = (uint32_t)(v + k);
    m->indices[3 * t + 2] = (uint32_t)(v + k + 1);
    m->face_material[t] = material;
  }
  m->vertex_count += (size_t)n;
}

void tu_mesh_tri(bbc_mesh *m, const double *a, const double *b, const double *c,
                 uint32_t material) {
  const double *p[3] = {a, b, c};
  append_fan(m, p, 3, material);
}

void tu_mesh_quad(bbc_mesh *m, const double *a, const double *b, const double *c, const double *d,
                  uint32_t material) {
  const double *p[4] = {a, b, c, d};
  append_fan(m, p, 4, material);
}

void tu_mesh_from(bbc_mesh *m, const double *pos, size_t nv, const uint32_t *idx, size_t nt) {
  static const char *const names[1] = {"m"};
  tu_mesh_begin(m, nt, 1, names, NULL, "g");
  free(m->positions);
  m->positions = malloc(nv * 3 * sizeof(double));
  memcpy(m->positions, pos, nv * 3 * sizeof(double));
  m->vertex_count = nv;
  memcpy(m->indices, idx, nt * 3 * sizeof(uint32_t));
  m->triangle_count = nt;
}
