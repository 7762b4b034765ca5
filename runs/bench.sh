#!/usr/bin/env bash
# Benchmark of this build against the previous release, both measured in the same run: the
# previous one is checked out with `git worktree add` into a temporary directory and built there
# (Release, the `voussoir` target only; no network). Rows (CPU seconds of the process, user + sys,
# median of REPEAT runs, unless said otherwise):
#  1. the reference run (runs/reference.ini) with --no-record (it stops at the collapse);
#  2. the same with its HDF5 record (the fall is then integrated);
#  3. alpha 90 deg, k_n 48 N/mm^3, with its record;
#     (full mode) the split of rows 2 and 3: the record of the run ending at the collapse
#     (dynamic.fall_s = 0), and alpha 90 without a record; the fall to rest is the rest; and
#     rows 2 and 3 with the record's snapshots (src/record/record_snapshot.c) after the layout only
#     (--snapshot-share 1e-6) and after every flush (1), this build only;
#  4. the seed domain (alpha 0:45:5,60,75,90 x k_n 3, 48, records) by `sweep -j 2`: wall seconds;
#  5. process start-up: `voussoir --version`, mean CPU milliseconds (user + sys) over 50 starts
#     (HDF5 and cairo are loaded only by the commands that need them: src/plugin/plugin.h);
#  6. one run to collapse (--no-record) with 55 to 1760 voussoirs: CPU seconds, and the cost
#     relative to 55 voussoirs (linear: the ratio of the counts);
#  7. the limit analysis of the reference specimen (analysis.type = limit, 1 N at quarter span):
#     the whole analysis (the process, 21 LPs: two thrusts, the load factor, the thickness's
#     bisection), one LP from scratch (the least thrust's) and one from its basis (the load
#     factor's; each its cpu_s in the JSON), this build only, each against row 1 (the target:
#     a limit-analysis solve costs no more than the reference run to collapse); and the whole
#     analysis of the reference specimen on two piers of 4 courses (issue 28).
# Each row prints both figures and their ratio this / previous (below 1: faster). The full mode
# then prints runs/scaling.sh for this build (cost against the voussoir count, in detail).
# --quick (what .ci/run uses): one run each (CI time: the record rows follow the fall to rest,
# seconds each), no seed domain, 55 to 220 voussoirs.
# usage: runs/bench.sh [--quick] [BINARY]
#   BENCH_BASE=REV  what to compare with (default: the newest release tag v* before HEAD; without
#                   tags, the newest release in runs/releases that HEAD contains; without either,
#                   the parent of the oldest commit of this branch not on main, or HEAD~1)
set -euo pipefail
unset LD_LIBRARY_PATH # each binary loads the library of its own build (RUNPATH)
quick=0
if [ "${1:-}" = "--quick" ]; then quick=1; shift; fi
VOUSSOIR="${1:-${VOUSSOIR:-$(cd "$(dirname "$0")" && pwd)/../build/voussoir}}"
export VOUSSOIR
source "$(dirname "$0")/lib.sh"
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")" # the runs start in a scratch directory
repeat=$((quick ? 1 : 5))
sizes=(55 110 220 440 880 1760)
((quick)) && sizes=(55 110 220)
ref="$here/reference.ini"
work="$(mktemp -d)"
cleanup() {
  git -C "$here/.." worktree remove --force "$work/src" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

# --- the previous revision, built here ---
release() { # REV: the newest release tag (v*) reachable from REV, or nothing
  git -C "$here/.." describe --tags --abbrev=0 --match 'v[0-9]*' "$1" 2>/dev/null || true
}
base_rev="${BENCH_BASE:-}"
if [ -z "$base_rev" ]; then
  base_rev="$(release HEAD)"
  if [ -n "$base_rev" ] && [ "$(git -C "$here/.." rev-parse "$base_rev^{commit}")" = \
       "$(git -C "$here/.." rev-parse HEAD)" ]; then
    base_rev="$(release HEAD~1)" # HEAD is the release itself: the one before it
  fi
fi
if [ -z "$base_rev" ]; then # no tags (a clean clone need not carry them): runs/releases
  while read -r name commit _; do
    [[ "$name" == v* ]] || continue
    if git -C "$here/.." merge-base --is-ancestor "$commit" HEAD 2>/dev/null &&
       [ "$(git -C "$here/.." rev-parse "$commit")" != "$(git -C "$here/.." rev-parse HEAD)" ]; then
      base_rev="$commit"
      echo "no release tag (v*) in this checkout: $name from runs/releases ($commit)" >&2
    fi
  done <"$here/releases"
fi
if [ -z "$base_rev" ]; then # no release at all: the previous revision
  echo "no release tag (v*) in this checkout: comparing against the previous revision" >&2
  oldest="$(git -C "$here/.." rev-list main..HEAD 2>/dev/null | tail -n 1 || true)"
  if [ -n "$oldest" ]; then base_rev="$oldest~1"; else base_rev="HEAD~1"; fi
fi
base_bin=""
if git -C "$here/.." worktree add --detach "$work/src" "$base_rev" >/dev/null 2>&1 &&
   cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release >/dev/null 2>&1 &&
   cmake --build "$work/build" -j "$(nproc)" --target voussoir >/dev/null 2>&1; then
  base_bin="$work/build/voussoir"
  echo "previous: $base_rev ($(git -C "$here/.." rev-parse --short "$base_rev^{commit}"), built in $work); this: $bin"
else
  echo "previous revision $base_rev could not be built: its column is left empty" >&2
fi

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
cpu_once() { # BINARY args...: CPU seconds (user + sys) of one process
  local t TIMEFORMAT='%3U %3S'
  t="$({ time "$@" >/dev/null 2>&1; } 2>&1 || true)"
  awk '{print $1 + $2}' <<<"${t##*$'\n'}"
}
cpu_median() { # BINARY args...
  for ((i = 0; i < repeat; i++)); do (cd "$work" && cpu_once "$@"); done | median
}
now() { date +%s.%N; }
row() { # NAME PREVIOUS THIS [FORMAT]
  awk -v n="$1" -v a="$2" -v b="$3" -v f="${4:-%.3f}" 'BEGIN {
    pa = (a == "") ? "-" : sprintf(f, a); r = (a == "" || a == 0) ? "-" : sprintf("%.2f", b / a)
    printf "  %-44s %10s %10s %7s\n", n, pa, sprintf(f, b), r }'
}
both() { # NAME FUNCTION args...: the function prints one figure for the binary in $1
  local name="$1" fn="$2" a="" b
  shift 2
  [ -n "$base_bin" ] && a="$("$fn" "$base_bin" "$@")"
  b="$("$fn" "$bin" "$@")"
  row "$name" "$a" "$b"
}
ref_run() { local b="$1"; shift; cpu_median "$b" run "$ref" -q "$@"; }
domain() {
  local t0
  rm -rf "$work/domain"
  t0="$(now)"
  "$1" sweep "$ref" --alpha 0:45:5,60,75,90 --kn 3,48 -j 2 -o "$work/domain" -q >/dev/null 2>&1 || true
  awk -v a="$t0" -v b="$(now)" 'BEGIN {print b - a}'
}
# BINARY: CPU milliseconds of one `voussoir --version`, the mean over 50 starts: perf's
# task-clock when perf is installed, else the user + sys time of the shell's children (bash's
# times builtin; that also counts the forked shell before its exec, about 4 ms more)
startup() {
  if command -v perf >/dev/null 2>&1 &&
     perf stat -r 50 -x, -e task-clock "$1" --version >/dev/null 2>"$work/perf"; then
    awk -F, '$3 ~ /task-clock/ {print $1}' "$work/perf"
    return
  fi
  times >"$work/t0" # (in this shell: the second line is its children's CPU time)
  for ((i = 0; i < 50; i++)); do "$1" --version >/dev/null; done
  times >"$work/t1"
  cat "$work/t0" "$work/t1" | awk 'NR % 2 == 0 {gsub(/[ms]/, " "); t[NR] = 60 * $1 + $2 + 60 * $3 + $4}
                                   END {print 1e3 * (t[4] - t[2]) / 50}'
}
sized() { # BINARY COUNT: CPU s, or nothing when that build refuses the count (exit 2: v0.1.0
  local rc=0   # allowed at most 1000 voussoirs)
  "$1" run "$ref" -q --no-record --set arch.voussoirs="$2" --set support.max_mm=1 >/dev/null 2>&1 ||
    rc=$?
  [ "$rc" = 2 ] && return 0
  (cd "$work" && cpu_once "$1" run "$ref" -q --no-record --set arch.voussoirs="$2")
}

