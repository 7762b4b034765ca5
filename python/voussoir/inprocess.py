"""One run in process: voussoir.run(case) -> Result, through libvoussoir's public API (run.h).
The C calls release the GIL (cffi), so runs in threads go in parallel; the sample callback
collects the history and stops the run (VS_ERR_STOPPED) on Ctrl-C or a stop event."""
import math
from dataclasses import dataclass

import numpy as np

from . import _lib
from ._lib import ffi
from .case import Case
from .record import LoadCurve, first_crack_of

MM = 1e-3
_PHASES = ("quasistatic", "dynamic", "fall")
_EVENTS = ("joint_opened", "joint_closed", "hinge_formed", "limit_point", "snap_settled",
           "collapse", "joint_slipped", "pier_rocked", "course_opened", "crack_initiated")
_STOPPED, _WALL = _lib.STATUS["VS_ERR_STOPPED"], _lib.STATUS["VS_ERR_WALL_TIME"]

# What the history keeps of every recorded state, with units (the record's names).
HISTORY_UNITS = {"time": "s", "delta": "m", "phase": "", "left_Fx": "N", "left_Fz": "N",
                 "left_M": "N m", "right_Fx": "N", "right_Fz": "N", "right_M": "N m",
                 "elastic": "J", "gravity": "J", "kinetic": "J"}


_NAN6 = np.full(6, np.nan).tobytes()


def _ch(c):
    c = c if isinstance(c, bytes) else bytes([c])
    return c.decode() if c != b"\0" else ""


@dataclass
class Hinge:
    """A hinge as the JSON report gives it: label (A..), side ('I' intrados, 'E' extrados: the
    edge in contact), joints (1-based, several for a spread hinge) now and at onset, the support
    displacement and loading time at onset, open, order of appearance."""
    label: str
    side: str
    joints: tuple
    joints_onset: tuple
    delta_onset_mm: float
    time_onset_s: float
    open: bool
    order: int

    @property
    def name(self):
        """'9-10-I'."""
        return "-".join(str(j) for j in self.joints) + "-" + self.side


@dataclass
class Collapse:
    """The collapse: delta_mm (the collapse displacement delta_u), its components over the span
    dz_over_L_pct (down) and dx_over_L_pct (outward), its loading time, the detection, the
    mechanism ('rotational', 'sliding', 'mixed'), its hinges (left to right) and slips."""
    delta_mm: float
    dz_over_L_pct: float
    dx_over_L_pct: float
    time_s: float
    delta_detected_mm: float
    time_detected_s: float
    mechanism: str
    hinges: list
    slips: list


@dataclass
class LimitPoint:
    delta_mm: float
    collapse: bool
    delta_settled_mm: float  # a snap-through: where the path resumed (NaN for the collapse)
    hinges_before: str
    hinges_after: str


@dataclass
class Event:
    kind: str
    phase: str
    time_s: float
    delta_mm: float
    joint: int
    side: str
    label: str
    order: int
    load_factor: float = math.nan  # on a load path (analysis.type = load): lambda there


class History:
    """The recorded states as numpy arrays, one per quantity (HISTORY_UNITS: time s, delta m,
    phase 0 quasi-static / 1 dynamic / 2 fall, the supports' forces on the arch N and N m,
    energies J; kinetic NaN on the quasi-static path): history["delta"], history.unit("delta").
    A mortared run's also keeps the joints' crack history: joint_crack()."""

    def __init__(self, columns, joint_crack=None):
        self._cols = columns
        self._crack = joint_crack
        self.units = dict(HISTORY_UNITS)

    def joint_crack(self):
        """A mortared run's joints' lengths cracked through from the intrados and from the
        extrados (m) at every state, shape (states, joints, 2), as committed at each state:
        what Record.joint_crack() reads from the record (/observables/joint_crack). None for a
        dry run (joints.tensile_MPa = cohesion_MPa = 0) or without a history."""
        return self._crack

    def __getitem__(self, name):
        return self._cols[name]

    def __contains__(self, name):
        return name in self._cols

    def __len__(self):
        return len(self._cols["time"])

    def keys(self):
        return self._cols.keys()

    def unit(self, name):
        return self.units[name]

    def to_dataframe(self):
        """A pandas DataFrame, one row per state, the units in df.attrs["units"]."""
        from .tables import pandas
        df = pandas().DataFrame(self._cols)
        df.attrs["units"] = dict(self.units)
        return df


