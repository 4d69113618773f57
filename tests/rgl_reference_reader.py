#!/usr/bin/python3
"""An independent reader of RGL .bsdf files (Dupuy & Jakob 2018), written from the format's
description (docs/measured.md) with numpy and sharing no code with microbrdf's C++ reader.

Where the C++ reader blends precomputed per-slice CDFs, this one blends the per-slice normalised
densities for the query's parameters first and builds the CDFs of that one bilinear density on
the fly (the two agree because every step is linear in the data).

Usage:
  rgl_reference_reader.py FILE eval QUERIES OUT
      QUERIES: lines "wix wiy wiz wox woy woz wavelength_nm"; OUT: one f (1/sr) per line.
  rgl_reference_reader.py FILE albedo THETA_DEG PHI_DEG WAVELENGTH_NM N
      prints the directional albedo estimated with the file's own sampling on N x N strata.
"""
import struct
import sys

import numpy as np

DTYPES = {1: np.uint8, 2: np.int8, 3: np.uint16, 4: np.int16, 5: np.uint32, 6: np.int32,
          7: np.uint64, 8: np.int64, 9: np.float16, 10: np.float32, 11: np.float64}


def read_tensor_file(path):
    blob = open(path, "rb").read()
    if blob[:12] != b"tensor_file\0":
        raise ValueError("not a tensor file")
    if tuple(blob[12:14]) != (1, 0):
        raise ValueError("version")
    (count,) = struct.unpack_from("<I", blob, 14)
    pos, fields = 18, {}
    for _ in range(count):
        (nlen,) = struct.unpack_from("<H", blob, pos)
        name = blob[pos + 2:pos + 2 + nlen].decode()
        pos += 2 + nlen
        ndim, dtype, offset = struct.unpack_from("<HBQ", blob, pos)
        pos += 11
        shape = struct.unpack_from("<%dQ" % ndim, blob, pos)
        pos += 8 * ndim
        dt = np.dtype(DTYPES[dtype]).newbyteorder("<")
        n = int(np.prod(shape)) if ndim else 1
        fields[name] = np.frombuffer(blob, dtype=dt, count=n, offset=offset).reshape(shape)
    return fields


