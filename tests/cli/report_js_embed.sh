#!/usr/bin/env bash
# cmake/embed_report_js.cmake, which puts three.js into the report's glTF view: with the five
# modules present it embeds each one unchanged; with one missing, or with a module that imports
# something not embedded, it embeds nothing and gives the reason the report then shows (fake
# packages built here; the real one is checked by the browser test).
set -u
BIN=$1
HERE=$(cd "$(dirname "$0")" && pwd)
SCRIPT=$HERE/../../cmake/embed_report_js.cmake
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v cmake >/dev/null || { echo "SKIPPED: no cmake on PATH"; exit 77; }
: "$BIN"

fake() {  # fake three package in $1; $2: what GLTFLoader.js imports
  mkdir -p "$1/build" "$1/examples/jsm/loaders" "$1/examples/jsm/utils"
  printf '{"name": "three", "version": "9.8.7"}\n' >"$1/package.json"
  printf 'export const REVISION = "x"; // core;body\n' >"$1/build/three.core.js"
  printf "import { REVISION } from './three.core.js';\nexport { REVISION };\n" >"$1/build/three.module.js"
  printf "import {\n  REVISION\n} from 'three';\nexport const b = 1;\n" >"$1/examples/jsm/utils/BufferGeometryUtils.js"
  printf "import { REVISION } from 'three';\nexport const s = 2;\n" >"$1/examples/jsm/utils/SkeletonUtils.js"
  printf "/* @three_import import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js'; */\nimport {\n  REVISION\n} from '%s';\nimport { b } from '../utils/BufferGeometryUtils.js';\nexport class GLTFLoader {}\n" \
    "$2" >"$1/examples/jsm/loaders/GLTFLoader.js"
}
run() { cmake -DTHREE_DIR="$1" -DOUTPUT="$2" -P "$SCRIPT" || fail "cmake -P failed on $1"; }

# Complete: every module embedded, byte for byte, with the version; an import named in a comment
# is not an import.
fake "$T/ok" three
run "$T/ok" "$T/ok.cpp"
grep -q 'e.version = "9.8.7";' "$T/ok.cpp" || fail "version not embedded"
[ "$(grep -c 'e.modules.push_back' "$T/ok.cpp")" = 5 ] || fail "not 5 modules: $(grep -c 'e.modules.push_back' "$T/ok.cpp")"
grep -q 'e.missing' "$T/ok.cpp" && fail "complete package reported missing: $(grep e.missing "$T/ok.cpp")"
grep -qF 'R"mbjs(export const REVISION = "x"; // core;body' "$T/ok.cpp" || fail "three.core.js not verbatim"
grep -qF "from '../utils/BufferGeometryUtils.js';" "$T/ok.cpp" || fail "GLTFLoader.js not verbatim"

# A module missing: nothing embedded, the reason names it and the install script.
rm "$T/ok/examples/jsm/utils/SkeletonUtils.js"
run "$T/ok" "$T/missing.cpp"
grep -q 'e.modules.push_back' "$T/missing.cpp" && fail "modules embedded although one is missing"
grep -q 'e.missing = ".*SkeletonUtils.js; scripts/install-report-js.sh' "$T/missing.cpp" ||
  fail "no reason for the missing module: $(grep e.missing "$T/missing.cpp")"

# An import the page cannot satisfy: nothing embedded, the reason names it.
fake "$T/odd" "three/addons/foo.js"
run "$T/odd" "$T/odd.cpp"
grep -q 'e.modules.push_back' "$T/odd.cpp" && fail "modules embedded although an import is unknown"
grep -q "imports 'three/addons/foo.js'" "$T/odd.cpp" || fail "unknown import not named: $(grep e.missing "$T/odd.cpp")"

# Compiles as the build compiles it (the header beside the generated source).
for f in ok missing odd; do
  c++ -std=c++20 -Wall -Wextra -Werror -fsyntax-only -I "$HERE/../../src" "$T/$f.cpp" ||
    fail "$f.cpp does not compile"
done
echo "report_js_embed: all checks hold"
