/* fuzz_forest_model.c — libFuzzer harness: forest's model description file
 * (thesis Appendix B), parsed from memory. */
#include <stddef.h>
#include <stdint.h>

#include "bbc_forest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  bbc_forest_model model;
  bbc_error err;
  if (bbc_forest_model_parse((const char *)data, size, "fuzz.mdl", &model, &err) == BBC_OK)
    bbc_forest_model_free(&model);
  return 0;
}