printf '  %-44s %10s %10s %7s\n' "" previous this ratio
both "reference, --no-record (CPU s)" ref_run --no-record
ref_cpu="$(ref_run "$bin" --no-record)"
both "reference, with record (CPU s)" ref_run -o "$work/r.h5"
both "alpha 90, k_n 48, with record (CPU s)" ref_run --alpha 90 --kn 48 -o "$work/r.h5"
if ((!quick)); then # where the record rows' time goes: the same runs ending at the collapse
  both "  reference, record to the collapse (CPU s)" ref_run -o "$work/r.h5" --set dynamic.fall_s=0
  both "  alpha 90, k_n 48, --no-record (CPU s)" ref_run --alpha 90 --kn 48 --no-record
  both "  alpha 90, k_n 48, record to the collapse" ref_run --alpha 90 --kn 48 -o "$work/r.h5" \
    --set dynamic.fall_s=0
  # what the record's snapshots cost (this build: the previous one has none): the layout's alone,
  # against the default's (rows 2 and 3), and one after every flush
  for share in 1e-6 1; do
    row "  reference, record, --snapshot-share $share" "" \
      "$(ref_run "$bin" -o "$work/r.h5" --snapshot-share "$share")"
    row "  alpha 90, record, --snapshot-share $share" "" \
      "$(ref_run "$bin" --alpha 90 --kn 48 -o "$work/r.h5" --snapshot-share "$share")"
  done
