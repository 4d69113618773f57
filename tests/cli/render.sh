#!/usr/bin/env bash
# `microbrdf render` as a user meets it: help, JSON, outputs, determinism, errors.
set -u
BIN=$1 DATA=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
ENV="$DATA/envmaps/blender_studio.hdr"

$BIN render --help >"$T/help" 2>&1 || fail "--help exits non-zero"
grep -q "Examples" "$T/help" || fail "--help has no examples"

# A small render to PNG and EXR, with JSON on stdout and progress on stderr.
$BIN render --scene sphere --model ggx --alpha 0.2 --metal Cu --envmap "$ENV" --size 24 --spp 4 \
  --threads 2 -o "$T/a.png" -o "$T/a.exr" --json >"$T/j" 2>"$T/err" || fail "render: $(cat "$T/err")"
for k in '"seconds"' '"samples_per_second"' '"rays"' '"mean_linear_srgb"' '"settings"'; do
  grep -q "$k" "$T/j" || fail "JSON lacks $k"
done
grep -q "100%" "$T/err" || fail "no progress on stderr"
head -c 4 "$T/a.png" | od -c | grep -q "P   N   G" || fail "a.png is not a PNG"
[ "$(head -c 4 "$T/a.exr" | od -An -tx1 | tr -d ' ')" = "762f3101" ] || fail "a.exr is not an EXR"

# Same seed, other thread count: the same bytes.
$BIN render --scene sphere --model ggx --alpha 0.2 --metal Cu --envmap "$ENV" --size 24 --spp 4 \
  --threads 1 -o "$T/b.png" --quiet >/dev/null || fail "second render"
cmp -s "$T/a.png" "$T/b.png" || fail "image depends on the thread count"

# The direct-light estimators: resampling (the default) and MIS, reported in the JSON; bad
# candidate counts name their flag and exit 2.
grep -q '"direct": "ris"' "$T/j" || fail "JSON lacks \"direct\": \"ris\" (the default)"
$BIN render --scene sphere --model ggx --alpha 0.2 --metal Cu --envmap "$ENV" --size 16 --spp 2 \
  --direct mis -o "$T/m.png" --quiet --json >"$T/jm" 2>"$T/err" || fail "--direct mis: $(cat "$T/err")"
grep -q '"direct": "mis"' "$T/jm" || fail "JSON lacks \"direct\": \"mis\""
for bad in 4,x 0,1 4,0 17,1; do
  $BIN render --scene sphere --lambertian 1 --ris-candidates "$bad" -o "$T/x.png" 2>"$T/err"
  [ $? -eq 2 ] || fail "--ris-candidates $bad not exit 2"
  grep -q -- "--ris-candidates" "$T/err" || fail "--ris-candidates $bad: error does not name the flag"
done
$BIN render --scene sphere --lambertian 1 --direct nee -o "$T/x.png" 2>"$T/err"
[ $? -eq 2 ] && grep -q -- "--direct" "$T/err" || fail "--direct nee: not exit 2 naming the flag"
[ ! -e "$T/x.png" ] || fail "a refused render wrote its output"

# An OBJ mesh (a tetrahedron) under a point light and rotational brushing.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$T/t.obj"
$BIN render --scene obj --obj "$T/t.obj" --lambertian 0.8 --point 2,2,4:30 --brushing rotational \
  --size 16 --spp 2 -o "$T/t.png" --quiet >/dev/null 2>"$T/err" || fail "obj: $(cat "$T/err")"

# A Kirchhoff BRDF from a D_K table of a small generated surface.
$BIN generate gaussian --nx 128 --ny 128 --spacing 0.1um --sigma 0.03um --tau 1um -o "$T/g.x3p" >/dev/null 2>&1 || fail "generate"
$BIN ndf "$T/g.x3p" --method kirchhoff --wavelength 555nm --resolution 129 -o "$T/dk.npy" >/dev/null 2>&1 || fail "ndf kirchhoff"
$BIN render --scene sphere --kirchhoff "$T/dk.npy" --metal Au --size 16 --spp 2 -o "$T/k.png" --quiet >/dev/null 2>"$T/err" ||
  fail "kirchhoff: $(cat "$T/err")"

# Errors: usage problems (a missing input file included) exit 2, unreadable files exit 1,
# nothing is written.
$BIN render --scene teapot --lambertian 1 -o "$T/x.png" 2>"$T/err"; [ $? -eq 2 ] || fail "unknown scene not exit 2"
grep -q "known: cylinders" "$T/err" || fail "unknown scene message: $(cat "$T/err")"
$BIN render --scene sphere --lambertian 1 --envmap "$T/nope.hdr" -o "$T/x.png" 2>"$T/err"
[ $? -eq 2 ] || fail "missing env map not exit 2 (a usage error)"
grep -q "nope.hdr" "$T/err" || fail "missing env map message: $(cat "$T/err")"
head -c 300 "$ENV" >"$T/cut.hdr"
$BIN render --scene sphere --lambertian 1 --envmap "$T/cut.hdr" -o "$T/x.png" 2>"$T/err" && fail "truncated env map accepted"
grep -q "cut.hdr" "$T/err" || fail "truncated env map message: $(cat "$T/err")"
$BIN render --scene sphere --lambertian 1 --point 1,2:3 -o "$T/x.png" 2>"$T/err"; [ $? -eq 2 ] || fail "bad --point not exit 2"
$BIN render --scene sphere --lambertian 1 --mirror -o "$T/x.png" 2>"$T/err"; [ $? -eq 2 ] || fail "two materials not exit 2"
$BIN render --scene sphere --lambertian 1 -o "$T/x.jpg" 2>"$T/err"; [ $? -eq 2 ] || fail ".jpg not refused"
[ -e "$T/x.png" ] || [ -e "$T/x.jpg" ] && fail "output written despite an error"
echo ok
