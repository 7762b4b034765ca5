#!/usr/bin/env bash
# Limit displacement domain: alpha = 0, 5, ..., 45, 60, 75, 90 deg for k_n = 3 and 48 N/mm^3,
# runs to collapse: delta_x,u/L against delta_z,u/L (one point per alpha, one curve per k_n), and
# the hinge table at collapse (joints of A-E with sides, spread hinges) with the mode per alpha.
# Writes out/domain/summary.csv and out/domain.png. usage: runs/domain_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
"$bin" sweep "$here/reference.ini" --alpha 0:45:5,60,75,90 --kn 3,48 -o "$out_dir/domain" "$@"
"${PYTHON:-/usr/bin/python3}" "$here/plot_study.py" domain "$out_dir/domain/summary.csv" "$out_dir/domain.png"
echo "hinges at collapse and mode per direction:"
column -s, -t < <(cut -d, -f2,3,6,7,8,9,10,11 "$out_dir/domain/summary.csv")
echo "figure: $out_dir/domain.png"
