#!/usr/bin/env bash
# Stiffness sensitivity, settlement (alpha = 0): 16 log-spaced k_n from 0.1 to 100 N/mm^3, runs to
# collapse; delta_z,u/L against k_n and the hinge joints at collapse against k_n.
# Writes out/stiffness/summary.csv and out/stiffness.png. usage: runs/stiffness_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
kn="$(awk 'BEGIN {for (i = 0; i < 16; i++) printf "%s%.6g", (i ? "," : ""), 0.1 * 1000 ^ (i / 15)}')"
"$bin" sweep "$here/reference.ini" --alpha 0 --kn "$kn" -o "$out_dir/stiffness" "$@"
"${PYTHON:-/usr/bin/python3}" "$here/plot_study.py" stiffness "$out_dir/stiffness/summary.csv" "$out_dir/stiffness.png"
column -s, -t < <(cut -d, -f3,4,7,9,10,11 "$out_dir/stiffness/summary.csv")
echo "figure: $out_dir/stiffness.png"
