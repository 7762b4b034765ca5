"""A pointed (two-centred) arch settling: built from keyword arguments, run in process, its
supports' forces and hinges against the support displacement in one PDF of two pages.
usage: python3 pointed_arch.py [OUT.pdf]"""
import sys

from matplotlib.backends.backend_pdf import PdfPages

import voussoir
from voussoir import figures

arch = voussoir.Case(arch__shape="pointed", arch__span_mm=500, arch__eccentricity=0.5,
                     arch__thickness_mm=30, arch__voussoirs=21, support__alpha_deg=0)
res = voussoir.run(arch)
c = res.collapse
print(f"{res.status} at delta_u = {c.delta_mm:.2f} mm (dz/L {c.dz_over_L_pct:.2f} %), "
      f"hinges {res.hinges_at_collapse}")
with PdfPages(sys.argv[1] if len(sys.argv) > 1 else "pointed_arch.pdf") as pdf:
    pdf.savefig(figures.curves(res))
    pdf.savefig(figures.hinges(res))
