/* Untrusted text never reaches a terminal or a markup file as it is: vs_quote against a table of
 * inputs and random bytes (checked by a UTF-8 validator of this file's own); the program run
 * with escape sequences, bells, NUL and bytes that are not UTF-8 in a case file's section, key
 * and value, in its path, in options and operands: exit 2, and stderr holds no control byte but
 * the newlines; output names with control characters or the characters XDMF cannot refer to are
 * refused (exit 2, nothing written); a record named with XML's markup characters, "--" and
 * UTF-8 gets a sidecar that parses as XML (python3's xml.dom.minidom) and names the record's
 * file exactly; the JSON of a case whose path is not UTF-8 is valid JSON (python3's json). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VS_SCRATCH "quote"
#include "scratch.h"
#include "voussoir/status.h"
#include "quote.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static void write_file(const char *path, const char *text, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, n, f), n);
  assert_int_equal(fclose(f), 0);
}

/* ---------------------------------------------------------------------------------------------
 * What a terminal can be shown: no C0 control but the newline, no DEL, well-formed UTF-8 (this
 * file's own reading of RFC 3629: the shortest form, no surrogate, at most U+10FFFF) and no C1
 * control. 0 when s[0..n) is such text, else 1 + the offset of the first offending byte. */

static size_t first_unsafe(const unsigned char *s, size_t n) {
  for (size_t i = 0; i < n;) {
    const unsigned c = s[i];
    if (c < 0x80) {
      if ((c < 0x20 && c != '\n') || c == 0x7f) return i + 1;
      i++;
      continue;
    }
    const size_t len = c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc0 ? 2 : 0;
    if (len == 0 || c > 0xf4 || i + len > n) return i + 1;
    unsigned long cp = c & (0xffu >> (len + 1));
    for (size_t k = 1; k < len; k++) {
      if ((s[i + k] & 0xc0) != 0x80) return i + 1;
      cp = (cp << 6) | (s[i + k] & 0x3fu);
    }
    const unsigned long least[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < least[len] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff) ||
        (cp >= 0x80 && cp < 0xa0))
      return i + 1;
    i += len;
  }
  return 0;
}

/* s quoted for a failure message (the test's own output must not act on a terminal either). */
static const char *shown(const char *s) {
  static char buf[4096];
  return vs_quote(s, buf, sizeof buf);
}

/* g_dir/err.txt (and out.txt) hold nothing a terminal could act on. */
static void expect_safe_output(const char *what) {
  const char *names[2] = {"err.txt", "out.txt"};
  for (int i = 0; i < 2; i++) {
    size_t n = 0;
    const char *s = slurp(in_dir(names[i]), &n);
    const size_t at = first_unsafe((const unsigned char *)s, n);
    if (at != 0)
      fail_msg("%s: %s byte %zu is 0x%02x: %s", what, names[i], at, (unsigned char)s[at - 1],
               shown(s));
  }
}

static void expect_err_has(const char *needle, const char *what) {
  const char *s = slurp(in_dir("err.txt"), NULL);
  if (strstr(s, needle) == NULL) fail_msg("%s: stderr lacks \"%s\": %s", what, needle, shown(s));
}

/* ---------------------------------------------------------------------------------------------
 * vs_quote */

static void expect_quote(const char *in, const char *want) {
  char buf[256];
  vs_quote(in, buf, sizeof buf);
  if (strcmp(buf, want) != 0) fail_msg("vs_quote: got \"%s\", expected \"%s\"", buf, want);
}

