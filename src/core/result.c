/* result.c — result names and the small shared helpers of internal.h. */
#include "internal.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

const char *bbc_result_string(bbc_result result) {
  switch (result) {
  case BBC_OK:
    return "ok";
  case BBC_ERROR_INVALID_ARGUMENT:
    return "invalid argument";
  case BBC_ERROR_OUT_OF_RANGE:
    return "value out of range";
  case BBC_ERROR_NOT_FOUND:
    return "file not found";
  case BBC_ERROR_NOT_A_FILE:
    return "not a regular file";
  case BBC_ERROR_IO:
    return "input/output error";
  case BBC_ERROR_UNSUPPORTED_FORMAT:
    return "unsupported format";
  case BBC_ERROR_CORRUPT:
    return "corrupt or truncated file";
  case BBC_ERROR_INVALID_GEOMETRY:
    return "invalid geometry";
  case BBC_ERROR_EMPTY:
    return "no usable geometry";
  case BBC_ERROR_OUT_OF_MEMORY:
    return "out of memory";
  case BBC_ERROR_CANCELLED:
    return "cancelled";
  case BBC_RESULT_COUNT:
    break;
  }
  return "unknown error";
}

bbc_result bbc__fail(bbc_error *err, bbc_result code, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    err->code = code;
  }
  return code;
}

void bbc__log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...) {
  if (!cb || !cb->log) return;
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  cb->log(cb->user, level, buf);
}

void bbc__progress(const bbc_callbacks *cb, const char *stage, double fraction) {
  if (cb && cb->progress) cb->progress(cb->user, stage, fraction);
}

int bbc__cancelled(const bbc_callbacks *cb) {
  return cb && cb->cancel && cb->cancel(cb->user);
}

static int label_cancel(void *user) {
  bbc__label *l = user;
  return l->outer.cancel && l->outer.cancel(l->outer.user);
}

static void label_progress(void *user, const char *stage, double fraction) {
  bbc__label *l = user;
  snprintf(l->text, sizeof l->text, "%s: %s", l->label, stage);
  if (l->outer.progress) l->outer.progress(l->outer.user, l->text, fraction);
}

static void label_log(void *user, bbc_log_level level, const char *message) {
  bbc__label *l = user;
  snprintf(l->text, sizeof l->text, "%s: %s", l->label, message);
  if (l->outer.log) l->outer.log(l->outer.user, level, l->text);
}

static void label_debug(void *user, const bbc_debug_event *event) {
  bbc__label *l = user;
  bbc_debug_event e = *event;
  e.where = l->label;
  l->outer.debug(l->outer.user, &e);
}

void bbc__label_callbacks(const bbc_callbacks *in, bbc__label *l, bbc_callbacks *out,
                          const char *fmt, ...) {
  memset(l, 0, sizeof *l);
  if (in) l->outer = *in;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(l->label, sizeof l->label, fmt, ap);
  va_end(ap);
  out->progress = l->outer.progress ? label_progress : NULL;
  out->log = l->outer.log ? label_log : NULL;
  out->cancel = l->outer.cancel ? label_cancel : NULL;
  out->debug = l->outer.debug ? label_debug : NULL;
  out->user = l;
}

char *bbc__strdup(const char *s) {
  if (!s) return NULL;
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

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

double bbc__now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
