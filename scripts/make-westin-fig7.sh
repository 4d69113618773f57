#!/usr/bin/env bash
# Westin, Arvo & Torrance 1992, Fig. 7: the parallel-cylinder micro-scene (slightly rough
# aluminium cylinders on a black base, examples/scenes/cylinders.json) drawn as geometry
# (`render --micro-scene`) next to the plate with the BRDF `simulate` predicts for it
# (`render --sh`), with the cylinder axes across (left) and along (right) the screen, under the
# plate's default disk light (23 deg to the left of the camera, which looks straight down).
# Rows: the cylinders at the milliscale (3 tiles, 30 cylinders, across the plate); the same
# array far away (200 tiles: 2000 cylinders across 128 pixels, about 16 per pixel); the plate
# with the simulated SH BRDF. Writes docs/img/westin_fig7.png and, in WORK_DIR, the renders'
# summaries and far_field.json (mean luminance of rows 2 and 3 and their ratio, per
# orientation; docs/westin.md, "W92 Fig. 7").
# Usage: scripts/make-westin-fig7.sh [BIN] [WORK_DIR]   (about 5 minutes on 2 busy cores)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
W=${2:-$(mktemp -d)}
PY=${PYTHON:-/usr/bin/python3}
SCENE=examples/scenes/cylinders.json
IMG=docs/img
mkdir -p "$IMG" "$W"
R() { "$BIN" render --scene plate --quiet --threads 2 --seed 1 --json --size 128 "$@"; }

"$BIN" simulate "$SCENE" --lmax 16 --rays 4000000 --threads 2 --seed 1 --quiet \
  -o "$W/cylinders.shbrdf" --json >"$W/simulate.json"
# One exposure per column (the axes along the screen reflect 13 times more towards the camera).
for a in 0 90; do
  E=(--exposure "$([ "$a" = 0 ] && echo 1 || echo -1.5)")
  M=(--micro-scene "$SCENE" --brush-angle "$a" --spp 256 "${E[@]}")
  R "${M[@]}" --micro-tiles 3 -o "$W/near_$a.png" >"$W/near_$a.json"
  R "${M[@]}" --micro-tiles 200 -o "$W/far_$a.png" >"$W/far_$a.json"
  # --direct mis: the same image as the default resampling (equal within its noise), at a third
  # of the SH evaluations.
  R --sh "$W/cylinders.shbrdf" --brush-angle "$a" --spp 32 --direct mis "${E[@]}" \
    -o "$W/sh_$a.png" >"$W/sh_$a.json"
done
"$PY" scripts/westin_fig7_far_field.py "$W"
"$PY" scripts/figure_montage.py "$IMG/westin_fig7.png" --cols 2 --cell 160 \
  "$W/near_0.png=cylinders (30 across)\naxes across, +1 stop" \
  "$W/near_90.png=cylinders (30 across)\naxes along, -1.5 stops" \
  "$W/far_0.png=cylinders, far away\n(2000 across 128 px)" \
  "$W/far_90.png=cylinders, far away\n(2000 across 128 px)" \
  "$W/sh_0.png=plate with the\nsimulated SH BRDF" "$W/sh_90.png=plate with the\nsimulated SH BRDF"
