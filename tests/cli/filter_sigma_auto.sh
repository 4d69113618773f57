#!/usr/bin/env bash
# --filter-sigma auto in `ndf` and `predict`: the chosen sigma is the minimum of the written curve
# (Hellinger distance of the filtered NDF to D_K), the curve file matches the JSON, a two-scale
# surface (fine roughness far below lambda_q on a geometric-optics Gaussian) has its minimum
# inside the sweep, and predict compares naive, filtered and D_K and renders the NDF asked for.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# Two scales: tau 3 um / 0.2 um rms (q h ~ 4.5 at 555 nm) plus tau 0.1 um / 10 nm rms.
$BIN generate gaussian --nx 384 --ny 384 --spacing 25nm --sigma 0.2um --tau 3um --seed 1 \
  -o "$T/large.npy" 2>/dev/null || fail generate
$BIN generate gaussian --nx 384 --ny 384 --spacing 25nm --sigma 10nm --tau 0.1um --seed 2 \
  -o "$T/fine.npy" 2>/dev/null || fail generate
/usr/bin/python3 - "$T" <<'PY' || fail "sum of the two scales"
import numpy as np, sys
t = sys.argv[1]
np.save(t + "/two.npy", np.load(t + "/large.npy") + np.load(t + "/fine.npy"))
PY
$BIN ndf "$T/two.npy" --spacing 25nm --filter-sigma auto --patch whole --resolution 129 \
  --sweep-resolution 129 -o "$T/two_ndf.npy" --json >"$T/two_out.json" 2>"$T/two.err" ||
  fail "ndf --filter-sigma auto: $(cat "$T/two.err")"
/usr/bin/python3 - "$T" <<'PY' || fail "ndf --filter-sigma auto JSON / curve"
import csv, json, sys
t = sys.argv[1]
j = json.load(open(t + "/two_out.json"))
a = j["filter_sigma_auto"]
curve = a["curve"]
sig = [p["sigma_m"] for p in curve]
h = [p["hellinger"] for p in curve]
assert len(curve) >= 15, len(curve)
assert sig == sorted(sig), sig
assert all(0 <= x <= 1 for x in h), h
k = h.index(min(h))
assert j["filter_sigma_m"] == a["sigma_m"] == sig[k], (j["filter_sigma_m"], a["sigma_m"], sig[k])
assert 0 < k < len(h) - 1, ("minimum at an end", sig[k], h)
assert h[k] < h[0] - 0.03 and h[k] < h[-1] - 0.03, h
assert h[k] < a["distances"]["naive_kirchhoff"] - 0.03, a["distances"]
assert abs(sig[0] - 25e-9) < 1e-15, sig[0]  # the sweep starts at the sample spacing
side = json.load(open(t + "/two_ndf.json"))  # the table's sidecar records the chosen sigma
assert side["filter_sigma_m"] == a["sigma_m"], side["filter_sigma_m"]
rows = list(csv.DictReader(open(a["curve_file"])))
assert a["curve_file"].endswith("two_ndf_filter_sigma.csv"), a["curve_file"]
assert [float(r["sigma_m"]) for r in rows] == [float("%.9g" % s) for s in sig]
assert [float(r["hellinger"]) for r in rows] == [float("%.9g" % x) for x in h]
PY
grep -q "filter-sigma auto: " "$T/two.err" && fail "--json run printed a summary line"

# Without --json the choice is printed; errors name the flag and leave no output.
$BIN ndf "$T/two.npy" --spacing 25nm --filter-sigma auto --patch whole --resolution 65 \
  --sweep-resolution 65 -o "$T/plain.npy" 2>"$T/plain.err" >/dev/null || fail "plain run"
grep -q -- "--filter-sigma auto: .*Hellinger distance to D_K" "$T/plain.err" || fail "no summary line"
test -s "$T/plain_filter_sigma.csv" || fail "no curve file beside the table"
if $BIN ndf "$T/two.npy" --spacing 25nm --method naive --filter-sigma auto -o "$T/x.npy" \
  2>"$T/e1"; then fail "auto with --method naive accepted"; fi
grep -q -- "--filter-sigma auto applies to --method filtered" "$T/e1" || fail "$(cat "$T/e1")"
if $BIN ndf "$T/two.npy" --spacing 25nm --method kirchhoff --filter-sigma auto -o "$T/x.npy" \
  2>"$T/e1"; then fail "auto with --method kirchhoff accepted"; fi
