"""The library in process: libvoussoir loaded with cffi in ABI mode (Debian's python3-cffi; no
compiler needed), the declarations this package uses, and errors as exceptions.

Which library: $VOUSSOIR_LIB (a path to libvoussoir.so.N) when set; else the one beside the
`voussoir` program ($VOUSSOIR, else `voussoir` on PATH): in its directory (a build tree) or in
../lib or ../lib/<multiarch> (an installed prefix); else the dynamic loader's search for the
soname. docs/python.md says so; library_path() tells which one was loaded.

The declarations below are copied from the public headers (include/voussoir/*.h), only those
used. tests/python_cdef_check.py compiles them against the installed headers: every function
must redeclare the header's prototype exactly, every struct must have the header's size and
field offsets. vs_case is held as an opaque buffer (the package reads and writes it through
vs_case_key and vs_case_set only), whose size must be at least the header's.
"""
import os
import shutil
import threading

from cffi import FFI

# The ABI number (soname libvoussoir.so.N) these declarations are for.
ABI = 4

# Types: layouts of the header's structs (checked by size and offsets), opaque handles.
CDEF_TYPES = """
typedef int vs_status;
typedef struct { vs_status status; char msg[512]; } vs_error;
typedef struct { double opaque[2048]; } vs_case;  /* >= sizeof(vs_case): checked */
typedef struct vs_run vs_run;
typedef struct vs_model vs_model;
typedef struct vs_support_motion vs_support_motion;
typedef struct vs_joint_state vs_joint_state;
typedef struct {
  double kinetic, gravity, elastic;
  double support_work;
  double damped;
  double friction;
  double balance;
  double cracking;
} vs_energy;
typedef struct {
  int phase;
  double t, delta;
  const double *q, *v;
  const vs_energy *energy;
  const double *reactions;
  const vs_joint_state *joints;
  double elastic, gravity;
  long newton_iterations;
  long ida_steps, ida_newton_iterations;
  long fall_steps;
} vs_run_sample;
typedef struct {
  int kind;
  int phase;
  double t, delta;
  int joint;
  char side;
  char label;
  int order;
  double load_factor;
} vs_run_event;
typedef struct {
  char label;
  char side;
  int first, last;
  int onset_first, onset_last;
  double delta_onset;
  int order;
  int open;
  double delta_closed;
} vs_hinge;
typedef struct {
  int joint;
  char side;
  double slip;
} vs_slip;
typedef struct {
  double delta;
  int collapse;
  double delta_settled;
  char hinges_before[160], hinges_after[160];
} vs_limit_record;
typedef struct {
  int found;
  double delta;
  double t;
  double t_criterion;
  double delta_detected;
  double t_onset;
  int n_hinges;
  const vs_hinge *hinges;
  double reactions_limit[6];
  const char *mechanism;
  int n_slips;
  const vs_slip *slips;
} vs_collapse_record;
typedef struct {
  int sample;
  int status;
  double first_limit_mm;
  double delta_u_mm;
  double dz_u_mm, dx_u_mm;
  int mode;
  int hinge_joint[5];
  char hinge_side[5];
  char pattern[16];
  char error[400];
  double load_factor;
  int mortared;
  double first_crack_mm;
  int first_crack_joint;
  char first_crack_side;
} vs_mc_sample;
typedef struct {
  int done;
  int end;
  double hold;
  int held_limit;
  double load_factor;
  double deflection;
  double first_peak;
  int snap_back;
  int settled;
  int n;
  const double *lambda;
  const double *u;
  char mechanism[160];
  char cause[256];
  long steps, rejected, newton_iterations, jacobian_evals;
} vs_run_load_result;
typedef int (*vs_run_sample_fn)(void *user, const vs_run *run, const vs_run_sample *s);
typedef int (*vs_run_event_fn)(void *user, const vs_run *run, const vs_run_event *e);
"""

