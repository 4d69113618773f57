#!/usr/bin/env bash
# What is not a height map is said to be so, before any work: an 8-bit greyscale photograph
# saved as TIFF (integer counts have no height unit: --z-scale gives one), PNG and JPEG pictures,
# a colour TIFF; --z-scale scales the numbers of files that store no unit (checked against numpy
# on the same counts) and is refused where the file has a unit of its own.
set -u
BIN=$(realpath "$1")
DATA=$(realpath "$2")
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
cd "$T" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
/usr/bin/python3 - <<'PY' || fail "python could not write the pictures"
import numpy as np
from PIL import Image
y, x = np.mgrid[0:48, 0:64]
grey = (128 + 60 * np.sin(x / 5.0) * np.cos(y / 7.0)).astype(np.uint8)  # a smooth "photo"
Image.fromarray(grey, mode="L").save("grey.tif")
Image.fromarray(grey, mode="L").save("photo.png")
Image.fromarray(np.dstack([grey, grey, grey]), mode="RGB").save("photo.jpg")
Image.fromarray(np.dstack([grey, grey, grey]), mode="RGB").save("colour.tif")
np.save("counts.npy", grey.astype(np.float64))
Image.fromarray((grey / 255.0).astype(np.float32), mode="F").save("grey_float.tif")
PY
# refused CODE PATTERN -- CMD...: exit CODE, stderr matches PATTERN, nothing written.
refused() {
  local code=$1 pat=$2; shift 3
  "$@" >out.txt 2>err.txt </dev/null
  local rc=$?
  [ $rc -eq "$code" ] || fail "exit $rc (want $code) from: $*: $(cat err.txt)"
  grep -Eq -- "$pat" err.txt || fail "stderr does not match /$pat/ from: $*: $(cat err.txt)"
  [ ! -e rep ] && [ ! -e n.npy ] || fail "output written by a refused run: $*"
}
NO_UNIT="grey.tif: tiff: 8-bit integer samples and no height unit .*--z-scale 1nm.*a photograph or a greyscale picture is not a height map"
refused 1 "$NO_UNIT" -- $BIN info grey.tif --spacing 1um
refused 1 "$NO_UNIT" -- $BIN ndf grey.tif --spacing 1um --resolution 65 -o n.npy
refused 1 "$NO_UNIT" -- $BIN predict grey.tif --spacing 1um --metal Al --no-render --resolution 65 -o rep
refused 1 "photo.png: a PNG picture, not a height map" -- $BIN info photo.png --spacing 1um
refused 1 "photo.jpg: a JPEG picture, not a height map" -- $BIN predict photo.jpg --spacing 1um --metal Al -o rep
refused 1 "colour.tif: tiff: 3 samples per pixel \(a colour picture\?\)" -- $BIN info colour.tif --spacing 1um
refused 1 "sample-land.x3p: x3p files store their heights with a unit; --z-scale applies to" -- \
  $BIN info "$DATA/sample-land.x3p" --z-scale 1nm
refused 1 "height_u16_nm.tif: .*z_unit = nm\) and --z-scale gives another" -- \
  $BIN info "$DATA/height_u16_nm.tif" --spacing 1um --z-scale 1nm
refused 2 "error: --z-scale: must lie in 1 pm \.\. 1 m \(got -1nm\)" -- $BIN info grey.tif --spacing 1um --z-scale -1nm

# A float picture (grey values 0..1 read as metres): slopes of 10^4 at 1 um, no surface.
refused 1 "grey_float.tif: heights implausible for the spacing: the median slope between neighbouring samples is .* at a spacing of 1 um" -- \
  $BIN info grey_float.tif --spacing 1um
refused 1 "counts.npy: heights implausible for the spacing" -- $BIN ndf counts.npy --spacing 1um --resolution 65 -o n.npy

# With --z-scale the counts are heights: Sq of the unlevelled map against numpy's.
for f in grey.tif counts.npy; do
  $BIN info "$f" --spacing 1um --z-scale 2nm --level none --json >info.json 2>err.txt ||
    fail "info $f --z-scale 2nm: $(cat err.txt)"
  /usr/bin/python3 - "$f" <<'PY' || fail "$f: Sq differs from numpy's"
import json, sys
import numpy as np
y, x = np.mgrid[0:48, 0:64]
counts = (128 + 60 * np.sin(x / 5.0) * np.cos(y / 7.0)).astype(np.uint8).astype(float)
want = np.std(counts * 2e-9)
got = json.load(open("info.json"))["surfaces"][0]["sq_m"]
print(f"{sys.argv[1]}: Sq {got:.6e} m, numpy {want:.6e} m")
sys.exit(0 if abs(got - want) <= 1e-9 * want else 1)
PY
done
echo "ok: pictures refused naming the file; --z-scale checked against numpy"
