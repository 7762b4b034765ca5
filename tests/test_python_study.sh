#!/usr/bin/env bash
# voussoir.calibrate (against `voussoir calibrate`) and voussoir.Case.from_blocks (a Python-built
# arch against the keyed one and closed forms), in process, the package in place.
# usage: test_python_study.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 cc=$3
py=/usr/bin/python3
# shellcheck source=python_run.sh
. "$(dirname "$0")/python_run.sh"
python_runner "$cc" "${4:-}"
python_needs cffi numpy pandas h5py
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$vs" calibrate "$src/runs/reference.ini" --target-dz-pct 16.5 >"$tmp/cal.txt" 2>&1
export PYTHONPATH="$src/python" VOUSSOIR="$vs"
"${run[@]}" $py "$src/tests/python_study_check.py" "$src/runs/reference.ini" "$tmp/cal.txt"
