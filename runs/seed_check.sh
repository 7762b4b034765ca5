#!/usr/bin/env bash
# Results of a build on the seed domain (alpha = 0:45:5, 60, 75, 90 deg x k_n = 3, 48 N/mm^3), to
# check that a change meant to be faster left them alone. Runs the 26 points to collapse
# (--no-record --json, 2 at a time) into OUT_DIR, then, given a BASELINE_DIR written the same way
# by another build, compares per point: the collapsing limit point delta_u (relative difference;
# the check asks <= 1e-4), the hinges at collapse (label, joints, side), the mode and its side
# patterns, and, for information, every limit point, every hinge onset, the solver counts and
# how many results are the same in every printed digit.
# Exit status 1 when delta_u moved by more than 1e-4 relative or a mechanism changed anywhere.
# usage: runs/seed_check.sh OUT_DIR [BASELINE_DIR]   (binary: build/voussoir or $VOUSSOIR)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
[ $# -ge 1 ] || { echo "usage: ${0##*/} OUT_DIR [BASELINE_DIR]" >&2; exit 2; }
out="$1"
base="${2:-}"
mkdir -p "$out"
points=()
for kn in 3 48; do
  for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do points+=("$a $kn"); done
done
export bin out here
printf '%s\n' "${points[@]}" | xargs -P 2 -L 1 bash -c \
  '"$bin" run "$here/reference.ini" --alpha "$0" --kn "$1" --no-record -q --json \
     >"$out/run-$0-$1.json" 2>"$out/run-$0-$1.err" || true'
[ -n "$base" ] || { echo "wrote $out (26 runs)"; exit 0; }
"${PYTHON:-/usr/bin/python3}" - "$here" "$base" "$out" <<'EOF'
import os, sys
sys.dont_write_bytecode = True  # nothing written into runs/
sys.path.insert(0, sys.argv[1])
from run_json import collapse_lp, hinges, load as load_json
base, new = sys.argv[2], sys.argv[3]

def load(d, a, kn):
    return load_json(os.path.join(d, f"run-{a}-{kn}.json"))

def mechanism(d):
    return (hinges(d), (d or {}).get("mode"), (d or {}).get("hinge_sides_initial"),
            (d or {}).get("hinge_sides_collapse"))

def rel(x, y):
    return abs(x - y) / max(abs(y), 1e-300)

def worst_list(xs, ys):
    if len(xs) != len(ys):
        return float("inf")
    return max([rel(x, y) for x, y in zip(xs, ys)] or [0.0])

def onsets(d):
    return [h["delta_onset_mm"] for h in (d or {}).get("hinges") or []]

def lps(d):
    return [lp["delta_mm"] for lp in (d or {}).get("limit_points") or []]

def strip(d):  # the whole result but for the wall-clock time
    if isinstance(d, dict):
        return {k: strip(v) for k, v in d.items() if k != "wall_s"}
    return [strip(v) for v in d] if isinstance(d, list) else d

def counts(d):
    s = (d or {}).get("stats") or {}
    return (s.get("newton_iterations"), s.get("dynamic_steps"))

print(f"{'alpha':>5} {'k_n':>4} {'base delta_u':>13} {'new delta_u':>13} {'rel diff':>9} {'LPs':>8}"
      f" {'onsets':>8}  mechanism  counts (base -> new)")
worst, bad, identical = 0.0, [], 0
for kn in (3, 48):
    for a in (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90):
        db, dn = load(base, a, kn), load(new, a, kn)
        lb, ln = collapse_lp(db), collapse_lp(dn)
        r = rel(ln, lb) if lb is not None and ln is not None else (0.0 if lb == ln else float("inf"))
        same = mechanism(db) == mechanism(dn)
        worst = max(worst, r)
        identical += db is not None and strip(db) == strip(dn)
        if r > 1e-4 or not same:
            bad.append(f"alpha {a} k_n {kn}")
        fmt = lambda v: f"{v:13.6f}" if v is not None else f"{'-':>13}"
        print(f"{a:5} {kn:4} {fmt(lb)} {fmt(ln)} {r:9.2e} {worst_list(lps(dn), lps(db)):8.1e}"
              f" {worst_list(onsets(dn), onsets(db)):8.1e}  {'same' if same else 'DIFFERENT':9}"
              f"  {counts(db)} -> {counts(dn)}"
              + ("" if same else f"\n      base {mechanism(db)}\n      new  {mechanism(dn)}"))
print(f"largest relative difference of delta_u: {worst:.2e}; {identical} of 26 results identical"
      " in every printed digit (wall time apart); "
      + ("mechanisms identical" if not bad else "FAILED at " + ", ".join(bad)))
sys.exit(1 if bad else 0)
EOF
