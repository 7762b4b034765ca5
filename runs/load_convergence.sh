#!/usr/bin/env bash
# The load path's load factor against the limit analysis' as k_n grows (issue 28): the reference
# specimen with 1 N at quarter span (x = L/4), analysis.type = load against analysis.type =
# limit (CLP), k_n = 3, 30, 300 and 1e4 N/mm^3. Prints the markdown table of docs/model.md
# ("The live load's path"); writes out/load_convergence.csv.
# usage: runs/load_convergence.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/load_convergence.csv"
x_mm="$(/usr/bin/python3 -c 'import math; print(0.25 * 2 * 300 * math.sin(math.radians(62.5)))')"
load=(--set load.kind=point --set load.x_mm="$x_mm" --set load.value_N=1)
lim="$("$bin" run "$here/reference.ini" "${load[@]}" --set analysis.type=limit --json)"
lim="$(sed -nE 's/.*"limit":\{"load_factor":([-0-9.eE+]+).*/\1/p' <<<"$lim")"
echo "kn_N_mm3,load_factor,limit_load_factor,below_pct" >"$csv"
row1="| k_n (N/mm^3) |" row2="|---|" row3="| load factor (path) |" row4="| below the LP's ($(printf '%.3f' "$lim")) |"
for kn in 3 30 300 1e4; do
  lf="$(jnum load_factor "$("$bin" run "$here/reference.ini" "${load[@]}" --kn "$kn" \
        --set analysis.type=load --json -q --no-record)")"
  gap="$(/usr/bin/python3 -c "print('%.1f' % (100 * (1 - $lf / $lim)))")"
  echo "$kn,$lf,$lim,$gap" >>"$csv"
  row1+=" $kn |" row2+="---|" row3+=" $(printf '%.3f' "$lf") |" row4+=" $gap % |"
done
printf '%s\n%s\n%s\n%s\n' "$row1" "$row2" "$row3" "$row4"
echo "table: $csv" >&2
