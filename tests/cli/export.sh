#!/usr/bin/env bash
# `export bsdf|mitsuba|pbrt` as a user runs them: a MERL file of an isotropic GGX lobe (F = 1,
# G = 1, written here by numpy) -> .bsdf -> evaluated by the independent numpy reader
# (tests/rgl_reference_reader.py) against the analytic lobe; scenes for Mitsuba and pbrt.
set -u
BIN=$1
HERE=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

/usr/bin/python3 - "$T/ggx.binary" <<'PY' || fail "python could not write the MERL file"
import sys, numpy as np
a = 0.3
i, j, k = np.meshgrid(np.arange(90), np.arange(90), np.arange(180), indexing="ij")
th, td, pd = ((i + .5) / 90) ** 2 * np.pi / 2, (j + .5) / 90 * np.pi / 2, (k + .5) / 180 * np.pi
d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)])
wi = np.stack([np.cos(th) * d[0] + np.sin(th) * d[2], d[1], -np.sin(th) * d[0] + np.cos(th) * d[2]])
hz = np.cos(th)
woz = 2 * np.cos(td) * hz - wi[2]
D = 1 / (np.pi * a * a * (np.sin(th) ** 2 / a ** 2 + hz ** 2) ** 2)
f = np.where((wi[2] > 0) & (woz > 0), D / (4 * np.maximum(wi[2], 1e-9) * np.maximum(woz, 1e-9)), -1.0)
scale = np.array([1 / 1500, 1.15 / 1500, 1.66 / 1500])
with open(sys.argv[1], "wb") as out:
    np.array([90, 90, 180], "<i4").tofile(out)
    for c in range(3):
        np.where(f >= 0, f / scale[c], -1.0).astype("<f8").tofile(out)
PY

$BIN export bsdf "$T/ggx.binary" --wavelengths 3 -o "$T/ggx.bsdf" >"$T/out" 2>"$T/err" \
  || fail "export bsdf: $(cat "$T/err")"
printf '%s\n' "0 0 1 0.1 0 0.99498743710662 550" "0.5 0 0.86602540378 -0.4 0.1 0.91104335791 550" \
  "0.3 0.2 0.93273790530 -0.35 -0.15 0.92466210044 550" >"$T/q"
/usr/bin/python3 "$HERE/rgl_reference_reader.py" "$T/ggx.bsdf" eval "$T/q" "$T/a" \
  || fail "the independent reader cannot read the export"
/usr/bin/python3 - "$T/q" "$T/a" <<'PY' || exit 1
import sys, numpy as np
q, got, a = np.loadtxt(sys.argv[1]), np.loadtxt(sys.argv[2]), 0.3
for row, g in zip(q, got):
    wi, wo = row[:3] / np.linalg.norm(row[:3]), row[3:6] / np.linalg.norm(row[3:6])
    h = (wi + wo) / np.linalg.norm(wi + wo)
    ref = 1 / (np.pi * a * a * ((h[0]**2 + h[1]**2) / a**2 + h[2]**2) ** 2) / (4 * wi[2] * wo[2])
    print(f"export bsdf (MERL): f {g:.5g} vs analytic {ref:.5g} ({100 * (g / ref - 1):+.2f}%)")
    assert abs(g / ref - 1) < 0.03, (g, ref)
PY

$BIN export mitsuba --bsdf "$T/ggx.bsdf" -o "$T/mi" >/dev/null || fail "export mitsuba"
$BIN export pbrt --bsdf "$T/ggx.bsdf" -o "$T/pb" >/dev/null || fail "export pbrt"
for f in mi/scene.xml mi/material.xml mi/ggx.bsdf pb/scene.pbrt pb/material.pbrt pb/ggx.bsdf; do
  [ -s "$T/$f" ] || fail "missing $f"
done
/usr/bin/python3 -c "
import xml.etree.ElementTree as E
b = E.parse('$T/mi/scene.xml').getroot().find('bsdf')
assert b.get('type') == 'measured' and b.find('string').get('value') == 'ggx.bsdf'" \
  || fail "Mitsuba scene does not reference the .bsdf"
grep -q 'Material "measured" "string filename" "ggx.bsdf"' "$T/pb/scene.pbrt" || fail "pbrt material"

# A point set is not a full BRDF; a broken .bsdf is refused before anything is written.
printf 'theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n1,0,1,180,550,1\n' >"$T/p.csv"
$BIN export bsdf "$T/p.csv" -o "$T/p.bsdf" 2>"$T/err"; [ $? -eq 2 ] || fail "CSV not a usage error"
head -c 300 "$T/ggx.bsdf" >"$T/cut.bsdf"
$BIN export mitsuba --bsdf "$T/cut.bsdf" -o "$T/cut" 2>"$T/err" && fail "truncated .bsdf accepted"
grep -q "cut.bsdf" "$T/err" || fail "message does not name the file: $(cat "$T/err")"
[ -e "$T/cut" ] && fail "output directory created despite the error"
echo OK
