#!/usr/bin/env bash
# One corrupt scan among seven under 3 ranks: one clear error naming the file, a non-zero exit,
# no output file (nor temporary), and every rank gone (the run is bounded by `timeout`; exit 124
# would mean a rank hung). The same for a scan no rank can open. docs/scale.md, "Errors".
set -u
BIN=$1
MPIRUN=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)

for i in 1 2 3 4 5 6 7; do
  $BIN generate gaussian --nx 96 --ny 64 --spacing 0.5um --sigma 0.2um --tau 3um --seed $i \
    -o "$T/s$i.x3p" >/dev/null 2>&1 || fail "generate $i"
done
head -c 2000 "$T/s5.x3p" >"$T/cut.x3p" && mv "$T/cut.x3p" "$T/s5.x3p"  # truncated ZIP

check() {  # check WHAT BAD_FILE OUTPUT -- command...
  local what=$1 bad=$2 out=$3; shift 4
  timeout 60 "${MPI[@]}" "$@" >"$T/out.txt" 2>"$T/err.txt"
  local rc=$?
  [ $rc -ne 0 ] || fail "$what: exit 0"
  [ $rc -ne 124 ] || fail "$what: a rank hung (killed by timeout)"
  [ "$(grep -c "error: $bad" "$T/err.txt")" = 1 ] \
    || { cat "$T/err.txt"; fail "$what: not one error naming $bad"; }
  ls "$T" | grep -q "^$(basename "$out")" && fail "$what: output written"
  ls -a "$T" | grep -qi "tmp" && fail "$what: temporary file left"
  sleep 1
  pgrep -f "$out" >/dev/null && fail "$what: a rank is still running"
  return 0
}
check "filtered NDF" "$T/s5.x3p" "$T/ndf_out.npy" -- \
  $BIN ndf "$T"/s?.x3p --method filtered --resolution 129 -o "$T/ndf_out.npy"
check "texture" "$T/s5.x3p" "$T/tex_out.exr" -- \
  $BIN texture "$T"/s?.x3p --texel 14um -o "$T/tex_out.exr"
check "missing scan" "$T/nope.x3p" "$T/miss_out.npy" -- \
  $BIN ndf "$T"/s1.x3p "$T"/s2.x3p "$T/nope.x3p" "$T"/s3.x3p --resolution 129 \
  -o "$T/miss_out.npy"
echo ok
