#!/usr/bin/env bash
# The cost of a run of each shape with 55 voussoirs against the reference run: CPU seconds of
# the process (user + sys), median of REPEAT runs (default 5), settlement (alpha = 0), k_n = 3
# N/mm^3, --no-record (each stops at its collapse): the reference specimen, then the shapes of
# runs/shape_figures.sh (span 532.2 mm), the reference with vertical joints and friction 2 (mu
# 0.7 lets its vertical joints near the springings slide), and the reference read back from the
# blocks file `voussoir blocks` writes of it. Prints each one's seconds, its collapse and its
# ratio to the reference's; the issue asks for at most 2.
# usage: runs/shapes_bench.sh [REPEAT]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
repeat="${1:-5}"
ref="$here/reference.ini"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bin" blocks "$ref" -o "$work/reference.json"
printf '[arch]\nshape = file\nblocks_file = %s\n' "$work/reference.json" >"$work/file.ini"
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
cpu_once() { # args...: CPU seconds (user + sys) of one run
  local t TIMEFORMAT='%3U %3S'
  t="$({ time "$bin" run "$@" --no-record -q >/dev/null 2>&1; } 2>&1 || true)"
  awk '{print $1 + $2}' <<<"${t##*$'\n'}"
}
span=(--set arch.span_mm=532.2)
declare -A case_of=(
  [reference]="$ref"
  [semicircle]="$ref ${span[*]} --set arch.rise_mm=266.1 --set arch.thickness_mm=40"
  [pointed]="$ref ${span[*]} --set arch.shape=pointed --set arch.eccentricity=0.25 --set arch.thickness_mm=40"
  [elliptical]="$ref ${span[*]} --set arch.shape=elliptical --set arch.rise_mm=325.9 --set arch.thickness_mm=40"
  [basket]="$ref ${span[*]} --set arch.shape=basket --set arch.rise_mm=200 --set arch.thickness_mm=50"
  [parabolic]="$ref ${span[*]} --set arch.shape=parabolic --set arch.rise_mm=266.1 --set arch.thickness_mm=40"
  [catenary]="$ref ${span[*]} --set arch.shape=catenary --set arch.rise_mm=266.1 --set arch.thickness_mm=40"
  [vertical]="$ref --set arch.joints=vertical --set joints.friction=2"
  [blocks_file]="$work/file.ini"
)
base=""
printf '%-12s %9s %12s %7s\n' case "CPU s" "delta_u mm" ratio
for c in reference semicircle pointed elliptical basket parabolic catenary vertical blocks_file; do
  # shellcheck disable=SC2086
  s="$(for ((i = 0; i < repeat; i++)); do cpu_once ${case_of[$c]}; done | median)"
  # shellcheck disable=SC2086
  d="$(jcollapse delta_mm "$("$bin" run ${case_of[$c]} --no-record -q --json 2>/dev/null || true)")"
  [ -n "$base" ] || base="$s"
  printf '%-12s %9.3f %12s %7.2f\n' "$c" "$s" "${d:-none}" "$(awk -v a="$s" -v b="$base" 'BEGIN {print a / b}')"
done
