#!/usr/bin/env bash
# How a Monte Carlo study survives SIGKILL at random moments (docs/studies.md, montecarlo
# --resume): ROUNDS times, a study of SAMPLES imperfect arches (the reference specimen with 21
# voussoirs and the test suite's imperfections) is started, killed with SIGKILL after a random
# delay of 20 to 300 ms, and continued with --resume (started afresh while no manifest was
# written yet), again and again until one of its runs finishes. Its samples.csv and
# statistics.csv are then compared byte for byte with those of the same study run once without
# interruption. A measurement, not a test: it exits 0 whatever it finds, and prints the counts.
# usage: runs/mc_kill_stress.sh [ROUNDS]   (ROUNDS default 30; SAMPLES=48, JOBS=2; VOUSSOIR=binary
#        as the other scripts; about 0.5 s a round)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
rounds="${1:-30}" samples="${SAMPLES:-48}" jobs="${JOBS:-2}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
args=("$here/reference.ini" --set arch.voussoirs=21 --set imperfections.kn_cov=0.3
      --set imperfections.face_mm=0.002 --set imperfections.angle_cov=0.02 --samples "$samples"
      --seed 7 -j "$jobs" -q)
"$bin" montecarlo "${args[@]}" -o "$work/whole" >/dev/null
kills=0 same=0 differ=0 max_kills=0
for ((r = 1; r <= rounds; r++)); do
  rm -rf "$work/study"
  k=0
  while :; do
    resume=()
    [ -f "$work/study/montecarlo.manifest" ] && resume=(--resume)
    "$bin" montecarlo "${args[@]}" -o "$work/study" "${resume[@]}" >/dev/null 2>&1 &
    pid=$!
    sleep "0.$(printf '%03d' $((RANDOM % 281 + 20)))"
    kill -9 "$pid" 2>/dev/null || true
    rc=0
    wait "$pid" 2>/dev/null || rc=$?
    if [ "$rc" -eq 137 ]; then # killed: continue it
      k=$((k + 1))
      continue
    fi
    [ "$rc" -eq 0 ] || echo "round $r: montecarlo exited with status $rc" >&2
    break # it had finished before the kill: the study is complete
  done
  kills=$((kills + k))
  ((k > max_kills)) && max_kills=$k
  if cmp -s "$work/study/samples.csv" "$work/whole/samples.csv" &&
     cmp -s "$work/study/statistics.csv" "$work/whole/statistics.csv"; then
    same=$((same + 1))
  else
    differ=$((differ + 1))
    mkdir -p "$out_dir"
    cp -r "$work/study" "$out_dir/mc-differs-$r"
  fi
done
echo "| rounds | SIGKILLs | most in one round | tables identical to the uninterrupted study's | differing |"
echo "|---|---|---|---|---|"
echo "| $rounds | $kills | $max_kills | $same | $differ |"
((differ == 0)) || echo "differing studies kept in $out_dir (mc-differs-R)"
