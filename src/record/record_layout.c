/* What the record holds from its creation on and that does not change during the run: the
 * root attributes, /parameters (the case), /geometry (the reference configuration),
 * /imperfections; and the empty /summary, /observables and /events the run fills. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "record_internal.h"
#include "voussoir/units.h"
#include "voussoir/version.h"

/* Layout version, in the root attribute "layout". */
#define VS_OUTPUT_LAYOUT "voussoir-h5 2"

/* ------------------------------------------------------------------------------------------ */
/* Geometry: outlines of the voussoirs and the joint segments                                   */

/* Reference outline of block b in np points (vs_block_outline: each curved edge in arc_points
 * + 2 points, ends included; for an arch voussoir the intrados arc from phi0 to phi1, then the
 * extrados arc back, counter-clockwise), the last point repeated to fill np (a block without
 * an outline: its centroid). */
static void block_outline(const vs_geometry *g, int b, int arc_points, int np, double *pts) {
  int k = vs_block_outline(g, b, arc_points + 2, INFINITY, pts, np);
  if (k == 0) pts[0] = g->blocks[b].cx, pts[1] = g->blocks[b].cz, k = 1;
  for (; k < np; k++) pts[2 * k] = pts[2 * k - 2], pts[2 * k + 1] = pts[2 * k - 1];
}

vs_status vs_record_geometry_init(vs_output *o, const vs_geometry *g) {
  o->nb = g->n_blocks;
  o->nj = g->n_joints;
  o->np = 1; /* the most points an outline needs */
  for (int b = 0; b < o->nb; b++) {
    const int k = vs_block_outline(g, b, o->opts.arc_points + 2, INFINITY, NULL, 0);
    if (k > o->np) o->np = k;
  }
  o->bref = malloc((size_t)o->nb * (size_t)o->np * 2 * sizeof *o->bref);
  o->jref = malloc((size_t)o->nj * 4 * sizeof *o->jref);
  o->rot = malloc(2 * (size_t)(o->nb > 0 ? o->nb : 1) * sizeof *o->rot);
  if (o->bref == NULL || o->jref == NULL || o->rot == NULL) return VS_ERR_NOMEM;
  for (int b = 0; b < o->nb; b++)
    block_outline(g, b, o->opts.arc_points, o->np, o->bref + (size_t)b * (size_t)o->np * 2);
  for (int k = 0; k < o->nj; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double h = 0.5 * j->length;
    o->jref[4 * k] = j->px - h * sx;
    o->jref[4 * k + 1] = j->pz - h * sz;
    o->jref[4 * k + 2] = j->px + h * sx;
    o->jref[4 * k + 3] = j->pz + h * sz;
  }
  return VS_OK;
}

/* The per-block and per-joint columns of /geometry; buf holds 2 max(nb, nj) values. */
static herr_t geometry_columns(hid_t grp, const vs_geometry *g, size_t nb, size_t nj, double *buf) {
  herr_t rc = 0;
  hsize_t d2[2];
#define GEO_COLUMN(n_, expr, name, unit)                                                           \
  do {                                                                                             \
    for (size_t i = 0; i < (n_); i++) buf[i] = (expr);                                             \
    d2[0] = (hsize_t)(n_);                                                                         \
    if (rc >= 0)                                                                                   \
      rc = vs_h5_dset_write(grp, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, d2, buf, unit, NULL); \
  } while (0)
#define GEO_PAIR(n_, e0, e1, name, unit, cols)                                                     \
  do {                                                                                             \
    for (size_t i = 0; i < (n_); i++) buf[2 * i] = (e0), buf[2 * i + 1] = (e1);                    \
    d2[0] = (hsize_t)(n_), d2[1] = 2;                                                              \
    if (rc >= 0)                                                                                   \
      rc = vs_h5_dset_write(grp, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d2, buf, unit, cols); \
  } while (0)
  if (rc >= 0) {
    GEO_COLUMN(nb, g->blocks[i].mass, "block_mass", "kg");
    GEO_COLUMN(nb, g->blocks[i].inertia, "block_inertia", "kg m^2");
    GEO_COLUMN(nb, g->blocks[i].area, "block_area", "m^2");
    GEO_PAIR(nb, g->blocks[i].cx, g->blocks[i].cz, "block_centroid", "m,m", "x,z");
    GEO_PAIR(nb, g->blocks[i].phi0, g->blocks[i].phi1, "block_phi", "rad,rad", "phi0,phi1");
    GEO_PAIR(nj, g->joints[i].px, g->joints[i].pz, "joint_centre", "m,m", "x,z");
    GEO_PAIR(nj, g->joints[i].nx, g->joints[i].nz, "joint_normal", "1,1", "nx,nz");
    GEO_COLUMN(nj, g->joints[i].length, "joint_length", "m");
    GEO_COLUMN(nj, g->joints[i].depth, "joint_depth", "m");
  }
#undef GEO_COLUMN
#undef GEO_PAIR
  return rc;
}

