#!/usr/bin/env bash
# voussoir.figures (matplotlib) on real runs, the package in place (PYTHONPATH), the library
# beside the program.
# usage: test_python_figures.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 cc=$3
py=/usr/bin/python3
# shellcheck source=python_run.sh
. "$(dirname "$0")/python_run.sh"
python_runner "$cc" "${4:-}"
python_needs cffi numpy pandas h5py matplotlib
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$src/python" VOUSSOIR="$vs" MPLBACKEND=Agg
mkdir "$tmp/figs"
"${run[@]}" $py "$src/tests/python_figures_check.py" "$src/runs/reference.ini" "$tmp/figs"
