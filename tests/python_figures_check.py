"""voussoir.figures on real runs (tests/test_python_figures.sh): every function returns a
matplotlib Figure, save() writes PNG, PDF and SVG with editable text, the axes end where the
physics does (probabilities 0..1; the displacement curves stop at the end of the collapse, the
quasi-static path monotone in delta and ending at the Result's collapse displacement), and the
fragility curve is the empirical distribution of the samples' delta_u, computed here.
usage: python3 python_figures_check.py CASE.ini OUT_DIR (VOUSSOIR: the program)"""
import math
import os
import re
import sys
import zlib

import numpy as np
from matplotlib.figure import Figure

import voussoir
from voussoir import figures

case_path, out = sys.argv[1], sys.argv[2]


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def check_saved(fig, name):
    """save() writes the three formats; the SVG's text is <text> elements (not paths), the PDF
    embeds TrueType fonts (Type 42), the PNG is a PNG."""
    if not isinstance(fig, Figure):
        fail(f"{name}: {type(fig)} is not a matplotlib Figure")
    w, h = fig.get_size_inches()
    if abs(w - figures.COLUMN_IN) > 1e-9 or not 1.5 < h < 5:
        fail(f"{name}: {w} x {h} in, not a journal column")
    paths = figures.save(fig, os.path.join(out, name))
    if [os.path.splitext(p)[1] for p in paths] != [".png", ".pdf", ".svg"]:
        fail(f"{name}: wrote {paths}")
    for p in paths:
        if not os.path.isfile(p) or os.path.getsize(p) < 500:
            fail(f"{p}: missing or empty")
    png, pdf, svg = (open(p, "rb").read() for p in paths)
    if png[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{name}.png is not a PNG")
    texts = re.findall(rb"<text[ >]", svg)
    if len(texts) < 4:
        fail(f"{name}.svg: {len(texts)} <text> elements (text drawn as paths?)")
    if not pdf.startswith(b"%PDF") or b"/FontFile2" not in pdf:
        fail(f"{name}.pdf: no embedded TrueType font (pdf.fonttype 42)")
    if b"/Subtype /Type3" in pdf:
        fail(f"{name}.pdf: Type 3 fonts (text not editable)")
    fig.savefig(os.path.join(out, name + "_direct.svg"))  # savefig itself keeps the text
    if len(re.findall(rb"<text[ >]", open(os.path.join(out, name + "_direct.svg"), "rb").read())) \
            != len(texts):
        fail(f"{name}: fig.savefig('.svg') draws the text as paths")
    return len(texts)


def lines_of(ax):
    return [(ln.get_xdata(), ln.get_ydata(), ln.get_label()) for ln in ax.get_lines()]


# A run in process, and the same case's record through the program.
res = voussoir.run(case_path)
if res.collapse is None:
    fail(f"{case_path}: no collapse")
rec = os.path.join(out, "ref.h5")
voussoir.cli.run(case_path, record=rec)
du = res.collapse.delta_mm
h = res.history
print(f"run: collapse at {du:.3f} mm; states {len(h)} (quasi-static {int((h['phase'] == 0).sum())}"
      f", dynamic {int((h['phase'] == 1).sum())}, fall {int((h['phase'] == 2).sum())})")
if not (h["phase"] == 2).any():
    fail("the run has no fall: the curves' check below needs one")

for src, tag in ((res, "result"), (rec, "record")):
    fig = figures.curves(src)
    ax = fig.axes[0]
    series = [(x, y, lab) for x, y, lab in lines_of(ax) if lab.startswith(("left", "right"))]
    if sorted(lab for _, _, lab in series) != ["left Fx", "left Fz", "right Fx", "right Fz"]:
        fail(f"curves ({tag}): series {[lab for _, _, lab in series]}")
    # the plotted x-data is the history without the fall: no vertical smear at the end
    keep = h["phase"] != 2
    qs = h["phase"][keep] == 0
    for x, y, lab in series:
        x = np.asarray(x)
        if len(x) != int(keep.sum()):
            fail(f"curves ({tag}): {lab} has {len(x)} points, the path without the fall "
                 f"{int(keep.sum())}")
        if x.max() > h["delta"][keep].max() * 1e3 * (1 + 1e-12):
            fail(f"curves ({tag}): {lab} runs to {x.max()} mm, beyond the end of the collapse")
        xq = x[qs]
        if not (np.diff(xq) >= 0).all():
            fail(f"curves ({tag}): quasi-static delta not monotone")
        if abs(xq[-1] - du) > 1e-9 * du:
            fail(f"curves ({tag}): the quasi-static path ends at {xq[-1]} mm, collapse {du} mm")
    # on the quasi-static path the supports carry the weight: Fz left + right = W
    fz = np.asarray(series[[s[2] for s in series].index("left Fz")][1]) + \
        np.asarray(series[[s[2] for s in series].index("right Fz")][1])
    W = fz[qs][0]
    if np.abs(fz[qs] - W).max() > 1e-6 * W:
        fail(f"curves ({tag}): Fz sum varies on the quasi-static path")
    marks = [ln for ln in ax.get_lines() if ln.get_label() == "collapse"]
    if len(marks) != 1 or abs(marks[0].get_xdata()[0] - du) > 1e-9 * du:
        fail(f"curves ({tag}): the collapse mark is not at {du} mm")
    n = check_saved(fig, f"curves_{tag}")
    fig2 = figures.curves(src, fall=True)
    fall_x = np.asarray(fig2.axes[1].get_lines()[0].get_xdata())
    tf = h["time"][h["phase"] == 2]
    if len(fig2.axes) != 2 or not np.allclose(fall_x, tf - tf[0], rtol=0, atol=1e-9):
        fail(f"curves ({tag}, fall=True): the fall is not its own panel against time")
    check_saved(fig2, f"curves_fall_{tag}")
    fig = figures.hinges(src)
    labels = sorted(t.get_text()[0] for t in fig.axes[0].texts)
    if labels != sorted(x.label for x in res.hinges):
        fail(f"hinges ({tag}): labels {labels}, the run's {[x.label for x in res.hinges]}")
    check_saved(fig, f"hinges_{tag}")
    print(f"curves, hinges from the {tag}: quasi-static path monotone, ends at the collapse "
          f"{du:.3f} mm, no fall rows on the delta axis; Fz sum = {W:.4f} N throughout; "
          f"hinges {' '.join(labels)}; {n} SVG <text> elements")

# A sweep's domain from the DataFrame directly.
arch = voussoir.Case.from_file(case_path, arch__voussoirs=15, joints__kn_N_mm3=48)
table = voussoir.sweep(arch, alpha=[0, 45, 90], jobs=2)
fig = figures.domain(table)
pts = [ln for ln in fig.axes[0].get_lines() if ln.get_linestyle() != "None"]  # not the modes' marks
ok = table[table["status"] == "collapse"]
if len(pts) != 1 or not np.allclose(pts[0].get_xdata(), ok["dz_over_L_pct"]):
    fail("domain: not the sweep's collapses")
check_saved(fig, "domain")
print(f"domain: {len(ok)} collapses of the sweep's DataFrame drawn")

# Monte Carlo: fragility, convergence, hinge histogram.
mc = voussoir.montecarlo(voussoir.Case.from_file(case_path, arch__voussoirs=15,
                                                  imperfections__kn_cov=0.3), samples=12,
                         seed=3, jobs=2)
fig = figures.fragility(mc)
ax = fig.axes[0]
lo, hi = ax.get_ylim()
if (lo, hi) != (0.0, 1.0):
    fail(f"fragility: probability axis {lo}..{hi}")
step = [ln for ln in ax.get_lines() if ln.get_label() == "P(collapse)"][0]
d, p = np.asarray(step.get_xdata()), np.asarray(step.get_ydata())
if p.min() < 0 or p.max() > 1:
    fail("fragility: probabilities outside [0, 1]")
u = mc.loc[mc["status"] == "collapse", "delta_u_mm"].to_numpy()
valid = int(mc["status"].isin(["collapse", "max_displacement"]).sum())
want = np.array([np.count_nonzero(u <= x) / valid for x in d])  # the empirical CDF, here
if not np.array_equal(p, want) or p[-1] != len(u) / valid:
    fail("fragility: not the empirical distribution of the samples' delta_u")
band = ax.collections[0].get_paths()[0].vertices
eps = math.sqrt(math.log(2 / 0.05) / (2 * valid))
if band[:, 1].min() < 0 or band[:, 1].max() > 1 or not np.isclose(band[:, 1].max(), min(1, 1 + eps) if p[-1] == 1 else p.max() + eps):
    fail("fragility: the band is not p +- the DKW half-width clipped to [0, 1]")
check_saved(fig, "fragility")
fig = figures.convergence(mc, span_mm=arch.span_mm)
mean = fig.axes[0].get_lines()[0].get_ydata()
if not np.isclose(mean[-1], 100 * u.mean() / arch.span_mm):
    fail(f"convergence: final mean {mean[-1]}, samples' {100 * u.mean() / arch.span_mm}")
check_saved(fig, "convergence")
fig = figures.hinge_histogram(mc, joints=16)
bars = {c.get_label(): sum(b.get_height() for b in c) for c in fig.axes[0].containers}
for label, total in bars.items():
    if total != (mc.loc[mc["status"] == "collapse", label] != "").sum():
        fail(f"hinge_histogram: {label} counts {total}")
check_saved(fig, "hinge_histogram")
print(f"montecarlo: {len(mc)} samples, {len(u)} collapses; fragility = empirical CDF on 0..1, "
      f"DKW band +-{eps:.3f}; convergence mean {mean[-1]:.2f} %; hinges {bars}")
print("figures: ok")
