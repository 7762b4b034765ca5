/* Private: the one UTF-8 decoder of the text that is quoted or escaped (status.c's vs_quote,
 * the JSON of report.c, the XML of xdmf.c), so that all of them agree on what is well-formed. */
#ifndef VS_UTF8_H
#define VS_UTF8_H

/* Length (1 to 4) of the well-formed UTF-8 character that starts s, with its code point in
 * *cp; 0 when s does not start one: a stray continuation byte, an overlong form, a surrogate,
 * a code point beyond U+10FFFF, or a sequence cut short (by the NUL that ends s: no byte after
 * a NUL is read). ASCII, NUL included, is one byte. The ranges are those of the Unicode
 * Standard's table of well-formed byte sequences (Table 3-7). */
static inline int vs_utf8_char(const unsigned char *s, unsigned long *cp) {
  const unsigned b = s[0];
  int n = 0;
  unsigned lo = 0x80, hi = 0xbf; /* range of the second byte */
  if (b < 0x80) {
    *cp = b;
    return 1;
  }
  if (b >= 0xc2 && b <= 0xdf) n = 2;
  else if (b >= 0xe0 && b <= 0xef) n = 3;
  else if (b >= 0xf0 && b <= 0xf4) n = 4;
  else return 0;
  if (b == 0xe0) lo = 0xa0;      /* no overlong 3-byte form */
  else if (b == 0xed) hi = 0x9f; /* no surrogate */
  else if (b == 0xf0) lo = 0x90; /* no overlong 4-byte form */
  else if (b == 0xf4) hi = 0x8f; /* nothing beyond U+10FFFF */
  if (s[1] < lo || s[1] > hi) return 0;
  unsigned long c = b & (0x7fu >> n);
  for (int i = 1; i < n; i++) {
    if (i > 1 && (s[i] < 0x80 || s[i] > 0xbf)) return 0;
    c = (c << 6) | (s[i] & 0x3fu);
  }
  *cp = c;
  return n;
}

#endif
