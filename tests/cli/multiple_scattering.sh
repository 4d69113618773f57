#!/usr/bin/env bash
# --multiple-scattering as a user runs it: brdf slice with and without it, a tabulated NDF,
# repeatability, and the usage errors (exit 2, one line naming the flag).
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# White surface (n = 1, k = 1e3: F within 4e-6 of 1): single scattering loses energy at alpha
# 0.8 that multiple scattering gives back.
for ms in "" "--multiple-scattering --ms-walks 256"; do
  # shellcheck disable=SC2086
  $BIN brdf slice --model beckmann --alpha 0.8 --n 1 --k 1000 --theta-i 45 $ms \
    -o "$T/s${ms:+ms}.csv" --json >"$T/s${ms:+ms}.json" || fail "slice $ms"
done
python3 - "$T/s.json" "$T/sms.json" <<'PY' || fail "albedo single vs multiple"
import json, sys
a = json.load(open(sys.argv[1]))["directional_albedo"]
b = json.load(open(sys.argv[2]))["directional_albedo"]
# Beckmann alpha 0.8 at 45 deg: single scattering keeps ~0.75, the walk brings it to ~1.
assert a < 0.85, a
assert 0.97 < b < 1.03, b
PY
grep -q "multiple scattering" "$T/sms.json" || fail "the model line names multiple scattering"

# The same command twice gives the same numbers (seeded from the arguments, not the clock).
$BIN brdf slice --model beckmann --alpha 0.8 --n 1 --k 1000 --theta-i 45 --multiple-scattering \
  --ms-walks 256 -o "$T/again.csv" >/dev/null || fail "slice again"
cmp -s "$T/sms.csv" "$T/again.csv" || fail "not repeatable"

# A tabulated NDF takes it too.
$BIN tabulate --model ggx --alpha 0.5 --resolution 129 -o "$T/t.npy" >/dev/null 2>&1 || fail tabulate
$BIN brdf slice --ndf "$T/t.npy" --metal Cu --theta-i 30 --multiple-scattering --ms-walks 16 \
  -o "$T/t.csv" >/dev/null || fail "slice --ndf"

# Export: the .bsdf table holds the multiple-scattering BRDF; glTF's GGX cannot and says so.
$BIN export bsdf --model ggx --alpha 0.5 --metal Cu --multiple-scattering --ms-walks 2 \
  --theta-i 4 --ndf-grid 8 --samples 4 --wavelengths 2 -o "$T/m.bsdf" >/dev/null 2>&1 || fail "export bsdf"
[ -s "$T/m.bsdf" ] || fail "no .bsdf"
$BIN export gltf --model ggx --alpha 0.5 --metal Cu --multiple-scattering -o "$T/m.gltf" \
  2>"$T/gltf.err" >/dev/null || fail "export gltf"
grep -q "warning: multiple scattering" "$T/gltf.err" || fail "glTF says nothing of multiple scattering"

# Usage errors: exit 2 with the flag named.
expect2() {
  local what=$1; shift
  "$BIN" "$@" 2>"$T/err" >/dev/null; local rc=$?
  [ $rc -eq 2 ] || fail "$what: exit $rc"
  grep -q -- "$what" "$T/err" || fail "$what not named: $(cat "$T/err")"
}
expect2 --multiple-scattering brdf slice --sun 3 --metal Cu --multiple-scattering -o "$T/x.csv"
expect2 --ms-walks brdf slice --model ggx --alpha 0.3 --metal Cu --ms-walks 8 -o "$T/x.csv"
expect2 --separable-g brdf slice --model ggx --alpha 0.3 --metal Cu --multiple-scattering \
  --separable-g -o "$T/x.csv"
[ ! -e "$T/x.csv" ] || fail "output written after a usage error"
echo OK
