#!/usr/bin/env bash
# The figures of docs/model.md, "Shapes": each shape's mechanism at the collapse under
# settlement (alpha = 0) and under spreading (alpha = 90 deg), side by side, as docs/shapes/
# SHAPE.png (each under 100 kB). Span 532.2 mm, 55 voussoirs, k_n = 48 N/mm^3, normal joints:
# the semicircle, a pointed arch of eccentricity 0.25 and an elliptical one of its rise (325.9 mm)
# at 40 mm (runs/shapes_study.sh's), a basket-handle arch rising 200 mm at 50 mm, parabolic and
# catenary arches rising 266.1 mm at 40 mm. Each run stops at the collapse (dynamic.fall_s = 0);
# `voussoir plot` draws it (arch_collapse.png), matplotlib puts the two side by side.
# usage: runs/shape_figures.sh [DOCS_DIR]   (default: docs/shapes of this tree)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
docs="${1:-$here/../docs/shapes}"
mkdir -p "$docs" "$out_dir/shape_figures"
common=(--set arch.span_mm=532.2 --kn 48 --set dynamic.fall_s=0 -q)
declare -A shape=(
  [circular]="--set arch.rise_mm=266.1 --set arch.thickness_mm=40"
  [pointed]="--set arch.shape=pointed --set arch.eccentricity=0.25 --set arch.thickness_mm=40"
  [elliptical]="--set arch.shape=elliptical --set arch.rise_mm=325.9 --set arch.thickness_mm=40"
  [basket]="--set arch.shape=basket --set arch.rise_mm=200 --set arch.thickness_mm=50"
  [parabolic]="--set arch.shape=parabolic --set arch.rise_mm=266.1 --set arch.thickness_mm=40"
  [catenary]="--set arch.shape=catenary --set arch.rise_mm=266.1 --set arch.thickness_mm=40"
)
for s in circular pointed elliptical basket parabolic catenary; do
  for a in 0 90; do
    rec="$out_dir/shape_figures/$s-$a.h5"
    # shellcheck disable=SC2086
    "$bin" run "$here/reference.ini" "${common[@]}" ${shape[$s]} --alpha "$a" -o "$rec" >/dev/null
    "$bin" plot "$rec" -o "$out_dir/shape_figures/$s-$a" >/dev/null
  done
  "${PYTHON:-/usr/bin/python3}" - "$out_dir/shape_figures/$s" "$docs/$s.png" "$s" <<'EOF'
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.image as img
import matplotlib.pyplot as plt
base, png, name = sys.argv[1:]
fig, axes = plt.subplots(1, 2, figsize=(12, 3.7))
for ax, a, what in zip(axes, (0, 90), ("settlement (alpha = 0)", "spreading (alpha = 90 deg)")):
    pic = img.imread(f"{base}-{a}/arch_collapse.png")
    ax.imshow(pic[88:-66, :, :3], interpolation="antialiased")  # their title lines and key cropped
    ax.set_title(f"{name}: {what}", fontsize=10)
    ax.axis("off")
fig.tight_layout(pad=0.3)
fig.savefig(png, dpi=80)
EOF
  echo "$docs/$s.png: $(stat -c %s "$docs/$s.png") bytes"
done
