"""numpy peer of `microbrdf ndf SCAN --method naive -o OUT.npy` (Dong 2015 eq. 2; docs/theory.md
section 2.2): every grid cell is two triangles split along its (ix, iy)-(ix+1, iy+1) diagonal;
each triangle with three valid corners adds its projected area dx dy / 2 at its unit normal,
shared bilinearly by the four nearest table nodes. Plane-levelled first, as the CLI does.

usage: naive_ndf.py SCAN.npy OUT.npy [--resolution N]
"""
import numpy as np

from scan import level_plane, read_scan, save_table, splat_table, table_parser


def main():
    ap = table_parser(__doc__)
    a = ap.parse_args()
    z, valid, dx, dy = read_scan(a.scan)
    z = level_plane(z, valid)
    z00, z10, z01, z11 = z[:-1, :-1], z[:-1, 1:], z[1:, :-1], z[1:, 1:]
    v00, v10, v01, v11 = valid[:-1, :-1], valid[:-1, 1:], valid[1:, :-1], valid[1:, 1:]
    # Lower triangle (00, 10, 11) and upper triangle (00, 11, 01): their slopes.
    lower = v00 & v10 & v11
    upper = v00 & v11 & v01
    gx = np.concatenate([((z10 - z00) / dx)[lower], ((z11 - z01) / dx)[upper]])
    gy = np.concatenate([((z11 - z10) / dy)[lower], ((z01 - z00) / dy)[upper]])
    inv = 1.0 / np.sqrt(1.0 + gx * gx + gy * gy)
    save_table(a.out, splat_table(-gx * inv, -gy * inv, 0.5 * dx * dy, a.resolution))


if __name__ == "__main__":
    main()
