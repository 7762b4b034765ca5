#!/usr/bin/env bash
# The load path's load factor against the limit analysis' as k_n grows (issue 28): the reference
# specimen with 1 N at quarter span (x = L/4), analysis.type = load against analysis.type =
# limit (CLP), k_n = 3 to 1e6 N/mm^3. Each path runs with solver.step_mm = 0.05,
# step_max_mm = 0.25, limit_tol_mm = 5e-5 (finer than the defaults: on stiff joints the peak
# comes within 0.01 to 0.03 mm of deflection, and the defaults' first increment, 0.05 mm, stalls
# from k_n = 3e4 on), and again with the three halved: the change is the table's convergence
# check. The slope of log(gap) against log(k_n) between neighbours and fitted (least squares)
# from k_n = 300 on, against the elastic hinge's -1/3 (docs/model.md, "Against the limit
# analysis"). Prints the markdown table of docs/model.md; writes out/load_convergence.csv.
# usage: runs/load_convergence.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/load_convergence.csv"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
lim="$("$bin" run "$here/reference.ini" "${load[@]}" --set analysis.type=limit --json)"
lim="$(sed -nE 's/.*"limit":\{"load_factor":([-0-9.eE+]+).*/\1/p' <<<"$lim")"
path() { # path KN STEP_MM STEP_MAX_MM LIMIT_TOL_MM: the load factor
  local j
  j="$("$bin" run "$here/reference.ini" "${load[@]}" --kn "$1" --set solver.step_mm="$2" \
       --set solver.step_max_mm="$3" --set solver.limit_tol_mm="$4" --set analysis.type=load \
       --json -q --no-record)"
  /usr/bin/python3 -c 'import json, sys
j = json.loads(sys.stdin.read())
if j["load"]["end"] != "peak":
    sys.exit("load_convergence.sh: k_n %s: the path ended %s: %s" % (sys.argv[1], j["load"]["end"], j["load"]["cause"]))
print(repr(j["load_factor"]))' "$1" <<<"$j"
}
echo "kn_N_mm3,load_factor,load_factor_halved,limit_load_factor,below_pct" >"$csv"
for kn in 3 30 300 1e4 3e4 1e5 3e5 1e6; do
  lf="$(path "$kn" 0.05 0.25 5e-5)" lf2="$(path "$kn" 0.025 0.125 2.5e-5)"
  echo "$kn,$lf,$lf2,$lim,$(/usr/bin/python3 -c "print(100 * (1 - $lf / $lim))")" >>"$csv"
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
kn = [float(r["kn_N_mm3"]) for r in rows]
lf = [float(r["load_factor"]) for r in rows]
lf2 = [float(r["load_factor_halved"]) for r in rows]
lim = float(rows[0]["limit_load_factor"])
gap = [100 * (1 - x / lim) for x in lf]
cell = lambda xs: " | ".join(xs)
slope = lambda i: math.log(gap[i] / gap[i - 1]) / math.log(kn[i] / kn[i - 1])
print("| k_n (N/mm^3) | " + cell(r["kn_N_mm3"] for r in rows) + " |")
print("|---|" + "---|" * len(rows))
print("| load factor (path) | " + cell("%.4f" % x for x in lf) + " |")
print("| steps halved: change | " + cell("%+.4f" % (b - a) for a, b in zip(lf, lf2)) + " |")
print("| below the LP's (%.3f) | " % lim + cell("%.2f %%" % g for g in gap) + " |")
print("| slope from the previous | – | " + cell("%.3f" % slope(i) for i in range(1, len(rows))) + " |")
# least squares of log(gap) on log(k_n) from 300 on (the asymptotic range)
pts = [(math.log(k), math.log(g)) for k, g in zip(kn, gap) if k >= 300]
mx = sum(p[0] for p in pts) / len(pts)
my = sum(p[1] for p in pts) / len(pts)
b = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
# where the gap falls under 1 %: between the neighbours that bracket it, log-log
k1 = next((math.exp(math.log(kn[i - 1]) + math.log(1 / gap[i - 1]) / math.log(gap[i] / gap[i - 1])
                   * math.log(kn[i] / kn[i - 1]))
           for i in range(1, len(rows)) if gap[i - 1] >= 1 > gap[i]), float("nan"))
print("\nlog-log slope from k_n = 300 N/mm^3 on (least squares): %.3f (elastic hinge: -1/3); "
      "the gap falls under 1 %% at k_n = %.3g N/mm^3 (log-log between neighbours)" % (b, k1))
PY
echo "table: $csv" >&2
