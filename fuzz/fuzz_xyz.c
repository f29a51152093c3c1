/* fuzz_xyz.c — libFuzzer harness: the .xyz reader (see fuzz_load.h). */
#include "fuzz_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  return bbc_fuzz_load("fuzz.xyz", data, size);
}
