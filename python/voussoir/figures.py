"""Publication figures with matplotlib: each function returns a matplotlib Figure sized for a
journal column (3.5 in wide), and save() writes it as PNG, PDF and SVG with editable text (the
SVG's labels are <text> elements, the PDF's fonts TrueType).

A run's charts take a record (a path or an open voussoir.Record) or an in-process Result:
curves (the supports' forces against the support displacement), hinges (the open joints and
the hinges against it). A sweep's DataFrame (or read_table rows) gives domain; a Monte Carlo
DataFrame (voussoir.montecarlo, or samples.csv read by pandas) gives fragility, convergence and
hinge_histogram. Axes end where the physics does: the displacement charts stop at the end of
the collapse (the rigid fall, in which the support hardly moves, is drawn against time on its
own axes when asked for), probabilities run from 0 to 1."""
import math
import os

import numpy as np

COLUMN_IN = 3.5  # one journal column, inches
STYLE = {"font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8, "legend.fontsize": 7,
         "xtick.labelsize": 7, "ytick.labelsize": 7, "lines.linewidth": 1.0,
         "lines.markersize": 3.5,
         "axes.linewidth": 0.6, "savefig.dpi": 300,
         "svg.fonttype": "none",  # SVG text stays text
         "pdf.fonttype": 42, "ps.fonttype": 42}  # TrueType in PDF and PS: editable
SIDES = {"I": "intrados", "E": "extrados"}
BAND_ALPHA = 0.05  # the fragility band: Dvoretzky-Kiefer-Wolfowitz, 95 % simultaneous


def _styled(fn):
    """Draw inside STYLE (legends and labels take their sizes when made)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kw):
        import matplotlib
        with matplotlib.rc_context(STYLE):
            return fn(*args, **kw)
    return wrapper


_FIGURE = None


def _figure_class():
    """matplotlib's Figure whose savefig writes in STYLE: the text stays editable however the
    figure is saved (fig.savefig, save(), PdfPages)."""
    global _FIGURE
    if _FIGURE is None:
        import matplotlib
        from matplotlib.figure import Figure

        class VoussoirFigure(Figure):
            def savefig(self, *args, **kw):
                with matplotlib.rc_context(STYLE):
                    return super().savefig(*args, **kw)
        _FIGURE = VoussoirFigure
    return _FIGURE


def figure(height_in=2.6, width_in=COLUMN_IN, rows=1, sharex=False):
    """A Figure of width_in x height_in inches with `rows` axes (a list when rows > 1), in the
    module's STYLE, without pyplot (no global state: safe in threads; show it in a notebook
    as the cell's value, or with fig.savefig)."""
    import matplotlib
    with matplotlib.rc_context(STYLE):
        fig = _figure_class()(figsize=(width_in, height_in), layout="constrained")
        axes = fig.subplots(rows, 1, sharex=sharex)
    return fig, axes


def save(fig, stem, formats=("png", "pdf", "svg")):
    """Write fig as stem.png, stem.pdf, stem.svg (or the formats given), text editable;
    returns the paths written."""
    import matplotlib
    paths = []
    with matplotlib.rc_context(STYLE):  # also for a figure not made here
        for fmt in formats:
            path = f"{os.fspath(stem)}.{fmt}"
            fig.savefig(path, format=fmt)
            paths.append(path)
    return paths


# --- a run: a record or a Result as the same columns -------------------------------------------

class _Run:
    """What the run charts need, from a record or a Result: delta (mm), time (s), phase
    (0 quasi-static, 1 dynamic, 2 fall), forces {name: N}, open joints per row (record only),
    hinges [(label, side, joints_onset, joints, delta_onset_mm)], limits_mm, collapse_mm."""

    def __init__(self, src):
        from .record import Record
        if hasattr(src, "history"):
            self._result(src)
        elif isinstance(src, Record):
            self._record(src)
        else:
            with Record(src) as r:
                self._record(r)

    def _result(self, res):
        h = res.history
        if len(h) == 0:
            raise ValueError("the Result keeps no history: run with history=True")
        self.delta, self.time = h["delta"] / 1e-3, h["time"]
        self.phase = np.asarray(h["phase"], int)
        self.forces = {n: h[n] for n in ("left_Fx", "left_Fz", "right_Fx", "right_Fz")}
        self.open_joints = None
        self.hinges = [(x.label, x.side, x.joints_onset, x.joints, x.delta_onset_mm)
                       for x in res.hinges]
        self.limits_mm = [p.delta_mm for p in res.limit_points if not p.collapse]
        self.collapse_mm = res.collapse.delta_mm if res.collapse is not None else math.nan

    def _record(self, r):
        self.delta, self.time = r.series("delta").values / 1e-3, r.time().values
        names = r.series_names()
        self.phase = (r.series("phase").values.astype(int) if "phase" in names
                      else np.zeros(len(self.delta), int))
        reac = r.series("reactions")
        self.forces = {n: reac.column(n).values for n in ("left_Fx", "left_Fz", "right_Fx",
                                                          "right_Fz")}
        self.open_joints = r.series("joint_hinge").values if "joint_hinge" in names else None
        s = r.summary()
        self.hinges = [(h["label"], h["side"], _joints(h["name_onset"]), _joints(h["name"]),
                        h["delta_onset"] / 1e-3) for h in s.get("hinges", [])]
        lps = s.get("limit_points", [])
        self.limits_mm = [p["delta"] / 1e-3 for p in lps if p["kind"] != "collapse"]
        c = s.get("collapse", {})
        self.collapse_mm = c["delta"] / 1e-3 if c.get("found") else math.nan


