#!/usr/bin/env bash
# Build the libFuzzer targets with Debian's clang (-fsanitize=fuzzer,address,undefined, from the
# sources each needs) and fuzz each for SECONDS (default 60) on a copy of its seed corpus
# (corpus/TARGET), so that the tree is not changed. Targets (fuzz_TARGET.c says what each checks):
#   case     the case file and the option parsers (--set, lists, numbers)
#   merge    `voussoir merge`: the shards' tables, and the summary written from them
#   record   `voussoir plot` and the XDMF sidecar: records of any shapes, types and values
#   journal  `sweep --resume`, `montecarlo --resume`: the journals' header and rows
#   blocks   arch.shape = file: the blocks file (JSON), read, written back, read again
# Usage: tests/fuzz/run.sh [-j N] [SECONDS] [TARGET...]   (default: every target, one at a time;
# -j N: N targets at once). The scratch directory is $FUZZ_WORK (kept, its corpora growing from
# run to run), or a new one under /tmp, removed when nothing was found. Prints, per target, the
# inputs it ran and how many per second.
# Exit status: 0 no finding; 1 a finding (a crash, a sanitizer report or a failed check: the
# reproducer's path and the log's are printed; replay with TARGET_BINARY REPRODUCER); 2 usage,
# or clang or a build failed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
all=(case merge record journal blocks)
jobs=1
if [ "${1:-}" = -j ]; then
  jobs="${2:-}"
  [[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz: -j needs a number >= 1" >&2; exit 2; }
  shift 2
fi
secs=60
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then
  secs="$1"
  shift
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz: unknown target $t (targets: ${all[*]})" >&2; exit 2; }
done
if ! command -v clang >/dev/null 2>&1; then
  echo "fuzz: clang not found (Debian 12: apt-get install clang libclang-rt-14-dev; .ci/deps" \
       "installs them)" >&2
  exit 2
fi

work="${FUZZ_WORK:-}"
if [ -z "$work" ]; then # our own scratch directory: removed unless there is a finding
  work="$(mktemp -d /tmp/voussoir-fuzz.XXXXXX)"
  trap 'rc=$?; [ "$rc" -eq 0 ] && rm -rf "$work"; exit "$rc"' EXIT
fi

# The sources and libraries of each target (every layer's folder on the include path, for the
# private headers).
s="$root/src"
layer_dirs=(-I"$work/include") # version.h, made below from version.h.in as CMake makes it
for d in "$s"/*/; do layer_dirs+=(-I"$d"); done
mkdir -p "$work/include/voussoir"
ver="$(sed -n 's/^project(voussoir VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")"
IFS=. read -r v1 v2 v3 <<<"$ver"
sed "s/@PROJECT_VERSION@/$ver/; s/@PROJECT_VERSION_MAJOR@/$v1/; s/@PROJECT_VERSION_MINOR@/$v2/;
     s/@PROJECT_VERSION_PATCH@/$v3/" "$root/include/voussoir/version.h.in" \
  >"$work/include/voussoir/version.h"
case_src=("$s/case/case.c" "$s/case/case_read.c" "$s/base/parse.c" "$s/base/list.c"
          "$s/base/status.c" "$s/base/quote.c")
geometry_src=("$s/model/geometry.c" "$s/model/outline.c" "$s/model/shape.c" "$s/model/arch.c"
              "$s/model/piers.c"
              "$s/model/blocks.c")
sources() {
  case "$1" in
  case) echo "${case_src[@]}" ;;
  merge) echo "${case_src[@]}" "$s/study/montecarlo_merge.c" "$s/study/journal.c" \
              "$s/plot/montecarlo.c" "$s/record/h5util.c" "$s/base/outpath.c" "$s/base/fault.c" "$s/plot/plot.c" \
              "${geometry_src[@]}" "$s/model/support.c" "$s/run/montecarlo_travel.c" ;;
  record) echo "${case_src[@]}" "$s/plot/plot_cmd.c" "$s/plot/plot_record.c" \
               "$s/plot/plot.c" "$s/plot/plot_arch.c" "$s/plot/plot_frame.c" "$s/record/xdmf.c" "$s/record/xdmf_file.c" \
               "$s/record/xdmf_record.c" "$s/record/xdmf_rows.c" "$s/record/h5util.c" \
               "$s/base/outpath.c" "$s/base/fault.c" "$s/model/imperfections.c" "${geometry_src[@]}" \
               "$s/model/support.c" "$s/model/hinges.c" "$s/run/json.c" \
               "$s/solve/limit_analysis.c" "$s/solve/limit.c" "$s/base/wall_clock.c" ;;
  journal) echo "${case_src[@]}" "$s/study/journal.c" "$s/base/outpath.c" "$s/base/fault.c" ;;
  blocks) echo "${case_src[@]}" "${geometry_src[@]}" ;;
  esac
}
libs() {
  # shellcheck disable=SC2046
  case "$1" in
  case | journal) echo $(pkg-config --libs inih) -lm ;;
  merge) echo $(pkg-config --libs inih hdf5-serial cairo fontconfig jansson) -lm \
              -Wl,--wrap=vs_mc_write_summary -Wl,--wrap=vs_plot_emit ;;
  record) echo $(pkg-config --libs inih hdf5-serial cairo fontconfig jansson clp) -lm \
               -Wl,--wrap=vs_plot_emit ;;
  blocks) echo $(pkg-config --libs inih jansson) -lm ;;
  esac
}

# The longest input of each target (bytes): a case file, a few shards' tables, a record's
# description, a journal of some rows.
max_len() {
  case "$1" in
  case | journal) echo 8192 ;;
  merge) echo 16384 ;;
  record) echo 4096 ;;
  blocks) echo 16384 ;;
  esac
}

build() {
  local t="$1"
  mkdir -p "$work/$t"
  # shellcheck disable=SC2046
  clang -std=c17 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -I"$root/include" "${layer_dirs[@]}" $(pkg-config --cflags inih hdf5-serial cairo jansson clp) \
    "$here/fuzz_$t.c" $(sources "$t") $(libs "$t") -o "$work/$t/fuzz_$t" \
    >"$work/$t/build.log" 2>&1 || { cat "$work/$t/build.log" >&2; return 1; }
}

# Fuzz target $1 for $secs s in $work/$1; its summary line into $work/$1/result.
fuzz() {
  local t="$1" d="$work/$1" dict=() tmp
  mkdir -p "$d/corpus"
  cp -n "$here/corpus/$t"/* "$d/corpus/" 2>/dev/null || true
  [ -f "$here/$t.dict" ] && dict=(-dict="$here/$t.dict")
  # the files a target writes for each input: in memory when it can (a disk makes merge and
  # record some 20 times slower), removed afterwards whatever happened
  tmp="$(mktemp -d /dev/shm/voussoir-fuzz-"$t".XXXXXX 2>/dev/null || mktemp -d "$d/tmp.XXXXXX")"
  local rc=0
  (cd "$d" && TMPDIR="$tmp" ./"fuzz_$t" -max_total_time="$secs" -timeout=10 \
     -rss_limit_mb=2048 -max_len="$(max_len "$t")" -close_fd_mask=3 -print_final_stats=1 \
     -artifact_prefix="$d/" "${dict[@]}" corpus >"$d/log" 2>&1) || rc=$?
  rm -rf "$tmp"
  local n r
  n="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$d/log" | grep -o '[0-9]*$' || true)"
  r="$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$d/log" | grep -o '[0-9]*$' || true)"
  if [ "$rc" -eq 0 ]; then
    echo "fuzz: $t: no finding, ${n:-?} inputs in $secs s (${r:-?}/s)" >"$d/result"
  else
    local repro
    repro="$(grep -o 'Test unit written to .*' "$d/log" | sed 's/^Test unit written to //' |
             tail -n 1 || true)"
    { echo "fuzz: $t: FINDING after ${n:-?} inputs: reproducer ${repro:-(none written)}"
      echo "fuzz: $t: log $d/log; replay: $d/fuzz_$t ${repro:-REPRODUCER}"; } >"$d/result"
    tail -n 40 "$d/log" >&2
    return 1
  fi
}

echo "fuzz: building ${targets[*]} in $work"
pids=()
for t in "${targets[@]}"; do
  build "$t" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then wait "${pids[0]}" || exit 2; pids=("${pids[@]:1}"); fi
done
for p in "${pids[@]}"; do wait "$p" || exit 2; done

status=0
pids=()
names=()
for t in "${targets[@]}"; do
  echo "fuzz: $t for $secs s"
  fuzz "$t" &
  pids+=($!)
  names+=("$t")
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    cat "$work/${names[0]}/result"
    pids=("${pids[@]:1}")
    names=("${names[@]:1}")
  fi
done
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || status=1
  cat "$work/${names[$i]}/result"
done
exit "$status"
