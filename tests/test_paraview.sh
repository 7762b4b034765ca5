#!/usr/bin/env bash
# ParaView (Debian's pvpython, headless under xvfb-run when there is no display) opens a record's
# XDMF sidecar and colours the blocks by a field; skipped, saying why, without pvpython.
# usage: test_paraview.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
command -v pvpython >/dev/null ||
  { echo "SKIP: pvpython not found (Debian: apt-get install paraview python3-paraview xvfb)"; exit 77; }
run=()
if [ -z "${DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null || { echo "SKIP: no display and no xvfb-run (apt-get install xvfb)"; exit 77; }
  run=(xvfb-run -a)
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$vs" run "$src/runs/reference.ini" --first-limit -q -o "$tmp/run.h5" >/dev/null
cd "$tmp"
set +e
"${run[@]}" pvpython "$src/tests/paraview_check.py" >"$tmp/out" 2>"$tmp/err"
rc=$?
set -e
grep -a -v '^$' "$tmp/out" || true
[ $rc -eq 0 ] && grep -q 'paraview: ok' "$tmp/out" || { tail -20 "$tmp/err"; exit 1; }
