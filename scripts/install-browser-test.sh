#!/usr/bin/env bash
# Installs what the browser test (tests/browser/run.sh) drives Chromium with: puppeteer-core from
# the npm registry, the version pinned in tests/browser/package.json and package-lock.json, into
# tests/browser/node_modules (ignored by git). puppeteer-core never downloads a browser; the test
# uses Debian's /usr/bin/chromium. Idempotent: returns at once when it is already installed.
#
#   scripts/install-browser-test.sh
set -euo pipefail
DIR=$(cd "$(dirname "$0")/../tests/browser" && pwd)
if [ -f "$DIR/node_modules/puppeteer-core/package.json" ]; then
  exit 0
fi
command -v npm >/dev/null || {
  echo "install-browser-test: npm not found (scripts/install-deps.sh --report installs it)" >&2
  exit 1
}
cd "$DIR"
npm ci --no-audit --no-fund --ignore-scripts
