#!/usr/bin/env bash
# Renders of the BRDFs that `microbrdf simulate` predicts for Westin, Arvo & Torrance 1992's
# micro-geometries (parallel cylinders of rough aluminium, velvet, woven cloth) on objects
# (docs/westin.md, "Renders of the simulated BRDFs"). Every image is made by the tool: simulate
# -> .shbrdf -> render --sh.
# Usage: [SECTIONS="sim cyl velvet cloth"] scripts/make-westin-renders.sh [BIN] [WORK_DIR]
# WORK_DIR keeps the .shbrdf files and the simulation summaries (default: a temporary folder).
# About 30 minutes on 2 heavily loaded cores (the SH evaluation dominates the renders).
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
W=${2:-$(mktemp -d)}
ENV=data/envmaps
IMG=docs/img
SCENES=examples/scenes
mkdir -p "$IMG" "$W"
want() { [[ " ${SECTIONS:-sim cyl velvet cloth} " == *" $1 "* ]]; }
S() { "$BIN" simulate --quiet --threads 2 --seed 1 --json "$@"; }
R() { "$BIN" render --quiet --threads 2 --seed 1 "$@" >/dev/null; }

# 1. The simulations (W92 sections 5.2-5.4). The cloth is hierarchical: the thread surface
#    (parallel nylon fibres) is simulated first and its SH BRDF is the material of the weave.
if want sim; then
  S "$SCENES/cylinders.json" --lmax 16 --rays 4000000 -o "$W/cylinders.shbrdf" >"$W/cylinders.json"
  S "$SCENES/velvet.json" --lmax 12 --rays 2000000 -o "$W/velvet.shbrdf" >"$W/velvet.json"
  S "$SCENES/cloth_threads.json" --lmax 12 --rays 2000000 -o "$W/threads.shbrdf" >"$W/threads.json"
  cp "$SCENES/cloth.json" "$W/cloth.json"  # reads threads.shbrdf next to itself
  S "$W/cloth.json" --lmax 12 --rays 2000000 -o "$W/cloth.shbrdf" >"$W/cloth_sim.json"
  for f in cylinders velvet threads cloth_sim; do
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(sys.argv[2], *(f'{k}={d[k]:.4g}' for k in ('mean_exit_energy','energy_depth_capped','energy_below','q','seconds')))" "$W/$f.json" "$f"
  done
fi

# 2. Parallel cylinders (W92 Figs. 7, 8 and 10). The BRDF's x axis is the cylinders' axis.
#    The cylinder pair: axis horizontal on the left, vertical on the right (W92 Fig. 7, lower
#    half: the same BRDF with the axis of anisotropy turned); a vase with the axis along circles
#    about its axis (W92 Fig. 10, the teapot polished by rotation) beside the same matrix
#    averaged over rotations about the normal (W92 Fig. 8: isotropic vs anisotropic aluminium).
if want cyl; then
  R --scene cylinders --sh "$W/cylinders.shbrdf" --envmap "$ENV/blender_courtyard.exr" \
    --size 160 --spp 128 -o "$IMG/westin_cyl_pair.png"
  VASE=(--scene vase --sh "$W/cylinders.shbrdf" --envmap "$ENV/blender_interior.exr" --size 192 --spp 32)
  R "${VASE[@]}" --brushing rotational -o "$IMG/westin_cyl_vase_rotational.png"
  R "${VASE[@]}" --isotropic-average -o "$IMG/westin_cyl_vase_isotropic.png"
  # W92 Fig. 9 (the wheel): a flat plate brushed by rotation, from above, under a small light.
  R --scene plate --sh "$W/cylinders.shbrdf" --brushing rotational --size 192 --spp 32 \
    --exposure -1 -o "$IMG/westin_cyl_plate_rotational.png"
fi

# 3. Velvet (W92 Fig. 12): a doughnut.
if want velvet || want cloth; then
  python3 - "$W/torus.obj" "$W/cushion.obj" <<'PY'
import math, sys
# Torus tilted 35 deg towards the camera.
R, r, nu, nv, t = 1.0, 0.42, 96, 48, math.radians(35)
rot = lambda px, py, pz: (px, py * math.cos(t) + pz * math.sin(t), -py * math.sin(t) + pz * math.cos(t))
with open(sys.argv[1], "w") as f:
    for i in range(nu):
        for j in range(nv):
            a, b = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            x, y, z = (R + r * math.cos(b)) * math.cos(a), r * math.sin(b), (R + r * math.cos(b)) * math.sin(a)
            f.write("v %.6f %.6f %.6f\n" % rot(x, y, z))
            f.write("vn %.6f %.6f %.6f\n" % rot(math.cos(b) * math.cos(a), math.sin(b), math.cos(b) * math.sin(a)))
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j + 1, ((i + 1) % nu) * nv + j + 1
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv + 1, i * nv + (j + 1) % nv + 1
            f.write("f %d//%d %d//%d %d//%d %d//%d\n" % (a, a, b, b, c, c, d, d))
# Cushion: two halves z = +-0.45 (1 - x^8)^(1/2) (1 - y^8)^(1/2) over the square [-1, 1]^2,
# tilted 50 deg back (we look at its upper face), smooth normals from the renderer.
n, t = 48, math.radians(-50)
rot = lambda px, py, pz: (px, py * math.cos(t) - pz * math.sin(t), py * math.sin(t) + pz * math.cos(t))
with open(sys.argv[2], "w") as f:
    for side in (1, -1):
        for i in range(n + 1):
            for j in range(n + 1):
                x, y = -1 + 2 * i / n, -1 + 2 * j / n
                z = side * 0.45 * math.sqrt(max(0.0, 1 - x ** 8)) * math.sqrt(max(0.0, 1 - y ** 8))
                f.write("v %.6f %.6f %.6f\n" % rot(x, z, -y))
    for side in range(2):
        o = side * (n + 1) ** 2 + 1
        for i in range(n):
            for j in range(n):
                a, b, c, d = o + i * (n + 1) + j, o + (i + 1) * (n + 1) + j, o + (i + 1) * (n + 1) + j + 1, o + i * (n + 1) + j + 1
                f.write("f %d %d %d %d\n" % ((a, b, c, d) if side == 0 else (a, d, c, b)))
PY
fi
if want velvet; then
  R --scene obj --obj "$W/torus.obj" --sh "$W/velvet.shbrdf" --isotropic-average \
    --envmap "$ENV/blender_interior.exr" --size 192 --spp 32 --exposure 2 -o "$IMG/westin_velvet_torus.png"
fi

# 4. Cloth (W92 Fig. 15): a cushion upholstered in the black nylon weave (warp along the
#    image's horizontal).
if want cloth; then
  R --scene obj --obj "$W/cushion.obj" --sh "$W/cloth.shbrdf" \
    --envmap "$ENV/blender_interior.exr" --size 192 --spp 32 --exposure 2 -o "$IMG/westin_cloth_cushion.png"
fi
ls -l "$IMG"/westin_*.png
