#!/usr/bin/env bash
# `microbrdf simulate` as a user runs it: a JSON micro-scene to a .shbrdf (JSON summary keys,
# energy of a white Lambertian plane, determinism for a seed), the direct in-plane mode (CSV,
# plot), and clear errors (missing scene, bad JSON, unknown material, --rays with --time) with a
# non-zero exit and no output file.
set -u
BIN=$1
DATA=$2
SCENES="$DATA/../../examples/scenes"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN simulate --help | grep -q "Example" || fail "help lacks examples"
$BIN simulate "$SCENES/lambert_plane.json" --lmax 6 --rays 40000 --seed 3 -o "$T/a.shbrdf" \
  --json >"$T/a.json" 2>"$T/a.err" || fail "simulate lambert"
grep -q "Q =" "$T/a.err" || fail "no progress with Q on stderr"
head -c 8 "$T/a.shbrdf" | grep -q MBSHBRDF || fail "no MBSHBRDF magic"
$BIN simulate "$SCENES/lambert_plane.json" --lmax 6 --rays 40000 --seed 3 -o "$T/b.shbrdf" -q \
  || fail "second run"
python3 - "$T" <<'PY' || fail "same seed, different matrix"
import struct, sys
T = sys.argv[1]
def matrix(p):
    b = open(p, "rb").read()
    n = struct.unpack("<I", b[8:12])[0]
    return b[12 + n:]
assert matrix(f"{T}/a.shbrdf") == matrix(f"{T}/b.shbrdf")
PY
$BIN brdf info --sh "$T/a.shbrdf" --json >"$T/info.json" || fail "brdf info --sh"
python3 - "$T" <<'PY' || fail "summary"
import json, sys
T = sys.argv[1]
j = json.load(open(f"{T}/a.json"))
for k in ("output", "lmax", "size", "q", "incident_rays", "exit_rays", "exit_rays_per_second",
          "mean_exit_energy", "energy_depth_capped", "seconds", "threads"):
    assert k in j, k
assert j["lmax"] == 6 and j["size"] == 21, j
assert abs(j["mean_exit_energy"] - 1) < 1e-12, j
assert abs(j["albedo_normal"] - 1) < 0.03, j
assert j["incident_rays"] == 40000, j
info = json.load(open(f"{T}/info.json"))
assert info["lmax"] == 6, info
PY

# Direct in-plane mode on a small Gaussian mirror surface with the He / Smith references.
cat >"$T/g.json" <<'J'
{"materials": {"m": {"type": "mirror"}},
 "objects": [{"type": "heightfield", "material": "m",
   "generate": {"kind": "gaussian", "nx": 64, "ny": 64, "spacing": "8um", "sigma": "10um",
                "tau": "65um", "seed": 2}}]}
J
$BIN simulate "$T/g.json" --in-plane 0,45 --gonio-rays 20000 --he-sigma 10um --he-tau 65um \
  --single-scatter --csv "$T/g.csv" --plot "$T/g.png" -q || fail "in-plane"
[ -s "$T/g.png" ] || fail "no plot"
head -1 "$T/g.csv" | grep -q "theta_i_deg,theta_r_deg,simulated" || fail "csv header"

# Errors: non-zero exit, message naming the problem, no output.
$BIN simulate "$T/nope.json" -o "$T/x.shbrdf" 2>"$T/e1" && fail "missing scene accepted"
grep -q "nope.json" "$T/e1" || fail "missing scene not named"
echo '{"materials": ' >"$T/bad.json"
$BIN simulate "$T/bad.json" -o "$T/x.shbrdf" 2>"$T/e2" && fail "bad JSON accepted"
grep -q "bad.json" "$T/e2" || fail "bad JSON not named"
cat >"$T/um.json" <<'J'
{"tile": "10x10um", "materials": {"a": {"type": "lambert"}},
 "objects": [{"type": "plane", "z": "0um", "material": "b"}]}
J
$BIN simulate "$T/um.json" -o "$T/x.shbrdf" 2>"$T/e3" && fail "unknown material accepted"
grep -q "unknown material 'b'" "$T/e3" || fail "unknown material message"
$BIN simulate "$SCENES/lambert_plane.json" --rays 10 --time 1s -o "$T/x.shbrdf" 2>/dev/null \
  && fail "--rays with --time accepted"
[ -e "$T/x.shbrdf" ] && fail "output written on error"
echo ok
