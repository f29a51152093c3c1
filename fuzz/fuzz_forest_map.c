/* fuzz_forest_map.c — libFuzzer harness: forest's map file (thesis
 * Appendix B), parsed from memory as `forest` parses it after reading it. */
#include <stddef.h>
#include <stdint.h>

#include "bbc_forest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  bbc_forest_map map;
  bbc_error err;
  if (bbc_forest_map_parse((const char *)data, size, "fuzz.map", &map, &err) == BBC_OK)
    bbc_forest_map_free(&map);
  return 0;
}
