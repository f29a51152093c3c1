/* fuzz_load.h — one libFuzzer entry point per reader we own: the bytes as a
 * file of a given extension, through bbc_mesh_load_memory (the function
 * bbc_mesh_load uses after reading the file), then freed. Textures are not
 * decoded (no files are read or written). */
#ifndef BBC_FUZZ_LOAD_H
#define BBC_FUZZ_LOAD_H

#include <stddef.h>
#include <stdint.h>

#include "bbc.h"

static inline int bbc_fuzz_load(const char *name, const uint8_t *data, size_t size) {
  bbc_load_options o;
  bbc_load_options_default(&o);
  o.skip_textures = 1;
  bbc_mesh m;
  bbc_error err;
  if (bbc_mesh_load_memory(name, data, size, &o, &m, &err) == BBC_OK) {
    /* what the steps read first: the frame must be finite */
    if (!(m.radius >= 0) || m.radius != m.radius) __builtin_trap();
    bbc_mesh_free(&m);
  }
  return 0;
}

#endif
