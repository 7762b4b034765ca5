#!/usr/bin/env bash
# Build the libFuzzer target (Debian's clang) and run it for SECONDS (default 60) on a copy of
# the seed corpus, so the tree is not changed. Usage: tests/fuzz/run.sh [SECONDS] [WORKDIR]
# Exit status: 0 no finding, non-zero a crash or a failed check (the reproducer is in WORKDIR).
set -euo pipefail
secs="${1:-60}"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
work="${2:-}"
if [ -z "$work" ]; then # our own scratch directory: removed unless there is a finding
  work="$(mktemp -d /tmp/voussoir-fuzz.XXXXXX)"
  trap 'rc=$?; [ "$rc" -eq 0 ] && rm -rf "$work"; exit "$rc"' EXIT
fi
mkdir -p "$work/corpus"
cp -n "$here"/corpus/* "$work/corpus/" 2>/dev/null || true
# shellcheck disable=SC2046
clang -std=c17 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"$root/include" -I"$root/src/base" -I"$root/src/case" $(pkg-config --cflags inih) \
  "$here/fuzz_case.c" "$root/src/case/case.c" "$root/src/case/case_read.c" \
  "$root/src/base/parse.c" \
  "$root/src/base/list.c" "$root/src/base/status.c" $(pkg-config --libs inih) -lm -o "$work/fuzz_case"
echo "fuzz: $work/fuzz_case for $secs s (corpus and any reproducer in $work)"
cd "$work"
./fuzz_case -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
  -dict="$here/case.dict" -print_final_stats=1 corpus
