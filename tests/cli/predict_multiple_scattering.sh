#!/usr/bin/env bash
# predict reports the energy single scattering loses on the measured NDF (white furnace, F = 1,
# random walks on the table) and, where it matters, shows the multiple-scattering BRDF in the
# comparison strip with a multiple-vs-single difference image. Reference, written here on its own:
# 1 - the single-scattering albedo of the same table by quadrature over its nodes (Smith Lambda
# from the table's own projected area, height-correlated G2), since the walk conserves energy.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
$BIN generate gaussian --sigma 1um --tau 3um --nx 256 --ny 256 --spacing 500nm --seed 5 \
  -o "$T/r.npy" 2>/dev/null || fail generate
R=(--metal Al --level none --resolution 129 --theta-i 45 --render-width 32 --spp 2)
$BIN predict "$T/r.npy" "${R[@]}" -o "$T/on" 2>"$T/err" || fail "predict: $(cat "$T/err")"
grep -q "multiple scattering: single scattering loses" "$T/err" || fail "no log line"
$BIN predict "$T/r.npy" "${R[@]}" --multiple-scattering off -o "$T/off" 2>/dev/null ||
  fail "predict off"
$BIN predict "$T/r.npy" "${R[@]}" --multiple-scattering sometimes -o "$T/bad" 2>/dev/null &&
  fail "a bad --multiple-scattering was accepted"
/usr/bin/python3 - "$T" <<'PY' || fail "energy loss"
import json, os, sys
import numpy as np
t = sys.argv[1]
s = json.load(open(f"{t}/on/summary.json"))
m = s["multiple_scattering"]
assert m["ndf"] == "filtered", m["ndf"]
# The table the walk used, and its single-scattering albedo by quadrature on its nodes.
d = np.load(f"{t}/on/ndf_filtered.npy").astype(float)
n = d.shape[0]
x = -1 + 2 * np.arange(n) / (n - 1)
mx, my = np.meshgrid(x, x)
inside = mx**2 + my**2 < 1
mz = np.sqrt(np.clip(1 - mx**2 - my**2, 0, 1))
m_ = np.stack([mx[inside], my[inside], mz[inside]], -1)
w = d[inside] * (2 / (n - 1)) ** 2 / m_[:, 2]          # D dw per node
w /= np.sum(w * m_[:, 2])                                # projected area 1, as the table is
def lam(v):                                              # Smith Lambda of the table, per row of v
    sig = np.maximum(v @ m_.T, 0) @ w
    return np.maximum(sig / v[:, 2] - 1, 0)
for p in m["per_incidence"]:
    ti, pi = np.radians(p["theta_i_deg"]), np.radians(p["phi_i_deg"])
    if p["theta_i_deg"] > 70:
        continue
    wi = np.array([np.sin(ti) * np.cos(pi), np.sin(ti) * np.sin(pi), np.cos(ti)])
    dot = m_ @ wi
    wo = 2 * dot[:, None] * m_ - wi
    ok = (dot > 0) & (wo[:, 2] > 1e-9)
    li = lam(wi[None, :])[0]
    lo = np.zeros(len(m_))
    idx = np.nonzero(ok)[0]
    for k in range(0, len(idx), 2000):
        lo[idx[k:k + 2000]] = lam(wo[idx[k:k + 2000]])
    g2 = 1 / (1 + li + lo)
    # E_ss = integral D(h) G2 (wi.h) / cos_i dw_h (dw_o = 4 (wi.h) dw_h)
    e_ss = np.sum((w * g2 * dot)[ok]) / wi[2]
    lost_ref = 1 - e_ss
    got, se = p["energy_lost_f1"], p["standard_error"]
    print(f"theta_i {p['theta_i_deg']:4.0f} phi_i {p['phi_i_deg']:3.0f}: lost {got:.4f} +- {se:.4f}, "
          f"1 - quadrature single albedo {lost_ref:.4f}; walk single albedo {p['single_albedo_f1']:.4f} vs {e_ss:.4f}")
    assert abs(got - lost_ref) < max(0.012, 4 * se), (p, lost_ref)
    assert abs(p["single_albedo_f1"] - e_ss) < max(0.012, 4 * se), (p, e_ss)
assert m["max_energy_lost_f1"] > 0.02 and m["in_comparison_strip"], m["why"]
keys = [x["model"] for x in s["render_comparison"]["scenes"][0]["models"]]
assert "multiple_scattering" in keys, keys
for sc in s["render_comparison"]["scenes"]:
    ms = sc["multiple_scattering"]
    assert os.path.exists(f"{t}/on/{ms['difference_image']}"), ms
    # Its own scale (the strip's is set by the largest model difference and hides a few per cent).
    assert 0 < ms["difference_scale"]["max"] < 1e3, ms
    assert ms["difference_scale"]["reference_luminance"] == sc["difference_scale"]["reference_luminance"]
cyl = s["render_comparison"]["scenes"][0]["multiple_scattering"]
assert cyl["single"] == "measured" and cyl["mean_luminance_ratio"] > 1, cyl  # MS adds light
html = open(f"{t}/on/report.html").read()
assert "Energy single scattering loses" in html and "Multiple against single scattering" in html
assert "on its own scale" in html
off = json.load(open(f"{t}/off/summary.json"))
assert not off["multiple_scattering"]["in_comparison_strip"]
assert "multiple_scattering" not in [x["model"] for x in off["render_comparison"]["scenes"][0]["models"]]
PY
echo ok
