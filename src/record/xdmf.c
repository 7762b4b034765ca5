/* The XDMF sidecar of a record (ParaView plays the motion from it), written from what the
 * record's HDF5 file holds: after a run, or for a record left by a killed run. Here its text;
 * the record is read in xdmf_record.c, the listed rows and outlines come from xdmf_rows.c. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "h5util.h"
#include "utf8.h"
#include "xdmf.h"
#include "xdmf_internal.h"
#include "quote.h"

/* Every cell field any grid carries. ParaView's default XDMF reader (Xdmf3ReaderS, what File >
 * Open picks) flattens a step's grids into pieces of one data set, and its geometry filter then
 * appends the pieces keeping only the fields that all of them carry: a field on the blocks alone
 * is dropped and colouring by it leaves the arch grey. So every grid carries every field, NaN
 * where the field is not its own (ParaView draws NaN in its NaN colour and leaves it out of
 * ranges; the NaN is the record's /xdmf/nan, written once, which the padding refers to);
 * Xdmf3ReaderT keeps the grids as named blocks and reads the same file. */
enum { F_THETA, F_UX, F_UZ, F_SPEED, F_N, F_T, F_M, F_GAPI, F_GAPE, F_HINGE, F_FX, F_FZ,
       F_CRACKI, F_CRACKE, F_COUNT };
static const char *const XDMF_FIELDS[] = {
    "theta_rad", "ux_m",  "uz_m",    "speed_m_s", "N_N",
    "T_N",       "M_N_m", "gap_i_m", "gap_e_m",   "hinge_0closed_1intrados_2extrados",
    "Fx_N",      "Fz_N",  "crack_i_m", "crack_e_m"};
_Static_assert(sizeof XDMF_FIELDS / sizeof XDMF_FIELDS[0] == F_COUNT, "a name for every field");
#define F_BIT(f) (1u << (f))
#define F_ALL ((1u << F_COUNT) - 1u)

/* The fields each grid carries itself; the rest it carries as NaN. */
static const unsigned GRID_OWN[] = {
    F_BIT(F_THETA) | F_BIT(F_UX) | F_BIT(F_UZ) | F_BIT(F_SPEED),
    F_BIT(F_N) | F_BIT(F_T) | F_BIT(F_M) | F_BIT(F_GAPI) | F_BIT(F_GAPE) | F_BIT(F_HINGE) |
        F_BIT(F_CRACKI) | F_BIT(F_CRACKE),
    F_BIT(F_FX) | F_BIT(F_FZ) | F_BIT(F_M),
    F_BIT(F_FX) | F_BIT(F_FZ) | F_BIT(F_M) | F_BIT(F_UX) | F_BIT(F_UZ),
    0u, /* the ground */
    F_BIT(F_FX) | F_BIT(F_FZ), /* the live load */
};
_Static_assert(sizeof GRID_OWN / sizeof GRID_OWN[0] == G_COUNT, "the fields of every grid");

/* What every row shares is written once, before the rows, as children of the Domain (which
 * ParaView's XDMF 3 library leaves aside unless they are grids) named by xml:id, and each row
 * includes it with XInclude: <xi:include xpointer="ID"/>, or xpointer(id('ID ...')) for several
 * elements at once (XPath's id() yields them in document order). The library resolves an
 * include to the one item it made of that element, so a shared item is parsed once and its
 * data read at most once a frame. Shared: the topologies ("tb" the blocks' polygons, "tj" the
 * joints' segments, "t1" the one segment of a support or the ground), the ground's points ("gg"),
 * and the NaN fields, per number of cells ("b<i>" n_blocks cells, "j<i>" n_joints, "s<i>" one; i
 * the field's index in XDMF_FIELDS). Only whole Attribute, Topology and Geometry elements are
 * shared: the library moves a DataItem's contents into the element that holds it, so a
 * DataItem included twice is empty the second time (and it does not implement XDMF 2's
 * Reference="XML" items at all). Measured on the reference run (414 states): 6.4 MB of XML
 * with every grid spelling its items out, 2.0 MB this way. */
