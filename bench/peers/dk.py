"""numpy/scipy peer of `microbrdf ndf SCAN --method kirchhoff --dk-stack single -o OUT.npy`
(Dong 2015 eq. 6 and App. A; docs/kirchhoff.md, with its defaults: lambda_q 555 nm, midpoint
rule, Hann window, 70 x 53 um patches, node values as cell averages where the table is coarser
than lambda_q / (2 L), Nyquist mask). Plane-levelled first, as the CLI does.

Per tile (round(L / patch) equal tiles per axis, at least one; the remainder left out) and per
table node m = (m_x, m_y, m_z), q = 4 pi m / lambda_q:

    I(q) = dx dy sum_j w_j (q_z - q_x gx_j - q_y gy_j) exp(-i (q_x x_j + q_y y_j + q_z h_j))

w = the Hann taper sin^2(pi (i + 1/2) / n) per axis on valid samples (0 on invalid ones),
(gx, gy) = central differences over valid neighbours in the whole scan (one-sided beside a hole
or an edge, 0 with none). The table is sum over tiles of |I|^2, zero outside the disk, normalised
to sum D delta^2 = 1 (the factor 1 / (4 pi^2 A_w) cancels).

How: at fixed q_z the sum is a 2-D DFT at the nodes' (q_x, q_y), a regular grid, so it is two
chirp-z (zoom) FFTs (scipy.signal.ZoomFFT) per array; q_z varies from node to node, so the
amplitude is computed on K Chebyshev slices q_z in [0, |q|] and interpolated to every node's own
q_z (barycentric formula). The amplitude is an entire function of q_z whose bandwidth is the
tile's height half-range H, so K ~ |q| H / 2 + a margin converges fast (--slices; the default
adds 8 slices to |q| H / 2; `--check` also runs 8 more slices and prints the relative L1
between the two tables). Only the specular split of scans with 8 tiles or more (docs/kirchhoff.md,
"The specular part") is not implemented: such scans are refused.

usage: dk.py SCAN.npy OUT.npy [--wavelength M] [--resolution N] [--slices K] [--check]
"""
import sys

import numpy as np
from scipy.signal import ZoomFFT

from scan import level_plane, normalise_disk, read_scan, save_table, table_parser


def tiles(n, d, patch):
    count = max(1, min(int(round(n * d / patch)), n))
    return count, n // count


def slopes(z, valid, d, axis):
    """Central differences along `axis` over valid neighbours, one-sided or 0 without them."""
    zz = np.moveaxis(np.where(valid, z, 0.0), axis, 0)
    vv = np.moveaxis(valid, axis, 0)
    lo = np.zeros_like(vv)
    hi = np.zeros_like(vv)
    lo[1:] = vv[:-1]
    hi[:-1] = vv[1:]
    zlo = np.zeros_like(zz)
    zhi = np.zeros_like(zz)
    zlo[1:] = zz[:-1]
    zhi[:-1] = zz[1:]
    g = np.where(lo & hi, (zhi - zlo) / (2 * d),
                 np.where(hi, (zhi - zz) / d, np.where(lo, (zz - zlo) / d, 0.0)))
    return np.moveaxis(g, 0, axis)


def tile_intensity(h, w, gx, gy, dx, dy, qmax, nf, slices):
    """|I|^2 on the nf x nf node grid of one tile (0 outside the disk)."""
    ny, nx = h.shape
    m = -1.0 + 2.0 * np.arange(nf) / (nf - 1)
    qx, qy = qmax * m, qmax * m
    r2 = m[None, :] ** 2 + m[:, None] ** 2
    disk = r2 < 1
    qz_node = qmax * np.sqrt(np.where(disk, 1 - r2, 0.0))
    # Heights about the middle of their range: a global phase, |I| is unchanged.
    hv = h[w > 0]
    h = h - 0.5 * (hv.min() + hv.max())
    zx = ZoomFFT(nx, [-qmax, qmax], nf, fs=2 * np.pi / dx, endpoint=True)
    zy = ZoomFFT(ny, [-qmax, qmax], nf, fs=2 * np.pi / dy, endpoint=True)
    # Chebyshev points of the first kind on [0, qmax] and their barycentric weights.
    k = np.arange(slices)
    theta = (2 * k + 1) * np.pi / (2 * slices)
    nodes = 0.5 * qmax * (1 - np.cos(theta))
    lam = (-1.0) ** k * np.sin(theta)
    num = np.zeros((nf, nf), complex)
    den = np.zeros((nf, nf))
    for qz, lk in zip(nodes, lam):
        e = w * np.exp(-1j * qz * h)
        xa = zx(e, axis=1)  # (ny, nf): sum over x at every q_x
        x1 = qz * xa - qx[None, :] * zx(e * gx, axis=1)
        x2 = zx(e * gy, axis=1)
        amp = zy(x1, axis=0) - qy[:, None] * zy(x2, axis=0)  # (nf, nf), rows q_y
        diff = qz_node - qz
        diff[diff == 0] = 1e-300  # a node on a slice: its weight dominates, as it should
        c = lk / diff
        num += c * amp
        den += c
    amp = num / den * (dx * dy)
    return np.where(disk, np.abs(amp) ** 2, 0.0)


