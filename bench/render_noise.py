#!/usr/bin/python3
"""Render noise at equal spp and at equal CPU time (docs/benchmarks.md, "Render noise").

    PYTHONPATH=build/python /usr/bin/python3 bench/render_noise.py [--size 64] [--spp 64]
        [--wavelengths 4,8] [--direct mis,ris] [--baseline OLD/build/python] [--figure out.png]

For each case (white sky / courtyard map; cylinder pair / plate; GGX (0.08, 0.3) copper; with
--cases 3,4,5 also GGX 0.3 gold on the sphere under the studio map, Beckmann 0.2 silver on the
vase under the interior map, and Beckmann (0.008, 0.16) stainless steel on the cylinder pair
under the courtyard map), renders a
reference with 4096 samples per pixel (Sobol', 16 hero wavelengths, MIS direct light, seed 999;
cached in --cache), then images at --spp with seeds 1..--seeds with: the independent sampler at
4 hero wavelengths (MIS), and the Sobol' sampler at each of --wavelengths with each direct-light
estimator of --direct (mis, ris: `mb.render(direct=...)`). With --baseline, the same images are also
rendered by an older build's Python module (a separate process with that PYTHONPATH; its own
default sampler), so that its error and its CPU time are measured in the same run. Prints, per
configuration, the RMS over pixels of the per-pixel relative RGB error |I - R| / |R| (and of the
luminance), over the pixels brighter than 2% of the reference's 99th luminance percentile,
the process CPU time per image (time.process_time, all threads), and the error ratio at equal
time against the first configuration (the baseline when given):
e_ref sqrt(t_ref) / (e sqrt(t)).
"""
import argparse
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
LUMA = np.array([0.2126, 0.7152, 0.0722])
BRDF = dict(model="ggx", alpha_x=0.08, alpha_y=0.3, metal="Cu")
CASES = [("white", "cylinders", 4096, BRDF), ("courtyard", "cylinders", 4096, BRDF),
         ("courtyard", "plate", 4096, BRDF),
         ("studio", "sphere", 4096, dict(model="ggx", alpha=0.3, metal="Au")),
         ("interior", "vase", 4096, dict(model="beckmann", alpha=0.2, metal="Ag")),
         # The configuration the render figures were first measured with: brushed stainless
         # (Dong 2015 Fig. 12 Beckmann fit) on the cylinder pair under the courtyard map.
         ("courtyard", "cylinders", 4096,
          dict(model="beckmann", alpha_x=0.008, alpha_y=0.16, metal="SS-austenitic"))]


def case_kwargs(lights, scene, size, threads):
    kw = dict(scene=scene, size=size, threads=threads)
    if lights != "white":
        kw["envmap"] = str(ROOT / "data" / "envmaps" / f"blender_{lights}.exr")
    return kw


def render(mb, kw, spp, seed, sampler=None, wavelengths=4, direct=None, brdf=BRDF):
    # (no sampler: an older build's module, which knows neither keyword)
    extra = {} if sampler is None else {"sampler": sampler}
    if direct is not None:  # "mis", "ris" or "ris:M/N" (M BRDF and N light candidates)
        extra["direct"] = direct.split(":")[0]
        if ":" in direct:
            m, n = direct.split(":")[1].split("/")
            extra["ris_brdf_candidates"], extra["ris_light_candidates"] = int(m), int(n)
    t = time.process_time()
    img = mb.render(mb.brdf(**brdf), spp=spp, seed=seed, wavelengths=wavelengths, **extra, **kw)
    return np.array(img, dtype=np.float64), time.process_time() - t


def errors(img, ref, mask):
    rgb = np.sqrt(np.mean(((img - ref) ** 2).sum(-1)[mask] / (ref**2).sum(-1)[mask]))
    lum = np.sqrt(np.mean(((img @ LUMA - ref @ LUMA) / (ref @ LUMA))[mask] ** 2))
    return rgb, lum


