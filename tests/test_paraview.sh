#!/usr/bin/env bash
# ParaView (Debian's pvpython, on a private Xvfb server when there is no display) opens two
# records' XDMF sidecars (a run to its first limit point, a run to rest on the ground) with both
# XDMF 3 readers, finds every grid of several frames equal to the records' data and colours each
# grid by its own field; skipped, saying why, without pvpython.
# usage: test_paraview.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
command -v pvpython >/dev/null ||
  { echo "SKIP: pvpython not found (Debian: apt-get install paraview python3-paraview xvfb)"; exit 77; }
tmp=$(mktemp -d)
xpid=""
trap '[ -n "$xpid" ] && kill "$xpid" 2>/dev/null; rm -rf "$tmp"' EXIT
if [ -z "${DISPLAY:-}" ]; then
  command -v Xvfb >/dev/null || { echo "SKIP: no display and no Xvfb (apt-get install xvfb)"; exit 77; }
  # Xvfb picks a free display itself and writes its number only once it accepts connections
  # (-displayfd): no race on the display number, no fixed wait (xvfb-run -a had both, and
  # pvpython then aborted now and then with "bad X server connection").
  Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.err" &
  xpid=$!
  for _ in $(seq 1 1200); do # polling interval 0.1 s, bound 120 s: the condition is the number
    [ -s "$tmp/display" ] && break
    kill -0 "$xpid" 2>/dev/null || { echo "Xvfb did not start:"; cat "$tmp/xvfb.err"; exit 1; }
    sleep 0.1
  done
  [ -s "$tmp/display" ] || { echo "Xvfb gave no display number in 120 s"; exit 1; }
  export DISPLAY=":$(tr -d '[:space:]' <"$tmp/display")"
fi
"$vs" run "$src/runs/reference.ini" --first-limit -q -o "$tmp/run.h5" >/dev/null
"$vs" run "$src/runs/reference.ini" -q -o "$tmp/fall.h5" >/dev/null
cd "$tmp"
# On this workplace's machines about a third of X connections to a fresh Xvfb fail right after
# connect (measured: 87 of 300 XOpenDisplay calls), and pvpython then aborts with "bad X server
# connection" before the check starts. That is the X transport, not ParaView reading the record:
# only that abort is retried, at most 10 times (all 10 failing by chance: below 1e-5).
for attempt in $(seq 1 10); do
  set +e
  pvpython "$src/tests/paraview_check.py" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  set -e
  [ $rc -ne 0 ] && grep -q 'bad X server connection' "$tmp/err" || break
  echo "pvpython could not connect to the X server (attempt $attempt); again"
done
grep -a -v '^$' "$tmp/out" || true
[ $rc -eq 0 ] && grep -q 'paraview: ok' "$tmp/out" || { grep -a -v '^ *[0-9]* *0x' "$tmp/err" | tail -20; exit 1; }
