"""The Python package against a record and the program (tests/test_python.sh).
usage: /usr/bin/python3 python_check.py CASE DIR  (voussoir importable, VOUSSOIR = the program)"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import voussoir  # noqa: E402


def check(cond, msg):
    if not cond:
        print("FAIL:", msg)
        sys.exit(1)


case, out = sys.argv[1], sys.argv[2]
rec_path = os.path.join(out, "ref.h5")
res = voussoir.cli.run(case, record=rec_path, first_limit=True)
check(res["status"] == "limit_point", f"status {res['status']}")
with voussoir.open_record(rec_path) as r:
    check(r.status == "completed", r.status)
    delta = r.series("delta")
    check(delta.unit == "m", delta.unit)
    # The JSON summary (mm) and the record (m) tell the same first limit point.
    check(abs(r.summary()["first_limit"]["delta"] * 1e3 - res["first_limit"]["delta_mm"]) < 1e-6,
          "first limit point differs between record and JSON")
    # Statics: on every quasi-static row the supports' forces on the arch carry its weight
    # (independent of the solver: the weight comes from the geometry's masses).
    weight = r.geometry("block_mass").values.sum() * r.parameters()["arch.gravity_m_s2"]
    react = r.series("reactions")
    fz = react.column("left_Fz").values + react.column("right_Fz").values
    fx = react.column("left_Fx").values + react.column("right_Fx").values
    qs = r.series("phase").values == 0
    check(react.column("right_Fz").unit == "N", react.unit)
    check(np.abs(fz[qs] - weight).max() < 1e-6 * weight, f"sum Fz {fz[qs].min()} vs W {weight}")
    check(np.abs(fx[qs]).max() < 1e-6 * weight, "horizontal forces do not cancel")
    kinds = [e["kind"] for e in r.events()]
    check("limit_point" in kinds, f"events {kinds}")
    # The blocks' outlines from the positions: the record's frames (float32) at the rows it keeps.
    frames, frame_rows = r.file["xdmf/block_points"][:], r.file["xdmf/block_points_row"][:]
    every = r.block_outlines()
    check(every.shape[0] == len(delta.values) and len(frame_rows) > 0, "outlines: rows")
    check(np.abs(every[frame_rows] - frames).max() < 1e-6, "outlines differ from the frames")
    check(np.array_equal(r.block_outlines(-1), every[-1]), "outlines of one row")
    fig, ax = plt.subplots(1, 2, figsize=(12, 4))
    voussoir.draw_mechanism(r, -1, ax[0])
    voussoir.draw_curves(r, ax[1])
    fig.savefig(os.path.join(out, "record.png"))
table = voussoir.cli.sweep(case, os.path.join(out, "sw"), {"support.alpha_deg": [0, 90]},
                       sets={"arch.voussoirs": 11}, first_limit=True, jobs=2)
check(len(table) == 2 and {row["support.alpha_deg"] for row in table} == {0.0, 90.0}, f"table {table}")
# The domain of a sweep over alpha alone (its table has no k_n column): one line through the
# collapses, in the order of alpha, at the table's own dz/L and dx/L.
table = voussoir.cli.sweep(case, os.path.join(out, "sw_alpha"), {"support.alpha_deg": "90,0"},
                       sets={"arch.voussoirs": 11}, jobs=2)
coll = sorted((r for r in table if r["status"] == "collapse"), key=lambda r: r["support.alpha_deg"])
check(len(coll) == 2, f"alpha sweep: {table}")
lines = voussoir.draw_domain(table).get_lines()
check(len(lines) == 1, f"domain: {len(lines)} lines")
check(list(lines[0].get_xdata()) == [r["dz_over_L_pct"] for r in coll] and
      list(lines[0].get_ydata()) == [r["dx_over_L_pct"] for r in coll], "domain: points")

# Any shape: a pointed arch of 7 voussoirs, both supports moving (the left one outward at half
# the right one's rate, the right one at alpha = 30 deg), and its blocks written to a file.
pointed = os.path.join(out, "pointed.ini")
with open(pointed, "w") as f:
    f.write("[arch]\nshape = pointed\nspan_mm = 600\neccentricity = 0.3\nthickness_mm = 40\n"
            "voussoirs = 7\ndepth_mm = 100\n[joints]\nkn_N_mm3 = 10\n[support]\nalpha_deg = 30\n"
            "rate_mm_s = 0.04\nleft_alpha_deg = 90\nleft_rate_mm_s = 0.02\n")
res = voussoir.cli.run(pointed, record=os.path.join(out, "pointed.h5"))
check(res["status"] == "collapse", f"pointed: {res['status']} {res['error']}")
with voussoir.open_record(os.path.join(out, "pointed.h5")) as r:
    # each support's history against the motion the case prescribes (closed form in delta)
    delta = r.series("delta").values
    sup = r.supports(outward=True)
    check(sup["left"].unit == "m,m,rad" and sup["right"].columns == ["dx", "dz", "rot"], "units")
    a = np.radians(30.0)
    want = {"left": np.stack([0.5 * delta, 0 * delta, 0 * delta], 1),
            "right": np.stack([np.sin(a) * delta, np.cos(a) * delta, 0 * delta], 1)}
    for side in ("left", "right"):
        err = np.abs(sup[side].values - want[side]).max()
        check(err < 1e-12 + 1e-9 * np.abs(delta).max(), f"{side} support: off by {err} m")
    raw = r.supports()
    check(np.array_equal(raw["left"].column("ux").values, -sup["left"].column("dx").values),
          "left support: ux is -dx")
    # the blocks' outlines: areas by the shoelace formula against the record's masses over
    # density and depth; the intrados and extrados are arcs, the outline their chords, so the
    # polygon falls short by the segments (under 1 % at these turns)
    polys = r.reference_outlines()
    mass = r.geometry("block_mass").values
    check(len(polys) == len(mass) == 7, f"{len(polys)} outlines")
    depth = r.parameters()["arch.depth_mm"] * 1e-3
    rho = r.parameters()["arch.density_kg_m3"]
    for b, q in enumerate(polys):
        area = 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])
        exact = mass[b] / rho / depth
        check(0.99 * exact < area <= exact * (1 + 1e-12), f"block {b + 1}: area {area} vs {exact}")
    ax = voussoir.draw_mechanism(r, -1)
    check(len(ax.patches) == 7, f"pointed: {len(ax.patches)} blocks drawn")
    ax.figure.savefig(os.path.join(out, "pointed.png"))
    plt.close(ax.figure)
col = res["collapse"]
d = col["delta_mm"]
check(abs(col["left"]["dx_mm"] - 0.5 * d) < 1e-6 * d and
      abs(col["right"]["dz_mm"] - np.cos(a) * d) < 1e-6 * d, f"collapse supports {col}")
bad = False
try:
    voussoir.cli.run(case, sets={"joints.kn_N_mm3": -1})
except Exception as e:  # bad input: exit 2 raised, naming the key
    bad = "kn_N_mm3" in str(getattr(e, "stderr", ""))
check(bad, "bad input not raised with the key named")
print("python: ok")
