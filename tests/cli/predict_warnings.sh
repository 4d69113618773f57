#!/usr/bin/env bash
# `microbrdf predict` warnings: each check is made to fire on an input built for it, and the
# warning must appear in summary.json "warnings" (code, message, what_to_do) and in the box at
# the top of report.html, also under --quiet. A clean input has none and says so. Fits that end
# on a parameter bound are not converged (summary, report and `fit --json`).
set -u
BIN=$1
DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
FAST=(--no-render --quiet)

# check DIR CODE...: every CODE is in summary.json warnings with a message and what to do, and
# in the report's warnings box (which comes before the first section).
check() {
  python3 - "$@" <<'PY'
import json, os, sys
d, codes = sys.argv[1], sys.argv[2:]
s = json.load(open(os.path.join(d, "summary.json")))
w = s["warnings"]
html = open(os.path.join(d, "report.html")).read()
box = html.index('id="warnings"')
assert box < html.index('id="s1"'), "warnings box is not at the top"
end = html.index("</div>", box)
for c in codes:
    hits = [e for e in w if e["code"] == c]
    assert hits, (c, [e["code"] for e in w])
    for e in hits:
        assert len(e["message"]) > 20 and len(e["what_to_do"]) > 20, e
    assert "<code>" + c + "</code>" in html[box:end], c
assert ("Warnings (%d)" % len(w)) in html[box:end]
PY
}

# A clean, well-resolved isotropic surface: no warning, and the box says so.
$BIN generate gaussian --nx 256 --ny 256 --spacing 0.25um --sigma 0.1um --tau 1.5um --seed 5 \
  -o "$T/clean.x3p" 2>/dev/null || fail generate
$BIN predict "$T/clean.x3p" --level none --resolution 257 "${FAST[@]}" -o "$T/clean" >/dev/null ||
  fail "predict clean"
python3 - "$T/clean" <<'PY' || fail "clean input has warnings"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
assert s["warnings"] == [], s["warnings"]
assert all(f["converged"] and f["at_bound"] is None for f in s["fits"]), s["fits"]
html = open(os.path.join(sys.argv[1], "report.html")).read()
assert "Warnings: none." in html
PY

# filter_sigma_below_spacing (0.1 um on a 0.25 um grid).
$BIN predict "$T/clean.x3p" --level none --resolution 257 --filter-sigma 0.1um \
  "${FAST[@]}" -o "$T/sigma" >/dev/null || fail "predict sigma"
check "$T/sigma" filter_sigma_below_spacing || fail "filter sigma warning"
# kirchhoff_integral: on a 0.5 um grid the slopes' lobe reaches past the scan's Nyquist band
# (pi / 0.5 um < |q|), the band mask removes part of D_K and the rest integrates to about 0.96.
$BIN generate gaussian --nx 128 --ny 128 --spacing 0.5um --sigma 0.3um --tau 2um --seed 5 \
  -o "$T/coarse.x3p" 2>/dev/null || fail generate
$BIN predict "$T/coarse.x3p" --level none --resolution 129 --kirchhoff --dk-integration midpoint \
  "${FAST[@]}" -o "$T/dk" >/dev/null || fail "predict dk"
check "$T/dk" kirchhoff_integral || fail "D_K integral warning"

# The smooth Zygo scan: its lobe (rms slopes ~0.001) spans a few nodes of the 1025^2 table:
# table_too_coarse, and the fits run on a zoomed filtered table (ndf_filtered_zoom.npy, its window
# in the sidecar) where the lobe spans tens of nodes; they converge inside their bounds. The
# Beckmann width departs from the zoomed table's rms slopes by more than 5% because the slopes
# are far from Gaussian (kurtosis > 3): fit_width_vs_rms says so. Its plane-levelled heights are
# dominated by form (Sq 13 nm vs 3 nm with poly3).
$BIN predict "$DATA/metropro-1.dat" "${FAST[@]}" -o "$T/zygo" >/dev/null || fail "predict zygo"
check "$T/zygo" table_too_coarse form_dominates fit_width_vs_rms || fail "zygo warnings"
python3 - "$T/zygo" <<'PY' || fail "zygo zoomed fits"
import json, math, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
z = s["ndf"]["filtered"]["zoom"]
side = json.load(open(os.path.join(d, "ndf_filtered_zoom.json")))
assert side["window"]["x"] == z["window"]["x"] and side["sampling"] == "cell", side
half = (z["window"]["x"][1] - z["window"]["x"][0]) / 2
assert half < 0.05 and z["window_mass"] > 0.999, z
smin = min(z["slope_rms_x"], z["slope_rms_y"])
assert 4 * smin / z["node_spacing"] >= 10, z  # the lobe spans >= 10 nodes of the zoomed table
codes = [e["code"] for e in s["warnings"]]
assert "fit_at_bound" not in codes, codes
for f in s["fits"]:
    assert f["converged"] is True and f["at_bound"] is None and f["source"] == "filtered_zoom", f
    assert min(f["params"]["alpha_x"], f["params"]["alpha_y"]) > 1e-4, f
b = [f for f in s["fits"] if f["model"] == "beckmann"][0]["width_vs_rms"]
assert max(abs(x) for x in b["relative_difference"]) > 0.05 and max(b["slope_kurtosis"]) > 3, b
w = [e for e in s["warnings"] if e["code"] == "fit_width_vs_rms"][0]
assert "kurtosis" in w["message"] and "heavy tails" in w["message"], w
table = [e for e in s["warnings"] if e["code"] == "table_too_coarse" and "filtered" in e["message"]]
assert table and "ndf_filtered_zoom.npy" in table[0]["what_to_do"], table
PY
# `fit` on the zoomed table reads its window and agrees with predict; on the whole-disk table
# the lobe is below the node spacing and the fit ends at the lower alpha bound: not converged.
$BIN fit "$T/zygo/ndf_filtered_zoom.npy" --model beckmann --json >"$T/fitz.json" 2>/dev/null ||
  fail "fit zoom"