grep -q -- "--filter-sigma auto applies to --method filtered" "$T/e1" || fail "$(cat "$T/e1")"
$BIN generate gaussian --nx 8 --ny 8 --spacing 50nm --sigma 10nm --tau 0.1um -o "$T/tiny.x3p" \
  2>/dev/null || fail generate
if $BIN ndf "$T/tiny.x3p" --filter-sigma auto -o "$T/tiny.npy" 2>"$T/e2"; then
  fail "tiny field accepted"
fi
grep -q "is too small for it" "$T/e2" || fail "$(cat "$T/e2")"
test -e "$T/tiny.npy" && fail "output left behind"

# predict: the comparison section, the curve, the NDF of the renders.
$BIN predict "$T/two.npy" --spacing 25nm --level none --theory geometric --filter-sigma auto --resolution 129 \
  --sweep-resolution 129 --no-render --quiet -o "$T/p" >/dev/null || fail "predict auto"
/usr/bin/python3 - "$T/p" "$T/two_out.json" <<'PY' || fail "predict --filter-sigma auto summary/report"
import json, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
ndf = json.load(open(sys.argv[2]))
c = s["ndf_comparison"]
a = c["filter_sigma_auto"]
assert a["sigma_m"] == ndf["filter_sigma_m"], (a["sigma_m"], ndf["filter_sigma_m"])
assert s["ndf"]["filtered"]["filter_sigma_m"] == a["sigma_m"]
assert s["settings"]["filter_sigma_m"] == a["sigma_m"] and s["settings"]["filter_sigma_auto"]
assert c["render_ndf"] == "filtered" and "--filter-sigma auto" in c["render_reason"], c
h = c["hellinger"]
assert h["filtered_kirchhoff"] < h["naive_kirchhoff"], h
assert c["nearest_to_kirchhoff"] == "filtered", c
assert os.path.exists(os.path.join(d, a["curve_csv"])) and os.path.exists(os.path.join(d, a["curve_plot"]))
html = open(os.path.join(d, "report.html")).read()
for text in ["Which NDF: naive, filtered and D_K compared", "The renders use",
             "Hellinger distance naive–filtered"]:
    assert text in html, text
PY

# --render-ndf naive: the measured BRDF is the naive NDF's, and the report says D_K is nearer
# the filtered one (a warning).
$BIN predict "$T/two.npy" --spacing 25nm --level none --theory geometric --filter-sigma auto --resolution 129 \
  --sweep-resolution 129 --render-ndf naive --no-render --quiet -o "$T/pn" >/dev/null ||
  fail "predict --render-ndf naive"
/usr/bin/python3 - "$T/pn" <<'PY' || fail "predict --render-ndf naive"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
assert s["ndf_comparison"]["render_ndf"] == "naive"
labels = [m["label"] for m in s["brdf"]["models"]]
assert "measured (naive NDF)" in labels, labels
assert "render_ndf_not_nearest_dk" in [w["code"] for w in s["warnings"]], s["warnings"]
PY
# A scan sampled far coarser than lambda_q / 4: D_K keeps a small band about the pole only, and
# the report says so.
$BIN generate gaussian --nx 96 --ny 96 --spacing 2um --sigma 1um --tau 15um -o "$T/coarse.x3p" \
  2>/dev/null || fail generate
$BIN predict "$T/coarse.x3p" --level none --filter-sigma auto --resolution 65 \
  --sweep-resolution 65 --no-render --quiet -o "$T/pc" >/dev/null || fail "predict coarse"
/usr/bin/python3 - "$T/pc" <<'PY' || fail "aliased D_K warning"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
a = s["ndf_comparison"]["filter_sigma_auto"]
assert a["sweep"]["kirchhoff_aliased_fraction"] > 0.5, a["sweep"]
assert "filter_sigma_auto_aliased" in [w["code"] for w in s["warnings"]], s["warnings"]
PY
# --render-ndf kirchhoff means the Kirchhoff theory (D_K is computed for it): with another
# --theory it is a contradiction, refused before any work.
if $BIN predict "$T/two.npy" --spacing 25nm --render-ndf kirchhoff --theory geometric -o "$T/pk" \
  2>"$T/e3"; then
  fail "--render-ndf kirchhoff with --theory geometric accepted"
fi
grep -q "contradicts --theory geometric" "$T/e3" || fail "$(cat "$T/e3")"
test -e "$T/pk" && fail "predict output left behind"
echo OK
