/* Status messages (generated from the X-macro list), the error detail object, and the quoting
 * that keeps untrusted text in a message from acting on the terminal that shows it. */
#include "voussoir/status.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "quote.h"

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
  char raw[sizeof err->msg]; /* formatted apart: err->msg may be among the arguments */
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(raw, sizeof raw, fmt, ap);
  va_end(ap);
  vs_quote(raw, err->msg, sizeof err->msg);
  return status;
}
