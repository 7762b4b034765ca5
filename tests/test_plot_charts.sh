#!/usr/bin/env bash
# voussoir plot's charts, drawn by matplotlib (python3 -m voussoir.figures, run by the program
# with the package beside it): a run's curves and hinges, a load run's load-deflection curve, a
# sweep's domain and sensitivity, a Monte Carlo study's fragility, convergence and hinge
# histogram, each as PNG, PDF and SVG; the figures' data against the files read with h5py and
# the JSON (tests/plot_charts_check.py); without python3 the arch pictures and exit status 3.
# usage: test_plot_charts.sh VOUSSOIR SOURCE_DIR CC [sanitize (a sanitizer build)]
set -euo pipefail
vs=$1 src=$2 cc=$3
py=/usr/bin/python3
# shellcheck source=python_run.sh
. "$(dirname "$0")/python_run.sh"
python_runner "$cc" "${4:-}"
python_needs cffi numpy h5py matplotlib
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ref=$src/runs/reference.ini
"$vs" run "$ref" -q --set dynamic.fall_s=0 -o "$tmp/ref.h5" >/dev/null
load=(--set analysis.type=load --set load.kind=point --set load.x_mm=150 --set load.value_N=1000)
"$vs" run "$ref" -q --json "${load[@]}" -o "$tmp/load.h5" >"$tmp/load.json"
"$vs" sweep "$ref" --alpha 0,20,90 --kn 3,48 -j 2 -q -o "$tmp/sw" >/dev/null
"$vs" montecarlo "$ref" --samples 16 --seed 5 --set imperfections.kn_cov=0.3 \
  --set dynamic.fall_s=0 -j 2 -q -o "$tmp/mc" >/dev/null
for f in ref.h5 load.h5 sw/summary.h5 mc/summary.h5; do
  out=$tmp/$(echo "$f" | tr / _)_plots
  st=0
  # no PYTHONPATH: the program finds the package beside it (build/python)
  env -u PYTHONPATH VOUSSOIR_PYTHON=$py "$vs" plot "$tmp/$f" -o "$out" >"$tmp/plot.log" 2>&1 || st=$?
  [ "$st" -eq 0 ] || { cat "$tmp/plot.log"; echo "FAIL: voussoir plot $f: exit $st"; exit 1; }
done
# a python3 without matplotlib (or none): the arch pictures, the reason, exit status 3
st=0
VOUSSOIR_PYTHON=/nonexistent/python3 "$vs" plot "$tmp/ref.h5" -o "$tmp/nopy" >/dev/null 2>"$tmp/err" || st=$?
[ "$st" -eq 3 ] && [ -f "$tmp/nopy/arch_collapse.png" ] && [ ! -e "$tmp/nopy/curves.png" ] &&
  grep -q "no charts" "$tmp/err" ||
  { cat "$tmp/err"; echo "FAIL: without python3: exit $st (want 3, the arch pictures, no charts)"; exit 1; }
st=0
VOUSSOIR_PYTHON=/nonexistent/python3 "$vs" plot "$tmp/sw/summary.h5" -o "$tmp/nopy_sw" >/dev/null 2>&1 || st=$?
[ "$st" -eq 3 ] || { echo "FAIL: a sweep without python3: exit $st, not 3"; exit 1; }
export PYTHONPATH="$src/python" VOUSSOIR="$vs" MPLBACKEND=Agg
"${run[@]}" $py "$src/tests/plot_charts_check.py" "$tmp" "$ref"
