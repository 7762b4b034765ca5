"""voussoir.calibrate and voussoir.Case.from_blocks in process (tests/test_python_study.sh).
calibrate: the same runs as `voussoir calibrate` (each k_n and component the program prints) and
its k_n reproduces the target within the tolerance in a run of its own; a target out of reach is
a ValueError naming the scan's range. from_blocks: the reference arch built in Python as
polygons (each voussoir's intrados and extrados arcs as 8 chords, a pier under each springing
face) weighs rho g b times the polygons' area (shoelace, here) as the keyed arch weighs the
annular sector's closed form, and collapses at the keyed arch's displacement with the same
hinges; a copy keeps the temporary blocks file; a bad polygon is a CaseError.
usage: python3 python_study_check.py CASE.ini CALIBRATE_OUTPUT (VOUSSOIR: the program)"""
import math
import os
import re
import sys

import numpy as np

import voussoir

case_path, cal_out = sys.argv[1], sys.argv[2]
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


# --- calibrate ---------------------------------------------------------------------------------
TARGET, TOL = 16.5, 0.01
df = voussoir.calibrate(case_path, TARGET, tol_pct=TOL)
prog = [(float(k), float(v)) for k, v in
        re.findall(r"k_n = (\S+)\s+collapse dz/L = (\S+) %", open(cal_out).read())]
ours = [(float(f"{k:.6g}"), float(f"{v:.4f}")) for k, v in zip(df["kn_N_mm3"], df["dz_over_L_pct"])]
check(ours == prog, f"calibrate: runs {ours}, the program's {prog}")
kn = df.attrs["kn_N_mm3"]
check(df.attrs["converged"] and df.attrs["runs"] == len(df) == len(prog),
      f"calibrate: attrs {df.attrs}")
again = voussoir.run(case_path, joints__kn_N_mm3=kn, dynamic__fall_s=0, history=False)
check(abs(again.collapse.dz_over_L_pct - TARGET) <= TOL,
      f"calibrate: k_n {kn} gives dz/L {again.collapse.dz_over_L_pct} %, target {TARGET} +- {TOL}")
s = df.attrs["sensitivity_pct_per_decade"]
pair = df[df["stage"] == "sensitivity"]["dz_over_L_pct"].to_numpy()
check(len(pair) == 2 and abs(s - (pair[0] - pair[1]) / 0.02) < 1e-12 * abs(s),
      "calibrate: the sensitivity is not the central difference of its two runs")
try:
    voussoir.calibrate(case_path, 60.0, kn_max=10)
    check(False, "calibrate: a target out of reach did not raise")
except ValueError as e:
    check("the scan gives" in str(e), f"calibrate: out of reach: {e}")
print(f"calibrate: k_n = {kn:.6g} N/mm^3 in {len(df)} runs, as the program; dz/L "
      f"{again.collapse.dz_over_L_pct:.4f} % again; sensitivity {s:.4g} % per decade")

# --- from_blocks -----------------------------------------------------------------------------
keyed = voussoir.Case.from_file(case_path)
R, t, emb, n = (keyed["arch.radius_mm"], keyed["arch.thickness_mm"], keyed["arch.embrace_deg"],
                keyed["arch.voussoirs"])
rho, g, b = keyed["arch.density_kg_m3"], keyed["arch.gravity_m_s2"], keyed["arch.depth_mm"]


def arc(r, a0, a1, k):
    return [(r * math.cos(a), r * math.sin(a)) for a in np.linspace(a0, a1, k + 1)]


left, step = math.radians(90 + emb / 2), math.radians(emb) / n
vous = [{"name": f"v{i + 1}", "polygon": np.array(arc(R, left - i * step, left - (i + 1) * step, 8)
                                                  + arc(R + t, left - (i + 1) * step, left - i * step, 8))}
        for i in range(n)]


def pier(a, side):
    pi, pe = (R * math.cos(a), R * math.sin(a)), ((R + t) * math.cos(a), (R + t) * math.sin(a))
    low = min(pi[1], pe[1]) - 40.0
    return {"name": side, "support": side, "polygon": [pi, pe, (pe[0], low), (pi[0], low)]}


blocks = [pier(left, "left")] + vous + [pier(left - n * step, "right")]
built = voussoir.Case.from_blocks(blocks, ring=[x["name"] for x in blocks], base=case_path)
check(built["arch.shape"] == "file" and os.path.isfile(built["arch.blocks_file"]),
      f"from_blocks: shape {built['arch.shape']}, file {built['arch.blocks_file']}")


def shoelace(p):
    p = np.asarray(p, float)
    return 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))


w_poly = rho * g * b * sum(shoelace(v["polygon"]) for v in vous) * 1e-9   # N (mm^3 -> m^3)
w_sector = rho * g * b * math.radians(emb) * ((R + t) ** 2 - R ** 2) / 2 * 1e-9
res = {}
for name, c in (("keys", keyed), ("blocks", built.copy())):  # a copy keeps the blocks file
    r = voussoir.run(c, dynamic__fall_s=0)
    h = r.history
    qs = h["phase"] == 0
    res[name] = (r, h["left_Fz"][qs] + h["right_Fz"][qs])
(rk, wk), (rb, wb) = res["keys"], res["blocks"]
check(np.abs(wk - w_sector).max() <= 1e-9 * w_sector,
      f"keyed arch: weight {wk[0]} N, annular sector {w_sector} N")
check(np.abs(wb - w_poly).max() <= 1e-9 * w_poly,
      f"blocks arch: weight {wb[0]} N, its polygons' {w_poly} N")
check(abs(w_poly - w_sector) <= 1e-5 * w_sector, f"8 chords per arc: {w_poly} N against {w_sector} N")
du_k, du_b = rk.collapse.delta_mm, rb.collapse.delta_mm
check(abs(du_b - du_k) <= 1e-4 * du_k, f"delta_u: blocks {du_b} mm, keys {du_k} mm")
check(rb.hinges_at_collapse == rk.hinges_at_collapse and rb.mode == rk.mode,
      f"hinges: blocks {rb.hinges_at_collapse} ({rb.mode}), keys {rk.hinges_at_collapse} ({rk.mode})")
bad = [dict(x) for x in blocks]
bad[5] = {"name": "v5", "polygon": [[0, 0], [1, 1]]}
try:
    voussoir.Case.from_blocks(bad, ring=[x["name"] for x in blocks], base=case_path).validate()
    voussoir.run(voussoir.Case.from_blocks(bad, ring=[x["name"] for x in blocks], base=case_path))
    check(False, "from_blocks: a two-vertex polygon was taken")
except voussoir.CaseError as e:
    check("polygon" in str(e), f"from_blocks: bad polygon: {e}")
print(f"from_blocks: weight {wb[0]:.6f} N (polygons {w_poly:.6f}, sector {w_sector:.6f}); "
      f"delta_u {du_b:.4f} mm, keys {du_k:.4f} mm; hinges {rb.hinges_at_collapse}")

for m in failures:
    print("FAIL:", m)
print(f"python study: {len(failures)} failures")
sys.exit(1 if failures else 0)
