#!/usr/bin/env bash
# Support kinds: the collapse of the reference specimen (k_n = 3 and 48 N/mm^3) with both
# springers fixed (clamped), the left or the right pinned, and both pinned, for alpha = 0 and
# 90 deg (quasi-static path with every limit point followed dynamically). A pinned springer turns
# freely about the centre of its springing face. Prints a table; writes out/pinned_study.csv.
# usage: runs/pinned_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/pinned_study.csv"
echo "alpha_deg,kn_N_mm3,left_kind,right_kind,first_limit_mm,delta_u_mm,dz_over_L_pct,snaps,hinges_at_collapse,energy_balance_rel" >"$csv"
printf '%-6s %-5s %-7s %-7s %12s %12s %8s %6s %-10s %9s\n' alpha kn left right "limit mm" "delta_u mm" "dz/L %" snaps sides balance
for alpha in 0 90; do
  for kn in 3 48; do
    for kinds in "fixed fixed" "pinned fixed" "fixed pinned" "pinned pinned"; do
      set -- $kinds
      j="$("$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" --set support.left_kind="$1" \
            --set support.right_kind="$2" --json -q --no-record || true)"
      fl="$(sed -nE 's/.*"first_limit":\{[^}]*"delta_mm":([-0-9.eE+]+|null).*/\1/p' <<<"$j" | head -1)"
      du="$(jcollapse delta_mm "$j")"; dz="$(jcollapse dz_over_L_pct "$j")"
      sides="$(jstr hinge_sides_collapse "$j")"; bal="$(jnum balance_error_rel "$j")"
      snaps="$(count snap "$j")"
      echo "$alpha,$kn,$1,$2,$fl,$du,$dz,$snaps,$sides,$bal" >>"$csv"
      printf '%-6s %-5s %-7s %-7s %12.4f %12.4f %8.3f %6d %-10s %9.1e\n' "$alpha" "$kn" "$1" "$2" \
        "${fl/null/nan}" "${du/null/nan}" "${dz/null/nan}" "$snaps" "$sides" "$bal"
    done
  done
done
echo "table: $csv"
