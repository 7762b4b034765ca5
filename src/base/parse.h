/* Numbers from text: the one parser behind the case file, --set and every command-line option, so
 * that the same text means the same number everywhere.
 *
 * Accepted forms (C locale, whole text, nothing before or after):
 *   real:    [+-] digits [. [digits]] [(e|E) [+-] digits]   or   [+-] . digits [exponent]
 *            e.g. 300, -45, 0.5, .5, 5., 1e-3, 2.5E+4
 *   integer: [+-] digits                                     e.g. 55, -1, +3
 * Refused: empty text, blanks, hexadecimal (0x10, 0x1p3), inf/infinity/nan in any case, digit
 * separators, units or any trailing character, and magnitudes a double cannot hold (overflow
 * such as 1e999, or underflow such as 1e-400 that would silently become 0 or lose precision). */
#ifndef VOUSSOIR_PARSE_H
#define VOUSSOIR_PARSE_H

#include "voussoir/status.h"

typedef enum {
  VS_NUM_OK = 0,
  VS_NUM_EMPTY,        /* "" */
  VS_NUM_NOT_NUMBER,   /* no number at the start: "abc", " 3" */
  VS_NUM_TRAILING,     /* a number followed by anything: "3mm", "2x", "3 " */
  VS_NUM_HEX,          /* "0x10", "-0X1p3" */
  VS_NUM_NOT_FINITE,   /* "nan", "inf", "-Infinity" */
  VS_NUM_NOT_INTEGER,  /* a real where an integer is expected: "5.5", "5e1" */
  VS_NUM_OUT_OF_RANGE, /* beyond a double (1e999, 1e-400) or a long (99999999999999999999) */
} vs_num_status;

/* Parse s (not NULL) as a real. *out is written only on VS_NUM_OK. */
vs_num_status vs_parse_double(const char *s, double *out);

/* Parse s (not NULL) as an integer (plain decimal digits with an optional sign). *out is written
 * only on VS_NUM_OK. */
vs_num_status vs_parse_long(const char *s, long *out);

/* Short reason for a status, e.g. "unexpected characters after the number"; never NULL. */
const char *vs_num_reason(vs_num_status st);

/* Command-line helpers: parse the value text of option (e.g. "-j"), require lo <= value <= hi,
 * and on failure fill err (VS_ERR_USAGE) with "OPTION TEXT: reason (allowed: ...)". */
vs_status vs_parse_option_int(const char *option, const char *text, int lo, int hi, int *out,
                              vs_error *err);
vs_status vs_parse_option_double(const char *option, const char *text, double lo, double hi,
                                 double *out, vs_error *err);

#endif
