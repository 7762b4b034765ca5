#!/usr/bin/env bash
# Imperfection study: the reference specimen with nearly rigid joints (k_n = 48 N/mm^3) and
# non-coplanar joint faces ([imperfections] face_mm: standard deviation of the as-built gap at a
# joint's open edge), SAMPLES imperfect arches per amplitude (voussoir montecarlo, seed 1).
# Question (issue 13): which face scatter brings the mean collapse at alpha = 0 down to the
# laboratory's 16.5 % of L, and what does that scatter predict at alpha = 90 (measured 3.7 %)?
# Prints a table; writes out/imperfection_study.csv and out/imperfection_study.png.
# usage: runs/imperfection_study.sh [SAMPLES]   (default 32; VOUSSOIR=..., OUT_DIR=..., PYTHON=... with
# matplotlib, override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
samples="${1:-32}"
faces=(0 0.05 0.1 0.15 0.2 0.3)
csv="$out_dir/imperfection_study.csv"
stat() { awk -F, -v k="$1" '$1 == k {print $2}' "$2"; }
echo "alpha_deg,face_mm,samples,collapses,failed,mean_over_L_pct,cov,q05_over_L_pct" >"$csv"
printf '%-6s %-8s %8s %9s %7s %12s %7s %12s\n' alpha face_mm samples collapses failed "mean u/L %" CoV "q05 u/L %"
for alpha in 0 90; do
  for f in "${faces[@]}"; do
    d="$out_dir/imperfection_study/a${alpha}_f${f}"
    mkdir -p "$d"
    "$bin" montecarlo "$here/reference.ini" --samples "$samples" --seed 1 -q -o "$d" \
      --set support.alpha_deg="$alpha" --set joints.kn_N_mm3=48 --set imperfections.face_mm="$f" >/dev/null
    s="$d/statistics.csv"
    row="$alpha,$f,$(stat samples "$s"),$(stat collapses "$s"),$(stat failed "$s"),$(stat mean_delta_u_over_L "$s"),$(stat cov_delta_u "$s"),$(stat q05_delta_u_over_L "$s")"
    echo "$row" >>"$csv"
    IFS=, read -r a ff n c fl m cv q <<<"$row"
    printf '%-6s %-8s %8s %9s %7s %12.3f %7.4f %12.3f\n' "$a" "$ff" "$n" "$c" "$fl" "$m" "$cv" "$q"
  done
done
"${PYTHON:-/usr/bin/python3}" "$here/plot_imperfection_study.py" "$csv" "$out_dir/imperfection_study.png"
echo "table: $csv  figure: $out_dir/imperfection_study.png"
