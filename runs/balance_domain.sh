#!/usr/bin/env bash
# Energy balance and constraint drift of the dynamic phase on the seed domain (alpha = 0, 5, ...,
# 45, 60, 75, 90 deg x k_n = 3, 48 N/mm^3): per run to collapse, delta_u, the energy balance up to
# the collapse criterion (relative to the largest energy term; the support's work is the work of
# the multipliers lambda), the constraint drift max |g| and the wall time; then the worst of each.
# usage: runs/balance_domain.sh
set -euo pipefail
source "$(dirname "$0")/lib.sh"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
printf '%5s %4s %10s %12s %10s %7s\n' alpha k_n delta_u_mm balance_rel drift_m wall_s
worst_b=0 worst_g=0
for kn in 3 48; do
  for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do
    json="$(cd "$tmp" && "$bin" run "$here/reference.ini" --alpha "$a" --kn "$kn" --no-record -q --json)"
    du="$(jcollapse delta_mm "$json")" b="$(jnum balance_error_rel "$json")"
    g="$(jnum constraint_drift_m "$json")" w="$(jnum wall_s "$json")"
    printf '%5s %4s %10.4f %12.3e %10.2e %7.2f\n' "$a" "$kn" "$du" "$b" "$g" "$w"
    worst_b="$(awk -v x="$b" -v y="$worst_b" 'BEGIN { print (x > y) ? x : y }')"
    worst_g="$(awk -v x="$g" -v y="$worst_g" 'BEGIN { print (x > y) ? x : y }')"
  done
done
echo "worst energy balance up to the collapse: $worst_b (relative); worst constraint drift: $worst_g m"
