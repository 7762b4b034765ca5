#!/usr/bin/env python3
"""Compare two sweep summaries (DIR/summary.csv of `voussoir sweep`) row by row: the same cases,
the same status, delta_u and the first limit point within a relative tolerance (default 1e-4),
the same hinges at collapse. Modes are compared too and reported; --allow-mode lets them differ
(a deliberate change to the classification). Exit status 0 when they agree, 1 otherwise.
usage: runs/compare_sweeps.py A/summary.csv B/summary.csv [--rtol 1e-4] [--allow-mode]"""
import csv
import math
import sys


def rows(path):
    with open(path, newline="") as f:
        r = list(csv.DictReader(f))
    axes = [k for k in r[0].keys() if k not in ("run",) and k not in STATIC] if r else []
    return {tuple(row[a] for a in axes): row for row in r}, axes


STATIC = {"status", "first_limit_mm", "delta_u_mm", "dz_over_L_pct", "dx_over_L_pct",
          "hinges_at_collapse", "mode", "snaps", "wall_s", "error"}


def close(a, b, rtol):
    x, y = float(a), float(b)
    if math.isnan(x) or math.isnan(y):
        return math.isnan(x) and math.isnan(y)
    return abs(x - y) <= rtol * max(abs(x), abs(y), 1e-12)


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    rtol = 1e-4
    if "--rtol" in argv:
        rtol = float(argv[argv.index("--rtol") + 1])
        args.remove(argv[argv.index("--rtol") + 1])
    a, axes = rows(args[0])
    b, _ = rows(args[1])
    bad = 0
    worst = 0.0
    for key in sorted(set(a) | set(b)):
        ra, rb = a.get(key), b.get(key)
        name = ", ".join(f"{x} {v}" for x, v in zip(axes, key))
        if ra is None or rb is None:
            print(f"{name}: only in {'B' if ra is None else 'A'}")
            bad += 1
            continue
        problems = []
        if ra["status"] != rb["status"]:
            problems.append(f"status {ra['status']} / {rb['status']}")
        for col in ("delta_u_mm", "first_limit_mm"):
            if not close(ra[col], rb[col], rtol):
                problems.append(f"{col} {ra[col]} / {rb[col]}")
            elif not math.isnan(float(ra[col])):
                worst = max(worst, abs(float(ra[col]) - float(rb[col])) / max(abs(float(ra[col])), 1e-12))
        if ra["hinges_at_collapse"] != rb["hinges_at_collapse"]:
            problems.append(f"hinges {ra['hinges_at_collapse']} / {rb['hinges_at_collapse']}")
        if ra["mode"] != rb["mode"]:
            msg = f"mode '{ra['mode']}' / '{rb['mode']}'"
            if "--allow-mode" in argv:
                print(f"{name}: {msg} (allowed)")
            else:
                problems.append(msg)
        if problems:
            bad += 1
            print(f"{name}: " + "; ".join(problems))
    print(f"{len(a)} cases, {bad} differ beyond rtol {rtol:g}; largest relative difference of "
          f"delta_u and the first limit {worst:.2e}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
