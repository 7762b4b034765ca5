"""A Monte Carlo fragility: the reference specimen (15 voussoirs) with its joints' k_n scattered
(CoV 0.3), 16 samples in threads; the probability of collapse against the support displacement
with its 95 % band, the running statistics and where the hinges sat, as a PDF of three pages.
usage: python3 fragility.py [OUT.pdf]   (more samples: voussoir montecarlo, docs/montecarlo.md)"""
import sys

from matplotlib.backends.backend_pdf import PdfPages

import voussoir
from voussoir import figures

case = voussoir.Case(arch__voussoirs=15, imperfections__kn_cov=0.3)
mc = voussoir.montecarlo(case, samples=16, seed=1, jobs=2)
u = mc.loc[mc["status"] == "collapse", "delta_u_mm"]
print(f"{len(u)} of {len(mc)} samples collapse, delta_u {u.min():.1f} .. {u.max():.1f} mm")
with PdfPages(sys.argv[1] if len(sys.argv) > 1 else "fragility.pdf") as pdf:
    pdf.savefig(figures.fragility(mc))
    pdf.savefig(figures.convergence(mc, span_mm=case.span_mm))
    pdf.savefig(figures.hinge_histogram(mc, joints=case["arch.voussoirs"] + 1))
