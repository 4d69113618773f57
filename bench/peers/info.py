"""numpy/scipy peer of `microbrdf info SCAN --json` (plane-levelled, as the CLI's default): the
statistics of its record that a numpy user computes, under the JSON's own keys, written to
OUT.json as {"surfaces": [record]}:
 - heights: mean_m, min_m, max_m, sq_m, sa_m, skewness, kurtosis (over valid samples);
 - slope_rms_x, slope_rms_y: central differences where both neighbours are valid;
 - corr_length_x_m, corr_length_y_m, corr_length_m: where the normalised autocorrelation (FFT,
   zero-padded to linear correlation, lags with >= 64 valid pairs) first falls to 1/e along x,
   along y and in its radial average (rings of the smaller spacing), linearly interpolated;
 - psd: the areal PSD of the whole scan with the Hann window sin^2(pi (i + 1/2)/n) per axis,
   window-weighted mean removed, dx dy |FFT|^2 / sum_valid w^2 (ISO 10110-8): sq_m,
   integral_m2, integral_over_sq2, rms_slope;
 - tis: per wavelength (405, 555, 633, 1064 nm) and incidence (0, 20, 45, 70 deg), the
   rayleigh_factor (4 pi Sq cos theta / lambda)^2 and propagating_sq_m, the rms height of the
   PSD's nodes with |lambda f - sin(theta) (-1, 0)| < 1.

usage: info.py SCAN.npy OUT.json
"""
import json
import sys

import numpy as np
from scipy import fft

from scan import level_plane, read_scan


def correlation_length(r, acf):
    """First 1/e crossing of acf(r), linearly interpolated; None if a gap or no crossing."""
    target = np.exp(-1.0)
    for i in range(1, len(r)):
        if not (np.isfinite(acf[i]) and np.isfinite(acf[i - 1])):
            return None
        if acf[i] <= target:
            t = (acf[i - 1] - target) / (acf[i - 1] - acf[i])
            return float(r[i - 1] + t * (r[i] - r[i - 1]))
    return None


def autocorrelation(h, valid, min_overlap=64):
    """Normalised ACF on lags (-(ny-1)..ny-1, -(nx-1)..nx-1), NaN where pairs < min_overlap."""
    ny, nx = h.shape
    shape = (fft.next_fast_len(2 * ny - 1), fft.next_fast_len(2 * nx - 1))
    hh = fft.irfft2(np.abs(fft.rfft2(h, shape)) ** 2, shape)
    vv = fft.irfft2(np.abs(fft.rfft2(valid.astype(np.float64), shape)) ** 2, shape)
    hh = np.roll(hh, (ny - 1, nx - 1), axis=(0, 1))[: 2 * ny - 1, : 2 * nx - 1]
    vv = np.roll(vv, (ny - 1, nx - 1), axis=(0, 1))[: 2 * ny - 1, : 2 * nx - 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        acf = np.where(vv >= min_overlap - 0.5, hh / vv, np.nan)
    return acf / acf[ny - 1, nx - 1]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("usage: ")[1])
    z, valid, dx, dy = read_scan(sys.argv[1])
    z = level_plane(z, valid)
    ny, nx = z.shape
    zv = z[valid]
    mean = zv.mean()
    d = zv - mean
    sq = np.sqrt(np.mean(d**2))
    rec = {"nx": nx, "ny": ny, "dx_m": dx, "dy_m": dy, "valid_count": int(valid.sum()),
           "mean_m": float(mean), "min_m": float(zv.min()), "max_m": float(zv.max()),
           "sq_m": float(sq), "sa_m": float(np.mean(np.abs(d))),
           "skewness": float(np.mean(d**3) / sq**3), "kurtosis": float(np.mean(d**4) / sq**4)}
    sx = (z[:, 2:] - z[:, :-2]) / (2 * dx)  # NaN wherever a neighbour is invalid
    sy = (z[2:, :] - z[:-2, :]) / (2 * dy)
    rec["slope_rms_x"] = float(np.sqrt(np.nanmean(sx**2)))
    rec["slope_rms_y"] = float(np.sqrt(np.nanmean(sy**2)))

    h = np.where(valid, z - mean, 0.0)
    acf = autocorrelation(h, valid)
    rec["corr_length_x_m"] = correlation_length(np.arange(nx) * dx, acf[ny - 1, nx - 1:])
    rec["corr_length_y_m"] = correlation_length(np.arange(ny) * dy, acf[ny - 1:, nx - 1])
    dr = min(dx, dy)
    nbins = int(min((nx - 1) * dx, (ny - 1) * dy) / dr) + 1
    lx = np.arange(-(nx - 1), nx) * dx
    ly = np.arange(-(ny - 1), ny) * dy
    b = np.floor(np.hypot(lx[None, :], ly[:, None]) / dr + 0.5).astype(np.int64)
    use = np.isfinite(acf) & (b < nbins)
    sums = np.bincount(b[use], acf[use], minlength=nbins)
    counts = np.bincount(b[use], minlength=nbins)
    ring = counts > 0
    rec["corr_length_m"] = correlation_length(np.arange(nbins)[ring] * dr,
                                              sums[ring] / counts[ring])

    # Areal PSD, Hann window, the whole scan as one tile.
    wx = np.sin(np.pi * (np.arange(nx) + 0.5) / nx) ** 2
    wy = np.sin(np.pi * (np.arange(ny) + 0.5) / ny) ** 2
    w = np.where(valid, wy[:, None] * wx[None, :], 0.0)
    tile_mean = (w * np.where(valid, z, 0.0)).sum() / w.sum()
    psd = np.abs(fft.fft2(np.where(valid, z - tile_mean, 0.0) * w)) ** 2 * dx * dy / (w**2).sum()
    psd[0, 0] = 0.0
    dfx, dfy = 1 / (nx * dx), 1 / (ny * dy)
    fx, fy = np.fft.fftfreq(nx, dx), np.fft.fftfreq(ny, dy)
    integral = psd.sum() * dfx * dfy
    f2 = fx[None, :] ** 2 + fy[:, None] ** 2
    rec["psd"] = {"sq_m": float(sq), "integral_m2": float(integral),
                  "integral_over_sq2": float(integral / sq**2),
                  "rms_slope": float(np.sqrt((4 * np.pi**2 * f2 * psd).sum() * dfx * dfy))}
    rec["tis"] = []
    for lam in (405e-9, 555e-9, 633e-9, 1064e-9):
        for deg in (0.0, 20.0, 45.0, 70.0):
            th = np.radians(deg)
            inside = (lam * fx[None, :] + np.sin(th)) ** 2 + (lam * fy[:, None]) ** 2 < 1
            rec["tis"].append({"wavelength_m": lam, "theta_i_rad": float(th),
                               "rayleigh_factor": float((4 * np.pi * sq * np.cos(th) / lam) ** 2),
                               "propagating_sq_m": float(np.sqrt(psd[inside].sum() * dfx * dfy))})
    with open(sys.argv[2], "w") as f:
        json.dump({"surfaces": [rec]}, f)


if __name__ == "__main__":
    main()
