"""Studies in process: a sweep over case keys and a Monte Carlo over imperfect arches, each case
run by libvoussoir in a thread pool (the C calls release the GIL), returned as pandas tables with
the columns of the program's own tables (`voussoir sweep`'s summary.csv, `voussoir
montecarlo`'s samples.csv)."""
import itertools
import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor

from . import _lib
from ._lib import ffi
from .case import Case, _key_name
from .inprocess import run as _run
from .tables import pandas

SWEEP_COLUMNS = ["status", "first_limit_mm", "delta_u_mm", "dz_over_L_pct", "dx_over_L_pct",
                 "hinges_at_collapse", "mode", "snaps", "wall_s", "error"]
MC_COLUMNS = ["sample", "status", "first_limit_mm", "delta_u_mm", "dz_u_mm", "dx_u_mm", "mode",
              "pattern", "A", "B", "C", "D", "E", "error"]
# each support's own travel at the collapse (mm, outward and downward positive), the last four
# columns of both tables as in the program's summary.csv and samples.csv
TRAVEL_COLUMNS = ["left_dx_mm", "left_dz_mm", "right_dx_mm", "right_dz_mm"]
SWEEP_COLUMNS += TRAVEL_COLUMNS + ["load_factor"]  # load_factor: analysis.type = load, else NaN
MC_COLUMNS += TRAVEL_COLUMNS + ["load_factor"]
# a mortared study's (a case with joints.tensile_MPa or cohesion_MPa > 0): the first crack, the
# JSON's first_crack (NaN, 0, "" when none), the program's tables' last three columns
CRACK_COLUMNS = ["first_crack_mm", "first_crack_joint", "first_crack_side"]
_MC_STATUS = ("collapse", "max_displacement", "failed")


def _base(case, fall):
    if not isinstance(case, Case):
        case = Case.from_file(case)
    return case if fall else case.copy(dynamic__fall_s=0)


def _pool(jobs, fn, items):
    """fn over items in jobs threads, results in order. Ctrl-C (or any exception) in the waiting
    thread sets the stop event, which ends the runs under way at their next state and starts no
    other; the exception is then raised."""
    stop = threading.Event()
    jobs = jobs or os.cpu_count() or 1
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        futs = [ex.submit(fn, item, stop) for item in items]
        try:
            return [f.result() for f in futs]
        except BaseException:
            stop.set()
            for f in futs:
                f.cancel()
            raise


def sweep(case, alpha=None, kn=None, *, jobs=None, fall=False, **axes):
    """Run case (a Case or a case file) at every combination of the axes' values: alpha
    (support.alpha_deg, deg), kn (joints.kn_N_mm3, N/mm^3) and any section__key=[values]
    (numbers, or names of a choice: dynamic__damping_model=["joint", "rayleigh"]; the last
    axis varies fastest, as `voussoir sweep --vary`), in `jobs` threads (default:
    the number of CPUs). As `voussoir sweep`, the runs stop at the collapse (dynamic.fall_s =
    0) unless fall=True. Every case is checked before any runs (CaseError naming the key).

    Returns a pandas DataFrame, one row per run, with the columns of the program's
    summary.csv: run, one per axis (its section.key), status, first_limit_mm, delta_u_mm,
    dz_over_L_pct, dx_over_L_pct, hinges_at_collapse, mode, snaps, wall_s, error (a run that
    failed is a row with its error, not an exception), left_dx_mm, left_dz_mm, right_dx_mm,
    right_dz_mm (each support's own travel at the collapse, outward and downward positive),
    load_factor (analysis.type = load); and when a case has mortar (joints.tensile_MPa or
    cohesion_MPa > 0) first_crack_mm, first_crack_joint, first_crack_side (CRACK_COLUMNS)."""
    base = _base(case, fall)
    ax = []
    if alpha is not None:
        ax.append(("support.alpha_deg", alpha))
    if kn is not None:
        ax.append(("joints.kn_N_mm3", kn))
    ax += [(_key_name(k), v) for k, v in axes.items()]
    ax = [(k, [v] if isinstance(v, (int, float)) else list(v)) for k, v in ax]
    keys = [k for k, _ in ax]
    combos = list(itertools.product(*[v for _, v in ax]))
    cases = [base.copy(dict(zip(keys, c))).validate() for c in combos]

    def one(i, stop):
        row = {"run": i + 1}
        row.update(zip(keys, (x if isinstance(x, str) else float(x) for x in combos[i])))
        row.update(_sweep_row(cases[i], stop))
        return row

    rows = _pool(jobs, one, range(len(cases)))
    mortar = any(_mortared(c) for c in cases)
    return pandas().DataFrame(rows, columns=["run"] + keys + SWEEP_COLUMNS +
                              (CRACK_COLUMNS if mortar else []))


