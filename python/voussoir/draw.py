"""Pictures with matplotlib: the mechanism at a row, the reaction curves, a sweep's domain."""
import numpy as np


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(8, 4.5))
    return ax


def draw_mechanism(rec, row=-1, ax=None):
    """The blocks at a recorded row, true scale (mm), open joints drawn red."""
    ax = _axes(ax)
    pts = rec.block_outlines(row) * 1e3
    conn = rec.geometry("block_connectivity").values
    for c in conn:
        poly = pts[c]
        ax.fill(poly[:, 0], poly[:, 1], facecolor="0.85", edgecolor="0.3", linewidth=0.5)
    jp = rec.series("joint_points").values[row] * 1e3
    hinge = rec.series("joint_hinge").values[row]
    for j in np.nonzero(hinge)[0]:
        seg = jp[2 * j:2 * j + 2]
        ax.plot(seg[:, 0], seg[:, 1], color="red", linewidth=2)
    delta = rec.series("delta").values[row] * 1e3
    ax.set_title(f"support displacement {delta:.3f} mm (open joints red)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    return ax


def draw_curves(rec, ax=None):
    """Both force components at both supports (on the arch) against the support displacement."""
    ax = _axes(ax)
    delta = rec.series("delta").values * 1e3
    r = rec.series("reactions")
    units = r.unit.split(",")
    for i, name in enumerate(r.columns):
        if units[i].strip() == "N":  # the force components (moments have their own unit)
            ax.plot(delta, r.values[:, i], label=f"{name} (N)")
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel("force of the support on the arch (N)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return ax


def draw_domain(table, ax=None):
    """Limit displacement domain of a sweep (voussoir.sweep's DataFrame or read_table rows): collapse dz/L against dx/L, one
    line per k_n through the directions alpha. A column the sweep did not vary is not in its
    table: without joints.kn_N_mm3 the collapses are one line (the case's k_n), without
    support.alpha_deg they are joined in the table's order."""
    ax = _axes(ax)
    if hasattr(table, "to_dict"):  # a pandas DataFrame
        table = table.to_dict("records")
    rows = [r for r in table if r.get("status") == "collapse"]
    kns = {r.get("joints.kn_N_mm3") for r in rows}
    for kn in sorted(kns, key=lambda k: -1.0 if k is None else k):
        sel = [r for r in rows if r.get("joints.kn_N_mm3") == kn]
        if all("support.alpha_deg" in r for r in sel):
            sel.sort(key=lambda r: r["support.alpha_deg"])
        ax.plot([r["dz_over_L_pct"] for r in sel], [r["dx_over_L_pct"] for r in sel], "o-",
                label="the case's k_n" if kn is None else f"k_n = {kn:g} N/mm^3")
    ax.set_xlabel("collapse settlement dz/L (%)")
    ax.set_ylabel("collapse spreading dx/L (%)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return ax
