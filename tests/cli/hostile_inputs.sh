#!/usr/bin/env bash
# Hostile inputs: small files that claim huge sizes, deep JSON, absurd numbers and counts,
# non-regular files. Each one ends with a clean non-zero exit and a message naming the file (or
# the flag), never a crash or a bare "std::" message, and never a multi-gigabyte allocation:
# the readers run under a 3 GB address-space limit here, so a reader that allocates what a
# header claims fails this test instead of swamping the machine.
set -u
BIN=$1 DATA=$2
HERE=$(cd "$(dirname "$0")" && pwd)
MAKE="/usr/bin/python3 $HERE/make_hostile.py"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# expect CODE PATTERN -- CMD...: exit code CODE (any non-zero when "nz"), stderr matches PATTERN,
# no internal error / bare std:: message, max RSS < 1 GiB, at most 20 s, no temporaries left
# (tests/cli/lib/hostile_expect.bash), under a 3 GB address-space limit.
HOSTILE_DIR=$T
. "$HERE/lib/hostile_expect.bash"
expect() { VMEM_LIMIT_KIB=3000000 LIMIT_SECONDS=20 hostile_run "$@"; }

# 1. Small files that claim gigabytes: refused before the allocation, naming the file and size.
$MAKE x3p-zeros "$T/zeros.x3p" 6000
expect 1 "zeros.x3p: a file of .* asks for 446 MiB for a height map of 36000000 samples" -- $BIN info "$T/zeros.x3p"
# --max-memory lifts the expansion rule but keeps a cap.
expect 1 "zeros.x3p: needs .* over the memory budget of 64 MiB (--max-memory)" -- $BIN info "$T/zeros.x3p" --max-memory 64M
expect nz "max-memory" -- $BIN info "$T/zeros.x3p" --max-memory lots
$MAKE x3p-datalist "$T/list.x3p" 5000000
expect 1 "list.x3p: .*main.xml and its document tree" -- $BIN info "$T/list.x3p"
$MAKE tiff-deflate "$T/junk.tif" 16000
expect 1 "junk.tif: .*asks for" -- $BIN info "$T/junk.tif" --spacing 1um
$MAKE exr-junk "$T/junk.exr" 16384
expect 1 "junk.exr: .*asks for" -- $BIN info "$T/junk.exr" --spacing 1um
$MAKE paramtex-junk "$T/params.exr" 16384
expect 1 "params.exr: .*parameter texture of 16384 x 16384" -- $BIN render --texture "$T/params.exr" --size 8 --spp 1 -o "$T/p.png"
[ -e "$T/p.png" ] && fail "render wrote an image from a refused texture"

# 2. Deep JSON: refused at parse time wherever JSON is read (scene, .npy sidecar).
$BIN generate gaussian --nx 32 --ny 32 -o "$T/g.npy" >/dev/null 2>&1 || fail "generate npy"
/usr/bin/python3 - "$T" "$HERE/../../fuzz/corpus/shbrdf" <<'PY'
import json, sys
t = sys.argv[1]
deep = '{"a":' * 1000000 + '1' + '}' * 1000000
open(t + "/deep_scene.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, '
    '"objects": [{"type": "plane", "material": "m"}], "note": ' + deep + '}')
open(t + "/g.json", "w").write('{"dx_m": 1e-6, "x": ' + '[' * 200000 + ']' * 200000 + '}')
# A .shbrdf whose header "meta" nests 200000 objects (the header is copied into the BRDF).
import struct
src = open(sys.argv[2] + "/lambert_l2.shbrdf", "rb").read()
n = struct.unpack("<I", src[8:12])[0]
head = json.loads(src[12:12 + n])
text = json.dumps(head)[:-1] + ', "note": ' + '{"a":' * 200000 + '1' + '}' * 200000 + '}'
open(t + "/deep.shbrdf", "wb").write(src[:8] + struct.pack("<I", len(text)) + text.encode() + src[12 + n:])
PY
expect 1 "deep_scene.json: JSON nested deeper than 64 levels" -- $BIN simulate "$T/deep_scene.json" -o "$T/d.shbrdf" --rays 100
expect 1 "g.json: JSON nested deeper than 64 levels" -- $BIN info "$T/g.npy"
expect 1 "deep.shbrdf: JSON nested deeper than 64 levels" -- $BIN render --sh "$T/deep.shbrdf" --size 8 --spp 1 -o "$T/d.png"
[ -e "$T/d.shbrdf" ] || [ -e "$T/d.png" ] && fail "output written from a refused input"

