/* fuzz_objr.c — libFuzzer harness for our OBJ reader (src/io/load_obj.c):
 * the bytes as an OBJ file's, through bbc__parse_obj (libraries named by
 * mtllib are looked for beside "fuzz.obj", in the working folder), then,
 * when it did not leave the file to Assimp, the conversion's finishing and
 * the frame. Assimp itself is not run: what the reader defers goes no
 * further here (fuzz_obj feeds Assimp). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bbc.h"
#include "io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *buf = malloc(size + 1);
  if (!buf) return 0;
  if (size) memcpy(buf, data, size);
  buf[size] = 0;
  bbc_load_options o;
  bbc_load_options_default(&o);
  o.skip_textures = 1;
  bbc_mesh m;
  memset(&m, 0, sizeof m);
  bbc_error err;
  int deferred = 1;
  bbc_result r = bbc__parse_obj("fuzz.obj", buf, size, &o, &m, &deferred, &err);
  free(buf);
  if (deferred) return 0;
  if (bbc__load_finish("fuzz.obj", r, 1, &o, &m, &err) == BBC_OK) {
    if (!(m.radius >= 0) || m.radius != m.radius) __builtin_trap();
    bbc_mesh_free(&m);
  }
  return 0;
}