enum { PAD_BLOCKS, PAD_JOINTS, PAD_ONE, PAD_LOADS, PAD_COUNT };
static const char PAD_PREFIX[] = {'b', 'j', 's', 'l'};
static const int GRID_PAD[] = {PAD_BLOCKS, PAD_JOINTS, PAD_ONE, PAD_ONE, PAD_ONE, PAD_LOADS};
static const char *const GRID_TOPOLOGY[] = {"tb", "tj", "t1", "t1", "t1", "tl"};
_Static_assert(sizeof PAD_PREFIX == PAD_COUNT, "a prefix for every padding");
_Static_assert(sizeof GRID_PAD / sizeof GRID_PAD[0] == G_COUNT &&
                   sizeof GRID_TOPOLOGY / sizeof GRID_TOPOLOGY[0] == G_COUNT,
               "a padding and a topology for every grid");

/* The record's file name as the sidecar's text: XML's five markup characters as entities (a
 * name checked by vs_xdmf_name_check holds nothing XML cannot). malloc'd, NULL when out of
 * memory. */
static char *xml_escape(const char *s) {
  char *out = malloc(6 * strlen(s) + 1), *o = out; /* "&quot;" is the longest */
  for (; out != NULL && *s != '\0'; s++) {
    const char *rep = *s == '&'    ? "&amp;"
                      : *s == '<'  ? "&lt;"
                      : *s == '>'  ? "&gt;"
                      : *s == '"'  ? "&quot;"
                      : *s == '\'' ? "&apos;"
                                   : NULL;
    if (rep != NULL) o += sprintf(o, "%s", rep);
    else *o++ = *s;
  }
  if (out != NULL) *o = '\0';
  return out;
}

vs_status vs_xdmf_name_check(const char *h5_path, vs_error *err) {
  const char *slash = strrchr(h5_path, '/'), *base = slash != NULL ? slash + 1 : h5_path;
  const char *why = NULL;
  if (!vs_quote_clean(base, NULL))
    why = "a control character or bytes that are not UTF-8 text, which XML cannot hold";
  else if (base[0] == ' ')
    why = "a leading blank, which XDMF trims from the reference";
  else if (strpbrk(base, ":|") != NULL)
    why = "':' or '|', where XDMF splits its reference FILE:/DATASET|SLAB";
  for (const unsigned char *p = (const unsigned char *)base; why == NULL && *p != '\0';) {
    unsigned long cp = 0;
    const int n = vs_utf8_char(p, &cp);
    if (cp == 0xfffe || cp == 0xffff) why = "U+FFFE or U+FFFF, which are not XML characters";
    p += n > 0 ? n : 1;
  }
  if (why == NULL) return VS_OK;
  return vs_error_set(err, VS_ERR_INVALID,
                      "%s: the XDMF sidecar could not name this file: its name holds %s (rename "
                      "the record)",
                      h5_path, why);
}

/* The sidecar repeats its few kinds of lines for every grid of every state (some 20 000 numbers
 * and names for 400 states): fprintf's parsing of its format, then stdio's locking and copying
 * of every small piece, were most of its cost, so the text is put together in x->buf and handed
 * to stdio in large blocks. */
static void out_flush(xdmf_ctx *x) {
  fwrite(x->buf, 1, x->used, x->f);
  x->used = 0;
}

static void out_mem(xdmf_ctx *x, const char *s, size_t n) {
  if (x->used + n > sizeof x->buf) {
    out_flush(x);
    if (n > sizeof x->buf) {
      fwrite(s, 1, n, x->f);
      return;
    }
  }
  memcpy(x->buf + x->used, s, n);
  x->used += n;
}

static void out_s(xdmf_ctx *x, const char *s) { out_mem(x, s, strlen(s)); }

static void out_c(xdmf_ctx *x, char c) { out_mem(x, &c, 1); }

/* v in decimal, as "%llu" prints it. */
static void out_u(xdmf_ctx *x, unsigned long long v) {
  char b[24];
  size_t i = sizeof b;
  do b[--i] = (char)('0' + (int)(v % 10)); while ((v /= 10) != 0);
  out_mem(x, b + i, sizeof b - i);
}

