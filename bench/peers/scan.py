"""What every numpy peer starts with: a height map as `microbrdf generate ... -o SCAN.npy`
writes it (heights in metres, NaN where invalid, the spacing in the JSON sidecar SCAN.json),
levelled with a least-squares plane (the CLI's default, `--level plane`), and the NDF table's
normalisation.

The peers are written from the definitions in docs/ (what is computed), never from the
library's code paths, and never call the library: they are the independent reference the
harness bench/whole_process.py checks the CLI against, and the script a researcher would time
the CLI against.
"""
import argparse
import json
import os

import numpy as np


def table_parser(doc):
    """The command line every table peer shares: SCAN.npy OUT.npy [--resolution N]."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("scan")
    ap.add_argument("out")
    ap.add_argument("--resolution", type=int, default=1025, help="table size N (default 1025)")
    return ap


def read_scan(path):
    """Heights z (ny, nx) in metres (NaN = invalid), validity mask, dx, dy in metres."""
    z = np.load(path).astype(np.float64)
    with open(os.path.splitext(path)[0] + ".json") as f:
        side = json.load(f)
    valid = np.isfinite(z)
    return z, valid, float(side["dx_m"]), float(side["dy_m"])


def level_plane(z, valid):
    """z minus the least-squares plane through the valid samples (invalid samples stay NaN)."""
    ny, nx = z.shape
    # Column and row indices about the centre, scaled to [-1, 1] (conditioning only).
    u = (np.arange(nx) - (nx - 1) / 2) / max(1.0, (nx - 1) / 2)
    v = (np.arange(ny) - (ny - 1) / 2) / max(1.0, (ny - 1) / 2)
    U, V = np.meshgrid(u, v)
    A = np.stack([np.ones(valid.sum()), U[valid], V[valid]], axis=1)
    c, *_ = np.linalg.lstsq(A, z[valid], rcond=None)
    out = np.full_like(z, np.nan)
    out[valid] = z[valid] - A @ c
    return out


def splat_table(mx, my, weight, resolution):
    """The N x N disk table of normals (mx, my): node (ix, iy) at m = -1 + 2 (ix, iy)/(N-1),
    each normal's weight shared bilinearly by its four nodes, 0 outside the unit disk,
    normalised so that sum D delta^2 = 1 (the integral of D(m)(m.n) over the hemisphere)."""
    n = resolution
    delta = 2.0 / (n - 1)
    fx = (mx + 1.0) / delta
    fy = (my + 1.0) / delta
    keep = (fx >= 0) & (fx <= n - 1) & (fy >= 0) & (fy <= n - 1)
    fx, fy = fx[keep], fy[keep]
    w = np.broadcast_to(weight, keep.shape)[keep]
    ix = np.minimum(np.floor(fx), n - 2).astype(np.int64)
    iy = np.minimum(np.floor(fy), n - 2).astype(np.int64)
    tx, ty = fx - ix, fy - iy
    i00 = iy * n + ix
    table = np.bincount(i00, w * (1 - tx) * (1 - ty), minlength=n * n)
    table += np.bincount(i00 + 1, w * tx * (1 - ty), minlength=n * n)
    table += np.bincount(i00 + n, w * (1 - tx) * ty, minlength=n * n)
    table += np.bincount(i00 + n + 1, w * tx * ty, minlength=n * n)
    return normalise_disk(table.reshape(n, n))


def normalise_disk(table):
    """Zero outside the unit disk, then sum D delta^2 = 1."""
    n = table.shape[0]
    m = -1.0 + 2.0 * np.arange(n) / (n - 1)
    table[m[:, None] ** 2 + m[None, :] ** 2 > 1.0] = 0.0
    return table / (table.sum() * (2.0 / (n - 1)) ** 2)


def save_table(path, table):
    """The table as the CLI writes it: float64, C order, shape (N, N), row iy."""
    np.save(path, np.ascontiguousarray(table, dtype=np.float64))
