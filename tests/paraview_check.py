"""Run by pvpython (tests/test_paraview.sh): open two records' XDMF sidecars with both XDMF 3
readers and check that ParaView sees the records' numbers and colours every grid by a field:
Xdmf3ReaderT (named grids) and the default reader, the one OpenDataFile and the GUI's File > Open
pick (Xdmf3ReaderS, which flattens the grids into pieces of one set). The sidecar defines what
every row shares (topologies, the NaN fields, the ground's points) once and includes it by
XInclude: every frame checked here reads those shared items through the includes. The blocks'
points are checked against outlines computed here from /geometry/block_points and
/observables/block_position, whichever of its three sources the sidecar took them from: the
record's frames (/xdmf/block_points: run, fall), inline values (killed: a run killed before its
status) or an earlier version's per-state outlines (old).
usage: pvpython paraview_check.py  (cwd holds run.h5, run.xmf: a run to its first limit point;
fall.h5, fall.xmf: a run to rest on the ground after the collapse; killed.h5, killed.xmf and
old.h5, old.xmf: see test_paraview.sh)"""
import os
import sys

import h5py
import numpy as np
from paraview.simple import (ColorBy, CreateRenderView, Delete, GetColorTransferFunction, Hide,
                             OpenDataFile, Render, SaveScreenshot, Show, Xdmf3ReaderT)
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

FIELDS = ["theta_rad", "ux_m", "uz_m", "speed_m_s", "N_N", "T_N", "M_N_m", "gap_i_m", "gap_e_m",
          "hinge_0closed_1intrados_2extrados", "Fx_N", "Fz_N", "crack_i_m", "crack_e_m"]
GRIDS = ["blocks", "joints", "support_left", "support_right", "ground"]  # a row's order
OWN = {"blocks": "theta_rad", "joints": "N_N", "support_left": "Fz_N", "support_right": "Fz_N"}


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


class Record:
    """What a record's row should look like in ParaView: per grid, its points (x, z), cells and
    the 14 fields (its own from the record, the others NaN)."""

    def __init__(self, path):
        with h5py.File(path, "r") as f:
            g = lambda p: f[p][:]
            self.time = g("observables/delta/time")
            self.jp = g("observables/joint_points/value")
            self.ref, self.cen = g("geometry/block_points"), g("geometry/block_centroid")
            self.bpos, self.bs = g("observables/block_position/value"), g("observables/block_speed/value")
            self.joint = {k: g(f"observables/joint_{v}/value") for k, v in
                          (("N_N", "N"), ("T_N", "T"), ("M_N_m", "M"), ("gap_i_m", "gap_i"),
                           ("gap_e_m", "gap_e"), ("hinge_0closed_1intrados_2extrados", "hinge"))}
            self.crack = g("observables/joint_crack/value")
            self.react, self.sup = g("observables/reactions/value"), g("observables/support_displacement/value")
            self.bc, self.jc = g("geometry/block_connectivity"), g("geometry/joint_connectivity")
            self.ground = g("summary/ground/points") if "summary/ground/points" in f else None
            self.weight = float(f["geometry/block_mass"][:].sum()) * float(f["parameters/arch"].attrs["gravity_m_s2"])
        self.nb, self.nj = self.bc.shape[0], self.jc.shape[0]

    def outlines(self, r):
        """The blocks' outlines at row r: the reference points moved rigidly with their block
        (turned by theta about the centroid, which moved by ux, uz), rounded to float32."""
        q, nb = self.bpos[r], self.nb
        d = self.ref.reshape(nb, -1, 2) - self.cen[:, None, :]
        c, s = np.cos(q[:, 2])[:, None], np.sin(q[:, 2])[:, None]
        x = self.cen[:, 0, None] + q[:, 0, None] + c * d[:, :, 0] - s * d[:, :, 1]
        z = self.cen[:, 1, None] + q[:, 1, None] + s * d[:, :, 0] + c * d[:, :, 1]
        return np.stack([x, z], axis=-1).reshape(-1, 2).astype(np.float32)

    def row_of(self, t):
        rows = np.flatnonzero(self.time == t)
        if rows.size == 0:
            fail(f"ParaView time {t!r} is no row's time")
        return int(rows[0])

    def grids(self, r):
        nan = lambda n: {k: np.full(n, np.nan) for k in FIELDS}
        segment = np.array([[0, 1]])
        b = nan(self.nb)
        b.update(theta_rad=self.bpos[r, :, 2], ux_m=self.bpos[r, :, 0], uz_m=self.bpos[r, :, 1], speed_m_s=self.bs[r])
        j = nan(self.nj)
        j.update({k: v[r] for k, v in self.joint.items()})
        j.update(crack_i_m=self.crack[r, :, 0], crack_e_m=self.crack[r, :, 1])
        sl, sr = nan(1), nan(1)
        sl.update(Fx_N=self.react[r, 0:1], Fz_N=self.react[r, 1:2], M_N_m=self.react[r, 2:3])
        sr.update(Fx_N=self.react[r, 3:4], Fz_N=self.react[r, 4:5], M_N_m=self.react[r, 5:6],
                  ux_m=self.sup[r, 0:1], uz_m=self.sup[r, 1:2])
        out = {"blocks": (self.outlines(r), self.bc, b), "joints": (self.jp[r], self.jc, j),
               "support_left": (self.jp[r, :2], segment, sl),
               "support_right": (self.jp[r, 2 * self.nj - 2:], segment, sr)}
        if self.ground is not None:
            out["ground"] = (self.ground, segment, nan(1))
        return out


