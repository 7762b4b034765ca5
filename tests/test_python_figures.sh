#!/usr/bin/env bash
# voussoir.figures (matplotlib) on real runs, the package in place (PYTHONPATH), the library
# beside the program.
# usage: test_python_figures.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
py=/usr/bin/python3
$py -c "import cffi, numpy, pandas, h5py, matplotlib" 2>/dev/null ||
  { echo "SKIP: $py lacks cffi/numpy/pandas/h5py/matplotlib (.ci/deps installs them)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$src/python" VOUSSOIR="$vs" MPLBACKEND=Agg
mkdir "$tmp/figs"
$py "$src/tests/python_figures_check.py" "$src/runs/reference.ini" "$tmp/figs"
