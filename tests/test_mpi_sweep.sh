#!/usr/bin/env bash
# voussoir sweep on 3 MPI ranks (rank 0 hands out the runs) writes the same summary as one
# process with its forked workers: summary.csv and summary.h5 equal but for the runs' wall
# times (compared through h5dump with the wall_s member left out), and every run's record and
# JSON in place. usage: test_mpi_sweep.sh MPIEXEC VOUSSOIR SOURCE_DIR
set -euo pipefail
mpiexec="$1" bin="$2" src="$3"
dir="$(mktemp -d /tmp/vs_mpi_sweep_XXXXXX)"
trap 'rm -rf "$dir"' EXIT
args=("$src/runs/reference.ini" --set arch.voussoirs=21 --alpha 0,45,90 --kn 3,10 -q)
nax=2 runs=6
# CI runs as root; --oversubscribe: 3 ranks on a 2-core machine
"$mpiexec" --oversubscribe --allow-run-as-root -np 3 "$bin" sweep "${args[@]}" -o "$dir/mpi" >"$dir/mpi.out"
"$bin" sweep "${args[@]}" -j 2 -o "$dir/one" >/dev/null
grep -q "on 2 processes" "$dir/mpi.out" || { cat "$dir/mpi.out"; echo "expected 2 worker ranks"; exit 1; }
wall=$((nax + 10)) # run, the axes, status, first limit, delta_u, dz, dx, hinges, mode, snaps, wall_s
cut -d, --complement -f "$wall" "$dir/mpi/summary.csv" >"$dir/mpi.csv"
cut -d, --complement -f "$wall" "$dir/one/summary.csv" >"$dir/one.csv"
cmp "$dir/mpi.csv" "$dir/one.csv"
# h5dump prints one member per line after "(i): {", in the order of their offsets: run, the
# axes, status, mode, hinges, error, first limit, delta_u, dz, dx, wall_s, snaps
strip() { h5dump -d /summary -m %.17g "$1" | awk -v w=$((nax + 10)) \
  '/^ *\([0-9]+\): \{/ {i = 0; print; next} {i++; if (i != w) print}' | tail -n +2; }
strip "$dir/mpi/summary.h5" >"$dir/mpi.dump"
strip "$dir/one/summary.h5" >"$dir/one.dump"
grep -q '"wall_s"' "$dir/mpi.dump" # the type lists it: the member left out is the value only
diff "$dir/mpi.dump" "$dir/one.dump"
n="$(grep -c ',collapse,' "$dir/mpi.csv")"
[ "$n" -eq "$runs" ] || { echo "expected $runs collapses, got $n"; exit 1; }
for r in $(seq -f %04g 1 "$runs"); do
  [ -s "$dir/mpi/run_$r.h5" ] && [ -s "$dir/mpi/run_$r.json" ] || { echo "run $r: no record or JSON"; exit 1; }
done
echo "PASS: 3 MPI ranks and one process give the same sweep summary"
