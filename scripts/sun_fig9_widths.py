#!/usr/bin/python3
"""Sun 2002 Fig. 9: the highlight's width along the row, measured on the renders and predicted
from the analytic BRDF, for scripts/make-sun-fig9.sh.

  sun_fig9_widths.py WORK_DIR METAL ... --s S,S,...   (reads WORK_DIR/vase_METAL_sS.npy)

With the point light at the camera every point of the vase is lit and seen from the same
direction v, so the micro-area that reflects the light back is the one facing v (h = v, the
Fresnel term is R(0) everywhere) and the radiance is

    L = rho(theta, theta) cos(theta) I / d^2,
    rho = s^2 exp(-s^2 tan^2(theta) / 4) / (16 pi cos^3(theta)) Gamma0(theta)^2   (eq. 3.5.3),
    Gamma0(theta) = exp[-(tan(theta) / (sqrt(2 pi) s)) exp(-s^2 / (4 tan^2(theta)))] (eq. 3.4.23),

theta the angle between the vase's normal and v, d the distance to the light. The lobe's own
width is theta_half, where rho cos falls to half its value at theta = 0. The row is the image
row through the point whose normal faces the camera (from the vase's geometry: the profile
r(y) = 0.5 + 0.25 cos(pi (y + 0.3) / 1.3), the camera at (0, 0.8, 4.5) looking at
(0, -0.05, 0), tan(fov/2) = 0.26, docs/render.md). Along it the predicted profile is L at each
pixel (8 x 4 sub-samples, the vase intersected and its normal taken analytically), independent of
the renderer; measured and predicted widths are the full widths at half the row's maximum
(linear interpolation between pixel centres), also relative to the vase's width on that row.
Writes WORK_DIR/widths.json and prints the table of docs/sun2002.md.
"""
import argparse
import json
import math
import pathlib
import sys

import numpy as np

CAM, TARGET, TAN_HALF = np.array([0, 0.8, 4.5]), np.array([0, -0.05, 0]), 0.26


def vase_r(y):
    return 0.5 + 0.25 * np.cos(np.pi * (y + 0.3) / 1.3)


def vase_dr(y):
    return -0.25 * np.pi / 1.3 * np.sin(np.pi * (y + 0.3) / 1.3)


def camera():
    f = (TARGET - CAM) / np.linalg.norm(TARGET - CAM)
    r = np.cross(f, [0, 1, 0])
    r /= np.linalg.norm(r)
    return f, r, np.cross(r, f)


def ray(px, py, size):
    f, r, u = camera()
    d = f + (2 * px / size - 1) * TAN_HALF * r + (1 - 2 * py / size) * TAN_HALF * u
    return d / np.linalg.norm(d)


def hit(d):
    """First intersection of the camera ray with the vase's outer wall: (point, unit normal)."""
    t = np.linspace(3.0, 5.5, 2501)
    p = CAM[None, :] + t[:, None] * d[None, :]
    inside = (np.hypot(p[:, 0], p[:, 2]) - vase_r(p[:, 1]) < 0) & (np.abs(p[:, 1]) <= 1)
    k = np.argmax(inside)
    if not inside[k]:
        return None
    lo, hi = t[k - 1], t[k]
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        q = CAM + mid * d
        if np.hypot(q[0], q[2]) - vase_r(q[1]) < 0:
            hi = mid
        else:
            lo = mid
    q = CAM + hi * d
    rad = np.array([q[0], 0, q[2]]) / np.hypot(q[0], q[2])
    n = rad - vase_dr(q[1]) * np.array([0, 1, 0])
    return q, n / np.linalg.norm(n)


def lobe(theta, s):
    """rho(theta, theta) cos(theta) of eq. 3.5.3 with R = 1."""
    t = np.tan(theta)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        g0 = np.where(t > 0, np.exp(-(t / (math.sqrt(2 * math.pi) * s)) *
                                    np.exp(-s * s / (4 * np.maximum(t, 1e-300) ** 2))), 1.0)
    return s * s * np.exp(-s * s * t * t / 4) / (16 * math.pi * np.cos(theta) ** 3) * g0 * g0 * np.cos(theta)


