/* fuzz_3ds.c — libFuzzer harness: a .3ds read by Assimp from memory, then our
 * mesh building (materials, groups, nodes, triangles), finishing and frame
 * (see fuzz_load.h). Crashes inside Assimp are Assimp's (Debian's
 * libassimp); the harness runs in make fuzz, not in CI. */
#include "fuzz_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  return bbc_fuzz_load("fuzz.3ds", data, size);
}
