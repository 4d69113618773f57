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

# The smooth Zygo scan: its lobe (rms slopes ~0.001) spans a few nodes of the 1025^2 table and
# every fit stops at the lower alpha bound: table_too_coarse, fit_at_bound, not converged.
# Its plane-levelled heights are dominated by form (Sq 13 nm vs 3 nm with poly3).
$BIN predict "$DATA/metropro-1.dat" "${FAST[@]}" -o "$T/zygo" >/dev/null || fail "predict zygo"
check "$T/zygo" table_too_coarse fit_at_bound form_dominates || fail "zygo warnings"
python3 - "$T/zygo" <<'PY' || fail "zygo fits reported as converged"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
for f in s["fits"]:
    assert f["converged"] is False and f["at_bound"].startswith("the lower alpha bound 0.000488"), f
    assert abs(min(f["params"]["alpha_x"], f["params"]["alpha_y"]) - 1 / 2048) < 1e-9, f
html = open(os.path.join(sys.argv[1], "report.html")).read()
assert html.count("no (at the lower alpha bound 0.000488") == 3, "report says converged"
PY
# `fit --json` on the same table says the same.
$BIN fit "$T/zygo/ndf_filtered.npy" --json >"$T/fit.json" 2>/dev/null || fail "fit"
python3 - "$T/fit.json" <<'PY' || fail "fit --json reports a bound fit as converged"
import json, sys
f = json.load(open(sys.argv[1]))
f = f.get("fit", f)
assert f["converged"] is False and "lower alpha bound" in f["at_bound"], f
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

# Without --quiet every warning is also a progress line on stderr.
$BIN predict "$T/clean.x3p" --level none --resolution 257 --filter-sigma 0.1um --no-render \
  -o "$T/loud" >/dev/null 2>"$T/stderr.txt" || fail "predict loud"
grep -q "warning: filter sigma 100 nm is below the sample spacing" "$T/stderr.txt" ||
  { cat "$T/stderr.txt"; fail "warning not printed"; }
echo ok