/* As printf, for the lines written once, or once a row. */
static void out_f(xdmf_ctx *x, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void out_f(xdmf_ctx *x, const char *fmt, ...) {
  char line[1024];
  va_list ap, again;
  va_start(ap, fmt);
  va_copy(again, ap);
  const int n = vsnprintf(line, sizeof line, fmt, ap);
  if (n >= 0 && (size_t)n < sizeof line) {
    out_mem(x, line, (size_t)n);
  } else if (n > 0) { /* the header, or a long file name */
    out_flush(x);
    vfprintf(x->f, fmt, again);
  }
  va_end(again);
  va_end(ap);
}

static void xdmf_dims(xdmf_ctx *x, int rank, const hsize_t *d) {
  for (int i = 0; i < rank; i++) {
    if (i) out_c(x, ' ');
    out_u(x, (unsigned long long)d[i]);
  }
}

/* The block [start, start + count) of dataset `which`, in XDMF 3's own hyperslab syntax:
 * "file:/path|start:stride:count:dataset dimensions". ParaView's default XDMF reader
 * (Xdmf3ReaderS/T) reads it; it crashes on an ItemType="HyperSlab" item used as a geometry (it
 * asks the array's type before reading the slab), and the legacy "XDMF Reader" reads only that
 * older form, so there is no syntax both accept. Doubles (prec 8) state their type; float32
 * (the outlines) is XDMF's default type, NumberType="Float" Precision="4", left unsaid. */
static void xdmf_block(xdmf_ctx *x, int which, const hsize_t *start, const hsize_t *count,
                       int prec) {
  const xdmf_ds *d = &x->ds[which];
  const hsize_t stride[3] = {1, 1, 1};
  out_s(x, "<DataItem Dimensions=\"");
  xdmf_dims(x, d->rank, count);
  out_s(x, prec == 8 ? "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
                     : "\" Format=\"HDF\">");
  out_s(x, x->h5name);
  out_c(x, ':');
  out_s(x, d->path);
  out_c(x, '|');
  xdmf_dims(x, d->rank, start);
  out_c(x, ':');
  xdmf_dims(x, d->rank, stride);
  out_c(x, ':');
  xdmf_dims(x, d->rank, count);
  out_c(x, ':');
  xdmf_dims(x, d->rank, d->dims);
  out_s(x, "</DataItem>");
}

/* Row r of dataset `which`, columns [col, col + ncol) of its last dimension (ncol 0: all). */
static void xdmf_slab(xdmf_ctx *x, int which, hsize_t r, hsize_t col, hsize_t ncol, int prec) {
  const xdmf_ds *d = &x->ds[which];
  hsize_t start[3] = {r, 0, 0}, count[3] = {1, d->dims[1], d->dims[2]};
  if (ncol > 0) start[d->rank - 1] = col, count[d->rank - 1] = ncol;
  xdmf_block(x, which, start, count, prec);
}

/* Cell field XDMF_FIELDS[field] of the open grid, a double; its name carries its unit (ParaView
 * shows names only). XDMF's default AttributeType, Scalar, is left unsaid. */
static void xdmf_attribute(xdmf_ctx *x, int field, int which, hsize_t r, hsize_t col,
                           hsize_t ncol) {
  out_s(x, "<Attribute Name=\"");
  out_s(x, XDMF_FIELDS[field]);
  out_s(x, "\" Center=\"Cell\">");
  xdmf_slab(x, which, r, col, ncol, 8);
  out_s(x, "</Attribute>\n");
}

/* Open grid `kind` (XDMF's default GridType, Uniform) with its shared topology. */
static void xdmf_grid_open(xdmf_ctx *x, const char *name, int kind) {
  out_s(x, "<Grid Name=\"");
  out_s(x, name);
  out_s(x, "\"><xi:include xpointer=\"");
  out_s(x, GRID_TOPOLOGY[kind]);
  out_s(x, "\"/>\n");
}

/* The NaN fields of grid `kind`: those it does not carry itself. A grid that is not the blocks
 * starts with them, theta_rad first: ParaView shows the first field of a grid on opening, and
 * the blocks' rotation is the one worth seeing first. */
static void xdmf_pads(xdmf_ctx *x, int kind) { out_s(x, x->pads[kind]); }

/* The n float32 values v inline, as "%.9g" prints them (enough to read back the same float). */
static void xdmf_inline_floats(xdmf_ctx *x, const float *v, size_t n) {
  char b[32];
  for (size_t i = 0; i < n; i++) {
    const int len = snprintf(b + 1, sizeof b - 1, "%.9g", (double)v[i]);
    b[0] = ' ';
    out_mem(x, i ? b : b + 1, (size_t)len + (i ? 1 : 0));
  }
}

/* The blocks' moved outlines at row r, the x->listed-th listed row (see BP_STATES). */
static void xdmf_outline(xdmf_ctx *x, hsize_t r) {
  const long g = x->bp_source == BP_STATES ? (long)r : x->geo[x->listed];
  if (g >= 0) {
    xdmf_slab(x, X_BPTS, (hsize_t)g, 0, 0, 4);
    return;
  }
  const hsize_t nb = x->ds[X_BCONN].dims[0], np = x->ds[X_BCONN].dims[1];
  const long i = -1 - g; /* its inline frame */
  if (x->inl_at < 0 || i < x->inl_at || i >= x->inl_at + XDMF_INLINE_BLOCK) {
    const long m = x->n_inl - i < XDMF_INLINE_BLOCK ? x->n_inl - i : XDMF_INLINE_BLOCK;
    if (vs_xdmf_outlines(x->pos, x->need + i, m, (int)nb, (int)np, x->ref, x->cen, x->inl) < 0)
      x->failed = 1;
    x->inl_at = i;
  }
  out_s(x, "<DataItem Dimensions=\"");
  out_u(x, (unsigned long long)(nb * np));
  out_s(x, " 2\" Format=\"XML\">");
  xdmf_inline_floats(x, x->inl + (size_t)(i - x->inl_at) * 2 * nb * np, 2 * nb * np);
  out_s(x, "</DataItem>");
}

/* The blocks at row r: one polygon each, moved. */
static void xdmf_blocks(xdmf_ctx *x, hsize_t r) {
  xdmf_grid_open(x, "blocks", G_BLOCKS);
  out_s(x, "<Geometry GeometryType=\"XY\">");
  xdmf_outline(x, r);
  out_s(x, "</Geometry>\n");
  xdmf_attribute(x, F_THETA, X_BPOS, r, 2, 1);
  xdmf_attribute(x, F_UX, X_BPOS, r, 0, 1);
  xdmf_attribute(x, F_UZ, X_BPOS, r, 1, 1);
  xdmf_attribute(x, F_SPEED, X_BSPEED, r, 0, 0);
  xdmf_pads(x, G_BLOCKS);
  out_s(x, "</Grid>\n");
}

/* The joints at row r: one segment each, intrados to extrados. */
static void xdmf_joints(xdmf_ctx *x, hsize_t r) {
  xdmf_grid_open(x, "joints", G_JOINTS);
  out_s(x, "<Geometry GeometryType=\"XY\">");
  xdmf_slab(x, X_JPTS, r, 0, 0, 4);
  out_s(x, "</Geometry>\n");
  xdmf_pads(x, G_JOINTS);
  xdmf_attribute(x, F_N, X_N, r, 0, 0);
  xdmf_attribute(x, F_T, X_T, r, 0, 0);
  xdmf_attribute(x, F_M, X_M, r, 0, 0);
  xdmf_attribute(x, F_GAPI, X_GAPI, r, 0, 0);
  xdmf_attribute(x, F_GAPE, X_GAPE, r, 0, 0);
  /* read as a double (HDF5 converts), the type the other grids' NaN has */
  xdmf_attribute(x, F_HINGE, X_HINGE, r, 0, 0);
  /* mortar: the lengths cracked through from each edge (0 for dry joints) */
  xdmf_attribute(x, F_CRACKI, X_CRACK, r, 0, 1);
  xdmf_attribute(x, F_CRACKE, X_CRACK, r, 1, 1);
  out_s(x, "</Grid>\n");
}

/* A support at row r: the face it carries (the springing's, joint 1 on the left, n+1 on the
 * right; with piers a pier's base), with the force it exerts on the arch and, for the moved
 * right support, its displacement. */
static void xdmf_support(xdmf_ctx *x, int right, hsize_t r) {
  const hsize_t start[3] = {r, 2 * x->sup_joint[right ? 1 : 0], 0}, count[3] = {1, 2, 2};
  const int kind = right ? G_RIGHT : G_LEFT;
  xdmf_grid_open(x, right ? "support_right" : "support_left", kind);
  out_s(x, "<Geometry GeometryType=\"XY\">");
  xdmf_block(x, X_JPTS, start, count, 4);
  out_s(x, "</Geometry>\n");
  xdmf_pads(x, kind);
  xdmf_attribute(x, F_FX, X_REACT, r, right ? 3 : 0, 1);
  xdmf_attribute(x, F_FZ, X_REACT, r, right ? 4 : 1, 1);
  xdmf_attribute(x, F_M, X_REACT, r, right ? 5 : 2, 1);
  if (right) {
    xdmf_attribute(x, F_UX, X_SUPPORT, r, 0, 1);
    xdmf_attribute(x, F_UZ, X_SUPPORT, r, 1, 1);
  }
  out_s(x, "</Grid>\n");
}

/* The ground (a fixed segment), when the fall landed on it: every part shared, every field
 * NaN. */
static void xdmf_ground(xdmf_ctx *x) {
  xdmf_grid_open(x, "ground", G_GROUND);
  out_s(x, "<xi:include xpointer=\"gg\"/>\n");
  xdmf_pads(x, G_GROUND);
  out_s(x, "</Grid>\n");
}

/* The load factor of row r: a load run's path's (its last n_curve rows), 0 before it. */
static double row_lambda(const xdmf_ctx *x, hsize_t r) {
  const long k = (long)r - (x->rows - x->n_curve);
  return x->n_curve > 0 && k >= 0 && k < x->n_curve ? x->curve_lambda[k] : 0.0;
}

/* The live load of row r (a load run's /summary/load/forces): one segment per force, an arrow's
 * shaft ending at its point moved with its block to the row (x->load_q), its length that of the
 * shared reference arrows (xdmf_load_shared); Fx_N Fz_N the forces at the row's load factor. */
static void xdmf_load(xdmf_ctx *x, hsize_t r) {
  const int n = x->n_loads;
  const double *v = x->loads;
  if (vs_xdmf_load_row(x, r) != 0) {
    x->failed = 1;
    return;
  }
  xdmf_grid_open(x, "load", G_LOAD);
  out_f(x, "<Geometry GeometryType=\"XY\"><DataItem "
           "Dimensions=\"%d 2\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">", 2 * n);
  for (int i = 0; i < n; i++) {
    const int b = (int)v[5 * i];
    const double *q = x->load_q + 3 * b, c = cos(q[2]), s = sin(q[2]);
    double p[2]; /* the point moves with its block; the shaft keeps the load's direction */
    vs_xdmf_move(x->load_cen[2 * b], x->load_cen[2 * b + 1], q[0], q[1], c, s, v[5 * i + 3],
                 v[5 * i + 4], p);
    out_f(x, "%s%.17g %.17g %.17g %.17g", i ? " " : "", p[0] - x->load_arrow * v[5 * i + 1],
          p[1] - x->load_arrow * v[5 * i + 2], p[0], p[1]);
  }
  out_s(x, "</DataItem></Geometry>\n");
  const double lam = row_lambda(x, r);
  for (int k = 0; k < 2; k++) {
    out_f(x, "<Attribute Name=\"%s\" Center=\"Cell\"><DataItem Dimensions=\"%d\" "
             "NumberType=\"Float\" Precision=\"8\" Format=\"XML\">",
          XDMF_FIELDS[k ? F_FZ : F_FX], n);
    for (int i = 0; i < n; i++) out_f(x, "%s%.17g", i ? " " : "", lam * v[5 * i + 1 + k]);
    out_s(x, "</DataItem></Attribute>\n");
  }
  xdmf_pads(x, G_LOAD);
  out_s(x, "</Grid>\n");
}

/* One time step: the row's objects as named grids of a spatial collection. */
static void xdmf_step(xdmf_ctx *x, hsize_t r, double t) {
  out_f(x,
        "<Grid Name=\"row %llu\" GridType=\"Collection\" CollectionType=\"Spatial\">"
        "<Time Value=\"%.17g\"/>\n",
        (unsigned long long)r, t);
  xdmf_blocks(x, r);
  xdmf_joints(x, r);
  xdmf_support(x, 0, r);
  xdmf_support(x, 1, r);
  if (x->ground) xdmf_ground(x);
  if (x->n_loads > 0) xdmf_load(x, r);
  out_s(x, "</Grid>\n");
}

/* The NaN fields every row's grids of `pad` cells include: the union of what they lack. */
static unsigned xdmf_pad_fields(const xdmf_ctx *x, int pad) {
  unsigned m = 0;
  for (int k = 0; k < G_COUNT; k++)
    if (GRID_PAD[k] == pad && (k != G_GROUND || x->ground) && (k != G_LOAD || x->n_loads > 0))
      m |= F_ALL & ~GRID_OWN[k];
  return m;
}

/* Field XDMF_FIELDS[i] as NaN on n_cells cells, named "<prefix><i>": the first n_cells values
 * of the record's /xdmf/nan, or inline for a record written before it had that dataset. */
static void xdmf_nan_field(xdmf_ctx *x, char prefix, int i, hsize_t n_cells) {
  out_f(x,
        "<Attribute xml:id=\"%c%d\" Name=\"%s\" Center=\"Cell\"><DataItem Dimensions=\"%llu\" "
        "NumberType=\"Float\" Precision=\"8\" ",
        prefix, i, XDMF_FIELDS[i], (unsigned long long)n_cells);
  if (n_cells <= x->nan_n) {
    out_f(x, "Format=\"HDF\">%s:" XDMF_NAN "|0:1:%llu:%llu", x->h5name, (unsigned long long)n_cells,
          (unsigned long long)x->nan_n);
  } else {
    out_s(x, "Format=\"XML\">");
    for (hsize_t c = 0; c < n_cells; c++) out_s(x, c ? " nan" : "nan");
  }
  out_s(x, "</DataItem></Attribute>\n");
}

/* The live load's shared parts: the topology tl (one segment per force), its points lg (an
 * arrow's shaft from len x -F / |F|max above the point to the point, len the first joint's
 * length, the arch's thickness), and its fields lfx, lfz (the forces at lambda = 1, N). */
static void xdmf_load_shared(xdmf_ctx *x) {
  const int n = x->n_loads;
  const double *v = x->loads;
  double big = 0.0;
  for (int i = 0; i < n; i++) big = fmax(big, hypot(v[5 * i + 1], v[5 * i + 2]));
  const double len = x->joint_len > 0.0 ? x->joint_len : 0.01;
  x->load_arrow = big > 0.0 ? len / big : 0.0; /* m per N: the rows' arrows too */
  out_f(x, "<Topology xml:id=\"tl\" TopologyType=\"Polyline\" NodesPerElement=\"2\" "
           "NumberOfElements=\"%d\"><DataItem Dimensions=\"%d 2\" NumberType=\"Int\" "
           "Precision=\"4\" Format=\"XML\">", n, n);
  for (int i = 0; i < 2 * n; i++) out_f(x, i ? " %d" : "%d", i);
  out_f(x, "</DataItem></Topology>\n<Geometry xml:id=\"lg\" GeometryType=\"XY\"><DataItem "
           "Dimensions=\"%d 2\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">", 2 * n);
  for (int i = 0; i < n; i++) {
    const double fx = v[5 * i + 1], fz = v[5 * i + 2], px = v[5 * i + 3], pz = v[5 * i + 4];
    const double s = big > 0.0 ? len / big : 0.0;
    out_f(x, "%s%.17g %.17g %.17g %.17g", i ? " " : "", px - s * fx, pz - s * fz, px, pz);
  }
  out_s(x, "</DataItem></Geometry>\n");
  for (int c = 0; c < 2; c++) {
    out_f(x, "<Attribute xml:id=\"%s\" Name=\"%s\" Center=\"Cell\"><DataItem Dimensions=\"%d\" "
             "NumberType=\"Float\" Precision=\"8\" Format=\"XML\">",
          c ? "lfz" : "lfx", XDMF_FIELDS[c ? F_FZ : F_FX], n);
    for (int i = 0; i < n; i++) out_f(x, "%s%.17g", i ? " " : "", v[5 * i + 1 + c]);
    out_s(x, "</DataItem></Attribute>\n");
  }
}

/* The items every row includes (see PAD_PREFIX), and each grid's include of its NaN fields. */
static void xdmf_shared(xdmf_ctx *x) {
  const xdmf_ds *bc = &x->ds[X_BCONN], *jc = &x->ds[X_JCONN];
  out_f(x,
        "<Topology xml:id=\"tb\" TopologyType=\"Polygon\" NodesPerElement=\"%llu\" "
        "NumberOfElements=\"%llu\"><DataItem Dimensions=\"%llu %llu\" NumberType=\"Int\" "
        "Precision=\"4\" Format=\"HDF\">%s:%s</DataItem></Topology>\n"
        "<Topology xml:id=\"tj\" TopologyType=\"Polyline\" NodesPerElement=\"2\" "
        "NumberOfElements=\"%llu\"><DataItem Dimensions=\"%llu 2\" NumberType=\"Int\" "
        "Precision=\"4\" Format=\"HDF\">%s:%s</DataItem></Topology>\n"
        "<Topology xml:id=\"t1\" TopologyType=\"Polyline\" NodesPerElement=\"2\" "
        "NumberOfElements=\"1\"><DataItem Dimensions=\"1 2\" NumberType=\"Int\" "
        "Precision=\"4\" Format=\"XML\">0 1</DataItem></Topology>\n",
        (unsigned long long)bc->dims[1], (unsigned long long)bc->dims[0],
        (unsigned long long)bc->dims[0], (unsigned long long)bc->dims[1], x->h5name, bc->path,
        (unsigned long long)jc->dims[0], (unsigned long long)jc->dims[0], x->h5name, jc->path);
  if (x->ground)
    out_f(x,
          "<Geometry xml:id=\"gg\" GeometryType=\"XY\"><DataItem Dimensions=\"2 2\" "
          "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/summary/ground/points"
          "</DataItem></Geometry>\n",
          x->h5name);
  if (x->n_loads > 0) xdmf_load_shared(x);
  const hsize_t cells[PAD_COUNT] = {bc->dims[0], jc->dims[0], 1, (hsize_t)x->n_loads};
  for (int p = 0; p < PAD_COUNT; p++) {
    const unsigned m = xdmf_pad_fields(x, p);
    for (int i = 0; i < F_COUNT; i++)
      if (m & F_BIT(i)) xdmf_nan_field(x, PAD_PREFIX[p], i, cells[p]);
  }
  for (int k = 0; k < G_COUNT; k++) {
    char *s = x->pads[k];
    const size_t size = sizeof x->pads[k];
    size_t n = (size_t)snprintf(s, size, "<xi:include xpointer=\"xpointer(id('");
    const char *sep = "";
    for (int i = 0; i < F_COUNT; i++)
      if (!(GRID_OWN[k] & F_BIT(i))) {
        n += (size_t)snprintf(s + n, size - n, "%s%c%d", sep, PAD_PREFIX[GRID_PAD[k]], i);
        sep = " ";
      }
    snprintf(s + n, size - n, "'))\"/>\n");
  }
}


/* The sidecar's opening: what it shows and how ParaView reads it. */
static void xdmf_header(xdmf_ctx *x, long rows, long stride) {
  /* the record's name stays out of the comment: a comment cannot hold "--", nor an entity */
  out_f(x,
        "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
        "<!-- voussoir record, %ld rows, every %ld-th shown (and the last), times strictly "
        "increasing (the loading time delta / rate, s; a load run's: the row's number, its "
        "load path's rows all at the held support displacement).\n"
        "     ParaView: either XDMF 3 reader colours by any field: every grid carries every "
        "field, NaN where it is not the grid's own (slabs of the record's /xdmf/nan; the default "
        "Xdmf3ReaderS keeps only the fields all grids carry); Xdmf3ReaderT also keeps the grids "
        "as named blocks.\n"
        "     blocks (polygons): theta_rad rotation, ux_m uz_m centroid displacement, speed_m_s;\n"
        "     joints (segments, intrados to extrados): N_N normal force (compression > 0), T_N "
        "shear force, M_N_m moment about the joint centre, gap_i_m gap_e_m edge openings, "
        "hinge code 0 closed, 1 intrados, 2 extrados;\n"
        "     support_left, support_right (the springing faces; with piers the piers' bases): "
        "Fx_N Fz_N force of the support on the arch (x right, z up), M_N_m its moment "
        "(counter-clockwise, about that face's centre), ux_m uz_m displacement of the moved "
        "support;\n"
        "     ground (a segment, when the fall landed on it): the plane the debris rests on;\n"
        "     load (a live load's forces, one segment each, ending on its point moved with its "
        "block to the row): Fx_N Fz_N at the row's load factor (0 on the support's path); "
        "shared: its topology tl, and at load factor 1 in the reference configuration lg, lfx, "
        "lfz.\n"
        "     What every row shares is defined once, below, and included by xml:id (XInclude): "
        "the topologies tb (blocks), tj (joints), t1 (one segment), the ground's points gg, and "
        "the NaN fields b<i>, j<i>, s<i> (n_blocks, n_joints, one cell; i: the field's place in "
        "the list theta_rad ux_m uz_m speed_m_s N_N T_N M_N_m gap_i_m gap_e_m "
        "hinge_0closed_1intrados_2extrados Fx_N Fz_N).\n"
        "     The HDF5 file is named relative to this file. -->\n"
        "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n<Domain>\n",
        rows, stride);
}

vs_status vs_xdmf_write(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                        vs_error *err) {
  char tmp[4096];
  const vs_status st = vs_xdmf_write_tmp(file, h5_path, xmf_path, max_grids, tmp, sizeof tmp, err);
  return st == VS_OK ? vs_xdmf_publish(tmp, xmf_path, err) : st;
}

vs_status vs_xdmf_write_tmp(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                            char *tmp, size_t size, vs_error *err) {
  xdmf_ctx x;
  x.geo = x.need = NULL;
  x.n_inl = 0;
  x.inl_at = -1;
  x.inl = NULL;
  x.pos = H5I_INVALID_HID;
  x.ref = x.cen = NULL;
  x.failed = 0;
  const long rows = vs_xdmf_shapes(file, &x);
  if (rows < 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: %s: not a voussoir record (datasets for "
                        "the XDMF missing, of inconsistent shapes or larger than the file "
                        "holds)",
                        h5_path);
  double *t = NULL;
  long *sel = NULL, n = 0;
  x.rows = rows;
  vs_xdmf_loads(file, &x); /* before the listing: a load run's rows are timed by their number */
  vs_status st = vs_xdmf_name_check(h5_path, err);
  if (st == VS_OK) st = vs_xdmf_listing(file, &x, rows, max_grids, h5_path, &t, &sel, &n, err);
  const char *base = strrchr(h5_path, '/');
  char *name = xml_escape(base != NULL ? base + 1 : h5_path);
  if (name == NULL && st == VS_OK) st = vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  x.h5name = name;
  x.ground = vs_xdmf_has_ground(file);
  x.joint_len = vs_xdmf_joint_length(file);
  vs_xdmf_support_joints(file, &x);
  x.nan_n = vs_xdmf_nan_count(file);
  if (st == VS_OK) st = vs_xdmf_open_tmp(xmf_path, tmp, size, &x.f, err);
  if (st == VS_OK) {
    x.used = 0;
    xdmf_header(&x, rows, vs_xdmf_stride(rows, max_grids));
    xdmf_shared(&x);
    out_s(&x, "<Grid Name=\"voussoir\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    for (x.listed = 0; x.listed < n; x.listed++)
      xdmf_step(&x, (hsize_t)sel[x.listed], t[sel[x.listed]]);
    out_s(&x, "</Grid>\n</Domain>\n</Xdmf>\n");
    out_flush(&x);
    if (x.failed) {
      fclose(x.f);
      remove(tmp);
      st = vs_h5_fail(err, h5_path, "cannot read /observables/block_position");
    } else {
      st = vs_xdmf_close_tmp(x.f, tmp, xmf_path, err);
    }
  }
  vs_h5_close(x.pos);
  free(name);
  free(t);
  free(sel);
  free(x.geo);
  free(x.need);
  free(x.inl);
  free(x.ref);
  free(x.cen);
  free(x.loads);
  free(x.curve_lambda);
  free(x.load_q);
  free(x.load_cen);
  vs_h5_close(x.load_pos);
  return st;
}