def dk_table(z, valid, dx, dy, wavelength, resolution, slices_extra, slices=None,
             patch=(70e-6, 53e-6)):
    ny, nx = z.shape
    cx, lx = tiles(nx, dx, patch[0])
    cy, ly = tiles(ny, dy, patch[1])
    if cx * cy >= 8:
        sys.exit("dk.py: %d tiles: the specular split of 8 tiles or more is not implemented"
                 % (cx * cy))
    qmax = 4 * np.pi / wavelength
    # Cell averages of S x S sub-nodes when the node spacing exceeds lambda_q / (2 L).
    delta = 2.0 / (resolution - 1)
    s = max(1, int(np.ceil(min(delta * 2 * max(lx * dx, ly * dy) / wavelength, 1e6) - 1e-9)))
    s += s % 2 == 0
    while s > 1 and s * (resolution - 1) + 1 > 1025:
        s -= 2
    nf = s * (resolution - 1) + 1
    gx, gy = slopes(z, valid, dx, 1), slopes(z, valid, dy, 0)
    wx = np.sin(np.pi * (np.arange(lx) + 0.5) / lx) ** 2
    wy = np.sin(np.pi * (np.arange(ly) + 0.5) / ly) ** 2
    fine = np.zeros((nf, nf))
    used = 0
    for ty in range(cy):
        for tx in range(cx):
            sl = (slice(ty * ly, (ty + 1) * ly), slice(tx * lx, (tx + 1) * lx))
            v = valid[sl]
            if not v.any():
                continue
            w = np.where(v, wy[:, None] * wx[None, :], 0.0)
            h = np.where(v, z[sl], 0.0)
            half_range = 0.5 * (h[v].max() - h[v].min())
            k = slices or int(np.ceil(qmax * half_range / 2)) + slices_extra
            used = max(used, k)
            fine += tile_intensity(h, w, gx[sl], gy[sl], dx, dy, qmax, nf, k)
    # Nyquist mask: nodes beyond the scan's band are aliases.
    q = qmax * (-1.0 + 2.0 * np.arange(nf) / (nf - 1))
    fine[np.abs(q) > np.pi / dy, :] = 0.0
    fine[:, np.abs(q) > np.pi / dx] = 0.0
    if s > 1:  # every sub-node belongs to one cell; cells clipped at the grid's edge
        fine = np.pad(fine, s // 2).reshape(resolution, s, resolution, s).sum(axis=(1, 3))
    return normalise_disk(fine), used


def main():
    ap = table_parser(__doc__)
    ap.add_argument("--wavelength", type=float, default=555e-9, help="lambda_q, m")
    ap.add_argument("--slices", type=int, default=None, help="q_z slices (default: auto)")
    ap.add_argument("--check", action="store_true", help="also run 8 more slices, print the L1")
    a = ap.parse_args()
    z, valid, dx, dy = read_scan(a.scan)
    z = level_plane(z, valid)
    table, k = dk_table(z, valid, dx, dy, a.wavelength, a.resolution, 8, a.slices)
    save_table(a.out, table)
    if a.check:
        more, k2 = dk_table(z, valid, dx, dy, a.wavelength, a.resolution, 16, k + 8)
        print("dk.py: %d vs %d q_z slices: relative L1 %.3g"
              % (k, k2, np.abs(table - more).sum() / np.abs(more).sum()), file=sys.stderr)


if __name__ == "__main__":
    main()
