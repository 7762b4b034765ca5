/* A JSON string literal (report.h): the one writer of the JSON summaries, the record readers'
 * plots.json and the tools that print JSON. */
#include <stdio.h>

#include "utf8.h"
#include "voussoir/report.h"

/* JSON text is UTF-8 (RFC 8259): a byte of s that is not part of well-formed UTF-8 (a path in
 * another encoding) becomes U+FFFD, the replacement character, so the output stays valid JSON;
 * control characters and DEL are escaped, so that printing the JSON cannot act on a terminal. */
void vs_json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p;) {
    unsigned long cp = 0;
    const int n = vs_utf8_char(p, &cp);
    if (n == 0) fputs("\\ufffd", out);
    else if (*p == '"' || *p == '\\') fprintf(out, "\\%c", *p);
    else if (*p == '\n') fputs("\\n", out);
    else if (*p < 0x20 || *p == 0x7f) fprintf(out, "\\u%04x", *p);
    else fwrite(p, 1, (size_t)n, out);
    p += n > 0 ? n : 1;
  }
  fputc('"', out);
}
