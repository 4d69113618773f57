#!/usr/bin/env bash
# Sun 2002, Fig. 9: vases of gold, silver and copper at smoothness s = 0.5, 0.8, 1, 2, 4, 5, 7,
# 10, 20, the point light at the camera, Sun's BRDF as published (eq. 3.5.3), each image scaled
# to its brightest pixels (--normalize) as in the paper. Writes docs/img/sun_fig9.png (rows: Au,
# Ag, Cu) and, in WORK_DIR, the renders (.png, and .npy for the measurement) and widths.json:
# the highlight's width along the row through it, measured on each render and predicted from
# the analytic BRDF (scripts/sun_fig9_widths.py; docs/sun2002.md, "Fig. 9").
# Usage: scripts/make-sun-fig9.sh [BIN] [WORK_DIR]   (about 2 minutes on 2 busy cores)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
W=${2:-$(mktemp -d)}
PY=${PYTHON:-/usr/bin/python3}
IMG=docs/img
S=0.5,0.8,1,2,4,5,7,10,20
mkdir -p "$IMG" "$W"
cells=()
for m in Au Ag Cu; do
  for s in ${S//,/ }; do
    "$BIN" render --scene vase --sun "$s" --sun-form published --metal "$m" --point 0,0.8,4.5:40 \
      --size 128 --spp 16 --normalize --quiet --threads 2 --seed 1 \
      -o "$W/vase_${m}_s$s.png" -o "$W/vase_${m}_s$s.npy" >/dev/null
    cells+=("$W/vase_${m}_s$s.png=$m, s = $s")
  done
done
"$PY" scripts/sun_fig9_widths.py "$W" Au Ag Cu --s "$S"
"$PY" scripts/figure_montage.py "$IMG/sun_fig9.png" --cols 9 --cell 96 "${cells[@]}"
