"""Run by pvpython (tests/test_paraview.sh): open a record's XDMF sidecar as the README says and
check that ParaView sees named grids carrying the record's numbers and colours the blocks by a
field.  usage: pvpython paraview_check.py DIR  (DIR holds run.h5 and run.xmf; cwd = DIR)"""
import sys

import h5py
import numpy as np
from paraview import servermanager
from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction, Render,
                             SaveScreenshot, Show, Xdmf3ReaderT)
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

    view = CreateRenderView()
    view.ViewSize = [480, 320]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    display = Show(reader, view)
    view.ResetCamera()
    Render(view)
    SaveScreenshot("solid.png", view, ImageResolution=[480, 320])
    ColorBy(display, ("CELLS", "theta_rad"))
    lut = GetColorTransferFunction("theta_rad")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    display.RescaleTransferFunctionToDataRange(False, True)
    lo, hi = lut.RGBPoints[0], lut.RGBPoints[-4]
    if abs(lo - pv_theta.min()) > 1e-9 or abs(hi - pv_theta.max()) > 1e-9:
        fail(f"colour map range {lo}..{hi}, data {pv_theta.min()}..{pv_theta.max()}")
    Render(view)
    SaveScreenshot("theta.png", view, ImageResolution=[480, 320])
    solid, coloured = saturated_pixels("solid.png"), saturated_pixels("theta.png")
    print(f"theta_rad {pv_theta.min():.4f}..{pv_theta.max():.4f} rad; saturated pixels: "
          f"solid colour {solid}, coloured by theta_rad {coloured}; supports Fz sum {fz:.4f} N, W {weight:.4f} N")
    if not (coloured > 1000 and solid < 50):
        fail("colouring by theta_rad does not colour the blocks")
    print("paraview: ok")


main()
