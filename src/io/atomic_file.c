/* atomic_file.c — outputs written to a temporary file and renamed into place,
 * so that a failed or interrupted run never leaves a half-written file. */
#include "io.h"

#include <assert.h>
#include <ctype.h>

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Distinguishes temporary names of one process; the file system's O_EXCL
 * makes the final choice, so this is not a correctness-critical global. */
static atomic_uint g_temp_counter;

bbc_result bbc__atomic_open(bbc__atomic_file *af, const char *path, bbc_error *err) {
  memset(af, 0, sizeof *af);
  size_t n = strlen(path);
  af->final_path = bbc__strdup(path);
  af->temp_path = malloc(n + 40);
  if (!af->final_path || !af->temp_path) {
    bbc__atomic_abort(af);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  }
  /* Same folder as the destination: rename() is atomic only within one file
   * system. open(O_EXCL) with mode 0666 (not mkstemp's 0600) so the output
   * gets the permissions the user's umask asks for. */
  int fd = -1, e = 0;
  for (int attempt = 0; attempt < 100 && fd < 0; attempt++) {
    unsigned k = atomic_fetch_add(&g_temp_counter, 1u);
    snprintf(af->temp_path, n + 40, "%s.tmp.%ld.%u", path, (long)getpid(), k);
    fd = open(af->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    e = errno;
    if (fd < 0 && e != EEXIST) break;
  }
  if (fd < 0) {
    free(af->temp_path);
    af->temp_path = NULL;
    bbc__atomic_abort(af);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot create output: %s", path, strerror(e));
  }
  af->fp = fdopen(fd, "wb");
  if (!af->fp) {
    close(fd);
    bbc__atomic_abort(af);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot open output", path);
  }
  return BBC_OK;
}

bbc_result bbc__atomic_commit(bbc__atomic_file *af, bbc_error *err) {
  int failed = ferror(af->fp) != 0;
  if (fflush(af->fp) != 0) failed = 1;
  int e = errno;
  if (fclose(af->fp) != 0) failed = 1;
  af->fp = NULL;
  if (!failed && rename(af->temp_path, af->final_path) != 0) {
    e = errno;
    failed = 1;
  }
  if (failed) {
    bbc_result r =
        bbc__fail(err, BBC_ERROR_IO, "%s: write failed: %s", af->final_path, strerror(e));
    bbc__atomic_abort(af);
    return r;
  }
  free(af->temp_path);
  free(af->final_path);
  af->temp_path = af->final_path = NULL;
  return BBC_OK;
}

void bbc__atomic_abort(bbc__atomic_file *af) {
  if (af->fp) fclose(af->fp);
  if (af->temp_path) unlink(af->temp_path);
  free(af->temp_path);
  free(af->final_path);
  memset(af, 0, sizeof *af);
}

bbc_result bbc_write_file_atomic(const char *path, const void *data, size_t size, bbc_error *err) {
  assert(path && (data || size == 0));
  bbc__atomic_file af;
  bbc_result r = bbc__atomic_open(&af, path, err);
  if (r != BBC_OK) return r;
  if (size && fwrite(data, 1, size, af.fp) != size) {
    int e = errno;
    bbc__atomic_abort(&af);
    return bbc__fail(err, BBC_ERROR_IO, "%s: write failed: %s", path,
                     e ? strerror(e) : "short write");
  }
  return bbc__atomic_commit(&af, err);
}