fi
((quick)) || both "seed domain, 26 runs, sweep -j 2 (wall s)" domain
a=""
[ -n "$base_bin" ] && a="$(startup "$base_bin")"
row "voussoir --version (CPU ms)" "$a" "$(startup "$bin")" "%.1f"
echo "  one run to collapse, --no-record, against the voussoir count (CPU s; x55: over 55 voussoirs)"
a55="" b55=""
for nv in "${sizes[@]}"; do
  a=""
  [ -n "$base_bin" ] && a="$(sized "$base_bin" "$nv")"
  b="$(sized "$bin" "$nv")"
  [ "$nv" = 55 ] && { a55="$a"; b55="$b"; }
  x="$(awk -v b="$b" -v c="$b55" -v n="$nv" 'BEGIN {printf "x55 %.1f (count x%.0f)", b / c, n / 55}')"
  row "$nv voussoirs   $x" "$a" "$b"
done
# row 7: the limit analysis (the previous release has none); ratio: over row 1 (this build)
lim_args=(--set analysis.type=limit --set load.kind=point --set load.x_mm=133.05)
lim_lp() { # BINARY SOLUTION: CPU s of that solution's LP (limit.SOLUTION.cpu_s in the JSON)
  for ((i = 0; i < repeat; i++)); do
    "$1" run "$ref" -q "${lim_args[@]}" --json | grep -o "\"$2\":{[^}]*}" |
      grep -o '"cpu_s":[0-9.e+-]*' | cut -d: -f2
  done | median
}
echo "  the limit analysis, 55 voussoirs (ratio: over the reference run to collapse, row 1)"
row "  the whole analysis, 21 LPs (CPU s)" "$ref_cpu" "$(ref_run "$bin" "${lim_args[@]}")"
row "  one LP from scratch, the least thrust's" "$ref_cpu" "$(lim_lp "$bin" thrust_min)" "%.4f"
row "  one LP from its basis, the load factor's" "$ref_cpu" "$(lim_lp "$bin" collapse)" "%.4f"
# the same on two piers of 4 courses (300 mm high, 150 mm wide: docs/studies.md, "Piers"):
# 63 blocks, 64 joints
pier_args=(--set piers.height_mm=300 --set piers.width_mm=150 --set piers.courses=4)
row "  the whole analysis on two 4-course piers (CPU s)" "$ref_cpu" \
  "$(ref_run "$bin" "${lim_args[@]}" "${pier_args[@]}")"
lim_args+=("${pier_args[@]}")
row "  one LP from scratch on the piers, the least thrust's" "$ref_cpu" "$(lim_lp "$bin" thrust_min)" "%.4f"
((quick)) || { echo; "$here/scaling.sh" "$bin"; }
