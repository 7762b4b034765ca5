"""Mortar joints from Python (voussoir.Case/run, Record, record_to_xarray, figures.cracks)
against independent paths: the program's JSON (`voussoir run --json`) and its record read with
h5py for the same case, and the closed form of the cracking energy, G_f x the area cracked
through (b, the arch's depth, times the cracked lengths the record ends with; docs/mortar.md).
Also the record's cracking energy against the JSON's, the in-process history's crack lengths
against the record's, and a mortared sweep's and Monte Carlo study's first crack columns
against each run's JSON.
usage: /usr/bin/python3 python_mortar_check.py CASE DIR  (VOUSSOIR = the program)"""
import csv
import json
import math
import os
import subprocess
import sys

import h5py
import numpy as np

import voussoir
import voussoir.cli
import voussoir.figures as vf
import voussoir.study


def check(cond, msg):
    if not cond:
        print("FAIL:", msg)
        sys.exit(1)


def _u(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def close(a, b, rel=1e-8):  # the JSON prints 10 significant digits
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-300)


case_path, out = sys.argv[1], sys.argv[2]
prog = os.environ["VOUSSOIR"]
FT, GF = 0.002, 0.0002  # MPa, N/mm: docs/mortar.md's run (softening ends at 0.2 mm)
SETS = [f"joints.tensile_MPa={FT}", f"joints.gf_N_mm={GF}"]


def program(sets, record=None):
    args = [prog, "run", case_path, "--json", "-q"]
    args += ["-o", record] if record else ["--no-record"]
    for s in sets:
        args += ["--set", s]
    return json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)


# 1. The mortar keys as Case overrides (section__key), read back through the key table.
case = voussoir.Case.from_file(case_path, joints__tensile_MPa=FT, joints__gf_N_mm=GF)
check(case["joints.tensile_MPa"] == FT and case["joints.gf_N_mm"] == GF, "mortar keys")
check(case["joints.cohesion_MPa"] == 0 and case["joints.gc_N_mm"] == 0, "cohesion default 0")
keys = {"joints.cohesion_MPa": 0.001, "joints.gc_N_mm": 0.01, "imperfections.tensile_cov": 0.3,
        "imperfections.gf_cov": 0.2, "imperfections.debonded": 0.25}
c2 = voussoir.Case.from_file(case_path, keys)
check(all(c2[k] == v for k, v in keys.items()), "the other mortar keys, as a dict")
for bad, field in (({"joints__tensile_MPa": -1}, "joints.tensile_MPa"),
                   ({"joints__tensile_MPa": FT, "joints__gf_N_mm": 1e-9}, "joints.gf_N_mm")):
    try:
        voussoir.run(voussoir.Case.from_file(case_path, **bad))
        check(False, f"{bad} accepted")
    except voussoir.CaseError as e:
        check(field in str(e), f"{bad}: the error names {field}: {e}")

# 2. In process against the program's JSON and record of the same case.
res = voussoir.run(case, history=False)
rec_path = os.path.join(out, "mortar.h5")
ref = program(SETS, rec_path)
check(res.mortared, "Result.mortared")
check(res.status == ref["status"], f"status {res.status} / {ref['status']}")
fc, rfc = res.first_crack, ref["first_crack"]
check(fc is not None and rfc is not None, f"first crack {fc} / {rfc}")
check(close(fc.delta_mm, rfc["delta_mm"]) and fc.joint == rfc["joint"] and
      fc.side == rfc["side"], f"first_crack {fc} in process, {rfc} by the program")
check(math.isnan(fc.load_factor) and "load_factor" not in rfc, "no load factor off a load path")
cj = res.energy["cracking_J"]
check(cj > 0 and close(cj, ref["energy"]["cracking_J"]),
      f"cracking_J {cj} in process, {ref['energy']['cracking_J']} by the program")
crack_events = [e for e in res.events if e.kind == "crack_initiated"]
check(crack_events, "crack_initiated events in Result.events")

# 3. The record read with h5py: the event table and the crack history.
with h5py.File(rec_path, "r") as f:
    ev = f["events"][:]
    kinds = [k.decode() if isinstance(k, bytes) else str(k) for k in ev["kind"]]
    h5_cracks = sorted((int(e["joint"]), e["side"].decode() if isinstance(e["side"], bytes)
                        else str(e["side"]), float(e["delta"]))
                       for e, k in zip(ev, kinds) if k == "crack_initiated")
    crack = f["observables/joint_crack/value"][()]
    unit = f["observables/joint_crack/value"].attrs["unit"]
    unit = unit.decode() if isinstance(unit, bytes) else str(unit)
    b = float(f["parameters/arch"].attrs["depth_mm"]) * 1e-3
    t_joint = float(f["parameters/arch"].attrs["thickness_mm"]) * 1e-3  # radial joints: t
