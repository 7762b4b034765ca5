/* A record's root attribute "status" ("completed", "failed: ...", "stopped ...") read back with
 * HDF5, for the tests that check how a run's record was closed. */
#ifndef VS_TEST_RECORD_STATUS_H
#define VS_TEST_RECORD_STATUS_H

#include <hdf5.h>
#include <stdio.h>

/* The status of the record at path into out (size bytes); a file HDF5 cannot open, or without
 * the attribute, fails the test. */
static inline void vs_test_record_status(const char *path, char *out, size_t size) {
  out[0] = '\0';
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) fail_msg("%s: HDF5 cannot open it", path);
  hid_t a = H5Aopen(f, "status", H5P_DEFAULT);
  if (a < 0) fail_msg("%s: no status", path);
  hid_t mt = H5Tcopy(H5T_C_S1);
  H5Tset_size(mt, H5T_VARIABLE);
  H5Tset_cset(mt, H5T_CSET_UTF8);
  char *s = NULL;
  assert_true(H5Aread(a, mt, &s) >= 0);
  snprintf(out, size, "%s", s);
  H5free_memory(s);
  H5Tclose(mt);
  H5Aclose(a);
  H5Fclose(f);
}

#endif