def lerp_weights(nodes, x):
    """[(index, weight)] of the linear interpolation over `nodes` at x, clamped at the ends."""
    nodes = np.asarray(nodes, dtype=np.float64)
    if len(nodes) == 1:
        return [(0, 1.0)]
    i = int(np.clip(np.searchsorted(nodes, x, side="left") - 1, 0, len(nodes) - 2))
    t = float(np.clip((x - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0))
    return [(i, 1.0 - t), (i + 1, t)]


def blend(table, param_nodes, params, normalise):
    """The 2-D slice of `table` (params..., ny, nx) at `params`; each slice normalised to unit
    integral of its bilinear interpolant over [0,1]^2 first when `normalise`."""
    combos = [((), 1.0)]
    for nodes, x in zip(param_nodes, params):
        combos = [(idx + (i,), w * v) for idx, w in combos for i, v in lerp_weights(nodes, x)]
    out = 0.0
    for idx, w in combos:
        s = np.asarray(table[idx], dtype=np.float64)
        if normalise:
            ny, nx = s.shape
            cells = 0.25 * (s[:-1, :-1] + s[1:, :-1] + s[:-1, 1:] + s[1:, 1:])
            s = s / (cells.sum() / ((nx - 1) * (ny - 1)))
        out = out + w * s
    return out


def bilinear(d, x, y):
    ny, nx = d.shape
    px = np.clip(x, 0, 1) * (nx - 1)
    py = np.clip(y, 0, 1) * (ny - 1)
    ix = np.minimum(px.astype(int), nx - 2)
    iy = np.minimum(py.astype(int), ny - 2)
    tx, ty = px - ix, py - iy
    return ((1 - ty) * ((1 - tx) * d[iy, ix] + tx * d[iy, ix + 1]) +
            ty * ((1 - tx) * d[iy + 1, ix] + tx * d[iy + 1, ix + 1]))


class Warp:
    """Continuous marginal (y) / conditional (x) warp of one bilinear density (unit integral)."""

    def __init__(self, d):
        self.d = d
        ny, nx = d.shape
        self.nx, self.ny = nx, ny
        # CDFs in "node units": column steps of 1, row steps of 1 (rescaled at the end).
        self.cond = np.concatenate([np.zeros((ny, 1)),
                                    np.cumsum(0.5 * (d[:, :-1] + d[:, 1:]), axis=1)], axis=1)
        row = self.cond[:, -1]
        self.marg = np.concatenate([[0.0], np.cumsum(0.5 * (row[:-1] + row[1:]))])
        self.total = self.marg[-1]

    def pdf(self, x, y):
        return bilinear(self.d, x, y)

    def invert(self, x, y):
        nx, ny = self.nx, self.ny
        px, py = np.clip(x, 0, 1) * (nx - 1), np.clip(y, 0, 1) * (ny - 1)
        ix, iy = np.minimum(px.astype(int), nx - 2), np.minimum(py.astype(int), ny - 2)
        s, t = px - ix, py - iy
        d = self.d
        c0 = (1 - t) * d[iy, ix] + t * d[iy + 1, ix]
        c1 = (1 - t) * d[iy, ix + 1] + t * d[iy + 1, ix + 1]
        # integral over columns [0, ix + s] of the density at row position iy + t
        before = (1 - t) * self.cond[iy, ix] + t * self.cond[iy + 1, ix]
        ux = before + s * c0 + 0.5 * s * s * (c1 - c0)
        r0, r1 = self.cond[iy, -1], self.cond[iy + 1, -1]
        ux = ux / ((1 - t) * r0 + t * r1)
        uy = (self.marg[iy] + t * r0 + 0.5 * t * t * (r1 - r0)) / self.total
        return ux, uy

    def sample(self, ux, uy):
        eps = 1e-7
        ux, uy = np.clip(ux, eps, 1 - eps), np.clip(uy, eps, 1 - eps)
        target = uy * self.total
        row = np.clip(np.searchsorted(self.marg, target, side="right") - 1, 0, self.ny - 2)
        rem = target - self.marg[row]
        r0, r1 = self.cond[row, -1], self.cond[row + 1, -1]
        # r0 t + (r1 - r0) t^2 / 2 = rem, solved in the cancellation-free form
        disc = np.sqrt(np.maximum(r0 * r0 + 2 * rem * (r1 - r0), 0))
        t = np.clip(np.where(r0 + disc > 0, 2 * rem / np.maximum(r0 + disc, 1e-300), 0), 0, 1)
        cond_t = (1 - t)[:, None] * self.cond[row] + t[:, None] * self.cond[row + 1]
        target_x = ux * cond_t[:, -1]
        col = np.clip((cond_t < target_x[:, None]).sum(axis=1) - 1, 0, self.nx - 2)
        remx = target_x - cond_t[np.arange(len(col)), col]
        d = self.d
        c0 = (1 - t) * d[row, col] + t * d[row + 1, col]
        c1 = (1 - t) * d[row, col + 1] + t * d[row + 1, col + 1]
        disc = np.sqrt(np.maximum(c0 * c0 + 2 * remx * (c1 - c0), 0))
        s = np.clip(np.where(c0 + disc > 0, 2 * remx / np.maximum(c0 + disc, 1e-300), 0), 0, 1)
        x, y = (col + s) / (self.nx - 1), (row + t) / (self.ny - 1)
        return x, y, self.pdf(x, y)


class Bsdf:
    def __init__(self, path):
        f = read_tensor_file(path)
        self.theta_i = f["theta_i"].astype(np.float64)
        self.phi_i = f["phi_i"].astype(np.float64)
        self.ndf = f["ndf"].astype(np.float64)
        self.sigma = f["sigma"].astype(np.float64)
        self.vndf = f["vndf"]
        self.lum = f["luminance"]
        self.spectra = f["spectra"]
        self.wl = f["wavelengths"].astype(np.float64)
        self.jacobian = bool(f["jacobian"][0])
        self.isotropic = len(self.phi_i) <= 2
        if len(self.phi_i) > 2:
            span = self.phi_i[-1] - self.phi_i[0]
            assert round(2 * np.pi / span) == 1, "reduced azimuth ranges are not handled here"

    @staticmethod
    def angles(v):
        theta = np.arccos(np.clip(v[2], -1, 1))
        return theta, np.arctan2(v[1], v[0])

    @staticmethod
    def u_of(theta, phi):
        return np.sqrt(theta / (np.pi / 2)), (phi + np.pi) / (2 * np.pi)

    def slice_params(self, phi_i, theta_i):
        return (self.phi_i, self.theta_i), (phi_i, theta_i)

    def spectrum_at(self, sx, sy, phi_i, theta_i, wl_nm):
        d = blend(self.spectra, (self.phi_i, self.theta_i, self.wl), (phi_i, theta_i, wl_nm), False)
        return bilinear(d, sx, sy)

    def eval(self, wi, wo, wl_nm):
        wi, wo = np.asarray(wi, float), np.asarray(wo, float)
        if wi[2] <= 0 or wo[2] <= 0:
            return 0.0
        m = (wi + wo) / np.linalg.norm(wi + wo)
        theta_i, phi_i = self.angles(wi)
        theta_m, phi_m = self.angles(m)
        ux, uy = self.u_of(theta_m, phi_m - phi_i if self.isotropic else phi_m)
        uy = uy - np.floor(uy)
        nodes, params = self.slice_params(phi_i, theta_i)
        warp = Warp(blend(self.vndf, nodes, params, True))
        sx, sy = warp.invert(np.array([ux]), np.array([uy]))
        r = self.spectrum_at(sx, sy, phi_i, theta_i, wl_nm)[0]
        if self.jacobian:
            wx, wy = self.u_of(theta_i, phi_i)
            r *= bilinear(self.ndf, np.array([ux]), np.array([uy]))[0] / (
                4 * bilinear(self.sigma, np.array([wx]), np.array([wy]))[0])
        return r / wo[2]

    def albedo(self, wi, wl_nm, n):
        theta_i, phi_i = self.angles(wi)
        nodes, params = self.slice_params(phi_i, theta_i)
        lum = Warp(blend(self.lum, nodes, params, True))
        vndf = Warp(blend(self.vndf, nodes, params, True))
        g = (np.arange(n) + 0.5) / n
        u1, u2 = [a.ravel() for a in np.meshgrid(g, g)]
        sx, sy, p_lum = lum.sample(u1, u2)
        ux, uy, p_vndf = vndf.sample(sx, sy)
        theta_m = ux * ux * np.pi / 2
        phi_m = (2 * uy - 1) * np.pi + (phi_i if self.isotropic else 0)
        m = np.stack([np.sin(theta_m) * np.cos(phi_m), np.sin(theta_m) * np.sin(phi_m),
                      np.cos(theta_m)])
        wim = wi @ m
        wo = 2 * wim * m - wi[:, None]
        jac = np.maximum(2 * np.pi ** 2 * ux * np.sin(theta_m), 1e-6) * 4 * wim
        pdf = p_lum * p_vndf / jac
        r = self.spectrum_at(sx, sy, phi_i, theta_i, wl_nm)
        if self.jacobian:
            wx, wy = self.u_of(theta_i, phi_i)
            r = r * bilinear(self.ndf, ux, uy) / (
                4 * bilinear(self.sigma, np.array([wx]), np.array([wy]))[0])
        ok = (wo[2] > 0) & (pdf > 0) & (wim > 0)
        weights = np.where(ok, r / np.where(ok, pdf, 1), 0)
        return weights.mean()


def main():
    b = Bsdf(sys.argv[1])
    if sys.argv[2] == "eval":
        q = np.loadtxt(sys.argv[3], ndmin=2)
        out = [b.eval(row[0:3], row[3:6], row[6]) for row in q]
        np.savetxt(sys.argv[4], np.array(out), fmt="%.9g")
    elif sys.argv[2] == "albedo":
        t, p = np.radians(float(sys.argv[3])), np.radians(float(sys.argv[4]))
        wi = np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])
        print("%.9g" % b.albedo(wi, float(sys.argv[5]), int(sys.argv[6])))
    else:
        sys.exit("unknown mode " + sys.argv[2])


if __name__ == "__main__":
    main()
