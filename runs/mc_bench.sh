#!/usr/bin/env bash
# Monte Carlo benchmark: SAMPLES (default 1000) imperfect reference arches (k_n = 3 N/mm^3,
# alpha = 0, joint k_n CoV 0.2 and faces of 0.01 mm) on JOBS (default 2) forked workers: wall
# time and CPU time (user + system of every process); then RANK_SAMPLES (default 60) samples on
# 1, 2 and 3 MPI ranks when mpirun is there (one rank runs the samples itself; with more, rank 0
# only hands out work, so 2 ranks are 1 worker and 3 ranks are 2). The load average is printed
# before and after each measurement: on a shared machine the wall times depend on it. Not a
# test: timings depend on the machine.
# usage: runs/mc_bench.sh [SAMPLES] [JOBS]   (VOUSSOIR=..., OUT_DIR=..., RANK_SAMPLES=... override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
samples="${1:-1000}" jobs="${2:-2}" rank_samples="${RANK_SAMPLES:-60}"
imp=(--set imperfections.kn_cov=0.2 --set imperfections.face_mm=0.01 --seed 1 -q)
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
    'BEGIN {printf "%s: %.1f s wall, %.1f s CPU (load average %s before, %s after)\n", l, w, u + s, a, b}'
  last_wall="$wall"
}
echo "machine: $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
timed "$samples samples on $jobs forked workers" \
  "$bin" montecarlo "$here/reference.ini" --samples "$samples" "${imp[@]}" -j "$jobs" -o "$out_dir/mc_bench"
awk -v w="$last_wall" -v n="$samples" 'BEGIN {printf "  %.3f s wall per sample\n", w / n}'
grep -E '^(collapses|failed|mean_delta_u_over_L|cov_delta_u|q05_delta_u_over_L),' "$out_dir/mc_bench/statistics.csv"
if command -v mpirun >/dev/null; then
  for np in 1 2 3; do
    timed "$rank_samples samples on $np MPI rank(s)" \
      mpirun --oversubscribe --allow-run-as-root -np "$np" "$bin" montecarlo "$here/reference.ini" \
      --samples "$rank_samples" "${imp[@]}" -o "$out_dir/mc_bench_mpi$np"
    [ "$np" = 1 ] && one="$last_wall"
    awk -v a="$one" -v b="$last_wall" 'BEGIN {printf "  speed-up against 1 rank: %.2f\n", a / b}'
  done
  cmp -s "$out_dir/mc_bench_mpi1/samples.csv" "$out_dir/mc_bench_mpi3/samples.csv" &&
    echo "  1 and 3 ranks: the same samples.csv"
fi