# One vs_run_sample as bytes: the fields the history keeps, read by numpy after the run.
_SAMPLE_FIELDS = [("phase", "i4"), ("t", "f8"), ("delta", "f8"), ("elastic", "f8"),
                  ("gravity", "f8")]


def _sample_dtype():
    t = ffi.typeof("vs_run_sample")
    offs = dict((name, f.offset) for name, f in t.fields)
    return np.dtype({"names": [n for n, _ in _SAMPLE_FIELDS],
                     "formats": [f for _, f in _SAMPLE_FIELDS],
                     "offsets": [offs[n] for n, _ in _SAMPLE_FIELDS],
                     "itemsize": ffi.sizeof("vs_run_sample")})


class _Collector:
    """The run's sample function: keeps each state's bytes (cheap in the callback), stops the
    run when asked (stop event set, or Ctrl-C raised inside it)."""
    SIZE = ffi.sizeof("vs_run_sample")
    DTYPE = None

    def __init__(self, history, stop, cracks=False):
        self.rows, self.reactions, self.kinetic, self.cracks = [], [], [], []
        self.history, self.stop, self.interrupted = history, stop, False
        self.keep_cracks, self._crack_buf, self.n_joints = history and cracks, None, 0
        self.cb = ffi.callback("vs_run_sample_fn", self._sample, onerror=self._error)

    def _sample(self, user, run, s):
        if self.stop is not None and self.stop.is_set():
            return 1
        if self.history:
            self.rows.append(ffi.buffer(s, self.SIZE)[:])
            self.reactions.append(ffi.buffer(s.reactions, 48)[:] if s.reactions != ffi.NULL
                                  else _NAN6)
            e = s.energy
            self.kinetic.append(e.kinetic if e != ffi.NULL else math.nan)
            if self.keep_cracks:  # a mortared run's cracks, as the record's joint_crack row
                L = _lib.lib()
                if self._crack_buf is None:
                    self.n_joints = L.vs_run_joint_cracks(run, ffi.NULL)
                    self._crack_buf = ffi.new("double[]", 2 * self.n_joints)
                L.vs_run_joint_cracks(run, self._crack_buf)
                self.cracks.append(ffi.buffer(self._crack_buf)[:])
        return 0

    def _error(self, exc, value, tb):
        # Ctrl-C (KeyboardInterrupt raised while the callback ran) or a failure in it: stop.
        self.interrupted = value if value is not None else exc()
        return 1

    def columns(self):
        if _Collector.DTYPE is None:
            _Collector.DTYPE = _sample_dtype()
        a = np.frombuffer(b"".join(self.rows), dtype=_Collector.DTYPE)
        r = np.frombuffer(b"".join(self.reactions), dtype="f8").reshape(-1, 6)
        cols = {"time": a["t"].copy(), "delta": a["delta"].copy(),
                "phase": a["phase"].astype(np.int8)}
        for j, n in enumerate(("left_Fx", "left_Fz", "left_M", "right_Fx", "right_Fz",
                               "right_M")):
            cols[n] = r[:, j].copy()
        cols["elastic"], cols["gravity"] = a["elastic"].copy(), a["gravity"].copy()
        cols["kinetic"] = np.array(self.kinetic, dtype="f8")
        return cols

    def joint_crack(self):
        """The cracks of every state kept (keep_cracks), (states, joints, 2); None if none kept."""
        if not self.keep_cracks:
            return None
        return np.frombuffer(b"".join(self.cracks), dtype="f8").reshape(-1, self.n_joints, 2)


