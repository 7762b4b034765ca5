/* Numbers from text: a strict scanner for the accepted forms (see parse.h), then strtod/strtol
 * for the value, so that nothing the C library would also accept (hex, inf, nan, blanks) slips
 * through in one place and not another. */
#define _POSIX_C_SOURCE 200809L /* strncasecmp */
#include "parse.h"
#include "quote.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <strings.h>

static size_t digits(const char *s) {
  size_t n = 0;
  while (s[n] >= '0' && s[n] <= '9') n++;
  return n;
}

/* Length of the longest prefix of s in the accepted real (or integer) form; 0 if none. */
static size_t scan(const char *s, bool integer) {
  size_t i = (s[0] == '+' || s[0] == '-') ? 1 : 0;
  size_t whole = digits(s + i), frac = 0;
  i += whole;
  if (!integer && s[i] == '.') {
    frac = digits(s + i + 1);
    if (whole + frac > 0) i += 1 + frac;
  }
  if (whole + frac == 0) return 0;
  if (!integer && (s[i] == 'e' || s[i] == 'E')) {
    size_t j = i + 1 + ((s[i + 1] == '+' || s[i + 1] == '-') ? 1 : 0);
    size_t ex = digits(s + j);
    if (ex > 0) i = j + ex;
  }
  return i;
}

/* Why s (which does not scan as a whole number) is refused. */
static vs_num_status refuse(const char *s, bool integer) {
  if (*s == '\0') return VS_NUM_EMPTY;
  const char *p = s + ((s[0] == '+' || s[0] == '-') ? 1 : 0);
  if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) return VS_NUM_HEX;
  if (strncasecmp(p, "inf", 3) == 0 || strncasecmp(p, "nan", 3) == 0) return VS_NUM_NOT_FINITE;
  size_t n = scan(s, integer);
  if (n == 0) return VS_NUM_NOT_NUMBER;
  if (integer && scan(s, false) > n) /* 5.5, 5e1: a real, not an integer */
    return s[scan(s, false)] == '\0' ? VS_NUM_NOT_INTEGER : VS_NUM_TRAILING;
  return VS_NUM_TRAILING;
}

vs_num_status vs_parse_double(const char *s, double *out) {
  size_t n = scan(s, false);
  if (n == 0 || s[n] != '\0') return refuse(s, false);
  errno = 0;
  double v = strtod(s, NULL);
  if (errno == ERANGE || !isfinite(v)) return VS_NUM_OUT_OF_RANGE;
  *out = v;
  return VS_NUM_OK;
}

vs_num_status vs_parse_long(const char *s, long *out) {
  size_t n = scan(s, true);
  if (n == 0 || s[n] != '\0') return refuse(s, true);
  errno = 0;
  long v = strtol(s, NULL, 10);
  if (errno == ERANGE) return VS_NUM_OUT_OF_RANGE;
  *out = v;
  return VS_NUM_OK;
}

const char *vs_num_reason(vs_num_status st) {
  switch (st) {
  case VS_NUM_OK: return "ok";
  case VS_NUM_EMPTY: return "empty value (expected a number)";
  case VS_NUM_NOT_NUMBER: return "not a number";
  case VS_NUM_TRAILING: return "unexpected characters after the number";
  case VS_NUM_HEX: return "hexadecimal is not accepted (write the number in decimal)";
  case VS_NUM_NOT_FINITE: return "not a finite number";
  case VS_NUM_NOT_INTEGER: return "integer expected";
  case VS_NUM_OUT_OF_RANGE: return "out of range";
  }
  return "invalid number";
}

/* Echo at most this much of the user's text in a message (quoted, "..." beyond). */
enum { ECHO_MAX = 64 };
typedef struct {
  char s[ECHO_MAX + 4];
} echo_buf;

vs_status vs_parse_option_int(const char *option, const char *text, int lo, int hi, int *out,
                              vs_error *err) {
  long v = 0;
  vs_num_status st = vs_parse_long(text, &v);
  if (st == VS_NUM_OK && (v < lo || v > hi)) st = VS_NUM_OUT_OF_RANGE;
  echo_buf b;
  if (st != VS_NUM_OK)
    return vs_error_set(err, VS_ERR_USAGE, "%s %s: %s (allowed: integer in [%d, %d])", option,
                        vs_quote(text, b.s, sizeof b.s), vs_num_reason(st), lo, hi);
  *out = (int)v;
  return VS_OK;
}

vs_status vs_parse_option_double(const char *option, const char *text, double lo, double hi,
                                 double *out, vs_error *err) {
  double v = 0.0;
  vs_num_status st = vs_parse_double(text, &v);
  if (st == VS_NUM_OK && !(v >= lo && v <= hi)) st = VS_NUM_OUT_OF_RANGE;
  echo_buf b;
  if (st != VS_NUM_OK)
    return vs_error_set(err, VS_ERR_USAGE, "%s %s: %s (allowed: [%g, %g])", option,
                        vs_quote(text, b.s, sizeof b.s), vs_num_reason(st), lo, hi);
  *out = v;
  return VS_OK;
}