def same(a, b):
    """Equal values, NaN where NaN."""
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    return a.shape == b.shape and np.array_equal(np.isnan(a), np.isnan(b)) and np.array_equal(a[~np.isnan(a)], b[~np.isnan(b)])


OFF_BY = {"points": 0, "exact": 0, "ulp": 0}  # the blocks' points against outlines computed here


def close_f32(got, want):
    """float32 points within one float32 step of those computed here (another cos or sin may
    round a last bit otherwise); counted in OFF_BY."""
    got, want = np.asarray(got, np.float32).ravel(), np.asarray(want, np.float32).ravel()
    if got.shape != want.shape or not np.isfinite(got).all():
        return False
    off = np.abs(got.astype(float) - want.astype(float))
    OFF_BY["points"] += got.size
    OFF_BY["exact"] += int((off == 0).sum())
    OFF_BY["ulp"] = max(OFF_BY["ulp"], float((off / np.spacing(np.abs(want))).max()))
    return bool((off <= np.spacing(np.abs(want))).all())


def check_grid(ds, want, tag):
    """A grid as ParaView read it against the record: points, cells, every field."""
    pts, conn, fields = want
    p = vtk_to_numpy(ds.GetPoints().GetData())
    ok = close_f32(p[:, :2], pts) if tag.endswith(" blocks") else same(p[:, :2], pts.reshape(-1, 2))
    if not ok or p[:, 2].any():
        fail(f"{tag}: points differ from the record's")
    if ds.GetNumberOfCells() != conn.shape[0]:
        fail(f"{tag}: {ds.GetNumberOfCells()} cells, the record has {conn.shape[0]}")
    for c in range(ds.GetNumberOfCells()):
        ids = ds.GetCell(c).GetPointIds()
        if [ids.GetId(k) for k in range(ids.GetNumberOfIds())] != list(conn[c]):
            fail(f"{tag}: cell {c} has other points than the record's connectivity")
    cd = ds.GetCellData()
    names = [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())]
    if sorted(names) != sorted(FIELDS):
        fail(f"{tag}: fields {names}")
    # ParaView shows a grid's first scalar field on opening: theta_rad on every grid
    if names[0] != "theta_rad" or cd.GetScalars() is None or cd.GetScalars().GetName() != "theta_rad":
        fail(f"{tag}: first field {names[0]}")
    for k, v in fields.items():
        if not same(vtk_to_numpy(cd.GetArray(k)), v):
            fail(f"{tag}: {k} differs from the record's (NaN where not the grid's own)")


def leaves(obj):
    it = obj.NewIterator()
    it.InitTraversal()
    out = []
    while not it.IsDoneWithTraversal():
        name = it.GetCurrentMetaData().Get(obj.NAME()) if it.HasCurrentMetaData() else None
        out.append((name, it.GetCurrentDataObject()))
        it.GoToNextItem()
    return out


def read_frame(reader, t):
    reader.UpdatePipeline(t)
    return reader.GetClientSideObject().GetOutputDataObject(0)


def check_frames(reader, rec, tag):
    """Frames last, first, ..., back and forth (shared items are read once and kept between
    frames: a stale or released one would show): every grid against the record. Returns the
    last frame's grids by name."""
    steps = list(reader.TimestepValues)
    n = len(steps)
    seq = [n - 1, 0, 1, 2, n // 2, n // 2 + 1, n - 1, n - 2, 1, n - 1]
    for i in seq:
        r = rec.row_of(steps[i])
        want = rec.grids(r)
        got = leaves(read_frame(reader, steps[i]))
        if reader.GetXMLName() == "Xdmf3ReaderT":  # named blocks; [k] appended after the first step
            named = {name.split("[")[0]: ds for name, ds in got}
        else:  # pieces, in the row's order
            if len(got) != len(want):
                fail(f"{tag}: row {r}: {len(got)} pieces, want {len(want)}")
            named = dict(zip(GRIDS, (ds for _, ds in got)))
        if sorted(named) != sorted(want):
            fail(f"{tag}: row {r}: grids {sorted(named)}, want {sorted(want)}")
        for name, ds in named.items():
            check_grid(ds, want[name], f"{tag} row {r} {name}")
    return n, len(seq), named


def saturated_pixels(png):
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).astype(int)[:, :3]
    return int(((img.max(axis=1) - img.min(axis=1)) > 60).sum())


