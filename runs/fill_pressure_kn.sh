#!/usr/bin/env bash
# Why the settlement's collapse displacement delta_u is not monotone in the fill's horizontal
# pressure fill.k_horizontal = K (docs/model.md, "Fill"): the reference specimen under 16 kN/m^3
# of fill up to 50 mm above the crown, settling (alpha = 0), at k_n = 3 (the case's), 30 and 300
# N/mm^3: delta_u, the hinges' sides first and at collapse, and the thickness factor of the arch
# held at 0.97 delta_u (analysis.type = limit with analysis.hold_mm: 1 at a geometric collapse
# of rigid blocks, well below it at a limit point of soft joints). Prints the markdown table;
# writes out/fill_pressure_kn.csv.
# usage: runs/fill_pressure_kn.sh   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/fill_pressure_kn.csv"
fill=(--set fill.unit_weight_kN_m3=16 --set fill.level_mm=50)
echo "kn_N_mm3,k_horizontal,delta_u_mm,sides_first,sides_collapse,held_thickness_factor" >"$csv"
for kn in 3 30 300; do
  for K in 0 0.25 0.5 0.75 1; do
    j="$("$bin" run "$here/reference.ini" "${fill[@]}" --kn "$kn" --set fill.k_horizontal="$K" \
         --json -q --no-record)"
    du="$(jcollapse delta_mm "$j")"
    s0="$(jstr hinge_sides_initial "$j")" s1="$(jstr hinge_sides_collapse "$j")"
    hold="$(/usr/bin/python3 -c "print('%.4f' % (0.97 * $du))")"
    l="$("$bin" run "$here/reference.ini" "${fill[@]}" --kn "$kn" --set fill.k_horizontal="$K" \
         --set analysis.type=limit --set analysis.hold_mm="$hold" --json 2>/dev/null || true)"
    tf="$(sed -nE 's/.*"limit":\{[^}]*"thickness_factor":([-0-9.eE+]+).*/\1/p' <<<"$l")"
    echo "$kn,$K,$du,$s0,$s1,${tf:-}" >>"$csv"
  done
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ks = sorted({r["k_horizontal"] for r in rows}, key=float)
print("| k_n (N/mm^3) | " + " | ".join("K = %s" % k for k in ks) + " |")
print("|---|" + "---|" * len(ks))
for kn in ("3", "30", "300"):
    cells = []
    for k in ks:
        r = next(r for r in rows if r["kn_N_mm3"] == kn and r["k_horizontal"] == k)
        tf = "%.2f" % float(r["held_thickness_factor"]) if r["held_thickness_factor"] else "–"
        cells.append("%.1f mm, %s → %s, %s" % (float(r["delta_u_mm"]), r["sides_first"],
                                               r["sides_collapse"], tf))
    print("| %s | %s |" % (kn, " | ".join(cells)))
PY
echo "table: $csv" >&2
