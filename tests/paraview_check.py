"""Run by pvpython (tests/test_paraview.sh): open a record's XDMF sidecar with both XDMF 3
readers and check that ParaView sees the record's numbers and colours the blocks by a field:
Xdmf3ReaderT (named grids) and the default reader, the one OpenDataFile and the GUI's File > Open
pick (Xdmf3ReaderS, which flattens the grids into pieces of one set).
usage: pvpython paraview_check.py  (cwd holds run.h5 and run.xmf)"""
import os
import sys

import h5py
import numpy as np
from paraview import servermanager
from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction, OpenDataFile,
                             Render, SaveScreenshot, Show, Xdmf3ReaderT)
from vtk.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def blocks_by_name(mb):
    out = {}
    for i in range(mb.GetNumberOfBlocks()):
        name = mb.GetMetaData(i).Get(mb.NAME()).split("[")[0]  # Xdmf3ReaderT appends [step] after the first
        out[name] = mb.GetBlock(i)
    return out


def saturated_pixels(png):
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).astype(int)[:, :3]
    return int(((img.max(axis=1) - img.min(axis=1)) > 60).sum())


def pieces(obj):
    """The leaves of a composite data set (the default reader's multi-piece set)."""
    it = obj.NewIterator()
    it.InitTraversal()
    out = []
    while not it.IsDoneWithTraversal():
        out.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return out


def colour_check(reader, t, pv_theta, tag):
    """Draw the reader's output at time t in a solid colour, then coloured by theta_rad; fail
    unless the colour map spans the blocks' theta_rad and the blocks turn colourful. Returns the
    saturated pixel counts and the field ParaView showed before any ColorBy."""
    view = CreateRenderView()
    view.ViewSize = [480, 320]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    display = Show(reader, view)
    shown = display.ColorArrayName[1]
    ColorBy(display, None)
    view.ResetCamera()
    Render(view)
    SaveScreenshot(f"solid_{tag}.png", view, ImageResolution=[480, 320])
    ColorBy(display, ("CELLS", "theta_rad"))
    lut = GetColorTransferFunction("theta_rad")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    display.RescaleTransferFunctionToDataRange(False, True)
    lo, hi = lut.RGBPoints[0], lut.RGBPoints[-4]
    if abs(lo - pv_theta.min()) > 1e-9 or abs(hi - pv_theta.max()) > 1e-9:
        fail(f"{tag}: colour map range {lo}..{hi}, data {pv_theta.min()}..{pv_theta.max()}")
    Render(view)
    SaveScreenshot(f"theta_{tag}.png", view, ImageResolution=[480, 320])
    solid, coloured = saturated_pixels(f"solid_{tag}.png"), saturated_pixels(f"theta_{tag}.png")
    if not (coloured > 1000 and solid < 50):
        fail(f"{tag}: colouring by theta_rad does not colour the blocks (saturated pixels: solid "
             f"{solid}, coloured {coloured})")
    return solid, coloured, shown


def main():
    with h5py.File("run.h5", "r") as f:
        theta = f["observables/block_position/value"][-1, :, 2]
        weight = float(f["geometry/block_mass"][:].sum()) * float(f["parameters/arch"].attrs["gravity_m_s2"])
        nb = theta.size
    reader = Xdmf3ReaderT(FileName="./run.xmf")  # a path with a directory: see the README
    t = reader.TimestepValues[-1]
    reader.UpdatePipeline(t)
    grids = blocks_by_name(servermanager.Fetch(reader))
    if sorted(grids) != ["blocks", "joints", "support_left", "support_right"]:
        fail(f"grids {sorted(grids)}")
    blocks = dsa.WrapDataObject(grids["blocks"])
    if blocks.GetNumberOfCells() != nb:
        fail(f"{blocks.GetNumberOfCells()} block cells, record has {nb}")
    pv_theta = np.asarray(blocks.CellData["theta_rad"]).ravel()
    if np.abs(pv_theta - theta).max() > 1e-12:
        fail("theta_rad in ParaView differs from the record's last row")
    if not pv_theta.max() - pv_theta.min() > 1e-3:
        fail(f"theta_rad range {pv_theta.min()}..{pv_theta.max()} rad is trivial")
    # The supports carry the weight: their forces on the arch sum to W upward and cancel
    # horizontally (a quasi-static row).
    fz = sum(float(np.asarray(dsa.WrapDataObject(grids[s]).CellData["Fz_N"])[0]) for s in ("support_left", "support_right"))
    fx = sum(float(np.asarray(dsa.WrapDataObject(grids[s]).CellData["Fx_N"])[0]) for s in ("support_left", "support_right"))
    if abs(fz - weight) > 1e-6 * weight or abs(fx) > 1e-6 * weight:
        fail(f"support forces Fx {fx} N, Fz {fz} N; weight {weight} N")

    solid, coloured, shown = colour_check(reader, t, pv_theta, "T")
    print(f"Xdmf3ReaderT: theta_rad {pv_theta.min():.4f}..{pv_theta.max():.4f} rad; saturated pixels: "
          f"solid colour {solid}, coloured by theta_rad {coloured}; supports Fz sum {fz:.4f} N, W {weight:.4f} N")

    # The default reader, given an absolute path (a bare relative name makes ParaView 5.11 look
    # for the HDF5 file at 'run.xmfrun.h5' and abort: see the README).
    default = OpenDataFile(os.path.abspath("run.xmf"))
    kind = default.GetXMLName()
    default.UpdatePipeline(t)
    leaves = pieces(servermanager.Fetch(default))
    cells = sorted(leaf.GetNumberOfCells() for leaf in leaves)
    if nb not in cells or nb + 1 not in cells:
        fail(f"{kind}: pieces with {cells} cells, no blocks ({nb}) or joints ({nb + 1})")
    # ParaView keeps only the fields every piece carries: each must carry them all
    names = [sorted(leaf.GetCellData().GetArrayName(i) for i in range(leaf.GetCellData().GetNumberOfArrays()))
             for leaf in leaves]
    if any(n != names[0] for n in names):
        fail(f"{kind}: pieces carry different fields: {names}")
    for leaf in leaves:
        arr = leaf.GetCellData().GetArray("theta_rad")
        if arr is None:
            fail(f"{kind}: a piece of {leaf.GetNumberOfCells()} cells lacks theta_rad")
        vals = vtk_to_numpy(arr)
        if leaf.GetNumberOfCells() == nb and np.abs(vals - theta).max() > 1e-12:
            fail(f"{kind}: theta_rad on the blocks differs from the record's last row")
        if leaf.GetNumberOfCells() != nb and not np.isnan(vals).all():
            fail(f"{kind}: theta_rad on a piece that is not the blocks is not NaN")
    solid, coloured, shown = colour_check(default, t, pv_theta, kind)
    if shown != "theta_rad":
        fail(f"{kind}: on opening ParaView shows {shown!r}, not theta_rad")
    print(f"{kind} (the default reader): {len(leaves)} pieces, each with the same {len(names[0])} fields, "
          f"theta_rad NaN off the blocks and shown "
          f"on opening; saturated pixels: solid colour {solid}, coloured by theta_rad {coloured}")
    print("paraview: ok")


main()