def worker(args):
    """--worker JSON: renders with whatever `microbrdf` is on sys.path (no sampler argument:
    an older build's default), writes the images and CPU times to an .npz."""
    import microbrdf as mb

    job = json.loads(args)
    imgs, cpu = [], []
    for seed in job["seeds"]:
        img, t = render(mb, job["kw"], job["spp"], seed, brdf=job["brdf"])
        imgs.append(img)
        cpu.append(t)
    np.savez(job["out"], imgs=np.array(imgs), cpu=np.array(cpu))


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--worker":
        return worker(sys.argv[2])
    import microbrdf as mb

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=64, help="image side, pixels")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel of the compared images")
    ap.add_argument("--seeds", type=int, default=4, help="images per configuration (seeds 1..N)")
    ap.add_argument("--threads", type=int, default=1, help="render threads (CPU time counts all)")
    ap.add_argument("--wavelengths", default="4,8", help="hero wavelengths of the Sobol' images")
    ap.add_argument("--direct", default="mis,ris",
                    help="direct-light estimators of the Sobol' images (mis, ris, ris:M/N)")
    ap.add_argument("--baseline", help="PYTHONPATH of an older build's module, rendered alike")
    ap.add_argument("--cases", default="0,1,2", help="which cases (indices into CASES, 0-5)")
    ap.add_argument("--cache", default="/tmp/microbrdf-render-noise", help="reference cache")
    ap.add_argument("--figure", help="PNG of the error against spp (matplotlib, Agg)")
    a = ap.parse_args()
    os.makedirs(a.cache, exist_ok=True)
    seeds = list(range(1, a.seeds + 1))
    curves = []
    for ci in [int(c) for c in a.cases.split(",")]:
        lights, scene, ref_spp, brdf = CASES[ci]
        kw = case_kwargs(lights, scene, a.size, a.threads)
        # (the BRDF in the name when it is not the default: two cases share lights and scene)
        tag = "" if brdf is BRDF else "_" + "_".join(f"{k}{v}" for k, v in sorted(brdf.items()))
        path = f"{a.cache}/{lights}_{scene}{tag}_{a.size}_{ref_spp}.npy"
        if os.path.exists(path):
            ref = np.load(path)
        else:
            ref, _ = render(mb, {**kw, "threads": 0}, ref_spp, 999, "sobol", 16, "mis", brdf)
            np.save(path, ref)
        mask = ref @ LUMA > 0.02 * np.percentile(ref @ LUMA, 99)
        print(f"{lights} / {scene} ({brdf['model']} {brdf['metal']}), {a.size}^2, {a.spp} spp, "
              f"{len(seeds)} seeds, "
              f"{a.threads} thread(s); reference {ref_spp} spp, {mask.sum()} pixels", flush=True)
        rows = []
        if a.baseline:
            out = f"{a.cache}/baseline_{os.getpid()}.npz"
            job = dict(kw=kw, spp=a.spp, seeds=seeds, out=out, brdf=brdf)
            env = {**os.environ, "PYTHONPATH": a.baseline}
            subprocess.run([sys.executable, __file__, "--worker", json.dumps(job)], env=env,
                           check=True)
            d = np.load(out)
            os.remove(out)
            e = np.mean([errors(img, ref, mask) for img in d["imgs"]], axis=0)
            rows.append(("baseline build", e, float(np.mean(d["cpu"]))))
        configs = [("independent", 4, "mis")] + [
            ("sobol", int(w), d) for d in a.direct.split(",") for w in a.wavelengths.split(",")]
        for sampler, wl, direct in configs:
            runs = [render(mb, kw, a.spp, seed, sampler, wl, direct, brdf) for seed in seeds]
            e = np.mean([errors(img, ref, mask) for img, _ in runs], axis=0)
            rows.append((f"{sampler}, {wl} wl, {direct}", e, float(np.mean([t for _, t in runs]))))
        e0, t0 = rows[0][1][0], rows[0][2]
        for name, e, t in rows:
            ratio = e0 * np.sqrt(t0) / (e[0] * np.sqrt(t))
            print(f"  {name:26s} RGB {100 * e[0]:6.2f}%  luminance {100 * e[1]:6.2f}%  "
                  f"CPU {t:.3f} s/image  equal-time ratio vs first {ratio:.2f}", flush=True)
        if a.figure:
            spps = [4, 16, 64, 256]
            for sampler in ("independent", "sobol"):
                errs = []
                for spp in spps:
                    runs = [render(mb, kw, spp, seed, sampler, 4, "mis", brdf) for seed in (1, 2)]
                    errs.append(np.mean([errors(img, ref, mask)[0] for img, _ in runs]))
                slope = np.polyfit(np.log(spps), np.log(errs), 1)[0]
                print(f"  {sampler:11s} " + "  ".join(
                    f"{s} spp {100 * e:.2f}%" for s, e in zip(spps, errs)) + f"  slope {slope:.2f}")
                curves.append((lights, scene, sampler, spps, errs, slope))
    if a.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        keys = sorted({(l, s) for l, s, *_ in curves}, key=lambda k: [c[:2] for c in CASES].index(k))
        fig, axs = plt.subplots(1, len(keys), figsize=(4 * len(keys), 3.6), squeeze=False)
        for ax, (lights, scene) in zip(axs[0], keys):
            for l, s, sampler, spps, errs, slope in curves:
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
