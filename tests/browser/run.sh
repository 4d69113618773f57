#!/usr/bin/env bash
# The report in a real browser (tests/browser/report_test.mjs): makes a small predict report (a
# synthetic anisotropic scan, 16-pixel renders, the bundled courtyard map; the view adds the
# studio map beside it) and opens it in Debian's
# headless Chromium with the network off. The report's glTF view needs three.js embedded by the
# build (scripts/install-report-js.sh before cmake configures); without it the test fails, saying
# so. The comparisons of both views with `microbrdf render` take about 20 s of the test.
#
#   tests/browser/run.sh BIN [DATA_DIR]      (ctest label "browser", part of `make test`)
#
# Skipped (exit 77, which ctest reports as "Skipped"), saying why, when Chromium, Node.js or
# puppeteer-core is missing: `scripts/install-deps.sh --report` installs all three (puppeteer-core
# from npm into tests/browser/node_modules, by scripts/install-browser-test.sh). The test never
# downloads anything itself. BROWSER_TEST_SHOTS=DIR keeps PNG screenshots of the view there;
# BROWSER_TEST_REPORT=DIR checks that predict folder instead of making one (docs/report.md's
# screenshots: the demo's real scan).
set -u
BIN=$1
case "$BIN" in /*) ;; *) BIN=$(pwd)/$BIN ;; esac
HERE=$(cd "$(dirname "$0")" && pwd)
DATA=${2:-$HERE/../../data}
CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
skip() {
  echo "SKIPPED: browser test: $1"
  exit 77
}
[ -x "$CHROMIUM" ] || skip "no Chromium at $CHROMIUM (scripts/install-deps.sh --report installs it)"
command -v node >/dev/null || skip "no Node.js (scripts/install-deps.sh --report installs it)"
[ -f "$HERE/node_modules/puppeteer-core/package.json" ] ||
  skip "puppeteer-core is not installed in tests/browser/node_modules (scripts/install-browser-test.sh)"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
SHOTS=${BROWSER_TEST_SHOTS:-}
[ -z "$SHOTS" ] || { mkdir -p "$SHOTS" && SHOTS=$(cd "$SHOTS" && pwd); }
if [ -n "${BROWSER_TEST_REPORT:-}" ]; then  # an existing predict folder instead of a new one
  REPORT=$(cd "$BROWSER_TEST_REPORT" && pwd) || exit 1
  cd "$HERE" && node report_test.mjs "$BIN" "$REPORT" "$CHROMIUM" $SHOTS
  exit $?
fi
"$BIN" generate gaussian --nx 256 --ny 192 --spacing 0.25um --sigma 0.1um --tau 8um --tau-y 1.5um \
  --seed 3 -o "$T/b.x3p" >/dev/null 2>&1 || { echo "FAIL: generate"; exit 1; }
if ! "$BIN" predict "$T/b.x3p" --level none --resolution 129 --theta-i 30 --render-width 16 \
  --spp 1 --metal Cu --envmap "$DATA/envmaps/blender_courtyard.exr" -o "$T/out" >/dev/null 2>"$T/err"; then
  cat "$T/err"
  echo "FAIL: predict"
  exit 1
fi
cd "$HERE" && node report_test.mjs "$BIN" "$T/out" "$CHROMIUM" $SHOTS
