#!/usr/bin/env bash
# Regenerates the renderer figures of docs/render.md and docs/validation.md with the tool itself.
# Usage: [SECTIONS="1 6"] scripts/make-render-figures.sh [BIN] [ENVMAP_DIR]  (default data/envmaps)
# SECTIONS picks the numbered parts below (default: all). About 7 minutes on 2 busy cores.
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
ENV=${2:-data/envmaps}
IMG=docs/img
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
mkdir -p "$IMG"
R() { "$BIN" render --quiet --threads 2 --seed 1 "$@" >/dev/null; }
CYL=(--scene cylinders --envmap "$ENV/blender_courtyard.exr" --size 256 --spp 64)
want() { [[ " ${SECTIONS:-1 2 3 4 5 6} " == *" $1 "* ]]; }
if want 1 || want 2; then  # the filtered NDF of a generated stainless #4 surface (parts 1, 2)
  "$BIN" generate brushed --preset stainless4 --seed 1 -o "$W/ss4.x3p" 2>/dev/null
  "$BIN" ndf "$W/ss4.x3p" --level none --method filtered -o "$W/ss4.npy" 2>/dev/null >/dev/null
fi

# 1. Dong 2015 Fig. 10: two cylinder sections, brushing horizontal on the left cylinder and
#    vertical on the right, under an HDR environment (courtyard instead of St. Peter's).
#    Stainless #4 as the Dong Fig. 12 Beckmann fit, as its ellipsoid fit, and as the filtered NDF
#    of a generated stainless #4 surface; an isotropic surface for contrast; brushed copper.
if want 1; then
  R "${CYL[@]}" --model beckmann --alpha-x 0.008 --alpha-y 0.16 --metal SS-austenitic -o "$IMG/render_cyl_ss4_beckmann.png"
  R "${CYL[@]}" --model ellipsoid --alpha-x 0.0074 --alpha-y 0.142 --metal SS-austenitic -o "$IMG/render_cyl_ss4_ellipsoid.png"
  R "${CYL[@]}" --ndf "$W/ss4.npy" --metal SS-austenitic -o "$IMG/render_cyl_ss4_tabulated.png"
  R "${CYL[@]}" --model ggx --alpha 0.08 --metal SS-austenitic -o "$IMG/render_cyl_isotropic.png"
  R "${CYL[@]}" --model beckmann --alpha-x 0.01 --alpha-y 0.2 --metal Cu -o "$IMG/render_cyl_cu_brushed.png"
fi

# 2. Dong 2015 Fig. 13: the plate seen from above under a small disk light 23 deg to the left;
#    scratches running up the image (--brush-angle 90) give the bright stripe; rotational
#    brushing (Westin's wheel) gives the bow tie.
if want 2; then
  PLATE=(--scene plate --ndf "$W/ss4.npy" --metal SS-austenitic --size 256 --spp 64 --exposure -3)
  R "${PLATE[@]}" --brush-angle 90 -o "$IMG/render_plate_ss4_linear.png"
  R "${PLATE[@]}" --brushing rotational -o "$IMG/render_plate_ss4_rotational.png"
fi

# 3. Sun 2002 Fig. 9: copper vases from diffuse-looking to specular (s = 1, 5, 20), the light at
#    the camera.
want 3 && for s in 1 5 20; do
  R --scene vase --sun "$s" --metal Cu --point 0,0.8,4.5:40 --size 192 --spp 32 -o "$IMG/render_sun_vase_s$s.png"
done

# 4. An OBJ mesh (a torus written here, tilted towards the camera; file normals), brushed
#    gold with rotational brushing about the vertical axis.
if want 4; then
python3 - "$W/torus.obj" <<'PY'
import math, sys
R, r, nu, nv, t = 1.0, 0.35, 96, 48, math.radians(35)
with open(sys.argv[1], "w") as f:
    for i in range(nu):
        for j in range(nv):
            a, b = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            x, y, z = (R + r * math.cos(b)) * math.cos(a), r * math.sin(b), (R + r * math.cos(b)) * math.sin(a)
            nx, ny, nz = math.cos(b) * math.cos(a), math.sin(b), math.cos(b) * math.sin(a)
            rot = lambda px, py, pz: (px, py * math.cos(t) + pz * math.sin(t), -py * math.sin(t) + pz * math.cos(t))
            f.write("v %.6f %.6f %.6f\n" % rot(x, y, z))
            f.write("vn %.6f %.6f %.6f\n" % rot(nx, ny, nz))
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j + 1, ((i + 1) % nu) * nv + j + 1
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv + 1, i * nv + (j + 1) % nv + 1
            f.write("f %d//%d %d//%d %d//%d %d//%d\n" % (a, a, b, b, c, c, d, d))
PY
R --scene obj --obj "$W/torus.obj" --model beckmann --alpha-x 0.02 --alpha-y 0.25 --metal Au --brushing rotational \
  --envmap "$ENV/blender_interior.exr" --size 256 --spp 64 -o "$IMG/render_obj_torus.png"
fi

# 5. Validation: white furnace, mirror sphere, and the three estimators at equal samples.
if want 5; then
  R --scene furnace_sphere --white-env --lambertian 1 --size 128 --spp 64 -o "$IMG/render_furnace.png"
  R --scene sphere --mirror --metal Al --envmap "$ENV/blender_courtyard.exr" --size 256 --spp 16 -o "$IMG/render_mirror_sphere.png"
  for m in mis brdf light; do
    R --scene sphere --model ggx --alpha 0.05 --metal Al --envmap "$ENV/blender_studio.exr" --size 128 --spp 16 \
      --mis $m --direct mis -o "$IMG/render_mis_$m.png"
  done
fi

# 6. Further material kinds. The cylinder pair with a synthesised stainless #4 parameter texture
#    (ellipsoid fits of 13.2 um texels of three generated scans, synthesised to 256^2 texels;
#    --uv-scale 1: one texture repeat per scene unit, so a texel is about a pixel), and a sphere
#    with an SH-matrix BRDF (GGX alpha 0.2 on Al projected to lmax 24, Westin 1992; `brdf
#    sh-project`) beside the analytic model it came from.
if want 6; then
  for s in 1 2 3; do
    "$BIN" generate brushed --preset stainless4 --nx 640 --ny 480 --seed $((300 + s)) \
      -o "$W/tex$s.x3p" >/dev/null 2>&1
  done
  "$BIN" texture "$W"/tex?.x3p --texel 13.2um -o "$W/ex.exr" --no-preview >/dev/null 2>&1
  "$BIN" texture "$W/ex.exr" --size 256 --seed 1 -o "$W/ss4_tex.exr" \
    --preview "$IMG/render_tex_ss4_params.png" --preview-size 128 >/dev/null 2>&1
  R "${CYL[@]}" --texture "$W/ss4_tex.exr" --uv-scale 1 --metal SS-austenitic -o "$IMG/render_cyl_ss4_texture.png"
  "$BIN" brdf sh-project --model ggx --alpha 0.2 --metal Al --lmax 24 -o "$W/ggx.shbrdf" >/dev/null 2>&1
  SPH=(--scene sphere --envmap "$ENV/blender_studio.exr" --size 192 --spp 64)
  R "${SPH[@]}" --sh "$W/ggx.shbrdf" -o "$IMG/render_sphere_sh_ggx.png"
  R "${SPH[@]}" --model ggx --alpha 0.2 --metal Al -o "$IMG/render_sphere_ggx_ref.png"
fi
ls -l "$IMG"/render_*.png