def theta_half(s):
    th = np.radians(np.linspace(0, 89.9, 89901))
    g = lobe(th, s)
    return math.degrees(th[np.argmax(g < 0.5 * g[0])])


def row_geometry(py, size):
    """Per pixel of the row, per sub-sample: theta (NaN off the vase) and the light's distance."""
    theta, dist = np.full((size, 32), np.nan), np.ones((size, 32))
    for px in range(size):
        for k in range(32):
            h = hit(ray(px + (k % 8 + 0.5) / 8, py + (k // 8 + 0.5) / 4, size))
            if h is not None:
                q, n = h
                v = CAM - q
                dist[px, k] = np.linalg.norm(v)
                theta[px, k] = math.acos(min(1.0, float(n @ (v / dist[px, k]))))
    on = np.where(~np.isnan(theta).all(axis=1))[0]
    return theta, dist, int(on[-1] - on[0] + 1)


def predicted_row(geometry, s):
    theta, dist, _ = geometry
    values = np.where(np.isnan(theta), 0.0, lobe(np.nan_to_num(theta), s) / dist ** 2)
    return values.mean(axis=1)


def fwhm(row):
    """Full width at half the maximum around the maximum, pixels (interpolated)."""
    i = int(np.argmax(row))
    half = 0.5 * row[i]
    left = i
    while left > 0 and row[left - 1] >= half:
        left -= 1
    right = i
    while right < len(row) - 1 and row[right + 1] >= half:
        right += 1
    xl = left - (row[left] - half) / (row[left] - row[left - 1]) if left > 0 else 0.0
    xr = right + (row[right] - half) / (row[right] - row[right + 1]) if right < len(row) - 1 else len(row) - 1.0
    return xr - xl


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("work")
    ap.add_argument("metals", nargs="+")
    ap.add_argument("--s", required=True)
    a = ap.parse_args()
    w = pathlib.Path(a.work)
    values = [float(x) for x in a.s.split(",")]
    size = np.load(w / f"vase_{a.metals[0]}_s{a.s.split(',')[0]}.npy").shape[1]
    # The row through the point whose normal faces the camera (smallest theta on the centre line).
    def centre_theta(py):
        h = hit(ray(size / 2, py + 0.5, size))
        return 9.0 if h is None else math.acos(min(1.0, float(h[1] @ ((CAM - h[0]) / np.linalg.norm(CAM - h[0])))))
    best = min(range(size), key=centre_theta)
    out = {"row": best, "size": size, "vases": []}
    print(f"row {best} of {size}")
    print("| smoothness | lobe theta_half | predicted width, px (of the vase) | " +
          " | ".join(f"{m} measured, px (ratio)" for m in a.metals) + " |")
    print("|" + " --- |" * (3 + len(a.metals)))
    geometry = row_geometry(best, size)
    vase_px = geometry[2]
    for s_text in a.s.split(","):
        s = float(s_text)
        pred = predicted_row(geometry, s)
        p_w = fwhm(pred)
        entry = {"s": s, "theta_half_deg": theta_half(s), "vase_width_px": vase_px,
                 "predicted_fwhm_px": p_w, "measured": {}}
        cells = []
        for m in a.metals:
            img = np.load(w / f"vase_{m}_s{s_text}.npy")
            y = img[best] @ np.array([0.2126, 0.7152, 0.0722])
            m_w = fwhm(y)
            entry["measured"][m] = {"fwhm_px": m_w, "ratio": m_w / p_w}
            cells.append(f"{m_w:.1f} ({m_w / p_w:.3f})")
        out["vases"].append(entry)
        print(f"| s = {s:g} | {entry['theta_half_deg']:.1f} deg | {p_w:.1f} ({p_w / vase_px:.3f}) | " +
              " | ".join(cells) + " |")
    (w / "widths.json").write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
