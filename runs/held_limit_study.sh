#!/usr/bin/env bash
# The limit analysis of the arch held on its path (issue 28, item 5): the reference specimen
# settles (alpha = 0) by hold_mm, a fraction of its collapse displacement delta_u (each k_n's own
# support run), and is held; the limit analysis of the held arch (analysis.type = load reports it
# as "limit" beside the path's "load_factor") against the load path's load factor for 1 N at
# quarter span, and the held arch's thickness factor, at k_n = 3 (the case's) and 1000 N/mm^3
# (stiff joints: the rigid limit). Prints the markdown table of docs/model.md ("The arch held on
# its path"); writes out/held_limit_study.csv.
# usage: runs/held_limit_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/held_limit_study.csv"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
echo "kn_N_mm3,delta_u_mm,hold_mm,hold_fraction,thickness_factor,limit_load_factor,load_factor,first_peak,mechanism" >"$csv"
for kn in 3 1000; do
  du="$(jnum delta_mm "$(sed -nE 's/.*("collapse":\{[^}]*).*/\1/p' <<<"$("$bin" run "$here/reference.ini" --kn "$kn" --json -q --no-record)")")"
  for f in 0 0.25 0.5 0.75 0.9 0.99; do
    hold="$(/usr/bin/python3 -c "print('%.4f' % ($f * $du))")"
    j="$("$bin" run "$here/reference.ini" "${load[@]}" --kn "$kn" --set analysis.type=load \
        --set analysis.hold_mm="$hold" --json -q --no-record)"
    /usr/bin/python3 - "$kn" "$du" "$hold" "$f" "$j" >>"$csv" <<'PY'
import json, sys
kn, du, hold, f, j = sys.argv[1:6]
j = json.loads(j)
lim = j["limit"] or {}
print(",".join(str(v) for v in (kn, du, hold, f, lim.get("thickness_factor"),
                                 lim.get("load_factor"), j["load_factor"],
                                 j["load"]["first_peak"], j["load"]["mechanism"].replace(",", ";"))))
PY
  done
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, sys
def num(v, fmt="%.3f"):
    try:
        return fmt % float(v)
    except (TypeError, ValueError):
        return "–"
print("| k_n (N/mm^3) | hold / delta_u | hold (mm) | thickness factor (held) | load factor, limit analysis (held) | load factor, path | path / limit |")
print("|---|---|---|---|---|---|---|")
for r in csv.DictReader(open(sys.argv[1])):
    try:
        ratio = "%.3f" % (float(r["load_factor"]) / float(r["limit_load_factor"]))
    except (TypeError, ValueError, ZeroDivisionError):
        ratio = "–"
    print("| %s | %.2f | %s | %s | %s | %s | %s |" % (r["kn_N_mm3"], float(r["hold_fraction"]),
          num(r["hold_mm"], "%.2f"), num(r["thickness_factor"], "%.4f"),
          num(r["limit_load_factor"]), num(r["load_factor"]), ratio))
PY
echo "table: $csv" >&2
