"""A first look at a voussoir record in ParaView: open its XDMF sidecar, colour the blocks by a
field (grey where a grid does not carry it: the joints, the supports and the ground for a block
field, NaN in the record's sidecar), label every frame with the support displacement and write
the animation as PNG frames.

usage: pvpython paraview_record.py RECORD.xmf|RECORD.h5 [--field theta_rad] [--out DIR]
                                   [--frames N] [--size 960x540]
  RECORD.xmf: the sidecar `voussoir run -o RECORD.h5` writes beside the record (a bare name
  works: it is made absolute before ParaView opens it); --field: a cell field of the sidecar
  (docs/record.md: theta_rad, ux_m, uz_m, speed_m_s, N_N, T_N, M_N_m, gap_i_m, gap_e_m,
  hinge_0closed_1intrados_2extrados, Fx_N, Fz_N, crack_i_m, crack_e_m); --frames: N frames evenly spread over the
  sidecar's steps (default: every step); --out: where STEM.NNNN.png go (default: STEM_frames).
Prints one line per frame: its file, loading time (s), support displacement (mm) and phase.
Without a display: run it under xvfb-run, or with pvpython --force-offscreen-rendering."""
import argparse
import os
import sys

import numpy as np
from paraview.simple import (ColorBy, CreateRenderView, GetColorTransferFunction,
                             GetScalarBar, OpenDataFile, Render, SaveScreenshot, Show, Text)

PHASES = {0: "quasi-static", 1: "dynamic", 2: "fall"}


def parse():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("record")
    p.add_argument("--field", default="theta_rad")
    p.add_argument("--out")
    p.add_argument("--frames", type=int, default=0)
    p.add_argument("--size", default="960x540")
    return p.parse_args()


def record_rows(h5):
    """{loading time: (delta m, phase)} of every recorded row, from the HDF5 record (h5py), so
    each frame is labelled with the support displacement of its own row."""
    try:
        import h5py
    except ImportError:
        return None
    with h5py.File(h5, "r") as f:
        t = f["observables/delta/time"][:]
        d = f["observables/delta/value"][:]
        ph = f["observables/phase/value"][:] if "phase" in f["observables"] else np.zeros(len(t))
    return t, d, ph


def main():
    a = parse()
    stem, ext = os.path.splitext(a.record)
    xmf = os.path.abspath(stem + ".xmf")  # ParaView 5.11 misreads a bare name: see docs/python.md
    if not os.path.isfile(xmf):
        sys.exit(f"paraview_record: {xmf}: no such sidecar (voussoir run -o RECORD.h5 writes it)")
    out = a.out or os.path.basename(stem) + "_frames"
    os.makedirs(out, exist_ok=True)
    w, h = (int(x) for x in a.size.split("x"))
    reader = OpenDataFile(xmf)
    steps = list(reader.TimestepValues)
    if a.frames and a.frames < len(steps):
        steps = [steps[round(i * (len(steps) - 1) / (a.frames - 1))] for i in range(a.frames)] \
            if a.frames > 1 else [steps[-1]]
    view = CreateRenderView()
    view.ViewSize = [w, h]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:  # ParaView 5.10+: the view's own background, not the palette's
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = Show(reader, view)
    display.LineWidth = 2
    ColorBy(display, ("CELLS", a.field))
    lut = GetColorTransferFunction(a.field)
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.NanColor = [0.5, 0.5, 0.5]  # the grids that do not carry the field
    display.RescaleTransferFunctionToDataRangeOverTime()
    bar = GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = a.field, ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    display.SetScalarBarVisibility(view, True)
    label = Text()
    label_display = Show(label, view)
    label_display.Color = [0, 0, 0]
    label_display.WindowLocation = "Upper Left Corner"
    label_display.FontSize = 14
    rows = record_rows(stem + ".h5")
    view.ViewTime = steps[-1]
    view.ResetCamera()  # the whole motion in view: frame the last state (the fall, if any)
    for i, t in enumerate(steps):
        if rows is not None:
            k = int(np.argmin(np.abs(rows[0] - t)))
            delta_mm, phase = rows[1][k] * 1e3, PHASES.get(int(rows[2][k]), "")
            label.Text = f"support displacement {delta_mm:.3f} mm ({phase}), t = {t:.2f} s"
        else:
            delta_mm, phase = float("nan"), ""
            label.Text = f"loading time {t:.2f} s"
        view.ViewTime = t
        Render(view)
        png = os.path.join(out, f"{os.path.basename(stem)}.{i:04d}.png")
        SaveScreenshot(png, view, ImageResolution=[w, h])
        print(f"{png} time_s={t!r} delta_mm={delta_mm:.6f} phase={phase}")


main()
