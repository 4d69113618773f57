#!/usr/bin/env bash
# Installs what the glTF test (tests/gltf/run.sh) validates the exported files with: the Khronos
# glTF-Validator from the npm registry (package gltf-validator), the version pinned in
# tests/gltf/package.json and package-lock.json, into tests/gltf/node_modules (ignored by git).
# Idempotent: returns at once when it is already installed.
#
#   scripts/install-gltf-validator.sh
set -euo pipefail
DIR=$(cd "$(dirname "$0")/../tests/gltf" && pwd)
if [ -f "$DIR/node_modules/gltf-validator/package.json" ]; then
  exit 0
fi
command -v npm >/dev/null || {
  echo "install-gltf-validator: npm not found (apt-get install nodejs npm)" >&2
  exit 1
}
cd "$DIR"
npm ci --no-audit --no-fund --ignore-scripts