static void test_quote_table(void **s) {
  (void)s;
  expect_quote("radius_mm = 3 mm/s (a-z) [x] \\ ~", "radius_mm = 3 mm/s (a-z) [x] \\ ~");
  expect_quote("a\x1b[2Jb", "a\\x1b[2Jb");
  expect_quote("\x1b]0;title\x07", "\\x1b]0;title\\x07");
  expect_quote("l1\nl2\tc\rd", "l1\\nl2\\tc\\rd");
  expect_quote("\x7f\x01\x1f", "\\x7f\\x01\\x1f");
  expect_quote("vo\xc3\xbbte \xe2\x82\xac \xf0\x9f\x98\x80",
               "vo\xc3\xbbte \xe2\x82\xac \xf0\x9f\x98\x80"); /* kept: printable UTF-8 */
  expect_quote("\xc2\x9b" "2J", "\\xc2\\x9b2J");       /* C1 CSI in UTF-8 */
  expect_quote("\x9b" "2J", "\\x9b2J");                /* C1 CSI of an 8-bit terminal */
  expect_quote("\xff\xfe", "\\xff\\xfe");              /* never UTF-8 */
  expect_quote("\xc0\xaf", "\\xc0\\xaf");              /* overlong '/' */
  expect_quote("\xed\xa0\x80", "\\xed\\xa0\\x80");     /* a surrogate */
  expect_quote("\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80"); /* beyond U+10FFFF */
  expect_quote("ab\xe2\x82", "ab\\xe2\\x82");          /* cut short */
  expect_quote("x\xe2\x80\xaey", "x\\xe2\\x80\\xaey");  /* U+202E: right-to-left override */
  expect_quote("x\xe2\x80\xa8y", "x\\xe2\\x80\\xa8y");  /* U+2028: line separator */
  expect_quote("x\xd8\x9cy", "x\\xd8\\x9cy");           /* U+061C: Arabic letter mark */
  expect_quote("", "");
  expect_quote(NULL, "");
  size_t bad = 99;
  assert_int_equal(vs_quote_clean("plain \xc3\xa9", &bad), 1);
  assert_int_equal(bad, strlen("plain \xc3\xa9"));
  assert_int_equal(vs_quote_clean("ab\x1b", &bad), 0);
  assert_int_equal(bad, 2);
  assert_int_equal(vs_quote_clean("ab\xc3", &bad), 0);
  assert_int_equal(bad, 2);
}

/* Too long: cut before a whole escape or character, "..." at the end, within the buffer. */
static void test_quote_cut(void **s) {
  (void)s;
  char buf[10];
  assert_string_equal(vs_quote("abcdefghijkl", buf, sizeof buf), "abcdef...");
  assert_string_equal(vs_quote("abcde\x1bxyz", buf, sizeof buf), "abcde...");
  assert_string_equal(vs_quote("abcde\xc3\xa9xyz", buf, sizeof buf), "abcde...");
  assert_string_equal(vs_quote("abcd\xc3\xa9xyzw", buf, sizeof buf), "abcd\xc3\xa9...");
  assert_string_equal(vs_quote("abcdefg\xe2\x82\xac", buf, sizeof buf), "abcdef...");
  assert_string_equal(vs_quote("abcdef\xe2\x82\xac", buf, sizeof buf), "abcdef\xe2\x82\xac");
  assert_string_equal(vs_quote("abcdefghi", buf, sizeof buf), "abcdefghi"); /* fits exactly */
  char tiny[2];
  assert_string_equal(vs_quote("abc", tiny, sizeof tiny), "a");
}

/* Random bytes: the quoted text is safe to show, fits, and quoting it again changes nothing. */
static void test_quote_random(void **s) {
  (void)s;
  unsigned long x = 12345;
  for (int trial = 0; trial < 20000; trial++) {
    unsigned char in[48];
    const int n = 1 + trial % 47;
    for (int i = 0; i < n; i++) {
      x = x * 6364136223846793005UL + 1442695040888963407UL;
      unsigned b = (unsigned)(x >> 56);
      if (trial % 3 == 0) b = 0x80 | (b & 0x3f); /* continuation bytes, often */
      if (trial % 5 == 0 && i % 3 == 0) b = 0xc2 + b % 0x33; /* lead bytes, often */
      in[i] = (unsigned char)(b == 0 ? 'z' : b);
    }
    in[n] = '\0';
    const size_t size = trial % 2 ? 256 : 3 + (size_t)(trial % 40);
    char q[256], qq[256];
    vs_quote((const char *)in, q, size);
    assert_true(strlen(q) < size);
    if (first_unsafe((const unsigned char *)q, strlen(q)) != 0)
      fail_msg("trial %d: quoted text not safe: %s", trial, q);
    assert_int_equal(vs_quote_clean(q, NULL), 1);
    vs_quote(q, qq, sizeof qq);
    assert_string_equal(q, qq);
  }
}

/* ---------------------------------------------------------------------------------------------
 * The program */

#define VS VS_BINARY

/* A case file's text with an escape sequence (and more) in a section name, a key, a value: the
 * message names the line and shows the token escaped. */
