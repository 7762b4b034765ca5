#!/usr/bin/env bash
# What the fall after the collapse costs against the rest of the run (docs/fall.md),
# for each fall scheme (fall.scheme: rigid, the default; penalty). Per case, the CPU time (user +
# sys) of the run with its record following the fall to rest, split in two (medians of REPEAT
# runs). Rigid: the fall's own (the run's JSON, stats.fall.cpu_s: the process's CPU time over
# the fall, its samples' writing included) and the rest of the run (the process's whole CPU time,
# process start included, less the fall's: the path, the dynamics to the collapse, the record).
# Penalty (IDA integrates the fall on from the dynamics): the rest is the CPU time of the same
# run with dynamic.fall_s = 0, which ends at the collapse criterion, and the fall's the
# difference. Then the fall's simulated time (last recorded state - collapse detection), its
# steps (rigid: time steps, of which those of the slow step, those of the arch in the air solved
# as a chain, and those whose Gauss-Seidel stopped at its cap; penalty: IDA steps and root
# events), the kinetic energy of the last state over the rest level, the deepest vertex below
# the ground at the end and during the fall, the deepest vertex inside another block or a pier
# during the fall, and how the fall ended. Last, per scheme: how many falls came to rest, the
# range of the ratio, how often the fall cost no more than the rest, the sums of both CPU times,
# the deepest overlaps over all the falls and the longest fall.
#   runs/fall_cost.sh                      # both schemes (REPEAT=3: ~1.5 min on an idle machine)
#   SCHEMES=rigid REPEAT=1 runs/fall_cost.sh
#   CASES="0 3,90 48" runs/fall_cost.sh    # alpha k_n pairs
#   CASES=seed SCHEMES=rigid REPEAT=1 runs/fall_cost.sh  # the seed domain, 26 cases (~10 s)
#   ARGS="--set fall.step_ms=2" runs/fall_cost.sh          # more options for every run
#   CASES=seed KNS="6 10 20" SCHEMES=rigid REPEAT=1 runs/fall_cost.sh  # other k_n (N/mm^3)
#   CASES=seed KNS="3 48 6 10 20 4 8 15 30" SCHEMES=rigid runs/fall_cost.sh  # 117 falls (~2 min)
#   ARGS="--set fall.max_sweeps=30 --set fall.slow_factor=1" ...  # before the slow step
set -euo pipefail
. "$(dirname "$0")/lib.sh"
repeat="${REPEAT:-3}"
ref="$here/reference.ini"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# cpu ARGS...: REPEAT runs; prints the medians (s) of their CPU times (user + sys), of their
# falls' own (stats.fall.cpu_s; 0 where the JSON has none) and of the difference; the last run's
# stdout in $tmp/out, the exit status of the first that failed (0: none) in $tmp/rc. Every
# record and output is removed first: a run that fails must not leave an earlier case's to read.
cpu() {
  local totals=() falls=() rests=()
  echo 0 >"$tmp/rc"
  for ((i = 0; i < repeat; i++)); do
    rm -f "$tmp"/r*.h5 "$tmp"/r*.xmf "$tmp/out"
    # bash's times: the second line is the children's user and sys time, "0m0.150s 0m0.020s"
    # shellcheck disable=SC2086 # ARGS: words, split on purpose
    totals+=("$( ( "$bin" run "$ref" --json -q ${ARGS:-} "$@" >"$tmp/out" 2>"$tmp/err" ||
      { rc=$?; [ "$(cat "$tmp/rc")" != 0 ] || echo "$rc" >"$tmp/rc"; }; times ) |
      tail -1 |
      awk '{t = 0; for (i = 1; i <= 2; i++) { split($i, p, /[ms]/); t += 60 * p[1] + p[2] } print t}')")
    local fc; fc="$(jnum cpu_s "$(cat "$tmp/out")")"
    falls+=("${fc:-0}")
    rests+=("$(awk -v t="${totals[-1]}" -v f="${fc:-0}" 'BEGIN {print t - f}')")
  done
  echo "$(median "${totals[@]}") $(median "${falls[@]}") $(median "${rests[@]}")"
}
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
um() { awk -v x="$1" 'BEGIN {printf "%.3g", x * 1e6}'; } # m -> um, 3 digits
# h5 FILE DATASET: a scalar of the record
h5() { h5dump -d "$2" "$1" 2>/dev/null | sed -nE 's/^ *\(0\): ([-0-9.eE+]+).*/\1/p' | head -1; }
# h5a FILE ATTRIBUTE: an integer attribute of the record
h5a() { h5dump -a "$2" "$1" 2>/dev/null | sed -nE 's/^ *\(0\): ([-0-9]+).*/\1/p' | head -1; }
# last_ke FILE: the kinetic energy of the record's last state
last_ke() {
  local n; n="$(h5dump -H -d /observables/energy/value "$1" | sed -nE 's/.*SIMPLE \{ \( ([0-9]+), 7 \).*/\1/p' | head -1)"
  h5dump -d /observables/energy/value -s "$((n - 1)),0" -c "1,1" "$1" | sed -nE 's/^ *\([0-9]+,0\): ([-0-9.eE+]+).*/\1/p'
}