# 3. Scene counts: 64-bit, bounded; absurd sizes name the file and key.
scene() { printf '{"tile": "%s", "materials": {"m": {"type": "mirror"}}, "objects": [%s]}' "$1" "$2" >"$T/$3"; }
scene 1x1mm '{"type": "cylinders", "radius": "1um", "count": 2000000000, "material": "m"}' c2e9.json
expect 1 "c2e9.json: 'count' is 2000000000; it must lie in 1..33554432" -- $BIN simulate "$T/c2e9.json" -o "$T/c.shbrdf" --rays 100
scene 1x1mm '{"type": "cylinders", "radius": "1um", "count": 4294967304, "material": "m"}' cwrap.json
expect 1 "cwrap.json: 'count' is 4294967304" -- $BIN simulate "$T/cwrap.json" -o "$T/c.shbrdf" --rays 100
scene 1x1mm '{"type": "fibers", "radius": "1um", "length": "10um", "count": 2000000000, "material": "m"}' f2e9.json
expect 1 "f2e9.json: 'count' is 2000000000" -- $BIN simulate "$T/f2e9.json" -o "$T/c.shbrdf" --rays 100
scene 2x2um '{"type": "weave", "pitch": "1um", "radius": "0.2um", "crimp": "0.3um", "segments": 2000000000, "material": "m"}' weave.json
expect 1 "weave.json: 'segments' is 2000000000" -- $BIN simulate "$T/weave.json" -o "$T/c.shbrdf" --rays 100
scene 1x1mm '{"type": "heightfield", "generate": {"kind": "gaussian", "nx": -1, "spacing": "1um", "sigma": "0.1um", "tau": "5um"}, "material": "m"}' nx.json
expect 1 "nx.json: 'nx' is -1; it must lie in 2..32768" -- $BIN simulate "$T/nx.json" -o "$T/c.shbrdf" --rays 100
scene 000x500um '{"type": "plane", "material": "m"}' tile0.json
expect 1 "tile0.json: .*tile: both sides must be > 0" -- $BIN simulate "$T/tile0.json" -o "$T/c.shbrdf" --rays 100
[ -e "$T/c.shbrdf" ] && fail "simulate wrote output from a refused scene"

# 4. Absurd finite heights: an error naming the file and the sample, before any arithmetic.
/usr/bin/python3 - "$T" <<'PY'
import json, sys
import numpy as np
t = sys.argv[1]
z = np.random.default_rng(1).normal(0, 1e-7, (64, 64)); z[10, 20] = 1e308
np.save(t + "/huge.npy", z); json.dump({"dx_m": 1e-6, "dy_m": 1e-6}, open(t + "/huge.json", "w"))
np.save(t + "/one.npy", np.zeros((1, 1))); json.dump({"dx_m": 1e-6}, open(t + "/one.json", "w"))
z = np.full((200, 200), np.nan); z[0:4, 0:4] = np.arange(16).reshape(4, 4) * 1e-8
np.save(t + "/sparse.npy", z); json.dump({"dx_m": 1e-6}, open(t + "/sparse.json", "w"))
np.save(t + "/bigtab.npy", np.full((65, 65), 1e308))
np.save(t + "/zerotab.npy", np.zeros((65, 65)))
PY
for cmd in "info" "ndf --resolution 65 -o $T/h.npy" "convert --level plane $T/h.x3p" "predict --no-render --resolution 65 -o $T/hp"; do
  set -- $cmd
  sub=$1; shift
  expect 1 "huge.npy: height 1e+308 m at sample (x 20, y 10) is absurd" -- $BIN $sub "$T/huge.npy" "$@"
