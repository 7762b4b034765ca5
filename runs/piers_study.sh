#!/usr/bin/env bash
# The reference specimen on piers against rigid springers (issue 28, study a): alpha = 0:45:5, 60,
# 75, 90 deg at k_n = 3 and 48 N/mm^3 (the seed's directions, as runs/domain_study.sh), runs to
# collapse (--no-record: the collapse is read before the fall), three supports each: the rigid
# springers (no piers), two piers 300 mm high, 150 mm wide, 4 courses (the arch's density, the
# joints' friction at the base), and the same 110 mm wide (the arch's thrust at the springing
# level, ~15 N, over 300 mm against the pier's and half the arch's weight: it stands on its own
# down to about 100 mm). Prints the table docs/studies.md shows: delta_u on each, its ratio to
# the springers', the hinges at the collapse, what the piers did (events: rocking, a course joint
# opening, a base sliding). Writes out/piers/runs.csv.
# usage: runs/piers_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
jobs=2
if [ "${1:-}" = "-j" ]; then jobs=$2; fi
mkdir -p "$out_dir/piers"
list="$out_dir/piers/list"
: >"$list"
for kn in 3 48; do for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do for w in 0 150 110; do
  echo "$a $kn $w" >>"$list"
done; done; done
export bin ref="$here/reference.ini" dir="$out_dir/piers"
xargs -P "$jobs" -L 1 bash -c '
  a=$0 kn=$1 w=$2 p=()
  [ "$w" != 0 ] && p=(--set piers.height_mm=300 --set piers.width_mm="$w" --set piers.courses=4)
  "$bin" run "$ref" --alpha "$a" --kn "$kn" --no-record -q --json "${p[@]}" >"$dir/run-$a-$kn-$w.json" || true
' <"$list"
"${PYTHON:-/usr/bin/python3}" - "$out_dir/piers" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
def load(a, kn, w):
    j = json.load(open(os.path.join(d, f"run-{a}-{kn}-{w}.json")))
    c = j.get("collapse") or {}
    hinges = " ".join(f"{h['label']}:{'-'.join(map(str, h['joints']))}-{h['side']}"
                      for h in c.get("hinges", []))
    ev = (j.get("piers") or {}).get("events", [])
    what = ", ".join(sorted({f"{e['kind']} {e['pier']}" + (f"/{e['course']}" if e['kind'] == 'course_opening' else '')
                             for e in ev})) or "-"
    return c.get("delta_mm"), hinges, what, j["status"]
rows = []
print("| alpha | k_n | delta_u springers (mm) | on piers 150 mm | ratio | on piers 110 mm | ratio | hinges at collapse, springers | on piers 110 mm | piers 110 mm did |")
print("|---|---|---|---|---|---|---|---|---|---|")
for kn in (3, 48):
    for a in (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90):
        r0, r1, r2 = load(a, kn, 0), load(a, kn, 150), load(a, kn, 110)
        f = lambda x: f"{x:.2f}" if x is not None else "-"
        q = lambda x: f"{x / r0[0]:.4f}" if x is not None and r0[0] else "-"
        print(f"| {a} | {kn} | {f(r0[0])} | {f(r1[0])} | {q(r1[0])} | {f(r2[0])} | {q(r2[0])} | {r0[1]} | {r2[1]} | {r2[2]} |")
        rows.append([a, kn, r0[0], r1[0], r2[0], r0[1], r1[1], r2[1], r1[2], r2[2]])
with open(os.path.join(d, "runs.csv"), "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["alpha_deg", "kn_N_mm3", "delta_u_springers_mm", "delta_u_piers150_mm",
                "delta_u_piers110_mm", "hinges_springers", "hinges_piers150", "hinges_piers110",
                "piers150_events", "piers110_events"])
    w.writerows(rows)
PY
