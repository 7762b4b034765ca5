#!/usr/bin/env bash
# The Python package in process (libvoussoir through cffi), installed as docs/python.md says: a
# venv with Debian's packages (--system-site-packages), pip offline; the library found beside
# the program ($VOUSSOIR). First the cdef against the headers, then the runs against the program.
# usage: test_python_inprocess.sh VOUSSOIR SOURCE_DIR BUILD_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 build=$3 cc=$4
py=/usr/bin/python3
# shellcheck source=python_run.sh
. "$(dirname "$0")/python_run.sh"
python_runner "$cc" "${5:-}"
python_needs cffi numpy pandas xarray h5py venv ensurepip
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/python" "$tmp/src" # pip builds in place; keep the source tree clean
$py -m venv --system-site-packages "$tmp/venv"
"$tmp/venv/bin/pip" install --quiet --no-index --no-build-isolation --no-deps "$tmp/src"
cd "$tmp"
"$tmp/venv/bin/python" "$src/tests/python_cdef_check.py" "$cc" "$tmp/cdef" -I"$src/include" \
  -I"$build/include"
VOUSSOIR=$vs "${run[@]}" "$tmp/venv/bin/python" "$src/tests/python_inprocess_check.py" "$src/runs/reference.ini" "$tmp"
