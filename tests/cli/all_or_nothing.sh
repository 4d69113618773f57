#!/usr/bin/env bash
# A run that fails on one of its outputs changes nothing on disk: earlier files keep their
# bytes, and no temporary is left beside them (ndf, render, convert, texture, predict).
set -u
BIN=$1 DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
sum() { md5sum "$1" | cut -d' ' -f1; }
no_temps() { local left; left=$(find "$T" -name '*.tmp-*' -o -name '.*.partial-*' | head -3)
  [ -z "$left" ] || fail "$1: temporaries left: $left"; }

$BIN generate gaussian --nx 64 --ny 64 --spacing 1um --sigma 50nm --tau 5um -o "$T/g.x3p" >/dev/null 2>&1 \
  || fail "generate"
mkdir -p "$T/f"

# ndf: table + preview; the preview's folder does not exist.
$BIN ndf "$T/g.x3p" --resolution 65 -o "$T/f/ndf.npy" >/dev/null 2>&1 || fail "first ndf"
before=$(sum "$T/f/ndf.npy") side=$(sum "$T/f/ndf.json")
$BIN ndf "$T/g.x3p" --resolution 129 -o "$T/f/ndf.npy" --preview /nonexistent/p.png 2>"$T/err" \
  && fail "ndf with an unwritable preview succeeded"
grep -q "/nonexistent/p.png" "$T/err" || fail "ndf: message does not name the preview: $(cat "$T/err")"
[ "$(sum "$T/f/ndf.npy")" = "$before" ] || fail "ndf: the table was replaced by a failed run"
[ "$(sum "$T/f/ndf.json")" = "$side" ] || fail "ndf: the sidecar was replaced by a failed run"
no_temps ndf

# render: two images, the second one unwritable.
$BIN render --alpha 0.3 --size 16 --spp 1 -o "$T/a.png" >/dev/null 2>&1 || fail "first render"
before=$(sum "$T/a.png")
$BIN render --alpha 0.5 --size 16 --spp 2 -o "$T/a.png" -o /nonexistent/a.exr 2>"$T/err" \
  && fail "render with an unwritable second output succeeded"
[ "$(sum "$T/a.png")" = "$before" ] || fail "render: a.png was replaced by a failed run"
no_temps render

# convert: the surface and its preview.
$BIN convert "$T/g.x3p" "$T/c.npy" >/dev/null 2>&1 || fail "first convert"
before=$(sum "$T/c.npy") side=$(sum "$T/c.json")
$BIN convert "$T/g.x3p" "$T/c.npy" --level plane --preview /nonexistent/p.png 2>"$T/err" \
  && fail "convert with an unwritable preview succeeded"
[ "$(sum "$T/c.npy")" = "$before" ] || fail "convert: c.npy was replaced by a failed run"
[ "$(sum "$T/c.json")" = "$side" ] || fail "convert: the sidecar was replaced by a failed run"
no_temps convert

# texture: the parameter texture and its preview.
$BIN generate brushed --nx 256 --ny 128 --spacing 1um -o "$T/b.x3p" >/dev/null 2>&1 || fail "generate brushed"
$BIN texture "$T/b.x3p" --texel 32um --resolution 33 -o "$T/t.exr" --no-preview >/dev/null 2>&1 \
  || fail "first texture"
before=$(sum "$T/t.exr")
$BIN texture "$T/b.x3p" --texel 32um --resolution 65 -o "$T/t.exr" --preview /nonexistent/t.png 2>"$T/err" \
  && fail "texture with an unwritable preview succeeded"
[ "$(sum "$T/t.exr")" = "$before" ] || fail "texture: t.exr was replaced by a failed run"
no_temps texture

# predict: a second scan that cannot be read; the earlier report stays as it was.
$BIN predict "$T/g.x3p" -o "$T/rep" --no-render --resolution 65 --quiet >/dev/null 2>&1 || fail "first predict"
before=$(sum "$T/rep/summary.json")
head -c 3000 /dev/urandom >"$T/junk.x3p"
$BIN predict "$T/g.x3p" "$T/junk.x3p" -o "$T/rep" --no-render --resolution 65 --quiet 2>"$T/err" \
  && fail "predict with an unreadable scan succeeded"
grep -q "junk.x3p" "$T/err" || fail "predict: message does not name the scan: $(cat "$T/err")"
[ "$(sum "$T/rep/summary.json")" = "$before" ] || fail "predict: the earlier report was changed"
no_temps predict

# predict on a full disk (a file-size limit of 40 KiB stands in for it): exit 1 (a failure
# while working, not a usage error), a message naming the output under -o (not the hidden
# staging folder), the earlier report unchanged and no staging folder left.
(trap '' XFSZ; ulimit -f 40
 $BIN predict "$T/g.x3p" -o "$T/rep" --no-render --resolution 129 --quiet 2>"$T/err" >/dev/null)
rc=$?
[ $rc -eq 1 ] || fail "predict on a full disk: exit $rc (want 1): $(cat "$T/err")"
grep -q "$T/rep" "$T/err" || fail "predict on a full disk: message does not name -o: $(cat "$T/err")"
grep -q "partial" "$T/err" && fail "predict on a full disk: message names the staging folder: $(cat "$T/err")"
[ "$(sum "$T/rep/summary.json")" = "$before" ] || fail "predict on a full disk: the earlier report was changed"
no_temps "predict (full disk)"
echo ok
