"""The load factor after settlement: the reference specimen's right support settles by a held
amount (analysis.hold_mm), then a 1 N point load at quarter span grows to collapse. Five holds
run in threads; the residual load factor against the settlement, and the load-deflection
curves, as a PDF of two pages.
usage: python3 load_after_settlement.py [OUT.pdf]   (the full study: runs/residual_study.sh)"""
import sys
from concurrent.futures import ThreadPoolExecutor

from matplotlib.backends.backend_pdf import PdfPages

import voussoir
from voussoir import figures

holds_mm = [0, 10, 20, 40, 60]
cases = [voussoir.Case(analysis__type="load", analysis__hold_mm=h, load__kind="point",
                       load__value_N=1, load__x_mm=133) for h in holds_mm]
with ThreadPoolExecutor(max_workers=2) as pool:  # runs release the GIL
    results = list(pool.map(voussoir.run, cases))
span = cases[0].span_mm
for h, r in zip(holds_mm, results):
    print(f"settled {h:2d} mm ({100 * h / span:5.2f} % of the span): load factor "
          f"{r.load_factor:.3f} ({r.load_curve().end})")
with PdfPages(sys.argv[1] if len(sys.argv) > 1 else "load_after_settlement.pdf") as pdf:
    fig, ax = figures.figure()
    ax.plot(holds_mm, [r.load_factor for r in results], marker="o", color="C0")
    ax.set_xlabel("support settlement held (mm)")
    ax.set_ylabel("load factor at collapse")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    pdf.savefig(fig)
    fig, ax = figures.figure()
    for h, r in zip(holds_mm, results):
        lc = r.load_curve()
        ax.plot(lc.deflection / 1e-3, lc.load_factor, label=f"{h} mm")
    ax.set_xlabel("deflection under the load (mm)")
    ax.set_ylabel("load factor lambda")
    ax.set_ylim(bottom=0)
    ax.legend(title="settled", frameon=False)
    pdf.savefig(fig)