$BIN fit "$T/zygo/ndf_filtered.npy" --json >"$T/fit.json" 2>/dev/null || fail "fit"
python3 - "$T/fitz.json" "$T/fit.json" "$T/zygo/summary.json" <<'PY' || fail "fit --json on the zygo tables"
import json, sys
z, f, s = (json.load(open(p)) for p in sys.argv[1:])
b = [x for x in s["fits"] if x["model"] == "beckmann"][0]
assert z["converged"], z
for a in ("x", "y"):
    assert all(abs(p - q) < 1e-15 for p, q in zip(z["window"][a], b["window"][a])), (z, b)
assert abs(z["params"]["alpha_x"] / b["params"]["alpha_x"] - 1) < 1e-6, (z["params"], b["params"])
assert f["converged"] is False and "lower alpha bound" in f["at_bound"], f
PY

# fit_at_bound in predict: a surface smoother than the fits' smallest width (rms slope ~1.4e-6,
# alpha floor 1e-5) even on the zoomed table: every fit ends at the bound, not converged.
$BIN generate gaussian --nx 256 --ny 256 --spacing 0.25um --sigma 0.005nm --tau 5um --seed 5 \
  -o "$T/flat.x3p" 2>/dev/null || fail "generate flat"
$BIN predict "$T/flat.x3p" --level none --resolution 257 "${FAST[@]}" -o "$T/flat" >/dev/null ||
  fail "predict flat"
check "$T/flat" table_too_coarse fit_at_bound || fail "flat warnings"
python3 - "$T/flat" <<'PY' || fail "flat fits reported as converged"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
for f in s["fits"]:
    assert f["converged"] is False and f["at_bound"].startswith("the lower alpha bound 1e-05"), f
html = open(os.path.join(sys.argv[1], "report.html")).read()
assert html.count("no (at the lower alpha bound 1e-05") == len(s["fits"]), "report says converged"
PY

# The bullet land (the cylinder left by plane levelling; 10.8% invalid samples):
# form_dominates and invalid_samples; poly3 levelling removes the form warning.
$BIN predict "$DATA/sample-land.x3p" "${FAST[@]}" -o "$T/land" >/dev/null || fail "predict land"
check "$T/land" form_dominates invalid_samples || fail "land warnings"
$BIN predict "$DATA/sample-land.x3p" --level poly3 "${FAST[@]}" -o "$T/land3" >/dev/null ||
  fail "predict land poly3"
python3 - "$T/land3/summary.json" <<'PY' || fail "poly3 levelling still warns of the form"
import json, sys
s = json.load(open(sys.argv[1]))
assert "form_dominates" not in [e["code"] for e in s["warnings"]], s["warnings"]
assert s["inputs"][0]["form_check"] is None
PY

# fit_poor: a sinusoidal grating's NDF (two ridges at the extreme slopes) is no single lobe.
$BIN generate grating --amplitude 50nm --period 4um --nx 512 --ny 256 -o "$T/grating.x3p" \
  2>/dev/null || fail "generate grating"
$BIN predict "$T/grating.x3p" --level none --resolution 257 "${FAST[@]}" -o "$T/grating" \
  >/dev/null || fail "predict grating"
check "$T/grating" fit_poor || fail "grating warnings"

# Verdicts: each fit's word follows its own numbers (thresholds of docs/report.md, applied here
# independently), the report's first line quotes the best fit that is not poor, or none.
verdicts() {
  python3 - "$1" <<'PY'
import json, os, re, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
html = open(os.path.join(d, "report.html")).read()
first = html[html.index("<p>", html.index('id="warnings"')):]
first = first[:first.index("</p>")]
ok = []
for f in s["fits"]:
    l2, h = f["relative_l2_error"], f["hellinger"]
    want = ("poor" if not f["converged"] or f["at_bound"] is not None or not l2 < 0.45
            else "good" if l2 < 0.2 and h < 0.1 else "usable")
    assert f["verdict"] == want, (f["model"], f["verdict"], want, l2, h)
    assert "<b>%s</b>" % want in html
    if want != "poor":
        ok.append(f)
if ok:
    best = min(ok, key=lambda f: (f["verdict"] != "good", f["hellinger"]))
    assert "best fit %s (%s)" % (best["model"], best["verdict"]) in first, first
    poor = [w for w in s["warnings"] if w["code"] == "fit_poor" and best["model"] in w["message"]]
    assert not poor, "the line quotes a model the warnings call poor"
else:
    assert "no parametric model fits this NDF" in first, first
print(d, [(f["model"], f["verdict"]) for f in s["fits"]])
PY
}
verdicts "$T/clean" || fail "verdicts of the clean surface"
verdicts "$T/grating" || fail "verdicts of the grating"
verdicts "$T/land" || fail "verdicts of the land"

# Without --quiet every warning is also a progress line on stderr.
$BIN predict "$T/clean.x3p" --level none --resolution 257 --filter-sigma 0.1um --no-render \
  -o "$T/loud" >/dev/null 2>"$T/stderr.txt" || fail "predict loud"
grep -q "warning: filter sigma 100 nm is below the sample spacing" "$T/stderr.txt" ||
  { cat "$T/stderr.txt"; fail "warning not printed"; }
echo ok
