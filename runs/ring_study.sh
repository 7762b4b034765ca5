#!/usr/bin/env bash
# The ringing criterion of mortared arches (dynamic.ring_periods; docs/mortar.md "Cost") against
# the rest criterion alone (ring_periods = 0) and against a tighter version of itself (4
# periods): the reference specimen over the seed's directions alpha = 0:45:5, 60, 75, 90 deg,
# f_t = 0.25 to 10 kPa with G_f = f_t x 0.1 mm (as runs/mortar_study.sh), ring_periods = 0
# (the default), 1, 2 and 4, to collapse (--no-record). Prints, for each f_t: the largest
# difference of delta_u from the rest criterion's and from the 2- and 4-period criterion's, the
# runs whose first crack, hinges at the collapse (joints and sides) or mode differ, the snaps the
# ringing ended, the vibration energy those left against the cracking energy, and the IDA steps
# (sum over the directions) of each criterion. Writes out/ring/runs.csv.
# usage: runs/ring_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
jobs=2
if [ "${1:-}" = "-j" ]; then jobs=$2; fi
mkdir -p "$out_dir/ring"
list="$out_dir/ring/list"
: >"$list"
for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do
  for ft in 0.00025 0.0005 0.001 0.002 0.005 0.01; do
    for p in 0 1 2 4; do echo "$a $ft $p" >>"$list"; done
  done
done
export bin ref="$here/reference.ini" dir="$out_dir/ring"
xargs -P "$jobs" -L 1 bash -c '
  a=$0 ft=$1 p=$2
  gf=$(awk -v f="$ft" "BEGIN { printf \"%.10g\", f * 0.1 }")
  "$bin" run "$ref" --alpha "$a" --no-record -q --json --set joints.tensile_MPa="$ft" \
    --set joints.gf_N_mm="$gf" --set dynamic.ring_periods="$p" >"$dir/run-$a-$ft-$p.json" || true
' <"$list"
"${PYTHON:-/usr/bin/python3}" - "$out_dir/ring" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
alphas = (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90)
fts = ("0.00025", "0.0005", "0.001", "0.002", "0.005", "0.01")
periods = ("0", "1", "2", "4")
def load(a, ft, p):
    try:
        j = json.load(open(os.path.join(d, f"run-{a}-{ft}-{p}.json")))
    except (OSError, ValueError):
        return None
    c = j.get("collapse") or {}
    hs = sorted(c.get("hinges", []), key=lambda h: h["joints"][0])
    fc = j.get("first_crack") or {}
    e = j.get("energy") or {}
    return dict(du=c.get("delta_mm"), hinges=" ".join(f"{'-'.join(map(str, h['joints']))}-{h['side']}" for h in hs),
                mode=j.get("mode") or "-", crack=(fc.get("delta_mm"), fc.get("joint"), fc.get("side")),
                steps=j["stats"]["dynamic_steps"], rings=e.get("ringing_snaps", 0),
                ring_J=e.get("ringing_J", 0.0), cracking=e.get("cracking_J") or 0.0,
                balance=e.get("balance_error_rel"), status=j["status"])
R = {(a, ft, p): load(a, ft, p) for a in alphas for ft in fts for p in periods}
bad = [k for k, r in R.items() if r is None or r["du"] is None]
if bad:
    print("runs without a collapse:", bad)
def diff(p, q):
    """Per f_t: max |delta_u_p - delta_u_q| (mm) and the runs (alpha) whose first crack, hinges
    or mode differ."""
    out = {}
    for ft in fts:
        dmax, where = 0.0, []
        for a in alphas:
            x, y = R[a, ft, p], R[a, ft, q]
            if x is None or y is None or x["du"] is None or y["du"] is None:
                where.append(f"{a}?")
                continue
            dmax = max(dmax, abs(x["du"] - y["du"]))
            if x["crack"] != y["crack"] or x["hinges"] != y["hinges"] or x["mode"] != y["mode"]:
                where.append(str(a))
        out[ft] = (dmax, where)
    return out
kpa = lambda ft: f"{float(ft) * 1e3:g}"
pairs = (("1", "0"), ("1", "2"), ("1", "4"), ("4", "0"))
D = {pq: diff(*pq) for pq in pairs}
print("ring_periods = 1 (an option) against the rest criterion alone (0, the default) and against 2 and 4")
print("periods, and 4 against 0: the largest |d delta_u| (mm) over the 13 directions, and the")
print("directions whose first crack, hinges at the collapse or mode differ (none: all agree):\n")
print("| f_t (kPa) | " + " | ".join(f"{p} vs {q}" for p, q in pairs) + " |")
print("|---" * (len(pairs) + 1) + "|")
for ft in fts:
    cell = lambda x: f"{x[0]:.4f} ({', '.join(x[1]) if x[1] else 'none'})"
    print(f"| {kpa(ft)} | " + " | ".join(cell(D[pq][ft]) for pq in pairs) + " |")
print("\nIDA steps (sum over the 13 directions), snaps ended by their ringing, and the vibration")
print("energy they left (sum, mJ) against the energy dissipated by cracking (sum, mJ), ring_periods = 1:\n")
print("| f_t (kPa) | steps, 0 | steps, 1 | steps, 2 | steps, 4 | snaps rung out | vibration left (mJ) | cracking (mJ) | worst balance |")
print("|---|---|---|---|---|---|---|---|---|")
for ft in fts:
    s = {p: sum(R[a, ft, p]["steps"] for a in alphas if R[a, ft, p]) for p in periods}
    one = [R[a, ft, "1"] for a in alphas if R[a, ft, "1"]]
    print(f"| {kpa(ft)} | {s['0']} | {s['1']} | {s['2']} | {s['4']} | {sum(r['rings'] for r in one)} | "
          f"{sum(r['ring_J'] for r in one) * 1e3:.4f} | {sum(r['cracking'] for r in one) * 1e3:.3f} | "
          f"{max(r['balance'] for r in one):.1e} |")
with open(os.path.join(d, "runs.csv"), "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["alpha_deg", "ft_MPa", "ring_periods", "delta_u_mm", "first_crack", "hinges", "mode",
                "dynamic_steps", "ring_settles", "ring_J", "cracking_J", "status"])
    for (a, ft, p), r in R.items():
        if r:
            w.writerow([a, ft, p, r["du"], r["crack"], r["hinges"], r["mode"], r["steps"], r["rings"],
                        r["ring_J"], r["cracking"], r["status"]])
PY
