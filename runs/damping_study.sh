#!/usr/bin/env bash
# Damping study: the collapse of the reference specimen for every damping model and ratio,
# alpha = 0, 30, 45, 60, 90 deg, k_n = 3 and 48 N/mm^3 (quasi-static path, every limit point
# followed dynamically). For each run: delta_u, which limit point turned into the collapse
# (its index among the limit points and its delta), the hinge sides at collapse, the snaps, and
# the modes' damping ratio the model gives, the impacts resolved (the impact model). Writes out/damping_study.csv and the table of docs/results.md
# out/damping_study.md; prints the table.
# none and impact take no ratio (run once, ratio 0); joint and rayleigh at 0.5, 2, 5, 20 % (their
# ratio 0 is the none model: the same code path, vs_model_set_damping(m, 0)).
# usage: runs/damping_study.sh   (VOUSSOIR=path/to/binary, OUT_DIR=..., MODELS="none joint ...",
#        LIMIT_S=seconds per run, default 300, to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
csv="$out_dir/damping_study.csv"
md="$out_dir/damping_study.md"
models="${MODELS:-none joint rayleigh impact}"
# a run still going after LIMIT_S seconds (default 300) is stopped and shown as "> LIMIT_S s":
# heavy Rayleigh damping can hold the falling arch under the collapse criterion, so that it creeps
# dynamically towards support.max_mm for a long time
limit_s="${LIMIT_S:-300}"
echo "alpha_deg,kn_N_mm3,model,ratio,delta_u_mm,collapse_limit_index,collapse_limit_mm,limit_points,snaps,hinges_at_collapse,zeta_mode1,zeta_mode2,wall_s,impacts" >"$csv"
summarise() { # JSON on stdin -> the CSV fields after ratio
  python3 -c '
import json, sys
j = json.load(sys.stdin)
lim = j.get("limit_points") or []
idx = next((i + 1 for i, l in enumerate(lim) if l["kind"] == "collapse"), None)
col = j.get("collapse") or {}
modes = (j.get("damping") or {}).get("modes_self_weight") or []
z = [m["damping_ratio"] for m in modes] + [float("nan")] * 2
f = lambda x: "nan" if x is None else "%.4f" % x
print(",".join([f(col.get("delta_mm")), str(idx or ""), f(lim[idx - 1]["delta_mm"]) if idx else "",
                str(len(lim)), str(sum(l["kind"] == "snap" for l in lim)),
                j.get("hinge_sides_collapse") or "", "%.4g" % z[0], "%.4g" % z[1],
                "%.2f" % j["stats"]["wall_s"], str((j.get("damping") or {}).get("impacts", ""))]))'
}
for alpha in 0 30 45 60 90; do
  for kn in 3 48; do
    for model in $models; do
      case "$model" in none | impact) ratios="0" ;; *) ratios="0.005 0.02 0.05 0.2" ;; esac
      for z in $ratios; do
        rc=0
        j="$(timeout "$limit_s" "$bin" run "$here/reference.ini" --alpha "$alpha" --kn "$kn" \
             --set dynamic.damping_model="$model" --set dynamic.damping="$z" --json -q --no-record)" || rc=$?
        if [ "$rc" = 124 ]; then # stopped by the time limit: no result, said so in the table
          row="$alpha,$kn,$model,$z,timeout,,,,,,,,$limit_s,"
        else
          row="$alpha,$kn,$model,$z,$(summarise <<<"$j")"
        fi
        echo "$row" >>"$csv"
        echo "$row"
      done
    done
  done
done
python3 - "$csv" "$md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cols = [("none", "0"), ("joint", "0.005"), ("joint", "0.02"), ("joint", "0.05"), ("joint", "0.2"),
        ("rayleigh", "0.005"), ("rayleigh", "0.02"), ("rayleigh", "0.05"), ("rayleigh", "0.2"),
        ("impact", "0")]
have = {(r["model"], r["ratio"]) for r in rows}
cols = [c for c in cols if c in have]
name = lambda m, z: m if m in ("none", "impact") else "%s %g %%" % (m, 100 * float(z))
out = ["delta_u in mm; in brackets the limit point (1st, 2nd, ...) whose motion became the collapse.", "",
       "| alpha | k_n | " + " | ".join(name(*c) for c in cols) + " |",
       "|---|---|" + "---|" * len(cols)]
for a in ["0", "30", "45", "60", "90"]:
    for k in ["3", "48"]:
        cells = []
        for m, z in cols:
            r = next((r for r in rows if r["alpha_deg"] == a and r["kn_N_mm3"] == k and r["model"] == m and r["ratio"] == z), None)
            if r is not None and r["delta_u_mm"] == "timeout":
                cells.append("> %s s" % r["wall_s"])
            else:
                cells.append("–" if r is None or r["delta_u_mm"] == "nan" else "%.1f (%s)" % (float(r["delta_u_mm"]), r["collapse_limit_index"]))
        out.append("| %s | %s | %s |" % (a, k, " | ".join(cells)))
open(sys.argv[2], "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
echo "table: $csv, $md"