cases=("0 3" "90 48" "45 48" "0 48" "90 3" "45 3")
if [ "${CASES:-}" = seed ]; then # the seed domain: 13 directions x k_n 3, 48 (or KNS)
  cases=()
  read -ra kns <<<"${KNS:-3 48}"
  for a in 0 7.5 15 22.5 30 37.5 45 52.5 60 67.5 75 82.5 90; do
    for kn in "${kns[@]}"; do cases+=("$a $kn"); done
  done
elif [ -n "${CASES:-}" ]; then
  IFS=, read -ra cases <<<"$CASES"
fi
read -ra schemes <<<"${SCHEMES:-rigid penalty}"
echo "| scheme | alpha (deg) | k_n (N/mm^3) | CPU of the rest (s) | CPU of the fall (s) | ratio | fall simulated (s) | steps | of which | final KE / rest level | deepest below ground: end / during (um) | inside another body, during (um) | fall ended |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
summary=()
for scheme in "${schemes[@]}"; do
  n_rest=0 n_cheap=0 n_cases=0 n_failed=0 ratios=()
  sums="0 0 0 0 0 0" # fall, rest CPU; deepest (m) below the ground at the end, during; inside
  # another body; the longest fall (s)
  for c in "${cases[@]}"; do
    set -- $c
    a="$1" kn="$2"
    read -r c1 cf c0 < <(cpu --alpha "$a" --kn "$kn" --set fall.scheme="$scheme" -o "$tmp/r.h5")
    j1="$(cat "$tmp/out")"
    if [ "$(cat "$tmp/rc")" != 0 ]; then # no figures from a run that failed
      echo "| $scheme | $a | $kn | run failed (exit $(cat "$tmp/rc")): $(head -c 120 "$tmp/err" | head -1) |"
      n_cases=$((n_cases + 1)) n_failed=$((n_failed + 1))
      continue
    fi
    if [ "$scheme" = rigid ]; then # the rest: the whole run's CPU less the fall's own
      c1="$(awk -v r="$c0" -v f="$cf" 'BEGIN {print r + f}')"
    else # the rest: the run that ends at the collapse criterion
      cp "$tmp/r.h5" "$tmp/keep.h5" # the run's record, which the next one's removal would take
      read -r c0 _ _ < <(cpu --alpha "$a" --kn "$kn" --set fall.scheme="$scheme" \
        --set dynamic.fall_s=0 -o "$tmp/r0.h5")
      j0="$(cat "$tmp/out")"
      mv "$tmp/keep.h5" "$tmp/r.h5"
      if [ "$(cat "$tmp/rc")" != 0 ]; then
        echo "| $scheme | $a | $kn | run to the collapse failed (exit $(cat "$tmp/rc")) |"
        n_cases=$((n_cases + 1)) n_failed=$((n_failed + 1))
        continue
      fi
    fi
    tsim="$(awk -v a="$(jnum last_time_s "$j1")" -v b="$(jcollapse time_detected_s "$j1")" 'BEGIN {printf "%.3f", a - b}')"
    if [ "$scheme" = rigid ]; then
      steps="$(h5a "$tmp/r.h5" /summary/fall/steps)"
      detail="$(h5a "$tmp/r.h5" /summary/fall/slow_steps) slow, $(h5a "$tmp/r.h5" \
        /summary/fall/chain_steps) as a chain, $(h5a "$tmp/r.h5" /summary/fall/capped_steps) capped"
    else
      steps=$(($(jnum dynamic_steps "$j1") - $(jnum dynamic_steps "$j0")))
      detail="$(($(jnum root_events "$j1") - $(jnum root_events "$j0"))) root events"
    fi
    rest="$(h5 "$tmp/r.h5" /summary/ground/rest_level)"
    inside="$(h5 "$tmp/r.h5" /summary/ground/overlap_max)"
    ke="$(last_ke "$tmp/r.h5")"
    pen_end="$(h5 "$tmp/r.h5" /summary/ground/penetration_final)"
    pen_max="$(h5 "$tmp/r.h5" /summary/ground/penetration_max)"
    rest_attr="$(h5a "$tmp/r.h5" /summary/ground/at_rest)"
    # not at rest: at fall_s (5 s by default), or (penalty) IDA failed in the fall before it
    ended="$(awk -v r="$rest_attr" -v t="$tsim" 'BEGIN {s = (r == 1) ? "at rest" : (t > 4.999) ? "at fall_s" : "stopped early"; print s}')"
    awk -v sc="$scheme" -v a="$a" -v kn="$kn" -v c0="$c0" -v c1="$c1" -v ts="$tsim" -v st="$steps" \
        -v de="$detail" -v ke="$ke" -v rl="$rest" -v pe="$pen_end" -v pm="$pen_max" -v iv="$inside" \
        -v en="$ended" 'BEGIN {
      f = c1 - c0; ins = (iv == "") ? "-" : sprintf("%.3g", iv * 1e6)
      printf "| %s | %s | %s | %.2f | %.2f | %.1f | %s | %d | %s | %.2g | %.3g / %.3g | %s | %s |\n",
        sc, a, kn, c0, f, f / c0, ts, st, de, ke / rl, pe * 1e6, pm * 1e6, ins, en}'
    n_cases=$((n_cases + 1))
    ratio="$(awk -v c0="$c0" -v c1="$c1" 'BEGIN {printf "%.2f", (c1 - c0) / c0}')"
    if [ "$ended" = "at rest" ]; then
      n_rest=$((n_rest + 1))
      awk -v r="$ratio" 'BEGIN {exit !(r <= 1)}' && n_cheap=$((n_cheap + 1))
    fi
    ratios+=("$ratio")
    sums="$(awk -v s="$sums" -v c0="$c0" -v c1="$c1" -v pe="$pen_end" -v pm="$pen_max" \
      -v iv="${inside:-0}" -v ts="$tsim" 'function m(x, y) {return (y + 0 > x + 0) ? y : x}
      BEGIN {split(s, a, " ")
      print a[1] + c1 - c0, a[2] + c0, m(a[3], pe), m(a[4], pm), m(a[5], iv), m(a[6], ts)}')"
  done
  range="$(printf '%s\n' "${ratios[@]}" | sort -g | sed -n '1p;$p' | paste -sd-)"
  read -r s_fall s_rest d_end d_during d_inside t_long <<<"$sums"
  failed=""
  ((n_failed == 0)) || failed=" ($n_failed runs failed: above)"
  summary+=("$scheme: $n_rest of $n_cases cases at rest$failed; the fall's CPU $range times the rest of \
the run, at most once in $n_cheap of the $n_rest at rest; all together $(printf %.2f "$s_fall") s \
of falls against $(printf %.2f "$s_rest") s of the rest; deepest below the ground at the end \
$(um "$d_end") um, during a fall $(um "$d_during") um, inside another body $(um "$d_inside") um; \
the longest fall $t_long s")
done
echo
printf '%s\n' "${summary[@]}"
