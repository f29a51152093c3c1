/* fuzz_batch.c — libFuzzer harness: the bytes as a batch file of the command
 * language (Appendix A), parsed command by command with bbc_script_next as
 * bbcgen exec does; each `set` is applied with bbc_params_set as bbcgen
 * applies it (nothing is loaded, run or written). Parsed values are checked
 * against what the language allows. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  bbc_command *k = malloc(sizeof *k);
  if (!k) return 0;
  bbc_params params;
  bbc_params_default(&params);
  size_t pos = 0;
  int line = 0;
  bbc_error err;
  for (;;) {
    int before = line;
    if (bbc_script_next((const char *)data, size, "fuzz.bbc", &pos, &line, k, &err) != BBC_OK) {
      if (!err.message[0] || strlen(err.message) >= sizeof err.message) __builtin_trap();
      break;
    }
    if (pos > size || line < before) __builtin_trap();
    if (k->kind == BBC_COMMAND_NONE) {
      if (pos != size) __builtin_trap(); /* the end only */
      break;
    }
    if (k->kind <= BBC_COMMAND_NONE || k->kind >= BBC_COMMAND_KIND_COUNT) __builtin_trap();
    switch (k->kind) {
    case BBC_COMMAND_SET:
      if (!k->name[0] || !k->rest[0]) __builtin_trap();
      if (bbc_param_find(k->name)) {
        bbc_params p = params;
        if (bbc_params_set(&p, k->name, k->rest, &err) == BBC_OK && !k->part[0]) params = p;
      }
      break;
    case BBC_COMMAND_SHADE:
      if (k->shade_voxels < 0 || k->shade_voxels > 512 || !(k->shade_ambient >= 0) ||
          k->shade_ambient > 1)
        __builtin_trap();
      break;
    case BBC_COMMAND_SPLIT:
      if (k->split == BBC_SPLIT_PATTERNS && !k->rest[0]) __builtin_trap();
      break;
    case BBC_COMMAND_LOAD:
    case BBC_COMMAND_EXEC:
    case BBC_COMMAND_BBCLOAD:
      if (!k->arg[0]) __builtin_trap();
      break;
    default:
      break;
    }
  }
  free(k);
  return 0;
}
