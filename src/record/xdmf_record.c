/* The sidecar of a record file already written (vs_output_write_xdmf, output.h): the record
 * opened for xdmf.c. */
#include <stdlib.h>

#include "h5util.h"
#include "voussoir/output.h"
#include "xdmf.h"
#include "xdmf_internal.h"

vs_status vs_output_write_xdmf(const char *h5_path, int max_grids, vs_error *err) {
  vs_output_opts def;
  vs_output_opts_default(&def);
  if (max_grids <= 0) max_grids = def.xdmf_max_grids;
  if (max_grids < 2)
    return vs_error_set(err, VS_ERR_INVALID, "output: xdmf max_grids = %d (allowed: >= 2)",
                        max_grids);
  char *xmf = vs_output_xdmf_path_for(h5_path);
  if (xmf == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  vs_h5_quiet q = vs_h5_quiet_begin();
  hid_t f = H5Fopen(h5_path, H5F_ACC_RDONLY, H5P_DEFAULT);
  vs_status st = f < 0 ? vs_h5_fail(err, h5_path, "cannot open") : VS_OK;
  if (st == VS_OK) st = vs_xdmf_write(f, h5_path, xmf, max_grids, err);
  vs_h5_close(f);
  H5Eclear2(H5E_DEFAULT);
  vs_h5_quiet_end(q);
  free(xmf);
  return st;
}
