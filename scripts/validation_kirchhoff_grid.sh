#!/usr/bin/env bash
# docs/validation.md, "Wave optics with the defaults over a grid of surfaces": for generated Gaussian
# surfaces (sigma 2, 5, 20, 80 nm; tau 1, 5 um; one scan of 2240^2 samples at 250 nm each), the
# in-plane BRDF of the default D_K (`ndf --method kirchhoff`, `brdf slice --kirchhoff`) and of
# first-order Rayleigh-Rice (`brdf slice --rayleigh-rice`) against the Beckmann-Spizzichino series
# (scripts/bs_series.py), Al and Au at 555 nm, theta_i 0, 20, 45, 70 deg.
# Usage: scripts/validation_kirchhoff_grid.sh BIN [WORKDIR]   (about 12 min on 2 cores)
set -eu
BIN=$1
HERE=$(cd "$(dirname "$0")" && pwd)
W=${2:-$(mktemp -d)}
mkdir -p "$W"
seed=500
for sigma in 2 5 20 80; do
  for tau in 1 5; do
    seed=$((seed + 1))
    s="$W/s${sigma}_${tau}"
    if [ ! -f "$s.done" ]; then
      "$BIN" generate gaussian --sigma ${sigma}nm --tau ${tau}um --nx 2240 --ny 2240 \
        --spacing 250nm --seed $seed -o "$s.npy" 2>/dev/null
      "$BIN" ndf "$s.npy" --method kirchhoff -o "${s}_dk.npy" 2>/dev/null
      for metal in Al Au; do
        for ti in 0 20 45 70; do
          "$BIN" brdf slice --kirchhoff "${s}_dk.npy" --metal $metal --theta-i ${ti}deg \
            --samples 1441 -o "${s}_dk_${metal}_$ti.csv" >/dev/null 2>&1
          "$BIN" brdf slice --rayleigh-rice "$s.npy" --metal $metal --theta-i ${ti}deg \
            --samples 1441 -o "${s}_rr_${metal}_$ti.csv" >/dev/null 2>&1
        done
      done
      rm -f "$s.npy" "${s}_dk.npy"
      touch "$s.done"
    fi
  done
done
/usr/bin/python3 "$HERE/validation_kirchhoff_grid.py" "$W" "$HERE/.."
