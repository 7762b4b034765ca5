/* The one number parser (parse.h): the documented forms are accepted with their exact values,
 * everything else is refused with the documented reason, and the option helpers apply their
 * ranges. The values are checked against the decimal literals themselves, not program output. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parse.h"

static void ok_double(const char *s, double want) {
  double v = NAN;
  vs_num_status st = vs_parse_double(s, &v);
  if (st != VS_NUM_OK) fail_msg("\"%s\" refused: %s", s, vs_num_reason(st));
  if (memcmp(&v, &want, sizeof v) != 0) fail_msg("\"%s\" = %.17g, expected %.17g", s, v, want);
}

static void bad_double(const char *s, vs_num_status want) {
  double v = 42.0;
  vs_num_status st = vs_parse_double(s, &v);
  if (st != want) fail_msg("\"%s\": %s, expected %s", s, vs_num_reason(st), vs_num_reason(want));
  assert_true(v == 42.0); /* untouched */
}

static void test_real_forms(void **state) {
  (void)state;
  ok_double("300", 300.0);
  ok_double("-45", -45.0);
  ok_double("+3", 3.0);
  ok_double("0.5", 0.5);
  ok_double(".5", 0.5);
  ok_double("5.", 5.0);
  ok_double("1e-3", 1e-3);
  ok_double("2.5E+4", 2.5e4);
  ok_double("-0", -0.0);
  ok_double("1.7976931348623157e308", DBL_MAX);
  ok_double("2.2250738585072014e-308", DBL_MIN);
  /* 600 digits: no buffer cuts it */
  char long_num[700] = "0.";
  memset(long_num + 2, '0', 600);
  strcpy(long_num + 602, "1e600");
  ok_double(long_num, 1.0 / 10.0);
}

static void test_real_refused(void **state) {
  (void)state;
  bad_double("", VS_NUM_EMPTY);
  bad_double("abc", VS_NUM_NOT_NUMBER);
  bad_double(".", VS_NUM_NOT_NUMBER);
  bad_double("-", VS_NUM_NOT_NUMBER);
  bad_double("e5", VS_NUM_NOT_NUMBER);
  bad_double(" 3", VS_NUM_NOT_NUMBER);
  bad_double("3 ", VS_NUM_TRAILING);
  bad_double("3mm", VS_NUM_TRAILING);
  bad_double("16x", VS_NUM_TRAILING);
  bad_double("1e", VS_NUM_TRAILING);
  bad_double("1e+", VS_NUM_TRAILING);
  bad_double("1,5", VS_NUM_TRAILING);
  bad_double("1_000", VS_NUM_TRAILING);
  bad_double("0x10", VS_NUM_HEX);
  bad_double("-0X1p3", VS_NUM_HEX);
  bad_double("nan", VS_NUM_NOT_FINITE);
  bad_double("-Infinity", VS_NUM_NOT_FINITE);
  bad_double("INF", VS_NUM_NOT_FINITE);
  bad_double("1e999", VS_NUM_OUT_OF_RANGE);
  bad_double("-1e309", VS_NUM_OUT_OF_RANGE);
  bad_double("1e-400", VS_NUM_OUT_OF_RANGE); /* would silently become 0 */
  char long_junk[700];
  memset(long_junk, '1', 600);
  strcpy(long_junk + 600, "x");
  bad_double(long_junk, VS_NUM_TRAILING); /* junk after 600 characters is still seen */
}

static void test_integers(void **state) {
  (void)state;
  long v = 0;
  assert_int_equal(vs_parse_long("55", &v), VS_NUM_OK);
  assert_true(v == 55);
  assert_int_equal(vs_parse_long("-7", &v), VS_NUM_OK);
  assert_true(v == -7);
  assert_int_equal(vs_parse_long("+0", &v), VS_NUM_OK);
  assert_true(v == 0);
  v = 9;
  assert_int_equal(vs_parse_long("5.5", &v), VS_NUM_NOT_INTEGER);
  assert_int_equal(vs_parse_long("5e1", &v), VS_NUM_NOT_INTEGER);
  assert_int_equal(vs_parse_long("55.0", &v), VS_NUM_NOT_INTEGER);
  assert_int_equal(vs_parse_long("2x", &v), VS_NUM_TRAILING);
  assert_int_equal(vs_parse_long("5.5x", &v), VS_NUM_TRAILING);
  assert_int_equal(vs_parse_long("0x10", &v), VS_NUM_HEX);
  assert_int_equal(vs_parse_long("nan", &v), VS_NUM_NOT_FINITE);
  assert_int_equal(vs_parse_long("", &v), VS_NUM_EMPTY);
  assert_int_equal(vs_parse_long("many", &v), VS_NUM_NOT_NUMBER);
  assert_int_equal(vs_parse_long("99999999999999999999", &v), VS_NUM_OUT_OF_RANGE);
  assert_true(v == 9);
}

static void test_option_helpers(void **state) {
  (void)state;
  vs_error err;
  int j = 0;
  assert_int_equal(vs_parse_option_int("-j", "4", 1, 1024, &j, &err), VS_OK);
  assert_int_equal(j, 4);
  assert_int_equal(vs_parse_option_int("-j", "2x", 1, 1024, &j, &err), VS_ERR_USAGE);
  assert_string_equal(err.msg,
                      "-j 2x: unexpected characters after the number (allowed: integer in [1, 1024])");
  assert_int_equal(vs_parse_option_int("-j", "0", 1, 1024, &j, &err), VS_ERR_USAGE);
  assert_non_null(strstr(err.msg, "out of range"));
  assert_int_equal(vs_parse_option_int("-j", "4294967298", 1, 1024, &j, &err), VS_ERR_USAGE);
  assert_int_equal(j, 4);
  double x = 0.0;
  assert_int_equal(vs_parse_option_double("--tol-pct", "0.01", 0.0, 100.0, &x, &err), VS_OK);
  assert_true(x == 0.01);
  assert_int_equal(vs_parse_option_double("--target-dz-pct", "16x", 0.0, 100.0, &x, &err),
                   VS_ERR_USAGE);
  assert_non_null(strstr(err.msg, "--target-dz-pct 16x: unexpected characters"));
  assert_int_equal(vs_parse_option_double("--kn-min", "0x1p3", 0.0, 100.0, &x, &err), VS_ERR_USAGE);
  assert_non_null(strstr(err.msg, "hexadecimal"));
  assert_true(x == 0.01);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_real_forms),
      cmocka_unit_test(test_real_refused),
      cmocka_unit_test(test_integers),
      cmocka_unit_test(test_option_helpers),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
