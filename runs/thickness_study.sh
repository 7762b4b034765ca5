#!/usr/bin/env bash
# Geometry beyond the specimen: a semicircular arch (embrace 180 deg, intrados radius 300 mm,
# 55 voussoirs, k_n = 48 N/mm^3: nearly rigid joints), settlement, collapse displacement against
# the thickness, down to where the arch cannot stand under self-weight (t/R about 0.107 with R the
# centreline radius: t = 33.9 mm here). Writes out/thickness/summary.csv and out/thickness.png.
# usage: runs/thickness_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
"$bin" sweep "$here/reference.ini" --set arch.embrace_deg=180 --kn 48 \
  --vary arch.thickness_mm=32:40:1,42:60:2,65:90:5 -o "$out_dir/thickness" "$@" || true
"${PYTHON:-/usr/bin/python3}" "$here/plot_study.py" thickness "$out_dir/thickness/summary.csv" "$out_dir/thickness.png" 300
column -s, -t < <(cut -d, -f3,4,6,7,10,13 "$out_dir/thickness/summary.csv")
echo "figure: $out_dir/thickness.png"
