#!/usr/bin/env bash
# Installs what the report's glTF view is built from: three.js from the npm registry (package
# three, the version pinned in report-js/package.json and package-lock.json), into
# report-js/node_modules (ignored by git). cmake embeds its files into the report at configure
# time (cmake/embed_report_js.cmake; re-run cmake after installing); the build never runs npm and
# without them the report leaves the glTF view out, saying why. Idempotent: returns at once when
# it is already installed.
#
#   scripts/install-report-js.sh
exec "$(dirname "$0")/install-npm-pinned.sh" report-js three
