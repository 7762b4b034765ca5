"""The charts of `voussoir plot` (matplotlib, voussoir.figures) against the files they are drawn
from, read here with h5py (tests/test_plot_charts.sh): every chart written as PNG, PDF and SVG;
plots.json lists only arch pictures; a run's curves are the record's support forces on the path
without the fall; a sweep's domain points are its summary's collapses, sorted by k_n then alpha
and marked by their modes, its sensitivity delta_u/L each run's delta_u over the span in its own
record; a load run's load-deflection curve is /summary/load/curve, its collapse mark the JSON's
load_factor, the greatest load factor of the path (the peak), also found in process
(Result.load_curve, the collapse Event's load_factor); a Monte Carlo study's fragility agrees with
the probability the program computed in summary.h5 on its own grid, the convergence's last mean
with its statistics, the hinge histogram with its counts.
usage: python3 plot_charts_check.py TMP CASE.ini"""
import json
import math
import os
import sys

import h5py
import numpy as np

import voussoir
from voussoir import figures

tmp, case = sys.argv[1], sys.argv[2]
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


def text(b):
    return b.decode() if isinstance(b, bytes) else str(b)


def lines(fig, i=0):
    return {ln.get_label(): (np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float))
            for ln in fig.axes[i].get_lines()}


# --- the files ----------------------------------------------------------------------------------
WANT = {"ref.h5": ["curves", "hinges"], "load.h5": ["curves", "hinges", "load_deflection"],
        "sw_summary.h5": ["domain", "sensitivity"],
        "mc_summary.h5": ["fragility", "convergence", "hinge_histogram"]}
for src, names in WANT.items():
    d = os.path.join(tmp, src + "_plots")
    for n in names:
        for ext, magic in (("png", b"\x89PNG"), ("pdf", b"%PDF"), ("svg", b"<?xml")):
            p = os.path.join(d, f"{n}.{ext}")
            ok = os.path.isfile(p) and open(p, "rb").read(5).startswith(magic)
            check(ok, f"{src}: {n}.{ext} missing or not a {ext}")
        if os.path.isfile(os.path.join(d, f"{n}.svg")):
            svg = open(os.path.join(d, f"{n}.svg"), "rb").read()
            check(svg.count(b"<text") >= 4, f"{src}: {n}.svg draws its text as paths")
    pj = os.path.join(d, "plots.json")
    if src.startswith(("ref", "load")):
        pics = json.load(open(pj))["pictures"]
        check(pics and all(p["file"].startswith("arch_") for p in pics),
              f"{src}: plots.json lists {[p['file'] for p in pics]}")
    else:
        check(not os.path.exists(pj), f"{src}: a study's plots.json (it has no arch picture)")

# --- a run: the support forces against delta, without the fall -----------------------------------
rec = os.path.join(tmp, "ref.h5")
with h5py.File(rec, "r") as f:
    delta = f["observables/delta/value"][:] * 1e3
    phase = f["observables/phase/value"][:]
    reac = f["observables/reactions/value"]
    cols = text(reac.attrs["columns"]).split(",")
    forces = reac[:]
keep = phase != 2
fig = figures.curves(rec)
got = lines(fig)
for name in ("left_Fx", "left_Fz", "right_Fx", "right_Fz"):
    x, y = got.get(name.replace("_", " "), (np.zeros(0), np.zeros(0)))
    check(np.allclose(x, delta[keep], rtol=1e-12, atol=0) and
          np.array_equal(y, forces[keep, cols.index(name)]),
          f"curves: {name} is not the record's column without the fall")
print(f"curves: 4 forces, {int(keep.sum())} of {len(delta)} rows (the fall left out)")

# --- a sweep: domain and sensitivity -------------------------------------------------------------
sw = os.path.join(tmp, "sw", "summary.h5")
with h5py.File(sw, "r") as f:
    rows = f["summary"][:]
col = sorted(((float(r["joints.kn_N_mm3"]), float(r["support.alpha_deg"])), r) for r in rows
             if text(r["status"]) == "collapse")
check(len(col) == 6, f"{len(col)} of 6 sweep runs collapsed")
table = figures.read_sweep(sw)
fig = figures.domain(table)
got = lines(fig)
for kn in (3.0, 48.0):
    pts = [r for (k, _), r in col if k == kn]
    x, y = got.get(f"k_n = {kn:g} N/mm³", (np.zeros(0), np.zeros(0)))
    check(np.array_equal(x, [r["dz_over_L_pct"] for r in pts]) and
          np.array_equal(y, [r["dx_over_L_pct"] for r in pts]),
          f"domain: the k_n = {kn} line is not the summary's collapses along alpha")
marked = {}
for code, name, _ in figures.MODES:
    x, y = got.get(name, (np.zeros(0), np.zeros(0)))
    for xi, yi in zip(x, y):
        marked[(xi, yi)] = code
for _, r in col:
    m = text(r["mode"])
    check(marked.get((r["dz_over_L_pct"], r["dx_over_L_pct"])) == (m if m in ("I", "II", "III") else ""),
          f"domain: the point of mode {m} is marked {marked.get((r['dz_over_L_pct'], r['dx_over_L_pct']))}")
check({"I", "III"} <= set(marked.values()), f"domain modes {set(marked.values())}: alpha 0 and 90 give I and III")
fig = figures.sensitivity(table)
got = lines(fig)
for kn in (3.0, 48.0):
    pts = [r for (k, _), r in col if k == kn]
    want = []
    for r in pts:  # delta_u over the span of each run's own record
        with h5py.File(os.path.join(tmp, "sw", f"run_{int(r['run']):04d}.h5"), "r") as rf:
            want.append(100.0 * float(r["delta_u_mm"]) / (1e3 * float(rf["geometry/span"][()])))
    x, y = got.get(f"k_n = {kn:g} N/mm³", (np.zeros(0), np.zeros(0)))
    check(np.array_equal(x, [r["support.alpha_deg"] for r in pts]) and
          np.allclose(y, want, rtol=1e-9, atol=0), f"sensitivity: k_n = {kn}: {y} against {want}")
