#!/usr/bin/env bash
# The fill's dead load on the reference specimen (issue 28, item 2): the limit analysis' and the
# load path's load factor of 1 N at quarter span, and the settlement's collapse displacement,
# without fill and with 16 kN/m^3 up to the crown's extrados and 50 mm above it (k_n = 3 N/mm^3).
# Prints the markdown table of docs/model.md ("Fill"); writes out/fill_study.csv.
# usage: runs/fill_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/fill_study.csv"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
echo "unit_weight_kN_m3,level_mm,limit_load_factor,path_load_factor,delta_u_mm" >"$csv"
echo "| fill (kN/m^3) | level above the crown (mm) | limit analysis | load path | settlement's delta_u (mm) |"
echo "|---|---|---|---|---|"
for fill in "0 0" "16 0" "16 50"; do
  set -- $fill
  f=(--set fill.unit_weight_kN_m3="$1" --set fill.level_mm="$2")
  lim="$("$bin" run "$here/reference.ini" "${f[@]}" "${load[@]}" --set analysis.type=limit --json)"
  lim="$(sed -nE 's/.*"limit":\{"load_factor":([-0-9.eE+]+).*/\1/p' <<<"$lim")"
  path="$(jnum load_factor "$("$bin" run "$here/reference.ini" "${f[@]}" "${load[@]}" \
          --set analysis.type=load --json -q --no-record)")"
  du="$(jcollapse delta_mm "$("$bin" run "$here/reference.ini" "${f[@]}" --json -q --no-record)")"
  echo "$1,$2,$lim,$path,$du" >>"$csv"
  printf '| %s | %s | %.3f | %.3f | %.1f |\n' "$1" "$2" "$lim" "$path" "$du"
done
echo "table: $csv" >&2
