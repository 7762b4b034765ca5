#!/usr/bin/env bash
# The mortar's damage envelope against its cap (issue 29, item 1: the law exact, or its
# approximation shown to converge): runs/mortar_study.sh's 83 mortared runs with the binary as
# built (VS_JOINT_ENV_MAX = 16 vertices a joint) and with two builds of the program whose cap is
# 8 and 64 (configured under out/mortar-cap/, -DVS_JOINT_ENV_MAX=N; a few minutes each on two
# cores). The largest cap is taken as exact when none of its runs merged. Prints, per cap, the
# runs that merged, the merges, the most vertices a joint held, and against the largest cap the
# largest relative difference of delta_u and the runs whose hinges or mode differ.
# usage: runs/mortar_cap.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
jobs=2
if [ "${1:-}" = "-j" ]; then jobs=$2; fi
src="$here/.."
caps="8 16 64"
for cap in $caps; do
  dir="$out_dir/mortar-cap/$cap"
  mkdir -p "$dir"
  b="$bin"
  if [ "$cap" != 16 ]; then
    cmake -S "$src" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_C_FLAGS="-DVS_JOINT_ENV_MAX=$cap" >/dev/null
    cmake --build "$dir/build" -j "$jobs" --target voussoir >/dev/null
    b="$dir/build/voussoir"
  fi
  VOUSSOIR="$b" OUT_DIR="$dir" MORTAR_FIGURE="$dir/mortar.png" \
    "$here/mortar_study.sh" -j "$jobs" >"$dir/study.txt"
done
"${PYTHON:-/usr/bin/python3}" - "$out_dir/mortar-cap" $caps <<'PY'
import csv, json, os, sys
d, caps = sys.argv[1], sys.argv[2:]
def load(cap):
    rows = {}
    for name in os.listdir(os.path.join(d, cap, "mortar")):
        if not (name.startswith("run-") and name.endswith(".json")):
            continue
        j = json.load(open(os.path.join(d, cap, "mortar", name)))
        env = j.get("damage_envelope")
        if env is None:
            continue  # the dry runs
        c = j.get("collapse") or {}
        hinges = " ".join(f"{h['label']}:{'-'.join(map(str, h['joints']))}-{h['side']}"
                          for h in c.get("hinges", []))
        rows[name] = dict(du=c.get("delta_mm"), hinges=hinges, mode=j.get("mode"), **env)
    return rows
R = {cap: load(cap) for cap in caps}
exact = R[caps[-1]]
print(f"| cap (vertices) | runs that merged | merges | most vertices | largest \\|delta_u - exact\\| / delta_u | hinges / modes differing |")
print("|---|---|---|---|---|---|")
for cap in caps:
    r = R[cap]
    dmax = max(abs(r[k]["du"] - exact[k]["du"]) / exact[k]["du"] for k in exact)
    print(f"| {cap} | {sum(v['merges'] > 0 for v in r.values())} of {len(r)} | "
          f"{sum(v['merges'] for v in r.values())} | {max(v['max_vertices'] for v in r.values())} | "
          f"{dmax:.2g} | {sum(r[k]['hinges'] != exact[k]['hinges'] for k in exact)} / "
          f"{sum(r[k]['mode'] != exact[k]['mode'] for k in exact)} |")
if any(v["merges"] for v in exact.values()):
    print(f"(the cap {caps[-1]} merged too: not exact)")
PY
