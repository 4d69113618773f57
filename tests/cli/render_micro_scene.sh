#!/usr/bin/env bash
# `microbrdf render --micro-scene`: a `simulate` scene drawn as geometry on the plate, the .npy
# output, and the refusals (other scenes, BRDF flags, dielectrics, missing files).
set -u
BIN=$1 DATA=$3
SCENES="$DATA/../examples/scenes"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN render --help | grep -q -- "--micro-scene" || fail "--help does not list --micro-scene"
$BIN render --scene plate --micro-scene "$SCENES/cylinders.json" --micro-tiles 3 --size 16 --spp 2 \
  --threads 2 --quiet --json -o "$T/c.png" -o "$T/c.npy" >"$T/j" 2>"$T/err" || fail "render: $(cat "$T/err")"
grep -q "micro-scene parallel-cylinders, 3 tiles across" "$T/j" || fail "settings do not name the micro-scene"
# The .npy holds the linear image: shape (height, width, 3), its mean the JSON's.
/usr/bin/python3 - "$T/c.npy" "$T/j" <<'PY' || fail ".npy output"
import json, sys
import numpy as np
img = np.load(sys.argv[1])
assert img.shape == (16, 16, 3) and img.dtype == np.float64, img.shape
want = json.load(open(sys.argv[2]))["mean_linear_srgb"]
got = img.reshape(-1, 3).mean(axis=0)
assert np.allclose(got, want, rtol=1e-9, atol=0), (got, want)
assert img.max() > 0
PY
# An image one pixel high stays 3-D: (1, width, 3).
$BIN render --scene plate --model ggx --alpha 0.3 --metal Al --width 8 --height 1 --spp 1 --quiet \
  -o "$T/row.npy" 2>"$T/err" || fail "render one row: $(cat "$T/err")"
/usr/bin/python3 -c "import numpy as np, sys; a = np.load(sys.argv[1]); assert a.shape == (1, 8, 3), a.shape" \
  "$T/row.npy" || fail "one-row .npy is not (1, 8, 3)"

expect() {  # expect CODE TEXT -- ARGS...: exit code CODE, stderr mentions TEXT, no output file
  local code=$1 text=$2; shift 3
  rm -f "$T/x.png"
  $BIN render --size 8 --spp 1 --quiet -o "$T/x.png" "$@" 2>"$T/err" >/dev/null
  local rc=$?
  [ $rc -eq "$code" ] || fail "$* : exit $rc, want $code ($(cat "$T/err"))"
  grep -q -- "$text" "$T/err" || fail "$* : error does not mention '$text': $(cat "$T/err")"
  grep -q "^microbrdf render: error: " "$T/err" || fail "$* : error not in the usual form"
  [ ! -e "$T/x.png" ] || fail "$* : a refused render wrote its output"
}
expect 2 "--scene plate" -- --scene sphere --micro-scene "$SCENES/cylinders.json"
expect 2 "leave out the BRDF" -- --scene plate --micro-scene "$SCENES/cylinders.json" --metal Cu
expect 2 "leave out the BRDF" -- --scene plate --micro-scene "$SCENES/cylinders.json" --lambertian 1
expect 2 "nothing.json" -- --scene plate --micro-scene "$T/nothing.json"
expect 2 "--micro-tiles" -- --scene plate --micro-scene "$SCENES/cylinders.json" --micro-tiles 0
expect 2 "only with --micro-scene" -- --scene plate --model ggx --alpha 0.2 --metal Al --micro-tiles 4
expect 2 "rotational" -- --scene plate --micro-scene "$SCENES/cylinders.json" --brushing rotational
expect 2 "fibre" -- --scene plate --micro-scene "$SCENES/velvet.json"
echo '{"materials": {"a": {"type": "lambert"}}, "objects": []}' >"$T/bad.json"
expect 1 "bad.json" -- --scene plate --micro-scene "$T/bad.json"
echo "render_micro_scene: ok"
