#!/usr/bin/env bash
# Slow-loading fidelity: the whole loading integrated dynamically (--dynamic) at support rates
# 0.04 (the laboratory's), 0.4, 4, 40 and 400 mm/s, against the quasi-static path whose
# collapsing limit point is delta_u. With --dynamic, delta_u is the departure: the last instant
# before the detection at which the kinetic energy rose through the rest level (an IDA root), so
# what the table shows is inertia, not the lag of the collapse criterion (reported separately as
# the detection). Writes out/rate_study.csv.
# usage: runs/rate_study.sh [ALPHA_DEG] [KN_N_MM3]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
alpha="${1:-0}"; kn="${2:-3}"
csv="$out_dir/rate_study.csv"
j="$("$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" --json -q --no-record)"
ref="$(jcollapse delta_mm "$j")"; refdet="$(jcollapse delta_detected_mm "$j")"
echo "rate_mm_s,delta_u_mm,ratio_to_quasistatic,delta_detected_mm,mode,wall_s" >"$csv"
echo "alpha = $alpha deg, k_n = $kn N/mm^3; quasi-static + dynamic: delta_u = $ref mm (collapsing limit point), detected at $refdet mm ($(jstr mode "$j"))"
printf '%-10s %12s %10s %14s %-6s %8s\n' "rate mm/s" "delta_u mm" "/ q-s" "detected mm" mode "wall s"
for rate in 0.04 0.4 4 40 400; do
  j="$("$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" --dynamic --set support.rate_mm_s="$rate" --json -q --no-record || true)"
  du="$(jcollapse delta_mm "$j")"; det="$(jcollapse delta_detected_mm "$j")"
  mode="$(jstr mode "$j")"; wall="$(jnum wall_s "$j")"
  ratio="$(awk -v a="$du" -v b="$ref" 'BEGIN {if (a == "null" || a == "") print "null"; else printf "%.5f", a / b}')"
  echo "$rate,$du,$ratio,$det,$mode,$wall" >>"$csv"
  printf '%-10s %12s %10s %14s %-6s %8.2f\n' "$rate" "$du" "$ratio" "$det" "${mode:-null}" "$wall"
done
echo "table: $csv"
