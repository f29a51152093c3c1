/* text_scan.c — the readers' shared pieces (text_scan.h). */
#include "text_scan.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* The whole file in memory, NUL terminated (io.h). */
bbc_result bbc__read_whole_file(const char *path, char **data, size_t *size, bbc_error *err) {
  *data = NULL;
  *size = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return bbc__fail(err, BBC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (fseeko(f, 0, SEEK_END) != 0) {
    int e = errno;
    fclose(f);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot seek: %s", path, strerror(e));
  }
  off_t end = ftello(f);
  if (end < 0 || fseeko(f, 0, SEEK_SET) != 0) {
    int e = errno;
    fclose(f);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot determine the file size: %s", path,
                     strerror(e));
  }
  if ((uintmax_t)end >= (uintmax_t)SIZE_MAX) {
    fclose(f);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: file is too large to load (%jd bytes)",
                     path, (intmax_t)end);
  }
  size_t n = (size_t)end;
  char *buf = malloc(n + 1);
  if (!buf) {
    fclose(f);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %zu bytes", path, n);
  }
  size_t got = n ? fread(buf, 1, n, f) : 0;
  int read_error = ferror(f);
  int e = errno;
  fclose(f);
  if (got != n) {
    free(buf);
    if (read_error)
      return bbc__fail(err, BBC_ERROR_IO, "%s: read failed after %zu of %zu bytes: %s", path, got,
                       n, strerror(e));
    return bbc__fail(err, BBC_ERROR_IO, "%s: file shrank while reading (%zu of %zu bytes)", path,
                     got, n);
  }
  buf[n] = '\0';
  *data = buf;
  *size = n;
  return BBC_OK;
}

const char *bbc__quote_token(char *out, size_t out_size, const char *s, const char *e) {
  size_t n = 0;
  while (s < e && n + 4 < out_size && n < 24) {
    unsigned char c = (unsigned char)*s++;
    out[n++] = (c < 0x20 || c == 0x7f) ? '?' : (char)c;
  }
  if (s < e && n + 4 <= out_size) {
    memcpy(out + n, "...", 3);
    n += 3;
  }
  out[n] = '\0';
  return out;
}

bbc_result bbc__finish_loaded(bbc_mesh *mesh, const bbc_load_options *options, const char *path,
                              bbc_error *err) {
  const bbc_callbacks *cb = options ? &options->callbacks : NULL;
  bbc_result r = bbc_mesh_finalize(mesh, options ? !options->flat_normals : 1, path, err);
  if (r != BBC_OK) {
    bbc_mesh_free(mesh);
    return r;
  }
  if (mesh->kind == BBC_MESH_TRIANGLES && mesh->dropped_degenerate)
    bbc__log(cb, BBC_LOG_WARNING, "%s: dropped %zu zero-area triangles", path,
             mesh->dropped_degenerate);
  bbc__progress(cb, "load", 1.0);
  return BBC_OK;
}
