#!/usr/bin/env python3
"""The include graph between the layers of src/, before and after a change, as one figure:
each layer a box (the lowest at the bottom), each arrow a pair of layers with the number of
#include lines that run along it; an arrow against the order (UPWARD) red, one the engine must
never have (the INI case included by the model or the solvers) orange.

usage: runs/layers_figure.py BEFORE_REV OUT.png   (today's tree is the "after")
e.g.   runs/layers_figure.py ac21d2b docs/layers.png
"""
import os
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
LAYERS = ["base", "case", "model", "solve", "fall", "run", "record", "plot", "mpi", "plugin",
          "study", "cli"]
LINE = re.compile(r"^(\w+)\s+->\s+(\w+)\s+(\d+)(.*)$")


def edges(*extra):
    out = subprocess.run([os.path.join(ROOT, ".ci", "layers"), "--graph", *extra],
                         capture_output=True, text=True, check=True).stdout
    res = []
    for ln in out.splitlines():
        m = LINE.match(ln.strip())
        if m:
            res.append((m.group(1), m.group(2), int(m.group(3)), "UPWARD" in m.group(4),
                        "NEVER" in m.group(4)))
    return res


def panel(ax, es, title):
    y = {l: i for i, l in enumerate(LAYERS)}
    ax.set_xlim(-1.9, 1.3)
    ax.set_ylim(-0.8, len(LAYERS) - 0.2)
    ax.axis("off")
    for l, i in y.items():
        ax.add_patch(FancyBboxPatch((-0.45, i - 0.28), 0.9, 0.56, boxstyle="round,pad=0.02",
                                    fc="#eef3f8", ec="#44607a", lw=0.8))
        ax.text(0, i, l, ha="center", va="center", fontsize=8)
    n_up = n_never = 0
    for a, b, k, up, never in es:
        ya, yb = y[a], y[b]
        colour = "#c0392b" if up else ("#e67e22" if never else "#9aa5b1")
        n_up += k if up else 0
        n_never += k if never else 0
        side = 1 if up or never else -1  # bad arrows on the right, the rest on the left
        bend = 0.6 / (1.0 + 0.3 * abs(ya - yb))  # a long arrow bulges no further than a short one
        arr = FancyArrowPatch((side * 0.47, ya), (side * 0.47, yb),
                              connectionstyle=f"arc3,rad={-side * bend}",
                              arrowstyle="-|>", mutation_scale=7, lw=0.4 + 0.25 * min(k, 8) ** 0.5,
                              color=colour, alpha=0.9)
        ax.add_patch(arr)
    ax.set_title(f"{title}\n{n_up} includes upward, {n_never} of the INI case in the engine",
                 fontsize=8)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rev, out = sys.argv[1], sys.argv[2]
    fig, axes = plt.subplots(1, 2, figsize=(6.5, 5.2))
    panel(axes[0], edges("--at", rev), f"before ({rev[:7]}), files in the layers they moved to")
    panel(axes[1], edges(), "after (today's tree)")
    fig.text(0.5, 0.01, "grey: an include downward (left); red: upward; orange: the engine "
             "including the INI case (right)", ha="center", fontsize=7)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
