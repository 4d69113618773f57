#!/usr/bin/env bash
# Every number on the command line is checked against its range before any work, and a command
# line that does not parse is said with what was probably meant:
#  - lengths, angles, wavelengths, counts and plain numbers out of range (NaN, infinities,
#    1e300, negatives, 2^64 - 1) are refused with exit 2, naming the flag and the valid range,
#    in well under a second;
#  - a misspelt subcommand or flag gets the nearest real one; all unknown flags are listed at
#    once; every message starts "microbrdf CMD: error:"; `microbrdf` alone says where to start.
set -u
BIN=$(realpath "$1")
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
cd "$T" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
n=0
# refused PATTERN -- CMD...: exit 2 (CODE=1: exit 1) within 1 s, stderr matching PATTERN, nothing
# written.
refused() {
  local pat=$1; shift 2
  local t0=$SECONDS want=${CODE:-2}
  "$@" >out.txt 2>err.txt </dev/null
  local rc=$?
  [ $rc -eq "$want" ] || fail "exit $rc (want $want) from: $* : $(cat err.txt)"
  grep -Eq -- "$pat" err.txt || fail "stderr does not match /$pat/ from: $*: $(cat err.txt)"
  [ $((SECONDS - t0)) -le 1 ] || fail "took $((SECONDS - t0)) s (a usage check must be instant): $*"
  [ -z "$(ls -A | grep -v '^out.txt$\|^err.txt$\|^in$')" ] || fail "files written by a refused run: $(ls)"
  n=$((n + 1))
}

# Lengths: the flag and the range with SI prefixes.
refused ": error: --tau: must lie in 1 pm \.\. 1 m \(got 1e300m\)" -- $BIN generate gaussian --tau 1e300m -o g.npy
refused ": error: --tau: must lie in 1 pm \.\. 1 m \(got 1e-300m\)" -- $BIN generate gaussian --tau 1e-300m -o g.npy
refused ": error: --sigma: .*'infm'" -- $BIN generate gaussian --sigma infm -o g.npy
refused ": error: --amplitude: must lie in 0 \.\. 1 m" -- $BIN generate grating --amplitude -1um -o g.npy
refused ": error: --spacing: must lie in 1 pm \.\. 1 m" -- $BIN generate gaussian --spacing 1x1e-30m -o g.npy
refused ": error: --spacing: .*has no unit" -- $BIN generate gaussian --spacing 5 -o g.npy
refused ": error: --filter-sigma: must lie in 1 pm \.\. 1 m \(got 1000m\)" -- $BIN ndf x.npy --filter-sigma 1000m -o n.npy
refused ": error: --patch: .*'nan'" -- $BIN ndf x.npy --method kirchhoff --patch nanx1um -o n.npy
refused ": error: --texel: must lie in 1 pm" -- $BIN texture x.npy --texel -1um -o t.exr
# Wavelengths: 100 nm .. 20 um, the range of the optical constants.
refused ": error: --wavelength: must lie in 100 nm \.\. 20 um \(got 1e300m\)" -- $BIN ndf x.npy --wavelength 1e300m -o n.npy
refused ": error: --wavelength: must lie in 100 nm \.\. 20 um" -- $BIN brdf slice --alpha 0.2 --wavelength -1um -o s.csv
refused ": error: --wavelength: must lie in 100 nm" -- $BIN measured ndf x.csv --wavelength 50nm -o n.npy
# Angles: printed in degrees; lists checked item by item.
refused ": error: --angle: must lie in -360 \.\. 360 deg \(got 1e300deg\)" -- $BIN generate gaussian --angle 1e300deg -o g.npy
refused ": error: --phi: must lie in -360 \.\. 360 deg" -- $BIN tabulate --model ggx --alpha 0.1 --phi 1e300deg -o t.npy
refused ": error: --theta-i: must lie in 0 \.\. 90 deg \(got 95deg\)" -- $BIN brdf slice --alpha 0.2 --theta-i 95deg -o s.csv
refused ": error: --theta-i: must lie in 0 \.\. 89.9 deg \(got 120\)" -- $BIN predict x.npy --theta-i 20,120 -o rep
refused ": error: --instrument-fwhm: .*'nandeg'" -- $BIN ndf x.npy --instrument-fwhm nandeg -o n.npy
refused ": error: --azimuth: must lie in -360 \.\. 360 deg" -- $BIN slice x.npy --azimuth 0,1e300deg -o s.svg
# Counts: whole numbers with a budget, the reason said.
refused ": error: --rays: must be a whole number in \[1, 1e\+10\] \(got 18446744073709551615\): beyond 1e10" -- \
  $BIN simulate scene.json --rays 18446744073709551615 -o s.shbrdf
