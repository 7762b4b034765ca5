"""The in-process bindings (voussoir.Case, run, sweep, montecarlo) against the program, an
independent path through the CLI (tests/test_python_inprocess.sh).
usage: /usr/bin/python3 python_inprocess_check.py CASE DIR  (VOUSSOIR = the program)"""
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np

import voussoir


def check(cond, msg):
    if not cond:
        print("FAIL:", msg)
        sys.exit(1)


def close(a, b, rel=1e-8):  # the JSON prints 10 significant digits; NaN (none) equals NaN
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


case_path, out = sys.argv[1], sys.argv[2]
prog = os.environ["VOUSSOIR"]


def program_json(*sets):
    args = [prog, "run", case_path, "--json", "-q", "--no-record"]
    for s in sets:
        args += ["--set", s]
    return json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)


# 1. The reference case in process: the program's collapse, hinges, mode and limit points.
case = voussoir.Case.from_file(case_path)
res = voussoir.run(case)
ref = program_json()
check(res.status == ref["status"] == "collapse", f"status {res.status} / {ref['status']}")
c, rc = res.collapse, ref["collapse"]
for k in ("delta_mm", "dz_over_L_pct", "dx_over_L_pct", "time_s", "delta_detected_mm"):
    check(close(getattr(c, k), rc[k]) or (rc[k] == 0 and abs(getattr(c, k)) < 1e-12),
          f"collapse.{k}: {getattr(c, k)} in process, {rc[k]} by the program")
check(c.mechanism == rc["mechanism"], "mechanism")
check(len(res.hinges) == len(ref["hinges"]) == 4, f"hinges {res.hinges}")
for h, j in zip(res.hinges, ref["hinges"]):
    check(h.label == j["label"] and h.side == j["side"] and list(h.joints) == j["joints"] and
          list(h.joints_onset) == j["joints_onset"] and h.open == j["open"] and
          h.order == j["order"] and close(h.delta_onset_mm, j["delta_onset_mm"]),
          f"hinge {h} differs from the program's {j}")
check([h.label for h in c.hinges] == [j["label"] for j in rc["hinges"]], "collapse hinges")
check(res.mode == ref["mode"] and res.hinge_sides_collapse == ref["hinge_sides_collapse"], "mode")
check(len(res.limit_points) == len(ref["limit_points"]), "limit points")
check(close(res.first_limit.delta_mm, ref["first_limit"]["delta_mm"]), "first limit point")
# The history: statics on every quasi-static state (the supports carry the arch's weight, an
# independent figure: density x volume x g of the annular segment), delta increasing there.
h = res.history
qs = h["phase"] == 0
R, t = case["arch.radius_mm"] * 1e-3, case["arch.thickness_mm"] * 1e-3
b = case["arch.depth_mm"] * 1e-3
weight = (case["arch.density_kg_m3"] * case["arch.gravity_m_s2"] * b
          * math.radians(case["arch.embrace_deg"]) / 2 * ((R + t) ** 2 - R ** 2))
fz = h["left_Fz"] + h["right_Fz"]
check(np.abs(fz[qs] - weight).max() < 1e-6 * weight, f"sum Fz {fz[qs].min()} vs W {weight}")
check(h.unit("delta") == "m" and h.unit("right_Fz") == "N", "units")
check(np.all(np.diff(h["delta"][qs]) > 0), "delta increases along the path")
check(np.nanmax(h["kinetic"][~qs]) > 0 and np.all(np.isnan(h["kinetic"][qs])), "kinetic energy")
df = res.to_dataframe()
check(len(df) == len(h) and df.attrs["units"]["delta"] == "m", "to_dataframe")

# Without pandas (as if python3-pandas were not installed): an ImportError saying what to install.
saved = sys.modules.get("pandas")
sys.modules["pandas"] = None  # `import pandas` now raises ImportError
try:
    res.to_dataframe()
    check(False, "to_dataframe without pandas")
except ImportError as e:
    check("python3-pandas" in str(e), f"message {e}")
finally:
    sys.modules["pandas"] = saved

