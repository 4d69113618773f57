#!/usr/bin/env bash
# `microbrdf predict` as a user runs it: report and summary exist, every <img> carries a
# non-empty data: URI, no nan/inf and no empty table cell in the report, the summary is strict
# JSON (no NaN) with the keys docs/report.md lists, --json on stdout, errors leave no folder.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN generate gaussian --nx 256 --ny 192 --spacing 0.25um --sigma 0.1um --tau 8um --tau-y 1.5um \
  --seed 3 -o "$T/b.x3p" 2>/dev/null || fail generate
$BIN predict "$T/b.x3p" --level none --resolution 257 --theta-i 30,60 --render-width 32 --spp 2 \
  -o "$T/out" --json >"$T/stdout.json" 2>"$T/stderr.txt" || { cat "$T/stderr.txt"; fail predict; }
[ -s "$T/out/report.html" ] && [ -s "$T/out/summary.json" ] || fail "report or summary missing"
grep -q "renders" "$T/stderr.txt" || fail "no progress on stderr"

# The reader's checks (scripts/check-report.py): strict JSON, listed outputs exist, every <img>
# a non-empty data: URI, renders present, no nan/inf/null and no empty cell in the text.
python3 "$(dirname "$0")/../../scripts/check-report.py" "$T/out" >"$T/check.txt" || { cat "$T/check.txt"; fail "check-report"; }
python3 - "$T/out" "$T/stdout.json" <<'PY' || fail "summary contents"
import json, re, sys, os
d, out = sys.argv[1], json.load(open(sys.argv[2]))
assert out["report"].endswith("report.html") and os.path.exists(out["report"]), out
s = json.load(open(os.path.join(d, "summary.json")))
# Every registered model is fitted (the built-ins first) and ranked by Hellinger distance.
names = [f["model"] for f in s["fits"]]
assert names[:3] == ["ellipsoid", "beckmann", "ggx"], names
ranked = sorted(s["fits"], key=lambda f: f["rank"])
assert [f["rank"] for f in ranked] == list(range(1, len(names) + 1)), ranked
assert all(a["hellinger"] <= b["hellinger"] for a, b in zip(ranked, ranked[1:])), ranked
# The compared scenes and the colour swatch (no studio map without --envmap beside it).
assert [r["scene"] for r in s["renders"]] == ["cylinders", "sphere", "plate", "swatch"], s["renders"]
assert all(-10 <= r["exposure_stops"] <= 10 for r in s["renders"])
assert [round(a["theta_i_deg"]) for a in s["brdf"]["albedo"]] == [30, 60]
html = open(os.path.join(d, "report.html")).read()
assert len(re.findall(r"<img ", html)) >= 6  # height map, 2 NDFs, fit comparison, 2 renders
assert html.count("<svg") == 1 + 2 + 2 * 2 + html.count('class="zoomp"')  # regime map; NDF cuts x, y; in/out slices at 2 angles; zooms
# The comparison strip: every fit rendered like the measured-NDF cylinders, its difference image,
# SSIM in (0, 1] and RMS relative error against the measured render, and the render noise.
rc = s["render_comparison"]
assert rc["reference"] == "img/render_cylinders.png" and rc["width"] == 32 and rc["spp"] == 2
# (the three fits closest to the table, in the fits' order)
strip = [f["model"] for f in s["fits"] if f["rank"] <= 3]
assert [m["model"] for m in rc["models"]] == strip, (strip, rc)
for m in rc["models"]:
    assert 0 < m["ssim"] <= 1 and 0 <= m["rms_relative"] < 10, m
    for k in ("image", "difference_image"):
        assert os.path.getsize(os.path.join(d, m[k])) > 0 and m[k] in s["outputs"], m[k]
