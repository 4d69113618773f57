#!/usr/bin/env bash
# Westin, Arvo & Torrance 1992, Fig. 14: the cloth micro-geometry (examples/scenes/cloth.json: a
# plain weave of threads over a black base) drawn as geometry (`render --micro-scene`), the
# threads once ideal diffuse (albedo 0.8) and once with the thread BRDF `simulate` predicts from
# the parallel nylon fibres of examples/scenes/cloth_threads.json (W92's hierarchy: fibres ->
# thread BRDF -> weave). Two tiles (8 threads) across the plate, seen from straight above, lit by
# a uniform sky of radiance 0.5 and the plate's disk light at half its radiance (23 deg to the
# left). Each image is scaled to its brightest pixels. Writes docs/img/westin_fig14.png.
# Usage: scripts/make-westin-fig14.sh [BIN] [WORK_DIR]   (about 2 minutes on 2 busy cores)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
W=${2:-$(mktemp -d)}
PY=${PYTHON:-/usr/bin/python3}
IMG=docs/img
mkdir -p "$IMG" "$W"
"$BIN" simulate examples/scenes/cloth_threads.json --lmax 12 --rays 2000000 --threads 2 --seed 1 \
  --quiet -o "$W/threads.shbrdf" --json >"$W/threads.json"
cp examples/scenes/cloth.json "$W/cloth.json"  # reads threads.shbrdf next to itself
"$PY" - "$W/cloth.json" "$W/cloth_diffuse.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["name"] = "cloth-diffuse"
scene["materials"]["thread"] = {"type": "lambert", "albedo": 0.8}
json.dump(scene, open(sys.argv[2], "w"), indent=1)
PY
# Dong's plate light (render.md) at half its radiance: a disk of radius 12.8 tan 4.5 deg at
# distance 12.8, 23 deg to the left of the camera.
LIGHT=(--white-env --env-scale 0.5 --disk-light -5.00136,11.7825,0,0.390731,-0.920505,0,1.00738:81.2238,81.2238,81.2238)
for c in cloth_diffuse cloth; do
  "$BIN" render --scene plate --micro-scene "$W/$c.json" --micro-tiles 2 "${LIGHT[@]}" --size 128 \
    --spp 32 --direct mis --normalize --quiet --threads 2 --seed 1 --json -o "$W/$c.png" >"$W/$c.render.json"
done
"$PY" scripts/figure_montage.py "$IMG/westin_fig14.png" --cols 2 --cell 160 \
  "$W/cloth_diffuse.png=ideal diffuse threads" "$W/cloth.png=simulated thread BRDF"