# 2. Bad input: an exception naming the key and the allowed range, before anything runs.
for bad in (lambda: voussoir.Case.from_file(case_path, joints__kn_N_mm3=-1),
            lambda: voussoir.Case.from_file(case_path, {"joints.kn_N_mm3": -1}),
            lambda: voussoir.run(case, joints__kn_N_mm3=-1)):
    try:
        bad()
        check(False, "kn_N_mm3 = -1 accepted")
    except voussoir.CaseError as e:
        check("joints.kn_N_mm3" in str(e) and "allowed" in str(e) and e.status == "VS_ERR_INVALID",
              f"message {e}")
try:
    voussoir.Case(arch__no_such_key=1)
    check(False, "an unknown key accepted")
except voussoir.CaseError as e:
    check("arch.no_such_key" in str(e), f"message {e}")
try:
    voussoir.Case.from_file(os.path.join(out, "missing.ini"))
    check(False, "a missing file accepted")
except voussoir.CaseError as e:
    check("missing.ini" in str(e) and e.status == "VS_ERR_IO", f"message {e}")

# Values from numpy, a list as the case file's comma-separated list; a choice by its name.
c4 = voussoir.Case(arch__voussoirs=4, arch__joint_positions=np.array([0.25, 0.5, 0.75]),
                   joints__kn_N_mm3=np.float64(48), dynamic__damping_model="rayleigh")
check(c4["joints.kn_N_mm3"] == 48.0 and c4["dynamic.damping_model"] == "rayleigh" and
      [float(x) for x in c4["arch.joint_positions"].split(",")] == [0.25, 0.5, 0.75],
      f"case from numpy values: {c4.to_dict()}")
named = voussoir.sweep(case.copy(arch__voussoirs=11), alpha=[0],
                       dynamic__damping_model=["joint", "rayleigh"], jobs=2)
check(list(named["dynamic.damping_model"]) == ["joint", "rayleigh"], f"named axis: {named}")

# 3. A sweep over three directions in three threads equals three runs one at a time (the
# sweep's runs stop at the collapse, as `voussoir sweep`'s).
alphas = [0, 45, 90]
table = voussoir.sweep(case, alpha=alphas, jobs=3)
check(list(table["support.alpha_deg"]) == alphas, f"table {table}")
for a, row in zip(alphas, table.to_dict("records")):
    one = voussoir.run(case, support__alpha_deg=a, dynamic__fall_s=0, history=False)
    check(row["status"] == one.status == "collapse", f"alpha {a}: {row['status']}")
    check(row["delta_u_mm"] == one.collapse.delta_mm and
          row["first_limit_mm"] == one.first_limit.delta_mm and
          row["hinges_at_collapse"] == one.hinges_at_collapse,
          f"alpha {a}: sweep {row} differs from the single run {one.collapse}")
    prow = program_json(f"support.alpha_deg={a}", "dynamic.fall_s=0")["collapse"]
    check(close(row["delta_u_mm"], prow["delta_mm"]), f"alpha {a}: the program's delta_u")
    sd = (math.cos(math.radians(a)), math.sin(math.radians(a)))  # the direction's split
    check(close(row["dz_over_L_pct"], 100 * row["delta_u_mm"] * sd[0] / case.span_mm, 1e-12) or
          a == 90, f"alpha {a}: dz/L")
    check(close(row["dx_over_L_pct"], 100 * row["delta_u_mm"] * sd[1] / case.span_mm, 1e-12) or
          a == 0, f"alpha {a}: dx/L")

# Runs in threads at once give what each gives alone (the library keeps no state between
# runs; ARPACK's, which is process-wide, is taken in turns: src/model/modal.c). Big arches, so
# that the runs overlap: before that lock, two threads crashed in ARPACK's dsaupd.
big = case.copy(arch__voussoirs=600, dynamic__fall_s=0)
alone = voussoir.run(big, history=False).collapse.delta_mm
for _ in range(3):
    both = voussoir.sweep(big, alpha=[0, 0], jobs=2)
    check(list(both["delta_u_mm"]) == [alone, alone], f"two threads: {list(both['delta_u_mm'])}, "
          f"alone {alone}")

