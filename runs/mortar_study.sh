#!/usr/bin/env bash
# The reference specimen with mortar joints (issue 29, item 5): the seed's directions alpha =
# 0:45:5, 60, 75, 90 deg at k_n = 3 N/mm^3, tensile strength f_t = 0 (dry), 0.25, 0.5, 1, 2, 5
# and 10 kPa with the softening ending at the opening du = 2 G_f / f_t = 0.2 mm (G_f = f_t du
# / 2), no cohesion; then the sensitivity to G_f at alpha = 0 and f_t = 2 kPa (du = 0.05 to 1
# mm). Runs to collapse (--no-record). Prints the tables docs/mortar.md shows: delta_u against
# f_t (the dry arch the limit), the support displacement at the first crack, the hinges and the
# mode at the collapse, the G_f table, the damage envelopes' vertices and merges, and a
# settlement cycled before the collapse against the monotonic one. Writes out/mortar/runs.csv
# and the figure out/mortar/mortar.png, or MORTAR_FIGURE (delta_u / L against f_t, one line per
# direction; with matplotlib; docs/mortar.png is it).
# usage: runs/mortar_study.sh [-j N]
set -euo pipefail
source "$(dirname "$0")/lib.sh"
jobs=2
if [ "${1:-}" = "-j" ]; then jobs=$2; fi
mkdir -p "$out_dir/mortar"
list="$out_dir/mortar/list"
: >"$list"
for a in 0 5 10 15 20 25 30 35 40 45 60 75 90; do
  for ft in 0 0.00025 0.0005 0.001 0.002 0.005 0.01; do echo "$a $ft 0.2" >>"$list"; done
done
for du in 0.05 0.1 0.5 1.0; do echo "0 0.002 $du" >>"$list"; done
export bin ref="$here/reference.ini" dir="$out_dir/mortar"
xargs -P "$jobs" -L 1 bash -c '
  a=$0 ft=$1 du=$2
  gf=$(awk -v f="$ft" -v d="$du" "BEGIN { printf \"%.10g\", f * d / 2 }")
  "$bin" run "$ref" --alpha "$a" --no-record -q --json --set joints.tensile_MPa="$ft" \
    --set joints.gf_N_mm="$gf" >"$dir/run-$a-$ft-$du.json" || true
' <"$list"
# cycled: the right support settles 3, 6 and 12 mm and comes back each time, then settles on
# (the path in time at 0.04 mm/s; beyond its last point it goes on as it went)
cycle="0:0:0,100:0:3,200:0:0,300:0:6,400:0:0,500:0:12,600:0:0,700:0:40"
for ft in 0 0.001 0.002 0.005; do echo "$ft"; done | xargs -P "$jobs" -L 1 bash -c '
  ft=$0
  gf=$(awk -v f="$ft" "BEGIN { printf \"%.10g\", f * 0.1 }")
  "$bin" run "$ref" --no-record -q --json --set joints.tensile_MPa="$ft" --set joints.gf_N_mm="$gf" \
    --set support.right_path='"$cycle"' --set support.max_mm=300 >"$dir/cycled-$ft.json" || true
'
"${PYTHON:-/usr/bin/python3}" - "$out_dir/mortar" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
alphas = (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90)
fts = ("0", "0.00025", "0.0005", "0.001", "0.002", "0.005", "0.01")
def load(a, ft, du="0.2"):
    j = json.load(open(os.path.join(d, f"run-{a}-{ft}-{du}.json")))
    c = j.get("collapse") or {}
    hinges = " ".join(f"{h['label']}:{'-'.join(map(str, h['joints']))}-{h['side']}"
                      for h in c.get("hinges", []))
    fc = j.get("first_crack") or {}
    m = j.get("mechanism_turning") or {}
    turning = " ".join(f"{h['label'] or '-'}:{'-'.join(map(str, h['joints']))}-{h['side']}"
                       + (" closing" if h["closing"] else "") for h in m.get("hinges", []))
    env = j.get("damage_envelope") or {}
    return dict(du=c.get("delta_mm"), hinges=hinges, mode=j.get("mode") or "-",
                turning=turning, sides=m.get("sides") or "-",
                from_turning=m.get("mode_from") == "turning",
                vertices=env.get("max_vertices", 0), merges=env.get("merges", 0),
                balance=(j.get("energy") or {}).get("balance_error_rel"),
                crack=fc.get("delta_mm"), crack_at=(f"{fc['joint']}-{fc['side']}" if fc else "-"),
                cracking=(j.get("energy") or {}).get("cracking_J"), status=j["status"])
f = lambda x, p=2: f"{x:.{p}f}" if x is not None else "-"
kpa = lambda ft: f"{float(ft) * 1e3:g}"
R = {(a, ft): load(a, ft) for a in alphas for ft in fts}
print("delta_u (mm) against f_t (kPa; du = 2 G_f / f_t = 0.2 mm), k_n = 3 N/mm^3:\n")
print("| alpha (deg) | " + " | ".join("dry" if ft == "0" else kpa(ft) for ft in fts) + " |")
print("|---" * (len(fts) + 1) + "|")
for a in alphas:
    print(f"| {a} | " + " | ".join(f(R[a, ft]["du"]) for ft in fts) + " |")
print("\nsupport displacement at the first crack (mm), and where (joint-edge):\n")
print("| alpha (deg) | " + " | ".join(kpa(ft) for ft in fts[1:]) + " |")
print("|---" * len(fts) + "|")
for a in alphas:
    print(f"| {a} | " + " | ".join(f"{f(R[a, ft]['crack'])} ({R[a, ft]['crack_at']})" for ft in fts[1:]) + " |")
