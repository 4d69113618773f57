#!/usr/bin/env bash
# Renders of Sun 2002's analytic BRDF for docs/render.md: Fig. 8 (copper plates, the free travel
# probabilities left out or kept, as published and in the standard form) and Fig. 11 (vases with
# a smoothness texture on copper and with a colour texture). Every image is made by
# `microbrdf render`; the plate mesh and the two textures are written here.
# Usage: [SECTIONS="8 10 11"] scripts/make-sun-renders.sh [BIN]   (about 1 minute on 2 busy cores)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
IMG=docs/img
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
mkdir -p "$IMG"
want() { [[ " ${SECTIONS:-8 10 11} " == *" $1 "* ]]; }
R() { "$BIN" render --quiet --threads 2 --seed 1 --json "$@"; }

# The inputs: a 2 x 2 plate whose normal is 40 deg from the view direction (the camera 50 deg
# above its plane), and two 64 x 64 PNG textures (periodic in both directions).
python3 - "$W" <<'PY'
import math, struct, sys, zlib
w = sys.argv[1]
a = math.radians(50)
n, v = (0, math.cos(a), math.sin(a)), (0, -math.sin(a), math.cos(a))
N = 16
with open(w + "/plate.obj", "w") as f:
    for i in range(N + 1):
        for j in range(N + 1):
            x, y = -1 + 2 * i / N, -1 + 2 * j / N
            f.write("v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\n" % ((x, y * v[1], y * v[2]) + n))
    for i in range(N):
        for j in range(N):
            A, B = i * (N + 1) + j + 1, (i + 1) * (N + 1) + j + 1
            f.write("f %d//%d %d//%d %d//%d %d//%d\n" % (A, A, B, B, B + 1, B + 1, A + 1, A + 1))
def png(path, size, pixel):
    rows = b"".join(b"\0" + bytes(c for x in range(size) for c in pixel(x / size, 1 - (y + 0.5) / size))
                    for y in range(size))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
# Smoothness: diagonal bands, grey g = (1 + sin 2 pi (2u + v)) / 2 (s from --s-range).
def s_pixel(u, v):
    g = round(255 * (1 + math.sin(2 * math.pi * (2 * u + v))) / 2)
    return (g, g, g)
# Colour: 4 x 2 patches of metallic paints (gold, red, green, blue, silver, violet, orange, teal).
paints = [(230, 190, 90), (200, 40, 40), (60, 170, 70), (50, 80, 200),
          (200, 200, 205), (140, 60, 170), (235, 120, 30), (40, 160, 160)]
def c_pixel(u, v):
    return paints[int(4 * u) % 4 + 4 * (int(2 * v) % 2)]
png(w + "/s_texture.png", 64, s_pixel)
png(w + "/color_texture.png", 64, c_pixel)
PY
cp "$W/s_texture.png" "$IMG/sun_tex_s.png"
cp "$W/color_texture.png" "$IMG/sun_tex_color.png"

# Fig. 8: copper plates, the point light 1.7 above the plate's centre (the mirror point of the
# light lies near the plate's front edge), s = 1, 3, 5, 10, 20; each image scaled to its
# brightest pixels (--normalize) as in the paper. Rows: the published form (eq. 3.5.3) without
# the free travel probabilities, with the viewer's only, with both (Sun's three rows), and the
# standard microfacet form with both.
if want 8; then
  PLATE=(--scene obj --obj "$W/plate.obj" --metal Cu --point 0,1.0927,1.3023:1 --width 160 --height 120
         --spp 32 --normalize)
  for s in 1 3 5 10 20; do
    for row in published:none published:view published:both standard:both; do
      form=${row%%:*} ftp=${row##*:}
      R "${PLATE[@]}" --sun "$s" --sun-form "$form" --sun-ftp "$ftp" \
        -o "$IMG/sun_fig8_${form}_${ftp}_s$s.png" >/dev/null
    done
  done
fi

# Fig. 10: the silver vase with s = 1, the point light at the camera (as the Fig. 9 copper vases
# of scripts/make-render-figures.sh).
if want 10; then
  R --scene vase --sun 1 --sun-form published --metal Ag --point 0,0.8,4.5:40 --size 192 --spp 32 --exposure 2.5 \
    -o "$IMG/sun_fig10_silver_s1.png" >/dev/null
fi

# Fig. 11: vases under two point lights left and right of the camera and a dim uniform sky
# (radiance 0.4, so that the smooth parts show their colour and the rough ones stay dark). (a) the smoothness texture (s from 1 to 20) on copper; (b) the colour texture with
# s = 10. --uv-scale 2/pi: two texture repeats around the vase.
if want 11; then
  VASE=(--scene vase --point -1.5,1,4.5:10 --point 1.5,1,4.5:10 --white-env --env-scale 0.4
        --uv-scale 0.63662 --size 192 --spp 32)
  R "${VASE[@]}" --s-texture "$W/s_texture.png" --s-range 1,20 --metal Cu -o "$IMG/sun_fig11a_s_texture.png" >/dev/null
  R "${VASE[@]}" --sun 10 --color-texture "$W/color_texture.png" -o "$IMG/sun_fig11b_color_texture.png" >/dev/null
fi
ls -l "$IMG"/sun_fig*.png