py_cracks = sorted((e.joint, e.side, e.delta_mm * 1e-3) for e in crack_events)
check(len(py_cracks) == len(h5_cracks) and
      all(a[:2] == h[:2] and close(a[2], h[2], 1e-12) for a, h in zip(py_cracks, h5_cracks)),
      f"crack events: {len(py_cracks)} in process, {len(h5_cracks)} in the record")
check(unit == "m,m" and crack.ndim == 3 and crack.shape[2] == 2, f"joint_crack {crack.shape} {unit}")
check(bool((np.diff(crack, axis=0) >= 0).all()), "cracks never close (damage is irreversible)")
# The cracking energy (mortared runs only): J, one value per state, never decreasing, ending at
# the JSON's energy.cracking_J.
with h5py.File(rec_path, "r") as f:
    ce = f["observables/energy_cracking/value"][()]
    ce_unit = f["observables/energy_cracking/value"].attrs["unit"]
    ce_unit = ce_unit.decode() if isinstance(ce_unit, bytes) else str(ce_unit)
check(ce_unit == "J" and ce.shape == (crack.shape[0],), f"energy_cracking {ce.shape} {ce_unit}")
check(bool((np.diff(ce) >= 0).all()) and ce[0] >= 0, "the cracking energy never decreases")
check(close(ce[-1], ref["energy"]["cracking_J"]),
      f"energy_cracking ends at {ce[-1]}, the JSON's cracking_J {ref['energy']['cracking_J']}")
# The in-process history's crack lengths, state by state, against the record's (each state the
# program records is a state the run hands its sample function).
hist = voussoir.run(case).history
hc = hist.joint_crack()
check(hc is not None and hc.shape == crack.shape and np.array_equal(hc, crack),
      f"History.joint_crack {None if hc is None else hc.shape} against the record's {crack.shape}")
check(len(hist) == crack.shape[0], "one crack row per state of the history")
with voussoir.open_record(rec_path) as r:
    jc = r.joint_crack()
    check(np.array_equal(jc.values, crack) and jc.columns == ["intrados", "extrados"] and
          jc.unit == "m,m", "Record.joint_crack against h5py")
    rce = r.cracking_energy()
    check(rce is not None and np.array_equal(rce.values, ce) and rce.unit == "J",
          "Record.cracking_energy against h5py")
    rfc2 = r.first_crack()
    check(r.mortared() and rfc2 is not None and rfc2.joint == rfc["joint"] and
          rfc2.side == rfc["side"] and close(rfc2.delta_mm, rfc["delta_mm"]),
          f"Record.first_crack {rfc2} / the JSON's {rfc}")
    check(rfc2 == fc, f"Record.first_crack {rfc2} == Result.first_crack {fc}")
    ds = voussoir.record_to_xarray(r)
    da = ds["joint_crack"]
    check(da.dims == ("state", "joint", "joint_crack_component") and da.attrs["units"] == "m" and
          np.array_equal(da.values, crack) and
          list(da["joint_crack_component"].values) == ["intrados", "extrados"],
          f"xarray joint_crack {da.dims} {da.attrs}")
    fig = vf.cracks(r)
    vf.save(fig, os.path.join(out, "cracks"), ("png", "svg"))
    check(os.path.getsize(os.path.join(out, "cracks.png")) > 0, "cracks.png")

# 4. Bounds in closed form: every point cracked through gave up G_f per unit area, and every
# other point at most that (the process zones, damaged short of cracking through, dissipated
# part of it): G_f (N/mm = 1e3 J/m^2) x b x the lengths cracked through that the record ends
# with <= cracking_J <= G_f x b x every joint's length.
area = b * np.minimum(crack[-1].sum(axis=1), t_joint).sum()
want = GF * 1e3 * area
check(want > 0 and cj >= want * (1 - 1e-9) and cj <= GF * 1e3 * b * t_joint * crack.shape[1],
      f"cracking_J {cj} J, G_f x cracked area {want} J")
print(f"mortar: first crack joint {fc.joint}-{fc.side} at {fc.delta_mm:.4f} mm, "
      f"{len(crack_events)} edges cracked, {cj:.6g} J = G_f x {area * 1e6:.1f} mm^2")

