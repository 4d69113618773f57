#!/usr/bin/env bash
# Scans + a goniometer file -> comparison (docs/measured.md), end to end, drawing the figures of
# that page. Usage: examples/measured/workflow.sh [BIN] [OUT]   (defaults: build/bin/microbrdf,
# measured-demo). Needs the Python module (PYTHONPATH=build/python) for the virtual goniometer.
#
# The "scan" is a brushed patch written by `generate` (a profilometer stand-in). The goniometer
# file is a virtual measurement of a second patch of the same finish (another seed): 12 000
# points at theta_d = 14.14 deg of that patch's wave-optics (Kirchhoff, Dong eq. 8) BRDF at
# 550 nm, with 2 % multiplicative noise. A real instrument's file goes in its place unchanged.
set -euo pipefail
BIN=$(realpath "${1:-build/bin/microbrdf}")
OUT=${2:-measured-demo}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
export PYTHONPATH=${PYTHONPATH:-$ROOT/build/python}
mkdir -p "$OUT" && cd "$OUT"

# 1. Two patches of one brushed finish (0.06 along, 0.2 across the brushing).
for s in 1 2; do
  "$BIN" generate brushed --alpha-along 0.06 --alpha-across 0.2 --nx 1024 --ny 512 --seed $s \
    -o patch$s.x3p >/dev/null
done
# 2. The predictions from the scan: the filtered NDF (Dong 2015 sec. 5.1, geometric optics)
#    and the Kirchhoff D_K (sec. 6, wave optics at 550 nm, 28 um tiles).
"$BIN" ndf patch1.x3p --method filtered --filter-sigma 1um --resolution 513 -o filtered.npy \
  >/dev/null
"$BIN" ndf patch1.x3p --method kirchhoff --wavelength 550nm --patch 28x28um --resolution 513 \
  -o kirchhoff.npy >/dev/null
# 3. The virtual goniometer on patch 2.
"$BIN" ndf patch2.x3p --method kirchhoff --wavelength 550nm --patch 28x28um --resolution 513 \
  -o dk.npy >/dev/null
/usr/bin/python3 - <<'PY'
import numpy as np, microbrdf as mb
b = mb.brdf(kirchhoff="dk.npy", metal="Al")
rng = np.random.default_rng(7)
half = np.radians(14.14) / 2
r = 0.75 * np.sqrt(rng.random(12000)); a = 2 * np.pi * rng.random(12000)
h = np.column_stack([r * np.cos(a), r * np.sin(a), np.sqrt(1 - r * r)])
t1 = np.cross(h, [0, 0, 1]); t1 /= np.linalg.norm(t1, axis=1)[:, None]; t2 = np.cross(h, t1)
psi = 2 * np.pi * rng.random(12000)
bb = np.cos(psi)[:, None] * t1 + np.sin(psi)[:, None] * t2
wi, wo = np.cos(half) * h + np.sin(half) * bb, np.cos(half) * h - np.sin(half) * bb
ok = (wi[:, 2] > 0.05) & (wo[:, 2] > 0.05)
wi, wo = wi[ok], wo[ok]
f = b.eval(wi, wo, wavelength=550e-9) * (1 + 0.02 * rng.standard_normal(len(wi)))
deg = lambda w: (np.degrees(np.arccos(w[:, 2])), np.degrees(np.arctan2(w[:, 1], w[:, 0])))
ti, pi = deg(wi); to, po = deg(wo)
np.savetxt("goniometer.csv", np.column_stack([ti, pi, to, po, np.full(len(f), 550.0), f]),
           delimiter=",", fmt="%.6f",
           header="theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr",
           comments="")
print(f"goniometer.csv: {len(f)} points")
PY
# 4. Measurement -> effective NDF (Dong eq. 9), with the material's Fresnel term; the points
#    are splatted with a 1 deg kernel (about a detector's aperture).
"$BIN" measured ndf goniometer.csv --metal Al --kernel 1deg --resolution 513 -o measured.npy
"$BIN" fit measured.npy --model ggx --json >measured_fit.json
# 5. The comparison (Dong Figs. 8-9 layout), and the same inside the predict report.
"$BIN" measured compare measured.npy filtered.npy kirchhoff.npy --report compare
"$BIN" predict patch1.x3p --metal Al --no-render --resolution 513 --measured measured.npy \
  -o report --quiet >/dev/null
echo "figures: $PWD/compare/{filtered,kirchhoff}/{measured,predicted,slices}.png;" \
  "report: $PWD/report/report.html"