def _joints(name):
    """'9-10-I' -> (9, 10)."""
    return tuple(int(x) for x in name.split("-")[:-1])


def _marks(ax, run):
    for i, d in enumerate(run.limits_mm):
        ax.axvline(d, color="0.6", linewidth=0.6, linestyle=":",
                   label="limit point (snap)" if i == 0 else None)
    if math.isfinite(run.collapse_mm):
        ax.axvline(run.collapse_mm, color="0.3", linewidth=0.6, linestyle="--", label="collapse")


FORCE_STYLE = {"left_Fx": ("C0", "--"), "left_Fz": ("C0", "-"), "right_Fx": ("C3", "--"),
               "right_Fz": ("C3", "-")}


@_styled
def curves(src, fall=False):
    """The supports' forces on the arch (N: Fx dashed, Fz solid; left blue, right red) against
    the support displacement delta (mm), quasi-static path and collapse (the dynamic phases) only,
    with the limit points and the collapse marked. fall=True adds a second panel: the same forces
    during the rigid fall against the time since it began (s); delta hardly moves then, and
    against it the fall would be vertical lines. src: a record (path or Record) or a Result (with its history)."""
    run = _Run(src)
    has_fall = fall and bool((run.phase == 2).any())
    fig, axes = figure(height_in=4.4 if has_fall else 2.6, rows=2 if has_fall else 1)
    ax = axes[0] if has_fall else axes
    path = run.phase != 2
    for name, v in run.forces.items():
        c, ls = FORCE_STYLE[name]
        ax.plot(run.delta[path], v[path], color=c, linestyle=ls, label=name.replace("_", " "))
    _marks(ax, run)
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel("force on the arch (N)")
    ax.legend(ncols=2, frameon=False)
    if has_fall:
        f = run.phase == 2
        t = run.time[f] - run.time[f][0]
        for name, v in run.forces.items():
            c, ls = FORCE_STYLE[name]
            axes[1].plot(t, v[f], color=c, linestyle=ls)
        axes[1].set_xlim(0, t[-1])
        axes[1].set_xlabel("time since the fall began (s)")
        axes[1].set_ylabel("force on the arch (N)")
    return fig


@_styled
def hinges(src):
    """Hinge evolution against the support displacement (mm), quasi-static path and collapse:
    each hinge from its onset (joints then) to the end (joints at the collapse), labelled A..E,
    marker by side (intrados o, extrados s); from a record also every open joint at every state
    (dots, blue intrados, red extrados). src: a record or a Result."""
    run = _Run(src)
    fig, ax = figure()
    path = run.phase != 2
    end = run.delta[path].max() if path.any() else 0.0
    if run.open_joints is not None:
        for code, side, colour in ((1, "I", "C0"), (2, "E", "C3")):
            rows, joints = np.nonzero((run.open_joints == code) & path[:, None])
            ax.scatter(run.delta[rows], joints + 1, s=0.5, color=colour, linewidths=0,
                       label=f"open, hinge at the {SIDES[side]}", rasterized=True)
    for label, side, j0, j1, d0 in run.hinges:
        y0, y1 = np.mean(j0), np.mean(j1)
        ax.plot([d0, end], [y0, y1], color="k", linewidth=0.8,
                marker="o" if side == "I" else "s", markersize=3, markevery=[0])
        ax.annotate(f"{label} {'-'.join(map(str, j1))}-{side}", (end, y1), fontsize=6,
                    xytext=(2, 0), textcoords="offset points", va="center")
    _marks(ax, run)
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel("joint")
    if run.open_joints is not None:
        ax.legend(frameon=False, markerscale=6)
    return fig


# --- studies ----------------------------------------------------------------------------------

def _rows(table):
    """A DataFrame or a list of dicts -> list of dicts."""
    return table.to_dict("records") if hasattr(table, "to_dict") else list(table)


@_styled
def domain(table):
    """A sweep's limit displacement domain: collapse dz/L against dx/L (%), one line per k_n
    through the directions (table: voussoir.sweep's DataFrame or read_table rows)."""
    from .draw import draw_domain
    fig, ax = figure(height_in=3.0)
    draw_domain(_rows(table), ax=ax)
    ax.legend(frameon=False)
    for line in ax.get_lines():  # the axes start at 0 (no collapse at a negative travel here)
        if len(line.get_xdata()) and min(line.get_xdata()) < 0:
            break
    else:
        ax.set_xlim(left=0)
    if all(min(ln.get_ydata(), default=0) >= 0 for ln in ax.get_lines()):
        ax.set_ylim(bottom=0)
    return fig