# 5. python3 -m voussoir.figures draws cracks for this record.
paths = vf.charts(rec_path, os.path.join(out, "plots"), ("png",))
check(any(p.endswith("cracks.png") for p in paths), f"charts {paths}")
# and `voussoir plot`, which runs it after the arch pictures.
subprocess.run([prog, "plot", rec_path, "-o", os.path.join(out, "vplot")], check=True,
               capture_output=True, env=dict(os.environ, VOUSSOIR_PYTHON=sys.executable))
check(all(os.path.isfile(os.path.join(out, "vplot", f"cracks.{x}")) for x in ("png", "pdf", "svg")),
      "voussoir plot: cracks.png, .pdf, .svg")

# 6. On a load path (analysis.type = load) the first crack carries the load factor there.
LOAD = {"analysis.type": "load", "load.kind": "point", "load.x_mm": 150, "load.value_N": 1000,
        "joints.tensile_MPa": 0.01, "joints.gf_N_mm": 0.001}
lres = voussoir.run(voussoir.Case.from_file(case_path, LOAD), history=False)
lrec = os.path.join(out, "load.h5")
lref = program([f"{k}={v}" for k, v in LOAD.items()], lrec)
lfc, lrfc = lres.first_crack, lref["first_crack"]
check(lfc is not None and lrfc is not None and "load_factor" in lrfc, f"load: {lfc} / {lrfc}")
check(close(lfc.load_factor, lrfc["load_factor"]) and lfc.joint == lrfc["joint"] and
      lfc.side == lrfc["side"] and close(lfc.delta_mm, lrfc["delta_mm"]),
      f"load: first_crack {lfc} in process, {lrfc} by the program")
with voussoir.open_record(lrec) as r:
    check(close(r.first_crack().load_factor, lrfc["load_factor"]) and r.first_crack() == lfc,
          "load: Record.first_crack")
check(close(lres.energy["cracking_J"], lref["energy"]["cracking_J"]), "load: cracking_J")

# 7. A dry arch: no first crack, no cracking energy, no crack events, no cracks chart.
dry = voussoir.run(voussoir.Case.from_file(case_path), history=False)
check(not dry.mortared and dry.first_crack is None and dry.energy["cracking_J"] == 0.0,
      f"dry: {dry.first_crack} {dry.energy}")
check(not [e for e in dry.events if e.kind == "crack_initiated"], "dry: crack events")
check(voussoir.run(voussoir.Case.from_file(case_path)).history.joint_crack() is None,
      "dry: no crack history")
drec = os.path.join(out, "dry.h5")
dref = program([], drec)
check("first_crack" not in dref and "cracking_J" not in dref["energy"], "dry JSON unchanged")
with h5py.File(drec, "r") as f:
    check("energy_cracking" not in f["observables"], "dry record: no energy_cracking")
with voussoir.open_record(drec) as r:
    check(r.cracking_energy() is None, "dry: Record.cracking_energy() is None")
# Record.tensile_factor() and gf_factor(): /imperfections read with h5py, per joint. The dry
# record's are nominal (1); a scattered run's as drawn: f_t 0 exactly at the debonded joints,
# each law's draws on its own stream (f_t's the same with or without gf_cov), the log of the
# lognormal factors (mean 1, CoV c) with mean -s^2/2 and variance s^2 = ln(1 + c^2); a record
# without the datasets (written before them) gives None.
with voussoir.open_record(drec) as r:
    nj = int(r.parameters()["arch.voussoirs"]) + 1  # the joints: springings included
    check(r.geometry("joint_length").values.shape[0] == nj, "joints: voussoirs + 1")
    for get in (r.tensile_factor, r.gf_factor):
        v = get()
        check(v is not None and v.unit == "1" and np.all(v.values == 1.0) and
              v.values.shape == (nj,), f"dry record's {get.__name__}: {v}")
TCOV, GCOV, DEB = 0.3, 0.2, 0.25
scat = SETS + ["imperfections.seed=7", f"imperfections.tensile_cov={TCOV}",
               f"imperfections.debonded={DEB}", "dynamic.fall_s=0"]
srec, frec = os.path.join(out, "scatter.h5"), os.path.join(out, "scatter_ft.h5")
program(scat + [f"imperfections.gf_cov={GCOV}"], srec)
program(scat, frec)
with h5py.File(srec, "r") as f:
    h5t, h5g = f["imperfections/tensile_factor"][()], f["imperfections/gf_factor"][()]
    units = (f["imperfections/tensile_factor"].attrs["unit"], f["imperfections/gf_factor"].attrs["unit"])
with voussoir.open_record(srec) as r:
    t, g = r.tensile_factor(), r.gf_factor()
