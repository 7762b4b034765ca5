"""Run by tests/test_plot_data.sh: check plots.json (what `voussoir plot` drew) against the
records.  usage: python3 plot_data_check.py DIR"""
import json
import os
import struct
import sys

import h5py
import numpy as np

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    check(head[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG")
    return struct.unpack(">II", head[16:24])


def text(b):
    return b.decode() if isinstance(b, bytes) else str(b)


def check_run(tmp, name):
    """Every label drawn is a hinge of /summary/hinges with its side, drawn once per picture;
    the forming hinge at its onset joints; the collapse picture shows the record's hinges at
    the collapse, at their joints."""
    with h5py.File(os.path.join(tmp, name + ".h5"), "r") as f:
        rows = f["summary/hinges"][:]
        collapsed = "collapse/delta" in f["summary"] and np.isfinite(f["summary/collapse/delta"][()])
    rec = {text(r["label"]): r for r in rows}
    check(len(rec) == len(rows), f"{name}: labels repeat in /summary/hinges")
    check("?" not in rec, f"{name}: a hinge of the record is labelled '?'")
    plots = os.path.join(tmp, name + "_plots")
    with open(os.path.join(plots, "plots.json")) as fh:
        pics = {p["file"]: p for p in json.load(fh)["pictures"]}
    for fname, p in pics.items():
        check(os.path.exists(os.path.join(plots, fname)), f"{name}: {fname} listed, not written")
        check(fname.startswith("arch_"), f"{name}: plots.json lists {fname}, not an arch picture")
        check(png_size(os.path.join(plots, fname))[0] == 1200, f"{name}: {fname} is not 1200 px wide")
        labels = [h["label"] for h in p["hinges"]]
        check(len(labels) == len(set(labels)), f"{name}: {fname} labels {labels} twice")
        for h in p["hinges"]:
            r = rec.get(h["label"])
            check(r is not None, f"{name}: {fname} draws {h['label']}, not in /summary/hinges")
            if r is None:
                continue
            check(h["side"] == text(r["side"]), f"{name}: {fname} draws {h['label']} on side {h['side']}, record {text(r['side'])}")
            check(float(r["delta_onset"]) <= p["delta_mm"] * 1e-3 + 1e-9,
                  f"{name}: {fname} at {p['delta_mm']} mm draws {h['label']}, formed at {1e3 * r['delta_onset']} mm")
    for lab, r in rec.items():
        if r["during_fall"]:
            continue
        fname = f"arch_hinge_{lab}.png"
        check(fname in pics, f"{name}: no picture of hinge {lab} forming")
        if fname in pics:
            drawn = {h["label"]: h for h in pics[fname]["hinges"]}
            check(lab in drawn and (drawn[lab]["first"], drawn[lab]["last"]) == (r["onset_first"], r["onset_last"]),
                  f"{name}: {fname} draws {drawn.get(lab)}, record onset {r['onset_first']}-{r['onset_last']}")
            check(abs(pics[fname]["delta_mm"] - 1e3 * r["delta_onset"]) < 1e-6, f"{name}: {fname} not at the onset")
    if collapsed:
        want = {lab: (int(r["first"]), int(r["last"]), text(r["side"])) for lab, r in rec.items()
                if not r["during_fall"] and r["open"]}
        got = {h["label"]: (h["first"], h["last"], h["side"]) for h in pics["arch_collapse.png"]["hinges"]}
        check(got == want, f"{name}: collapse picture draws {got}, record {want}")
    return rec


def pictures(tmp, name):
    with open(os.path.join(tmp, name + "_plots", "plots.json")) as fh:
        return json.load(fh)["pictures"]


def check_supports(tmp):
    """Fixed supports do not turn; a pinned springer turns with its voussoir while their joint
    is closed (before the fall); a thickness-scattered arch is drawn with the record's
    thicknesses."""
    for name in ("ref", "a90"):
        for p in pictures(tmp, name):
            if "support_theta_rad" in p:
                check(p["support_theta_rad"] == [0, 0], f"{name}: {p['file']} turns a fixed support")
    with h5py.File(os.path.join(tmp, "pin.h5"), "r") as f:
        pos = f["observables/block_position/value"][:]
        delta = f["observables/delta/value"][:]
    turned = 0
    for p in pictures(tmp, "pin"):
        if "support_theta_rad" not in p or p["file"] == "arch_end.png":
            continue
        row = int(np.argmin(np.abs(1e3 * delta - p["delta_mm"])))
        if abs(1e3 * delta[row] - p["delta_mm"]) > 1e-6:
            continue  # interpolated states: compared on recorded rows only
        left, right = p["support_theta_rad"]
        check(abs(left - pos[row, 0, 2]) < 1e-3 and abs(right - pos[row, -1, 2]) < 1e-3,
              f"pin: {p['file']} springers {left}, {right} rad; voussoirs {pos[row, 0, 2]}, {pos[row, -1, 2]}")
        turned += abs(left) > 0.01
    check(turned >= 1, "pin: no picture shows a springer turned by more than 0.01 rad")
    with h5py.File(os.path.join(tmp, "thick.h5"), "r") as f:
        t = 1e3 * f["imperfections/voussoir_thickness"][:]
    drawn = pictures(tmp, "thick")[0].get("block_thickness_mm")
    check(drawn is not None and np.abs(np.asarray(drawn) - t).max() < 1e-6 and t.std() > 0.5,
          "thick: the pictures do not draw the record's voussoir thicknesses")


def main():
    tmp = sys.argv[1]
    ref = check_run(tmp, "ref")
    pin = check_run(tmp, "pin")
    a90 = check_run(tmp, "a90")
    # a pinned springer: two hinges of the arch make the mechanism, named A and B left to right
    first = sorted((r for r in pin.values() if not r["during_fall"]), key=lambda r: r["onset_first"])
    check([text(r["label"]) for r in first][:2] == ["A", "B"], f"pinned: hinges before the fall {[text(r['label']) for r in first]}")
    for name, rec in (("ref", ref), ("a90", a90)):
        abc = sorted((r for r in rec.values() if r["order"] <= 3), key=lambda r: r["onset_first"])
        check([text(r["label"]) for r in abc] == ["A", "B", "C"], f"{name}: first three not A, B, C left to right")
    check_run(tmp, "thick")
    check_supports(tmp)
    for m in failures:
        print("FAIL:", m)
    print(f"plot data: {len(failures)} failures; labels of ref ({len(ref)} hinges), pinned ({len(pin)}), "
          f"alpha 90 ({len(a90)}) checked")
    sys.exit(1 if failures else 0)


main()
