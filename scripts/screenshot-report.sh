#!/usr/bin/env bash
# Renders an HTML report (microbrdf predict's report.html) in headless Chromium to a PNG, so the
# report is checked as a person sees it in a browser.
#
#   scripts/screenshot-report.sh REPORT.html OUT.png [WIDTHxHEIGHT]
#
# Default window 1280x9000 px (the whole report, top to bottom). Chromium is Debian's package
# (`scripts/install-deps.sh --report` installs it); CHROMIUM=/path/to/chromium overrides.
# A fresh empty profile directory is used and removed afterwards; no network, no GPU.
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 REPORT.html OUT.png [WIDTHxHEIGHT]" >&2
  exit 2
fi
REPORT=$1 OUT=$2 SIZE=${3:-1280x9000}
CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
if ! [ -x "$CHROMIUM" ]; then
  CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
fi
if [ -z "$CHROMIUM" ] || ! [ -x "$CHROMIUM" ]; then
  echo "screenshot-report: chromium not found (install it with scripts/install-deps.sh --report," \
    "or set CHROMIUM=/path/to/chromium)" >&2
  exit 1
fi
if ! [ -f "$REPORT" ]; then
  echo "screenshot-report: $REPORT: no such file" >&2
  exit 1
fi
case "$SIZE" in
  *x*) W=${SIZE%x*} H=${SIZE#*x} ;;
  *) echo "screenshot-report: size must be WIDTHxHEIGHT, got '$SIZE'" >&2; exit 2 ;;
esac
ABS_REPORT=$(cd "$(dirname "$REPORT")" && pwd)/$(basename "$REPORT")
OUT_DIR=$(cd "$(dirname "$OUT")" && pwd)
ABS_OUT=$OUT_DIR/$(basename "$OUT")
PROFILE=$(mktemp -d)
TMP_OUT=$(mktemp "$OUT_DIR/.screenshot-XXXXXX.png")
trap 'rm -rf "$PROFILE"; rm -f "$TMP_OUT"' EXIT
# Chromium prints harmless D-Bus / sandbox chatter on stderr; keep it for a failure message only.
if ! "$CHROMIUM" --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking \
  --disable-component-update --disable-sync --hide-scrollbars --user-data-dir="$PROFILE" \
  --window-size="$W,$H" --screenshot="$TMP_OUT" "file://$ABS_REPORT" >"$PROFILE.log" 2>&1; then
  echo "screenshot-report: chromium failed on $REPORT:" >&2
  tail -20 "$PROFILE.log" >&2
  rm -f "$PROFILE.log"
  exit 1
fi
rm -f "$PROFILE.log"
if ! [ -s "$TMP_OUT" ]; then
  echo "screenshot-report: chromium wrote no screenshot for $REPORT" >&2
  exit 1
fi
chmod 644 "$TMP_OUT"
mv -f "$TMP_OUT" "$ABS_OUT"
echo "$ABS_OUT"
