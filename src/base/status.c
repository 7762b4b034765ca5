/* Status messages (generated from the X-macro list) and the error detail object. */
#include "voussoir/status.h"

#include <stdarg.h>
#include <stdio.h>

const char *vs_strerror(vs_status status) {
  switch (status) {
#define VS_STATUS_CASE(name, value, msg)                                           \
  case name:                                                                       \
    return msg;
    VS_STATUS_LIST(VS_STATUS_CASE)
#undef VS_STATUS_CASE
  }
  return "unknown status";
}

void vs_error_clear(vs_error *err) {
  if (err == NULL) return;
  err->status = VS_OK;
  err->msg[0] = '\0';
}

vs_status vs_error_set(vs_error *err, vs_status status, const char *fmt, ...) {
  if (err == NULL) return status;
  err->status = status;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err->msg, sizeof err->msg, fmt, ap);
  va_end(ap);
  return status;
}
