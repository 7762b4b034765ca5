#!/usr/bin/env bash
# Cost of a run against the voussoir count, and the seed domain's sweep (runs/bench.sh calls it).
#  1. One run of the reference case to its collapse, --no-record, with 55 to 1760 voussoirs: CPU
#     seconds (user + sys, median of REPEAT runs), the ratio to 55 voussoirs and the ratio a cost
#     linear in the count would give; then what the run did (quasi-static Newton iterations, IDA
#     steps, root events: the physics changes with the count, docs/benchmarks.md) and the CPU per
#     voussoir and solver iteration (flat when each iteration costs the same per voussoir).
#  2. The seed domain (alpha 0:45:5,60,75,90 x k_n 3, 48) by `voussoir sweep -j 2` with its
#     records: wall seconds, the CPU of the sweep and its workers, the load average around it;
#     then the CPU of the same 26 runs one process each without a record (fall_s = 0, as the
#     sweep runs them), summed: the physics plus 26 process start-ups; the rest of the sweep's
#     CPU is its records (and its own work: workers, summary).
# usage: runs/scaling.sh [--quick] [BINARY]   (--quick: 55 to 220 voussoirs, one run each, no domain)
#   REPEAT=N  runs per median (default 5; 1 with --quick)
set -euo pipefail
unset LD_LIBRARY_PATH
quick=0
if [ "${1:-}" = "--quick" ]; then quick=1; shift; fi
VOUSSOIR="${1:-${VOUSSOIR:-$(cd "$(dirname "$0")" && pwd)/../build/voussoir}}"
export VOUSSOIR
source "$(dirname "$0")/lib.sh"
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
repeat="${REPEAT:-$((quick ? 1 : 5))}"
sizes=(55 110 220 440 880 1760)
((quick)) && sizes=(55 110 220)
ref="$here/reference.ini"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
cpu_once() { # args...: CPU seconds (user + sys) of the command and its children
  local t TIMEFORMAT='%3U %3S'
  t="$({ time "$@" >/dev/null 2>&1; } 2>&1 || true)"
  awk '{print $1 + $2}' <<<"${t##*$'\n'}"
}
sized() { (cd "$work" && cpu_once "$bin" run "$ref" -q --no-record --set arch.voussoirs="$1"); }

echo "one run to collapse, --no-record, against the voussoir count (CPU s, median of $repeat)"
printf '  %9s %8s %6s %7s  %9s %9s %7s %8s  %11s\n' voussoirs "CPU s" x55 linear \
  "QS Newton" "IDA steps" roots "delta_u" "us/(N iter)"
c55=""
for nv in "${sizes[@]}"; do
  c="$(for ((i = 0; i < repeat; i++)); do sized "$nv"; done | median)"
  [ "$nv" = 55 ] && c55="$c"
  j="$(cd "$work" && "$bin" run "$ref" --no-record --json --set arch.voussoirs="$nv" 2>/dev/null || true)"
  qn="$(jnum newton_iterations "$j")" ds="$(jnum dynamic_steps "$j")"
  dn="$(jnum dynamic_newton_iterations "$j")" re="$(jnum root_events "$j")"
  du="$(jcollapse delta_mm "$j")"
  awk -v n="$nv" -v c="$c" -v c55="$c55" -v qn="$qn" -v ds="$ds" -v dn="$dn" -v re="$re" \
    -v du="$du" 'BEGIN {
      it = qn + dn
      printf "  %9d %8.3f %6.1f %7.1f  %9d %9d %7d %8s  %11.2f\n", n, c, c / c55, n / 55, qn, ds,
        re, (du == "" || du == "null") ? "-" : sprintf("%.2f", du), (it > 0) ? 1e6 * c / (n * it) : 0 }'
done
((quick)) && exit 0

echo "seed domain: alpha 0:45:5,60,75,90 x k_n 3, 48 (26 runs)"
load0="$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo -)"
t0="$(date +%s.%N)"
cs="$(cpu_once "$bin" sweep "$ref" --alpha 0:45:5,60,75,90 --kn 3,48 -j 2 -o "$work/domain" -q)"
wall="$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN {print b - a}')"
mb="$(du -sm "$work/domain" | cut -f1)"
rm -rf "$work/domain"
load1="$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo -)"
norec=0
for kn in 3 48; do
  for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do
    c="$(cd "$work" && cpu_once "$bin" run "$ref" -q --alpha "$a" --kn "$kn" --set dynamic.fall_s=0 --no-record)"
    norec="$(awk -v s="$norec" -v c="$c" 'BEGIN {print s + c}')"
  done
done
awk -v w="$wall" -v cs="$cs" -v mb="$mb" -v n="$norec" -v l0="$load0" -v l1="$load1" 'BEGIN {
  printf "  sweep -j 2 with records: %.2f s wall, %.2f s CPU (sweep and workers), %d MB written;\n", w, cs, mb
  printf "    load average %s before, %s after (wall = CPU / 2 only on an idle machine)\n", l0, l1
  printf "  the 26 runs without records, one process each: %.2f s CPU (physics and start-ups)\n", n
}'
