#!/usr/bin/env bash
# `predict --renders measured`: the measured NDF's three scenes only (no comparison strip, studio
# renders or swatch), a report that still reads; a bad value fails before any work and leaves no
# folder. Under a map with the studio map beside it, the studio views come from their scenes'
# passes (a second light set, 2 x 2 pixels averaged).
set -u
BIN=$1 REPO_DATA=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN generate gaussian --nx 128 --ny 96 --spacing 0.25um --sigma 0.1um --tau 8um --tau-y 1.5um \
  --seed 4 -o "$T/b.x3p" 2>/dev/null || fail generate
$BIN predict "$T/b.x3p" --level none --resolution 129 --render-width 16 --spp 2 \
  --renders measured -o "$T/out" --quiet >/dev/null || fail "--renders measured"
python3 "$(dirname "$0")/../../scripts/check-report.py" "$T/out" >"$T/check.txt" ||
  { cat "$T/check.txt"; fail "check-report"; }
python3 - "$T/out" <<'PY' || fail "summary of --renders measured"
import json, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
assert s["settings"]["renders"] == "measured", s["settings"]
assert [r["scene"] for r in s["renders"]] == ["cylinders", "sphere", "plate"], s["renders"]
assert all("shared_paths_with" not in r for r in s["renders"])
assert "render_comparison" not in s
assert not any(f.startswith("img/compare_") for f in s["outputs"])
html = open(os.path.join(d, "report.html")).read()
assert 'id="compare-' not in html
PY

# The default renders everything: the strip shares the measured render's paths.
$BIN predict "$T/b.x3p" --level none --resolution 129 --render-width 16 --spp 2 -o "$T/all" \
  --quiet >/dev/null || fail "default renders"
python3 - "$T/all/summary.json" <<'PY' || fail "summary of the default"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["settings"]["renders"] == "all"
scenes = [r for r in s["renders"] if r["role"] == "scene"]
# The strip: the three fits closest to the table (lowest Hellinger distance), in the fits' order.
strip = [f["model"] for f in s["fits"] if f["rank"] <= 3]
assert all(r["shared_paths_with"] == strip for r in scenes), (strip, scenes)
assert len(s["render_comparison"]["scenes"]) == 3
PY

$BIN predict "$T/b.x3p" --level none --resolution 129 --render-width 32 --spp 2 \
  --envmap "$REPO_DATA/envmaps/blender_courtyard.exr" -o "$T/env" --quiet >/dev/null ||
  fail "renders under a map"
python3 - "$T/env" <<'PY' || fail "studio views"
import json, os, struct, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "summary.json")))
studio = {r["scene"]: r for r in s["renders"] if r["role"] == "studio"}
assert sorted(studio) == ["cylinders_studio", "sphere_studio"], studio
for name, r in studio.items():
    assert r["rendered_in_pass_of"] == name[: -len("_studio")], r
    assert (r["width"], r["height"], r["spp"]) == (16, 16, 8), r
    with open(os.path.join(d, r["file"]), "rb") as f:
        head = f.read(24)
    assert struct.unpack(">II", head[16:24]) == (16, 16), head  # the PNG's IHDR size
    assert "render_" + name + "_s" not in s["timing"]  # (the pass's time is its scene's)
PY

$BIN predict "$T/b.x3p" --renders some -o "$T/bad" 2>"$T/err.txt"; rc=$?
[ $rc -ne 0 ] && grep -q -- "--renders" "$T/err.txt" && [ ! -e "$T/bad" ] ||
  fail "bad --renders: rc $rc, $(cat "$T/err.txt")"
echo ok
