#!/usr/bin/env python3
"""Print a voussoir record's status, collapse and hinges and plot its support reactions: a thin
wrapper over the Python package in python/ (used from the source tree when not installed).

usage: /usr/bin/python3 runs/read_run.py RUN.h5 [OUT.png]
Debian packages: python3-h5py, python3-numpy, python3-matplotlib.
"""
import os
import sys

sys.path.insert(1, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import voussoir  # noqa: E402


def main(path, png):
    with voussoir.open_record(path) as r:
        delta = r.series("delta").values
        print(f"{path}: status {r.status}; {len(delta)} recorded states, delta up to {delta.max() * 1e3:.3f} mm")
        s = r.summary()
        col = s.get("collapse")
        if col and col.get("delta") == col.get("delta"):  # not NaN
            print(f"collapse at delta_u = {col['delta'] * 1e3:.3f} mm, dz/L = {100 * col['dz_over_L']:.3f} %, "
                  f"mode {s.get('mode', '?')}")
        for h in s.get("hinges", []):
            print(f"  hinge {h.get('label')}: {h.get('name_onset')} at onset, {h.get('name')} at the end, onset at {h.get('delta_onset', float('nan')) * 1e3:.3f} mm")
        fig, ax = plt.subplots(figsize=(8, 4.5))
        voussoir.draw_curves(r, ax)
        fig.tight_layout()
        fig.savefig(png, dpi=120)
    print(f"figure: {png}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "reaction.png")
