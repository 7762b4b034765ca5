#!/usr/bin/env bash
# How a record survives SIGKILL at a random moment: N runs of the reference specimen with their
# record (to the collapse: dynamic.fall_s = 0), each killed after a random delay of 5 to 64 ms
# (most of the run: it takes about 60 ms), and what each left at the record's path:
#   - nothing (killed before the record's first snapshot, taken once its layout is written:
#     only PATH.part, the working file, which the next run removes);
#   - a record that opens and whose every dataset and attribute reads (h5dump of the whole file);
#   - a record that opens but holds an object that does not read, kept as torn-K.h5 in OUT_DIR
#     for inspection. HDF5 1.10 has no crash-consistent flush, so a kill inside one can tear the
#     file it writes; that file is PATH.part, and PATH is only ever replaced (renamed over) by a
#     whole copy of it taken after a flush (src/record/record_snapshot.c). Before that design, 1 record
#     in 247 was torn.
# A measurement, not a test: it exits 0 whatever it finds, and prints the counts.
# usage: runs/kill_stress.sh [N]   (N default 200; VOUSSOIR=binary, OUT_DIR=... as the other
#        scripts; about 0.2 s a kill)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
n="${1:-200}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
none=0 good=0 torn=0 closed=0
for ((i = 1; i <= n; i++)); do
  rm -f "$work"/r.*
  "$bin" run "$here/reference.ini" -o "$work/r.h5" --set dynamic.fall_s=0 -q >/dev/null 2>&1 &
  pid=$!
  sleep "0.0$(printf '%02d' $((RANDOM % 60 + 5)))"
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null && closed=$((closed + 1)) || true # finished before the kill
  if [ ! -f "$work/r.h5" ]; then
    none=$((none + 1))
  elif h5dump "$work/r.h5" >/dev/null 2>&1; then
    good=$((good + 1))
  else
    torn=$((torn + 1))
    mkdir -p "$out_dir"
    cp "$work/r.h5" "$out_dir/torn-$i.h5"
  fi
done
echo "| kills | no record yet (only PATH.part) | record reads whole | record with an unreadable object | run had finished |"
echo "|---|---|---|---|---|"
echo "| $n | $none | $good | $torn | $closed |"
((torn == 0)) || echo "torn records kept in $out_dir (torn-K.h5)"
