/* Lists of numbers for sweeps: comma-separated numbers and inclusive "first:last:step" ranges. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parse.h"
#include "list.h"

/* The item [s, end) as a number, in the forms of parse.h. */
static int parse_number(const char *s, const char *end, double *out) {
  size_t n = (size_t)(end - s);
  char *item = malloc(n + 1);
  if (item == NULL) return -1;
  memcpy(item, s, n);
  item[n] = '\0';
  int rc = vs_parse_double(item, out) == VS_NUM_OK ? 0 : -1;
  free(item);
  return rc;
}

static int push(double **v, int *n, int *cap, double x) {
  if (*n >= VS_LIST_MAX_VALUES) return -1;
  if (*n == *cap) {
    int c = *cap ? 2 * *cap : 16;
    double *nv = realloc(*v, (size_t)c * sizeof *nv);
    if (nv == NULL) return -1;
    *v = nv;
    *cap = c;
  }
  (*v)[(*n)++] = x;
  return 0;
}

vs_status vs_parse_list(const char *what, const char *text, double **values, int *n,
                        vs_error *err) {
  *values = NULL;
  *n = 0;
  int cap = 0;
  const char *p = text;
  if (text == NULL || *text == '\0')
    return vs_error_set(err, VS_ERR_USAGE, "%s: empty list (expected e.g. 0:90:5 or 0,45,90)", what);
  for (;;) {
    const char *comma = strchr(p, ',');
    const char *end = comma ? comma : p + strlen(p);
    const char *c1 = memchr(p, ':', (size_t)(end - p));
    double a, b, step;
    int bad = 0;
    if (c1 == NULL) {
      bad = parse_number(p, end, &a) != 0 || push(values, n, &cap, a) != 0;
    } else {
      const char *c2 = memchr(c1 + 1, ':', (size_t)(end - c1 - 1));
      bad = c2 == NULL || parse_number(p, c1, &a) != 0 || parse_number(c1 + 1, c2, &b) != 0 ||
            parse_number(c2 + 1, end, &step) != 0 || !(step > 0.0) || b < a ||
            (b - a) / step > VS_LIST_MAX_VALUES;
      for (int k = 0; !bad && a + k * step <= b + 1e-9 * step; k++)
        bad = push(values, n, &cap, a + k * step) != 0;
    }
    if (bad) {
      free(*values);
      *values = NULL;
      *n = 0;
      return vs_error_set(err, VS_ERR_USAGE,
                          "%s: '%.*s%s' is not a number or a range first:last:step (step > 0, "
                          "last >= first; at most %d values in a list)",
                          what, (int)(end - p > 64 ? 64 : end - p), p, end - p > 64 ? "..." : "",
                          VS_LIST_MAX_VALUES);
    }
    if (comma == NULL) break;
    p = comma + 1;
  }
  return VS_OK;
}

vs_status vs_logspace(double a, double b, int n, double **values, vs_error *err) {
  *values = NULL;
  if (!(a > 0.0) || !(b > 0.0) || n < 2)
    return vs_error_set(err, VS_ERR_USAGE, "logspace %g to %g in %d (allowed: > 0, n >= 2)", a, b, n);
  *values = malloc((size_t)n * sizeof **values);
  if (*values == NULL) return vs_error_set(err, VS_ERR_NOMEM, "out of memory");
  for (int i = 0; i < n; i++) (*values)[i] = a * pow(b / a, (double)i / (n - 1));
  return VS_OK;
}
