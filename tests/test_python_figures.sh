#!/usr/bin/env bash
# voussoir.figures (matplotlib) on real runs, the package in place (PYTHONPATH), the library
# beside the program.
# usage: test_python_figures.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 cc=$3
py=/usr/bin/python3
# A sanitizer build's library loads into python3 only after the sanitizers' runtimes: they are
# preloaded, without leak detection (the interpreter does not free everything at exit).
run=(env)
if [ "${4:-}" = sanitize ]; then
  asan=$("$cc" -print-file-name=libasan.so) ubsan=$("$cc" -print-file-name=libubsan.so)
  [ -f "$asan" ] && [ -f "$ubsan" ] ||
    { echo "SKIP: $cc does not name its libasan.so and libubsan.so"; exit 77; }
  run=(env LD_PRELOAD="$asan $ubsan" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0")
fi
$py -c "import cffi, numpy, pandas, h5py, matplotlib" 2>/dev/null ||
  { echo "SKIP: $py lacks cffi/numpy/pandas/h5py/matplotlib (.ci/deps installs them)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$src/python" VOUSSOIR="$vs" MPLBACKEND=Agg
mkdir "$tmp/figs"
"${run[@]}" $py "$src/tests/python_figures_check.py" "$src/runs/reference.ini" "$tmp/figs"
