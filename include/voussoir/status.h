/* voussoir status codes and error detail.
 * One X-macro list generates the enum and the messages, so no code lacks a message. */
#ifndef VOUSSOIR_STATUS_H
#define VOUSSOIR_STATUS_H

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
  X(VS_ERR_INTERRUPTED, -9, "interrupted")                                        \
  X(VS_ERR_WALL_TIME, -10, "stopped: wall-time limit reached")

typedef enum {
#define VS_STATUS_ENUM(name, value, msg) name = value,
  VS_STATUS_LIST(VS_STATUS_ENUM)
#undef VS_STATUS_ENUM
} vs_status;

/* Short, static description of a status code; never NULL. */
const char *vs_strerror(vs_status status);

/* Detail of the last error: a status and a human-readable message such as
 * "case.ini:14: joints.kn_N_mm3 = -3: must be > 0 (allowed: > 0)".
 * Caller-owned (usually on the stack); functions that fail fill it in. */
typedef struct {
  vs_status status;
  char msg[512];
} vs_error;

/* Reset err to VS_OK with an empty message. NULL is allowed and ignored. */
void vs_error_clear(vs_error *err);

/* Record status and a printf-style message in err (NULL allowed) and return status. The message
 * is quoted (vs_quote) as a whole, so that no error message carries a control character or a
 * byte a terminal would act on, whatever path or token it names. */
vs_status vs_error_set(vs_error *err, vs_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Untrusted text (a case file's token, a path, an option's value, a field read from a file)
 * made safe to show on a terminal or to put in a message, into buf (size bytes, NUL-terminated;
 * returns buf; s NULL reads as ""). Kept as it is: printable ASCII (0x20-0x7e) and well-formed
 * UTF-8 of printable characters, so that a file name with accents reads as it was typed (a UTF-8
 * terminal cannot be made to act on a printable character). Escaped: newline, tab and carriage
 * return as \n, \t, \r, and as \xNN every other byte that could move the cursor, change the
 * terminal's state or hide what is shown: the C0 controls and DEL, the C1 controls U+0080-U+009F
 * (an 8-bit terminal reads 0x9b as ESC [), the characters that reorder or break the displayed
 * line (U+061C, U+200E, U+200F, U+2028-U+202E, U+2066-U+2069), and each byte of what is not
 * well-formed UTF-8 (stray continuation bytes, overlong forms, surrogates, beyond U+10FFFF).
 * A backslash is kept as it is: quoting is idempotent, so text quoted where it was read and
 * again where it is printed reads the same (at the price of the four characters \x1b typed in
 * a name reading like an escaped ESC). When the quoted text does not fit, it is cut before a
 * whole character or escape and ends with "..." (when size >= 4). */
const char *vs_quote(const char *s, char *buf, size_t size);

/* 1 when vs_quote would keep s as it is (nothing to escape), else 0; *bad (NULL allowed)
 * receives the offset of the first byte it would escape, or strlen(s). */
int vs_quote_clean(const char *s, size_t *bad);

#endif