def colour_check(reader, t, grids, tag):
    """Draw the reader's output at time t in a solid colour, then coloured by each grid's own
    field (NaN in grey, so that only the cells that have the field turn colourful); fail unless
    the colour map spans that field's values and the grid's cells turn colourful. Returns the
    saturated pixel counts and the field ParaView showed before any ColorBy."""
    view = CreateRenderView()
    view.ViewSize = [480, 320]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    display = Show(reader, view)
    display.LineWidth = 3
    shown = display.ColorArrayName[1]
    ColorBy(display, None)
    view.ResetCamera()
    Render(view)
    SaveScreenshot(f"solid_{tag}.png", view, ImageResolution=[480, 320])
    counts = {"solid": saturated_pixels(f"solid_{tag}.png")}
    if counts["solid"] > 50:
        fail(f"{tag}: {counts['solid']} saturated pixels in a solid colour")
    for field in dict.fromkeys(OWN.values()):
        values = np.concatenate([vtk_to_numpy(grids[g].GetCellData().GetArray(field)) for g in OWN if OWN[g] == field])
        ColorBy(display, ("CELLS", field))
        lut = GetColorTransferFunction(field)
        lut.ApplyPreset("Viridis (matplotlib)", True)
        lut.NanColor = [0.5, 0.5, 0.5]
        display.RescaleTransferFunctionToDataRange(False, True)
        lo, hi = lut.RGBPoints[0], lut.RGBPoints[-4]
        if abs(lo - values.min()) > 1e-9 * max(1, abs(lo)) or abs(hi - values.max()) > 1e-9 * max(1, abs(hi)):
            fail(f"{tag}: colour map of {field} {lo}..{hi}, data {values.min()}..{values.max()}")
        Render(view)
        SaveScreenshot(f"{field}_{tag}.png", view, ImageResolution=[480, 320])
        counts[field] = saturated_pixels(f"{field}_{tag}.png")
    least = {"theta_rad": 1000, "N_N": 300, "Fz_N": 20}
    for field, n in least.items():
        if counts[field] < n:
            fail(f"{tag}: colouring by {field} colours {counts[field]} pixels (the grids that carry it "
                 f"stay grey): {counts}")
    Hide(reader, view)
    Delete(view)
    return counts, shown


def shared_items(xmf, rec):
    """The sidecar's shared items (xml:id) and its XIncludes: every grid of every row includes its
    topology and its NaN fields, the ground also its points (what the frames below read)."""
    text = open(xmf).read()
    defs, includes, rows = text.count(' xml:id="'), text.count("<xi:include "), text.count('<Time Value="')
    per_row = 4 * 2 + (3 if rec.ground is not None else 0)
    if defs == 0 or includes != rows * per_row:
        fail(f"{xmf}: {defs} shared items, {includes} includes for {rows} rows (want {per_row} a row)")
    return defs, includes


def main():
    run, fall = Record("run.h5"), Record("fall.h5")
    if run.ground is not None or fall.ground is None:
        fail("the test wants run.h5 without the ground and fall.h5 with it")
    records = [("run", run), ("fall", fall), ("killed", Record("killed.h5")), ("old", Record("old.h5"))]
    for name, rec in records:
        defs, includes = shared_items(f"{name}.xmf", rec)
        print(f"{name}.xmf: {defs} items defined once, {includes} XIncludes of them")
        # Xdmf3ReaderT given a path with a directory, the default reader an absolute path (a bare
        # relative name makes ParaView 5.11 look for the HDF5 file at 'run.xmfrun.h5' and abort:
        # see docs/record.md)
        for reader in (Xdmf3ReaderT(FileName=f"./{name}.xmf"), OpenDataFile(os.path.abspath(f"{name}.xmf"))):
            kind = reader.GetXMLName()
            tag = f"{name}.xmf {kind}"
            steps, checked, grids = check_frames(reader, rec, tag)
            line = (f"{tag}: {steps} steps; {checked} frames, each grid's points, cells and {len(FIELDS)} fields "
                    f"equal to the record's (NaN off its own)")
            if name == "run":
                # a quasi-static row: the supports carry the weight, upward, and cancel horizontally
                fz = sum(float(vtk_to_numpy(grids[s].GetCellData().GetArray("Fz_N"))[0]) for s in ("support_left", "support_right"))
                fx = sum(float(vtk_to_numpy(grids[s].GetCellData().GetArray("Fx_N"))[0]) for s in ("support_left", "support_right"))
                if abs(fz - run.weight) > 1e-6 * run.weight or abs(fx) > 1e-6 * run.weight:
                    fail(f"{tag}: support forces Fx {fx} N, Fz {fz} N; weight {run.weight} N")
                counts, shown = colour_check(reader, reader.TimestepValues[-1], grids, kind)
                if kind != "Xdmf3ReaderT" and shown != "theta_rad":
                    fail(f"{tag}: on opening ParaView shows {shown!r}, not theta_rad")
                line += (f"; supports' Fz sum {fz:.4f} N = W; saturated pixels: solid {counts['solid']}, "
                         f"by theta_rad {counts['theta_rad']}, N_N {counts['N_N']}, Fz_N {counts['Fz_N']}; "
                         f"shown on opening: {shown}")
            print(line)
            Delete(reader)
    print(f"blocks' points: {OFF_BY['points']} checked against outlines computed from the geometry "
          f"and positions, {OFF_BY['exact']} bit-equal, at most {OFF_BY['ulp']:g} float32 step off")
    print("paraview: ok")


main()
