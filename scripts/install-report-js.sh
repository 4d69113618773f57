#!/usr/bin/env bash
# Installs what the report's glTF view is built from: three.js from the npm registry (package
# three, the version pinned in report-js/package.json and package-lock.json), into
# report-js/node_modules (ignored by git). cmake embeds its files into the report at configure
# time (cmake/embed_report_js.cmake; re-run cmake after installing); the build never runs npm and
# without them the report leaves the glTF view out, saying why. Idempotent: returns at once when
# it is already installed.
#
#   scripts/install-report-js.sh
set -euo pipefail
DIR=$(cd "$(dirname "$0")/../report-js" && pwd)
if [ -f "$DIR/node_modules/three/package.json" ]; then
  exit 0
fi
command -v npm >/dev/null || {
  echo "install-report-js: npm not found (apt-get install nodejs npm)" >&2
  exit 1
}
cd "$DIR"
npm ci --no-audit --no-fund --ignore-scripts
