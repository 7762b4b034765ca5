#!/usr/bin/env bash
# voussoir plot draws what its titles and labels say: the labels of every arch picture (read
# from plots.json, the data the pictures are drawn from) against the record's /summary/hinges
# for the reference run, a pinned run and an alpha = 90 deg run; the springers (pinned: turned
# with their voussoir, whose joint stays closed) and the scattered thicknesses of the record.
# (The charts' data, matplotlib's, are checked by test_plot_charts.)
# usage: test_plot_data.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
py=/usr/bin/python3
$py -c "import h5py, numpy" 2>/dev/null ||
  { echo "SKIP: $py lacks h5py/numpy (apt-get install python3-h5py)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$vs" run "$src/runs/reference.ini" -q -o "$tmp/ref.h5" >/dev/null
# the reference run falls to rest (its end picture shows the debris); the others stop at the
# collapse, where every label they are checked for is fixed (the fall is most of a run's time)
"$vs" run "$src/runs/pinned.ini" -q --set dynamic.fall_s=0 -o "$tmp/pin.h5" >/dev/null
"$vs" run "$src/runs/reference.ini" --set support.alpha_deg=90 --set dynamic.fall_s=0 -q -o "$tmp/a90.h5" >/dev/null
"$vs" run "$src/runs/reference.ini" --first-limit --set imperfections.thickness_cov=0.1 -q -o "$tmp/thick.h5" >/dev/null
# the arch pictures only: no charts' Python (exit status 3)
for r in ref pin a90 thick; do
  st=0
  VOUSSOIR_PYTHON=/nonexistent/python3 "$vs" plot "$tmp/$r.h5" -o "$tmp/${r}_plots" >/dev/null 2>&1 || st=$?
  [ "$st" -eq 3 ] || { echo "FAIL: voussoir plot $r.h5 without python3: exit $st, not 3"; exit 1; }
done
$py "$src/tests/plot_data_check.py" "$tmp"
