#!/usr/bin/env bash
# The CLI as a user meets it: bad input gets a message naming the file and the problem, a
# non-zero exit, and no partial output file.
set -u
BIN=$1 DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# Every subcommand teaches with --help.
for c in info convert generate "generate gaussian" "generate brushed" "generate profile" "generate cylinders" "generate grating"; do
  $BIN $c --help >"$T/help" 2>&1 || fail "$c --help exits non-zero"
  grep -q "Usage\|USAGE\|usage" "$T/help" || fail "$c --help prints no usage"
done

# A missing file: exit 1, message names it.
$BIN info "$T/nope.x3p" 2>"$T/err" && fail "missing file accepted"
grep -q "nope.x3p" "$T/err" || fail "error does not name the file: $(cat "$T/err")"

# A bare length is an error (exit 2), with a hint.
$BIN generate gaussian --spacing 110 -o "$T/g.x3p" 2>"$T/err"; [ $? -eq 2 ] || fail "bare length not exit 2"
grep -q "no unit" "$T/err" || fail "bare length message: $(cat "$T/err")"
[ -e "$T/g.x3p" ] && fail "output written despite the error"

# A truncated real file: clear error naming the file, and convert leaves no output behind.
head -c 5000 "$DATA/metropro-1.dat" >"$T/cut.dat"
$BIN convert "$T/cut.dat" "$T/out.x3p" 2>"$T/err" && fail "truncated file accepted"
grep -q "cut.dat" "$T/err" || fail "truncated: message does not name the file: $(cat "$T/err")"
ls "$T" | grep -q "out.x3p" && fail "partial output left behind"

# Garbage with a known extension.
head -c 3000 /dev/urandom >"$T/junk.sur"
$BIN info "$T/junk.sur" 2>"$T/err" && fail "junk accepted"
grep -q "junk.sur" "$T/err" || fail "junk: message does not name the file"

# Unwritable / unknown output format: non-zero, nothing written.
$BIN convert "$DATA/test.gwy" "$T/out.unknown" 2>"$T/err" && fail "unknown output extension accepted"
$BIN convert "$DATA/test.gwy" "$T/out.sur" 2>"$T/err" && fail "read-only format written"
grep -q "not supported" "$T/err" || fail "read-only format message: $(cat "$T/err")"
[ -z "$(ls "$T" | grep -E 'out\.(unknown|sur)')" ] || fail "output left behind"

# An image format without spacing asks for --spacing.
cp "$DATA/test.gwy" "$T/x.npy" 2>/dev/null
$BIN generate gaussian --nx 32 --ny 32 -o "$T/g.npy" || fail "generate npy"
rm -f "$T/g.json"
$BIN info "$T/g.npy" 2>"$T/err" && fail "npy without sidecar or --spacing accepted"
grep -q -- "--spacing" "$T/err" || fail "npy: no hint about --spacing: $(cat "$T/err")"
$BIN info "$T/g.npy" --spacing 110nm >/dev/null || fail "npy with --spacing"
echo "ok"