static void test_case_file_tokens(void **s) {
  (void)s;
#define TEXT(s) s, sizeof s - 1
  static const struct {
    const char *text;
    size_t n;
    const char *shown;
  } cases[] = {
      {TEXT("[arch]\nra\x1b[2Jdius_mm = 3\n"), "ra\\x1b[2Jdius_mm"},
      {TEXT("[ar\x1b]0;owned\x07ch]\nradius_mm = 3\n"), "[ar\\x1b]"},
      {TEXT("[arch]\nradius_mm = 3\x1b[2J\xff\x9b\n"), "3\\x1b[2J\\xff\\x9b"},
      {TEXT("[arch]\nscheme = \xe2\x80\xaerigid\n"), "\\xe2\\x80\\xaerigid"},
      {TEXT("[fall]\nscheme = r\x7fi\x01gid\n"), "r\\x7fi\\x01gid"},
      {TEXT("\x1b[31m = 3\n"), "\\x1b[31m"},
      {TEXT("[arch]\nradius_mm = 3\x00\x1b[2J\n"), "NUL"},
  };
#undef TEXT
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    write_file(in_dir("bad.ini"), cases[i].text, cases[i].n);
    char *argv[] = {VS, "run", "bad.ini", "-q", "--no-record", NULL};
    char what[32];
    snprintf(what, sizeof what, "case text %zu", i);
    const int rc = run_argv(argv);
    if (rc != 2) fail_msg("%s: exit status %d, expected 2", what, rc);
    expect_safe_output(what);
    expect_err_has(cases[i].shown, what);
  }
}

/* Paths, options and operands on the command line. */
static void test_command_line_words(void **s) {
  (void)s;
  write_file(in_dir("bad\x1b[2J\xff.ini"), "[arch]\nradius_mm = -1\n", 22);
  char *runs[][10] = {
      {VS, "run", "bad\x1b[2J\xff.ini", "-q", "--no-record", NULL},    /* named in the message */
      {VS, "run", "missing\x1b]2;t\x07.ini", "-q", NULL},                /* cannot open */
      {VS, "run", REFERENCE, "--set", "arch.radius_mm=3\x1b[2J", "-q", NULL},
      {VS, "run", REFERENCE, "--set", "ar\x1b[2Jch.radius_mm=3", "-q", NULL},
      {VS, "run", REFERENCE, "--snapshot-share", "\x1b[2J", "-q", NULL},
      {VS, "run", REFERENCE, "--\x1b[2J", "-q", NULL},                   /* unknown option */
      {VS, "run", REFERENCE, "other\x1b[2J.ini", "-q", NULL},            /* two cases */
      {VS, "r\x1b[2Jun", NULL},                                          /* unknown command */
      {VS, "sweep", REFERENCE, "--vary", "arch.radius_mm\x1b[2J=1,2", "-o", "sw", "-q", NULL},
      {VS, "sweep", REFERENCE, "--alpha", "0,\x1b[2J", "-o", "sw", "-q", NULL},
      {VS, "montecarlo", REFERENCE, "--samples", "2", "--shard", "1\x1b[2J/2", NULL},
      {VS, "merge", "nodir\x1b[2J", "-o", "m", NULL},
      {VS, "plot", "norecord\x1b[2J.h5", "-o", "p", NULL},
  };
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    char what[32];
    snprintf(what, sizeof what, "command line %zu", i);
    const int rc = run_argv(runs[i]);
    if (rc != 2) fail_msg("%s: exit status %d, expected 2", what, rc);
    expect_safe_output(what);
    expect_err_has("\\x1b", what);
  }
}

