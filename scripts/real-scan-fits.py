#!/usr/bin/python3
"""Every model's fit to the filtered NDF of real scans, and the distance a perfect model would
have (docs/fitting.md, "Every model on the bundled real scans").

Usage: scripts/real-scan-fits.py BIN PREDICT_DIR... (each made by
`microbrdf predict SCAN --no-render -o PREDICT_DIR`; MODELS="m1 m2 ..." picks the models).

Per scan: the table `predict` fitted (summary.json fits[].source), `fit --model M --json` for
every model (Hellinger distance, objective, tail exponent or weight), and H0: the Hellinger
distance between the best of ellipsoid / Beckmann / GGX and a histogram of the table's number of
normals drawn independently from that fit, splatted bilinearly onto the same nodes as the
estimator does (mean of 3 draws).
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

BIN = sys.argv[1]
MODELS = os.environ.get("MODELS", "ellipsoid beckmann ggx student-t mixture:ggx+beckmann "
                        "mixture:student-t+student-t").split()


def hellinger(a, b, delta):
    a, b = np.clip(np.nan_to_num(a), 0, None), np.clip(b, 0, None)
    return np.sqrt(0.5 * np.sum((np.sqrt(a) - np.sqrt(b)) ** 2) * delta ** 2)


def fit(table, model, out=None):
    cmd = [BIN, "fit", table, "--model", model, "--json"] + (["--table", out] if out else [])
    return json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)


def floor(table, meta, model, rng):
    """H0 of `model`'s fit to `table`."""
    with tempfile.TemporaryDirectory() as tmp:
        fit(table, model, os.path.join(tmp, "m.npy"))
        m = np.load(os.path.join(tmp, "m.npy"))
    n = m.shape[0]
    delta = (meta["window"]["x"][1] - meta["window"]["x"][0]) / (n - 1)
    count = int(round(meta["samples_used"] * meta.get("window_mass", 1)))
    p = np.clip(m, 0, None).ravel()
    p /= p.sum()
    out = []
    for _ in range(3):
        iy, ix = np.divmod(rng.choice(p.size, size=count, p=p), n)
        fx, fy = ix + rng.uniform(-0.5, 0.5, count), iy + rng.uniform(-0.5, 0.5, count)
        ax, ay = np.floor(fx).astype(int), np.floor(fy).astype(int)
        ux, uy = fx - ax, fy - ay
        h = np.zeros((n + 1, n + 1))
        for dx, dy, w in [(0, 0, (1 - ux) * (1 - uy)), (1, 0, ux * (1 - uy)),
                          (0, 1, (1 - ux) * uy), (1, 1, ux * uy)]:
            np.add.at(h, (np.clip(ay + dy, 0, n), np.clip(ax + dx, 0, n)), w)
        out.append(hellinger(h[:n, :n] / (count * delta ** 2), m, delta))
    return float(np.mean(out))


rng = np.random.default_rng(1)
for d in sys.argv[2:]:
    src = json.load(open(os.path.join(d, "summary.json")))["fits"][0]["source"]
    table = os.path.join(d, "ndf_" + src + ".npy")
    meta = json.load(open(table[:-4] + ".json"))
    h = {}
    for m in MODELS:
        j = fit(table, m)
        p = j["params"]
        extra = f" gamma {p['gamma']:.3g}" if "gamma" in p else f" w {p['weight']:.2f}" if "weight" in p else ""
        h[m] = j["hellinger"]
        print(f"{os.path.basename(d)} ({src}, N {meta['samples_used']}): {m}: Hellinger "
              f"{j['hellinger']:.4f}, objective {j['final_cost']:.5g}{extra}", flush=True)
    old = [m for m in ("ellipsoid", "beckmann", "ggx") if m in h]
    new = [m for m in h if m not in old]
    if old:
        best_old = min(old, key=h.get)
        line = f"{os.path.basename(d)}: best of ellipsoid/Beckmann/GGX {best_old} {h[best_old]:.4f}"
        if new:
            best_new = min(new, key=h.get)
            line += f", best new {best_new} {h[best_new]:.4f}, gain {1 - h[best_new] / h[best_old]:+.1%}"
        print(line + f", H0 {floor(table, meta, best_old, rng):.4f}", flush=True)
