#!/usr/bin/env bash
# voussoir montecarlo on 3 MPI ranks (rank 0 hands out the samples) writes the same summary as
# one process with its forked workers: samples.csv and statistics.csv byte for byte, summary.h5
# by h5diff; and a study killed on one process and resumed on 3 ranks (rank 0 reads the journal
# and hands out only the samples missing) writes that summary too.
# usage: test_mpi_montecarlo.sh MPIEXEC VOUSSOIR SOURCE_DIR
set -euo pipefail
mpiexec="$1" bin="$2" src="$3"
dir="$(mktemp -d /tmp/vs_mpi_XXXXXX)"
trap 'rm -rf "$dir"' EXIT
args=("$src/runs/reference.ini" --set arch.voussoirs=21 --set imperfections.kn_cov=0.3
      --set imperfections.face_mm=0.002 --set imperfections.angle_cov=0.02 --samples 7 --seed 5 -q)
# CI runs as root; --oversubscribe: 3 ranks on a 2-core machine
"$mpiexec" --oversubscribe --allow-run-as-root -np 3 "$bin" montecarlo "${args[@]}" -o "$dir/mpi"
"$bin" montecarlo "${args[@]}" -j 2 -o "$dir/one"
cmp "$dir/mpi/samples.csv" "$dir/one/samples.csv"
cmp "$dir/mpi/statistics.csv" "$dir/one/statistics.csv"
h5diff "$dir/mpi/summary.h5" "$dir/one/summary.h5"
n="$(grep -c ',collapse,' "$dir/mpi/samples.csv")"
[ "$n" -eq 7 ] || { echo "expected 7 collapses, got $n"; exit 1; }
# killed by itself once 3 samples are journalled (VS_FAULT_KILL_AFTER: no timing), then resumed
rc=0
VS_FAULT_KILL_AFTER=3 "$bin" montecarlo "${args[@]}" -j 2 -o "$dir/res" || rc=$?
[ "$rc" -eq 137 ] || { echo "expected the kill (137), got exit status $rc"; exit 1; }
"$mpiexec" --oversubscribe --allow-run-as-root -np 3 "$bin" montecarlo "${args[@]}" -o "$dir/res" \
  --resume >"$dir/out"
grep -q "3 of them from the journal" "$dir/out" || { cat "$dir/out"; exit 1; }
cmp "$dir/res/samples.csv" "$dir/one/samples.csv"
cmp "$dir/res/statistics.csv" "$dir/one/statistics.csv"
echo "PASS: 3 MPI ranks and one process give the same summary, also resumed under MPI"
