/* Untrusted text (a case file's token, a path, an option's value, a field read from a file)
 * quoted for a terminal or a message. Private: every binary links its own copy (src/base). */
#ifndef VS_QUOTE_H
#define VS_QUOTE_H

#include <stddef.h>

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

/* s quoted by value, for a message: vs_q(path).s lives until the end of the printf that uses
 * it. */
typedef struct {
  char s[1024];
} vs_quoted;
static inline vs_quoted vs_q(const char *s) {
  vs_quoted q;
  vs_quote(s, q.s, sizeof q.s);
  return q;
}

#endif
