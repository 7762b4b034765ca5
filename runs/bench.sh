#!/usr/bin/env bash
# Benchmark: wall time, equilibria and Newton iterations of runs to the first limit point of
# the reference specimen, alpha = 0 and 90 deg, k_n = 3 and 48 N/mm^3. Each case is run
# REPEAT times (default 20); the median wall time of the path (JSON stats.wall_s) is printed.
# usage: runs/bench.sh [BINARY] [REPEAT]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../build/voussoir}"
repeat="${2:-20}"
[ -x "$bin" ] || { echo "bench: $bin not built (cmake --build build)" >&2; exit 2; }
field() { sed -E "s/.*\"$1\":([-0-9.eE+]+).*/\1/" <<<"$2"; }
printf '%-8s %-10s %14s %12s %8s %10s %12s\n' alpha_deg kn_N_mm3 "limit (mm)" "wall (ms)" steps newton "ms/newton"
for alpha in 0 90; do
  for kn in 3 48; do
    times=()
    for ((i = 0; i < repeat; i++)); do
      out="$("$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" --json -q)"
      times+=("$(field wall_s "$out")")
    done
    med="$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
    lim="$(sed -E 's/.*"first_limit":\{"delta_mm":([-0-9.eE+]+).*/\1/' <<<"$out")"
    steps="$(field steps "$out")"
    newton="$(field newton_iterations "$out")"
    awk -v a="$alpha" -v k="$kn" -v l="$lim" -v w="$med" -v s="$steps" -v n="$newton" \
      'BEGIN {printf "%-8s %-10s %14.4f %12.2f %8d %10d %12.3f\n", a, k, l, 1e3*w, s, n, 1e3*w/n}'
  done
done
