#!/usr/bin/env bash
# Reflectance-model commands as a user runs them: tabulate -> NDF file with integral 1,
# `brdf slice` (analytic and --ndf) CSV sanity and reciprocity, plots, `brdf color`, `sun ftp
# --json`, and clear errors with a non-zero exit for bad inputs.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# --- tabulate: the .npy holds D with sum D Delta^2 = 1 (parsed without numpy), sidecar JSON.
$BIN tabulate --model beckmann --alpha 0.3 --resolution 257 -o "$T/b.npy" --json >"$T/tab.json" \
  || fail "tabulate"
[ -s "$T/b.json" ] || fail "no JSON sidecar"
python3 - "$T/b.npy" "$T/b.json" "$T/tab.json" <<'PY' || fail "tabulated NDF file"
import json, struct, sys, array, ast
raw = open(sys.argv[1], "rb").read()
assert raw[:6] == b"\x93NUMPY", "not an npy file"
hlen = struct.unpack("<H", raw[8:10])[0] if raw[6] == 1 else struct.unpack("<I", raw[8:12])[0]
off = 10 if raw[6] == 1 else 12
hdr = ast.literal_eval(raw[off:off + hlen].decode("latin1"))
assert hdr["descr"] == "<f8" and hdr["shape"] == (257, 257), hdr
a = array.array("d"); a.frombytes(raw[off + hlen:])
assert len(a) == 257 * 257
delta = 2.0 / 256
integral = sum(a) * delta * delta
assert abs(integral - 1) < 1e-12, integral
assert min(a) >= 0
side = json.load(open(sys.argv[2]))
assert side["resolution"] == 257 and side["method"] == "beckmann", side
summ = json.load(open(sys.argv[3]))
assert summ["resolution"] == 257 and abs(summ["peak"][2] - 1) < 1e-12, summ
PY

# --- brdf slice, analytic: positive values, peak at the mirror direction, reciprocity.
$BIN brdf slice --model ggx --alpha 0.2 --metal Cu --theta-i 30deg --samples 181 -o "$T/a30.csv" \
  --json >"$T/a30.json" || fail "brdf slice analytic"
$BIN brdf slice --model ggx --alpha 0.2 --metal Cu --theta-i 50deg --samples 181 -o "$T/a50.csv" \
  >/dev/null || fail "brdf slice analytic 50"
# --ndf with a plot (PNG and SVG) and an out-of-plane cut.
$BIN brdf slice --ndf "$T/b.npy" --metal Au --theta-i 30deg --samples 181 -o "$T/t30.csv" \
  --plot "$T/t30.png" --json >"$T/t30.json" || fail "brdf slice --ndf"
$BIN brdf slice --ndf "$T/b.npy" --metal Au --theta-i 50deg --samples 181 -o "$T/t50.csv" \
  --plot "$T/t50.svg" >/dev/null || fail "brdf slice --ndf 50"
$BIN brdf slice --ndf "$T/b.npy" --metal Au --theta-i 30deg --plane out --plot "$T/out.png" \
  --log-y >/dev/null || fail "brdf slice --ndf out-of-plane plot only"
$BIN brdf slice --model beckmann --alpha 0.3 --metal Au --theta-i 30deg --samples 181 \
  -o "$T/b30.csv" >/dev/null || fail "brdf slice analytic beckmann"
[ -s "$T/t30.png" ] && [ -s "$T/out.png" ] || fail "no PNG plot"
head -c 8 "$T/t30.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "plot is not a PNG"
grep -q "<svg" "$T/t50.svg" || fail "plot is not an SVG"
python3 - "$T" <<'PY' || fail "slice CSV sanity"
import csv, json, math, sys
T = sys.argv[1]
def load(name):
    rows = [r for r in open(f"{T}/{name}") if not r.startswith("#")]
    rd = csv.DictReader(rows)
    return {round(float(r["angle_deg"]), 6): float(r["brdf_per_sr"]) for r in rd}
for stem in ["a", "t"]:
    s30, s50 = load(f"{stem}30.csv"), load(f"{stem}50.csv")
    assert len(s30) == 181
    assert all(v >= 0 for v in s30.values()) and all(math.isfinite(v) for v in s30.values())
    assert all(v > 0 for a, v in s30.items() if abs(a) < 89), stem
    if stem == "a":  # GGX 0.2: the peak sits at the mirror direction
        peak = max(s30, key=s30.get)
        assert abs(peak - 30) <= 2.0, (stem, peak)
    # Reciprocity: light at 30 deg, view at +50 deg (far side) == light at 50, view at +30.
    f1, f2 = s30[50.0], s50[30.0]
    assert abs(f1 / f2 - 1) < 1e-6, (stem, f1, f2)
