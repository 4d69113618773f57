#!/usr/bin/env bash
# `predict --measured FILE`: the report and summary.json gain the comparison with the
# measurement. (1) The measurement is the prediction's own filtered NDF (from `ndf` with the
# same settings): the comparison is exact. (2) A goniometer CSV of a GGX lobe twice as wide as
# the scan's across one axis: the width ratios say so. (3) A bad file: error, nothing written.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
GONI=$(cd "$(dirname "$0")" && pwd)/make_goniometer.py
cd "$T" || exit 1

$BIN generate gaussian --sigma 0.1um --tau 2um --nx 256 --ny 256 --spacing 0.2um --seed 3 \
  -o scan.x3p >/dev/null 2>err || fail "generate: $(cat err)"
$BIN ndf scan.x3p --method filtered --filter-sigma 1um --resolution 129 -o self.npy >/dev/null \
  2>err || fail "ndf: $(cat err)"
$BIN predict scan.x3p --no-render --resolution 129 --measured self.npy -o rep --quiet >/dev/null \
  2>err || fail "predict --measured: $(cat err)"
/usr/bin/python3 - rep <<'PY' || fail "predict --measured (self)"
import json, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
m = s["measured"]
c = m["comparisons"][0]
print(f"predict --measured (its own table): {c['nodes']} nodes, relative L2 {c['relative_l2']:.3g}, "
      f"width ratios {c['alpha_x_ratio']:.6f} {c['alpha_y_ratio']:.6f}")
assert c["prediction"] == "filtered" and c["nodes"] > 1000
assert c["relative_l2"] < 1e-6 and abs(c["alpha_x_ratio"] - 1) < 1e-6, c
for k in ("measured", "predicted", "slices"):
    assert os.path.getsize(os.path.join(d, c["images"][k])) > 1000, k
assert os.path.exists(os.path.join(d, m["table"]))
assert m["table"] in s["outputs"] and c["images"]["slices"] in s["outputs"]
assert "measured_s" in s["timing"]
html = open(os.path.join(d, "report.html")).read()
assert "Prediction against the measurement" in html and html.count("data:image/png") >= 3
PY

# (2) A goniometer CSV: GGX with the (isotropic) scan's width from `fit` along x, twice that along y.
$BIN fit self.npy --model ggx --json >fit.json || fail "fit"
read -r AX AY < <(/usr/bin/python3 -c "
import json, sys, math; p = json.load(open(sys.argv[1]))['params']
a0 = math.sqrt(p['alpha_x'] * p['alpha_y']); print(a0, 2 * a0)" fit.json) || fail "fit.json"
/usr/bin/python3 "$GONI" goni.csv --alpha "$AX" "$AY" --rings 40 --max-r 0.9 --seed 5 --min-cos 0.05 \
  --wavelength 555 --digits 8 || fail "python could not write the CSV"
$BIN predict scan.x3p --no-render --resolution 129 --measured goni.csv --instrument-fwhm 0.5deg \
  -o rep2 --quiet >/dev/null 2>err || fail "predict --measured goni.csv: $(cat err)"
/usr/bin/python3 - rep2/summary.json <<'PY' || fail "predict --measured (wider CSV)"
import json, sys
s = json.load(open(sys.argv[1]))
m = s["measured"]; c = m["comparisons"][0]
print(f"predict --measured goni.csv (alpha_y doubled): width ratios x {c['alpha_x_ratio']:.3f} "
      f"y {c['alpha_y_ratio']:.3f}, relative L2 {c['relative_l2']:.3f}")
assert abs(m["instrument_fwhm_rad"] - 0.00872665) < 1e-6
assert abs(s["settings"]["instrument_fwhm_rad"] - 0.00872665) < 1e-6
assert abs(m["theta_d_rad"] - 0.246789) < 1e-5
assert 0.4 < c["alpha_y_ratio"] < 0.6, c   # predicted / measured: half as wide across
assert 0.85 < c["alpha_x_ratio"] < 1.2, c
PY

# A measured instrument signature (an NDF table) instead of the Gaussian: recorded, named in the
# report, and it widens the prediction (the ratio across grows towards 1 from about 0.5).
$BIN tabulate --model beckmann --alpha 0.02 --resolution 129 -o sig.npy >/dev/null || fail tabulate
$BIN predict scan.x3p --no-render --resolution 129 --measured goni.csv --instrument sig.npy \
  -o rep4 --quiet >/dev/null 2>err || fail "predict --instrument: $(cat err)"
/usr/bin/python3 - rep2/summary.json rep4/summary.json <<'PY' || fail "predict --instrument"
import json, sys
g, s = (json.load(open(p)) for p in sys.argv[1:])
assert s["settings"]["instrument"] == "sig.npy" and s["measured"]["instrument"] == "sig.npy"
cg, cs = g["measured"]["comparisons"][0], s["measured"]["comparisons"][0]
print(f"predict --instrument sig.npy: alpha_y ratio {cs['alpha_y_ratio']:.3f} "
      f"(Gaussian 0.5 deg: {cg['alpha_y_ratio']:.3f})")
assert cs["alpha_y_ratio"] > cg["alpha_y_ratio"], (cs, cg)
PY
grep -q "measured signature <code>sig.npy</code>" rep4/report.html || fail "signature not in report"
$BIN predict scan.x3p --no-render --measured goni.csv --instrument sig.npy --instrument-fwhm 1deg \
  -o rep5 --quiet >/dev/null 2>err && fail "both signatures accepted"
grep -q -- "--instrument-fwhm or --instrument" err || fail "both signatures: $(cat err)"

# (3) A file of no known kind: refused before any work, no output folder.
printf 'x' >m.txt
$BIN predict scan.x3p --no-render --measured m.txt -o rep3 --quiet >/dev/null 2>err \
  && fail "unknown --measured accepted"
grep -q "m.txt" err || fail "message does not name the file: $(cat err)"
[ -e rep3 ] && fail "output written despite the error"
$BIN predict scan.x3p --no-render --measured missing.csv -o rep3 --quiet >/dev/null 2>err \
  && fail "missing --measured accepted"
grep -q "missing.csv" err || fail "message does not name the missing file: $(cat err)"
echo OK
