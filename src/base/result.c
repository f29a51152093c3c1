/* result.c — result names and the small shared helpers of base.h. */
#include "base.h"

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

static bbc_result vfail(bbc_error *err, bbc_result code, const char *fmt, va_list ap) {
  if (err) {
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    err->code = code;
  }
  return code;
}

bbc_result bbc__fail(bbc_error *err, bbc_result code, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vfail(err, code, fmt, ap);
  va_end(ap);
  return code;
}

bbc_result bbc_error_set(bbc_error *err, bbc_result code, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vfail(err, code, fmt, ap);
  va_end(ap);
  return code;
}

static void vlog(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, va_list ap) {
  if (!cb || !cb->log) return;
  char buf[1024];
  vsnprintf(buf, sizeof buf, fmt, ap);
  cb->log(cb->user, level, buf);
}

void bbc__log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vlog(cb, level, fmt, ap);
  va_end(ap);
}

void bbc_callbacks_log(const bbc_callbacks *cb, bbc_log_level level, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vlog(cb, level, fmt, ap);
  va_end(ap);
}

void bbc__progress(const bbc_callbacks *cb, const char *stage, double fraction) {
  if (cb && cb->progress) cb->progress(cb->user, stage, fraction);
}

int bbc__cancelled(const bbc_callbacks *cb) {
  return cb && cb->cancel && cb->cancel(cb->user);
}

static int label_cancel(void *user) {
  bbc_label *l = user;
  return l->outer.cancel && l->outer.cancel(l->outer.user);
}

static void label_progress(void *user, const char *stage, double fraction) {
  bbc_label *l = user;
  snprintf(l->text, sizeof l->text, "%s: %s", l->label, stage);
  if (l->outer.progress) l->outer.progress(l->outer.user, l->text, fraction);
}

static void label_log(void *user, bbc_log_level level, const char *message) {
  bbc_label *l = user;
  snprintf(l->text, sizeof l->text, "%s: %s", l->label, message);
  if (l->outer.log) l->outer.log(l->outer.user, level, l->text);
}

static void label_debug(void *user, const bbc_debug_event *event) {
  bbc_label *l = user;
  bbc_debug_event e = *event;
  e.where = l->label;
  l->outer.debug(l->outer.user, &e);
}

void bbc_callbacks_label(const bbc_callbacks *in, bbc_label *l, bbc_callbacks *out, const char *fmt,
                         ...) {
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

double bbc__now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *const k_kind_names[BBC_PLANE_KIND_COUNT] = {
    "standard", "coplanar", "posttweaked", "cardboard", "parachute", "stem"};

const char *bbc_plane_kind_name(bbc_plane_kind kind) {
  return (unsigned)kind < BBC_PLANE_KIND_COUNT ? k_kind_names[kind] : "unknown";
}