# Functions: each exactly as its header declares it (the check pastes these after the headers).
CDEF_FUNCTIONS = """
const char *vs_strerror(vs_status status);
void vs_error_clear(vs_error *err);
void vs_case_defaults(vs_case *c);
vs_status vs_case_read(vs_case *c, const char *path, char **text_out, vs_error *err);
vs_status vs_case_parse(vs_case *c, const char *name, const char *text, size_t len,
                        vs_error *err);
vs_status vs_case_set(vs_case *c, const char *assignment, vs_error *err);
vs_status vs_case_validate(const vs_case *c, vs_error *err);
vs_status vs_case_check_path(const vs_case *c, const char *command, vs_error *err);
int vs_case_key_count(void);
int vs_case_key(const vs_case *c, int i, const char **section, const char **key,
                const char **unit, int *is_int, double *value);
int vs_case_key_text(const vs_case *c, int i, char *buf, size_t size);
const char *vs_case_key_name_of(int i, int value);
int vs_case_text_key_count(void);
int vs_case_text_key(const vs_case *c, int i, const char **section, const char **key,
                     char *text, size_t size);
double vs_case_loading_rate_mm_s(const vs_case *c);
double vs_case_span_mm(const vs_case *c);
vs_status vs_run_create(const vs_case *c, vs_run **out, vs_error *err);
void vs_run_destroy(vs_run **r);
vs_status vs_run_execute(vs_run *r, vs_run_sample_fn sample, vs_run_event_fn event,
                         void *user, vs_error *err);
const vs_case *vs_run_case(const vs_run *r);
const vs_model *vs_run_model(const vs_run *r);
int vs_run_limit_count(const vs_run *r);
const vs_limit_record *vs_run_limit(const vs_run *r, int i);
const vs_collapse_record *vs_run_collapse(const vs_run *r);
const vs_run_load_result *vs_run_load(const vs_run *r);
int vs_run_hinge_count(const vs_run *r);
const vs_hinge *vs_run_hinge(const vs_run *r, int i);
int vs_run_event_count(const vs_run *r);
const vs_run_event *vs_run_event_get(const vs_run *r, int i);
const char *vs_run_mode(const vs_run *r);
const char *vs_run_pattern_initial(const vs_run *r);
const char *vs_run_pattern_collapse(const vs_run *r);
double vs_run_delta(const vs_run *r);
double vs_run_time(const vs_run *r);
double vs_run_wall_s(const vs_run *r);
double vs_model_cracking_energy(const vs_model *m);
int vs_run_joint_cracks(const vs_run *r, double *out);
const vs_support_motion *vs_model_support_motion(const vs_model *m, int right);
void vs_support_motion_at(const vs_support_motion *mo, double delta, double u[3],
                          double du[3]);
void vs_hinges_list(const vs_hinge *h, int n, int open_only, char *buf, size_t size);
void vs_mc_run_sample(const vs_case *base, int sample, vs_mc_sample *out);
void vs_mc_travel(const vs_case *c, double delta_mm, double t[4]);
"""

# Status codes (status.h; the check compares them with the header's).
STATUS = {"VS_OK": 0, "VS_ERR_NOMEM": -1, "VS_ERR_IO": -2, "VS_ERR_PARSE": -3,
          "VS_ERR_INVALID": -4, "VS_ERR_SOLVER": -5, "VS_ERR_NO_EQUILIBRIUM": -6,
          "VS_ERR_USAGE": -7, "VS_ERR_INTERNAL": -8, "VS_ERR_INTERRUPTED": -9,
          "VS_ERR_WALL_TIME": -10, "VS_ERR_STOPPED": -11}
STATUS_NAME = {v: k for k, v in STATUS.items()}

ffi = FFI()
ffi.cdef(CDEF_TYPES)
ffi.cdef(CDEF_FUNCTIONS)

_lock = threading.Lock()
_lib = None
_path = None


class Error(Exception):
    """An error of the library: str(e) is its message (vs_error.msg, e.g. "--set
    support.alpha_deg=500: out of range (allowed: [-180, 180])"); status is its code's name
    ("VS_ERR_INVALID"), code the number. A failed run's partial result is in e.result."""

    def __init__(self, code, message, result=None):
        self.code = code
        self.status = STATUS_NAME.get(code, str(code))
        self.message = message
        self.result = result
        super().__init__(message)


class CaseError(Error, ValueError):
    """Bad input: a key, a value out of range, a malformed or unreadable case file
    (VS_ERR_PARSE, VS_ERR_INVALID, VS_ERR_IO); the message names the key and the range."""


class SolverError(Error, RuntimeError):
    """The run failed (VS_ERR_SOLVER, VS_ERR_NO_EQUILIBRIUM, ...) or stopped at its wall-time
    limit; e.result holds what it computed up to there."""


def raise_for(code, err, result=None):
    """Raise the exception for status code (with err's message) unless it is VS_OK."""
    if code == 0:
        return
    msg = ffi.string(err.msg).decode("utf-8", "replace") if err is not None else ""
    msg = msg or ffi.string(lib().vs_strerror(code)).decode()
    cls = CaseError if code in (-2, -3, -4) else SolverError
    raise cls(code, msg, result)


def _candidates():
    env = os.environ.get("VOUSSOIR_LIB")
    if env:
        return [env]
    soname = f"libvoussoir.so.{ABI}"
    out = []
    prog = os.environ.get("VOUSSOIR") or shutil.which("voussoir")
    if prog:
        d = os.path.dirname(os.path.realpath(prog))
        out.append(os.path.join(d, soname))
        lib = os.path.join(os.path.dirname(d), "lib")
        out.append(os.path.join(lib, soname))
        if os.path.isdir(lib):
            out += [os.path.join(lib, s, soname) for s in sorted(os.listdir(lib))
                    if s.endswith("-linux-gnu")]
    return [p for p in out if os.path.exists(p)] + [soname]


def lib():
    """The loaded library (loaded on first use)."""
    global _lib, _path
    with _lock:
        if _lib is None:
            tried = []
            for p in _candidates():
                try:
                    _lib = ffi.dlopen(p)
                    _path = p
                    break
                except OSError as e:
                    tried.append(f"{p}: {e}")
            if _lib is None:
                raise OSError("libvoussoir not found; set VOUSSOIR_LIB to the library, or VOUSSOIR "
                              "to the voussoir program it was built with (tried: "
                              + "; ".join(tried) + ")")
        return _lib


def library_path():
    """The path (or soname) of the library loaded."""
    lib()
    return _path


def new_error():
    err = ffi.new("vs_error *")
    lib().vs_error_clear(err)
    return err


def text(p):
    """A C string as str (None for NULL)."""
    return None if p == ffi.NULL else ffi.string(p).decode("utf-8", "replace")
