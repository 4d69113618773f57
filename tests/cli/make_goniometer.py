#!/usr/bin/python3
"""A goniometer CSV of a known anisotropic GGX conductor at a fixed theta_d, for the CLI tests.

    make_goniometer.py OUT --alpha AX AY [--theta-d 14.14] [--rings 50] [--max-r 0.85]
        [--seed 4] [--min-cos 0] [--n N --k K] [--smith] [--wavelength 550] [--digits 10]
        [--extra-column]

Half vectors on rings of the disk (radius max_r (ring/rings)^1.5, 80 jittered azimuths each),
each with a random plane of incidence, wi and wo theta_d/2 either side of h. The value is
F(cos(theta_d/2)) D(h) G / (4 cos_i cos_o): F = 1 unless --n/--k are given (exact conductor
Fresnel, unpolarised), G = 1 unless --smith (height-correlated Smith, GGX Lambda). Points with
cos_i or cos_o <= min-cos are left out. --extra-column adds an ignored text column.
"""
import argparse

import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("--alpha", type=float, nargs=2, required=True)
ap.add_argument("--theta-d", type=float, default=14.14)
ap.add_argument("--rings", type=int, default=50)
ap.add_argument("--max-r", type=float, default=0.85)
ap.add_argument("--seed", type=int, default=4)
ap.add_argument("--min-cos", type=float, default=None)
ap.add_argument("--n", type=float)
ap.add_argument("--k", type=float)
ap.add_argument("--smith", action="store_true")
ap.add_argument("--wavelength", default="550")
ap.add_argument("--digits", type=int, default=10)
ap.add_argument("--extra-column", action="store_true")
a = ap.parse_args()
ax, ay = a.alpha
half = np.radians(a.theta_d) / 2


def fresnel(c):
    if a.n is None:
        return 1.0
    eta = a.n + 1j * a.k
    ct = np.sqrt(1 - (1 - c * c) / eta**2)
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


def lam(w):
    t2 = (w[0] ** 2 * ax**2 + w[1] ** 2 * ay**2) / w[2] ** 2
    return (np.sqrt(1 + t2) - 1) / 2


def ang(w):
    return np.degrees(np.arccos(w[2])), np.degrees(np.arctan2(w[1], w[0]))


rng = np.random.default_rng(a.seed)
head = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr"
rows = [head + (",instrument_note" if a.extra_column else "")]
d = a.digits
for ring in range(1, a.rings + 1):
    for k in range(80):
        r, phi = a.max_r * (ring / a.rings) ** 1.5, 2 * np.pi * (k + rng.random()) / 80
        h = np.array([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - r * r)])
        t1 = np.cross(h, [0, 0, 1])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(h, t1)
        psi = 2 * np.pi * rng.random()
        b = np.cos(psi) * t1 + np.sin(psi) * t2
        wi, wo = np.cos(half) * h + np.sin(half) * b, np.cos(half) * h - np.sin(half) * b
        if a.min_cos is not None and (wi[2] <= a.min_cos or wo[2] <= a.min_cos):
            continue
        D = 1 / (np.pi * ax * ay * (h[0] ** 2 / ax**2 + h[1] ** 2 / ay**2 + h[2] ** 2) ** 2)
        G = 1 / (1 + lam(wi) + lam(wo)) if a.smith else 1.0
        f = fresnel(np.cos(half)) * D * G / (4 * wi[2] * wo[2])
        ti, pi = ang(wi)
        to, po = ang(wo)
        rows.append(f"{ti:.{d}f},{pi:.{d}f},{to:.{d}f},{po:.{d}f},{a.wavelength},{f:.{d}g}"
                    + (",x" if a.extra_column else ""))
open(a.out, "w").write("\n".join(rows) + "\n")
