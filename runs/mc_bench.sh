#!/usr/bin/env bash
# Monte Carlo benchmark: SAMPLES (default 1000) imperfect reference arches (k_n = 3 N/mm^3,
# alpha = 0, joint k_n CoV 0.2 and faces of 0.01 mm) on all cores with forked workers, wall time
# printed; then 60 samples on 1, 2 and 3 MPI ranks (rank 0 only hands out work, so 3 ranks are 2
# workers) when mpirun is there. Not a test: timings depend on the machine.
# usage: runs/mc_bench.sh [SAMPLES]   (VOUSSOIR=..., OUT_DIR=... override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
samples="${1:-1000}"
imp=(--set imperfections.kn_cov=0.2 --set imperfections.face_mm=0.01 --seed 1 -q)
t0="$(date +%s.%N)"
"$bin" montecarlo "$here/reference.ini" --samples "$samples" "${imp[@]}" -o "$out_dir/mc_bench" >/dev/null
awk -v a="$t0" -v b="$(date +%s.%N)" -v n="$samples" -v j="$(nproc)" \
  'BEGIN {printf "%d samples on %d processes: %.1f s wall (%.3f s per sample)\n", n, j, b - a, (b - a) / n}'
grep -E '^(collapses|failed|mean_delta_u_over_L|cov_delta_u|q05_delta_u_over_L),' "$out_dir/mc_bench/statistics.csv"
if command -v mpirun >/dev/null; then
  for np in 1 2 3; do
    t0="$(date +%s.%N)"
    mpirun --oversubscribe --allow-run-as-root -np "$np" "$bin" montecarlo "$here/reference.ini" \
      --samples 60 "${imp[@]}" -o "$out_dir/mc_bench_mpi$np" >/dev/null
    awk -v a="$t0" -v b="$(date +%s.%N)" -v np="$np" \
      'BEGIN {printf "60 samples on %d MPI rank(s): %.1f s wall\n", np, b - a}'
  done
fi
