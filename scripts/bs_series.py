"""Reference formulas for a Gaussian surface with Gaussian correlation, written on their own (no
microbrdf code): the Beckmann-Spizzichino ensemble series of the scalar Kirchhoff integral with the
(q.m) factor (how D_K is defined, docs/kirchhoff.md) and the scalar first-order (Rayleigh-Rice)
limit of the same surface's PSD.

  D_K(q) = |q|^4 / (4 pi^2 q_z^2) exp(-g) sum_m g^m / m! (pi tau^2 / m) exp(-q_xy^2 tau^2 / (4 m)),
  g = (q_z sigma)^2, q = (2 pi / lambda)(wi + wo);  f = D_K F(wi.h) / (4 cos_i cos_o)  (Dong eq. 8,
  G = 1), F the unpolarised Fresnel reflectance of the complex index, linearly interpolated in the
  repository's optical-constant tables (data/optical).
"""
import csv
from pathlib import Path

import numpy as np

TABLES = {"Al": "Al_Rakic1995.csv", "Au": "Au_JohnsonChristy1972.csv"}


def index(root, metal, lam):
    rows = list(csv.DictReader(open(Path(root) / "data" / "optical" / TABLES[metal])))
    wl = np.array([float(r["wavelength_nm"]) for r in rows])
    n = np.interp(lam * 1e9, wl, [float(r["n"]) for r in rows])
    k = np.interp(lam * 1e9, wl, [float(r["k"]) for r in rows])
    return complex(n, k)


def fresnel(c, eta):
    ct = np.sqrt(eta**2 - (1 - c * c) + 0j)
    rs = (c - ct) / (c + ct)
    rp = (eta**2 * c - ct) / (eta**2 * c + ct)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


def in_plane(theta_i, theta_o):
    """wi (light at azimuth 180 deg) and wo in the plane of incidence, angles in degrees."""
    ti, to = np.radians(theta_i), np.radians(np.asarray(theta_o, float))
    wi = np.array([-np.sin(ti), 0, np.cos(ti)])
    wo = np.stack([np.sin(to), np.zeros_like(to), np.cos(to)], -1)
    return wi, wo


def series(theta_i, theta_o, sigma, tau, eta, lam, terms=60):
    """In-plane BRDF (1/sr) of the Beckmann-Spizzichino series (diffuse part, m >= 1)."""
    wi, wo = in_plane(theta_i, theta_o)
    q = 2 * np.pi / lam * (wi[None, :] + wo)
    qxy2, qz = q[:, 0] ** 2 + q[:, 1] ** 2, q[:, 2]
    g = (qz * sigma) ** 2
    s, term = np.zeros_like(g), np.exp(-g)
    for m in range(1, terms):
        term = term * g / m
        s += term * (np.pi * tau**2 / m) * np.exp(-qxy2 * tau**2 / (4 * m))
    d = (qxy2 + qz**2) ** 2 / (4 * np.pi**2 * qz**2) * s
    h = q / np.linalg.norm(q, axis=1)[:, None]
    F = np.array([fresnel(float(wi @ x), eta) for x in h])
    return d * F / (4 * np.cos(np.radians(theta_i)) * wo[:, 2])


def read_slice(path):
    rows = list(csv.DictReader(l for l in open(path) if not l.startswith("#")))
    return (np.array([float(r["angle_deg"]) for r in rows]),
            np.array([float(r["brdf_per_sr"]) for r in rows]))


def compared_range(angles, ref, theta_i, off_specular=2.0, floor=1e-3):
    """From `off_specular` deg off the mirror direction to where the reference falls below
    `floor` of its peak."""
    peak = ref[np.abs(angles) < 88].max()
    return (np.abs(angles - theta_i) >= off_specular) & (ref > floor * peak) & (np.abs(angles) < 89.5)
