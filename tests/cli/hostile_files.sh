#!/usr/bin/env bash
# Hostile files, second round: JSON that is long rather than deep, data whose problems must be
# blamed on the input file (not the output), outputs that would replace an input, and file
# names that must not break out of the strings of exported scenes. Every case ends within 10 s
# under 1 GB of RSS, with a clean exit (or a run that says what it did) and a message naming
# the file or the flag, and leaves no temporary behind.
set -u
export LC_ALL=C  # messages hold file names that are not UTF-8: grep them as bytes
BIN=$1
HERE=$(cd "$(dirname "$0")" && pwd)
PY=/usr/bin/python3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# expect CODE PATTERN -- CMD...: exit code CODE ("nz": any non-zero), stderr matches PATTERN,
# no internal error / bare std:: message, max RSS < 1 GiB, at most 10 s, no temporaries left.
HOSTILE_DIR=$T
. "$HERE/lib/hostile_expect.bash"
# Every case under 3 GB of address space as well (a bomb must be refused, not attempted).
expect() { VMEM_LIMIT_KIB=3000000 hostile_run "$@"; }
same() { cmp -s "$1" "$2" || fail "$1 was changed"; }

$BIN generate gaussian --nx 48 --ny 48 --spacing 1um --sigma 0.1um --tau 5um -o "$T/g.npy" >/dev/null 2>&1 || fail "generate"
$BIN tabulate --model ggx --alpha 0.3 --resolution 65 -o "$T/p.npy" >/dev/null 2>&1 || fail "tabulate"

# 1. JSON that is long, not deep: 3 MB of {} parse in linear time, wherever JSON is read.
$PY - "$T" <<'PY'
import sys
t = sys.argv[1]
flat = "[" + ",".join(["{}"] * 1000000) + "]"
open(t + "/flat_scene.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": ' + flat + '}')
open(t + "/flat_note.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, '
    '"objects": [{"type": "plane", "material": "m"}], "note": ' + flat + '}')
import shutil
for stem in ("gflat", "pflat"):
    shutil.copy(t + ("/g.npy" if stem == "gflat" else "/p.npy"), t + "/" + stem + ".npy")
side = open(t + "/g.json").read().rstrip().rstrip("}")
open(t + "/gflat.json", "w").write(side + ', "junk": ' + flat + "}")
side = open(t + "/p.json").read().rstrip().rstrip("}")
open(t + "/pflat.json", "w").write(side + ', "junk": ' + flat + "}")
# One level past the limit inside a flat megabyte: still refused.
open(t + "/gdeep.json", "w").write('{"dx_m": 1e-6, "junk": [' + ",".join(["{}"] * 300000) + "," +
                                   "[" * 64 + "]" * 64 + "]}")
shutil.copy(t + "/g.npy", t + "/gdeep.npy")
PY
expect 1 "flat_scene.json: " -- $BIN simulate "$T/flat_scene.json" -o "$T/f.shbrdf" --rays 100
$BIN simulate "$T/flat_note.json" -o "$T/f.shbrdf" --rays 200 --lmax 2 -q 2>"$T/err" >/dev/null
rc=$?; { [ $rc -eq 0 ] || grep -q "flat_note.json" "$T/err"; } || fail "flat_note.json: $(cat "$T/err")"
expect 0 "" -- $BIN info "$T/gflat.npy"
grep -q "48 x 48" "$T/.out" || fail "info on a 3 MB sidecar: $(cat "$T/.out")"
expect 0 "" -- $BIN fit "$T/pflat.npy" --model ggx
expect 1 "gdeep.json: JSON nested deeper than 64 levels" -- $BIN info "$T/gdeep.npy"
rm -f "$T"/f.shbrdf

# 2. Data problems name the input file, never the output.
gonio() {  # gonio FILE ROWS... : a goniometer CSV with the standard header
  local f=$1; shift
  printf 'theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n' >"$T/$f"
  for r in "$@"; do printf '%s\n' "$r" >>"$T/$f"; done
}
rows=(); for ti in 0 10 20 30; do for to in 5 15 25 35; do for po in 160 180 200; do
  rows+=("$ti,0,$to,$po,550,2.5"); done; done; done
