#!/usr/bin/env bash
# The fill's horizontal pressure (fill.k_horizontal) and a live load's spread through the fill
# (load.spread_deg) on the reference specimen (issue 28, item 2): 16 kN/m^3 up to 50 mm above the
# crown's extrados, 1 N at quarter span on the fill's surface (k_n = 3 N/mm^3); the limit
# analysis' load factor, least and greatest thrust and thickness factor, the load path's load
# factor and the settlement's collapse displacement.
# Prints the markdown table of docs/model.md ("Fill"); writes out/fill_pressure_study.csv.
# usage: runs/fill_pressure_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/fill_pressure_study.csv"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
fill=(--set fill.unit_weight_kN_m3=16 --set fill.level_mm=50)
lnum() { sed -nE "s/.*\"limit\":\{[^}]*\"$1\":([-0-9.eE+]+).*/\1/p" <<<"$2" | head -1; }
echo "k_horizontal,spread_deg,limit_load_factor,thrust_min_N,thrust_max_N,thickness_factor,path_load_factor,delta_u_mm" >"$csv"
echo "| K | spread (deg) | limit analysis | least thrust (N) | greatest thrust (N) | thickness factor | load path | settlement's delta_u (mm) |"
echo "|---|---|---|---|---|---|---|---|"
for row in "0 0" "0.5 0" "1 0" "0 30" "0 45" "0.5 30"; do
  set -- $row
  f=("${fill[@]}" --set fill.k_horizontal="$1" --set load.spread_deg="$2")
  lim="$("$bin" run "$here/reference.ini" "${f[@]}" "${load[@]}" --set analysis.type=limit --json)"
  lf="$(lnum load_factor "$lim")" tmin="$(lnum thrust_min_N "$lim")"
  tmax="$(lnum thrust_max_N "$lim")" tf="$(lnum thickness_factor "$lim")"
  path="$(jnum load_factor "$("$bin" run "$here/reference.ini" "${f[@]}" "${load[@]}" \
          --set analysis.type=load --json -q --no-record)")"
  du="$(jcollapse delta_mm "$("$bin" run "$here/reference.ini" "${f[@]}" --json -q --no-record)")"
  echo "$1,$2,$lf,$tmin,$tmax,$tf,$path,$du" >>"$csv"
  printf '| %s | %s | %.3f | %.2f | %.2f | %.3f | %.3f | %.1f |\n' "$1" "$2" "$lf" "$tmin" "$tmax" \
    "$tf" "$path" "$du"
done
echo "table: $csv" >&2
