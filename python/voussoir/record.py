"""A voussoir HDF5 record as numpy arrays that carry their units."""
from dataclasses import dataclass

import h5py
import numpy as np


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


@dataclass
class Series:
    """One time series: values (rows first), its unit(s) and column names (None if one column)."""
    values: np.ndarray
    unit: str
    columns: list = None

    def column(self, name):
        """One named column (e.g. 'right_Fz') with its unit."""
        i = self.columns.index(name)
        units = self.unit.split(",")
        return Series(self.values[..., i], units[i] if len(units) > 1 else units[0])


@dataclass
class LoadCurve:
    """A load run's load-deflection curve (analysis.type = load): load_factor (1) and
    deflection (m: the loads' displacement from where loading began, as the record's
    /summary/load/curve) at every equilibrium of the load path, numpy arrays; peak: the load
    factor at collapse (the JSON's load_factor), first_peak, deflection_at_peak (m), hold (m,
    the held support displacement), end, mechanism. units: {name: unit}."""
    load_factor: np.ndarray
    deflection: np.ndarray
    peak: float
    first_peak: float
    deflection_at_peak: float
    hold: float
    end: str
    mechanism: str
    units = {"load_factor": "1", "deflection": "m", "peak": "1", "first_peak": "1",
             "deflection_at_peak": "m", "hold": "m"}


@dataclass(eq=False)
class FirstCrack:
    """A mortared run's first crack (the JSON's first_crack): the support displacement delta_mm
    where the first joint edge's tensile stress reached f_t, its joint (1-based), side (the edge
    that cracks: 'I' intrados, 'E' extrados) and, on a load path (analysis.type = load), the
    load factor there (else NaN)."""
    delta_mm: float
    joint: int
    side: str
    load_factor: float = float("nan")

    def __eq__(self, other):  # NaN load factors (off a load path) compare equal
        if not isinstance(other, FirstCrack):
            return NotImplemented
        lf = self.load_factor == other.load_factor or (
            self.load_factor != self.load_factor and other.load_factor != other.load_factor)
        return (self.delta_mm, self.joint, self.side) == (other.delta_mm, other.joint,
                                                          other.side) and lf


def first_crack_of(events):
    """The crack_initiated event of least support displacement (the program's rule) among
    events (dicts or objects with kind, delta m or delta_mm, joint, side, load_factor) as a
    FirstCrack, or None."""
    def get(e, k):
        return e[k] if isinstance(e, dict) else getattr(e, k)
    cracks = [e for e in events if get(e, "kind") == "crack_initiated"]
    if not cracks:
        return None
    mm = [get(e, "delta") / 1e-3 if isinstance(e, dict) else e.delta_mm for e in cracks]
    i = int(np.argmin(mm))
    e = cracks[i]
    lf = get(e, "load_factor") if (not isinstance(e, dict) or "load_factor" in e) else None
    return FirstCrack(float(mm[i]), int(get(e, "joint")), str(get(e, "side")),
                      float("nan") if lf is None else float(lf))