class Result:
    """What a run computed: status ('collapse', 'limit_point', 'max_displacement', 'stopped',
    'failed'), collapse (Collapse, or None without one), first_limit (LimitPoint or None),
    limit_points, hinges (as reported: order of appearance, each as at the collapse's onset),
    events, mode ('I', 'II', 'III' or None), hinge_sides_initial / hinge_sides_collapse,
    hinges_at_collapse ("D:1-E A:9-10-I ...", "" without a collapse),
    history (History), wall_s (the run's wall-clock time), case (Case), load_factor (with
    analysis.type = load: the live load's factor at collapse, 0 when the arch fell before the
    hold; NaN otherwise), mortared (joints.tensile_MPa or cohesion_MPa > 0), first_crack
    (FirstCrack: delta_mm, joint, side, load_factor, the JSON's first_crack; None when no joint
    cracked or the joints are dry), energy ({"cracking_J": the energy the joints' cracking
    dissipated, J, the JSON's energy.cracking_J; 0 for dry joints})."""

    def __init__(self, case, run, status, err, history):
        L = _lib.lib()
        self.case = case
        self.status = _end_name(run, case, status)
        self.error = _lib.text(err.msg) if status != 0 else None
        self.wall_s = L.vs_run_wall_s(run)
        self.last_delta_mm = L.vs_run_delta(run) / MM
        self.last_time_s = L.vs_run_time(run)
        self.mode = _lib.text(L.vs_run_mode(run))
        self.hinge_sides_initial = _lib.text(L.vs_run_pattern_initial(run))
        self.hinge_sides_collapse = _lib.text(L.vs_run_pattern_collapse(run))
        rate = L.vs_case_loading_rate_mm_s(case._c)
        self.hinges = [_hinge(L.vs_run_hinge(run, i), rate)
                       for i in range(L.vs_run_hinge_count(run))]
        self.limit_points = [_limit(L.vs_run_limit(run, i))
                             for i in range(L.vs_run_limit_count(run))]
        self.first_limit = self.limit_points[0] if self.limit_points else None
        self.events = [_event(L.vs_run_event_get(run, i))
                       for i in range(L.vs_run_event_count(run))]
        self.collapse = _collapse(run, case, rate)
        buf = ffi.new("char[]", 512)  # as `voussoir sweep`'s hinges_at_collapse
        c = L.vs_run_collapse(run)
        if c.found:
            L.vs_hinges_list(c.hinges, c.n_hinges, 0, buf, 512)
        self.hinges_at_collapse = ffi.string(buf).decode()
        self.history = history
        ld = L.vs_run_load(run)
        self.load_factor = ld.load_factor if ld.done else math.nan
        self._load = _load_curve(ld) if ld.done else None
        self.mortared = case["joints.tensile_MPa"] > 0 or case["joints.cohesion_MPa"] > 0
        self.first_crack = first_crack_of(self.events)
        self.energy = {"cracking_J": L.vs_model_cracking_energy(L.vs_run_model(run))}

    def load_curve(self):
        """The load-deflection curve of a load run (LoadCurve); ValueError for another
        analysis."""
        if self._load is None:
            raise ValueError("not a load run (analysis.type = load): no load-deflection curve")
        return self._load

    def to_dataframe(self):
        """The history as a pandas DataFrame (one row per recorded state, units in
        df.attrs["units"]; the run's status in df.attrs["status"] and, after a collapse, its
        displacement in df.attrs["collapse_delta_mm"])."""
        df = self.history.to_dataframe()
        df.attrs["status"] = self.status
        if self.collapse is not None:
            df.attrs["collapse_delta_mm"] = self.collapse.delta_mm
        return df

    def __repr__(self):
        c = f", collapse {self.collapse.delta_mm:.3f} mm" if self.collapse else ""
        return f"<voussoir.Result {self.status}{c}, {len(self.hinges)} hinges>"


def _hinge(h, rate_mm_s):
    return Hinge(_ch(h.label), _ch(h.side), tuple(range(h.first, h.last + 1)),
                 tuple(range(h.onset_first, h.onset_last + 1)), h.delta_onset / MM,
                 h.delta_onset / MM / rate_mm_s, bool(h.open), h.order)


def _limit(p):
    return LimitPoint(p.delta / MM, bool(p.collapse), p.delta_settled / MM,
                      ffi.string(p.hinges_before).decode(), ffi.string(p.hinges_after).decode())


def _event(e):
    return Event(_EVENTS[e.kind] if 0 <= e.kind < len(_EVENTS) else str(e.kind),
                 _PHASES[e.phase], e.t, e.delta / MM, e.joint, _ch(e.side), _ch(e.label),
                 e.order, e.load_factor)


_LOAD_ENDS = ("none", "peak", "sliding", "max_displacement", "stalled")


