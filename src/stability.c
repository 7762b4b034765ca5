/* Positive definiteness by a Cholesky attempt on the symmetric part (stability.h), in band
 * storage (band.h): the tangent of a chain of blocks is a narrow band. */
#include "voussoir/stability.h"

#include <stdlib.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/band.h"

struct vs_spd {
  int n;
  vs_band *b; /* the order and the band storage, from the first test's pattern */
};

vs_status vs_spd_create(int n, vs_spd **out, vs_error *err) {
  *out = NULL;
  vs_spd *s = calloc(1, sizeof *s);
  if (s == NULL) return vs_error_set(err, VS_ERR_NOMEM, "stability: out of memory");
  s->n = n;
  *out = s;
  return VS_OK;
}

void vs_spd_destroy(vs_spd **sp) {
  if (sp == NULL || *sp == NULL) return;
  vs_band_destroy(&(*sp)->b);
  free(*sp);
  *sp = NULL;
}

int vs_spd_test(vs_spd *s, SUNMatrix K) {
  if (s->b == NULL) {
    vs_error err;
    vs_error_clear(&err);
    if (vs_band_create(s->n, SUNSparseMatrix_IndexPointers(K), SUNSparseMatrix_IndexValues(K),
                       &s->b, &err) != VS_OK)
      return -1;
  }
  return vs_band_spd(s->b, SUNSparseMatrix_Data(K));
}
