"""Publication figures with matplotlib: each function returns a matplotlib Figure sized for a
journal column (3.5 in wide), and save() writes it as PNG, PDF and SVG with editable text (the
SVG's labels are <text> elements, the PDF's fonts TrueType).

A run's charts take a record (a path or an open voussoir.Record) or an in-process Result:
curves (the supports' forces against the support displacement), hinges (the open joints and
the hinges against it); a mortared run's record also gives cracks (each joint's cracked length
against it). A sweep's DataFrame (or read_table rows) gives domain; a Monte Carlo
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
        from ..record import Record
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
    for i, d in enumerate(x for x in run.limits_mm if math.isfinite(x)):
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


@_styled
def cracks(src):
    """A mortared run's cracks: the length of each joint cracked through (from the intrados plus
    from the extrados, mm; /observables/joint_crack) against the support displacement delta
    (mm), quasi-static path and collapse, one line per joint that cracked, coloured by its
    number (a length counts once cracked through: past the softening's end, so a joint's line
    leaves 0 after its crack_initiated event, where its stress reached f_t); the first crack (the JSON's first_crack) marked, the limit points and the collapse
    as in curves. src: a record (path or Record); ValueError when no joint cracked."""
    from ..record import Record
    if not isinstance(src, Record):
        with Record(src) as r:
            return cracks(r)
    run = _Run(src)
    crack = src.joint_crack().values.sum(axis=2) / 1e-3  # rows x joints, mm
    path = run.phase != 2
    cracked = np.nonzero(crack[path].max(axis=0, initial=0.0) > 0)[0]
    if cracked.size == 0:
        raise ValueError("no joint cracked (a dry run, or the mortar held): no cracks chart")
    import matplotlib
    fig, ax = figure()
    nj = crack.shape[1]
    cmap = matplotlib.colormaps["viridis"]
    norm = matplotlib.colors.Normalize(1, nj)
    for j in cracked:
        ax.plot(run.delta[path], crack[path, j], color=cmap(norm(j + 1)), linewidth=0.7)
    first = src.first_crack()
    if first is not None:
        ax.plot([first.delta_mm], [0.0], marker="v", color="k", linestyle="none",
                label=f"first crack: joint {first.joint}-{first.side}")
    _marks(ax, run)
    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, label="joint")
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel("cracked length (mm)")
    ax.set_ylim(bottom=0)
    ax.legend(frameon=False)
    return fig


# --- studies ----------------------------------------------------------------------------------

def _rows(table):
    """A DataFrame or a list of dicts -> list of dicts."""
    return table.to_dict("records") if hasattr(table, "to_dict") else list(table)


MODES = (("I", "mode I", "o"), ("II", "mode II", "s"), ("III", "mode III", "^"),
         ("", "no mode (sides match none)", "D"))


def _collapses(table):
    """A sweep's collapses (rows with status collapse and a finite dz/L), sorted by k_n then
    alpha (a column the sweep did not vary reads as NaN: the case's value)."""
    rows = [r for r in _rows(table) if r.get("status") == "collapse"
            and _finite(r.get("dz_over_L_pct"))]
    for r in rows:
        for k in ("joints.kn_N_mm3", "support.alpha_deg"):
            r[k] = float(r[k]) if _finite(r.get(k)) else math.nan
    return sorted(rows, key=lambda r: (_nan_first(r["joints.kn_N_mm3"]),
                                       _nan_first(r["support.alpha_deg"])))


def _finite(v):
    try:
        return math.isfinite(float(v))
    except (TypeError, ValueError):
        return False


def _nan_first(v):
    return (0, 0.0) if math.isnan(v) else (1, v)


def _mode_of(r):
    m = r.get("mode")
    return m if m in ("I", "II", "III") else ""


def _study_chart(ax, rows, x, y, per_kn):
    """Lines through the points (one per k_n, or one through all), then the points again, one
    marker series per mode present (labelled "mode I".., linestyle none)."""
    groups = {}
    for r, xi, yi in zip(rows, x, y):
        key = r["joints.kn_N_mm3"] if per_kn else None
        groups.setdefault(("nan" if key is not None and math.isnan(key) else key), []).append(
            (xi, yi))
    for i, (kn, pts) in enumerate(groups.items()):
        label = (None if kn is None else "k_n of the case" if kn == "nan"
                 else f"k_n = {kn:g} N/mm³")
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color=f"C{i}", label=label)
    for code, name, marker in MODES:
        sel = [(xi, yi) for r, xi, yi in zip(rows, x, y) if _mode_of(r) == code]
        if sel:
            ax.plot([p[0] for p in sel], [p[1] for p in sel], linestyle="none", marker=marker,
                    markerfacecolor="white", markeredgecolor="k", markersize=4, label=name)


@_styled
def domain(table):
    """A sweep's limit displacement domain: the support displacement at collapse, spreading dx/L
    against settlement dz/L (%), one line per k_n through the directions alpha, each point marked
    by its mode (I, II, III). table: voussoir.sweep's DataFrame, read_table rows or
    read_sweep(summary.h5)."""
    rows = _collapses(table)
    if not rows:
        raise ValueError("no run of the sweep collapsed: no domain to draw")
    fig, ax = figure(height_in=3.0)
    _study_chart(ax, rows, [r["dz_over_L_pct"] for r in rows],
                 [r["dx_over_L_pct"] for r in rows], per_kn=True)
    ax.set_xlabel("collapse settlement dz/L (%)")
    ax.set_ylabel("collapse spreading dx/L (%)")
    ax.legend(frameon=False)
    lines = [ln for ln in ax.get_lines() if len(ln.get_xdata())]
    if all(min(ln.get_xdata()) >= 0 for ln in lines):  # from 0 when no travel is negative
        ax.set_xlim(left=0)
    if all(min(ln.get_ydata()) >= 0 for ln in lines):
        ax.set_ylim(bottom=0)
    return fig


def sensitivity_axis(table):
    """'alpha' when the sweep's collapses take at least two directions, else 'kn' when they take
    at least two k_n, else None (nothing to draw against)."""
    rows = _collapses(table)
    for key, name in (("support.alpha_deg", "alpha"), ("joints.kn_N_mm3", "kn")):
        if len({r[key] for r in rows if not math.isnan(r[key])}) >= 2:
            return name
    return None


@_styled
def sensitivity(table):
    """A sweep's collapse displacement delta_u/L = hypot(dz/L, dx/L) (%) against the direction
    alpha (deg), one line per k_n, or against k_n (N/mm^3) when the sweep varies only k_n; each
    point marked by its mode. ValueError when the sweep varies neither."""
    rows = _collapses(table)
    axis = sensitivity_axis(rows)
    if axis is None:
        raise ValueError("the sweep's collapses vary neither alpha nor k_n")
    by_alpha = axis == "alpha"
    x = [r["support.alpha_deg" if by_alpha else "joints.kn_N_mm3"] for r in rows]
    y = [math.hypot(r["dz_over_L_pct"], r["dx_over_L_pct"]) for r in rows]
    fig, ax = figure()
    _study_chart(ax, rows, x, y, per_kn=by_alpha)
    ax.set_xlabel("direction alpha from the vertical (deg)" if by_alpha
                  else "joint normal stiffness k_n (N/mm³)")
    ax.set_ylabel("collapse displacement delta_u/L (%)")
    ax.set_ylim(bottom=0)
    ax.legend(frameon=False)
    return fig


def _mc(table):
    """Monte Carlo samples -> (delta_u of the collapses (mm), valid count: collapses + samples
    without one within support.max_mm; failed samples left out)."""
    rows = _rows(table)
    du = np.array([r["delta_u_mm"] for r in rows if r["status"] == "collapse"], float)
    valid = sum(1 for r in rows if r["status"] in ("collapse", "max_displacement"))
    return du, valid


def fragility_curve(table, points=201):
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



# --- a load run --------------------------------------------------------------------------------

def _load_curve(src):
    """A LoadCurve from a load run's record (path or Record), a Result or a LoadCurve."""
    from ..record import LoadCurve, Record
    if isinstance(src, LoadCurve):
        return src
    if hasattr(src, "load_curve"):
        return src.load_curve()
    with Record(src) as r:
        return r.load_curve()


@_styled
def load_deflection(src):
    """A load run's load-deflection curve (analysis.type = load): the load factor lambda against
    the loads' displacement from where loading began (mm), at every equilibrium of the load
    path, the peak (the load factor at collapse) marked, and the first peak when it comes
    earlier (where load control would snap). src: the run's record (path or Record), its
    in-process Result or a LoadCurve."""
    lc = _load_curve(src)
    fig, ax = figure()
    u = lc.deflection / 1e-3
    ax.plot(u, lc.load_factor, color="C0", marker="o" if len(u) <= 40 else None,
            label="load path")
    if math.isfinite(lc.peak) and lc.peak > 0:
        ax.axhline(lc.peak, color="0.3", linewidth=0.6, linestyle="--",
                   label=f"collapse, lambda = {lc.peak:.4g}")
    if math.isfinite(lc.first_peak) and lc.first_peak > 0 and lc.first_peak < 0.999 * lc.peak:
        ax.axhline(lc.first_peak, color="0.6", linewidth=0.6, linestyle=":",
                   label=f"first peak, lambda = {lc.first_peak:.4g}")
    ax.set_xlabel("deflection under the load (mm)")
    ax.set_ylabel("load factor lambda")
    ax.set_ylim(bottom=0)
    if len(u) and u.min() >= 0:
        ax.set_xlim(left=0)
    ax.legend(frameon=False)
    return fig


# --- files the program writes ------------------------------------------------------------------

MC_STATUS = {0: "collapse", 1: "max_displacement", 2: "failed"}


def read_sweep(path):
    """A sweep's summary.h5 (/summary, the table voussoir sweep writes) as a list of dicts, the
    columns of summary.csv (texts decoded, numbers as floats)."""
    import h5py
    with h5py.File(path, "r") as f:
        t = _bounded(f, "summary", path)[()]
    if t.ndim != 1 or t.dtype.names is None:
        raise ValueError(f"/summary is not a sweep's summary table (a table of rank 1: rank "
                         f"{t.ndim})")
    return [{k: (_decode(r[k]) if t.dtype[k].kind in "SOU" else float(r[k]))
             for k in t.dtype.names} for r in t]


def _bounded(group, name, path):
    """group[name], a dataset whose declared size a reader may allocate: at most 2100 x the
    file's size + 16 MiB (what deflate's 1032:1 and a float read as a double allow; the
    program's readers check the same, docs/record.md), else ValueError naming it."""
    d = group[name]
    need = d.size * d.dtype.itemsize
    have = os.path.getsize(path)
    if need > 2100 * have + (16 << 20):
        raise ValueError(f"{d.name} declares more rows than the file holds ({need} bytes in a "
                         f"file of {have}; allowed: at most 2100 x its size + 16 MiB)")
    return d


def _decode(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def read_montecarlo(path):
    """A Monte Carlo study's summary.h5 (voussoir montecarlo) as (rows, span_mm): one dict per
    sample with the columns fragility, convergence and hinge_histogram read (sample, status
    'collapse' / 'max_displacement' / 'failed', delta_u_mm, dz_u_mm, dx_u_mm, mode,
    load_factor, and A..E: the hinge's middle joint and side at the collapse, '9-I', or '');
    span_mm: the arch's span (None when the files do not say)."""
    import h5py
    with h5py.File(path, "r") as f:
        g = f["samples"]
        col = {k: _bounded(g, k, path)[()] for k in ("sample", "status", "delta_u", "dz_u",
                                                    "dx_u", "mode", "load_factor") if k in g}
        hj = _bounded(g, "hinge_joint", path)[()].reshape(len(col["status"]), -1)
        desc = _decode(f.attrs.get("description", ""))
    span = _mc_span_mm(path, desc)
    rows = []
    for i in range(len(col["status"])):
        r = {"sample": int(col["sample"][i]), "status": MC_STATUS.get(int(col["status"][i]), "?"),
             "delta_u_mm": col["delta_u"][i] / 1e-3, "dz_u_mm": col["dz_u"][i] / 1e-3,
             "dx_u_mm": col["dx_u"][i] / 1e-3, "mode": int(col["mode"][i]),
             "load_factor": float(col["load_factor"][i]) if "load_factor" in col else math.nan}
        for k, label in enumerate("ABCDE"[:hj.shape[1]]):
            j = int(hj[i, k])
            r[label] = "" if j == 0 else f"{abs(j)}-{'I' if j > 0 else 'E'}"
        rows.append(r)
    return rows, span


def _mc_span_mm(path, desc):
    """The span of a Monte Carlo study, mm: samples.csv's header beside summary.h5 (L_mm, in
    full), else summary.h5's description (six digits), else None."""
    import re
    csv = os.path.join(os.path.dirname(os.fspath(path)), "samples.csv")
    try:
        with open(csv) as f:
            m = re.search(r"\bL_mm=(\S+)", f.readline())
        if m:
            return float(m.group(1))
    except (OSError, ValueError):
        pass
    m = re.search(r"\bL ([0-9.eE+-]+) mm", desc)
    return float(m.group(1)) if m else None


def kind_of(path):
    """What an HDF5 file voussoir wrote is: 'record' (a run's), 'sweep' (a sweep's summary.h5),
    'montecarlo' (a Monte Carlo study's summary.h5); ValueError otherwise."""
    import h5py
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise ValueError(f"{path}: not an HDF5 file voussoir wrote ({e})") from None
    with f:
        if isinstance(f.get("summary"), h5py.Dataset):
            return "sweep"
        if "samples" in f and "fragility" in f:
            return "montecarlo"
        if "observables" in f and isinstance(f.get("summary"), h5py.Group):
            return "record"
    raise ValueError(f"{path}: neither a run's record, a sweep's summary.h5 nor a Monte Carlo "
                     "study's summary.h5")


def charts(path, out_dir, formats=("png", "pdf", "svg")):
    """The charts of a file voussoir wrote, saved in out_dir (created when absent) as
    NAME.FORMAT for each of formats: a run's record: curves, hinges (and load_deflection for a
    load run, cracks for a mortared run whose joints cracked); a sweep's summary.h5: domain,
    sensitivity (when the sweep varies alpha or k_n); a
    Monte Carlo summary.h5: fragility, convergence, hinge_histogram. Returns the paths written;
    ValueError for a file of none of these kinds."""
    kind = kind_of(path)
    figs = []
    if kind == "record":
        from ..record import Record
        with Record(path) as r:
            figs = [("curves", curves(r)), ("hinges", hinges(r))]
            if "summary/load" in r.file:
                figs.append(("load_deflection", load_deflection(r)))
            if r.mortared() and r.first_crack() is not None:
                figs.append(("cracks", cracks(r)))
    elif kind == "sweep":
        rows = read_sweep(path)
        figs = [("domain", domain(rows))]
        if sensitivity_axis(rows) is not None:
            figs.append(("sensitivity", sensitivity(rows)))
    else:
        rows, span = read_montecarlo(path)
        figs = [("fragility", fragility(rows)), ("convergence", convergence(rows, span)),
                ("hinge_histogram", hinge_histogram(rows))]
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for name, fig in figs:
        paths += save(fig, os.path.join(out_dir, name), formats)
    return paths


USAGE = """usage: python3 -m voussoir.figures FILE.h5 [-o DIR] [--format png,pdf,svg]
Draws the charts of a file voussoir wrote with matplotlib, each a journal column wide, as PNG,
PDF and SVG (text editable): a run's record: curves (the supports' forces against the support
displacement), hinges (the hinges and open joints against it), for a load run
(analysis.type = load) load_deflection, and for a mortared run whose joints cracked cracks (each
joint's cracked length against the support displacement); a sweep's summary.h5: domain (dx/L against dz/L per
k_n, the points marked by mode) and sensitivity (delta_u/L against alpha, or k_n); a Monte Carlo
study's summary.h5: fragility (with its 95 % band), convergence, hinge_histogram. DIR: default
FILE without .h5 and "_plots" (voussoir plot's). exit status: 0 done, 1 a figure could not be
written, 2 bad input, 3 matplotlib (or h5py, numpy) missing."""


def main(argv=None):
    """The command line (USAGE); returns the exit status."""
    import argparse
    import sys
    p = argparse.ArgumentParser(prog="python3 -m voussoir.figures", usage=USAGE.split("\n")[0][7:],
                                description=USAGE.split("\n", 1)[1],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("file")
    p.add_argument("-o", dest="dir")
    p.add_argument("--format", default="png,pdf,svg")
    try:
        a = p.parse_args(argv)
    except SystemExit as e:
        return 0 if e.code == 0 else 2
    formats = tuple(x for x in a.format.split(",") if x)
    bad = [x for x in formats if x not in ("png", "pdf", "svg")]
    if bad or not formats:
        print(f"voussoir.figures: --format {a.format}: allowed png, pdf, svg (comma-separated)",
              file=sys.stderr)
        return 2
    out = a.dir or (a.file[:-3] if a.file.endswith(".h5") else a.file) + "_plots"
    try:
        import h5py  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError as e:
        print(f"voussoir.figures: no charts: {e} (Debian: apt-get install python3-matplotlib "
              "python3-h5py python3-numpy)", file=sys.stderr)
        return 3
    try:
        kind_of(a.file)
    except ValueError as e:
        print(f"voussoir.figures: {e}", file=sys.stderr)
        return 2
    try:
        paths = charts(a.file, out, formats)
    except ValueError as e:  # a file of its kind with nothing to draw (no collapse)
        print(f"voussoir.figures: {a.file}: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"voussoir.figures: {out}: {e}", file=sys.stderr)
        return 1
    for path in paths:
        print(f"  {path}")
    return 0
