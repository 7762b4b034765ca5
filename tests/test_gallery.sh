#!/usr/bin/env bash
# The gallery: every examples/*.py but the pvpython one runs as its docstring says, the package
# in place (PYTHONPATH), the library beside the program, and writes a PDF of as many pages as
# figures it saves (its "/Type /Page" objects), each in a few seconds.
# usage: test_gallery.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
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
cd "$tmp"
declare -A pages=([seed_domain]=1 [pointed_arch]=2 [fragility]=3 [load_after_settlement]=2)
n=0
for ex in "$src"/examples/*.py; do
  name=$(basename "$ex" .py)
  [ "$name" = paraview_record ] && continue # pvpython's: tests/test_paraview.sh runs it
  [ -n "${pages[$name]:-}" ] || { echo "FAIL: $name.py is not in this test's list"; exit 1; }
  start=$(date +%s%N)
  "${run[@]}" $py "$ex" "$name.pdf" >"$name.out"
  sed 's/^/  /' "$name.out"
  head -c 5 "$name.pdf" | grep -q '%PDF-' || { echo "FAIL: $name.pdf is not a PDF"; exit 1; }
  got=$(grep -a -c '/Type /Page\b' "$name.pdf" || true)
  [ "$got" -eq "${pages[$name]}" ] ||
    { echo "FAIL: $name.pdf has $got pages, want ${pages[$name]}"; exit 1; }
  ms=$((($(date +%s%N) - start) / 1000000))
  echo "$name.py: $name.pdf, $got page(s), $ms ms"
  n=$((n + 1))
done
[ $n -eq ${#pages[@]} ] || { echo "FAIL: ran $n examples, want ${#pages[@]}"; exit 1; }
echo "gallery: ok"
