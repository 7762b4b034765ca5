"""The seed domain, small: the limit displacement domain of the reference specimen's shape with
15 voussoirs at four directions of the support's motion and two joint stiffnesses (deformable
3 N/mm^3, rigid-like 48 N/mm^3), run in process in threads, drawn as a PDF.
usage: python3 seed_domain.py [OUT.pdf]   (the full domain: runs/domain_study.sh)"""
import sys

import voussoir
from voussoir import figures

case = voussoir.Case(arch__voussoirs=15)          # the reference specimen, 15 voussoirs
table = voussoir.sweep(case, alpha=[0, 30, 60, 90], kn=[3, 48], jobs=2)
print(table[["support.alpha_deg", "joints.kn_N_mm3", "status", "dz_over_L_pct",
             "dx_over_L_pct"]].round(2).to_string(index=False))
fig = figures.domain(table)
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "seed_domain.pdf")