def _mc(table):
    """Monte Carlo samples -> (delta_u of the collapses (mm), valid count: collapses + samples
    without one within support.max_mm; failed samples left out)."""
    rows = _rows(table)
    du = np.array([r["delta_u_mm"] for r in rows if r["status"] == "collapse"], float)
    valid = sum(1 for r in rows if r["status"] in ("collapse", "max_displacement"))
    return du, valid


def fragility_curve(table, points=200):
    """(delta_mm, p, lo, hi): the empirical probability of collapse at a support displacement
    (collapses at or below it over the samples that did not fail) and its Dvoretzky-Kiefer-
    Wolfowitz band (95 % simultaneous, half-width sqrt(ln(2/0.05) / (2 n))), clipped to [0, 1].
    delta runs from 0 to 1.2 times the largest collapse."""
    du, valid = _mc(table)
    if valid == 0:
        raise ValueError("no sample ended in a collapse or at support.max_mm")
    top = 1.2 * du.max() if du.size else 1.0
    d = np.linspace(0.0, top, points)
    p = (du[None, :] <= d[:, None]).sum(axis=1) / valid
    eps = math.sqrt(math.log(2.0 / BAND_ALPHA) / (2.0 * valid))
    return d, p, np.clip(p - eps, 0, 1), np.clip(p + eps, 0, 1)


@_styled
def fragility(table):
    """Fragility: the probability of collapse against the support displacement (mm), with its
    95 % DKW band shaded; the probability axis is 0..1 (table: voussoir.montecarlo's DataFrame
    or the rows of samples.csv)."""
    d, p, lo, hi = fragility_curve(table)
    fig, ax = figure()
    ax.fill_between(d, lo, hi, step="post", color="C0", alpha=0.2, linewidth=0,
                    label="DKW 95 % band")
    ax.step(d, p, where="post", color="C0", label="P(collapse)")
    ax.set_ylim(0.0, 1.0)
    ax.set_xlim(0.0, d[-1])
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel("probability of collapse")
    ax.legend(frameon=False, loc="upper left")
    return fig


@_styled
def convergence(table, span_mm=None):
    """Running statistics of a Monte Carlo study against the number of samples: the mean and the
    5 % quantile of delta_u (over the span, %, when span_mm is given; else mm) and its
    coefficient of variation, on two panels. The samples are taken in their order."""
    rows = _rows(table)
    v = np.array([r["delta_u_mm"] if r["status"] == "collapse" else math.nan for r in rows],
                 float)
    scale, unit = (100.0 / span_mm, "delta_u / L (%)") if span_mm else (1.0, "delta_u (mm)")
    n = np.arange(1, len(v) + 1)
    mean, q05, cov = (np.full(len(v), math.nan) for _ in range(3))
    for k in n:
        w = v[:k][np.isfinite(v[:k])] * scale
        if w.size:
            mean[k - 1], q05[k - 1] = w.mean(), np.quantile(w, 0.05)
            cov[k - 1] = w.std(ddof=1) / w.mean() if w.size > 1 else math.nan
    fig, (a1, a2) = figure(height_in=3.4, rows=2, sharex=True)
    a1.plot(n, mean, color="C0", label="mean")
    a1.plot(n, q05, color="C1", linestyle="--", label="5 % quantile")
    a1.set_ylabel(unit)
    a1.legend(frameon=False)
    a2.plot(n, cov, color="C2")
    a2.set_ylabel("CoV of delta_u")
    a2.set_xlabel("samples")
    return fig


@_styled
def hinge_histogram(table, joints=None):
    """Where each hinge (A..E) sat at the collapse over a Monte Carlo study's samples: the number
    of collapses with that hinge at each joint, stacked by label (joints: the number of joints,
    voussoirs + 1, for the axis; else up to the largest joint seen)."""
    rows = [r for r in _rows(table) if r["status"] == "collapse"]
    counts = {}
    for label in "ABCDE":
        js = [int(r[label].split("-")[0]) for r in rows  # "9-I"; empty (or NaN from a csv)
              if isinstance(r.get(label), str) and r[label]]
        if js:
            counts[label] = np.bincount(js)
    top = joints or max((len(c) - 1 for c in counts.values()), default=1)
    fig, ax = figure()
    bottom = np.zeros(top)
    for label, c in counts.items():  # stacked: a joint's bar is its collapses, by label
        y = np.zeros(top + 1)
        n = min(len(c), top + 1)
        y[:n] = c[:n]
        ax.bar(np.arange(1, top + 1), y[1:], width=0.8, bottom=bottom, label=label)
        bottom += y[1:]
    ax.set_ylim(0, 1.2 * max(bottom.max(), 1))
    from matplotlib.ticker import MaxNLocator
    ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # counts
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))  # joints
    ax.set_xlim(0.5, top + 0.5)
    ax.set_xlabel("joint")
    ax.set_ylabel("collapses with the hinge there")
    ax.legend(frameon=False, ncols=len(counts) or 1)
    return fig

