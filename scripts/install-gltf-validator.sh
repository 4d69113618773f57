#!/usr/bin/env bash
# Installs what the glTF test (tests/gltf/run.sh) validates the exported files with: the Khronos
# glTF-Validator from the npm registry (package gltf-validator), the version pinned in
# tests/gltf/package.json and package-lock.json, into tests/gltf/node_modules (ignored by git).
# Idempotent: returns at once when it is already installed.
#
#   scripts/install-gltf-validator.sh
exec "$(dirname "$0")/install-npm-pinned.sh" tests/gltf gltf-validator
