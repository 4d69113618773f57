#!/usr/bin/env bash
# Installs what the browser test (tests/browser/run.sh) drives Chromium with: puppeteer-core from
# the npm registry, the version pinned in tests/browser/package.json and package-lock.json, into
# tests/browser/node_modules (ignored by git). puppeteer-core never downloads a browser; the test
# uses Debian's /usr/bin/chromium. Idempotent: returns at once when it is already installed.
#
#   scripts/install-browser-test.sh
exec "$(dirname "$0")/install-npm-pinned.sh" tests/browser puppeteer-core
