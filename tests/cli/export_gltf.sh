#!/usr/bin/env bash
# `export gltf` as a user runs it: help with examples, a .glb and a .gltf (+ .bin) with the
# --json keys, the warnings on stderr and in the file, and errors (exit 2, nothing written).
# The numbers themselves (round trip, textures) are tested in tests/test_gltf_export.cpp and
# python/tests/test_gltf_export.py; the Khronos validator runs in tests/gltf/run.sh.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN export gltf --help | grep -q "Examples:" || fail "help without examples"
$BIN export gltf --model ggx --alpha-x 0.1 --alpha-y 0.3 --phi 30deg --metal Al -o "$T/a.glb" \
  --json >"$T/a.json" 2>"$T/a.err" || fail "export .glb: $(cat "$T/a.err")"
grep -q "warning: Fresnel: glTF's metals use Schlick" "$T/a.err" || fail "no Fresnel warning"
/usr/bin/python3 - "$T/a.json" "$T/a.glb" <<'PY' || fail "JSON summary"
import json, math, struct, sys
j = json.load(open(sys.argv[1]))
for k in ("output", "files", "source", "ggx", "base_color_linear_srgb", "roughness",
          "anisotropy_strength", "anisotropy_rotation_rad", "warnings"):
    assert k in j, k
assert j["files"] == ["a.glb"]
assert abs(j["roughness"] - math.sqrt(0.1)) < 1e-12
# alpha_y is the wider axis: the direction is phi + 90 deg, folded into (-90, 90] deg.
assert abs(j["anisotropy_rotation_rad"] - math.radians(-60)) < 1e-12
data = open(sys.argv[2], "rb").read()
jlen = struct.unpack_from("<I", data, 12)[0]
doc = json.loads(data[20:20 + jlen])
assert doc["extras"]["microbrdf"]["warnings"] == j["warnings"]
assert doc["extensionsUsed"] == ["KHR_materials_anisotropy"]
assert [s["name"] for s in doc["scenes"]] == ["sphere", "plate"]
PY
$BIN export gltf --model beckmann --alpha 0.2 --metal Cu -o "$T/b.gltf" >"$T/b.out" 2>"$T/b.err" \
  || fail "export .gltf: $(cat "$T/b.err")"
[ -s "$T/b.gltf" ] && [ -s "$T/b.bin" ] || fail ".gltf without its .bin"
grep -q "Hellinger" "$T/b.err" || fail "the Beckmann fit is not said"
grep -q "roughness" "$T/b.out" || fail "no summary line"

# Errors: usage (exit 2), nothing written.
expect() {  # expect CODE MESSAGE ARGS...
  local code=$1 msg=$2
  shift 2
  $BIN export gltf "$@" >/dev/null 2>"$T/e.err"
  local rc=$?
  [ $rc -eq "$code" ] || fail "exit $rc, not $code, for $*: $(cat "$T/e.err")"
  grep -q -- "$msg" "$T/e.err" || fail "message '$msg' missing for $*: $(cat "$T/e.err")"
}
expect 2 "error: -o" --model ggx --alpha 0.2 --metal Al -o "$T/x.obj"
expect 2 "no glTF metal equivalent" --lambertian 0.5 -o "$T/l.glb"
expect 2 "give a BRDF" -o "$T/n.glb"
expect 2 "uv-scale" --model ggx --alpha 0.2 --metal Al --uv-scale 0 -o "$T/u.glb"
expect 2 "give one material" --model ggx --alpha 0.2 --metal Al --n 1 --k 2 -o "$T/m.glb"
ls "$T" | grep -E "^(x|l|n|u|m)\." && fail "an error left a file"
exit 0
