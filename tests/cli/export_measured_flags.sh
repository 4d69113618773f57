#!/usr/bin/env bash
# `export` and `measured ndf` take the model and material flags of every other command. The four
# command lines of docs/measured.md run exactly as typed; each .bsdf is read back by the
# independent numpy reader (tests/rgl_reference_reader.py) and compared with microbrdf's own
# BRDF along the in-plane and out-of-plane cuts of `brdf slice` (same flags); the goniometer
# CSV with a material gives an effective NDF that `fit` recovers. Then the nearest-GGX export of
# an ellipsoid to Mitsuba 3 / pbrt-v4, said in the files and on stderr.
set -u
BIN=$1
HERE=$(cd "$(dirname "$0")/.." && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cd "$T" || exit 1

# The filtered NDF of the real scan in tests/data (a 257^2 table keeps the test quick).
$BIN ndf "$HERE/data/metropro-1.dat" --method filtered --filter-sigma 2um --resolution 257 \
  -o ndf.npy >/dev/null 2>err || fail "ndf: $(cat err)"

# --- The four command lines, exactly. ------------------------------------------------------
$BIN export bsdf --model ggx --alpha 0.3 --n 1.2 --k 3.5 -o g.bsdf >out 2>err1 \
  || fail "export bsdf ggx: $(cat err1)"
grep -q "isotropic BRDF" err1 || fail "isotropy not reported: $(cat err1)"
$BIN export bsdf --model ggx --alpha-x 0.1 --alpha-y 0.3 --metal Al -o a.bsdf >out 2>err2 \
  || fail "export bsdf anisotropic ggx: $(cat err2)"
grep -q "anisotropic BRDF" err2 || fail "anisotropy not detected: $(cat err2)"
$BIN export bsdf --ndf ndf.npy --metal Fe -o t.bsdf >out 2>err3 \
  || fail "export bsdf --ndf: $(cat err3)"

# Goniometer CSV of an anisotropic GGX conductor (n 1.6, k 3.2): f = F D G2 / (4 cos cos).
/usr/bin/python3 "$HERE/cli/make_goniometer.py" goni.csv --alpha 0.12 0.3 --n 1.6 --k 3.2 --smith \
  --min-cos 0.02 || fail "python could not write the CSV"
$BIN measured ndf goni.csv --n 1.6 --k 3.2 -o eff.npy >out 2>err4 || fail "measured ndf: $(cat err4)"
grep -q "F of the material" err4 || fail "measured ndf does not say F is the material's: $(cat err4)"
$BIN fit eff.npy --model ggx --json >fit.json 2>err5 || fail "fit: $(cat err5)"
/usr/bin/python3 - fit.json eff.npy <<'PY' || fail "fit of the effective NDF"
import json, sys, numpy as np
p = json.load(open(sys.argv[1]))["params"]
d = np.load(sys.argv[2])
ax, ay = p["alpha_x"], p["alpha_y"]
print(f"measured ndf --n 1.6 --k 3.2 -> fit: alpha_x {ax:.4f} (true 0.12, {100*(ax/0.12-1):+.2f}%), "
      f"alpha_y {ay:.4f} (true 0.30, {100*(ay/0.3-1):+.2f}%), {int(np.isnan(d).sum())} NaN nodes")
assert abs(ax / 0.12 - 1) < 0.03 and abs(ay / 0.30 - 1) < 0.03, p
assert np.isnan(d).sum() > 0
# With the material's F divided out the table is the NDF's own scale (G = 1 aside): its peak is
# within 10 % of the GGX peak 1/(pi ax ay).
peak = np.nanmax(d)
print(f"  peak D {peak:.4g} 1/sr vs 1/(pi ax ay) = {1/(np.pi*0.12*0.3):.4g}")
assert abs(peak * np.pi * 0.12 * 0.3 - 1) < 0.1, peak
PY

# The slice of the effective NDF: unmeasured stays NaN in the CSV (not 0), the plot skips it.
$BIN slice eff.npy -o eff_slice.png --csv eff_slice.csv 2>err || fail "slice of eff.npy: $(cat err)"
/usr/bin/python3 - eff_slice.csv <<'PY' || fail "slice of the effective NDF"
import sys
rows = [l.strip().split(",") for l in open(sys.argv[1]) if not l.startswith("#") and l[0].isalpha()]
v = [float(r[3]) for r in rows[1:]]
nan = sum(x != x for x in v); pos = sum(x > 0 for x in v)
print(f"slice of eff.npy: {nan} unmeasured (NaN) and {pos} measured points")
assert nan > 0 and pos > 50
PY
[ -s eff_slice.png ] || fail "no slice plot"

# --- Each .bsdf against microbrdf's own BRDF along two cuts, by the independent reader. ------
check_cuts() {  # file, tag, flags...
  local file=$1 tag=$2; shift 2
  for plane in in out; do
    for ti in 20 50; do
      $BIN brdf slice "$@" --theta-i ${ti}deg --plane $plane --wavelength 550nm --samples 3601 \
        -o "s_${tag}_${plane}_${ti}.csv" 2>err || fail "brdf slice $tag: $(cat err)"
    done
  done
  /usr/bin/python3 - "$HERE/rgl_reference_reader.py" "$file" "$tag" s_"$tag"_*.csv <<'PY' || fail "cuts of $tag"
import subprocess, sys, numpy as np
reader, bsdf, tag = sys.argv[1:4]
errs, lines, cuts, queries = [], [], [], []
for path in sys.argv[4:]:
    ti = np.radians(float(path.rsplit("_", 1)[1][:-4]))
    s = np.loadtxt(path, delimiter=",", comments="#", skiprows=3)
    f, wo = s[:, 1], s[:, 2:5]
    keep = (f >= 0.01 * f.max()) & (wo[:, 2] > 0.02)
    wi = np.array([-np.sin(ti), 0, np.cos(ti)])
    queries.append(np.column_stack([np.tile(wi, (keep.sum(), 1)), wo[keep], np.full(keep.sum(), 550.0)]))
    cuts.append((path, f[keep]))
np.savetxt("q.txt", np.vstack(queries))  # one reader run per file
subprocess.run(["/usr/bin/python3", reader, bsdf, "eval", "q.txt", "a.txt"], check=True)
got, k = np.loadtxt("a.txt").reshape(-1), 0
for path, ref in cuts:
    e = np.abs(got[k:k + len(ref)] / ref - 1)
    k += len(ref)
    errs.extend(e)
    lines.append(f"  {path}: {len(ref)} points, median {100 * np.median(e):.3f}%")
med = float(np.median(errs))
print(f"export bsdf {tag}: independent reader vs brdf slice, median relative error "
      f"{100 * med:.3f}% over {len(errs)} lobe points (4 cuts)")
print("\n".join(lines))
assert med < 0.02, med
PY
}
check_cuts g.bsdf ggx --model ggx --alpha 0.3 --n 1.2 --k 3.5
check_cuts a.bsdf aniso --model ggx --alpha-x 0.1 --alpha-y 0.3 --metal Al
check_cuts t.bsdf ndf --ndf ndf.npy --metal Fe
/usr/bin/python3 - <<PY || fail "field shapes"
import sys; sys.path.insert(0, "$HERE")
import rgl_reference_reader as r
for name, n_phi in (("g.bsdf", 1), ("a.bsdf", 17), ("t.bsdf", 17)):
    f = r.read_tensor_file(name)
    assert f["phi_i"].shape == (n_phi,), (name, f["phi_i"].shape)
    assert f["spectra"].shape[:3] == (n_phi, 24, 25), (name, f["spectra"].shape)
PY

# --- Flags that do not go together are refused, nothing written. ---------------------------
$BIN export bsdf --model ggx --alpha 0.3 -o nomat.bsdf 2>err && fail "no material accepted"
grep -q -- "--metal" err || fail "missing material not explained: $(cat err)"
[ -e nomat.bsdf ] && fail "output written without a material"
$BIN export bsdf g.bsdf --model ggx --alpha 0.3 --metal Al -o both.bsdf 2>err \
  && fail "FILE and BRDF flags together accepted"
$BIN export bsdf --mirror --metal Al -o m.bsdf 2>err && fail "--mirror accepted"
$BIN measured ndf goni.csv --metal Unobtainium -o x.npy 2>err && fail "unknown metal accepted"
[ -e x.npy ] && fail "output written with an unknown metal"
$BIN measured ndf goni.csv --fresnel schlick -o x.npy 2>err && fail "--fresnel without a material accepted"
grep -q -- "--fresnel needs a material" err || fail "--fresnel alone not explained: $(cat err)"

# --- Mitsuba / pbrt: analytic models as rough conductors; the ellipsoid as the nearest GGX. --
for r in mitsuba pbrt; do
  $BIN export $r --model ellipsoid --alpha-x 0.1 --alpha-y 0.3 --theta-x 8deg --metal Al \
    -o "ell_$r" >out 2>err || fail "export $r ellipsoid: $(cat err)"
  grep -q "nearest GGX" err || fail "export $r: stderr does not say nearest GGX: $(cat err)"
  grep -q "skew" err || fail "export $r: stderr does not name the skew: $(cat err)"
done
grep -q "nearest GGX of the ellipsoid" ell_mitsuba/scene.xml || fail "Mitsuba scene lacks the note"
grep -q "nearest GGX of the ellipsoid" ell_mitsuba/material.xml || fail "Mitsuba material lacks the note"
grep -q "^ *# nearest GGX of the ellipsoid" ell_pbrt/scene.pbrt || fail "pbrt scene lacks the note"
/usr/bin/python3 - <<'PY' || fail "nearest GGX values"
import xml.etree.ElementTree as E, re
b = E.parse("ell_mitsuba/scene.xml").getroot().find("bsdf")
assert b.get("type") == "roughconductor", b.get("type")
v = {e.get("name"): e.get("value") for e in b}
au, av = float(v["alpha_u"]), float(v["alpha_v"])
t = open("ell_pbrt/material.pbrt").read()
pu = float(re.search(r'"float uroughness" \[ ([0-9.e+-]+) \]', t).group(1))
pv = float(re.search(r'"float vroughness" \[ ([0-9.e+-]+) \]', t).group(1))
print(f"ellipsoid 0.1 x 0.3, theta_x 8 deg -> nearest GGX alpha_u {au:.4f}, alpha_v {av:.4f} "
      f"(pbrt {pu:.4f}, {pv:.4f})")
assert abs(au - pu) < 1e-6 and abs(av - pv) < 1e-6
assert 0.08 < au < 0.12 and 0.25 < av < 0.35, (au, av)
assert v["distribution"] == "ggx"
for f in ("ell_mitsuba/eta.spd", "ell_mitsuba/k.spd", "ell_pbrt/eta.spd"):
    rows = [l.split() for l in open(f) if not l.startswith("#")]
    assert float(rows[0][0]) == 360 and float(rows[-1][0]) == 830, f  # nm
PY
# An untilted GGX is exported as it is (no note).
$BIN export mitsuba --model ggx --alpha-x 0.1 --alpha-y 0.3 --metal Au -o ggx_mi >out 2>err \
  || fail "export mitsuba ggx: $(cat err)"
grep -q "nearest" ggx_mi/scene.xml && fail "plain GGX export carries a nearest-GGX note"
grep -q 'name="alpha_u" value="0.1"' ggx_mi/scene.xml || fail "alpha_u of a GGX changed"
# A tabulated NDF becomes a `measured` material with its .bsdf written next to the scene.
$BIN export pbrt --ndf ndf.npy --metal Fe --wavelengths 3 --theta-i 6 -o tab_pb >out 2>err \
  || fail "export pbrt --ndf: $(cat err)"
grep -q 'Material "measured" "string filename" "material.bsdf"' tab_pb/scene.pbrt \
  || fail "pbrt measured material"
[ -s tab_pb/material.bsdf ] || fail "the .bsdf is not next to the pbrt scene"
# A Kirchhoff D_K table (wave optics) goes through the BRDF's own lobe; a parameter texture is
# exported as the ellipsoid of its mean texel (said on stderr), as the nearest GGX.
# (D_K by the midpoint rule: on this 1.1 um grid the exact rule needs ~56 points per triangle)
$BIN ndf "$HERE/data/metropro-1.dat" --method kirchhoff --dk-integration midpoint \
  --wavelength 550nm --resolution 257 \
  -o dk.npy >/dev/null 2>err || fail "ndf kirchhoff: $(cat err)"
$BIN export bsdf --kirchhoff dk.npy --metal Fe --theta-i 6 --wavelengths 3 -o k.bsdf >out 2>err \
  || fail "export bsdf --kirchhoff: $(cat err)"
[ -s k.bsdf ] || fail "no .bsdf of the Kirchhoff BRDF"
$BIN generate brushed --preset stainless4 --nx 640 --ny 512 --seed 2 -o s.x3p >/dev/null 2>&1 \
  || fail "generate"
$BIN texture s.x3p --texel 14um -o tex.exr --no-preview >/dev/null 2>&1 || fail "texture fit"
$BIN export mitsuba --texture tex.exr --metal Fe -o tex_mi >out 2>err \
  || fail "export mitsuba --texture: $(cat err)"
grep -q "mean valid texel" err || fail "texture export does not say it takes the mean: $(cat err)"
grep -q 'type="roughconductor"' tex_mi/scene.xml || fail "texture mean is not a rough conductor"
grep -q "nearest GGX of the ellipsoid" tex_mi/scene.xml || fail "texture export lacks the note"
echo OK