refused ": error: --samples: must be a whole number" -- $BIN brdf slice --alpha 0.2 --samples 18446744073709551615 -o s.csv
refused ": error: --incident: must be a whole number" -- $BIN brdf sh-estimate --lambertian 1 --incident 18446744073709551615
refused ": error: --size: must be a whole number in \[2, 32768\]" -- $BIN texture x.npy --size 1000000 -o t.exr
refused ": error: --lmax: must be a whole number in \[1, 64\]" -- $BIN simulate scene.json --lmax 100000 -o s.shbrdf
refused ": error: --ndf-grid: must be a whole number in \[3, 512\] \(got 2\)" -- $BIN export bsdf --model ggx --alpha 0.3 --metal Al --ndf-grid 2 -o t.bsdf
refused ": error: --nx x --ny: 100000 x 100000 samples is more than 2\^28" -- $BIN generate gaussian --nx 100000 --ny 100000 -o g.npy
# Plain numbers.
refused ": error: --alpha: must be in \(0, 10\] \(got 1e300\)" -- $BIN tabulate --model ggx --alpha 1e300 -o t.npy
refused ": error: --n: must be in \(0, 1000\]" -- $BIN brdf slice --alpha 0.2 --n 1e300 --k 1 -o s.csv
refused ": error: --s: must be in \(0, 1000\]" -- $BIN sun ftp --s 1e300 -o f.csv
refused ": error: --exposure: must be in \[-64, 64\]" -- $BIN render --alpha 0.2 --exposure nan -o r.png
refused ": error: --env-scale: must be in \(0, 1e\+06\]" -- $BIN render --alpha 0.2 --env-scale 1e300 -o r.png
# A memory budget the output cannot fit in: said before the work (the images, the table).
CODE=1 refused "error: render: needs 320 MiB for the images \(4096 x 4096 pixels\), over the memory budget of 16 MiB \(--max-memory\)" -- \
  $BIN --max-memory 16M render --alpha 0.3 --size 4096 --spp 1 -o r.png
CODE=1 refused "an NDF table: needs 512 MiB for 8193 x 8193 nodes, over the memory budget of 8 MiB \(--max-memory\)" -- \
  $BIN --max-memory 8M tabulate --model ggx --alpha 0.3 --resolution 8193 -o t.npy

# Parse errors: the command's prefix, the nearest real name, every unknown flag, the help.
refused "^microbrdf: error: unknown command 'ndff' \(did you mean 'ndf'\?\); the commands: .*predict" -- $BIN ndff x.npy
refused "^microbrdf generate: error: unknown command 'gausian' \(did you mean 'gaussian'\?\)" -- $BIN generate gausian -o g.npy
refused "^microbrdf brdf: error: give a command: .*slice" -- $BIN brdf --alpha 0.2
refused "^microbrdf ndf: error: unknown flags --resolutoin \(did you mean --resolution\?\), --filter-sigmaa \(did you mean --filter-sigma\?\), --zzzzzzzz$" -- \
  $BIN ndf x.npy --resolutoin 65 --filter-sigmaa 1um --zzzzzzzz -o n.npy
grep -q "^Run 'microbrdf ndf --help' for the options and examples.$" err.txt || fail "no pointer to the help: $(cat err.txt)"
refused "^microbrdf render: error: --tau-x|^microbrdf render: error: unknown flag --alpha-z \(did you mean --alpha-x\?\)" -- $BIN render --alpha-z 0.2 -o r.png
refused "^microbrdf tabulate: error: --alpha: must be in" -- $BIN tabulate --alpha -1 -o t.npy
refused "Start here: .make demo." -- $BIN
# Several bad values: all of them, each with its flag and range (CLI11 alone stops at the first).
refused "^microbrdf ndf: error: 3 values refused: --resolution: must be a whole number in \[17, 8193\] \(got 4\); --filter-sigma: must lie in 1 pm \.\. 1 m \(got -1um\); --window: " -- \
  $BIN ndf x.npy --resolution 4 --filter-sigma=-1um --window hamming -o n.npy
refused "^microbrdf predict: error: 2 values refused: --spp: .*\(got abc\); --render-width: .*\(got 0\)$" -- \
  $BIN predict x.npy --spp abc --render-width 0 -o r
# Outputs are checked before the work: a D_K that takes minutes refuses a .png table at once.
mkdir in && $BIN generate gaussian --nx 128 --ny 128 --spacing 0.25um -o in/g.x3p >/dev/null 2>&1 || fail "generate"
refused "error: -o: ndf.png: unknown extension '.png' \(expected .npy, .exr\)" -- \
  $BIN ndf in/g.x3p --method kirchhoff --resolution 1025 -o ndf.png
# ... a valid comma list is not among them (each item is checked), a flag takes no value, and
# unknown flags come first.
refused "^microbrdf info: error: unknown flag --bogus; 2 values refused: --wavelength: .*\(got 5m\); --theta-i: .*\(got 95\)$" -- \
  $BIN info x.npy --json --wavelength 405nm,633nm,5m --theta-i 95 --bogus
refused "^microbrdf info: error: 2 values refused: --theta-i: .*\(got 95\); --spacing: " -- \
  $BIN info x.npy --json --wavelength 405nm,633nm --theta-i 0,95 --spacing 5
# generate and convert check their outputs before making or reading heights.
refused "error: -o: nodir/g.npy: .*(folder|directory)" -- $BIN generate gaussian --nx 4096 --ny 4096 -o nodir/g.npy
refused "error: --preview: g.jpg: unknown extension" -- $BIN generate gaussian -o g.npy --preview g.jpg
refused "error: output: c.png: cannot write a height map as '.png'" -- $BIN convert in/g.x3p c.png
# predict without a material says which it assumes (every number depends on it).
$BIN predict in/g.x3p --no-render --resolution 65 --quiet -o rep >/dev/null 2>err.txt || fail "predict: $(cat err.txt)"
grep -q "note: no material given: iron (Fe) assumed .* give --metal" err.txt || fail "no note on the assumed metal: $(cat err.txt)"
$BIN predict in/g.x3p --no-render --resolution 65 --quiet --metal Al -o rep2 >/dev/null 2>err.txt || fail "predict Al"
grep -q "assumed" err.txt && fail "a note on the metal although --metal was given"
rm -rf in rep rep2
echo "ok: $n command lines refused before any work, each naming its flag or the nearest name"