assert 0 < rc["noise"]["rms_relative"] < 10 and 0 < rc["noise"]["ssim_two_seeds"] <= 1
assert rc["difference_scale"]["max"] > 0
assert "Each model rendered" in html and "Render noise" in html and "Wang et al. 2004" in html
# Every scene compared (the cylinder pair's keys also at the top level, as before), each with its
# noise; the smoothed error is below the per-pixel one for noise (averaging removes noise).
sc = rc["scenes"]
assert [x["scene"] for x in sc] == ["cylinders", "sphere", "plate"], [x["scene"] for x in sc]
assert {k: v for k, v in sc[0].items()} == {k: v for k, v in rc.items() if k != "scenes"}
for x in sc:
    n = x["noise"]
    # Smoothing averages the pixel noise away (the plate's light is mirrored into the camera,
    # so even this narrow lobe lights it: no scene is black).
    assert 0 < n["rms_relative_smoothed"] < n["rms_relative"], (x["scene"], n)
    assert [m["model"] for m in x["models"]] == strip
    assert x["exposure_stops"] == next(r for r in s["renders"] if r["scene"] == x["scene"])["exposure_stops"]
    for m in x["models"]:
        assert 0 < m["ssim"] <= 1 and 0 <= m["rms_relative_smoothed"] < 10, m
        for k in ("image", "difference_image"):
            assert m[k] in s["outputs"] and os.path.getsize(os.path.join(d, m[k])) > 0, m[k]
    assert x["reference"] == "img/render_%s.png" % x["scene"]
    assert "thumbnail" not in x["models"][0]  # 32-px renders: shown as they are
    assert 'id="compare-%s"' % x["scene"] in html
assert len(re.findall(r"<img ", html)) >= 6 + 1 + 2 * 3  # + the strip: reference, image + diff
PY

# Same inputs and seed: the same summary apart from timing (and "mpi", seconds per rank).
$BIN predict "$T/b.x3p" --level none --resolution 257 --theta-i 30,60 --render-width 32 --spp 2 \
  -o "$T/again" --quiet >/dev/null || fail "second run"
python3 - "$T/out/summary.json" "$T/again/summary.json" <<'PY' || fail "not deterministic"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ("timing", "mpi"): a.pop(k); b.pop(k)
assert a == b
PY

# With D_K beside the geometric theory the strip gains a Kirchhoff render; --no-render has no strip.
$BIN predict "$T/b.x3p" --level none --resolution 129 --kirchhoff --dk-integration midpoint \
  --theory geometric \
  --render-width 16 --spp 1 \
  -o "$T/dk" --quiet >/dev/null || fail "--kirchhoff run"
$BIN predict "$T/b.x3p" --level none --resolution 129 --no-render -o "$T/norender" --quiet \
  >/dev/null || fail "--no-render run"
python3 - "$T/dk/summary.json" "$T/norender/summary.json" <<'PY' || fail "strip with D_K / no render"
import json, sys
dk, nr = (json.load(open(p)) for p in sys.argv[1:3])
for x in dk["render_comparison"]["scenes"]:
    models = [m["model"] for m in x["models"]]
    strip = [f["model"] for f in dk["fits"] if f["rank"] <= 3]
    assert models == strip + ["kirchhoff"], models
    # (16 px at 1 spp: mostly noise, so SSIM may fall below 0; it stays an SSIM)
    assert all(-1 <= m["ssim"] <= 1 for m in x["models"])
assert "render_comparison" not in nr and "skipped" in nr["renders"]
PY

# Errors: exit code, message naming the file, no output folder, no staging folder.
$BIN predict "$T/nope.x3p" -o "$T/bad" 2>"$T/err.txt"; rc=$?
[ $rc -ne 0 ] && grep -q "nope.x3p" "$T/err.txt" && [ ! -e "$T/bad" ] || fail "missing input"
$BIN predict "$T/b.x3p" --metal Xx -o "$T/bad" 2>"$T/err.txt"; rc=$?
[ $rc -eq 2 ] && [ ! -e "$T/bad" ] || fail "unknown metal: rc $rc"
$BIN predict "$T/b.x3p" --strips "$T/b.x3p" -o "$T/bad" 2>/dev/null && fail "--strips with one file"
[ ! -e "$T/bad" ] || fail "partial output"
ls -a "$T" | grep -q partial && fail "staging folder left behind"
mkdir "$T/mine" && echo keep >"$T/mine/notes.txt"
$BIN predict "$T/b.x3p" --no-render --resolution 129 -o "$T/mine" 2>/dev/null && fail "replaced a foreign folder"
[ "$(cat "$T/mine/notes.txt")" = keep ] || fail "foreign folder touched"
$BIN predict --help | grep -q "summary.json" || fail "--help"
echo ok
