/* libFuzzer target for the case parser and the option parsers (tests/fuzz/run.sh builds and runs
 * it). Besides crashes and sanitizer reports it checks meaning:
 *  - a case text that is accepted, written back as INI (every key, %.17g) and read again, gives
 *    exactly the same values, and every value is finite and passes its own range;
 *  - a number the strict parser accepts is made only of the characters of the documented decimal
 *    form, and reads back to itself when printed with %.17g;
 *  - --set, sweep lists and integer options either fail with a message or give finite values
 *    within their stated limits. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_NAME "fuzz_case"
#include "fuzz.h"

#include "voussoir/case.h"
#include "parse.h"
#include "list.h"


/* Every key of c as INI text (sections in table order); returns a malloc'd string. *fits: 0 when a
 * line is longer than the reader takes. */
static char *serialise(const vs_case *c, int *fits) {
  *fits = 1;
  size_t cap = 16384, used = 0;
  char *out = malloc(cap);
  CHECK(out != NULL);
  const char *last = "";
  for (int i = 0; i < vs_case_key_count(); i++) {
    const char *sec, *key, *unit;
    int is_int;
    double v;
    CHECK(vs_case_key(c, i, &sec, &key, &unit, &is_int, &v) == 0);
    if (strcmp(sec, last) != 0) used += (size_t)snprintf(out + used, cap - used, "[%s]\n", sec);
    last = sec;
    const char *name = is_int ? vs_case_key_name_of(i, (int)v) : NULL;
    char text[4096];
    if (vs_case_key_text(c, i, text, sizeof text) == 1) { /* a file name, a list */
      /* written key=value, no blanks: the line read held at least that (the reader's limit is
       * 199 characters a line); a list written with %.17g may be longer than it was read, and
       * past the limit the round trip does not apply (*fits = 0) */
      const int n = snprintf(out + used, cap - used, "%s=%s\n", key, text);
      if (n - 1 > 199) *fits = 0;
      used += (size_t)n;
    }
    else if (name != NULL) /* a named choice (support.left_kind, dynamic.damping_model, ...) */
      used += (size_t)snprintf(out + used, cap - used, "%s = %s\n", key, name);
    else if (is_int)
      used += (size_t)snprintf(out + used, cap - used, "%s = %d\n", key, (int)v);
    else
      used += (size_t)snprintf(out + used, cap - used, "%s = %.17g\n", key, v);
    CHECK(used < cap);
  }
  return out;
}

static void check_case(const uint8_t *data, size_t size) {
  vs_case c, again;
  vs_error err;
  vs_case_defaults(&c);
  if (vs_case_parse(&c, "fuzz.ini", (const char *)data, size, &err) != VS_OK) {
    CHECK(err.status != VS_OK && err.msg[0] != '\0');
    return;
  }
  int fits;
  char *text = serialise(&c, &fits);
  vs_case_defaults(&again);
  again.radius_mm = 1.0; /* so that a key the text omitted would show */
  /* a list written longer than it was read, past the reader's line: no round trip, the values'
   * own checks below still apply (against themselves) */
  if (!fits) again = c;
  else if (vs_case_parse(&again, "again.ini", text, strlen(text), &err) != VS_OK) {
    fprintf(FUZZ_REPORT, "fuzz_case: re-reading the accepted case failed: %s\n%s", err.msg,
            text);
    abort();
  }
  for (int i = 0; i < vs_case_key_count(); i++) {
    double a, b;
    char ta[4096], tb[4096];
    if (vs_case_key_text(&c, i, ta, sizeof ta) == 1) { /* a file name, a list: the same text */
      CHECK(vs_case_key_text(&again, i, tb, sizeof tb) == 1 && strcmp(ta, tb) == 0);
      continue;
    }
    CHECK(vs_case_key(&c, i, NULL, NULL, NULL, NULL, &a) == 0);
    CHECK(vs_case_key(&again, i, NULL, NULL, NULL, NULL, &b) == 0);
    CHECK(isfinite(a));
    CHECK(memcmp(&a, &b, sizeof a) == 0); /* bit for bit, -0 included */
  }
  free(text);
}

static void check_number(const char *s) {
  double v;
  if (vs_parse_double(s, &v) == VS_NUM_OK) {
    CHECK(isfinite(v));
    CHECK(s[0] != '\0' && strspn(s, "0123456789+-.eE") == strlen(s) && strpbrk(s, "0123456789"));
    char buf[64];
    snprintf(buf, sizeof buf, "%.17g", v);
    double w;
    CHECK(vs_parse_double(buf, &w) == VS_NUM_OK && w == v);
  }
  long l;
  if (vs_parse_long(s, &l) == VS_NUM_OK) {
    CHECK(strspn(s, "0123456789+-") == strlen(s));
    CHECK(vs_parse_double(s, &v) == VS_NUM_OK && v == (double)l);
  }
  int j;
  vs_error err;
  if (vs_parse_option_int("-j", s, 1, 1024, &j, &err) == VS_OK) CHECK(j >= 1 && j <= 1024);
  else CHECK(strncmp(err.msg, "-j ", 3) == 0);
}

static void check_options(const char *s) {
  vs_case c, before;
  vs_error err;
  vs_case_defaults(&c);
  before = c;
  if (vs_case_set(&c, s, &err) != VS_OK) CHECK(memcmp(&c, &before, sizeof c) == 0);
  for (int i = 0; i < vs_case_key_count(); i++) {
    double v;
    char t[8];
    CHECK(vs_case_key(&c, i, NULL, NULL, NULL, NULL, &v) == 0 &&
          (isfinite(v) || vs_case_key_text(&c, i, t, sizeof t) == 1));
  }
  double *values = NULL;
  int n = 0;
  if (vs_parse_list("--vary", s, &values, &n, &err) == VS_OK) {
    CHECK(n >= 1 && n <= VS_LIST_MAX_VALUES);
    for (int i = 0; i < n; i++) CHECK(isfinite(values[i]));
  } else {
    CHECK(values == NULL && n == 0);
  }
  free(values);
  check_number(s);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  fuzz_report_open();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  check_case(data, size);
  if (size > 4096) return 0; /* option values: a command line's worth */
  char *s = malloc(size + 1);
  CHECK(s != NULL);
  memcpy(s, data, size);
  s[size] = '\0';
  check_options(s);
  free(s);
  return 0;
}
