#!/usr/bin/env python3
"""From a real scan to fitted NDFs: naive, filtered and Kirchhoff NDFs of a measured height map,
ellipsoid and GGX fits of each, and matplotlib figures (Agg backend, no display needed).

    PYTHONPATH=build/python python3 examples/python/scan_to_fits.py [SCAN] [-o OUT_DIR]

The default scan is tests/data/sample-land.x3p (a land engraved on a fired bullet, 918 x 256
samples of 2.58 um, 11 % of them invalid). Wave optics needs the sample spacing below a quarter of
lambda_q (else the scan cannot show the high spatial frequencies that scatter to large angles), so
the Kirchhoff NDF of this scan is computed at a CO2-laser wavelength, 10.6 um, by default.
Writes OUT_DIR/heights.png, ndfs.png, slices.png and fits.json.
"""
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import microbrdf as mb  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
DEFAULT_SCAN = HERE.parent.parent / "tests" / "data" / "sample-land.x3p"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scan", nargs="?", default=DEFAULT_SCAN, type=pathlib.Path)
    ap.add_argument("-o", "--out", default="scan_to_fits-out", type=pathlib.Path)
    ap.add_argument("--resolution", type=int, default=257, help="NDF table size N")
    ap.add_argument("--wavelength", type=float, default=10.6e-6, help="lambda_q of D_K, metres")
    ap.add_argument("--patch", type=float, default=600e-6, help="D_K tile size (coherence length), metres")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    # 1. The scan, levelled with a least-squares plane (as the CLI does by default).
    surface = mb.read_surface(args.scan).level("plane")
    stats = mb.statistics(surface, level="none")
    dx, dy = surface.spacing
    print(f"{args.scan.name}: {surface.nx} x {surface.ny} samples, spacing {dx * 1e6:.3g} um, "
          f"Sq {stats['sq_m'] * 1e6:.3g} um, rms slopes {stats['slope_rms_x']:.3g} / {stats['slope_rms_y']:.3g}")

    # 2. Three NDFs of the same surface (Dong 2015 sections 5.1 and 6).
    n = args.resolution
    ndfs = {
        "naive": mb.ndf(surface, method="naive", resolution=n, level="none"),
        "filtered": mb.ndf(surface, method="filtered", filter_sigma=2 * max(dx, dy), resolution=n, level="none"),
        # One table at the wavelength, to fit (a BRDF takes the default stack over lambda_q).
        "kirchhoff": mb.ndf(surface, method="kirchhoff", wavelength=args.wavelength,
                            patch=(args.patch, args.patch), resolution=n, level="none",
                            stack="single"),
    }

    # 3. Fits of each (Dong section 8).
    fits = {name: {model: mb.fit(D, model=model) for model in ("ellipsoid", "ggx")}
            for name, D in ndfs.items()}
    for name, by_model in fits.items():
        for model, r in by_model.items():
            p = r["params"]
            print(f"  {name:9s} {model:9s} alpha {p['alpha_x']:.4g} x {p['alpha_y']:.4g}, "
                  f"relative L2 error {r['relative_l2_error']:.3g}")
    (args.out / "fits.json").write_text(json.dumps(fits, indent=2))

    # 4. Figures.
    fig, ax = plt.subplots(figsize=(6, 4.5))
    im = ax.imshow(surface.heights * 1e6, cmap="viridis", origin="lower",
                   extent=[0, surface.nx * dx * 1e6, 0, surface.ny * dy * 1e6])
    ax.set_xlabel("x (um)")
    ax.set_ylabel("y (um)")
    fig.colorbar(im, ax=ax, label="height (um)")
    ax.set_title(f"{args.scan.name}, plane removed")
    fig.savefig(args.out / "heights.png", dpi=100)
    plt.close(fig)

    # Zoom on the peak: a window of +-5 rms slopes around the centre of the disk.
    half = min(1.0, 5 * max(stats["slope_rms_x"], stats["slope_rms_y"], 2 / (n - 1)))
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    for ax, (name, D) in zip(axes, ndfs.items()):
        t = np.asarray(D)  # a view of the table, no copy
        im = ax.imshow(np.log10(np.maximum(t, t.max() * 1e-4)), origin="lower", cmap="magma",
                       extent=[-1, 1, -1, 1])
        ax.set_xlim(-half, half)
        ax.set_ylim(-half, half)
        ax.set_title(name)
        ax.set_xlabel("m_x")
        ax.set_ylabel("m_y")
        fig.colorbar(im, ax=ax, label="log10 D (1/sr)")
    fig.tight_layout()
    fig.savefig(args.out / "ndfs.png", dpi=100)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, azimuth, label in ((axes[0], 0.0, "along x"), (axes[1], np.pi / 2, "along y")):
        for name, D in ndfs.items():
            sl = D.slice(azimuth=azimuth, samples=4 * n)
            line, = ax.semilogy(np.degrees(sl["theta"]), sl["value"], label=name)
            p = fits[name]["ellipsoid"]["params"]
            model = mb.tabulate(model="ellipsoid", alpha_x=p["alpha_x"], alpha_y=p["alpha_y"],
                                theta_x=p["theta_x"], theta_y=p["theta_y"], theta_z=p["theta_z"],
                                resolution=n)
            ms = model.slice(azimuth=azimuth, samples=4 * n)
            ax.semilogy(np.degrees(ms["theta"]), ms["value"], "--", color=line.get_color(), lw=0.8,
                        label=f"{name}, ellipsoid fit")
        lim = np.degrees(np.arcsin(half))
        ax.set_xlim(-lim, lim)
        peak = max(np.asarray(D).max() for D in ndfs.values())
        ax.set_ylim(peak * 1e-4, peak * 2)
        ax.set_xlabel("signed polar angle of m (deg)")
        ax.set_ylabel("D (1/sr)")
        ax.set_title(f"slice {label}")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out / "slices.png", dpi=100)
    plt.close(fig)
    print(f"figures in {args.out}/")


if __name__ == "__main__":
    main()
