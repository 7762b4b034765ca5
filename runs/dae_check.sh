#!/usr/bin/env bash
# Old against new formulation of the dynamic phase on the seed domain (alpha = 0, 5, ..., 45, 60,
# 75, 90 deg x k_n = 3, 48 N/mm^3): builds the last commit before the DAE (the dynamic phase as an
# ODE in residual form, supports as prescribed kinematics) from this repository's history into a
# temporary directory (git archive, no network), runs both to collapse and prints, per point, the
# collapsing limit point (the last entry of limit_points: where the arch leaves its last stable
# equilibrium) of each, their relative difference and the hinges at collapse (label:joints-side)
# of each; then the largest relative difference.
# usage: runs/dae_check.sh [OLD_COMMIT]   (default 76d0783, the parent of 6cf16d8 "Dynamic phase
# as a semi-explicit index-2 DAE"); the new binary is build/voussoir (or $VOUSSOIR).
set -euo pipefail
source "$(dirname "$0")/lib.sh"
old_commit="${1:-76d0783}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
git -C "$here/.." archive "$old_commit" | tar -x -C "$tmp"
echo "building $old_commit in $tmp ..." >&2
cmake -S "$tmp" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release -DVS_STRICT=OFF >"$tmp/cmake.log" 2>&1 ||
  { cat "$tmp/cmake.log" >&2; exit 1; }
cmake --build "$tmp/build" -j2 --target voussoir >"$tmp/build.log" 2>&1 ||
  { tail -20 "$tmp/build.log" >&2; exit 1; }
old_bin="$tmp/build/voussoir"
mkdir -p "$tmp/out"
for kn in 3 48; do
  for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do
    for which in old new; do
      b="$bin"; [ "$which" = old ] && b="$old_bin"
      (cd "$tmp/out" && "$b" run "$here/reference.ini" --alpha "$a" --kn "$kn" --no-record -q --json \
        >"$tmp/out/$which-$a-$kn.json") || true
    done
  done
done
"${PYTHON:-/usr/bin/python3}" - "$here" "$tmp/out" "$old_commit" <<'EOF'
import os, sys
sys.dont_write_bytecode = True  # nothing written into runs/
sys.path.insert(0, sys.argv[1])
from run_json import collapse_lp as limit, hinges, load as load_json
out, old = sys.argv[2], sys.argv[3]

def load(which, a, kn):
    return load_json(os.path.join(out, f"{which}-{a}-{kn}.json"))

print(f"{'alpha':>5} {'k_n':>4} {'old LP mm':>12} {'new LP mm':>12} {'rel diff':>9}  hinges at collapse"
      f" (old | new)")
worst, worst_at, same, n = 0.0, None, 0, 0
for kn in (3, 48):
    for a in (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90):
        do, dn = load("old", a, kn), load("new", a, kn)
        lo, ln = limit(do), limit(dn)
        rel = abs(ln - lo) / ln if lo is not None and ln is not None else float("nan")
        ho, hn = hinges(do), hinges(dn)
        n += 1
        same += ho == hn
        if rel == rel and rel > worst:
            worst, worst_at = rel, (a, kn)
        fmt = lambda x: f"{x:12.5f}" if x is not None else f"{'none':>12}"
        print(f"{a:5d} {kn:4d} {fmt(lo)} {fmt(ln)} {rel:9.2e}  {ho} | {hn}"
              + ("" if ho == hn else "   <- hinges differ"))
print(f"largest relative difference of the collapsing limit points: {worst:.2e} "
      f"(alpha {worst_at[0]}, k_n {worst_at[1]}); hinges at collapse the same on {same} of {n} "
      f"points (old = {old})")
EOF