def _mortared(case):
    return case["joints.tensile_MPa"] > 0 or case["joints.cohesion_MPa"] > 0


def _sweep_row(case, stop):
    nan = math.nan
    row = dict.fromkeys(SWEEP_COLUMNS, nan)
    row.update(hinges_at_collapse="", mode="", snaps=0, error="")
    try:
        res = _run(case, history=False, stop=stop)
    except _lib.SolverError as e:
        res = e.result
        row["error"] = e.message
    row["status"] = res.status
    row["wall_s"] = res.wall_s
    fc = res.first_crack if res.mortared else None
    row.update(first_crack_mm=fc.delta_mm if fc else nan, first_crack_joint=fc.joint if fc else 0,
               first_crack_side=fc.side if fc else "")
    row["load_factor"] = res.load_factor
    row["mode"] = res.mode or ""
    if res.first_limit is not None:
        row["first_limit_mm"] = res.first_limit.delta_mm
    row["snaps"] = sum(1 for p in res.limit_points
                       if not p.collapse and math.isfinite(p.delta_settled_mm))
    if res.collapse is not None:
        c = res.collapse
        row.update(delta_u_mm=c.delta_mm, dz_over_L_pct=c.dz_over_L_pct,
                   dx_over_L_pct=c.dx_over_L_pct, hinges_at_collapse=res.hinges_at_collapse)
        row.update(_travel(case, c.delta_mm))
    return row


def montecarlo(case, samples, seed=None, *, jobs=None):
    """Samples 0 .. samples-1 of case (a Case or a case file) with its [imperfections] (seed:
    imperfections.seed, else the case's), each run to the collapse (vs_mc_run_sample: without
    the fall) in `jobs` threads. Returns a pandas DataFrame with the columns of `voussoir
    montecarlo`'s samples.csv: sample, status (collapse, max_displacement: none within
    support.max_mm, failed), first_limit_mm, delta_u_mm, dz_u_mm, dx_u_mm, mode (1..3 for
    I..III, 0 unclassified), pattern, A..E (each hinge at collapse as joint-side, "9-I"),
    error, left_dx_mm, left_dz_mm, right_dx_mm, right_dz_mm (each support's own travel),
    load_factor (analysis.type = load), and for a case with mortar (joints.tensile_MPa or
    cohesion_MPa > 0) the first crack's first_crack_mm, first_crack_joint, first_crack_side
    (CRACK_COLUMNS). A sample's run cannot be stopped from Python: Ctrl-C starts no new sample
    and returns once those under way end."""
    base = case if isinstance(case, Case) else Case.from_file(case)
    if seed is not None:
        base = base.copy(imperfections__seed=seed)
    base.validate()
    err = _lib.new_error()
    _lib.raise_for(_lib.lib().vs_case_check_path(base._c, b"montecarlo", err), err)

    def one(i, stop):
        if stop.is_set():
            raise KeyboardInterrupt
        out = ffi.new("vs_mc_sample *")
        _lib.lib().vs_mc_run_sample(base._c, i, out)
        return _mc_row(out, base)

    return pandas().DataFrame(_pool(jobs, one, range(samples)),
                              columns=MC_COLUMNS + (CRACK_COLUMNS if _mortared(base) else []))


def _travel(case, delta_mm):
    """The four travel columns at the right support's travel delta_mm (vs_mc_travel)."""
    t = ffi.new("double[4]")
    _lib.lib().vs_mc_travel(case._c, delta_mm, t)
    return dict(zip(TRAVEL_COLUMNS, t))


def _mc_row(s, base):
    row = {"sample": s.sample, "status": _MC_STATUS[s.status], "first_limit_mm": s.first_limit_mm,
           "delta_u_mm": s.delta_u_mm, "dz_u_mm": s.dz_u_mm, "dx_u_mm": s.dx_u_mm,
           "mode": s.mode,
           "pattern": ffi.string(s.pattern).decode(),
           "error": ffi.string(s.error).decode()}
    row.update(_travel(base, s.delta_u_mm if s.status == 0 else math.nan))
    row["load_factor"] = s.load_factor
    side = s.first_crack_side.decode() if s.first_crack_side != b"\0" else ""
    row.update(first_crack_mm=s.first_crack_mm, first_crack_joint=s.first_crack_joint,
               first_crack_side=side)
    for k, label in enumerate("ABCDE"):
        side = s.hinge_side[k].decode() if s.hinge_side[k] != b"\0" else ""
        row[label] = f"{s.hinge_joint[k]}-{side}" if s.hinge_joint[k] else ""
    return row


CALIBRATE_SCAN = 9  # log-spaced k_n of the scan, as `voussoir calibrate`


