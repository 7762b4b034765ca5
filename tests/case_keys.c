/* The case's key table as text, for test_man.sh: one line per key, tab-separated:
 *   section  key  unit  default  allowed
 * from the table that defines the keys (vs_case_key_count, vs_case_key, vs_case_defaults; the
 * text keys after them, vs_case_text_key), the
 * allowed range as the program states it when a value is refused (vs_case_set), without the unit,
 * which has its own column. usage: case_keys */
#include "voussoir/case.h"
#include "voussoir/status.h"

#include <stdio.h>
#include <string.h>

/* The "(allowed: ...)" part of the refusal of a value no key accepts (a number beyond every
 * range, which is no integer nor any choice's name; for a file name, one too long). */
static int allowed_text(const char *section, const char *key, const char *unit, char *out,
                        size_t size) {
  vs_case c;
  vs_error err;
  char set[2200];
  vs_case_defaults(&c);
  vs_error_clear(&err);
  snprintf(set, sizeof set, "%s.%s=1e300", section, key);
  if (vs_case_set(&c, set, &err) == VS_OK) {
    int n = snprintf(set, sizeof set, "%s.%s=", section, key);
    for (; n < (int)sizeof set - 1; n++) set[n] = 'a';
    set[n] = '\0';
    if (vs_case_set(&c, set, &err) == VS_OK) return -1;
  }
  const char *a = strstr(err.msg, "(allowed: ");
  if (a == NULL) return -1;
  a += strlen("(allowed: ");
  size_t n = strlen(a);
  if (n == 0 || a[n - 1] != ')') return -1;
  n--;
  size_t u = strlen(unit);
  if (u > 0 && n > u + 1 && a[n - u - 1] == ' ' && strncmp(a + n - u, unit, u) == 0) n -= u + 1;
  snprintf(out, size, "%.*s", (int)n, a);
  return 0;
}

int main(void) {
  vs_case c;
  vs_case_defaults(&c);
  for (int i = 0; i < vs_case_key_count(); i++) {
    const char *section = NULL, *key = NULL, *unit = NULL, *name = NULL;
    int is_int = 0;
    double v = 0.0;
    char allowed[512];
    if (vs_case_key(&c, i, &section, &key, &unit, &is_int, &v) != 0 ||
        allowed_text(section, key, unit, allowed, sizeof allowed) != 0) {
      fprintf(stderr, "case_keys: key %d: no range in the refusal of a value\n", i);
      return 1;
    }
    char text[256];
    name = is_int ? vs_case_key_name_of(i, (int)v) : NULL;
    if (vs_case_key_text(&c, i, text, sizeof text) == 1)
      printf("%s\t%s\t%s\t%s\t%s\n", section, key, unit, text[0] ? text : "(none)", allowed);
    else if (name != NULL)
      printf("%s\t%s\t%s\t%s\t%s\n", section, key, unit, name, allowed);
    else
      printf("%s\t%s\t%s\t%.15g\t%s\n", section, key, unit, v, allowed);
  }
  for (int i = 0; i < vs_case_text_key_count(); i++) { /* the paths: text, "none" unset */
    const char *section = NULL, *key = NULL;
    char text[64], allowed[512];
    if (vs_case_text_key(&c, i, &section, &key, text, sizeof text) != 0 ||
        allowed_text(section, key, "", allowed, sizeof allowed) != 0) {
      fprintf(stderr, "case_keys: text key %d: no range in the refusal of a value\n", i);
      return 1;
    }
    printf("%s\t%s\t\t%s\t%s\n", section, key, text[0] != '\0' ? text : "none", allowed);
  }
  return 0;
}