/* Output names with control characters: refused before anything is written. */
static void test_output_names_refused(void **s) {
  (void)s;
  char *runs[][10] = {
      {VS, "run", REFERENCE, "-q", "-o", "rec\x1b[2J.h5", NULL},
      {VS, "run", REFERENCE, "-q", "-o", "rec\a\n.h5", NULL},
      {VS, "run", REFERENCE, "-q", "-o", "rec\xff.h5", NULL},
      {VS, "run", REFERENCE, "-q", "--no-record", "--csv", "h\x1b[2J.csv", NULL},
      {VS, "run", REFERENCE, "-q", "-o", "a:b.h5", NULL},  /* XDMF: FILE:/DATASET */
      {VS, "run", REFERENCE, "-q", "-o", "a|b.h5", NULL},  /* XDMF: ...|SLAB */
      {VS, "run", REFERENCE, "-q", "-o", " lead.h5", NULL}, /* XDMF trims it */
      {VS, "sweep", REFERENCE, "--alpha", "0", "-q", "-o", "sw\x1b[2J", NULL},
      {VS, "montecarlo", REFERENCE, "--samples", "2", "-q", "-o", "mc\x1b[2J", NULL},
  };
  for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
    char before[4096], after[4096], what[32];
    snprintf(what, sizeof what, "output name %zu", i);
    listing(before, sizeof before);
    const int rc = run_argv(runs[i]);
    if (rc != 2) fail_msg("%s: exit status %d, expected 2", what, rc);
    expect_safe_output(what);
    listing(after, sizeof after);
    if (strcmp(before, after) != 0) fail_msg("%s: files written: %s", what, shown(after));
  }
}

/* A record named with XML's markup characters, "--" (which no XML comment may hold), a blank and
 * UTF-8: its sidecar is well-formed XML whose every HDF reference names the record's file. */
static void test_sidecar_of_odd_name(void **s) {
  (void)s;
  const char *name = "a&b<c>\"d'e--f vo\xc3\xbbte.h5";
  char *argv[] = {VS, "run", REFERENCE, "--first-limit", "-q", "-o", (char *)name, NULL};
  assert_int_equal(run_argv(argv), 0);
  expect_safe_output("odd record name");
  const char *check =
      "import os, sys, xml.dom.minidom\n"
      "xmf, name = sys.argv[1], sys.argv[2]\n"
      "doc = xml.dom.minidom.parse(xmf)\n"
      "refs = [i.firstChild.data.strip() for i in doc.getElementsByTagName('DataItem')\n"
      "        if i.getAttribute('Format') == 'HDF']\n"
      "assert refs, 'no HDF reference'\n"
      "for r in refs:\n"
      "    f = r.split('|')[0].split(':', 1)[0]\n"
      "    assert f == name, (f, name)\n"
      "assert os.path.isfile(os.path.join(os.path.dirname(xmf), name))\n"
      "print('xml ok', len(refs))\n";
  char *py[] = {"/usr/bin/env", "python3", "-c", (char *)check,
                (char *)in_dir("a&b<c>\"d'e--f vo\xc3\xbbte.xmf"), (char *)name, NULL};
  const int rc = run_argv(py);
  if (rc != 0 || strstr(slurp(in_dir("out.txt"), NULL), "xml ok") == NULL)
    fail_msg("sidecar: %s", shown(slurp(in_dir("err.txt"), NULL)));
}

/* The JSON of a run whose case path is not UTF-8 is still valid JSON. */
static void test_json_of_non_utf8_path(void **s) {
  (void)s;
  size_t n = 0;
  const char *text = slurp(REFERENCE, &n);
  write_file(in_dir("arch\xff\x1b.ini"), text, n);
  char *argv[] = {VS, "run", "arch\xff\x1b.ini", "--first-limit", "--json", "--no-record", "-q",
                  NULL};
  assert_int_equal(run_argv(argv), 0);
  expect_safe_output("JSON");
  char copy[512];
  snprintf(copy, sizeof copy, "%s", in_dir("run.json")); /* out.txt is the next run's */
  assert_int_equal(rename(in_dir("out.txt"), copy), 0);
  char *py[] = {"/usr/bin/env", "python3", "-c",
                "import json, sys\n"
                "d = json.loads(open(sys.argv[1], 'rb').read())\n"
                "assert d['case'] == 'arch\\ufffd\\u001b.ini', d['case']\n"
                "print('json ok')\n",
                copy, NULL};
  const int rc = run_argv(py);
  if (rc != 0 || strstr(slurp(in_dir("out.txt"), NULL), "json ok") == NULL)
    fail_msg("JSON: %s", shown(slurp(in_dir("err.txt"), NULL)));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quote_table),
      cmocka_unit_test(test_quote_cut),
      cmocka_unit_test(test_quote_random),
      cmocka_unit_test(test_case_file_tokens),
      cmocka_unit_test(test_command_line_words),
      cmocka_unit_test(test_output_names_refused),
      cmocka_unit_test(test_sidecar_of_odd_name),
      cmocka_unit_test(test_json_of_non_utf8_path),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
