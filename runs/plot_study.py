#!/usr/bin/env python3
"""Figures of the seed studies from the summary tables of `voussoir sweep` (matplotlib).

usage: plot_study.py stiffness SUMMARY.csv OUT.png
       plot_study.py domain SUMMARY.csv OUT.png
       plot_study.py thickness SUMMARY.csv OUT.png RADIUS_MM
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f)]


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except ValueError:
        return None


def hinge_joints(text):
    """{'A': (joint, side), ...} from 'D:1-E A:9-10-I ...' (middle joint of a spread hinge)."""
    out = {}
    for item in text.split():
        label, rest = item.split(":", 1)
        *joints, side = rest.split("-")
        js = [int(j) for j in joints]
        out[label] = (js[len(js) // 2], side)
    return out


def stiffness(summary, png):
    rs = sorted((r for r in rows(summary) if r["status"] == "collapse"), key=lambda r: float(r["joints.kn_N_mm3"]))
    kn = [float(r["joints.kn_N_mm3"]) for r in rs]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    a1.semilogx(kn, [num(r["dz_over_L_pct"]) for r in rs], "o-", color="k")
    a1.set_ylabel("collapse settlement $\\delta_{z,u}/L$ (%)")
    a1.grid(True, which="both", alpha=0.3)
    a1.set_title("Reference specimen, settlement (alpha = 0): stiffness sensitivity")
    for label, colour in zip("ABCDE", ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]):
        xs, ys, ms = [], [], []
        for k, r in zip(kn, rs):
            h = hinge_joints(r["hinges_at_collapse"])
            if label in h:
                xs.append(k)
                ys.append(h[label][0])
                ms.append("^" if h[label][1] == "E" else "v")
        for x, y, m in zip(xs, ys, ms):
            a2.semilogx([x], [y], m, color=colour)
        if xs:
            a2.semilogx(xs, ys, "-", color=colour, alpha=0.5, label=label)
    a2.set_xlabel("joint normal stiffness $k_n$ (N/mm$^3$)")
    a2.set_ylabel("hinge joint at collapse")
    a2.legend(title="hinge (▲ E, ▼ I)", ncol=5, fontsize=8)
    a2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=130)


def domain(summary, png):
    rs = [r for r in rows(summary) if r["status"] == "collapse"]
    fig, ax = plt.subplots(figsize=(7, 6))
    for kn in sorted({float(r["joints.kn_N_mm3"]) for r in rs}):
        sel = sorted((r for r in rs if float(r["joints.kn_N_mm3"]) == kn), key=lambda r: float(r["support.alpha_deg"]))
        xs = [num(r["dz_over_L_pct"]) for r in sel]
        ys = [num(r["dx_over_L_pct"]) for r in sel]
        ax.plot(xs, ys, "o-", label=f"$k_n$ = {kn:g} N/mm$^3$")
        for r, x, y in zip(sel, xs, ys):
            ax.annotate(f"{float(r['support.alpha_deg']):g}°", (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("collapse settlement $\\delta_{z,u}/L$ (%)")
    ax.set_ylabel("collapse spreading $\\delta_{x,u}/L$ (%)")
    ax.set_title("Limit displacement domain (labels: direction alpha from the vertical)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=130)


def thickness(summary, png, radius):
    rs = sorted(rows(summary), key=lambda r: float(r["arch.thickness_mm"]))
    fig, ax = plt.subplots(figsize=(7, 5))
    ok = [r for r in rs if r["status"] == "collapse"]
    bad = [r for r in rs if r["status"] == "failed"]
    tr = lambda r: float(r["arch.thickness_mm"]) / (radius + float(r["arch.thickness_mm"]) / 2)  # noqa: E731
    ax.plot([tr(r) for r in ok], [num(r["dz_over_L_pct"]) for r in ok], "o-", color="k", label="collapse")
    if bad:
        ax.plot([tr(r) for r in bad], [0] * len(bad), "x", color="tab:red", label="cannot stand under self-weight")
    ax.axvline(0.107, color="tab:blue", ls="--", label="minimum thickness, t/R = 0.107 (Milankovitch)")
    ax.set_xlabel("thickness over centreline radius $t/R$")
    ax.set_ylabel("collapse settlement $\\delta_{z,u}/L$ (%)")
    ax.set_title("Semicircular arch, settlement: collapse against thickness")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=130)


if __name__ == "__main__":
    kind = sys.argv[1]
    if kind == "stiffness":
        stiffness(sys.argv[2], sys.argv[3])
    elif kind == "domain":
        domain(sys.argv[2], sys.argv[3])
    elif kind == "thickness":
        thickness(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    else:
        sys.exit(__doc__)
