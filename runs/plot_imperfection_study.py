#!/usr/bin/env python3
"""Table and figure of runs/imperfection_study.sh: the face scatter at which the mean collapse at
alpha = 0 reaches 16.5 % of L (linear between amplitudes) and what it gives at alpha = 90.
usage: plot_imperfection_study.py TABLE.csv FIGURE.png"""
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1])))
def series(a):
    r = [x for x in rows if x["alpha_deg"] == a]
    return [float(x["face_mm"]) for x in r], [float(x["mean_over_L_pct"]) for x in r], [float(x["q05_over_L_pct"]) for x in r]
f0, m0, q0 = series("0"); f90, m90, q90 = series("90")
# the face scatter at which the alpha = 0 mean crosses 16.5 % (linear between amplitudes)
star = None
for i in range(len(f0) - 1):
    if (m0[i] - 16.5) * (m0[i + 1] - 16.5) <= 0 and m0[i] != m0[i + 1]:
        star = f0[i] + (16.5 - m0[i]) * (f0[i + 1] - f0[i]) / (m0[i + 1] - m0[i])
        break
if star is None:
    print("the alpha = 0 mean does not reach 16.5 %% of L for face_mm <= %g (lowest mean %.2f %% at %g mm)"
          % (f0[-1], min(m0), f0[m0.index(min(m0))]))
else:
    j = max(i for i in range(len(f90)) if f90[i] <= star)
    j = min(j, len(f90) - 2)
    p = m90[j] + (star - f90[j]) * (m90[j + 1] - m90[j]) / (f90[j + 1] - f90[j])
    print("alpha = 0 mean collapse at 16.5 %% of L for face_mm = %.3f mm; at that scatter alpha = 90 "
          "gives a mean of %.2f %% of L (measured 3.7 %%)" % (star, p))
    for x in rows:  # the sampling error of each mean: CoV x mean / sqrt(collapses)
        n = float(x["collapses"])
        if n > 0 and float(x["face_mm"]) in (f0[j], f0[j + 1]):
            print("  alpha %s, face_mm %s: mean %.2f +- %.2f %% of L (one standard error)"
                  % (x["alpha_deg"], x["face_mm"], float(x["mean_over_L_pct"]),
                     float(x["cov"]) * float(x["mean_over_L_pct"]) / n ** 0.5))
fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
for a, (f, m, q), meas, lab in ((ax[0], (f0, m0, q0), 16.5, "alpha = 0: dz_u / L (%)"),
                                (ax[1], (f90, m90, q90), 3.7, "alpha = 90: dx_u / L (%)")):
    a.plot(f, m, "o-", label="mean")
    a.plot(f, q, "s--", label="5 % quantile")
    a.axhline(meas, color="k", lw=0.8, ls=":", label="laboratory")
    if star is not None: a.axvline(star, color="r", lw=0.8, ls=":", label="face_mm matching alpha 0")
    a.set_xlabel("face_mm: sd of the as-built gap at a joint's open edge (mm)")
    a.set_ylabel(lab); a.grid(alpha=0.3); a.legend(fontsize=8)
fig.suptitle("k_n = 48 N/mm^3 with non-coplanar faces, %s samples per point" % rows[0]["samples"])
fig.tight_layout(); fig.savefig(sys.argv[2], dpi=110)
