#!/usr/bin/env bash
# Wave optics by default on polished metal: `ndf --method kirchhoff` then `brdf slice --kirchhoff`
# with no other flag, on generated Gaussian surfaces (sigma 5 nm; tau 5 and 1 um; two scans of
# 560 um square at 250 nm each, averaged by `ndf` as any scan set), Al and Au at 555 nm, theta_i 0, 20, 45, 70 deg, against the Beckmann-Spizzichino
# ensemble series written here on its own (kirchhoff_bs_reference.py). The range compared is from
# 2 deg off the mirror direction to where the series falls below 1e-3 of its diffuse peak. Python
# (mb.brdf on the same file) gives the CLI's numbers.
set -u
BIN=$1
DATA=$2
HERE=$(cd "$(dirname "$0")" && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
for tau in 5 1; do
  for seed in 1 2; do
    $BIN generate gaussian --sigma 5nm --tau ${tau}um --nx 2240 --ny 2240 --spacing 250nm \
      --seed $((100 + 10 * tau + seed)) -o "$T/s${tau}_$seed.npy" 2>/dev/null || fail generate
  done
  $BIN ndf "$T/s${tau}_1.npy" "$T/s${tau}_2.npy" --method kirchhoff -o "$T/dk$tau.npy" 2>"$T/err" ||
    fail "ndf: $(cat "$T/err")"
  for metal in Al Au; do
    for ti in 0 20 45 70; do
      $BIN brdf slice --kirchhoff "$T/dk$tau.npy" --metal $metal --theta-i ${ti}deg \
        --samples 1441 -o "$T/s${tau}_${metal}_$ti.csv" >/dev/null 2>"$T/err" ||
        fail "slice: $(cat "$T/err")"
      grep -q "one D_K table" "$T/err" && fail "a default D_K warned that it is one table"
    done
  done
done
MICROBRDF_PYTHONPATH=${MICROBRDF_PYTHONPATH:-$(dirname "$BIN")/../python} /usr/bin/python3 "$HERE/kirchhoff_bs_reference.py" "$T" "$DATA" || fail "series"
echo ok