/* The joints' bodies and the outlines' points and connectivity; conn holds max(nb np, 2 nj). */
static herr_t geometry_outlines(hid_t grp, const vs_output *o, const vs_geometry *g,
                                int32_t *conn) {
  const size_t nb = (size_t)o->nb, nj = (size_t)o->nj, np = (size_t)o->np;
  herr_t rc = 0;
  hsize_t d2[2];
  if (rc >= 0) {
    for (size_t i = 0; i < nj; i++) conn[2 * i] = g->joints[i].a, conn[2 * i + 1] = g->joints[i].b;
    d2[0] = nj, d2[1] = 2;
    rc = vs_h5_dset_write(grp, "joint_bodies", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn, NULL,
                          "a,b");
  }
  hsize_t d3[3] = {nb * np, 2, 0};
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "block_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d3, o->bref,
                          "m,m", "x,z");
  for (size_t i = 0; rc >= 0 && i < nb * np; i++) conn[i] = (int32_t)i;
  d2[0] = nb, d2[1] = np;
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "block_connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn,
                          NULL, NULL);
  d3[0] = 2 * nj;
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "joint_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d3, o->jref,
                          "m,m", "x,z");
  for (size_t i = 0; rc >= 0 && i < 2 * nj; i++) conn[i] = (int32_t)i;
  d2[0] = nj, d2[1] = 2;
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "joint_connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn,
                          NULL, "intrados,extrados");
  return rc;
}

/* The arch's scalars, the counts and the description. */
static herr_t geometry_scalars(hid_t grp, const vs_output *o, const vs_geometry *g) {
  herr_t rc = vs_h5_dset_scalar(grp, "radius", g->radius, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(grp, "thickness", g->thickness, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(grp, "embrace", g->embrace, "rad");
  if (rc >= 0) rc = vs_h5_dset_scalar(grp, "span", g->span, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(grp, "rise", g->rise, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(grp, "gravity", g->gravity, "m/s^2");
  if (rc >= 0) rc = vs_h5_attr_int(grp, "n_blocks", o->nb);
  if (rc >= 0) rc = vs_h5_attr_int(grp, "n_joints", o->nj);
  if (rc >= 0) rc = vs_h5_attr_int(grp, "points_per_block", o->np);
  if (rc >= 0)
    rc = vs_h5_attr_str(
        grp, "description",
        "reference configuration; x right, z up; the origin at the circle's centre (circular), "
        "at mid-span on the springing line (the other shapes), the file's own (a blocks file). "
        "Block i's outline is block_points[i*P:(i+1)*P] (P = points_per_block), "
        "counter-clockwise, its last point repeated to fill P, a curved edge as chords; a "
        "circular arch's voussoir: intrados arc from phi0 to phi1, then extrados arc back. "
        "Joint k (1-based in reports) is row k-1; "
        "joint_bodies: block index, -1 left support, -2 right support");
  return rc;
}

static herr_t write_geometry(const vs_output *o, const vs_geometry *g) {
  hid_t grp = vs_h5_group_create(o->file, "geometry");
  if (grp < 0) return -1;
  const size_t nb = (size_t)o->nb, nj = (size_t)o->nj, np = (size_t)o->np;
  double *buf = malloc((nb > nj ? nb : nj) * 2 * sizeof *buf);
  int32_t *conn = malloc((nb * np > nj * 2 ? nb * np : nj * 2) * sizeof *conn);
  herr_t rc = (buf != NULL && conn != NULL) ? 0 : -1;
  if (rc >= 0) rc = geometry_columns(grp, g, nb, nj, buf);
  if (rc >= 0) rc = geometry_outlines(grp, o, g, conn);
  if (rc >= 0) rc = geometry_scalars(grp, o, g);
  free(buf);
  free(conn);
  vs_h5_close(grp);
  return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Parameters: the case's values under the case's keys and units                               */

static herr_t write_parameters(hid_t file, const vs_case *c) {
  hid_t grp = vs_h5_group_create(file, "parameters");
  herr_t rc = grp >= 0
                  ? vs_h5_attr_str(grp, "description",
                                   "the case's values as attributes of /parameters/<section>, "
                                   "named after the case keys, in the case's units (mm, N/mm^3, "
                                   "deg, kg/m^3, s)")
                  : -1;
  hid_t sec = H5I_INVALID_HID;
  const char *open_name = "";
  for (int i = 0; rc >= 0 && i < vs_case_key_count(); i++) {
    const char *section = NULL, *key = NULL;
    int is_int = 0;
    double value = 0.0;
    vs_case_key(c, i, &section, &key, NULL, &is_int, &value);
    if (strcmp(open_name, section) != 0) {
      vs_h5_close(sec);
      sec = vs_h5_group_create(grp, section);
      open_name = section;
      if (sec < 0) rc = -1;
    }
    char text[VS_ARCH_PATH_MAX];
    if (rc >= 0 && vs_case_key_text(c, i, text, sizeof text) == 1)
      rc = vs_h5_attr_str(sec, key, text); /* a file name, a list */
    else if (rc >= 0)
      rc = is_int ? vs_h5_attr_int(sec, key, (int)value) : vs_h5_attr_double(sec, key, value);
  }
  vs_h5_close(sec);
  vs_h5_close(grp);
  return rc;
}

static herr_t write_root(vs_output *o, const char *case_text) {
  char now[32];
  vs_iso8601_utc(now, sizeof now);
  herr_t rc = vs_h5_attr_str(o->file, "program", "voussoir");
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "version", VS_VERSION);
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "layout", VS_OUTPUT_LAYOUT);
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "created", now);
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "case", case_text != NULL ? case_text : "");
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "status", "running");
  if (rc >= 0) rc = vs_h5_attr_str(o->file, "finished", "");
  if (rc >= 0)
    rc = vs_h5_attr_str(o->file, "units", "SI (m, N, kg, s, rad); see each dataset's unit");
  return rc;
}