# 4. Ctrl-C: SIGINT during a long run stops it at its next state with KeyboardInterrupt (from
# the sample function: VS_ERR_STOPPED), well before its end; the next run is unaffected.
long_case = case.copy(arch__voussoirs=1000)
t0 = time.perf_counter()
voussoir.run(long_case, dynamic__fall_s=0, history=False)
t_full = time.perf_counter() - t0
threading.Timer(0.1 * t_full, os.kill, (os.getpid(), signal.SIGINT)).start()
t0 = time.perf_counter()
try:
    voussoir.run(long_case)
    check(False, "SIGINT did not stop the run")
except KeyboardInterrupt as e:
    t_stop = time.perf_counter() - t0
    check("stopped by Ctrl-C" in str(e), f"message {e}")
check(t_stop < 0.6 * t_full, f"stopped after {t_stop:.3f} s of a {t_full:.3f} s run")
again = voussoir.run(case)
check(again.collapse.delta_mm == res.collapse.delta_mm, "a run after the interrupt differs")
# In a sweep: the waiting thread gets KeyboardInterrupt, which stops the runs under way in
# the pool's threads at their next state and starts none of the others (four runs of t_full on
# two threads would take twice t_full).
threading.Timer(0.1 * t_full, os.kill, (os.getpid(), signal.SIGINT)).start()
t0 = time.perf_counter()
try:
    voussoir.sweep(long_case, alpha=[0, 10, 20, 30], jobs=2)
    check(False, "SIGINT did not stop the sweep")
except KeyboardInterrupt:
    t_stop = time.perf_counter() - t0
check(t_stop < 0.8 * t_full, f"sweep stopped after {t_stop:.3f} s (one run: {t_full:.3f} s)")
check(threading.active_count() == 1, f"threads left: {threading.enumerate()}")
# The same from another thread: a stop event ends the run, status stopped.
stop = threading.Event()
threading.Timer(0.1 * t_full, stop.set).start()
part = voussoir.run(long_case, stop=stop)
check(part.status == "stopped" and part.collapse is None, f"stop event: {part}")

# 5. Monte Carlo in threads equals the program's samples.csv (same case, seed, samples).
mc_case = case.copy(arch__voussoirs=11, imperfections__kn_cov=0.3)
mc = voussoir.montecarlo(mc_case, samples=4, seed=7, jobs=2)
mc_ini = os.path.join(out, "mc.ini")
with open(mc_ini, "w") as f:
    f.write("[arch]\nvoussoirs = 11\n[imperfections]\nkn_cov = 0.3\n")
subprocess.run([prog, "montecarlo", mc_ini, "--samples", "4", "--seed", "7", "-q", "-o",
                os.path.join(out, "mc")], check=True, capture_output=True)
pd = voussoir.tables.pandas()
prog_mc = pd.read_csv(os.path.join(out, "mc", "samples.csv"), comment="#", keep_default_na=False)
check(list(prog_mc.columns) == list(mc.columns), f"columns {list(prog_mc.columns)}")
for a, b in zip(mc.to_dict("records"), prog_mc.to_dict("records")):
    for k in mc.columns:
        x, y = a[k], b[k]
        same = close(float(x), float(y)) if isinstance(x, float) else str(x) == str(y)
        check(same, f"montecarlo sample {a['sample']}: {k} = {x!r} in process, {y!r} by the "
              "program")

# 6. A record as an xarray Dataset: the arrays of the program's record, units in attributes.
rec = os.path.join(out, "ref.h5")
voussoir.cli.run(case_path, record=rec)
ds = voussoir.record_to_xarray(rec)
with voussoir.open_record(rec) as r:
    check(np.array_equal(ds["delta"].values, r.series("delta").values), "xarray delta")
    check(ds["delta"].attrs["units"] == "m" and ds["right_Fz"].attrs["units"] == "N", "units")
    check(ds.attrs["status"] == r.status, "status")
print("python in process: ok")
