#!/usr/bin/env bash
# Damping study: the collapse displacement of the reference specimen for joint damping ratios
# 0, 2, 5 and 20 % of critical, alpha = 0, 45, 90 deg, k_n = 3 and 48 N/mm^3 (quasi-static path
# with every limit point followed dynamically). Prints a table; writes out/damping_study.csv.
# usage: runs/damping_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/damping_study.csv"
echo "alpha_deg,kn_N_mm3,damping,delta_u_mm,dz_over_L_pct,dx_over_L_pct,snaps,mode,hinges_at_collapse,energy_balance_rel,wall_s" >"$csv"
printf '%-6s %-5s %-8s %12s %8s %8s %6s %-5s %-10s %9s %8s\n' alpha kn damping "delta_u mm" "dz/L %" "dx/L %" snaps mode sides balance "wall s"
for alpha in 0 45 90; do
  for kn in 3 48; do
    for z in 0 0.02 0.05 0.2; do
      j="$("$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" --set dynamic.damping="$z" --json -q --no-record || true)"
      du="$(jcollapse delta_mm "$j")"; dz="$(jcollapse dz_over_L_pct "$j")"; dx="$(jcollapse dx_over_L_pct "$j")"
      mode="$(jstr mode "$j")"; sides="$(jstr hinge_sides_collapse "$j")"
      bal="$(jnum balance_error_rel "$j")"; wall="$(jnum wall_s "$j")"; snaps="$(count snap "$j")"
      echo "$alpha,$kn,$z,$du,$dz,$dx,$snaps,$mode,$sides,$bal,$wall" >>"$csv"
      printf '%-6s %-5s %-8s %12.4f %8.3f %8.3f %6d %-5s %-10s %9.1e %8.2f\n' "$alpha" "$kn" "$z" \
        "${du/null/nan}" "${dz/null/nan}" "${dx/null/nan}" "$snaps" "${mode:-null}" "$sides" "$bal" "$wall"
    done
  done
done
echo "table: $csv"
