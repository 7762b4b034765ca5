/* Private: the XDMF sidecar of a record, from the HDF5 file that holds it (xdmf.c). */
#ifndef VS_XDMF_H
#define VS_XDMF_H

#include <hdf5.h>

#include "voussoir/status.h"

/* Write the sidecar xmf_path (through "<xmf_path>.tmp", renamed) of the record h5_path opened
 * as file, listing at most max_grids rows (see vs_output_opts). Errors: VS_ERR_INVALID (not a
 * voussoir record, or xmf_path is not a regular file), VS_ERR_IO, VS_ERR_NOMEM. */
vs_status vs_xdmf_write(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                        vs_error *err);

#endif
