#!/usr/bin/env bash
# Limit displacement domain of three shapes of the reference's span (532.2 mm), thickness 40 mm
# (t/R about 0.14 on the semicircle's centre line: each stands well above its minimum), 55
# voussoirs, normal joints, k_n = 3 and 48 N/mm^3: a pointed arch of eccentricity 0.25 and an
# elliptical arch of the same rise (325.9 mm), and the semicircle, the tallest circular arch of
# that span (266.1 mm: a circle cannot rise higher than half its span, a two-centred pointed arch
# not lower, so a circle of the others' rise does not exist). alpha = 0:45:5, 60, 75, 90 deg, runs
# to collapse (--no-record sweeps: the domain is read before the fall). Prints the table
# docs/results.md shows (delta_u, dz/L and dx/L at the collapse, the sides at the collapse, the
# mode) and writes out/shapes/SHAPE/summary.csv and out/shapes.png.
# usage: runs/shapes_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
mkdir -p "$out_dir/shapes"
common=(--set arch.span_mm=532.2 --set arch.thickness_mm=40 --alpha 0:45:5,60,75,90 --kn 3,48)
declare -A shape=(
  [circular]="--set arch.shape=circular --set arch.rise_mm=266.1"
  [pointed]="--set arch.shape=pointed --set arch.eccentricity=0.25"
  [elliptical]="--set arch.shape=elliptical --set arch.rise_mm=325.9"
)
for s in circular pointed elliptical; do
  # shellcheck disable=SC2086
  "$bin" sweep "$here/reference.ini" "${common[@]}" ${shape[$s]} -q -o "$out_dir/shapes/$s" "$@" ||
    true
done
"${PYTHON:-/usr/bin/python3}" - "$out_dir" <<'EOF'
import csv, os, sys
out = sys.argv[1]
rows = {}
for s in ("circular", "pointed", "elliptical"):
    with open(os.path.join(out, "shapes", s, "summary.csv"), newline="") as f:
        rows[s] = list(csv.DictReader(f))
print("| alpha | k_n | " + " | ".join(f"{s}: delta_u mm (dz/L, dx/L %) mode" for s in rows) + " |")
print("|---|---|" + "---|" * len(rows))
keys = sorted({(float(r["joints.kn_N_mm3"]), float(r["support.alpha_deg"])) for r in rows["circular"]})
def cell(r):
    if r is None or r["status"] != "collapse":
        return (r or {}).get("status", "?")
    return (f'{float(r["delta_u_mm"]):.1f} ({float(r["dz_over_L_pct"]):.2f}, '
            f'{float(r["dx_over_L_pct"]):.2f}) {r["mode"] or "-"}')
for kn, a in keys:
    cells = []
    for s in rows:
        m = [r for r in rows[s] if float(r["joints.kn_N_mm3"]) == kn and float(r["support.alpha_deg"]) == a]
        cells.append(cell(m[0] if m else None))
    print(f"| {a:g} | {kn:g} | " + " | ".join(cells) + " |")
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(figsize=(7, 5.5))
for s, colour in zip(rows, ("k", "tab:red", "tab:blue")):
    for kn, style in ((3.0, "o-"), (48.0, "s--")):
        sel = sorted((r for r in rows[s] if float(r["joints.kn_N_mm3"]) == kn and r["status"] == "collapse"),
                     key=lambda r: float(r["support.alpha_deg"]))
        ax.plot([float(r["dz_over_L_pct"]) for r in sel], [float(r["dx_over_L_pct"]) for r in sel],
                style, color=colour, ms=4, label=f"{s}, $k_n$ = {kn:g}")
ax.set_xlabel("collapse settlement $\\delta_{z,u}/L$ (%)")
ax.set_ylabel("collapse spreading $\\delta_{x,u}/L$ (%)")
ax.set_title("Limit displacement domain: span 532 mm, t = 40 mm, 55 voussoirs")
ax.set_xlim(left=0)
ax.set_ylim(bottom=0)
ax.grid(True, alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(out, "shapes.png"), dpi=110)
print("figure:", os.path.join(out, "shapes.png"))
EOF
