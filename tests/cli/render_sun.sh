#!/usr/bin/env bash
# `microbrdf render` with Sun 2002's options as a user meets them (docs/render.md, "Sun 2002
# Figs. 8 and 11"): the free travel probabilities left out brighten a rough sphere and change
# nothing on a smooth one; the published form is darker than the standard one; a uniform
# smoothness texture renders exactly like --sun with that s, a uniform colour texture like
# --color with that colour; --normalize scales the PNG; bad combinations and files give a clear
# error, a non-zero exit and no output.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
R=(--scene sphere --size 24 --spp 16 --threads 2 --seed 3 --quiet --json)
r() {  # r NAME ARGS...: render to NAME.png, JSON to NAME.json
  local n=$1; shift
  $BIN render "${R[@]}" "$@" -o "$T/$n.png" >"$T/$n.json" 2>"$T/err" || fail "render $n: $(cat "$T/err")"
}
lum() { python3 -c "import json,sys; m=json.load(open(sys.argv[1]))['mean_linear_srgb']; print(0.2126*m[0]+0.7152*m[1]+0.0722*m[2])" "$1"; }
check() {  # check PYTHON_CONDITION MESSAGE, with the luminances as L[name]
  python3 - "$T" "$1" <<'PY' || fail "$2"
import glob, json, os, sys
L = {}
for p in glob.glob(sys.argv[1] + "/*.json"):
    m = json.load(open(p))["mean_linear_srgb"]
    L[os.path.basename(p)[:-5]] = 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2]
ok = eval(sys.argv[2])
if not ok:
    print({k: round(v, 5) for k, v in sorted(L.items())})
sys.exit(0 if ok else 1)
PY
}
png() {  # png FILE W H R,G,B: a uniform 8-bit RGB PNG
  python3 - "$@" <<'PY'
import struct, sys, zlib
path, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
c = bytes(int(x) for x in sys.argv[4].split(","))
rows = b"".join(b"\0" + c * w for _ in range(h))
chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                       + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
PY
}

# --- Free travel probabilities (Sun's Fig. 8 rows) under the white sky, copper. Every term left
# out can only add light: none >= view >= both. On the rough s = 1 the terms matter (measured,
# mean pixel with the sky: none / both = 1.92, view / both = 1.27); on the smooth s = 20 they
# change the image by < 3 % (measured 0.8 %).
for s in 1 20; do
  for f in none view both; do r "s${s}_$f" --sun $s --sun-ftp $f --metal Cu; done
done
check "L['s1_none'] > 1.5 * L['s1_both'] and L['s1_none'] > L['s1_view'] > L['s1_both']" \
  "FTP terms on the rough sphere"
check "1 <= L['s20_none'] / L['s20_both'] < 1.03" "FTP terms on the smooth sphere"
grep -q "free travel probabilities: view" "$T/s1_view.json" || fail "settings do not name the FTP terms"
# --- Published vs standard form: the published form has the extra factor
# (h.n) cos_i cos_o / (wi.h) <= 1, so it is darker (measured 0.78 at s = 5).
r s5_std --sun 5 --metal Cu
r s5_pub --sun 5 --sun-form published --metal Cu
check "0.5 < L['s5_pub'] / L['s5_std'] < 0.95" "published form not darker than the standard form"
grep -q "as published" "$T/s5_pub.json" || fail "settings do not name the published form"

# --- Textures (Sun's Fig. 11). White in the smoothness map is s_max: the same image as --sun
# s_max, bit for bit (same samples, same BRDF).
png "$T/white.png" 8 8 255,255,255
png "$T/gold.png" 4 4 230,194,122
r tex_s --s-texture "$T/white.png" --s-range 2,20 --metal Cu
r sun20 --sun 20 --metal Cu
cmp -s "$T/tex_s.png" "$T/sun20.png" || fail "uniform smoothness texture differs from --sun 20"
grep -q "smoothness texture" "$T/tex_s.json" || fail "settings do not name the smoothness texture"
# A uniform colour texture is the --color material of that colour (kappa tabulated on the same
# 5 nm grid: the same image within 0.1 %).
r tex_c --sun 8 --color-texture "$T/gold.png"
r col --sun 8 --color '#e6c27a'
check "abs(L['tex_c'] / L['col'] - 1) < 1e-3" "uniform colour texture differs from --color"
# A mid-grey map (s = 11 of 2..20) lies between the ends.
png "$T/black.png" 8 8 0,0,0
r tex_lo --s-texture "$T/black.png" --s-range 2,20 --metal Cu
check "L['tex_lo'] != L['tex_s']" "the smoothness map has no effect"

# --- --normalize: the exposure that takes the brightest pixels to white is reported and used
# (the sky of radiance 1 and the highlight above it: a negative exposure here).
r norm --sun 5 --metal Cu --normalize
python3 -c "import json,sys; e=json.load(open(sys.argv[1]))['png_exposure']; assert -5 < e < -0.01, e" \
  "$T/norm.json" || fail "--normalize exposure"
cmp -s "$T/norm.png" "$T/s5_std.png" && fail "--normalize did not change the PNG"

# --- Errors: clear message, non-zero exit, no output.
expect_error() {  # expect_error PATTERN ARGS...
  local pat=$1; shift
  rm -f "$T/x.png"
  $BIN render --scene sphere --size 8 --spp 1 --quiet "$@" -o "$T/x.png" >/dev/null 2>"$T/err" \
    && fail "accepted: $*"
  grep -q -- "$pat" "$T/err" || fail "unclear error for $*: $(cat "$T/err")"
  [ ! -e "$T/x.png" ] || fail "output written for $*"
}
expect_error "give both, view, light or none" --sun 2 --sun-ftp viewer
expect_error "give standard or published" --sun 2 --sun-form printed
expect_error "go with the Sun 2002 BRDF" --model ggx --alpha 0.2 --sun-ftp none
expect_error "leave out --sun" --sun 2 --s-texture "$T/white.png"
expect_error "leave out --metal" --sun 2 --color-texture "$T/gold.png" --metal Cu
expect_error "s-range" --s-texture "$T/white.png" --s-range 5,2
expect_error "missing.png" --s-texture "$T/missing.png"
printf 'not an image\n' >"$T/bad.png"
expect_error "bad.png" --sun 2 --color-texture "$T/bad.png"
head -c 60 "$T/gold.png" >"$T/trunc.png"
expect_error "trunc.png" --s-texture "$T/trunc.png"
echo "render_sun: ok"
