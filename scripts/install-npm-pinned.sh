#!/usr/bin/env bash
# Installs a folder's pinned npm packages (its package.json and package-lock.json) into
# FOLDER/node_modules (ignored by git), with `npm ci` and no install scripts. Idempotent: returns
# at once when PACKAGE is already there. Shared by the browser test (puppeteer-core), the glTF
# test (gltf-validator) and the report's glTF view (three).
#
#   scripts/install-npm-pinned.sh FOLDER PACKAGE     (FOLDER relative to the repository root)
set -euo pipefail
DIR=$(cd "$(dirname "$0")/../$1" && pwd)
[ -f "$DIR/node_modules/$2/package.json" ] && exit 0
command -v npm >/dev/null || {
  echo "install-npm-pinned: npm not found for $1 (apt-get install nodejs npm)" >&2
  exit 1
}
cd "$DIR"
npm ci --no-audit --no-fund --ignore-scripts