def calibrate(case, target_dz_pct=None, *, target_dx_pct=None, kn_min=0.1, kn_max=100.0,
              tol_pct=0.01):
    """The joint stiffness k_n (N/mm^3) at which the case's collapse displacement component
    dz/L (target_dz_pct) or dx/L (target_dx_pct), in % of the span, equals the target: the
    algorithm of `voussoir calibrate`, each evaluation a run in this process to the collapse
    (without the fall): a scan of 9 k_n log-spaced over [kn_min, kn_max] up to the first pair
    that brackets the target, then Illinois false position on log10 k_n until the component is
    within tol_pct of the target (or the bracket is narrower than 1e-5 decades), then the
    sensitivity by central differences over +-0.01 decade.

    Returns a pandas DataFrame, one row per run in order: stage ('scan', 'iteration',
    'bisection': a false-position point without a collapse, bisected instead; 'sensitivity'),
    kn_N_mm3, the component (dz_over_L_pct or dx_over_L_pct; NaN without a collapse), and
    residual_pct (component - target). df.attrs: kn_N_mm3 (the result), component,
    target_pct, tol_pct, converged (within tol_pct), sensitivity_pct_per_decade, runs.
    ValueError when no k_n of the scan brackets the target (its range is said), or for a bad
    target; CaseError for a bad case."""
    if (target_dz_pct is None) == (target_dx_pct is None):
        raise ValueError("calibrate: give one of target_dz_pct and target_dx_pct")
    dx = target_dx_pct is not None
    target = float(target_dx_pct if dx else target_dz_pct)
    if not (0 < kn_min < kn_max) or not tol_pct > 0 or not math.isfinite(target):
        raise ValueError(f"calibrate: kn_min {kn_min}, kn_max {kn_max}, tol_pct {tol_pct}, "
                         f"target {target}: need 0 < kn_min < kn_max, tol_pct > 0, a finite target")
    base = _base(case, False).validate()
    comp = "dx_over_L_pct" if dx else "dz_over_L_pct"
    if dx and base["support.left_rate_mm_s"] == 0 and base["support.left_path"] in ("", None) \
            and base["support.right_path"] in ("", None) \
            and abs(math.sin(math.radians(base["support.alpha_deg"]))) < 1e-12:
        raise ValueError("calibrate: target_dx_pct with alpha = 0: dx is always 0")
    rows = []

    def f(kn, stage):
        try:
            res = _run(base.copy(joints__kn_N_mm3=kn), history=False)
            v = getattr(res.collapse, comp) if res.collapse is not None else math.nan
        except _lib.SolverError:
            v = math.nan
        rows.append({"stage": stage, "kn_N_mm3": kn, comp: v, "residual_pct": v - target})
        return v - target

    kn = [kn_min * (kn_max / kn_min) ** (i / (CALIBRATE_SCAN - 1)) for i in range(CALIBRATE_SCAN)]
    fs, lo = [], -1
    for i, k in enumerate(kn):
        fs.append(f(k, "scan"))
        if i > 0 and math.isfinite(fs[i]) and math.isfinite(fs[i - 1]) and \
                (fs[i - 1] <= 0) != (fs[i] <= 0):
            lo = i - 1
            break
    if lo < 0:
        seen = [v + target for v in fs if math.isfinite(v)]
        span = f"{min(seen):.4f}..{max(seen):.4f} %" if seen else "no collapse"
        raise ValueError(f"calibrate: no k_n in [{kn_min:g}, {kn_max:g}] N/mm^3 gives a collapse "
                         f"{comp[:2]}/L of {target:g} %: the scan gives {span}")
    xa, xb, fa, fb = math.log10(kn[lo]), math.log10(kn[lo + 1]), fs[lo], fs[lo + 1]
    x, fx, side = xa, fa, 0
    for _ in range(40):
        x = (xa * fb - xb * fa) / (fb - fa)
        fx = f(10.0 ** x, "iteration")
        if not math.isfinite(fx):  # no collapse there: bisect instead
            x = 0.5 * (xa + xb)
            fx = f(10.0 ** x, "bisection")
            if not math.isfinite(fx):
                break
        if abs(fx) <= tol_pct or xb - xa < 1e-5:
            break
        if (fx <= 0) == (fa <= 0):
            xa, fa = x, fx
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            xb, fb = x, fx
            if side == 1:
                fa *= 0.5
            side = 1
    sens = math.nan
    if math.isfinite(fx):
        h = 0.01
        sens = (f(10.0 ** (x + h), "sensitivity") - f(10.0 ** (x - h), "sensitivity")) / (2 * h)
    df = pandas().DataFrame(rows, columns=["stage", "kn_N_mm3", comp, "residual_pct"])
    df.attrs.update(kn_N_mm3=10.0 ** x if math.isfinite(fx) else math.nan, component=comp,
                    target_pct=target, tol_pct=tol_pct, converged=bool(abs(fx) <= tol_pct),
                    sensitivity_pct_per_decade=sens, runs=len(rows))
    return df
