/* A sweep's summary table as DIR/summary.h5 (in the record plugin: HDF5). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "h5util.h"
#include "outpath.h"
#include "sweep_rows.h"

/* The summary as an HDF5 compound table DIR/summary.h5 (/summary), units in an attribute; rows
 * in run order. A study with a mortared case (a row's mortared) has the first crack's columns
 * besides (a dry study's table is as it was). */
vs_status vs_sweep_summary_h5(const char *dir, const vs_sweep_axis *ax, int nax,
                              const vs_sweep_row *rows, int n, vs_error *err) {
  char path[1100];
  snprintf(path, sizeof path, "%s/summary.h5", dir);
  typedef struct {
    int run;
    double axis[VS_SWEEP_MAX_AXES];
    const char *status, *mode, *hinges, *error;
    double first_limit, delta_u, dz, dx, wall;
    int snaps;
    double travel[4];
    double load_factor;
  } mem;
  typedef struct { /* a mortared study's row */
    mem m;
    double crack_mm;
    int crack_joint;
    const char *crack_side;
  } mem_mortar;
  int mortar = 0;
  for (int i = 0; i < n; i++) mortar |= rows[i].mortared;
  const size_t stride = mortar ? sizeof(mem_mortar) : sizeof(mem);
  unsigned char *buf = calloc((size_t)(n > 0 ? n : 1), stride);
  if (buf == NULL) return vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory", path);
  for (int i = 0; i < n; i++) {
    mem *m = (mem *)(buf + (size_t)i * stride);
    *m = (mem){rows[i].run,         {0},
                 rows[i].status,      rows[i].mode,
                 rows[i].hinges,      rows[i].error,
                 rows[i].first_limit_mm, rows[i].delta_u_mm,
                 rows[i].dz_pct,      rows[i].dx_pct,
                 rows[i].wall_s,      rows[i].snaps,
                 {0}, rows[i].load_factor};
    memcpy(m->axis, rows[i].axis, sizeof m->axis);
    const double tr[4] = {rows[i].left_dx_mm, rows[i].left_dz_mm, rows[i].right_dx_mm,
                          rows[i].right_dz_mm};
    memcpy(m->travel, tr, sizeof tr);
    if (mortar) {
      mem_mortar *mm = (mem_mortar *)m;
      mm->crack_mm = rows[i].first_crack_mm;
      mm->crack_joint = rows[i].first_crack_joint;
      mm->crack_side = rows[i].first_crack_side;
    }
  }
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t str = H5Tcopy(H5T_C_S1);
  H5Tset_size(str, H5T_VARIABLE);
  H5Tset_cset(str, H5T_CSET_UTF8);
  hid_t t = H5Tcreate(H5T_COMPOUND, stride);
  H5Tinsert(t, "run", HOFFSET(mem, run), H5T_NATIVE_INT);
  char units[1024] = "run: -";
  size_t used = strlen(units);
  for (int x = 0; x < nax; x++) {
    H5Tinsert(t, ax[x].key, HOFFSET(mem, axis) + (size_t)x * sizeof(double), H5T_NATIVE_DOUBLE);
    used += (size_t)snprintf(units + used, sizeof units - used, "; %s: case units", ax[x].key);
  }
  H5Tinsert(t, "status", HOFFSET(mem, status), str);
  H5Tinsert(t, "first_limit_mm", HOFFSET(mem, first_limit), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "delta_u_mm", HOFFSET(mem, delta_u), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dz_over_L_pct", HOFFSET(mem, dz), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dx_over_L_pct", HOFFSET(mem, dx), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "hinges_at_collapse", HOFFSET(mem, hinges), str);
  H5Tinsert(t, "mode", HOFFSET(mem, mode), str);
  H5Tinsert(t, "snaps", HOFFSET(mem, snaps), H5T_NATIVE_INT);
  H5Tinsert(t, "wall_s", HOFFSET(mem, wall), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "error", HOFFSET(mem, error), str);
  static const char *const travel[4] = {"left_dx_mm", "left_dz_mm", "right_dx_mm", "right_dz_mm"};
  for (int k = 0; k < 4; k++)
    H5Tinsert(t, travel[k], HOFFSET(mem, travel) + (size_t)k * sizeof(double), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "load_factor", HOFFSET(mem, load_factor), H5T_NATIVE_DOUBLE);
  snprintf(units + used, sizeof units - used,
           "; status, hinges_at_collapse, mode, error: text; first_limit_mm, delta_u_mm: mm; "
           "dz_over_L_pct, dx_over_L_pct: %% of the intrados span; snaps: count; wall_s: s; "
           "left_dx_mm, left_dz_mm, right_dx_mm, right_dz_mm: mm, each support's own travel at "
           "the collapse, outward and downward positive; load_factor: - (analysis.type = load)");
  if (mortar) {
    H5Tinsert(t, "first_crack_mm", HOFFSET(mem_mortar, crack_mm), H5T_NATIVE_DOUBLE);
    H5Tinsert(t, "first_crack_joint", HOFFSET(mem_mortar, crack_joint), H5T_NATIVE_INT);
    H5Tinsert(t, "first_crack_side", HOFFSET(mem_mortar, crack_side), str);
    used = strlen(units);
    snprintf(units + used, sizeof units - used,
             "; first_crack_mm: mm, first_crack_joint: 1-based (0 none), first_crack_side: I or "
             "E, the edge that cracks (mortar: the JSON's first_crack; NaN, 0, empty when none)");
  }
  /* written as summary.h5.part and renamed into place (only over a regular file): never
   * half-written */
  char part[1200];
  snprintf(part, sizeof part, "%s.part", path);
  hid_t f = vs_h5_create(part, H5P_DEFAULT, err);
  hsize_t dims[1] = {(hsize_t)n};
  hid_t sp = H5Screate_simple(1, dims, NULL);
  hid_t d = f >= 0 ? H5Dcreate2(f, "summary", t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT) : -1;
  int ok = d >= 0 && H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0;
  if (ok) {
    hid_t as = H5Screate(H5S_SCALAR), a = H5Acreate2(d, "unit", str, as, H5P_DEFAULT, H5P_DEFAULT);
    const char *u = units;
    ok = a >= 0 && H5Awrite(a, str, &u) >= 0;
    if (a >= 0) H5Aclose(a);
    H5Sclose(as);
  }
  if (d >= 0) H5Dclose(d);
  H5Sclose(sp);
  if (f >= 0 && H5Fclose(f) < 0) ok = 0;
  const vs_status st = f < 0 ? err->status
                       : !ok ? vs_h5_fail(err, part, "cannot write")
                             : vs_outpath_publish(part, path, err);
  if (st != VS_OK) vs_outpath_discard(part);
  H5Tclose(t);
  H5Tclose(str);
  free(buf);
  return st;
}