gonio ok.csv "${rows[@]}"
gonio neg.csv "${rows[@]}" "10,0,12,180,550,-0.25"
expect 1 "neg.csv: line 50: brdf_per_sr is negative" -- $BIN measured ndf "$T/neg.csv" --resolution 65 -o "$T/out.npy"
gonio one.csv "10,0,10,180,550,1" "10,0,10,180,550,2" "10,0,10,180,550,3"
expect 1 "one.csv: the goniometer points share one half vector" -- $BIN measured ndf "$T/one.csv" --resolution 65 -o "$T/out.npy"
gonio horizon.csv "10,0,90,180,550,1" "20,0,90,180,550,2"
expect 1 "horizon.csv: no goniometer point with both directions above the horizon" -- $BIN measured ndf "$T/horizon.csv" --resolution 65 -o "$T/out.npy"
expect 2 "\-\-kernel: must lie in 0 .. 30 deg" -- $BIN measured ndf "$T/ok.csv" --kernel 1e300deg --resolution 65 -o "$T/out.npy"
expect 2 "\-\-kernel: must lie in" -- $BIN measured ndf "$T/ok.csv" --kernel -1deg --resolution 65 -o "$T/out.npy"
expect 1 "ok.csv: no node of the 65 x 65 table lies within two kernel widths" -- $BIN measured ndf "$T/ok.csv" --kernel 1e-9deg --resolution 65 -o "$T/out.npy"
# A byte-order mark (spreadsheets) is skipped; a file measured at 1000 nm only is used at 550 nm
# with a warning naming the file and both wavelengths.
{ printf '\xef\xbb\xbf'; cat "$T/ok.csv"; } >"$T/bom.csv"
expect 0 "" -- $BIN measured ndf "$T/bom.csv" --resolution 65 -o "$T/bom.npy"
sed 's/,550,/,1000,/' "$T/ok.csv" >"$T/ir.csv"
expect 0 "ir.csv: warning: measured at 1000.0 nm, not at the requested 550.0 nm" -- $BIN measured ndf "$T/ir.csv" --resolution 65 -o "$T/ir.npy"
[ -e "$T/out.npy" ] && fail "an NDF was written from a refused input"
# MERL files: all negative ("no data" everywhere) and all zero: refused, naming the file.
$PY - "$T" <<'PY'
import struct, sys, numpy as np
t = sys.argv[1]
n = 90 * 90 * 180
for name, v in (("neg.binary", -1.0), ("zero.binary", 0.0)):
    with open(t + "/" + name, "wb") as f:
        f.write(struct.pack("<3i", 90, 90, 180))
        np.full(3 * n, v, "<f8").tofile(f)
