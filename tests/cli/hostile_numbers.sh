#!/usr/bin/env bash
# Hostile numbers: options and file fields whose values are valid numbers but absurd for the data
# they apply to (a spacing of 1e-30 m, a filter sigma of 1000 m, geometry of 1e300 m, a plane a
# million metres above its tile, --rays -1), budgets that must hold (--max-memory against the
# filtered-normal kernel, the Kirchhoff series and a goniometer CSV of many rows) and the file-size
# limit (ulimit -f). Every case ends within 10 s with a clean exit and a message naming the file
# or the flag, under 1 GiB of RSS (and 1.5 x --max-memory), leaving no temporary behind
# (tests/cli/lib/hostile_expect.bash).
set -u
BIN=$(realpath "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
[ -x /usr/bin/time ] || { echo "SKIP: /usr/bin/time (GNU time) not installed"; exit 0; }
HOSTILE_DIR=$T
. "$HERE/lib/hostile_expect.bash"
cd "$T" || exit 1
expect() { hostile_run "$@"; }

# Inputs of our own: a 64 x 64 scan (1 um spacing), a tall 2 x 6000 strip, a scan with 2 mm of
# form left in it, and a goniometer CSV of 300000 rows (12 MB, about 70 MB once parsed).
$BIN generate gaussian --nx 64 --ny 64 --spacing 1um -o scan.npy >/dev/null 2>&1 || fail "generate scan"
/usr/bin/python3 - <<'PY' || fail "python could not write the inputs"
import json
import numpy as np
rng = np.random.default_rng(3)
np.save("strip.npy", rng.normal(0, 1e-7, (6000, 2)))
json.dump({"dx_m": 1e-6, "dy_m": 1e-6}, open("strip.json", "w"))
y, x = np.mgrid[0:128, 0:128]
np.save("form.npy", 2e-3 * ((x - 64) ** 2 + (y - 64) ** 2) / 64 ** 2 + rng.normal(0, 1e-8, (128, 128)))
json.dump({"dx_m": 1e-6, "dy_m": 1e-6}, open("form.json", "w"))
with open("many.csv", "w") as f:
    f.write("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n")
    row = "10,0,12,180,550,0.5\n"
    f.write(row * 300000)
PY

# 1. Crashes: lengths that once overflowed a kernel or Embree's ray checks are refused.
# A spacing of 1e-30 m (the filtered-normal kernel would have had 1e25 taps).
# In a file (the sidecar's dx_m, dy_m): refused naming the file; on the command line: the flag.
cp scan.npy tiny.npy && echo '{"dx_m": 1e-30, "dy_m": 1e-30}' >tiny.json
for cmd in "ndf -o x.npy" "ndf --method naive -o x.npy" "info" "convert x.x3p" \
           "predict --no-render --resolution 65 -o rep"; do
  set -- $cmd
  sub=$1; shift
  expect 1 "tiny.npy: spacing 1e-30 m x 1e-30 m is absurd (below 1 pm).*--spacing" -- \
    $BIN $sub tiny.npy "$@"
  expect 2 "error: --spacing: must lie in 1 pm .. 1 m (got 1e-30m)" -- $BIN $sub scan.npy --spacing 1e-30m "$@"
done
# 1 pm is a valid spacing, but this scan's heights (an rms of 0.1 um) are then no surface.
expect 1 "scan.npy: heights implausible for the spacing: the median slope between neighbouring samples is .* at a spacing of 1 pm" -- \
  $BIN ndf scan.npy --spacing 1pm -o x.npy
# A surface made at 1 pm: the default filter sigma (1 um) is far longer than the scan.
$BIN generate gaussian --nx 64 --ny 64 --spacing 1pm --sigma 0.1pm --tau 5pm -o pm.npy >/dev/null 2>&1 ||
  fail "generate at 1 pm"
expect 1 "pm.npy: filter sigma 1 um is longer than the scan (64 x 64 samples of 1 pm x 1 pm" -- \
  $BIN ndf pm.npy -o x.npy
expect 1 "pm.npy: filter sigma 1 um is longer than the scan" -- \
  $BIN predict pm.npy --no-render --resolution 65 -o rep
[ -e x.npy ] || [ -e x.x3p ] || [ -e rep ] && fail "output written from a refused run"
# Micro-scene geometry of 1e300 m: refused naming the scene file and the object, before Embree.
scene() { printf '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [%s]}' "$1" >"$2"; }
scene '{"type": "spheres", "radius": "1e308um", "pitch": "50um", "material": "m"}' sphere.json
scene '{"type": "plane", "z": "1e300m", "material": "m"}' plane.json
scene '{"type": "fibers", "count": 4, "length": "1e300m", "material": "m"}, {"type": "plane", "material": "m"}' fibre.json
scene '{"type": "cylinders", "radius": "1um", "count": 4, "z": "-1e300m", "material": "m"}' cyl.json
scene '{"type": "weave", "pitch": "50um", "radius": "5um", "crimp": "1e300m", "material": "m"}' weave.json
for f in sphere plane fibre cyl weave; do
  expect 1 "$f.json: .*must lie within 10 mm (100 x the tile's shorter side 100 um)" -- \
    $BIN simulate $f.json --rays 1000 -o s.shbrdf
done
gen() { printf '{"materials": {"m": {"type": "mirror"}}, "objects": [{"type": "heightfield", "generate": {"kind": "gaussian", "nx": 32, "spacing": "1um", "sigma": "%s", "tau": "4um"}%s, "material": "m"}]}' "$1" "$2" >"$3"; }
gen 1e300m '' sigma.json
expect 1 "sigma.json: sigma must lie in 0 .. 1 m" -- $BIN simulate sigma.json --rays 1000 -o s.shbrdf
gen 0.1um ', "z_scale": 1e300' zscale.json
gen 0.1um ', "z_scale": 1e9' ztall.json
for f in zscale ztall; do
  expect 1 "$f.json: height field 1: height .* must lie within 3.2 mm" -- \
    $BIN simulate $f.json --rays 1000 -o s.shbrdf
done
gen 0.1um '' tiny.json; sed -i 's/"spacing": "1um"/"spacing": "1e-300m"/' tiny.json
expect 1 "tiny.json: spacing must lie in 1 pm .. 1 m" -- $BIN simulate tiny.json --rays 1000 -o s.shbrdf
# A tile below 1 nm (given, not generated).
scene '{"type": "plane", "material": "m"}' tile.json; sed -i 's/100x100um/1x1pm/' tile.json
expect 1 "tile.json: tile 1 pm x 1 pm: both sides must be at least 1 nm" -- $BIN simulate tile.json --rays 1000 -o s.shbrdf
# Generated scans and the instrument blur: the same ranges on the command line.
expect 2 "error: --spacing: must lie in 1 pm .. 1 m" -- $BIN generate gaussian --nx 64 --ny 64 --spacing 1e-300m -o g.npy
expect 2 "error: --sigma: must lie in 0 .. 1 m" -- $BIN generate gaussian --nx 64 --ny 64 --sigma 1e300m -o g.npy
expect 2 "error: --tau: must lie in 1 pm .. 1 m" -- $BIN generate gaussian --nx 64 --ny 64 --tau 1e300m -o g.npy
# Shares and scales that are not numbers in their range: refused naming the flag, before work.
for v in -1 nan 1.5 1e300; do
  expect 2 "error: --min-support: must be in \[0, 1\] (got $v)" -- $BIN ndf scan.npy --min-support $v -o x.npy
done
for v in 0 -1 nan inf; do
  expect 2 "error: --uv-scale: must be in (0, 1e+06\]" -- $BIN render --model ggx --alpha 0.2 --size 8 --spp 1 --uv-scale $v -o r.png
done
expect 2 "error: --instrument-fwhm: must lie in 0 .. 90 deg (got 1e300deg)" -- $BIN ndf scan.npy --instrument-fwhm 1e300deg -o x.npy
[ -e g.npy ] && fail "generate wrote a refused surface"
[ -e s.shbrdf ] && fail "simulate wrote output from a refused scene"

# 2. The file-size limit (100 KiB): reported like a full disk, exit 1, nothing left behind.
small=(bash -c 'ulimit -f 100; exec "$@"' small)
tiny=(bash -c 'ulimit -f 8; exec "$@"' tiny)  # the EXR table is compressed to 36 KiB
$BIN generate gaussian --nx 256 --ny 256 --spacing 1um -o big.x3p >/dev/null 2>&1 || fail "generate big"
$BIN export bsdf --model ggx --alpha 0.3 --metal Al -o ok.bsdf >/dev/null 2>&1 || fail "export small"
expect 1 "x.npy: the file size limit (ulimit -f: 100 KiB) was reached" -- "${small[@]}" $BIN ndf scan.npy -o x.npy
expect 1 "x.exr: the file size limit (ulimit -f: 8 KiB) was reached" -- "${tiny[@]}" $BIN ndf scan.npy -o x.exr
expect 1 "x.npy: the file size limit" -- "${small[@]}" $BIN convert big.x3p x.npy
expect 1 "x.txt: the file size limit" -- "${small[@]}" $BIN convert big.x3p x.txt
expect 1 "x.bsdf: the file size limit" -- "${small[@]}" $BIN export bsdf --model ggx --alpha 0.3 --metal Al -o x.bsdf
expect 1 "rep.*: the file size limit" -- "${small[@]}" $BIN predict scan.npy --no-render --resolution 257 -o rep
expect 1 "m.npy: the file size limit" -- "${small[@]}" $BIN measured ndf "$T/ok.bsdf" -o m.npy
expect 1 "s.shbrdf: the file size limit" -- "${small[@]}" $BIN simulate "$HERE/../../examples/scenes/lambert_plane.json" --rays 2000 --lmax 40 -o s.shbrdf
ls | grep -q "^x\.\|^rep$\|^m\.npy$\|^s\.shbrdf$" && fail "an output was written past the limit: $(ls)"

# 3. Budgets and hangs.
# A filter sigma of 1000 m under --max-memory 256M (once 4.2 GB and over 60 s): beyond any scan
# (1 m); 0.5 m, longer than this scan, is refused naming the scan.
expect 2 "error: --filter-sigma: must lie in 1 pm .. 1 m (got 1000m)" -- \
  $BIN --max-memory 256M ndf scan.npy --filter-sigma 1000m -o x.npy
expect 1 "scan.npy: filter sigma 500 mm is longer than the scan" -- \
  $BIN --max-memory 256M ndf scan.npy --filter-sigma 0.5m -o x.npy
# Within the scan's length but the kernel's working rows (6000 rows high) are over a small budget.
expect 1 "strip.npy: needs .* for the filtered normals' working buffers .* over the memory budget of 40 MiB" -- \
  $BIN --max-memory 40M ndf strip.npy --filter-sigma 5mm -o x.npy
# Kirchhoff on a scan with 2 mm of form: the series would need tens of GiB.
expect 1 "form.npy: Kirchhoff: the heights of a patch span .* over the memory budget of 256 MiB (--max-memory)" -- \
  $BIN --max-memory 256M ndf form.npy --method kirchhoff -o x.npy
# Patches of 1 pm: one D_K table per sample (64 x 64 of them) would take minutes.
expect 1 "scan.npy: Kirchhoff patch .* patches of 1 x 1 samples; a patch needs at least 4 samples a side (--patch)" -- \
  $BIN ndf scan.npy --method kirchhoff --patch 1x1pm -o x.npy
# A patch so small that the tile count overflows every integer: refused the same way, no
# arithmetic exception (the count was once converted from 1e295 to 0 and divided by).
# The flag is refused below 1 pm; the library's own check (Python reaches it) is in
# python/tests/test_hostile_numbers.py.
expect 2 "error: --patch: must lie in 1 pm .. 1 m (got 1e-300x1e-300m)" -- \
  $BIN ndf scan.npy --method kirchhoff --patch 1e-300x1e-300m -o x.npy
# 300000 goniometer rows (about 70 MB parsed) under a 32 MiB budget: refused before parsing.
expect 1 "many.csv: needs .* for up to 300002 goniometer rows .* over the memory budget of 32 MiB" -- \
  $BIN --max-memory 32M measured ndf many.csv -o x.npy
# Negative, overflowing and octal-looking counts: refused at parse time naming the flag (exit 2).
SC=$HERE/../../examples/scenes/cylinders.json
expect 2 "\-\-rays: must be a whole number >= 0" -- $BIN simulate "$SC" --rays -1 -o s.shbrdf
expect 2 "\-\-rays: must be a whole number" -- $BIN simulate "$SC" --rays 18446744073709551616 -o s.shbrdf
expect 2 "\-\-rays: must be a whole number" -- $BIN simulate "$SC" --rays 0x10 -o s.shbrdf
expect 2 "\-\-points: must be a whole number" -- $BIN simulate "$SC" --points -5 -o s.shbrdf
expect 2 "\-\-threads: must be a whole number" -- $BIN simulate "$SC" --threads -1 -o s.shbrdf
expect 2 "\-\-resolution: must be a whole number" -- $BIN ndf scan.npy --resolution -1 -o x.npy
expect 2 "\-\-nx: must be a whole number" -- $BIN generate gaussian --nx -64 -o g.npy
expect 2 "\-\-spp: must be a whole number" -- $BIN render --alpha 0.3 --spp -1 -o r.png
expect 2 "\-\-max-depth: must be a whole number" -- $BIN render --alpha 0.3 --max-depth -2 -o r.png
expect 2 "\-\-render-width: must be a whole number" -- $BIN predict scan.npy --render-width -256 -o rep
expect 2 "\-\-lmax: must be a whole number" -- $BIN simulate "$SC" --lmax 99999999999999999999 -o s.shbrdf
# Leading zeros are decimal, not octal: --nx 010 is 10 samples.
$BIN generate gaussian --nx 010 --ny 010 -o g10.npy --json >g10.json 2>&1 || fail "generate --nx 010: $(cat g10.json)"
/usr/bin/python3 -c "import numpy as np, sys; s = np.load('g10.npy').shape; sys.exit(s != (10, 10))" \
  || fail "--nx 010 did not give 10 samples"
# A plane far above its tile (once 150 rays/s): refused before tracing.
scene '{"type": "plane", "z": "1e6m", "material": "m"}' far.json
expect 1 "far.json: plane 1: z = 1e+06 m must lie within 10 mm" -- $BIN simulate far.json --rays 1000 -o s.shbrdf
[ -e s.shbrdf ] || [ -e x.npy ] || [ -e r.png ] && fail "output written despite a refusal"
echo ok