# The tabulated Beckmann (257^2) and the analytic one agree away from grazing.
t30, b30 = load("t30.csv"), load("b30.csv")
pk = max(b30.values())
# (Beckmann 0.3 at 30 deg peaks off-specular, beyond the mirror direction, in both.)
assert abs(max(t30, key=t30.get) - max(b30, key=b30.get)) <= 1.0
for a, v in b30.items():
    if abs(a) <= 70 and v > 0.01 * pk:
        assert abs(t30[a] / v - 1) < 0.05, (a, t30[a], v)
j = json.load(open(f"{T}/t30.json"))
assert j["ndf"].endswith("b.npy") and j["plot"].endswith("t30.png")
assert "tabulated NDF 257x257" in j["model"], j["model"]
assert 0 < j["directional_albedo"] < 1, j
PY

# --- brdf color --metal Au: yellowish (R > G > B clearly).
$BIN brdf color --metal Au --json >"$T/au.json" || fail "brdf color"
python3 - "$T/au.json" <<'PY' || fail "gold colour"
import json, sys
j = json.load(open(sys.argv[1]))
r, g, b = j["srgb8"]
assert r > g > b and r - b > 60 and g - b > 30, (r, g, b)
PY
$BIN brdf color --metal Au | grep -q "sRGB 8-bit" || fail "brdf color text"

# --- sun ftp --json.
$BIN sun ftp --s 1,5 --theta-step 15deg --json >"$T/ftp.json" || fail "sun ftp --json"
python3 - "$T/ftp.json" <<'PY' || fail "sun ftp JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["command"] == "sun ftp" and len(j["curves"]) == 2
for c in j["curves"]:
    pts = c["points"]
    assert len(pts) == 7, len(pts)
    first, last = pts[0], pts[-1]
    vals = [p["gamma0_sun"] if isinstance(p, dict) else p[2] for p in pts]
    assert abs(vals[0] - 1) < 1e-12 and abs(vals[-1]) < 1e-12, vals
    assert all(a >= b for a, b in zip(vals, vals[1:])), vals
PY
$BIN sun slice --s 3 --theta-i 40deg --n 0.2 --k 3 --theta-step 5deg --json >"$T/sun.json" \
  || fail "sun slice"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert 0 < j['albedo_standard'] < 1" \
  "$T/sun.json" || fail "sun slice JSON"

# --- bad inputs: clear message, non-zero exit, no output file.
expect_error() {  # expect_error "message fragment" command...
  local want=$1; shift
  "$@" >"$T/out" 2>"$T/err" && fail "succeeded: $*"
  grep -qi -- "$want" "$T/err" "$T/out" || fail "no '$want' in the message of: $* -> $(cat "$T/err")"
}
expect_error "no such file\|cannot\|not found\|open" \
  $BIN brdf slice --ndf "$T/missing.npy" --metal Au -o "$T/x.csv"
[ -e "$T/x.csv" ] && fail "partial output after an error"
expect_error "--ndf replaces" $BIN brdf slice --ndf "$T/b.npy" --alpha 0.1 --metal Au -o "$T/x.csv"
expect_error "give an output" $BIN brdf slice --model ggx --alpha 0.1 --metal Au
expect_error ".png or .svg" $BIN brdf slice --model ggx --alpha 0.1 --metal Au --plot "$T/p.gif"
expect_error "theta-i" $BIN brdf slice --model ggx --alpha 0.1 --metal Au --theta-i 95deg -o "$T/x.csv"
expect_error "alpha" $BIN brdf slice --model ggx --alpha -1 --metal Au -o "$T/x.csv"
expect_error "metal\|Au" $BIN brdf color --metal Unobtainium
expect_error "give one material" $BIN brdf color --metal Au --r0 0.5
expect_error "s must\|positive\|--s" $BIN sun ftp --s -1
expect_error "model" $BIN tabulate --model phong --alpha 0.1 -o "$T/p.npy"
printf 'not an npy' >"$T/bad.npy"
expect_error "npy\|format\|header\|magic" $BIN brdf slice --ndf "$T/bad.npy" --metal Au -o "$T/x.csv"
[ -e "$T/x.csv" ] && fail "partial output after an error"
echo ok
