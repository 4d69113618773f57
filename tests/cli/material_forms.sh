#!/usr/bin/env bash
# Every material form of the one vocabulary (--metal, --n/--k, --nk-csv, --r0, --color; exact or
# Schlick Fresnel) in every command that takes a material: brdf slice, brdf color, brdf
# sh-project, render, sun slice, predict and the scene JSON of simulate. Each form must give the
# reflectance it names: the normal-incidence albedo of a wide GGX lobe is the material's R0 times
# the lobe's own albedo (< 1 through Smith masking), so the forms are compared with each other.
set -u
BIN=$1
DATA=$(cd "$(dirname "$0")/../../data/optical" && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

FORMS=("--metal Cu" "--n 0.27 --k 3.41" "--nk-csv $DATA/Au_JohnsonChristy1972.csv" "--r0 0.9"
       "--color #e6c27a" "--metal Cu --fresnel schlick" "--r0 0.9 --fresnel schlick")

# brdf slice: each form runs; the directional albedo at normal incidence follows R0.
i=0
for f in "${FORMS[@]}"; do
  # shellcheck disable=SC2086
  $BIN brdf slice --model ggx --alpha 0.3 $f --theta-i 0deg --samples 91 -o "$T/s$i.csv" --json \
    >"$T/s$i.json" 2>"$T/err" || fail "brdf slice $f: $(cat "$T/err")"
  a=$(json "$T/s$i.json" 'd["directional_albedo"]')
  python3 -c "import sys; a=float(sys.argv[1]); assert 0.05 < a < 1, a" "$a" || fail "brdf slice $f: albedo $a"
  i=$((i + 1))
done
# R0 = 0.9 (exact) and R0 = 0.9 with Schlick agree at normal incidence (both are R0 there).
python3 - "$T/s3.json" "$T/s6.json" <<'PY' || fail "r0 exact vs schlick at normal incidence"
import json, sys
a, b = (json.load(open(p))["directional_albedo"] for p in sys.argv[1:3])
assert abs(a / b - 1) < 0.02, (a, b)
PY

# brdf color: each form gives a colour; --color gives back about the colour asked for.
for f in "${FORMS[@]:0:5}"; do
  # shellcheck disable=SC2086
  $BIN brdf color $f --json >"$T/c.json" 2>"$T/err" || fail "brdf color $f: $(cat "$T/err")"
done
$BIN brdf color --color '#e6c27a' --json >"$T/c.json" || fail "brdf color --color"
python3 - "$T/c.json" <<'PY' || fail "colour round trip"
import json, sys
c = json.load(open(sys.argv[1]))["srgb8"]
assert all(abs(x - y) <= 6 for x, y in zip(c, [0xe6, 0xc2, 0x7a])), c
PY

# brdf sh-project and sun slice with every form.
for f in "${FORMS[@]}"; do
  # shellcheck disable=SC2086
  $BIN brdf sh-project --model ggx --alpha 0.4 $f --lmax 4 -o "$T/p.shbrdf" >/dev/null 2>"$T/err" \
    || fail "brdf sh-project $f: $(cat "$T/err")"
  # shellcheck disable=SC2086
  $BIN sun slice --s 2 --theta-i 30deg $f --theta-step 5deg -o "$T/sun.csv" --json >"$T/sun.json" \
    2>"$T/err" || fail "sun slice $f: $(cat "$T/err")"
done
# sun slice without a material is R = 1, above any metal.
$BIN sun slice --s 2 --theta-i 30deg --theta-step 5deg --json >"$T/sun1.json" || fail "sun slice R=1"
python3 - "$T/sun1.json" "$T/sun.json" <<'PY' || fail "sun slice R = 1 vs a material"
import json, sys
one, m = (json.load(open(p)) for p in sys.argv[1:3])
assert one["fresnel"] == "R = 1" and m["albedo_standard"] < one["albedo_standard"]
PY

# render: every form on a small sphere under the uniform sky; brighter for higher R0.
i=0
for f in "${FORMS[@]}"; do
  # shellcheck disable=SC2086
  $BIN render --scene sphere --model ggx --alpha 0.3 $f --size 12 --spp 2 -o "$T/r$i.png" \
    --json --quiet >"$T/r$i.json" 2>"$T/err" || fail "render $f: $(cat "$T/err")"
  i=$((i + 1))
done
python3 - "$T/r3.json" "$T/r0.json" <<'PY' || fail "render: R0 0.9 not brighter than Cu in blue"
import json, sys
a, b = (json.load(open(p))["mean_linear_srgb"] for p in sys.argv[1:3])
assert a[2] > b[2], (a, b)
PY

# predict: every form (a tiny scan, no renders); the summary records the material.
$BIN generate gaussian --nx 64 --ny 64 --spacing 0.25um --sigma 0.05um --tau 3um --seed 3 \
  -o "$T/g.x3p" 2>/dev/null || fail generate
i=0
for f in "${FORMS[@]}"; do
  # shellcheck disable=SC2086
  $BIN predict "$T/g.x3p" --level none --resolution 65 --theta-i 30 --no-render $f \
    -o "$T/p$i" --quiet >/dev/null 2>"$T/err" || fail "predict $f: $(cat "$T/err")"
  [ -s "$T/p$i/summary.json" ] || fail "predict $f: no summary"
  i=$((i + 1))
done
[ "$(json "$T/p0/summary.json" 'd["settings"]["metal"]')" = "Cu" ] || fail "predict: metal not recorded"
grep -q "Schlick" "$T/p5/summary.json" || fail "predict --fresnel schlick not used"

# simulate: the scene JSON takes the same keys.
for m in '"metal": "Al"' '"n": 1.2, "k": 7' "\"nk_csv\": \"$DATA/Al_Rakic1995.csv\"" '"r0": 0.8' \
         '"color": "#e6c27a", "fresnel": "schlick"'; do
  cat >"$T/scene.json" <<JSON
{"name": "plane", "wavelength": "550nm", "tile": "100x100um",
 "materials": {"m": {"type": "microfacet", "model": "ggx", "alpha": 0.3, $m}},
 "objects": [{"type": "plane", "z": "0um", "material": "m"}]}
JSON
  $BIN simulate "$T/scene.json" --lmax 4 --rays 4000 --seed 1 -o "$T/sim.shbrdf" -q --json \
    >"$T/sim.json" 2>"$T/err" || fail "simulate with $m: $(cat "$T/err")"
done
# The former "fresnel": "Al" form is refused with a message naming the keys.
sed -i 's/"color": "#e6c27a", "fresnel": "schlick"/"fresnel": "Al"/' "$T/scene.json"
$BIN simulate "$T/scene.json" --lmax 4 --rays 4000 -o "$T/x.shbrdf" -q 2>"$T/err" \
  && fail "fresnel: Al accepted"
grep -q '"metal"' "$T/err" || fail "scene error does not name the material keys: $(cat "$T/err")"

# Two forms at once, a form without its partner, a bad colour: exit 2, the flag named.
$BIN brdf color --metal Au --r0 0.5 2>"$T/err"; [ $? -eq 2 ] || fail "two forms not exit 2"
grep -q -- "--metal" "$T/err" && grep -q -- "--r0" "$T/err" || fail "two forms: flags not named"
$BIN brdf color --n 1.2 2>"$T/err"; [ $? -eq 2 ] || fail "--n alone not exit 2"
grep -q -- "--k" "$T/err" || fail "--n alone: --k not named"
$BIN render --scene sphere --model ggx --alpha 0.2 --color 'x,y' -o "$T/x.png" 2>"$T/err"
[ $? -eq 2 ] || fail "bad colour not exit 2"
grep -q -- "--color" "$T/err" || fail "bad colour: flag not named"
echo "material forms: ok"
