"""Every command on every shape (tests/test_commands_shapes.sh): the outputs it wrote into DIR
checked against what follows independently from the case (closed forms, rigid motion, the
blocks' masses), not against the program's earlier output.
usage: /usr/bin/python3 commands_shapes_check.py DIR SHAPE..."""
import csv
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

out, shapes = sys.argv[1], sys.argv[2:]
SPAN, RISE, ALPHA = 600.0, 250.0, math.radians(30.0)
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
        print("FAIL:", msg)


def shoelace(q):
    return 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])


def areas_ok(shape, what, areas, exact):
    """Curved edges are drawn as chords: the polygon falls short of the block by the circular
    segments (under 1 % at these turns), never over it; a blocks file's polygons are exact."""
    lo = 1 - 1e-6 if shape == "file" else 0.99
    r = np.asarray(areas) / np.asarray(exact)
    check(np.all(r > lo) and np.all(r < 1 + 2e-6), f"{shape}: {what}: area / (mass / rho / b) "
          f"in [{r.min():.6f}, {r.max():.6f}], expected in ({lo}, 1]")


def slab(text, f):
    """An XDMF HDF DataItem 'file:/path|start:stride:count:dims' (or a whole dataset)."""
    m = re.match(r"\s*([^:]+):(/[^|]+)(?:\|(.*))?", text)
    ds = f[m.group(2)]
    if m.group(3) is None:
        return ds[()]
    start, stride, count, _ = [list(map(int, p.split())) for p in m.group(3).split(":")]
    idx = tuple(slice(s, s + st * c, st) for s, st, c in zip(start, stride, count))
    return ds[idx]