/* /imperfections: the values drawn for this run ([imperfections]; nominal when none), SI. */
static herr_t write_imperfections(hid_t file, const vs_imperfections *p) {
  hid_t grp = vs_h5_group_create(file, "imperfections");
  if (grp < 0) return -1;
  const hsize_t nj = (hsize_t)p->n_joints, nb = (hsize_t)p->n_blocks;
  herr_t rc = vs_h5_attr_str(grp, "description",
                             "drawn by the counter-based generator keyed by (seed, sample); see "
                             "/parameters/imperfections");
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "kn_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj, p->kn_factor,
                          "1", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "face_gap", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj, p->face_gap,
                          "m", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "tensile_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj,
                          p->ft_factor, "1", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "gf_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj,
                          p->gf_factor, "1", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "voussoir_angle", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nb,
                          p->angle, "rad", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "voussoir_thickness", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nb,
                          p->thickness, "m", NULL);
  const hsize_t two = 2;
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "support_offset", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &two,
                          p->support, "m, m", "outward, downward");
  vs_h5_close(grp);
  return rc;
}

/* /xdmf/nan: max(n_blocks, n_joints) NaN, written once. The XDMF sidecar's grids carry every
 * field (ParaView's default reader keeps only the fields all grids have), NaN where a field is
 * not the grid's own: that padding refers to a slab of this dataset instead of repeating it. */
static herr_t write_xdmf_nan(const vs_output *o) {
  hid_t grp = vs_h5_group_create(o->file, "xdmf");
  if (grp < 0) return -1;
  const hsize_t n = (hsize_t)(o->nb > o->nj ? o->nb : o->nj);
  double *buf = malloc((size_t)n * sizeof *buf);
  herr_t rc = buf != NULL ? 0 : -1;
  for (hsize_t i = 0; rc >= 0 && i < n; i++) buf[i] = NAN;
  if (rc >= 0)
    rc = vs_h5_attr_str(grp, "description",
                        "for the XDMF sidecar: nan, max(n_blocks, n_joints) NaN; a grid's field "
                        "that is not its own (NaN, so that every grid carries every field) "
                        "refers to its first cells");
  if (rc >= 0)
    rc = vs_h5_dset_write(grp, "nan", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &n, buf, "1", NULL);
  free(buf);
  vs_h5_close(grp);
  return rc;
}

vs_status vs_record_layout_write(vs_output *o, const vs_run *run, const char *case_text) {
  if (write_root(o, case_text) < 0)
    return vs_h5_fail(&o->err, o->path, "cannot write root attributes");
  if (write_parameters(o->file, vs_run_case(run)) < 0)
    return vs_h5_fail(&o->err, o->path, "cannot write /parameters");
  if (write_geometry(o, vs_run_geometry(run)) < 0)
    return vs_h5_fail(&o->err, o->path, "cannot write /geometry");
  if (write_imperfections(o->file, vs_run_imperfections(run)) < 0)
    return vs_h5_fail(&o->err, o->path, "cannot write /imperfections");
  if (write_xdmf_nan(o) < 0) return vs_h5_fail(&o->err, o->path, "cannot write /xdmf/nan");
  /* /summary is filled by vs_output_finish: created now, so that finishing never touches the
   * root group's header */
  hid_t obs = vs_h5_group_create(o->file, "summary");
  vs_h5_close(obs);
  obs = obs >= 0 ? vs_h5_group_create(o->file, "observables") : H5I_INVALID_HID;
  herr_t rc = obs >= 0 ? 0 : -1;
  for (int i = 0; rc >= 0 && i < S_COUNT; i++) rc = vs_record_series_create(o, obs, i);
  vs_h5_close(obs);
  if (rc < 0) return vs_h5_fail(&o->err, o->path, "cannot create /observables");
  if (vs_record_events_create(o) < 0) return vs_h5_fail(&o->err, o->path, "cannot create /events");
  return vs_record_flush(o);
}
