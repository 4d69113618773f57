#!/usr/bin/env bash
# `make demo`: the main job, `microbrdf predict`, on a real metal scan (a bullet's land-engraved
# area, Sensofar S neox, tests/data/sample-land.x3p) and on a synthetic
# brushed stainless #4 surface, each ending in a self-contained HTML report; headless Chromium
# then screenshots each report (scripts/screenshot-report.sh) so it is checked as a person sees it.
#
#   scripts/demo.sh [BIN] [OUT]     (defaults: build/bin/microbrdf, demo-out)
#
# Renders use the bundled CC0 courtyard environment map (data/envmaps/blender_courtyard.exr),
# the neutral studio map beside it, and a small light for the plate. 512 x 512 at 16 samples per
# pixel: each report compares every model with the measured NDF on three scenes (cylinder pair,
# sphere, plate), and states the render noise of each scene (about 20 % per pixel on the
# cylinders, 3 % after the 2-pixel smoothing of the difference images).
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
OUT=${2:-demo-out}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DATA=$ROOT/tests/data
ENVMAP=$ROOT/data/envmaps/blender_courtyard.exr
mkdir -p "$OUT"
START=$SECONDS

[ -f "$ENVMAP" ] || { echo "demo: $ENVMAP is missing (it is part of the repository)" >&2; exit 1; }
ENVFLAG=(--envmap "$ENVMAP")
RENDER=(--render-width 512 --spp 16)

echo "== 1. A synthetic brushed stainless #4 surface (Dong 2015 Fig. 12 widths)"
"$BIN" generate brushed --preset stainless4 --seed 1 -o "$OUT/brushed_stainless4.x3p" \
  --preview "$OUT/brushed_stainless4.png"

echo
echo "== 2. Statistics of the bundled real scans"
"$BIN" info "$DATA/sample-land.x3p" --level poly3
"$BIN" info --json "$DATA"/*.x3p "$DATA"/*.dat "$DATA"/*.datx "$DATA"/*.sur "$DATA"/*.gwy >"$OUT/statistics.json"

echo
# The land is a strip of a cylinder (the bullet): a 3rd-order polynomial takes the form out. The
# spacing is 2.58 um, so the filtered NDF uses a 5 um filter (two samples); the metal is not
# recorded in the file (a copper-alloy jacket is typical): Cu is an assumption.
echo "== 3. predict: a real scan, striated metal (bullet land, Sensofar S neox), copper assumed"
"$BIN" predict "$DATA/sample-land.x3p" --level poly3 --filter-sigma 5um --resolution 513 --metal Cu \
  "${ENVFLAG[@]}" "${RENDER[@]}" -o "$OUT/predict-land"

echo
echo "== 4. predict: the brushed surface, stainless steel, with the Kirchhoff D_K (wave optics)"
"$BIN" predict "$OUT/brushed_stainless4.x3p" --level none --metal SS-austenitic --kirchhoff \
  "${ENVFLAG[@]}" "${RENDER[@]}" -o "$OUT/predict-brushed"

echo
echo "== 5. Checks a reader would make: no broken image, no missing number (scripts/check-report.py)"
python3 "$ROOT/scripts/check-report.py" "$OUT/predict-land" "$OUT/predict-brushed"

echo
echo "== 6. Screenshots of the reports in headless Chromium"
SHOTS=()
for r in predict-land predict-brushed; do
  if "$ROOT/scripts/screenshot-report.sh" "$OUT/$r/report.html" "$OUT/$r/report.png" >/dev/null; then
    SHOTS+=("$OUT/$r/report.png")
  else
    echo "demo: no screenshot of $OUT/$r/report.html (see above)" >&2
  fi
done

echo
echo "Done in $((SECONDS - START)) s. Reports (open in a browser):"
echo "  $OUT/predict-land/report.html"
echo "  $OUT/predict-brushed/report.html"
echo "Summaries: $OUT/predict-land/summary.json $OUT/predict-brushed/summary.json"
[ ${#SHOTS[@]} -gt 0 ] && echo "Screenshots: ${SHOTS[*]}"
echo "Also: $OUT/brushed_stainless4.x3p (+ .png preview), $OUT/statistics.json"