def _load_curve(ld):
    """LoadCurve of a vs_run_load_result (copied: the run owns its arrays)."""
    n = ld.n
    lam = np.array(ffi.unpack(getattr(ld, "lambda"), n) if n else [], float)
    u = np.array(ffi.unpack(ld.u, n) if n else [], float)
    end = ("held_limit" if ld.held_limit else
           _LOAD_ENDS[ld.end] if 0 <= ld.end < len(_LOAD_ENDS) else "?")
    return LoadCurve(lam, u, ld.load_factor, ld.first_peak, ld.deflection, ld.hold, end,
                     ffi.string(ld.mechanism).decode())


def _support_relative(run, delta):
    """The right support's displacement relative to the left one's, mm: (outward, down)."""
    L = _lib.lib()
    m = L.vs_run_model(run)
    u = ffi.new("double[3]")
    L.vs_support_motion_at(L.vs_model_support_motion(m, 0), delta, u, ffi.NULL)
    lx, lz = -u[0] / MM, -u[1] / MM
    L.vs_support_motion_at(L.vs_model_support_motion(m, 1), delta, u, ffi.NULL)
    rx, rz = u[0] / MM, -u[1] / MM
    return rx + lx, rz - lz


def _collapse(run, case, rate_mm_s):
    L = _lib.lib()
    c = L.vs_run_collapse(run)
    if not c.found:
        return None
    dx, dz = _support_relative(run, c.delta)
    span = case.span_mm
    hinges = [_hinge(c.hinges[i], rate_mm_s) for i in range(c.n_hinges)]
    slips = [(c.slips[i].joint, _ch(c.slips[i].side), c.slips[i].slip / MM)
             for i in range(c.n_slips)]
    return Collapse(c.delta / MM, 100 * dz / span, 100 * dx / span, c.t, c.delta_detected / MM,
                    c.t_criterion, _lib.text(c.mechanism), hinges, slips)


def _end_name(run, case, st):
    L = _lib.lib()
    if st in (_STOPPED, _WALL):
        return "stopped"
    if st != 0:
        return "failed"
    if L.vs_run_collapse(run).found:
        return "collapse"
    if not case["dynamic.follow"] and not case["dynamic.full"] and L.vs_run_limit_count(run):
        return "limit_point"
    return "max_displacement"


def run(case, *, history=True, stop=None, **overrides):
    """Run case (a Case, or a case file's path) to the collapse, in this process; returns a
    Result. overrides (section__key=value) apply to a copy. history=False keeps no states.
    stop: a threading.Event whose set() stops the run at its next recorded state.

    Raises CaseError (bad input, before anything runs), SolverError (the run failed, or hit
    run.max_wall_s; e.result holds what it computed), KeyboardInterrupt (Ctrl-C: the run
    stopped at its next state, its memory freed)."""
    if not isinstance(case, Case):
        case = Case.from_file(case)
    if overrides:
        case = case.copy(**overrides)
    case.validate()
    L = _lib.lib()
    err = _lib.new_error()
    prun = ffi.new("vs_run **")  # NULL until created: vs_run_destroy accepts it
    mortared = case["joints.tensile_MPa"] > 0 or case["joints.cohesion_MPa"] > 0
    col = _Collector(history, stop, cracks=mortared)
    res = None
    try:
        _lib.raise_for(L.vs_run_create(case._c, prun, err), err)
        st = L.vs_run_execute(prun[0], col.cb, ffi.NULL, ffi.NULL, err)
        if col.interrupted and not isinstance(col.interrupted, KeyboardInterrupt):
            raise col.interrupted
        hist = History(col.columns() if history else {k: np.empty(0) for k in HISTORY_UNITS},
                       col.joint_crack())
        res = Result(case, prun[0], st, err, hist)
    except KeyboardInterrupt:  # Ctrl-C outside the sample function (while the run was built)
        col.interrupted = KeyboardInterrupt()
    finally:
        L.vs_run_destroy(prun)
    if isinstance(col.interrupted, KeyboardInterrupt):
        where = f" at support displacement {res.last_delta_mm:.3f} mm" if res else ""
        raise KeyboardInterrupt(f"voussoir.run: stopped by Ctrl-C{where}")
    if st == _STOPPED:
        res.stopped_by = "stop event"
        return res
    if st != 0:
        _lib.raise_for(st, err, res)
    return res
