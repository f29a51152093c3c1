/* path.c — paths of the files the library reads and writes: input checks,
 * extensions, folders. */
#include "io.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

bbc_result bbc__check_input_file(const char *path, bbc_error *err) {
  struct stat st;
  if (!path || !*path) return bbc__fail(err, BBC_ERROR_NOT_FOUND, "no input file given");
  if (stat(path, &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR)
      return bbc__fail(err, BBC_ERROR_NOT_FOUND, "%s: no such file", path);
    return bbc__fail(err, BBC_ERROR_IO, "%s: cannot access: %s", path, strerror(errno));
  }
  if (S_ISDIR(st.st_mode))
    return bbc__fail(err, BBC_ERROR_NOT_A_FILE, "%s: is a folder, not a model file", path);
  if (!S_ISREG(st.st_mode))
    return bbc__fail(err, BBC_ERROR_NOT_A_FILE, "%s: not a regular file", path);
  FILE *f = fopen(path, "rb");
  if (!f) return bbc__fail(err, BBC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  fclose(f);
  if (st.st_size == 0) return bbc__fail(err, BBC_ERROR_EMPTY, "%s: file is empty", path);
  return BBC_OK;
}

void bbc__path_extension(const char *path, char *ext, size_t ext_size) {
  ext[0] = 0;
  const char *slash = strrchr(path, '/');
  const char *dot = strrchr(path, '.');
  if (!dot || (slash && dot < slash) || ext_size == 0) return;
  size_t i = 0;
  for (const char *p = dot + 1; *p && i + 1 < ext_size; p++)
    ext[i++] = (char)tolower((unsigned char)*p);
  ext[i] = 0;
}

void bbc__path_folder(const char *path, char *folder, size_t folder_size) {
  snprintf(folder, folder_size, "%s", path);
  char *slash = strrchr(folder, '/');
  if (slash)
    slash[1] = 0;
  else
    folder[0] = 0;
}

int bbc__file_exists(const char *p) {
  struct stat st;
  return stat(p, &st) == 0 && S_ISREG(st.st_mode);
}
