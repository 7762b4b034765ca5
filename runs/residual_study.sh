#!/usr/bin/env bash
# Study (b) of issue 28: the residual capacity of the reference specimen after a support movement.
# The right support settles (alpha = 0) or spreads (alpha = 90) by hold_mm and is held; then a
# point load at quarter span (1 N on the extrados at x = L/4) grows to collapse (analysis.type
# = load; the load path through its peak, docs/model.md "The live load's path"). Two sweeps over
# analysis.hold_mm, at k_n = 3 N/mm^3 (the case's); prints a markdown table (the one in
# docs/studies.md) and writes out/residual_study.csv.
# usage: runs/residual_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set analysis.type=load --set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
"$bin" sweep "$here/reference.ini" "${load[@]}" --alpha 0 --vary analysis.hold_mm=0:80:10 \
  -o "$out_dir/residual_settle" -q
"$bin" sweep "$here/reference.ini" "${load[@]}" --alpha 90 --vary analysis.hold_mm=0:18:2 \
  -o "$out_dir/residual_spread" -q
/usr/bin/python3 - "$out_dir" <<'PY'
import csv, json, math, os, sys
out = sys.argv[1]
rows = []
for name, what in (("residual_settle", "settlement"), ("residual_spread", "spreading")):
    d = os.path.join(out, name)
    for r in csv.DictReader(open(os.path.join(d, "summary.csv"))):
        j = json.load(open(os.path.join(d, "run_%04d.json" % int(r["run"]))))
        ld = j["load"]
        rows.append((what, float(r["analysis.hold_mm"]), r["load_factor"], ld["first_peak"],
                     ld["end"], ld["mechanism"], int(r["snaps"]), ld["cause"]))
with open(os.path.join(out, "residual_study.csv"), "w") as f:
    w = csv.writer(f)
    w.writerow(["movement", "hold_mm", "load_factor", "first_peak", "end", "snaps",
                "mechanism"])
    for m, h, lf, fp, end, mech, snaps, cause in rows:
        w.writerow([m, h, lf, fp, end, snaps, mech])
def num(v):
    v = float(v) if v not in (None, "") else math.nan
    return "–" if math.isnan(v) else "%.3f" % v
print("| movement | hold (mm) | hold / L | load factor | first peak | snaps before | mechanism |")
print("|---|---|---|---|---|---|---|")
for m, h, lf, fp, end, mech, snaps, cause in rows:
    note = mech if end not in ("held_limit",) else cause.split(",")[0].replace("the arch ", "")
    print("| %s | %g | %.2f %% | %s | %s | %d | %s |" % (m, h, 100 * h / 532.2, num(lf), num(fp),
                                                     snaps, note))
PY
echo "table: $out_dir/residual_study.csv" >&2
