#!/usr/bin/python3
"""Render noise of the Sobol' and the independent path samplers (docs/benchmarks.md, "Render noise").

    PYTHONPATH=build/python /usr/bin/python3 bench/render_noise.py [--size 64] [--figure out.png]

For each case (white sky / courtyard map; cylinder pair / plate), renders a reference with many
samples per pixel (Sobol', 16 hero wavelengths, seed 999), then images at 4..256 spp with each
sampler (seeds 1 and 2) and prints the RMS over pixels of the per-pixel relative RGB error (and of
the luminance), with the process CPU time of each render. References are cached in --cache.
"""
import argparse
import os
import pathlib
import time

import numpy as np

import microbrdf as mb

ROOT = pathlib.Path(__file__).resolve().parent.parent
LUMA = np.array([0.2126, 0.7152, 0.0722])


def render(brdf, kw, spp, sampler, seed, wavelengths=4):
    t = time.process_time()
    img = mb.render(brdf, spp=spp, sampler=sampler, seed=seed, wavelengths=wavelengths, **kw)
    return np.array(img, dtype=np.float64), time.process_time() - t


def errors(img, ref, mask):
    rgb = np.sqrt(np.mean(((img - ref) ** 2).sum(-1)[mask] / (ref**2).sum(-1)[mask]))
    lum = np.sqrt(np.mean(((img @ LUMA - ref @ LUMA) / (ref @ LUMA))[mask] ** 2))
    return rgb, lum


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=64, help="image side, pixels")
    ap.add_argument("--cache", default="/tmp/microbrdf-render-noise", help="reference cache")
    ap.add_argument("--figure", help="PNG of the error against spp (matplotlib, Agg)")
    a = ap.parse_args()
    os.makedirs(a.cache, exist_ok=True)
    brdf = mb.brdf(model="ggx", alpha_x=0.08, alpha_y=0.3, metal="Cu")
    cases = [("white", "cylinders", 4096), ("courtyard", "cylinders", 2048),
             ("courtyard", "plate", 2048)]
    spps = [4, 16, 64, 256]
    curves = []
    for lights, scene, ref_spp in cases:
        kw = dict(scene=scene, size=a.size, threads=2)
        if lights != "white":
            kw["envmap"] = str(ROOT / "data" / "envmaps" / f"blender_{lights}.exr")
        path = f"{a.cache}/{lights}_{scene}_{a.size}_{ref_spp}.npy"
        if os.path.exists(path):
            ref = np.load(path)
        else:
            ref, _ = render(brdf, kw, ref_spp, "sobol", 999, wavelengths=16)
            np.save(path, ref)
        mask = ref @ LUMA > 0.02 * np.percentile(ref @ LUMA, 99)
        print(f"{lights} / {scene}, {a.size}^2, reference {ref_spp} spp, {mask.sum()} pixels")
        for sampler in ("independent", "sobol"):
            errs, cpu = [], []
            for spp in spps:
                runs = [render(brdf, kw, spp, sampler, seed) for seed in (1, 2)]
                e = np.mean([errors(img, ref, mask) for img, _ in runs], axis=0)
                errs.append(e)
                cpu.append(np.mean([t for _, t in runs]))
            slope = np.polyfit(np.log(spps), np.log([e[0] for e in errs]), 1)[0]
            for spp, e, t in zip(spps, errs, cpu):
                print(f"  {sampler:11s} {spp:4d} spp: RGB {100 * e[0]:6.2f}%  luminance "
                      f"{100 * e[1]:6.2f}%  CPU {t:.3f} s")
            print(f"  {sampler:11s} slope of log error vs log spp: {slope:.2f}")
            curves.append((lights, scene, sampler, [e[0] for e in errs], slope))
    if a.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axs = plt.subplots(1, len(cases), figsize=(4 * len(cases), 3.6))
        for ax, (lights, scene, _) in zip(axs, cases):
            for l, s, sampler, errs, slope in curves:
                if (l, s) == (lights, scene):
                    ax.loglog(spps, 100 * np.array(errs), "s-" if sampler == "sobol" else "o--",
                              label=f"{sampler} (slope {slope:.2f})")
            sky = "white sky" if lights == "white" else f"{lights} map"
            ax.set_title(f"{scene}, {sky}", fontsize=10)
            ax.set_xlabel("samples per pixel")
            ax.set_ylabel("RMS relative error (%)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.figure, dpi=90)


if __name__ == "__main__":
    main()
