#!/usr/bin/python3
"""Blind check of the NDF fits: which model (ellipsoid, Beckmann, GGX) fits best, on every bundled
real scan and on the brushed generator presets, whatever the answer is.

Everything that could be tuned is fixed here, before any result was looked at:

  surfaces  every instrument file in tests/data and data/ (the extensions below; the generated
            EXR/TIFF image fixtures are ramps, not scans, and are left out), plus
            `generate brushed --preset P --seed S` for every preset P, seeds 1, 2, 3, at the
            preset's full size (2048 x 1024) and at Dong's scan size (640 x 480).
  NDFs      two settings, each applied to every surface alike:
              filtered: --method filtered --filter-sigma 1um --resolution 1025 --level plane
              naive:    --method naive --resolution 1025 --level plane
  fits      `microbrdf fit NDF --model M --json` for M in ellipsoid, beckmann, ggx, with the
            defaults (sqrt objective = Hellinger distance, sampling auto).
  winner    the model with the lowest relative L2 error (|T - M| / |T| over the disk nodes);
            the lowest Hellinger distance is listed too. A surface whose NDF cannot be made
            (e.g. too few samples) is listed with the reason and no winner.

Usage: scripts/blind-check.py [BIN] [OUTDIR]   (defaults: build/bin/microbrdf, build/blind-check)
Writes OUTDIR/results.json and OUTDIR/table.md (the table in docs/validation.md).
"""
import glob
import json
import os
import subprocess
import sys
import time

BIN = sys.argv[1] if len(sys.argv) > 1 else "build/bin/microbrdf"
OUT = sys.argv[2] if len(sys.argv) > 2 else "build/blind-check"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SCAN_EXTENSIONS = ("x3p", "dat", "datx", "plu", "sur", "gwy", "sdf", "asc", "xyz")
PRESETS_SEEDS = (1, 2, 3)
PRESET_SIZES = ((None, None), (640, 480))  # None: the preset's own size (2048 x 1024)
NDF_SETTINGS = {
    "filtered": ["--method", "filtered", "--filter-sigma", "1um", "--resolution", "1025",
                 "--level", "plane"],
    "naive": ["--method", "naive", "--resolution", "1025", "--level", "plane"],
}
MODELS = ("ellipsoid", "beckmann", "ggx")


def run(args):
    p = subprocess.run([BIN] + args, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def last_line(text):
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return lines[-1] if lines else ""


def surfaces(work):
    out = []
    for d in ("tests/data", "data"):
        for path in sorted(glob.glob(os.path.join(ROOT, d, "**", "*"), recursive=True)):
            if path.rsplit(".", 1)[-1].lower() in SCAN_EXTENSIONS and os.path.isfile(path):
                out.append((os.path.relpath(path, ROOT), path))
    presets = ["stainless4", "aluminium4"]  # brushed_preset_names() in src/surface/generate.cpp
    for preset in presets:
        for nx, ny in PRESET_SIZES:
            for seed in PRESETS_SEEDS:
                size = f"{nx}x{ny}" if nx else "2048x1024"
                name = f"brushed {preset} {size} seed {seed}"
                path = os.path.join(work, f"{preset}_{size}_{seed}.x3p")
                args = ["generate", "brushed", "--preset", preset, "--seed", str(seed), "-o", path]
                if nx:
                    args += ["--nx", str(nx), "--ny", str(ny)]
                rc, _, err = run(args)
                out.append((name, path if rc == 0 else None))
    return out


def main():
    os.makedirs(OUT, exist_ok=True)
    work = os.path.join(OUT, "work")
    os.makedirs(work, exist_ok=True)
    t0 = time.time()
    results = []
    for k, (name, path) in enumerate(surfaces(work)):
        for setting, flags in NDF_SETTINGS.items():
            row = {"surface": name, "ndf": setting, "fits": {}}
            results.append(row)
            if path is None:
                row["error"] = "generate failed"
                continue
            ndf = os.path.join(work, f"{k}_{setting}.npy")
            rc, out, err = run(["ndf", path, "-o", ndf, "--json"] + flags)
            if rc != 0:
                row["error"] = "ndf: " + last_line(err)
                continue
            for model in MODELS:
                rc, out, err = run(["fit", ndf, "--model", model, "--json"])
                if rc != 0:
                    row["fits"][model] = {"error": last_line(err)}
                    continue
                j = json.loads(out)
                row["fits"][model] = {
                    "relative_l2_error": j["relative_l2_error"],
                    "hellinger": j["hellinger"],
                    "alpha_x": j["params"]["alpha_x"],
                    "alpha_y": j["params"]["alpha_y"],
                    "converged": j["converged"],
                    "at_bound": j.get("at_bound"),
                }
            ok = {m: f for m, f in row["fits"].items() if "error" not in f}
            if ok:
                row["winner_l2"] = min(ok, key=lambda m: ok[m]["relative_l2_error"])
                row["winner_hellinger"] = min(ok, key=lambda m: ok[m]["hellinger"])
            print(json.dumps(row), file=sys.stderr, flush=True)
    with open(os.path.join(OUT, "results.json"), "w") as f:
        json.dump({"settings": NDF_SETTINGS, "models": MODELS, "seconds": time.time() - t0,
                   "results": results}, f, indent=1)
    lines = ["| surface | NDF | rel. L2 ellipsoid | Beckmann | GGX | winner (L2) | "
             "winner (Hellinger) | notes |", "|---|---|---|---|---|---|---|---|"]
    for r in results:
        cells = []
        notes = []
        for m in MODELS:
            f = r["fits"].get(m)
            if f is None:
                cells.append("—")
            elif "error" in f:
                cells.append("failed")
                notes.append(f"{m}: {f['error']}")
            else:
                c = f"{f['relative_l2_error']:.3f}"
                if not f["converged"]:
                    c += " (nc)"
                    notes.append(f"{m} at bound {f['at_bound']}" if f["at_bound"]
                                 else f"{m} not converged")
                cells.append(c)
        if "error" in r:
            notes.append(r["error"])
        lines.append(f"| {r['surface']} | {r['ndf']} | " + " | ".join(cells) +
                     f" | {r.get('winner_l2', '—')} | {r.get('winner_hellinger', '—')} | "
                     + "; ".join(notes).replace("|", "/") + " |")
    tally = {}
    for r in results:
        if "winner_l2" in r:
            key = (r["ndf"], "preset" if r["surface"].startswith("brushed") else "real")
            tally.setdefault(key, {}).setdefault(r["winner_l2"], 0)
            tally[key][r["winner_l2"]] += 1
    lines.append("")
    for (ndf, kind), counts in sorted(tally.items()):
        lines.append(f"- {kind} surfaces, {ndf} NDF: " +
                     ", ".join(f"{m} {n}" for m, n in sorted(counts.items())))
    with open(os.path.join(OUT, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"{time.time() - t0:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
