#!/usr/bin/env bash
# Mortar joints from Python (first_crack, cracking energy, crack events, the record's joint_crack,
# figures.cracks) against the program's JSON, its record read with h5py and the closed form of
# the cracking energy; the package in place (PYTHONPATH), the library beside the program.
# usage: test_python_mortar.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 cc=$3
py=/usr/bin/python3
# shellcheck source=python_run.sh
. "$(dirname "$0")/python_run.sh"
python_runner "$cc" "${4:-}"
python_needs cffi numpy xarray h5py matplotlib
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$src/python" VOUSSOIR="$vs" MPLBACKEND=Agg
"${run[@]}" $py "$src/tests/python_mortar_check.py" "$src/runs/reference.ini" "$tmp"