check(np.array_equal(t.values, h5t) and np.array_equal(g.values, h5g) and
      t.values.shape == g.values.shape == (nj,) == h5t.shape,
      f"Record factors / h5py: {t.values} {g.values} / {h5t} {h5g}")
check(t.unit == _u(units[0]) and g.unit == _u(units[1]) == "1", f"units {t.unit} {g.unit} / {units}")
with voussoir.open_record(frec) as r:
    t_only, g_only = r.tensile_factor().values, r.gf_factor().values
check(np.array_equal(t_only, t.values) and np.all(g_only == 1.0),
      f"gf_cov leaves f_t's draws: {t_only} / {t.values}, gf {g_only}")
off = t.values == 0.0
check(0 < off.sum() < len(off) and np.all(t.values[~off] > 0) and np.all(g.values > 0) and
      len(np.unique(t.values[~off])) == (~off).sum() and len(np.unique(g.values)) == len(g.values),
      f"debonded joints {off.sum()} of {len(off)}; factors {t.values} {g.values}")
for vals, cov in ((np.log(t.values[~off]), TCOV), (np.log(g.values), GCOV)):
    s2 = math.log(1 + cov * cov)
    check(abs(vals.mean() + s2 / 2) < 4 * math.sqrt(s2 / len(vals)) and
          0.3 * s2 < vals.var(ddof=1) < 2.5 * s2, f"log factors mean {vals.mean()} var "
          f"{vals.var(ddof=1)} / {-s2 / 2} {s2}")
old_rec = os.path.join(out, "old.h5")
with h5py.File(srec, "r") as f, h5py.File(old_rec, "w") as o:
    for k in f:
        f.copy(k, o)
    del o["imperfections/tensile_factor"], o["imperfections/gf_factor"]
with voussoir.open_record(old_rec) as r:
    check(r.tensile_factor() is None and r.gf_factor() is None, "no datasets: None")

# Every joint debonded (imperfections.debonded = 1): a dry arch however strong the mortar, its
# collapse the dry one's; no crack.
deb = voussoir.run(voussoir.Case.from_file(case_path, dict(zip(("joints.tensile_MPa",
                   "joints.gf_N_mm", "imperfections.debonded"), (FT, GF, 1)))), history=False)
check(deb.mortared and deb.first_crack is None and deb.energy["cracking_J"] == 0.0 and
      deb.collapse.delta_mm == dry.collapse.delta_mm, f"all debonded: {deb.first_crack} "
      f"{deb.energy} {deb.collapse.delta_mm} / dry {dry.collapse.delta_mm}")

# 8. A mortared sweep's tables (summary.csv and summary.h5, read back in Python) carry the first
# crack of each run as its JSON's first_crack; the in-process study.sweep the same; a dry
# sweep's tables have none of those columns.
sw = os.path.join(out, "sweep")
table = voussoir.cli.sweep(case_path, sw, {"support.alpha_deg": [0, 45],
                                           "joints.tensile_MPa": [0, FT]},
                           sets={"joints.gf_N_mm": GF}, jobs=2, program=prog)
crack_cols = ["first_crack_mm", "first_crack_joint", "first_crack_side"]
with h5py.File(os.path.join(sw, "summary.h5"), "r") as f:
    h5rows = f["summary"][()]
check(len(table) == 4 and all(c in table[0] for c in crack_cols) and
      all(c in h5rows.dtype.names for c in crack_cols), f"sweep columns {list(table[0])}")
inproc = voussoir.study.sweep(case_path, alpha=[0, 45], joints__tensile_MPa=[0, FT],
                              joints__gf_N_mm=GF, jobs=2)
for row, h in zip(table, h5rows):
    run = int(row["run"])
    with open(os.path.join(sw, f"run_{run:04d}.json")) as f:
        jfc = json.load(f).get("first_crack")
    side = h["first_crack_side"]
    side = side.decode() if isinstance(side, bytes) else str(side)
    ip = inproc[inproc["run"] == run].iloc[0]
    if jfc is None:  # the dry runs of the study (f_t = 0), or no crack
        check(math.isnan(row["first_crack_mm"]) and row["first_crack_joint"] == 0 and
              row["first_crack_side"] == "" and math.isnan(h["first_crack_mm"]) and
              h["first_crack_joint"] == 0 and side == "" and math.isnan(ip["first_crack_mm"]),
              f"sweep run {run}: no first crack, {row}")
    else:
        check(close(row["first_crack_mm"], jfc["delta_mm"]) and
              row["first_crack_joint"] == jfc["joint"] and row["first_crack_side"] == jfc["side"],
              f"sweep run {run}: csv {row} / JSON {jfc}")
        check(close(h["first_crack_mm"], jfc["delta_mm"]) and h["first_crack_joint"] == jfc["joint"]
              and side == jfc["side"], f"sweep run {run}: summary.h5 / JSON {jfc}")
        check(close(ip["first_crack_mm"], jfc["delta_mm"]) and ip["first_crack_joint"] == jfc["joint"]
              and ip["first_crack_side"] == jfc["side"], f"study.sweep run {run} / JSON {jfc}")
