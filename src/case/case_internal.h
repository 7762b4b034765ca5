/* Private to the case (case.h): case.c (the key table, one assignment, --set, validation, SI
 * values) and case_read.c (the INI file reader) share the echo of a token and the table's
 * sections (the one assignment, vs_case_assign, is public: case.h). */
#ifndef VOUSSOIR_CASE_INTERNAL_H
#define VOUSSOIR_CASE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include "voussoir/case.h"

/* Echo user text into a message, shortened so the reason and the allowed range still fit. */
enum { VS_CASE_ECHO_MAX = 64 };
typedef struct {
  char s[VS_CASE_ECHO_MAX + 4];
} vs_case_echo;

/* s quoted (vs_quote: no control character or escape sequence gets through) in b: at most
 * VS_CASE_ECHO_MAX characters, or its first ones and "...". */
const char *vs_case_clip(const char *s, vs_case_echo *b);

/* Is section[0, len) a section of the table? section need not be NUL-terminated. */
bool vs_case_section_known(const char *section, size_t len);

/* The table's sections, ", "-separated, into buf (size bytes). */
void vs_case_list_sections(char *buf, size_t size);

/* The blanks of a case file's line (not the newline). */
static inline bool vs_case_is_blank(char ch) {
  return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\f' || ch == '\v';
}

#endif
