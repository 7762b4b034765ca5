/* voussoir status codes and error detail.
 * One X-macro list generates the enum and the messages, so no code lacks a message. */
#ifndef VOUSSOIR_STATUS_H
#define VOUSSOIR_STATUS_H

#include "voussoir/api.h"

#include <stddef.h>

#define VS_STATUS_LIST(X)                                                          \
  X(VS_OK, 0, "ok")                                                                \
  X(VS_ERR_NOMEM, -1, "out of memory")                                             \
  X(VS_ERR_IO, -2, "input/output error")                                           \
  X(VS_ERR_PARSE, -3, "malformed case file")                                       \
  X(VS_ERR_INVALID, -4, "invalid parameter")                                       \
  X(VS_ERR_SOLVER, -5, "solver failure")                                           \
  X(VS_ERR_NO_EQUILIBRIUM, -6, "no equilibrium found")                             \
  X(VS_ERR_USAGE, -7, "invalid command line")                                      \
  X(VS_ERR_INTERNAL, -8, "internal error")                                         \
  X(VS_ERR_INTERRUPTED, -9, "interrupted")                                         \
  X(VS_ERR_WALL_TIME, -10, "stopped: wall-time limit reached")                     \
  X(VS_ERR_STOPPED, -11, "stopped by the caller")

typedef enum {
#define VS_STATUS_ENUM(name, value, msg) name = value,
  VS_STATUS_LIST(VS_STATUS_ENUM)
#undef VS_STATUS_ENUM
} vs_status;

/* Short, static description of a status code; never NULL. */
VS_API const char *vs_strerror(vs_status status);

/* Detail of the last error: a status and a human-readable message such as
 * "case.ini:14: joints.kn_N_mm3 = -3: must be > 0 (allowed: > 0)".
 * Caller-owned (usually on the stack); functions that fail fill it in. */
typedef struct {
  vs_status status;
  char msg[512];
} vs_error;

/* Reset err to VS_OK with an empty message. NULL is allowed and ignored. */
VS_API void vs_error_clear(vs_error *err);

/* Record status and a printf-style message in err (NULL allowed) and return status. The message
 * is quoted as a whole (control characters and escape sequences escaped), so that no error message carries a control character or a
 * byte a terminal would act on, whatever path or token it names. */
VS_API vs_status vs_error_set(vs_error *err, vs_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
