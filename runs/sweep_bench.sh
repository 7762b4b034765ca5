#!/usr/bin/env bash
# Sweep benchmark: the seed domain (alpha 0:45:5,60,75,90 x k_n 3, 48, runs to collapse with
# records) and the same 26 cases made cheap (to the first limit point, 21 voussoirs, where the
# cost of starting a case shows), each on -j 2, wall and CPU time (user + system of every
# process) with the load average. Given OLD (another voussoir binary, e.g. a build of an earlier
# commit), it times OLD and this build alternately, REPEAT times (default 2), and checks that
# both give the same table (all columns but the wall times). Not a test: timings depend on the
# machine. usage: runs/sweep_bench.sh [OLD]   (VOUSSOIR=..., OUT_DIR=..., REPEAT=... override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
old="${1:-}" repeat="${REPEAT:-2}"
load() { cut -d' ' -f1-3 /proc/loadavg; }
# timed LABEL CMD...: runs CMD (stdout dropped), prints LABEL with wall and CPU seconds
timed() {
  local label="$1" l0 t
  shift
  l0="$(load)"
  TIMEFORMAT='%R %U %S'
  t="$( { time "$@" >/dev/null; } 2>&1 | tail -1)"
  read -r wall user sys <<<"$t"
  awk -v l="$label" -v w="$wall" -v u="$user" -v s="$sys" -v a="$l0" -v b="$(load)" \
    'BEGIN {printf "%-34s %6.1f s wall %6.1f s CPU   load %s -> %s\n", l, w, u + s, a, b}'
}
domain=(--alpha 0:45:5,60,75,90 --kn 3,48 -j 2 -q)
light=("${domain[@]}" --first-limit --set arch.voussoirs=21)
bins=("$bin")
[ -n "$old" ] && bins=("$old" "$bin")
for i in $(seq "$repeat"); do
  for b in "${bins[@]}"; do
    name="new"; [ "$b" = "$old" ] && name="old"
    timed "domain, $name" "$b" sweep "$here/reference.ini" "${domain[@]}" -o "$out_dir/sweep_bench_${name}_domain" || true
    timed "domain to the first limit, $name" "$b" sweep "$here/reference.ini" "${light[@]}" -o "$out_dir/sweep_bench_${name}_light" || true
  done
done
if [ -n "$old" ]; then
  for s in domain light; do # wall_s is column 12 (run, 2 axes, status, 4 results, hinges, mode, snaps)
    if cmp -s <(cut -d, --complement -f12 "$out_dir/sweep_bench_old_$s/summary.csv") \
              <(cut -d, --complement -f12 "$out_dir/sweep_bench_new_$s/summary.csv"); then
      echo "$s: old and new give the same table"
    else
      echo "$s: the tables DIFFER"
    fi
  done
fi
