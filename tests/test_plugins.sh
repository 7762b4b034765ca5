#!/usr/bin/env bash
# The program loads HDF5, cairo and MPI only for the commands that need them: `voussoir --version`
# and `voussoir run CASE --no-record` load none of them (the dynamic linker's own list of what it
# loads, LD_DEBUG=files, which names every object at start-up and at dlopen), a run with a
# record loads the record plugin and HDF5 and writes a record that `voussoir plot` (cairo) draws;
# a sweep that mpirun did not start loads no MPI (a build with MPI loads its MPI plugin under
# mpirun only: tests/test_mpi_*.sh).
# A missing or broken plugin: one line naming the file, exit 1, nothing written.
# usage: test_plugins.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
exe=$1 src=$(cd "$2" && pwd)
bindir=$(cd "$(dirname "$exe")" && pwd)
ref=$src/runs/reference.ini
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# "$@" under LD_DEBUG=files; the objects it loaded (their file names, one a line) in $tmp/loaded
# and its exit status in $rc
loaded() {
  set +e
  LD_DEBUG=files "$@" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  set -e
  sed -n 's/.*file=\([^ ]*\) .*/\1/p' "$tmp/err" | sort -u >"$tmp/loaded"
}
expect_not_loaded() { # what pattern...
  local what=$1
  shift
  for p in "$@"; do
    grep -q "$p" "$tmp/loaded" && fail "$what loaded $p: $(grep "$p" "$tmp/loaded" | tr '\n' ' ')"
  done
  return 0
}
expect_loaded() {
  local what=$1
  shift
  for p in "$@"; do grep -q "$p" "$tmp/loaded" || fail "$what did not load $p"; done
}

loaded "$exe" --version
[ $rc -eq 0 ] || fail "--version: exit $rc"
grep -q 'libvoussoir\.so' "$tmp/loaded" || fail "LD_DEBUG=files lists nothing: $(head -3 "$tmp/err")"
expect_not_loaded "--version" libhdf5 libcairo libvoussoir-record libvoussoir-plot libmpi \
  libvoussoir-mpi

loaded "$exe" run "$ref" --no-record -q --json
[ $rc -eq 0 ] || fail "run --no-record: exit $rc: $(grep -v '^ *[0-9]*:' "$tmp/err")"
grep -q '"collapse": *{' "$tmp/out" || fail "run --no-record: no collapse"
expect_not_loaded "run --no-record" libhdf5 libcairo libvoussoir-record libvoussoir-plot libmpi \
  libvoussoir-mpi

# with a record: the record plugin and HDF5, still no cairo; the record is complete
loaded "$exe" run "$ref" -q --set dynamic.fall_s=0 -o "$tmp/r.h5"
[ $rc -eq 0 ] || fail "run -o: exit $rc: $(grep -v '^ *[0-9]*:' "$tmp/err")"
expect_loaded "run -o" libhdf5 libvoussoir-record
expect_not_loaded "run -o" libcairo libvoussoir-plot
grep -q "^record   $tmp/r.h5" "$tmp/out" || fail "run -o: no record line: $(cat "$tmp/out")"
[ -s "$tmp/r.xmf" ] || fail "run -o: no XDMF sidecar"
# the arch pictures (the charts' python3 left out: exit status 3, test_plot_charts runs them)
loaded env VOUSSOIR_PYTHON=/nonexistent/python3 "$exe" plot "$tmp/r.h5" -o "$tmp/pics"
[ $rc -eq 3 ] || fail "plot: exit $rc: $(grep -v '^ *[0-9]*:' "$tmp/err")"
expect_loaded "plot" libhdf5 libcairo libvoussoir-plot
[ -s "$tmp/pics/arch_reference.png" ] && [ -s "$tmp/pics/plots.json" ] || fail "plot: no pictures"
loaded "$exe" sweep "$ref" --alpha 0 --set arch.voussoirs=11 --first-limit -j 1 -o "$tmp/sw0" -q
[ $rc -eq 0 ] || fail "sweep: exit $rc: $(grep -v '^ *[0-9]*:' "$tmp/err")"
expect_loaded "sweep" libvoussoir-record
expect_not_loaded "sweep" libmpi libvoussoir-mpi

# Plugins missing or broken: a library directory holding the core library alone, found first
# (LD_LIBRARY_PATH); the program looks for its plugins next to the core library it loaded.
lib=$tmp/lib
mkdir "$lib"
cp -L "$bindir/libvoussoir.so.4" "$lib/"
export LD_LIBRARY_PATH=$lib
nothing_written() { # what, then the paths that must not exist
  local what=$1
  shift
  for p in "$@"; do [ -e "$p" ] && fail "$what wrote $p"; done
  return 0
}
refused() { # what, the file it must name, then the command
  local what=$1 file=$2
  shift 2
  set +e
  "$@" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  set -e
  [ $rc -eq 1 ] || fail "$what: exit $rc, expected 1: $(cat "$tmp/err")"
  grep -q "cannot load $file" "$tmp/err" || fail "$what: the error does not name $file: $(cat "$tmp/err")"
  [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "$what: more than one line: $(cat "$tmp/err")"
}
"$exe" run "$ref" --no-record -q --first-limit >/dev/null || fail "run --no-record needs a plugin"
refused "run -o, no record plugin" "$lib/libvoussoir-record.so.4" \
  "$exe" run "$ref" -q -o "$tmp/m.h5" --csv "$tmp/m.csv"
nothing_written "run -o" "$tmp/m.h5" "$tmp/m.h5.part" "$tmp/m.h5.lock" "$tmp/m.xmf" "$tmp/m.csv"
refused "plot, no plugins" "$lib/libvoussoir-record.so.4" "$exe" plot "$tmp/r.h5" -o "$tmp/p2"
refused "sweep, no record plugin" "$lib/libvoussoir-record.so.4" \
  "$exe" sweep "$ref" --alpha 0 -o "$tmp/sw" -q
nothing_written "plot, sweep" "$tmp/p2" "$tmp/sw"

echo "this is not a library" >"$lib/libvoussoir-record.so.4"
refused "run -o, a broken record plugin" "$lib/libvoussoir-record.so.4" \
  "$exe" run "$ref" -q -o "$tmp/m.h5"
nothing_written "run -o" "$tmp/m.h5" "$tmp/m.h5.part" "$tmp/m.xmf"

cp -L "$bindir/libvoussoir-record.so.4" "$lib/"
cp -L "$bindir/libvoussoir.so.4" "$lib/libvoussoir-plot.so.4" # a library, not the plugin
refused "plot, a library without the table" "$lib/libvoussoir-plot.so.4" \
  "$exe" plot "$tmp/r.h5" -o "$tmp/p3"
grep -q "no vs_plot_plugin_table" "$tmp/err" || fail "plot: $(cat "$tmp/err")"
refused "montecarlo, the same" "$lib/libvoussoir-plot.so.4" \
  "$exe" montecarlo "$ref" --samples 2 -o "$tmp/mc" -q
nothing_written "plot, montecarlo" "$tmp/p3" "$tmp/mc"

# a build with MPI: started by mpirun (its environment says so) without the MPI plugin next to
# the core library: refused before anything is run
if [ -e "$bindir/libvoussoir-mpi.so.4" ]; then
  refused "sweep under mpirun, no MPI plugin" "$lib/libvoussoir-mpi.so.4" \
    env OMPI_COMM_WORLD_SIZE=1 "$exe" sweep "$ref" --alpha 0 -o "$tmp/sw1" -q
  nothing_written "sweep under mpirun" "$tmp/sw1/run_0001.h5"
fi
echo "plugins: ok"
