#!/usr/bin/env python3
"""Read a voussoir record with h5py and plot the reaction curve (matplotlib).

usage: /usr/bin/python3 runs/read_run.py RUN.h5 [OUT.png]

Every dimensional dataset carries its unit as an attribute, so the axes are labelled from the
file itself. Debian packages: python3-h5py, python3-matplotlib.
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path, png):
    with h5py.File(path, "r") as f:
        print(f"{path}: {f.attrs['program']} {f.attrs['version']}, status: {f.attrs['status']}")
        obs = f["observables"]
        delta = obs["delta/value"][:]
        reactions = obs["reactions/value"][:]  # left Fx, Fz, M, right Fx, Fz, M: forces the supports exert on the arch
        units = obs["reactions/value"].attrs["unit"].split(",")
        phase = obs["phase/value"][:]
        print(f"{len(delta)} recorded states, delta up to {delta.max() * 1e3:.3f} mm "
              f"({(phase == 1).sum()} dynamic samples)")
        summary = f["summary"]
        if "collapse" in summary:
            c = summary["collapse"]
            print(f"collapse at delta_u = {c['delta'][()] * 1e3:.3f} mm, "
                  f"dz/L = {100 * c['dz_over_L'][()]:.3f} %, mode {summary.attrs.get('mode', '?')}")
            for h in c["hinges"][:]:
                print(f"  hinge {h['label'].decode()}: {h['name'].decode() if isinstance(h['name'], bytes) else h['name']}"
                      f", onset at {h['delta_onset'] * 1e3:.3f} mm")
        for kind in ("limit_point", "collapse"):
            n = sum(1 for e in f["events"][:] if (e["kind"].decode() if isinstance(e["kind"], bytes) else e["kind"]) == kind)
            print(f"{n} '{kind}' events")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(delta * 1e3, reactions[:, 4], label="right (moved) support, vertical")
    ax.plot(delta * 1e3, reactions[:, 1], label="left (fixed) support, vertical")
    ax.plot(delta * 1e3, reactions[:, 0], label="horizontal thrust")
    ax.set_xlabel("support displacement delta (mm)")
    ax.set_ylabel(f"support reaction ({units[1]})")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"figure: {png}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "reaction.png")