# An effective-NDF table without a measured node (NaN inside the disk).
x = np.linspace(-1, 1, 65)
z = np.where(x[None, :] ** 2 + x[:, None] ** 2 < 1, np.nan, 0.0)
np.save(t + "/nan.npy", z)
PY
expect 1 "neg.binary: the file holds no valid BRDF value" -- $BIN measured ndf "$T/neg.binary" --resolution 65 -o "$T/out.npy"
expect 1 "zero.binary: the BRDF has no positive value" -- $BIN export bsdf "$T/zero.binary" --theta-i 2 --samples 2 --ndf-grid 3 --wavelengths 2 --isotropic -o "$T/out.bsdf"
expect 1 "nan.npy: the NDF table holds no positive value" -- $BIN measured compare "$T/nan.npy" "$T/p.npy"
rm -f "$T"/*.binary
# An RGL .bsdf whose spectra are negative: the .bsdf is blamed, not out.npy.
$BIN export bsdf --alpha 0.3 --metal Al --theta-i 4 --samples 8 --ndf-grid 8 --wavelengths 3 --isotropic -o "$T/pos.bsdf" >/dev/null 2>&1 || fail "export bsdf"
$PY - "$T" <<'PY'
import struct, sys
t = sys.argv[1]
b = bytearray(open(t + "/pos.bsdf", "rb").read())
assert b[:12] == b"tensor_file\0", b[:12]
count = struct.unpack_from("<I", b, 14)[0]
p, sizes = 18, {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 8, 8: 8, 9: 4, 10: 8}
for _ in range(count):
    ln = struct.unpack_from("<H", b, p)[0]; name = b[p + 2:p + 2 + ln].decode(); p += 2 + ln
    ndim, dtype, off = struct.unpack_from("<HBQ", b, p); p += 11
    shape = struct.unpack_from("<%dQ" % ndim, b, p); p += 8 * ndim
    if name == "spectra":
        assert dtype == 10  # float32
        k = 1
        for s in shape: k *= s
        vals = struct.unpack_from("<%df" % k, b, off)
        struct.pack_into("<%df" % k, b, off, *[-abs(v) - 1e-3 for v in vals])
open(t + "/negative.bsdf", "wb").write(b)
PY
expect 1 "negative.bsdf: " -- $BIN measured ndf "$T/negative.bsdf" --resolution 65 -o "$T/out.npy"
grep -q "out.npy" "$T/.err" && fail "the output is blamed for the input's negative values: $(cat "$T/.err")"
# A height field that does not fit the scene's tile: the scene file is named.
cp "$T/g.npy" "$T/hf.npy"; cp "$T/g.json" "$T/hf.json"
printf '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [{"type": "heightfield", "file": "hf.npy", "material": "m"}]}' >"$T/hf_scene.json"
expect 1 "hf_scene.json: micro-scene: height field extent .* does not match the tile" -- $BIN simulate "$T/hf_scene.json" -o "$T/f.shbrdf" --rays 100
[ -e "$T/f.shbrdf" ] && fail "simulate wrote output from a refused scene"

# 3. Outputs that resolve to an input of the run are refused; the input stays as it was.
cp "$T/g.npy" "$T/g0.npy"; cp "$T/g.json" "$T/g0.json"
expect 1 "g.npy: is an input of this run" -- $BIN ndf "$T/g.npy" --resolution 65 -o "$T/g.npy"
same "$T/g.npy" "$T/g0.npy"; same "$T/g.json" "$T/g0.json"
ln -s g.npy "$T/link.npy"; ln -s "$T" "$T/dir"
expect 1 "link.npy: is the input .*g.npy of this run" -- $BIN ndf "$T/g.npy" --resolution 65 -o "$T/link.npy"
expect 1 "is the input .*g.npy of this run" -- $BIN ndf "$T/g.npy" --resolution 65 -o "$T/dir/./g.npy"
expect 1 "is the input .*g.\(npy\|json\) of this run" -- $BIN convert "$T/g.npy" "$T/dir/g.npy"
# The sidecar: writing h.npy would replace h.json, a hard link to the scan's sidecar.
ln "$T/g.json" "$T/h.json"
expect 1 "h.json: is the input .*g.json of this run" -- $BIN ndf "$T/g.npy" --resolution 65 -o "$T/h.npy"
[ -e "$T/h.npy" ] && fail "h.npy written although its sidecar was refused"
same "$T/g.npy" "$T/g0.npy"; same "$T/g.json" "$T/g0.json"
cp "$T/pos.bsdf" "$T/pos0.bsdf"
expect 1 "pos.bsdf: is an input of this run" -- $BIN export bsdf "$T/pos.bsdf" --theta-i 4 --samples 8 --ndf-grid 8 --wavelengths 3 -o "$T/pos.bsdf"
same "$T/pos.bsdf" "$T/pos0.bsdf"
rm -f "$T/link.npy" "$T/dir" "$T/h.json"

# 4. File names in exported scenes: pbrt strings and XML attributes read back byte for byte.
$PY - "$T" <<'PY'
import os, sys
t = sys.argv[1].encode()
names = [b'q"uote', b'back\\slash', b'new\nline', b'amp&lt;<gt>', b"apos'", b'tab\t',
         '\u00e9t\u00e9 \u65e5\u672c'.encode(), b'all " \\ \n & < > \' \\n']
open(t + b"/names", "wb").write(b"\0".join(names))
for n in names:
    os.link(t + b"/pos.bsdf", t + b"/" + n + b".bsdf")
os.link(t + b"/pos.bsdf", t + b"/caf\xe9.bsdf")  # not UTF-8
PY
# The tokenizer of pbrt-v4 (src/pbrt/parser.cpp): strings end at an unescaped quote, a raw
# newline inside one is an error, backslash escapes b f n r t \ ' "; '#' comments to end of line.
cat >"$T/pbrt_name.py" <<'PY'
import sys
def tokens(b):
    i, out = 0, []
    while i < len(b):
        c = b[i:i + 1]
        if c in b" \n\t\r": i += 1
        elif c == b"#":
            while i < len(b) and b[i:i + 1] not in b"\n\r": i += 1
        elif c == b'"':
            s, i = b"", i + 1
            while True:
                if i >= len(b): sys.exit("premature end of file in a string")
                c = b[i:i + 1]
                if c == b'"': break
                if c == b"\n": sys.exit("unterminated string (raw newline)")
                if c == b"\\":
                    i += 1
                    e = b[i:i + 1]
                    m = {b"b": b"\b", b"f": b"\f", b"n": b"\n", b"r": b"\r", b"t": b"\t",
                         b"\\": b"\\", b"'": b"'", b'"': b'"'}
                    if e not in m: sys.exit("unexpected escaped character %r" % e)
                    s += m[e]
                else: s += c
                i += 1
            out.append(("q", s)); i += 1
        elif c in b"[]": out.append(("b", c)); i += 1
        else:
            e = i
            while e < len(b) and b[e:e + 1] not in b' \n\t\r"[]#': e += 1
            out.append(("b", b[i:e])); i = e
    return out
tok = tokens(open(sys.argv[1], "rb").read())
for k in range(len(tok) - 3):
    if tok[k] == ("b", b"Material") and tok[k + 1] == ("q", b"measured") and tok[k + 2] == ("q", b"string filename"):
        sys.stdout.buffer.write(tok[k + 3][1]); sys.exit(0)
sys.exit("no Material \"measured\" \"string filename\"")
PY
cat >"$T/xml_name.py" <<'PY'
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
for b in root.iter("bsdf"):
    if b.get("id") == "microbrdf":
        sys.stdout.buffer.write(b.find("string").get("value").encode()); sys.exit(0)
sys.exit("no bsdf")
PY
i=0
while IFS= read -r -d '' name || [ -n "$name" ]; do
  i=$((i + 1))
  rm -rf "$T/xp" "$T/xm"
  expect 0 "" -- $BIN export pbrt --bsdf "$T/$name.bsdf" -o "$T/xp"
  $PY "$T/pbrt_name.py" "$T/xp/scene.pbrt" >"$T/got" || fail "pbrt scene for name $i does not tokenize"
  printf '%s.bsdf' "$name" | cmp -s - "$T/got" || fail "pbrt name $i read back as $(cat -A "$T/got")"
  expect 0 "" -- $BIN export mitsuba --bsdf "$T/$name.bsdf" -o "$T/xm"
  $PY "$T/xml_name.py" "$T/xm/scene.xml" >"$T/got" || fail "mitsuba scene for name $i does not parse"
  printf '%s.bsdf' "$name" | cmp -s - "$T/got" || fail "mitsuba name $i read back as $(cat -A "$T/got")"
done <"$T/names"
[ $i -eq 8 ] || fail "read $i names, not 8"
rm -rf "$T/xp" "$T/xm"
expect 0 "" -- $BIN export pbrt --bsdf "$T/caf"$'\xe9'".bsdf" -o "$T/xp"
$PY "$T/pbrt_name.py" "$T/xp/scene.pbrt" >"$T/got" || fail "pbrt: latin-1 name"
printf 'caf\xe9.bsdf' | cmp -s - "$T/got" || fail "pbrt: latin-1 name read back as $(cat -A "$T/got")"
expect 1 "caf.*\.bsdf: the name holds bytes that are not UTF-8" -- $BIN export mitsuba --bsdf "$T/caf"$'\xe9'".bsdf" -o "$T/xm"
[ -e "$T/xm/scene.xml" ] && fail "mitsuba scene written with a name XML cannot hold"
rm -rf "$T/xp" "$T/xm"
# 5. Signals and limits that end a run say so.
# SIGINT: exit 130 with one line saying so, no output, no temporary.
$PY - "$BIN" "$T" <<'PY' || fail "SIGINT"
import os, signal, subprocess, sys, time
bin, t = sys.argv[1:3]
p = subprocess.Popen([bin, "render", "--alpha", "0.3", "--size", "512", "--spp", "100000",
                      "-o", t + "/int.png"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
time.sleep(1.0)
p.send_signal(signal.SIGINT)
err = p.communicate(timeout=30)[1].decode(errors="replace")
assert p.returncode == 130, (p.returncode, err)
assert err.count("microbrdf: interrupted (SIGINT)") == 1, err
left = [f for f in os.listdir(t) if f.startswith("int.png")]
assert not left, left
print("case: SIGINT: exit 130, said once, nothing left")
PY
# Address space too small for the renderer's Embree device (the libraries load in ~100 MB, the
# device needs ~300 MB): said as out of memory, with the limit, never an internal error.
(ulimit -v 200000; $BIN render --alpha 0.3 --size 8 --spp 1 -o "$T/v.png") >/dev/null 2>"$T/err"
rc=$?
if [ $rc -eq 127 ]; then
  echo "case: ulimit -v 200000: the libraries of this build do not load in 195 MiB; skipped"
else
  [ $rc -eq 1 ] || fail "ulimit -v 200000: exit $rc: $(cat "$T/err")"
  grep -q "internal error\|std::" "$T/err" && fail "ulimit -v 200000: $(cat "$T/err")"
  grep -q "error: .*out of memory or address space.*ulimit -v) is 195 MiB" "$T/err" ||
    fail "ulimit -v 200000: $(cat "$T/err")"
  [ -e "$T/v.png" ] && fail "ulimit -v 200000: an image was written"
  echo "case: ulimit -v 200000: exit 1: $(cat "$T/err")"
fi

echo ok
