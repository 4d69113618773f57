"""Tabulates the runs of validation_kirchhoff_grid.sh: per surface, method and incidence, the
median and the 10th / 90th percentiles of the ratio to the Beckmann-Spizzichino series over the
range from 2 deg off the mirror direction to 1e-3 of the series' peak (Markdown on stdout)."""
import sys
from pathlib import Path

import numpy as np

work, root = Path(sys.argv[1]), Path(sys.argv[2])
sys.path.insert(0, str(root / "scripts"))
from bs_series import compared_range, index, read_slice, series  # noqa: E402

LAM = 555e-9
print("| σ | τ | g at 0° | method | metal | θ_i 0° | θ_i 20° | θ_i 45° | θ_i 70° |")
print("|---|---|---|---|---|---|---|---|---|")
for sigma in (2, 5, 20, 80):
    for tau in (1, 5):
        g0 = (4 * np.pi * sigma * 1e-9 / LAM) ** 2
        for method, label in (("dk", "D_K (defaults)"), ("rr", "Rayleigh-Rice")):
            for metal in ("Al", "Au"):
                cells = []
                for ti in (0, 20, 45, 70):
                    a, b = read_slice(work / f"s{sigma}_{tau}_{method}_{metal}_{ti}.csv")
                    ref = series(ti, a, sigma * 1e-9, tau * 1e-6, index(root, metal, LAM), LAM)
                    sel = compared_range(a, ref, ti)
                    r = b[sel] / ref[sel]
                    p10, med, p90 = np.percentile(r, [10, 50, 90])
                    cells.append(f"{med:.2f} ({p10:.2f}–{p90:.2f})")
                print(f"| {sigma} nm | {tau} µm | {g0:.3g} | {label} | {metal} | " + " | ".join(cells)
                      + " |")
