#!/usr/bin/env bash
# The cost of a mortared reference run against the dry one (issue 29: at most twice): CPU seconds
# of the process (user + sys), median of REPEAT runs (default 5), settlement (alpha = 0), k_n = 3
# N/mm^3, --no-record (each stops at its collapse): the dry reference, then f_t = 0.25, 0.5, 1,
# 2, 3, 4, 5 kPa with the softening ending at 0.2 mm (G_f = f_t x 0.1 mm), as runs/mortar_study.sh;
# the snaps end at rest (the default; docs/mortar.md "Cost").
# Prints each one's seconds, delta_u, IDA steps and Newton iterations (quasi-static, dynamic),
# its ratio to the dry run's, and the IDA steps and ratio with the ringing criterion
# (dynamic.ring_periods = 1, an option).
# usage: runs/mortar_bench.sh [REPEAT]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
repeat="${1:-5}"
ref="$here/reference.ini"
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
cpu_once() { # args...: CPU seconds (user + sys) of one run
  local t TIMEFORMAT='%3U %3S'
  t="$({ time "$bin" run "$@" --no-record -q >/dev/null 2>&1; } 2>&1 || true)"
  awk '{print $1 + $2}' <<<"${t##*$'\n'}"
}
base=""
printf '%-10s %9s %12s %10s %10s %10s %7s %10s %10s\n' "f_t kPa" "CPU s" "delta_u mm" "IDA steps" \
  "QS Newton" "IDA Newton" ratio "ring: IDA" "ring: ratio"
for ft in 0 0.00025 0.0005 0.001 0.002 0.003 0.004 0.005; do
  args=("$ref" --set joints.tensile_MPa="$ft" --set joints.gf_N_mm="$(awk -v f="$ft" 'BEGIN {printf "%.10g", f * 0.1}')")
  s="$(for ((i = 0; i < repeat; i++)); do cpu_once "${args[@]}"; done | median)"
  j="$("$bin" run "${args[@]}" --no-record -q --json 2>/dev/null || true)"
  [ -n "$base" ] || base="$s"
  rest=("${args[@]}" --set dynamic.ring_periods=1)
  s0="$(for ((i = 0; i < repeat; i++)); do cpu_once "${rest[@]}"; done | median)"
  j0="$("$bin" run "${rest[@]}" --no-record -q --json 2>/dev/null || true)"
  printf '%-10s %9.3f %12s %10s %10s %10s %7.2f %10s %10.2f\n' "$(awk -v f="$ft" 'BEGIN {print f * 1000}')" \
    "$s" "$(jcollapse delta_mm "$j")" "$(jnum dynamic_steps "$j")" "$(jnum newton_iterations "$j")" \
    "$(jnum dynamic_newton_iterations "$j")" "$(awk -v a="$s" -v b="$base" 'BEGIN {print a / b}')" \
    "$(jnum dynamic_steps "$j0")" "$(awk -v a="$s0" -v b="$base" 'BEGIN {print a / b}')"
done
