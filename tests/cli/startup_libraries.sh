#!/usr/bin/env bash
# The CLI does not link libhdf5, libtiff or Cairo (their ~50 dependent libraries cost every
# process about 14 ms at start): each is loaded by its soname when a .datx, a TIFF or a plot
# first needs it (src/core/runtime_library.hpp). Checked on the binary's dynamic section and on
# what the dynamic loader reports opening (LD_DEBUG=files) in real runs.
set -u
BIN=$1 DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

needed=$(readelf -d "$BIN" | grep NEEDED) || fail "readelf -d $BIN"
for lib in libhdf5 libtiff libcairo libcurl; do
  ! grep -q "$lib" <<<"$needed" || fail "$BIN links $lib: $(grep "$lib" <<<"$needed")"
done

# loaded: the sonames the dynamic loader opened during a run (stderr of LD_DEBUG=files)
loaded() { LD_DEBUG=files "$@" 2>&1 >/dev/null | grep -o 'file=[^ ]*' | sort -u; }

# A command that needs none of them maps none of them.
$BIN generate gaussian --nx 64 --ny 64 --sigma 0.1um --tau 1um --seed 1 -o "$T/g.npy" 2>/dev/null \
  || fail "generate"
l=$(loaded "$BIN" ndf "$T/g.npy" --method naive -o "$T/n.npy")
! grep -qE 'libhdf5|libtiff|libcairo' <<<"$l" || fail "ndf loaded: $(grep -E 'libhdf5|libtiff|libcairo' <<<"$l")"

# Each is loaded when its reader or a plot needs it, and the command works.
l=$(loaded "$BIN" info "$DATA/zygo_test.datx")
grep -q 'libhdf5' <<<"$l" || fail ".datx read without loading libhdf5?"
$BIN info "$DATA/zygo_test.datx" | grep -q 'Zygo' || fail "info on the .datx"
l=$(loaded "$BIN" info "$DATA/height_f32.tif" --spacing 1um)
grep -q 'libtiff' <<<"$l" || fail "TIFF read without loading libtiff?"
$BIN info "$DATA/height_f32.tif" --spacing 1um | grep -q 'tif' || fail "info on the TIFF"
printf 'x,y\n0,1\n1,2\n2,3\n' >"$T/p.csv"
l=$(loaded "$BIN" plot "$T/p.csv" --x x --y y -o "$T/p.svg")
grep -q 'libcairo' <<<"$l" || fail "plot drawn without loading Cairo?"
grep -q '<svg' "$T/p.svg" || fail "no SVG plot"
l=$(loaded "$BIN" ndf "$T/g.npy" --method naive -o "$T/n2.npy" --preview "$T/n2.png")
grep -q 'libcairo' <<<"$l" || fail "NDF preview labelled without loading Cairo?"
[ -s "$T/n2.png" ] || fail "no NDF preview"
echo "OK"
