"""numpy/scipy peer of `microbrdf ndf SCAN --method filtered [--filter-sigma S] -o OUT.npy`
(Dong 2015 section 5.1; docs/theory.md sections 3.1-3.3): at every valid sample, the normal of
the plane fitted by least squares to the valid samples weighted with a 2-D Gaussian of std sigma
(taps out to floor(4 sigma / spacing) per axis, nothing outside the scan), each normal adding
dx dy at its position on the table, shared bilinearly by the four nearest nodes. Samples whose
weighted support is below --min-support (0.5) of the whole kernel's weight, or whose fit is
ill-conditioned, are skipped. Plane-levelled first, as the CLI does.

The weighted moments are separable correlations of the masked heights (scipy.ndimage), the
plane fit is solved in closed form per sample. For --filter-sigma auto, pass the sigma the CLI
chose (its JSON's filter_sigma_m).

usage: filtered_ndf.py SCAN.npy OUT.npy [--sigma METRES] [--min-support F] [--resolution N]
"""
import numpy as np
from scipy.ndimage import correlate1d

from scan import level_plane, read_scan, save_table, splat_table, table_parser


def taps(spacing, sigma, truncate=4.0):
    """Gaussian taps g, g u, g u^2 at offsets u = k spacing / sigma, |k| <= truncate sigma."""
    reach = int(np.floor(truncate * sigma / spacing))
    u = np.arange(-reach, reach + 1) * spacing / sigma
    g = np.exp(-0.5 * u * u)
    return g, g * u, g * u * u


def main():
    ap = table_parser(__doc__)
    ap.add_argument("--sigma", type=float, default=1e-6, help="filter sigma, m (default 1 um)")
    ap.add_argument("--min-support", type=float, default=0.5)
    a = ap.parse_args()
    z, valid, dx, dy = read_scan(a.scan)
    z = level_plane(z, valid)
    v = valid.astype(np.float64)
    h = np.where(valid, z - np.nanmean(z), 0.0)
    gx, ux, uux = taps(dx, a.sigma)
    gy, uy, uuy = taps(dy, a.sigma)

    def xy(img, kx, ky):  # sum over the window of img * kx(column offset) * ky(row offset)
        t = correlate1d(img, kx, axis=1, mode="constant")
        return correlate1d(t, ky, axis=0, mode="constant")

    m00, m10, m01 = xy(v, gx, gy), xy(v, ux, gy), xy(v, gx, uy)
    m20, m11, m02 = xy(v, uux, gy), xy(v, ux, uy), xy(v, gx, uuy)
    b00, b10, b01 = xy(h, gx, gy), xy(h, ux, gy), xy(h, gx, uy)
    # Weighted least squares for h = c + bx u + by v: centre the moments, solve the 2x2 system.
    with np.errstate(divide="ignore", invalid="ignore"):
        cu, cv = m10 / m00, m01 / m00
        suu, svv, suv = m20 - m10 * cu, m02 - m01 * cv, m11 - m10 * cv
        shu, shv = b10 - b00 * cu, b01 - b00 * cv
        det = suu * svv - suv * suv
        ok = valid & (m00 >= a.min_support * gx.sum() * gy.sum()) & (det > 1e-10 * m00 * m00)
        bx = (shu * svv - shv * suv)[ok] / det[ok] / a.sigma  # dz/dx, dimensionless
        by = (shv * suu - shu * suv)[ok] / det[ok] / a.sigma
    inv = 1.0 / np.sqrt(1.0 + bx * bx + by * by)
    save_table(a.out, splat_table(-bx * inv, -by * inv, dx * dy, a.resolution))


if __name__ == "__main__":
    main()
