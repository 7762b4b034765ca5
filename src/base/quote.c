/* Untrusted text made safe to show (quote.h). */
#include "quote.h"

#include <stdio.h>
#include <string.h>

#include "utf8.h"

/* ---------------------------------------------------------------------------------------------
 * Quoting (quote.h) */

/* A character shown as it is: printable, and nothing a terminal acts on or that reorders or
 * breaks the line it is shown in. */
static int shown(unsigned long cp) {
  if (cp < 0x20 || cp == 0x7f || (cp >= 0x80 && cp < 0xa0)) return 0;
  if (cp == 0x061c || cp == 0x200e || cp == 0x200f) return 0;
  if ((cp >= 0x2028 && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069)) return 0;
  return 1;
}

/* The next piece of the quoted text of p: a character kept as it is (its bytes), or the escape
 * of the byte at p, into esc. *len: its length; *used: the bytes of p it stands for. */
static const char *next_piece(const unsigned char *p, char esc[5], int *len, int *used) {
  unsigned long cp = 0;
  const int n = vs_utf8_char(p, &cp);
  if (n > 0 && shown(cp)) {
    *len = *used = n;
    return (const char *)p;
  }
  static const char hex[] = "0123456789abcdef";
  const char named = *p == '\n' ? 'n' : *p == '\t' ? 't' : *p == '\r' ? 'r' : 0;
  esc[0] = '\\';
  if (named) {
    esc[1] = named;
    *len = 2;
  } else {
    esc[1] = 'x';
    esc[2] = hex[*p >> 4];
    esc[3] = hex[*p & 15];
    *len = 4;
  }
  *used = 1;
  return esc;
}

/* Write the quoted text of p into buf while it fits in limit bytes (whole pieces only;
 * *written: how many); returns the length of the whole quoted text. */
static size_t quote_into(const unsigned char *p, char *buf, size_t limit, size_t *written) {
  size_t total = 0;
  int full = 0;
  *written = 0;
  while (*p != '\0') {
    char esc[5];
    int len = 0, used = 0;
    const char *piece = next_piece(p, esc, &len, &used);
    if (!full && *written + (size_t)len <= limit) {
      memcpy(buf + *written, piece, (size_t)len);
      *written += (size_t)len;
    } else {
      full = 1;
    }
    total += (size_t)len;
    p += used;
  }
  return total;
}

const char *vs_quote(const char *s, char *buf, size_t size) {
  if (buf == NULL || size == 0) return buf;
  const unsigned char *p = (const unsigned char *)(s != NULL ? s : "");
  size_t w = 0;
  if (quote_into(p, buf, size - 1, &w) > size - 1 && size >= 4) {
    quote_into(p, buf, size - 4, &w); /* cut before the piece that does not fit, then "..." */
    memcpy(buf + w, "...", 3);
    w += 3;
  }
  buf[w] = '\0';
  return buf;
}

int vs_quote_clean(const char *s, size_t *bad) {
  const unsigned char *p = (const unsigned char *)(s != NULL ? s : "");
  for (const unsigned char *q = p; *q != '\0';) {
    char esc[5];
    int len = 0, used = 0;
    if (next_piece(q, esc, &len, &used) == esc) {
      if (bad != NULL) *bad = (size_t)(q - p);
      return 0;
    }
    q += used;
  }
  if (bad != NULL) *bad = strlen((const char *)p);
  return 1;
}
