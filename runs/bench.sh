#!/usr/bin/env bash
# Benchmark of the reference specimen, each case run REPEAT times (default 10), median wall time
# of the run (JSON stats.wall_s):
#  1. to the first limit point (quasi-static only), alpha = 0 and 90 deg, k_n = 3 and 48 N/mm^3:
#     wall time, equilibria, Newton iterations, time per iteration;
#  2. to the collapse (quasi-static + dynamic), and the whole loading dynamically at the
#     laboratory rate 0.04 mm/s (about 35 minutes of simulated time): wall time, IDA steps.
#  3. the limit displacement domain (26 runs to collapse) end to end on all cores;
#  4. one run to collapse with 55 to 880 voussoirs: wall time and time per Newton iteration.
# usage: runs/bench.sh [BINARY] [REPEAT]
set -euo pipefail
VOUSSOIR="${1:-${VOUSSOIR:-$(cd "$(dirname "$0")" && pwd)/../build/voussoir}}"
repeat="${2:-10}"
source "$(dirname "$0")/lib.sh"
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
lastfile="$out_dir/bench_last.json"
run_median() { # args...: prints the median wall time; the last run's JSON goes to $lastfile
  local times=() j
  for ((i = 0; i < repeat; i++)); do
    j="$("$bin" run "$here/reference.ini" "$@" --json -q --no-record)"
    times+=("$(jnum wall_s "$j")")
  done
  printf '%s\n' "$j" >"$lastfile"
  printf '%s\n' "${times[@]}" | median
}
echo "1. to the first limit point (quasi-static)"
printf '   %-6s %-6s %12s %10s %7s %7s %10s\n' alpha kn "limit mm" "wall ms" steps newton "ms/newton"
for alpha in 0 90; do
  for kn in 3 48; do
    med="$(run_median --alpha "$alpha" --kn "$kn" --first-limit)"
    last="$(cat "$lastfile")"
    lim="$(sed -E 's/.*"first_limit":\{"delta_mm":([-0-9.eE+]+).*/\1/' <<<"$last")"
    steps="$(jnum steps "$last")"; newton="$(jnum newton_iterations "$last")"
    awk -v a="$alpha" -v k="$kn" -v l="$lim" -v w="$med" -v s="$steps" -v n="$newton" \
      'BEGIN {printf "   %-6s %-6s %12.4f %10.2f %7d %7d %10.3f\n", a, k, l, 1e3*w, s, n, 1e3*w/n}'
  done
done
echo "2. to the collapse"
printf '   %-32s %12s %10s %9s %9s\n' case "delta_u mm" "wall ms" "q-s eq." "IDA steps"
for spec in "quasi-static + dynamic, k_n 3|--kn 3" "quasi-static + dynamic, k_n 48|--kn 48" \
            "dynamic from rest, 0.04 mm/s, k_n 3|--kn 3 --dynamic"; do
  name="${spec%%|*}"; args="${spec#*|}"
  # shellcheck disable=SC2086
  med="$(run_median $args)"
  last="$(cat "$lastfile")"
  du="$(jcollapse delta_mm "$last")"
  awk -v c="$name" -v d="$du" -v w="$med" -v s="$(jnum steps "$last")" -v ds="$(jnum dynamic_steps "$last")" \
    'BEGIN {printf "   %-32s %12.4f %10.1f %9d %9d\n", c, d, 1e3*w, s, ds}'
done
echo "3. the limit displacement domain end to end (26 runs to collapse, runs/domain_study.sh's sweep)"
t0="$(date +%s.%N)"
"$bin" sweep "$here/reference.ini" --alpha 0:45:5,60,75,90 --kn 3,48 -o "$out_dir/bench_domain" -q >/dev/null || true
awk -v a="$t0" -v b="$(date +%s.%N)" -v j="$(nproc)" 'BEGIN {printf "   %.2f s on %d processes\n", b - a, j}'
echo "4. one run to collapse against the voussoir count (same arch and k_n, finer subdivision)"
printf '   %-9s %12s %10s %10s %10s %14s\n' voussoirs "delta_u mm" "wall s" "q-s Newton" "IDA Newton" "ms/iteration"
for nv in 55 110 220 440 880; do
  j="$("$bin" run "$here/reference.ini" --set arch.voussoirs="$nv" --json -q --no-record || true)"
  awk -v n="$nv" -v d="$(jcollapse delta_mm "$j")" -v w="$(jnum wall_s "$j")" -v a="$(jnum newton_iterations "$j")" \
    -v b="$(jnum dynamic_newton_iterations "$j")" \
    'BEGIN {printf "   %-9d %12.4f %10.3f %10d %10d %14.4f\n", n, d, w, a, b, 1e3 * w / (a + b)}'
done
