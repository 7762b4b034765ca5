#!/usr/bin/env bash
# The Python package: pip-installed (offline, Debian's setuptools) into a temporary target and
# used with Debian's python3 (the first python3 on PATH may lack h5py).
# usage: test_python.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
py=/usr/bin/python3
$py -c "import h5py, numpy, matplotlib" 2>/dev/null ||
  { echo "SKIP: $py lacks h5py/numpy/matplotlib (apt-get install python3-h5py python3-matplotlib)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/python" "$tmp/src" # pip builds in place; keep the source tree clean
if $py -m pip --version >/dev/null 2>&1; then
  $py -m pip install --quiet --no-index --no-build-isolation --no-deps --target "$tmp/site" "$tmp/src"
else
  echo "pip absent: using PYTHONPATH"
  cp -r "$tmp/src/voussoir" "$tmp/site"
fi
cd "$tmp"
VOUSSOIR=$vs PYTHONPATH=$tmp/site $py "$src/tests/python_check.py" "$src/runs/reference.ini" "$tmp"
