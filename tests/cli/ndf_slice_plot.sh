#!/usr/bin/env bash
# ndf / slice / plot as a user runs them: JSON contract, normalisation, previews, errors.
set -u
BIN=$1 DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN generate gaussian --nx 256 --ny 256 --spacing 0.25um --sigma 0.1um --tau 2um -o "$T/g.x3p" 2>/dev/null || fail generate
$BIN ndf "$T/g.x3p" --level none --resolution 257 -o "$T/f.npy" --preview "$T/f.png" --zoom --json >"$T/f.summary" \
  || fail "ndf filtered"
[ -s "$T/f.npy" ] && [ -s "$T/f.json" ] && [ -s "$T/f.summary" ] && [ -s "$T/f.png" ] || fail "outputs missing"
python3 - "$T/f.summary" <<'PY' || fail "ndf JSON contract"
import json, sys, math
j = json.load(open(sys.argv[1]))
for k in ["method", "resolution", "integral", "mean_normal", "peak", "slope_rms_x", "slope_rms_y",
          "samples_used", "samples_skipped", "filter_sigma_m", "wavelength_m", "output"]:
    assert k in j, k
assert j["method"] == "filtered" and j["resolution"] == 257
assert abs(j["integral"] - 1) < 1e-9
# filtered rms slope of a Gaussian surface: alpha tau^2/(tau^2+4s^2)/sqrt2, sigma .1 tau 2 s 1 (um)
expect = 0.1 * 4 / (4 + 4) / math.sqrt(2)
assert abs(j["slope_rms_x"] / expect - 1) < 0.1, j["slope_rms_x"]
PY
# The .npy is what numpy reads: magic and a dict header with the shape.
head -c 128 "$T/f.npy" | grep -q "'shape': (257, 257)" || fail "npy header"

# Instrument convolution widens the NDF and keeps it normalised.
$BIN ndf "$T/g.x3p" --level none --resolution 257 --instrument-fwhm 3deg -o "$T/c.npy" --json >"$T/c.summary" || fail conv
python3 -c "
import json; a=json.load(open('$T/f.summary')); b=json.load(open('$T/c.summary'))
assert abs(b['integral']-1)<1e-9 and b['slope_rms_x']>a['slope_rms_x'], (a['slope_rms_x'], b['slope_rms_x'])" || fail "convolution"

# The instrument signature applies to every method (Kirchhoff D_K too): the table changes, the
# integral stays 1, and the FWHM is recorded in the JSON summary and in the sidecar's notes.
for m in naive filtered kirchhoff; do
  # (D_K by the midpoint rule: the exact rule takes ~50 points per triangle on this 0.25 um grid)
  $BIN ndf "$T/g.x3p" --method $m --level none --resolution 257 --dk-integration midpoint \
    -o "$T/$m-0.npy" --json >"$T/$m-0.summary" 2>/dev/null || fail "ndf $m"
  $BIN ndf "$T/g.x3p" --method $m --level none --resolution 257 --dk-integration midpoint \
    --instrument-fwhm 3deg \
    -o "$T/$m-3.npy" --json >"$T/$m-3.summary" 2>/dev/null || fail "ndf $m --instrument-fwhm"
  /usr/bin/python3 - "$T/$m-0" "$T/$m-3" <<'PY' || fail "instrument with --method $m"
import json, sys, math
import numpy as np
a, b = json.load(open(sys.argv[1] + ".summary")), json.load(open(sys.argv[2] + ".summary"))
ta, tb = np.load(sys.argv[1] + ".npy"), np.load(sys.argv[2] + ".npy")
assert np.abs(ta - tb).max() > 0.01 * ta.max(), "table unchanged"
assert abs(b["integral"] - 1) < 1e-9 and b["slope_rms_x"] > a["slope_rms_x"]
assert a["instrument_fwhm_rad"] == 0 and abs(b["instrument_fwhm_rad"] - math.radians(3)) < 1e-12
side = json.load(open(sys.argv[2] + ".json"))
assert "angular Gaussian, FWHM 3 deg" in json.dumps(side), side
s2 = (math.radians(3) / (2 * math.sqrt(2 * math.log(2)))) ** 2
added = [(b[k] ** 2 - a[k] ** 2) / s2 for k in ("slope_rms_x", "slope_rms_y")]
print(f"ndf --method {a['method']} --instrument-fwhm 3deg: added variance / sigma^2 "
      f"x {added[0]:.4f} y {added[1]:.4f}")
assert all(abs(x - 1) < 0.05 for x in added), added
PY
done
# A measured signature (an NDF table: a narrow lobe about the pole) instead of the Gaussian.
$BIN tabulate --model beckmann --alpha 0.03 --resolution 257 -o "$T/sig.npy" >/dev/null || fail tabulate
$BIN ndf "$T/g.x3p" --method kirchhoff --dk-integration midpoint --level none --resolution 257 \
  --instrument "$T/sig.npy" \
  -o "$T/ks.npy" --json >"$T/ks.summary" 2>/dev/null || fail "ndf --instrument"
grep -q "measured instrument signature" "$T/ks.json" || fail "signature not recorded"
$BIN ndf "$T/g.x3p" --instrument "$T/sig.npy" --instrument-fwhm 1deg -o "$T/bad.npy" \
  2>"$T/err" && fail "both signatures accepted"
grep -q -- "--instrument-fwhm or --instrument" "$T/err" || fail "both signatures message"
$BIN ndf "$T/g.x3p" --method kirchhoff --instrument-fwhm -3deg -o "$T/bad.npy" 2>"$T/err" \
  && fail "negative FWHM accepted"
grep -q -- "--instrument-fwhm: must lie in 0 .. 90 deg" "$T/err" || fail "negative FWHM message"

$BIN ndf "$T/g.x3p" --method naive --level none --resolution 257 -o "$T/n.exr" 2>/dev/null || fail "ndf naive exr"
$BIN slice "$T/n.exr" "$T/f.npy" --azimuth 0,90 --log -o "$T/s.png" --csv "$T/s.csv" 2>/dev/null || fail slice
[ -s "$T/s.png" ] && grep -q "^f,90," "$T/s.csv" || fail "slice outputs"
printf 'x,a,b\n1,2,3\n2,4,5\n3,8,4\n' >"$T/d.csv"
$BIN plot "$T/d.csv" --x x --y a,b -o "$T/p.svg" || fail plot
grep -q "<svg" "$T/p.svg" || fail "svg"

# Errors: unknown method (exit 2), missing column, bad resolution; no output left behind.
$BIN ndf "$T/g.x3p" --method magic -o "$T/bad.npy" 2>"$T/err"; [ $? -eq 2 ] || fail "unknown method exit"
grep -q "naive | filtered" "$T/err" || fail "unknown method message"
$BIN plot "$T/d.csv" --x x --y nope -o "$T/bad.png" 2>"$T/err" && fail "missing column accepted"
grep -q "no column 'nope'" "$T/err" || fail "missing column message"
$BIN ndf "$T/g.x3p" --resolution 5 -o "$T/bad.npy" 2>/dev/null && fail "tiny resolution accepted"
ls "$T" | grep -q bad && fail "partial output left"
echo ok
