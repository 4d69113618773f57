#!/usr/bin/env bash
# `measured ndf` and `measured compare` as a user runs them: a goniometer CSV of an anisotropic
# GGX lobe (written here by numpy, F = 1, G = 1) -> effective NDF -> `fit` recovers both widths;
# bad input is refused with the file named and no output left behind.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

/usr/bin/python3 "$(cd "$(dirname "$0")" && pwd)/make_goniometer.py" "$T/goni.csv" --alpha 0.12 0.3 --extra-column \
  || fail "python could not write the CSV"

$BIN measured ndf "$T/goni.csv" --resolution 513 -o "$T/eff.npy" --json >"$T/ndf.json" 2>"$T/err" \
  || fail "measured ndf: $(cat "$T/err")"
grep -q "G = 1" "$T/err" || fail "measured ndf does not say G = 1: $(cat "$T/err")"
$BIN fit "$T/eff.npy" --model ggx --json >"$T/fit.json" || fail "fit of the effective NDF"
/usr/bin/python3 - "$T/fit.json" "$T/ndf.json" "$T/eff.npy" <<'PY' || exit 1
import json, sys, numpy as np
p = json.load(open(sys.argv[1]))["params"]
n = json.load(open(sys.argv[2]))
d = np.load(sys.argv[3])
ax, ay = p["alpha_x"], p["alpha_y"]
print(f"measured ndf -> fit: alpha_x {ax:.4f} (true 0.12), alpha_y {ay:.4f} (true 0.30), "
      f"{n['measured_nodes']} measured nodes, {int(np.isnan(d).sum())} NaN")
assert abs(ax / 0.12 - 1) < 0.03 and abs(ay / 0.30 - 1) < 0.03, p
assert np.isnan(d).sum() > 0 and n["measured_nodes"] > 0
PY

# compare: the measured table against itself is perfect; --report writes the images.
$BIN measured compare "$T/eff.npy" "$T/eff.npy" --report "$T/cmp" --json >"$T/cmp.json" \
  || fail "measured compare"
for f in compare.json measured.png predicted.png slices.csv slices.png; do
  [ -s "$T/cmp/$f" ] || fail "compare report lacks $f"
done
/usr/bin/python3 -c "import json,sys; c=json.load(open('$T/cmp.json'))['comparisons'][0]; assert c['relative_l2'] < 1e-6, c" \
  || fail "self-comparison not exact"

# Bad input: the file is named, exit non-zero, no output.
printf 'theta_i_deg,phi_i_deg\n1,2\n' >"$T/bad.csv"
$BIN measured ndf "$T/bad.csv" -o "$T/bad.npy" 2>"$T/err" && fail "bad CSV accepted"
grep -q "bad.csv" "$T/err" || fail "message does not name the file: $(cat "$T/err")"
[ -e "$T/bad.npy" ] && fail "output written despite the error"
head -c 1000 /dev/zero >"$T/x.binary"
$BIN measured ndf "$T/x.binary" -o "$T/x.npy" 2>"$T/err" && fail "bad MERL accepted"
grep -q "x.binary" "$T/err" || fail "MERL message does not name the file: $(cat "$T/err")"
$BIN measured ndf "$T/goni.csv" --shadowing maybe -o "$T/y.npy" 2>"$T/err"
[ $? -eq 2 ] || fail "bad --shadowing is not a usage error"
echo OK
