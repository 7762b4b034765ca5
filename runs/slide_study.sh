#!/usr/bin/env bash
# Friction: the reference specimen at alpha = 0 and 90 deg, k_n = 3 and 48 N/mm^3, mu = 0.2, 0.3,
# 0.4 and 0.7 (16 runs to collapse), each run's outcome: delta_u (mm), or the failure; the
# collapse's mechanism (rotational, sliding, mixed) and the joints that slid in it; the first
# limit point and whether it is the onset of slip. With BASELINE (another build's binary, e.g.
# one from before slip was followed) its outcome beside each. Prints a Markdown table; writes
# out/slide_study.md and out/slide_study.csv.
# usage: runs/slide_study.sh [BASELINE]   (VOUSSOIR=path/to/binary, OUT_DIR=... to override)
set -euo pipefail
source "$(dirname "$0")/lib.sh"
base="${1:-}"
[ -z "$base" ] || [ -x "$base" ] || { echo "${0##*/}: $base is not an executable" >&2; exit 2; }
dir="$out_dir/slide_study"
mkdir -p "$dir"
for alpha in 0 90; do
  for kn in 3 48; do
    for mu in 0.2 0.3 0.4 0.7; do
      args=("$here/reference.ini" --alpha "$alpha" --kn "$kn" --set joints.friction="$mu" --json -q --no-record)
      "$bin" run "${args[@]}" >"$dir/run-$alpha-$kn-$mu.json" 2>/dev/null || true
      [ -z "$base" ] || "$base" run "${args[@]}" >"$dir/base-$alpha-$kn-$mu.json" 2>/dev/null || true
    done
  done
done
"${PYTHON:-/usr/bin/python3}" - "$dir" "$out_dir" "${base:+yes}" <<'EOF'
import json, os, sys
dir, out, with_base = sys.argv[1], sys.argv[2], sys.argv[3] == "yes"

def load(name):
    try:
        with open(os.path.join(dir, name)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None

def outcome(d):
    """delta_u, or where and why the run failed."""
    if d is None:
        return "no result"
    if d["status"] == "collapse":
        return f"{d['collapse']['delta_mm']:.2f}"
    err = d.get("error") or ""
    why = "not a limit point" if "not a limit point" in err else err[:60]
    return f"failed at {d['last_delta_mm']:.2f}: {why}"

def mechanism(d):
    c = (d or {}).get("collapse") or {}
    if "mechanism" not in c:
        return ""
    joints = ", ".join(f"{s['joint']}{s['toward'][0].upper()}" for s in c["slips"])
    return c["mechanism"] + (f" (slips {joints})" if joints else "")

def first(d):
    fl = (d or {}).get("first_limit")
    if not fl:
        return ""
    kind = f", slip onset at joint {fl['slip_onset']['first_joint']}" if fl.get("slip_onset") else ""
    return f"{fl['delta_mm']:.2f}{kind}"

head = ["alpha", "k_n", "mu"] + (["before"] if with_base else []) + ["delta_u (mm)", "mechanism", "first limit (mm)"]
rows, csv = [], ["alpha_deg,kn_N_mm3,mu" + (",before" if with_base else "") + ",outcome,mechanism,first_limit"]
for alpha in (0, 90):
    for kn in (3, 48):
        for mu in ("0.2", "0.3", "0.4", "0.7"):
            d = load(f"run-{alpha}-{kn}-{mu}.json")
            cells = [str(alpha), str(kn), mu]
            if with_base:
                cells.append(outcome(load(f"base-{alpha}-{kn}-{mu}.json")))
            cells += [outcome(d), mechanism(d), first(d)]
            rows.append(cells)
            csv.append(",".join(f'"{c}"' for c in cells))
md = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)] + ["| " + " | ".join(r) + " |" for r in rows]
open(os.path.join(out, "slide_study.md"), "w").write("\n".join(md) + "\n")
open(os.path.join(out, "slide_study.csv"), "w").write("\n".join(csv) + "\n")
print("\n".join(md))
EOF
echo "table: $out_dir/slide_study.md"
