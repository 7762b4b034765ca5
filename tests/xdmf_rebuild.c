/* Test helper (tests/test_paraview.sh): rebuild the XDMF sidecar of each record named on the
 * command line with vs_output_write_xdmf, as for a killed run's record or an earlier version's.
 * usage: xdmf_rebuild FILE.h5 ... */
#include <stdio.h>

#include "voussoir/output.h"

int main(int argc, char **argv) {
  vs_output_process_init();
  int rc = 0;
  for (int i = 1; i < argc && rc == 0; i++) {
    vs_error err;
    if (vs_output_write_xdmf(argv[i], 0, &err) != VS_OK) {
      fprintf(stderr, "xdmf_rebuild: %s\n", err.msg);
      rc = 1;
    }
  }
  vs_output_process_end(1);
  return rc;
}