print("\nhinges at the collapse's onset and mode (alpha 0, 45, 90; * read from the hinges turning):\n")
print("| f_t (kPa) | alpha 0 | alpha 45 | alpha 90 |")
print("|---|---|---|---|")
for ft in fts:
    print(f"| {'dry' if ft == '0' else kpa(ft)} | " +
          " | ".join(f"{R[a, ft]['hinges']} ({R[a, ft]['mode']}{'*' if R[a, ft]['from_turning'] else ''})"
                     for a in (0, 45, 90)) + " |")
print("\nhinges turning at the collapse criterion and the mode (mortar only; * read from them):\n")
print("| f_t (kPa) | alpha 0 | alpha 45 | alpha 90 |")
print("|---|---|---|---|")
star = lambda r: r["mode"] + ("*" if r["from_turning"] else "")
for ft in fts[1:]:
    print(f"| {kpa(ft)} | " +
          " | ".join(f"{R[a, ft]['turning']} ({star(R[a, ft])})" for a in (0, 45, 90)) + " |")
print("\nthe mode in every direction (* read from the hinges turning at the criterion; "
      "unclassified: their sides):\n")
print("| alpha (deg) | " + " | ".join("dry" if ft == "0" else kpa(ft) for ft in fts) + " |")
print("|---" * (len(fts) + 1) + "|")
for a in alphas:
    print(f"| {a} | " + " | ".join(
        star(R[a, ft]) if R[a, ft]["mode"] != "-" or ft == "0" else R[a, ft]["sides"]
        for ft in fts) + " |")
print("\nsensitivity to G_f, alpha 0, f_t = 2 kPa:\n")
print("| du = 2 G_f / f_t (mm) | G_f (N/mm) | first crack (mm) | delta_u (mm) | cracking (mJ) | mode |")
print("|---|---|---|---|---|---|")
G = {}
for du in ("0.05", "0.1", "0.2", "0.5", "1.0"):
    G[du] = load(0, "0.002", du)
    r = G[du]
    print(f"| {du} | {0.002 * float(du) / 2:g} | {f(r['crack'])} | {f(r['du'])} | "
          f"{f(r['cracking'] * 1e3 if r['cracking'] is not None else None, 3)} | {r['mode']} |")
mortared = [r for (a, ft), r in R.items() if ft != "0"] + [r for du, r in G.items() if du != "0.2"]
print(f"\ndamage envelopes: {len(mortared)} mortared runs, the most vertices a joint held "
      f"{max(r['vertices'] for r in mortared)} (cap 16), runs that merged "
      f"{sum(r['merges'] > 0 for r in mortared)}, merges in all {sum(r['merges'] for r in mortared)}")
bal = sorted(r["balance"] for r in mortared if r["balance"] is not None)
dry_bal = [R[a, "0"]["balance"] for a in alphas if R[a, "0"]["balance"] is not None]
print(f"energy balance error (relative): mortared {bal[0]:.1g} to {bal[-1]:.1g}, median "
      f"{bal[len(bal) // 2]:.1g}; dry {min(dry_bal):.1g} to {max(dry_bal):.1g}")
print("\ncycled settlement (3, 6, 12 mm down and back, then on), alpha 0: the right support's")
print("settlement at the collapse (mm) against the monotonic delta_u:\n")
print("| f_t (kPa) | monotonic delta_u (mm) | cycled (mm) | cracking, monotonic (mJ) | cycled (mJ) | mode cycled |")
print("|---|---|---|---|---|---|")
for ft in ("0", "0.001", "0.002", "0.005"):
    j = json.load(open(os.path.join(d, f"cycled-{ft}.json")))
    c = j.get("collapse") or {}
    dz = (c.get("right") or {}).get("dz_mm")
    cr = (j.get("energy") or {}).get("cracking_J")
    m = R[0, ft]
    print(f"| {'dry' if ft == '0' else kpa(ft)} | {f(m['du'])} | {f(dz)} | "
          f"{f(m['cracking'] * 1e3 if m['cracking'] is not None else None, 3)} | "
          f"{f(cr * 1e3 if cr is not None else None, 3)} | {j.get('mode') or '-'} |")
with open(os.path.join(d, "runs.csv"), "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["alpha_deg", "ft_MPa", "du_mm", "delta_u_mm", "first_crack_mm", "first_crack_at",
                "hinges", "mode", "cracking_J", "status"])
    for (a, ft), r in R.items():
        w.writerow([a, ft, 0.2, r["du"], r["crack"], r["crack_at"], r["hinges"], r["mode"],
                    r["cracking"], r["status"]])
    for du, r in G.items():
        w.writerow([0, 0.002, du, r["du"], r["crack"], r["crack_at"], r["hinges"], r["mode"],
                    r["cracking"], r["status"]])
try:
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure
except ImportError:
    sys.exit(0)
L = 533.0
fig = Figure(figsize=(6.5, 4.0), dpi=120)
ax = fig.add_subplot()
x = [float(ft) * 1e3 for ft in fts[1:]]
for a in (0, 15, 30, 45, 90):
    y = [R[a, ft]["du"] / L * 100 if R[a, ft]["du"] is not None else float("nan") for ft in fts[1:]]
    line, = ax.plot(x, y, marker="o", label=f"alpha {a} deg")
    ax.axhline(R[a, "0"]["du"] / L * 100, color=line.get_color(), ls=":", lw=0.8)
ax.set_xscale("log")
ax.set_xlabel("mortar tensile strength f_t (kPa; softening to 2 G_f / f_t = 0.2 mm)")
ax.set_ylabel("delta_u / L (%)")
ax.set_title("reference specimen, k_n = 3 N/mm^3: dotted, the dry arch", fontsize=9)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.environ.get("MORTAR_FIGURE", os.path.join(d, "mortar.png")))
PY