class Record:
    """An open record (use as a context manager, or call close())."""

    def __init__(self, path):
        self.path = str(path)
        self.file = h5py.File(self.path, "r")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.file.close()

    @property
    def status(self):
        """'completed', 'running', 'failed: <cause>', 'stopped: wall-time limit S s
        reached' (run.max_wall_s ended the run) or 'stopped by the caller' (a program on the
        library stopped it from its callback): a stopped record holds the run up to the stop."""
        return _text(self.file.attrs["status"])

    @property
    def case_text(self):
        return _text(self.file.attrs["case"])

    def parameters(self):
        """{'arch.radius_mm': 300.0, ...}: every case key, in the case's units."""
        out = {}
        for sec, g in self.file["parameters"].items():
            for k, v in g.attrs.items():
                out[f"{sec}.{k}"] = v.item() if hasattr(v, "item") else v
        return out

    def series_names(self):
        return sorted(self.file["observables"].keys())

    def series(self, name):
        """/observables/<name>/value with its unit attribute (SI: m, N, rad, J, ...)."""
        ds = self.file[f"observables/{name}/value"]
        unit = _text(ds.attrs["unit"]) if "unit" in ds.attrs else ""
        cols = _text(ds.attrs["columns"]).split(",") if "columns" in ds.attrs else None
        return Series(ds[:], unit, cols)

    def block_outlines(self, row=None):
        """The blocks' outlines (m) at a row (None: every row), as (nb * P, 2) points (rows first
        when every row): /geometry/block_points moved with each block's /observables/
        block_position (its centroid, /geometry/block_centroid, moved by ux, uz; turned by theta
        about it). Block b owns points b*P .. b*P+P-1, as in /geometry/block_connectivity. The
        record keeps them only for the rows its XDMF sidecar lists (/xdmf/block_points)."""
        ref = self.file["geometry/block_points"][()]
        cen = self.file["geometry/block_centroid"][()]
        pos = self.file["observables/block_position/value"]
        q = pos[:] if row is None else pos[row][None]
        d = (ref.reshape(cen.shape[0], -1, 2) - cen[:, None, :])[None]
        c, s = np.cos(q[..., 2])[..., None], np.sin(q[..., 2])[..., None]
        x = cen[None, :, None, 0] + q[..., 0, None] + c * d[..., 0] - s * d[..., 1]
        z = cen[None, :, None, 1] + q[..., 1, None] + s * d[..., 0] + c * d[..., 1]
        pts = np.stack([x, z], axis=-1).reshape(q.shape[0], -1, 2)
        return pts if row is None else pts[0]

    def reference_outlines(self):
        """Each block's outline in the reference configuration (m), counter-clockwise: a list of
        (k, 2) arrays, one per block, from /geometry/block_points without the padding (a
        block's last point repeated to fill the row). Curved edges (any shape's intrados and
        extrados) are drawn as chords; a blocks file's polygons are exact."""
        pts = self.file["geometry/block_points"][()]
        out = []
        for row in self.file["geometry/block_connectivity"][()]:
            poly = pts[row]
            k = len(poly)
            while k > 1 and np.array_equal(poly[k - 1], poly[k - 2]):
                k -= 1
            out.append(poly[:k])
        return out

    def supports(self, outward=False):
        """Each support's displacement history: {'left': Series, 'right': Series}, rows first,
        columns ux, uz (m) and theta (rad) of the centre of its springing face (x right, z up,
        theta counter-clockwise), from /observables/supports. outward=True: columns dx, dz, rot
        (m, m, rad), outward, downward and outward-turning positive, as the JSON's
        collapse.left and collapse.right. A record written before both supports could move
        (no /observables/supports) gives the right support's /observables/support_displacement
        and a left support at rest."""
        if "supports" in self.file["observables"]:
            v = self.file["observables/supports/value"][:]
        else:
            right = self.file["observables/support_displacement/value"][:]
            v = np.zeros((right.shape[0], 6))
            v[:, 3:5] = right
        left, right = v[:, 0:3], v[:, 3:6]
        if not outward:
            cols = ["ux", "uz", "theta"]
            return {"left": Series(left, "m,m,rad", cols), "right": Series(right, "m,m,rad", cols)}
        cols = ["dx", "dz", "rot"]
        mirror_left = np.array([-1.0, -1.0, 1.0])  # the left support moves outward to -x
        mirror_right = np.array([1.0, -1.0, -1.0])  # the right one turns outward clockwise
        return {"left": Series(left * mirror_left + 0.0, "m,m,rad", cols),
                "right": Series(right * mirror_right + 0.0, "m,m,rad", cols)}

    def time(self):
        ds = self.file["observables/delta/time"]
        return Series(ds[:], _text(ds.attrs.get("unit", "s")))

    def geometry(self, name):
        """/geometry/<name> as an array (unit in the 'unit' attribute when dimensional)."""
        ds = self.file[f"geometry/{name}"]
        return Series(ds[()], _text(ds.attrs["unit"]) if "unit" in ds.attrs else "")

    def events(self):
        """The event table as a list of dicts (time s, delta m, joint, side, label, phase, order,
        kind, and in a record of this version load_factor: lambda on a load path, else NaN)."""
        rows = []
        for e in self.file["events"][:]:
            rows.append({k: (_text(e[k]) if e.dtype[k].kind in "SOU" else e[k].item())
                         for k in e.dtype.names})
        return rows

    def mortared(self):
        """Whether the run had mortar joints (joints.tensile_MPa or cohesion_MPa > 0)."""
        p = self.parameters()
        return p.get("joints.tensile_MPa", 0.0) > 0 or p.get("joints.cohesion_MPa", 0.0) > 0

    def first_crack(self):
        """The first crack (FirstCrack: delta_mm, joint, side, load_factor) from the event
        table's crack_initiated events, as the JSON's first_crack; None when no joint cracked
        (and for a dry run)."""
        return first_crack_of(self.events())

    def joint_crack(self):
        """/observables/joint_crack: per recorded state and joint the lengths cracked through
        from the intrados and from the extrados (m), a Series of shape (rows, joints, 2),
        columns ['intrados', 'extrados']; 0 for dry joints. ValueError for a record written
        before mortar joints (no joint_crack)."""
        if "joint_crack" not in self.file["observables"]:
            raise ValueError(f"{self.file.filename}: no /observables/joint_crack (a record "
                             "written before mortar joints)")
        return self.series("joint_crack")

    def cracking_energy(self):
        """/observables/energy_cracking: per recorded state the energy dissipated by the
        mortar's cracking since the run's start (J, as committed at that state), a Series of
        shape (rows,); its last value is the JSON's energy.cracking_J. None for a dry run (its
        record has none) or a record written before it."""
        if "energy_cracking" not in self.file["observables"]:
            return None
        return self.series("energy_cracking")

    def _imperfection(self, name):
        path = f"imperfections/{name}"
        if path not in self.file:
            return None
        ds = self.file[path]
        return Series(ds[()], _text(ds.attrs["unit"]) if "unit" in ds.attrs else "1")

    def tensile_factor(self):
        """/imperfections/tensile_factor: each joint's mortar tensile strength f_t over the
        nominal joints.tensile_MPa as drawn for the run (imperfections.tensile_cov, lognormal
        with mean 1; 0 for a debonded joint, imperfections.debonded), a Series of shape
        (joints,), unit '1'; all 1 without scatter (and for a dry run). None for a record
        written before the mortar's scatter (no such dataset)."""
        return self._imperfection("tensile_factor")

    def gf_factor(self):
        """/imperfections/gf_factor: each joint's mortar fracture energy G_f over the nominal
        joints.gf_N_mm as drawn for the run (imperfections.gf_cov, lognormal with mean 1; drawn
        for a debonded joint too, whose f_t of 0 makes it dry), a Series of shape (joints,),
        unit '1'; all 1 without scatter. None for a record written before the mortar's scatter
        (no such dataset)."""
        return self._imperfection("gf_factor")

    def load_curve(self):
        """A load run's load-deflection curve (analysis.type = load), /summary/load, as a
        voussoir.LoadCurve: load_factor (1) and deflection (m, the loads' displacement from where
        loading began) at every equilibrium of the load path, the peak (the load factor at
        collapse), first_peak, deflection_at_peak (m), hold (m), end, mechanism. ValueError when
        the record is not a load run's."""
        if "summary/load" not in self.file:
            raise ValueError(f"{self.file.filename}: no /summary/load (not a load run: "
                             "analysis.type = load)")
        g = self.file["summary/load"]
        c = g["curve"][()].reshape(-1, 2)
        return LoadCurve(c[:, 0].copy(), c[:, 1].copy(), float(g["load_factor"][()]),
                         float(g["first_peak"][()]), float(g["deflection"][()]),
                         float(g["hold"][()]), _text(g.attrs.get("end", "")),
                         _text(g.attrs.get("mechanism", "")))

    def summary(self):
        """The summary as nested dicts: scalars as floats, arrays as lists, tables as lists of dicts."""
        def walk(g):
            out = dict((k, _attr(v)) for k, v in g.attrs.items())
            for k, obj in g.items():
                if isinstance(obj, h5py.Group):
                    out[k] = walk(obj)
                elif obj.dtype.names:
                    out[k] = [{n: _attr(r[n]) for n in obj.dtype.names} for r in obj[:]]
                else:
                    out[k] = _attr(obj[()])
            return out
        return walk(self.file["summary"])


def _attr(v):
    if isinstance(v, (bytes, str)):
        return _text(v)
    if hasattr(v, "size") and v.size != 1:
        return [_attr(x) for x in v]  # an array (e.g. /summary/damping's frequencies)
    return v.item() if hasattr(v, "item") else v


def open_record(path):
    """Open a record: `with voussoir.open_record("reference.h5") as r: ...`."""
    return Record(path)