print(f"sweep: domain and sensitivity, {len(col)} collapses, modes {sorted(set(marked.values()))}")

# --- a load run: the load-deflection curve --------------------------------------------------------
lrec = os.path.join(tmp, "load.h5")
js = json.load(open(os.path.join(tmp, "load.json")))
with h5py.File(lrec, "r") as f:
    c = f["summary/load/curve"][:]
    peak_h5 = float(f["summary/load/load_factor"][()])
    ev = f["events"][:]
lam_json = js["load_factor"]
check(js["status"] == "collapse" and lam_json > 0, f"load run: {js['status']}, load_factor {lam_json}")
with voussoir.open_record(lrec) as r:
    lc = r.load_curve()
check(np.array_equal(lc.load_factor, c[:, 0]) and np.array_equal(lc.deflection, c[:, 1]),
      "Record.load_curve is not /summary/load/curve")
check(lc.units["deflection"] == "m" and lc.units["load_factor"] == "1", f"load curve units {lc.units}")
check(abs(lc.peak - lam_json) <= 1e-9 * lam_json and abs(peak_h5 - lam_json) <= 1e-9 * lam_json,
      f"load factor: record {lc.peak}, JSON {lam_json}")
check(abs(c[:, 0].max() - lam_json) <= 1e-9 * lam_json, "the collapse's load factor is not the path's peak")
jc = js["load"]["curve"]
check(np.allclose(jc["load_factor"], c[:, 0], rtol=1e-8) and
      np.allclose(np.asarray(jc["deflection_mm"]) * 1e-3, c[:, 1], rtol=1e-8, atol=1e-15),
      "the JSON's curve differs from the record's")
coll = [e for e in ev if text(e["kind"]) == "collapse"]
check(len(coll) == 1 and abs(coll[0]["load_factor"] - lam_json) <= 1e-8 * lam_json,
      "the record's collapse event does not carry the load factor")
fig = figures.load_deflection(lrec)
got = lines(fig)
x, y = got.get("load path", (np.zeros(0), np.zeros(0)))
check(np.array_equal(x, c[:, 1] / 1e-3) and np.array_equal(y, c[:, 0]),
      "load_deflection: not /summary/load/curve (deflection in mm, load factor)")
marks = [v for k, v in got.items() if k.startswith("collapse")]
check(len(marks) == 1 and abs(marks[0][1][0] - lam_json) <= 1e-9 * lam_json,
      "load_deflection: the collapse mark is not at the JSON's load factor")
check(fig.axes[0].get_ylim()[0] == 0.0, "load_deflection: the load factor axis does not start at 0")
res = voussoir.run(voussoir.Case.from_file(case, analysis__type="load", load__kind="point",
                                           load__x_mm=150, load__value_N=1000))
rl = res.load_curve()
check(abs(res.load_factor - lam_json) <= 1e-9 * lam_json and
      np.allclose(rl.load_factor, c[:, 0], rtol=1e-9) and np.allclose(rl.deflection, c[:, 1], rtol=1e-9, atol=1e-15),
      "in process: the load curve differs from the program's record")
ce = [e for e in res.events if e.kind == "collapse"]
check(len(ce) == 1 and abs(ce[0].load_factor - lam_json) <= 1e-9 * lam_json,
      f"in process: the collapse Event's load_factor {[e.load_factor for e in ce]}, JSON {lam_json}")
check(all(math.isnan(e.load_factor) for e in voussoir.run(case).events),
      "a support run's events carry a load factor")
print(f"load run: lambda = {lam_json:.6g} (JSON, record, in process, the curve's peak), "
      f"{len(c)} equilibria drawn")

# --- a Monte Carlo study ----------------------------------------------------------------------------
mc = os.path.join(tmp, "mc", "summary.h5")
with h5py.File(mc, "r") as f:
    fd, fp = f["fragility/delta"][:] * 1e3, f["fragility/probability"][:]
    mean = float(f["statistics/mean_delta_u_over_L"][()]) * 100.0
    hist = f["hinge_histogram"][:]
rows, span = figures.read_montecarlo(mc)
fig = figures.fragility(rows)
x, y = lines(fig)["P(collapse)"]
check(fig.axes[0].get_ylim() == (0.0, 1.0), "fragility: the probability axis is not 0..1")
# the same grid as the program's (201 points to 1.2 x the largest collapse, below max_mm here)
check(len(x) == len(fd) and np.allclose(x, fd, rtol=1e-12, atol=1e-12) and np.array_equal(y, fp),
      "fragility: the figure's probability differs from summary.h5's")
fig = figures.convergence(rows, span)
m = lines(fig)["mean"][1]
check(span is not None and abs(m[-1] - mean) <= 1e-9 * mean,
      f"convergence: last mean {m[-1]} %, summary.h5's {mean} %")
fig = figures.hinge_histogram(rows, joints=hist.shape[1])
for cont in fig.axes[0].containers:
    label = cont.get_label()
    h = np.array([b.get_height() for b in cont])
    want = hist["ABCDE".index(label), :len(h)]  # [label][joint 1..]
    check(np.array_equal(h, want), f"hinge_histogram: {label} {h} against summary.h5's {want}")
print(f"montecarlo: {len(rows)} samples; fragility on the program's grid, mean {mean:.4g} %, "
      f"hinge counts {int(hist.sum())}")

for msg in failures:
    print("FAIL:", msg)
print(f"plot charts: {len(failures)} failures")
sys.exit(1 if failures else 0)