done
[ -e "$T/h.npy" ] || [ -e "$T/h.x3p" ] || [ -e "$T/hp" ] && fail "output written from a refused scan"

# 5. Unbounded arguments: clamped with a note, or refused naming the flag.
$BIN render --alpha 0.3 --size 8 --spp 1 --threads 100000 -o "$T/t.png" 2>"$T/err" || fail "render --threads 100000: $(cat "$T/err")"
grep -q "note: --threads 100000 clamped to" "$T/err" || fail "no note on clamped threads: $(cat "$T/err")"
SC=$HERE/../../examples/scenes/cylinders.json
$BIN simulate "$SC" -o "$T/t.shbrdf" --rays 200 --threads 1000000 -q 2>"$T/err" || fail "simulate --threads 1000000: $(cat "$T/err")"
grep -q "clamped" "$T/err" || fail "simulate: no note on clamped threads"
expect 2 "\-\-branches" -- $BIN simulate "$SC" -o "$T/b.shbrdf" --rays 200 --branches 2147483647
expect 2 "\-\-points" -- $BIN simulate "$SC" -o "$T/b.shbrdf" --rays 200 --points 2147483647
expect 2 "\-\-rays: must be a whole number in \[1, 1e+10\] (got 0)$" -- $BIN simulate "$SC" -o "$T/b.shbrdf" --rays 0
expect 2 "\-\-visibility-samples" -- $BIN simulate "$SC" --visibility --visibility-samples 18446744073709551615
[ -e "$T/b.shbrdf" ] && fail "simulate wrote output despite a refused flag"

# 6. Messages that name the file; non-regular files refused; sparse scans warned about.
expect 1 "/etc/hostname: unrecognised file format" -- $BIN info /etc/hostname
expect 1 "one.npy: .*1 x 1" -- $BIN info "$T/one.npy"
expect 1 "bigtab.npy: NDF values are so large that their integral overflows" -- $BIN fit "$T/bigtab.npy"
expect 1 "zerotab.npy: the NDF table holds no positive value inside the unit disk" -- $BIN render --ndf "$T/zerotab.npy" --size 8 --spp 1 -o "$T/z.png"
# A scan whose every element touches a hole: "no normal could be estimated" names the scan.
/usr/bin/python3 -c "
import numpy as np, json; z = np.zeros((40, 40)); z[::2, :] = np.nan; z[:, ::2] = np.nan
np.save('$T/holes_all.npy', z); json.dump({'dx_m': 1e-6}, open('$T/holes_all.json', 'w'))"
expect 1 "holes_all.npy: no normal could be estimated" -- $BIN ndf "$T/holes_all.npy" --level none --method naive --resolution 65 -o "$T/ha.npy"
mkfifo "$T/fifo.x3p"
expect 1 "fifo.x3p: is not a regular file" -- timeout 20 $BIN info "$T/fifo.x3p"
$BIN info "$T/sparse.npy" >/dev/null 2>"$T/err"
grep -q "sparse.npy: warning: only 0.04% of the samples are valid (16 of 200 x 200)" "$T/err" || fail "no valid-fraction warning: $(cat "$T/err")"
$BIN generate gaussian --nx 48 --ny 48 -o "$T/holes.npy" >/dev/null 2>&1
/usr/bin/python3 -c "
import numpy as np; z = np.load('$T/holes.npy'); z[5:9, 5:9] = np.nan; np.save('$T/holes.npy', z)"
$BIN ndf "$T/holes.npy" --resolution 65 -o "$T/holes_ndf.npy" --json >"$T/out" 2>"$T/err" || fail "ndf with holes: $(cat "$T/err")"
grep -q '"samples_invalid": 16' "$T/out" || fail "ndf --json does not report the 16 invalid samples: $(cat "$T/out")"
$BIN ndf "$T/holes.npy" --resolution 65 -o "$T/holes_ndf.npy" 2>&1 >/dev/null | grep -q "16 of 2304 height samples invalid" || fail "ndf does not report invalid samples"
echo ok
