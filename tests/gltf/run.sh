#!/usr/bin/env bash
# The Khronos glTF-Validator over what `microbrdf export gltf` writes (tests/gltf/validate.mjs):
# an isotropic and a rotated anisotropic GGX, an ellipsoid, a parameter texture (.glb and .gltf
# with its .bin and PNGs), and the same anisotropic GGX in every built-in metal. Fails on any
# error or warning.
#
#   tests/gltf/run.sh BIN      (ctest "gltf.validate", label cli, part of `make test`)
#
# Skipped (exit 77, reported as "Skipped"), saying why, when Node.js or the validator is missing:
# scripts/install-deps.sh installs the validator wherever npm is available
# (scripts/install-gltf-validator.sh). The test never downloads anything itself.
set -u
BIN=$1
case "$BIN" in /*) ;; *) BIN=$(pwd)/$BIN ;; esac
HERE=$(cd "$(dirname "$0")" && pwd)
skip() {
  echo "SKIPPED: glTF validation: $1"
  exit 77
}
command -v node >/dev/null || skip "no Node.js (apt-get install nodejs npm)"
[ -f "$HERE/node_modules/gltf-validator/package.json" ] ||
  skip "gltf-validator is not installed in tests/gltf/node_modules (scripts/install-gltf-validator.sh)"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
run() {  # run OUTPUT FLAGS...: one export, stderr kept for the message on failure
  local out=$1
  shift
  "$BIN" export gltf "$@" -o "$T/$out" >/dev/null 2>"$T/err" || fail "export $out: $(cat "$T/err")"
}
run iso.glb --model ggx --alpha 0.2 --metal Al
run aniso.glb --model ggx --alpha-x 0.05 --alpha-y 0.3 --phi 30deg --metal Cu
run aniso.gltf --model ggx --alpha-x 0.3 --alpha-y 0.05 --phi -70deg --metal Au
run ellipsoid.glb --model ellipsoid --alpha-x 0.1 --alpha-y 0.25 --theta-x 5deg --theta-z 20deg \
  --metal Ni
# A small parameter texture: texels fitted on a generated brushed scan, then synthesised.
"$BIN" generate brushed --preset stainless4 --nx 384 --ny 256 --seed 1 -o "$T/s.x3p" \
  >/dev/null 2>&1 || fail "generate"
"$BIN" texture "$T/s.x3p" --texel 7um -o "$T/ex.exr" --no-preview >/dev/null 2>&1 ||
  fail "texture fit"
"$BIN" texture "$T/ex.exr" --size 32 --seed 1 -o "$T/tex.exr" --no-preview >/dev/null 2>&1 ||
  fail "texture synthesis"
run texture.glb --texture "$T/tex.exr" --uv-scale 2 --metal SS-austenitic
run texture.gltf --texture "$T/tex.exr" --metal Fe
[ -s "$T/texture_anisotropy.png" ] && [ -s "$T/texture_roughness.png" ] && [ -s "$T/texture.bin" ] ||
  fail ".gltf without its .bin and PNGs"
# Every built-in metal: the names the tool lists when it is given an unknown one.
METALS=$("$BIN" brdf color --metal unobtainium 2>&1 | sed -n 's/.*known: *//p' | tr -d ',)')
[ "$(echo "$METALS" | wc -w)" -ge 12 ] || fail "could not list the metals: $METALS"
for m in $METALS; do
  run "metal_$m.glb" --model ggx --alpha-x 0.1 --alpha-y 0.2 --phi 45deg --metal "$m"
done
FILES=("$T"/*.glb "$T"/*.gltf)
cd "$HERE" && node validate.mjs "${FILES[@]}" || fail "glTF-Validator reported errors or warnings"