check(sum(1 for r in table if r["first_crack_side"]) == 2, "the two mortared runs cracked")
dsw = os.path.join(out, "dry_sweep")
dtable = voussoir.cli.sweep(case_path, dsw, {"support.alpha_deg": [0]}, program=prog)
with h5py.File(os.path.join(dsw, "summary.h5"), "r") as f:
    dnames = f["summary"].dtype.names
check(not any(c in dtable[0] for c in crack_cols) and not any(c in dnames for c in crack_cols) and
      list(dtable[0])[-1] == "load_factor", "a dry sweep's tables as they were")
check(not any(c in voussoir.study.sweep(case_path, alpha=[0]).columns for c in crack_cols),
      "a dry study.sweep as it was")

# 9. A mortared Monte Carlo study (f_t scattered per joint): samples.csv, merge's copy of it,
# summary.h5 and study.montecarlo carry each sample's first crack, that of `voussoir run` of
# the same sample (imperfections.sample = i) by its JSON; a dry study's table has none.
MC = {"joints.tensile_MPa": FT, "joints.gf_N_mm": GF, "imperfections.tensile_cov": 0.3}
mc = os.path.join(out, "mc")
subprocess.run([prog, "montecarlo", case_path, "--samples", "3", "-j", "2", "-q", "-o", mc] +
               sum((["--set", f"{k}={v}"] for k, v in MC.items()), []), check=True,
               capture_output=True)
merged = os.path.join(out, "mc_merged")
subprocess.run([prog, "merge", mc, "-o", merged], check=True, capture_output=True)
with open(os.path.join(mc, "samples.csv"), newline="") as f:
    next(f)
    rows = list(csv.DictReader(f))
with open(os.path.join(merged, "samples.csv"), newline="") as f:
    next(f)
    mrows = list(csv.DictReader(f))
with h5py.File(os.path.join(mc, "summary.h5"), "r") as f:
    h5c, h5j = f["samples/first_crack"][()], f["samples/first_crack_joint"][()]
mcp = voussoir.study.montecarlo(voussoir.Case.from_file(case_path, MC), 3, jobs=2)
check(len(rows) == 3 and list(rows[0])[-3:] == crack_cols and mrows == rows and
      list(mcp.columns)[-3:] == crack_cols, f"montecarlo columns {list(rows[0])}")
for i, row in enumerate(rows):
    jfc = program([f"{k}={v}" for k, v in MC.items()] + [f"imperfections.sample={i}"])["first_crack"]
    check(jfc is not None, f"sample {i} cracks")
    check(close(float(row["first_crack_mm"]), jfc["delta_mm"]) and
          int(row["first_crack_joint"]) == jfc["joint"] and row["first_crack_side"] == jfc["side"],
          f"samples.csv sample {i}: {row} / JSON {jfc}")
    check(close(h5c[i], jfc["delta_mm"] * 1e-3) and
          h5j[i] == jfc["joint"] * (1 if jfc["side"] == "I" else -1), f"summary.h5 sample {i}")
    p = mcp.iloc[i]
    check(close(p["first_crack_mm"], jfc["delta_mm"]) and p["first_crack_joint"] == jfc["joint"]
          and p["first_crack_side"] == jfc["side"], f"study.montecarlo sample {i} / JSON {jfc}")
dmc = os.path.join(out, "mc_dry")
subprocess.run([prog, "montecarlo", case_path, "--samples", "1", "-q", "-o", dmc, "--set",
                "imperfections.kn_cov=0.1"], check=True, capture_output=True)
with open(os.path.join(dmc, "samples.csv")) as f:
    f.readline()
    dhead = f.readline().strip()
check(dhead.endswith(",load_factor"), f"a dry study's samples.csv as it was: {dhead}")
with h5py.File(os.path.join(dmc, "summary.h5"), "r") as f:
    check("first_crack" not in f["samples"], "a dry study's summary.h5 as it was")
print("python_mortar_check: ok")