def check_xdmf(shape, h5):
    """The sidecar's block polygons, as ParaView reads them: at every listed row each block's
    area equals its mass over density and depth (rigid blocks keep their area as they move)."""
    xmf = h5[:-3] + ".xmf"
    text = open(xmf).read()
    text = text.replace('<xi:include xpointer="tb"/>', "").replace("xi:include", "include")
    text = re.sub(r'<!DOCTYPE[^>]*>', "", text)
    text = text.replace('xmlns:xi="http://www.w3.org/2001/XInclude"', "")
    root = ET.fromstring(text)
    with h5py.File(h5, "r") as f:
        conn = f["geometry/block_connectivity"][()]
        g = f["geometry"]
        depth = g["joint_depth"][0]
        rho = f["parameters/arch"].attrs["density_kg_m3"]
        exact = g["block_mass"][()] / rho / depth
        grids = [gr for gr in root.iter("Grid") if gr.get("Name") == "blocks"]
        check(len(grids) >= 2, f"{shape}: {len(grids)} block grids in the sidecar")
        worst = []
        for gr in grids[:: max(1, len(grids) // 10)] + grids[-1:]:
            pts = slab(gr.find("Geometry/DataItem").text, f).reshape(-1, 2).astype(float)
            worst.append([shoelace(pts[c]) for c in conn])
        worst = np.array(worst)
        areas_ok(shape, "XDMF polygons (every listed row)", worst.min(0), exact)
        areas_ok(shape, "XDMF polygons (every listed row, largest)", worst.max(0), exact)


def table(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return [dict(zip(rows[0], r)) for r in rows[1:]], rows[0]


def check_travel(shape, what, row, delta, L):
    """The supports' travel columns at the collapse: the left support fixed, the right one moved
    by delta along alpha = 30 deg; dz/L and dx/L (when the table has them) of the same."""
    want = {"left_dx_mm": 0.0, "left_dz_mm": 0.0, "right_dx_mm": delta * math.sin(ALPHA),
            "right_dz_mm": delta * math.cos(ALPHA)}
    for k, v in want.items():
        check(abs(float(row[k]) - v) <= 1e-9 * max(1.0, delta), f"{shape}: {what}: {k} = "
              f"{row[k]}, expected {v}")
    if "dz_over_L_pct" in row:
        check(abs(float(row["dz_over_L_pct"]) - 100 * want["right_dz_mm"] / L) < 1e-7,
              f"{shape}: {what}: dz_over_L_pct {row['dz_over_L_pct']} (L = {L} mm)")


runs = {}
for s in shapes:
    j = json.load(open(os.path.join(out, f"{s}.json")))
    runs[s] = j
    # run: a collapse, normalised by the intrados span the case gives (a file's: its own)
    check(j["status"] == "collapse", f"{s}: run: {j['status']} {j['error']}")
    check(abs(j["span_mm"] - SPAN) < 1e-9 * SPAN, f"{s}: span {j['span_mm']}")
    if s not in ("pointed", "file"):
        check(abs(j["rise_mm"] - RISE) < 1e-9 * RISE, f"{s}: rise {j['rise_mm']}")
    c = j["collapse"]
    check(abs(c["right"]["dz_mm"] - c["delta_mm"] * math.cos(ALPHA)) < 1e-8 * c["delta_mm"] and
          c["left"]["dx_mm"] == 0 and c["left"]["dz_mm"] == 0, f"{s}: collapse supports {c}")
    h5 = os.path.join(out, f"{s}.h5")
    with h5py.File(h5, "r") as f:
        g = f["geometry"]
        conn, pts = g["block_connectivity"][()], g["block_points"][()]
        rho = f["parameters/arch"].attrs["density_kg_m3"]
        exact = g["block_mass"][()] / rho / g["joint_depth"][0]
        areas_ok(s, "record outlines", [shoelace(pts[q]) for q in conn], exact)
        check(abs(g["span"][()] * 1e3 - SPAN) < 1e-6, f"{s}: record span {g['span'][()]}")
        sup = f["observables/supports/value"][()]
        d = f["observables/delta/value"][()]
        check(np.abs(sup[:, 3] - d * math.sin(ALPHA)).max() < 1e-12 and
              np.abs(sup[:, 4] + d * math.cos(ALPHA)).max() < 1e-12 and
              np.abs(sup[:, :3]).max() == 0, f"{s}: /observables/supports against delta")
    check_xdmf(s, h5)
    # plot: the arch at the collapse, drawn from the record (the charts: test_plot_charts)
    for png in ("arch_collapse.png",):
        p = os.path.join(out, f"{s}_plots", png)
        check(os.path.getsize(p) > 10000, f"{s}: plot: {png}")

    # sweep over a geometry key: each run built with its value (the rise; a pointed arch's
    # follows from its eccentricity, h sqrt(1 + 2 e)), each a finite collapse, its supports'
    # travel as the motion gives it
    rows, cols = table(os.path.join(out, f"{s}_sw", "summary.csv"))
    check(cols[-5:] == ["left_dx_mm", "left_dz_mm", "right_dx_mm", "right_dz_mm", "load_factor"]
          and cols[-6] == "error", f"{s}: sweep columns {cols}")
    for r in rows:
        check(r["status"] == "collapse" and math.isfinite(float(r["delta_u_mm"])),
              f"{s}: sweep run {r['run']}: {r['status']} {r['error']}")
        if r["status"] != "collapse":
            continue
        check_travel(s, f"sweep run {r['run']}", r, float(r["delta_u_mm"]), SPAN)
        rj = json.load(open(os.path.join(out, f"{s}_sw", f"run_{int(r['run']):04d}.json")))
        if "arch.rise_mm" in r:
            check(abs(rj["rise_mm"] - float(r["arch.rise_mm"])) < 1e-9 * RISE,
                  f"{s}: sweep run {r['run']}: rise {rj['rise_mm']} for {r['arch.rise_mm']}")
        if "arch.eccentricity" in r:
            want = SPAN / 2 * math.sqrt(1 + 2 * float(r["arch.eccentricity"]))
            check(abs(rj["rise_mm"] - want) < 1e-9 * want,
                  f"{s}: sweep run {r['run']}: rise {rj['rise_mm']}, expected {want}")
        if "arch.thickness_mm" in r:
            with h5py.File(os.path.join(out, f"{s}_sw", f"run_{int(r['run']):04d}.h5"), "r") as f:
                check(abs(f["geometry/thickness"][()] * 1e3 - float(r["arch.thickness_mm"])) < 1e-9,
                      f"{s}: sweep run {r['run']}: thickness")

    # montecarlo with imperfections drawn on the shape: every sample a collapse (or a failure
    # with its cause), the supports' travel of each collapse from its delta_u
    rows, cols = table(os.path.join(out, f"{s}_mc", "samples.csv"))
    check(cols[-5:-1] == ["left_dx_mm", "left_dz_mm", "right_dx_mm", "right_dz_mm"],
          f"{s}: montecarlo columns {cols}")
    check(len(rows) == 3 and any(r["status"] == "collapse" for r in rows),
          f"{s}: montecarlo: {[(r['status'], r['error']) for r in rows]}")
    for r in rows:
        check(r["status"] == "collapse" or r["error"] != "", f"{s}: sample {r['sample']}")
        if r["status"] == "collapse":
            check_travel(s, f"sample {r['sample']}", r, float(r["delta_u_mm"]), SPAN)
    stats = {r[0]: r[1] for r in csv.reader(open(os.path.join(out, f"{s}_mc", "statistics.csv")))}
    du = [float(r["delta_u_mm"]) for r in rows if r["status"] == "collapse"]
    check(abs(float(stats["mean_delta_u_over_L"]) - 100 * np.mean(du) / SPAN) < 1e-5,
          f"{s}: montecarlo mean delta_u/L {stats['mean_delta_u_over_L']} (L = {SPAN} mm)")

    # the imperfect arch's blocks (thickness, angles) are still consistent with their masses
    if s != "file":
        with h5py.File(os.path.join(out, f"{s}_imp.h5"), "r") as f:
            g = f["geometry"]
            t = f["imperfections/voussoir_thickness"][()]
            check(np.std(t) > 0, f"{s}: imperfect thicknesses not drawn: {t}")
            rho = f["parameters/arch"].attrs["density_kg_m3"]
            exact = g["block_mass"][()] / rho / g["joint_depth"][0]
            areas_ok(s, "imperfect blocks", [shoelace(g["block_points"][()][q])
                                             for q in g["block_connectivity"][()]], exact)

    # calibrate: the k_n it reports gives the target when run
    cal = open(os.path.join(out, f"{s}_cal.txt")).read()
    m = re.search(r"k_n = ([0-9.eE+-]+) N/mm\^3 gives collapse dz/L = ([0-9.eE+-]+) % \(target "
                  r"([0-9.eE+-]+) %", cal)
    check(m is not None, f"{s}: calibrate: {cal[-300:]}")
    if m:
        jc = json.load(open(os.path.join(out, f"{s}_cal.json")))
        dz = jc["collapse"]["dz_over_L_pct"]
        check(abs(dz - float(m.group(3))) <= 0.011, f"{s}: calibrate: k_n {m.group(1)} gives "
              f"{dz} %, target {m.group(3)} %")

# the shape and the same blocks through a file: the same arch (the file's curved edges are
# chords), the same mechanism, collapse within the faceting's share
if "pointed" in runs and "file" in runs:
    a, b = runs["pointed"]["collapse"], runs["file"]["collapse"]
    check(abs(a["delta_mm"] - b["delta_mm"]) < 0.01 * a["delta_mm"],
          f"pointed {a['delta_mm']} mm vs its blocks file {b['delta_mm']} mm")
    sides = lambda c: [(h["side"], h["joints"]) for h in c["hinges"]]
    check(sides(a) == sides(b), f"hinges: pointed {sides(a)}, file {sides(b)}")

# both supports: the left one outward at half the right one's rate (closed form in delta), dz/L
# and dx/L of the relative displacement, as the run's JSON gives them
rows, _ = table(os.path.join(out, "two_sw", "summary.csv"))
for r in rows:
    check(r["status"] == "collapse", f"two supports: sweep run {r['run']}: {r['status']}")
    if r["status"] != "collapse":
        continue
    d, a = float(r["delta_u_mm"]), math.radians(float(r["support.alpha_deg"]))
    want = {"left_dx_mm": d / 2, "left_dz_mm": 0.0, "right_dx_mm": d * math.sin(a),
            "right_dz_mm": d * math.cos(a), "dz_over_L_pct": 100 * d * math.cos(a) / SPAN,
            "dx_over_L_pct": 100 * (d / 2 + d * math.sin(a)) / SPAN}
    for k, v in want.items():
        check(abs(float(r[k]) - v) < 1e-8 * max(1, abs(v)), f"two supports: run {r['run']}: "
              f"{k} = {r[k]}, expected {v}")
    rj = json.load(open(os.path.join(out, "two_sw", f"run_{int(r['run']):04d}.json")))["collapse"]
    check(abs(rj["dx_over_L_pct"] - float(r["dx_over_L_pct"])) < 1e-8, "two supports: JSON dx/L")
mc, _ = table(os.path.join(out, "two_mc", "samples.csv"))
for r in mc:
    if r["status"] == "collapse":
        d = float(r["delta_u_mm"])
        check(abs(float(r["left_dx_mm"]) - d / 2) < 1e-9 * d and
              abs(float(r["dx_u_mm"]) - (d / 2 + d * math.sin(ALPHA))) < 1e-9 * d and
              abs(float(r["dz_u_mm"]) - d * math.cos(ALPHA)) < 1e-9 * d,
              f"two supports: sample {r['sample']}: {r}")
whole = open(os.path.join(out, "two_mc", "samples.csv")).read()
check(open(os.path.join(out, "two_merged", "samples.csv")).read() == whole,
      "two supports: the merged shards differ from the whole study")
check(open(os.path.join(out, "two_merged", "statistics.csv")).read() ==
      open(os.path.join(out, "two_mc", "statistics.csv")).read(), "two supports: merged statistics")
jc = json.load(open(os.path.join(out, "two_cal.json")))["collapse"]
check(abs(jc["dx_over_L_pct"] - 4.0) <= 0.011 and
      abs(jc["dx_over_L_pct"] - 100 * jc["left"]["dx_mm"] / SPAN) < 1e-8,
      f"two supports: calibrate to dx/L 4 %: the run at its k_n gives {jc}")
# a table merged is merged again to the same table (the travel of a sample without a collapse
# written nan, never -nan, which merge refuses)
for name in ("samples.csv", "statistics.csv"):
    check(open(os.path.join(out, "old_merged", name)).read() ==
          open(os.path.join(out, "old_again", name)).read(), f"merged again: {name} differs")
old, cols = table(os.path.join(out, "old_merged", "samples.csv"))
check(cols[-2] == "right_dz_mm" and cols[-1] == "load_factor" and len(old) == 4, f"old table merged: {cols}")

print("commands on shapes:", "FAILED" if failures else "ok", f"({len(shapes)} shapes)")
sys.exit(1 if failures else 0)
