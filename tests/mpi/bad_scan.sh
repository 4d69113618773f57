#!/usr/bin/env bash
# One corrupt scan among seven under 3 ranks: one clear error naming the file, a non-zero exit,
# no output file (nor temporary), and every rank gone (the run is bounded by `timeout`; exit 124
# would mean a rank hung), for ndf, texture, info, predict; a bad scene for simulate; a scan no
# rank can open; a scan only some ranks can see. docs/scale.md, "Errors".
set -u
BIN=$(realpath "$1")
MPIRUN=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)

for i in 1 2 3 4 5 6 7; do
  $BIN generate gaussian --nx 96 --ny 64 --spacing 0.5um --sigma 0.2um --tau 3um --seed $i \
    -o "$T/s$i.x3p" >/dev/null 2>&1 || fail "generate $i"
done
head -c 2000 "$T/s5.x3p" >"$T/cut.x3p" && mv "$T/cut.x3p" "$T/s5.x3p"  # truncated ZIP

check() {  # check WHAT BAD_FILE OUTPUT COUNT -- command...  (COUNT: error lines, "any" = >= 1)
  local what=$1 bad=$2 out=$3 count=$4; shift 5
  local t0=$SECONDS
  timeout 60 "${MPI[@]}" "$@" >"$T/out.txt" 2>"$T/err.txt"
  local rc=$? t1=$SECONDS
  [ $rc -ne 0 ] || fail "$what: exit 0"
  [ $rc -ne 124 ] || fail "$what: a rank hung (killed by timeout)"
  local n; n=$(grep -c "error: .*$bad" "$T/err.txt")
  { [ "$count" = any ] && [ "$n" -ge 1 ]; } || [ "$n" = "$count" ] \
    || { cat "$T/err.txt"; fail "$what: $n errors naming $bad (expected $count)"; }
  ls "$T" | grep -q "^$(basename "$out")" && fail "$what: output written"
  ls -a "$T" | grep -qi "tmp\|partial" && fail "$what: temporary file or folder left"
  sleep 1
  pgrep -f "$out" >/dev/null && fail "$what: a rank is still running"
  echo "$what: exit $rc after $((t1 - t0)) s, one error: $(grep "error: " "$T/err.txt")"
  return 0
}
check "filtered NDF" "$T/s5.x3p" "$T/ndf_out.npy" 1 -- \
  $BIN ndf "$T"/s?.x3p --method filtered --resolution 129 -o "$T/ndf_out.npy"
check "texture" "$T/s5.x3p" "$T/tex_out.exr" 1 -- \
  $BIN texture "$T"/s?.x3p --texel 14um -o "$T/tex_out.exr"
check "info" "$T/s5.x3p" "$T/info_none" 1 -- $BIN info "$T"/s?.x3p --json
check "predict" "$T/s5.x3p" "$T/pred_out" 1 -- \
  $BIN predict "$T"/s?.x3p --resolution 129 --no-render -o "$T/pred_out"
echo '{"objects": [' >"$T/bad_scene.json"  # cut short
check "simulate" "$T/bad_scene.json" "$T/sim_out.shbrdf" 1 -- \
  $BIN simulate "$T/bad_scene.json" --rays 1000 -o "$T/sim_out.shbrdf"
# A missing file fails the checks every rank makes before the work starts: rank 0 reports it,
# once for all ranks.
check "missing scan" "$T/nope.x3p" "$T/miss_out.npy" 1 -- \
  $BIN ndf "$T"/s1.x3p "$T"/s2.x3p "$T/nope.x3p" "$T"/s3.x3p --resolution 129 \
  -o "$T/miss_out.npy"
# A file only some ranks can see (each rank starts in its own folder: --wdir per app context):
# the ranks that fail before the work starts hand their error to rank 0, which reports it once.
mkdir -p "$T/A" "$T/B"
cp "$T/s1.x3p" "$T/s2.x3p" "$T/A/" && cp "$T/s1.x3p" "$T/B/" && cp "$T/s3.x3p" "$T/A/only.x3p"
nargs=(ndf s1.x3p only.x3p --resolution 129 -o out.npy)
for order in "A B" "B A"; do
  set -- $order
  t0=$SECONDS
  timeout 60 "$MPIRUN" --allow-run-as-root --oversubscribe -np 1 --wdir "$T/$1" $BIN "${nargs[@]}" \
    : -np 2 --wdir "$T/$2" $BIN "${nargs[@]}" >"$T/out.txt" 2>"$T/err.txt"
  rc=$?
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "file in rank 0's folder $1 only: exit $rc"
  [ "$(grep -c "error: .*only.x3p" "$T/err.txt")" = 1 ] \
    || { cat "$T/err.txt"; fail "file in rank 0's folder $1 only: not one error"; }
  [ ! -e "$T/A/out.npy" ] && [ ! -e "$T/B/out.npy" ] || fail "file in $1 only: output written"
  echo "rank 0 in folder $1, ranks 1-2 in $2 (only.x3p in A alone): exit $rc after $((SECONDS - t0)) s, one error: $(grep "error: " "$T/err.txt")"
done
echo ok
