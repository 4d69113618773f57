#!/usr/bin/env bash
# SIGINT and SIGKILL at random moments of predict, ndf, render, convert and texture (TRIALS of
# each, default 10): after SIGINT the run exits 130 and leaves no temporary; after either signal
# the earlier output is intact (its old bytes, or the complete new output if the run finished).
# usage: interrupts.sh BIN DATA [TRIALS]
set -u
set -m  # each run in its own process group; background runs keep SIGINT
BIN=$1 TRIALS=${3:-10}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
sum() { md5sum "$1" | cut -d' ' -f1; }
temps() { find "$T/out" -name '*.tmp-*' -o -name '.*.partial-*'; }
now_ms() { date +%s%3N; }

$BIN generate gaussian --nx 256 --ny 256 --spacing 1um --sigma 50nm --tau 5um -o "$T/g.x3p" >/dev/null 2>&1 || fail generate
$BIN generate brushed --nx 512 --ny 256 --spacing 1um -o "$T/b.x3p" >/dev/null 2>&1 || fail "generate brushed"
mkdir -p "$T/out"

# One command: NAME, the output checked (file or folder/summary.json), the earlier run, the run
# that gets interrupted.
declare -A OLD NEW SECS
check_intact() {  # name target
  local s
  if [ "$1" = predict ]; then
    [ -f "$2" ] || fail "$1: the earlier report is gone"
    s=$(sum "$2")
    [ "$s" = "${OLD[$1]}" ] || { [ -f "$T/out/rep/report.html" ] &&
      /usr/bin/python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$2"; } ||
      fail "$1: the report is neither the earlier one nor a complete new one"
  else
    [ -f "$2" ] || fail "$1: the earlier output is gone"
    s=$(sum "$2")
    [ "$s" = "${OLD[$1]}" ] || [ "$s" = "${NEW[$1]}" ] || fail "$1: the output is corrupt ($s)"
  fi
}

run_case() {  # name target old-cmd new-cmd (strings)
  local name=$1 target=$2 old=$3 new=$4
  eval "$new" >/dev/null 2>&1 || fail "$name: reference run failed: $new"
  NEW[$name]=$(sum "$target")
  local t0; t0=$(now_ms)
  eval "$old" >/dev/null 2>&1 || fail "$name: earlier run failed: $old"
  SECS[$name]=$(( $(now_ms) - t0 ))
  OLD[$name]=$(sum "$target")
  local ms_new; t0=$(now_ms); eval "$new" >/dev/null 2>&1; ms_new=$(( $(now_ms) - t0 ))
  eval "$old" >/dev/null 2>&1
  local int_done=0 int_hit=0 kill_hit=0
  for sig in INT KILL; do
    for ((i = 0; i < TRIALS; i++)); do
      local delay=$(( RANDOM % (ms_new + 1) ))
      eval "exec $new" >/dev/null 2>&1 &
      local pid=$!
      sleep "$(printf '%d.%03d' $((delay / 1000)) $((delay % 1000)))"
      kill -s $sig -- -$pid 2>/dev/null  # the run's process group
      wait $pid; local rc=$?
      if [ $sig = INT ]; then
        [ $rc -eq 130 ] && int_hit=$((int_hit + 1))
        [ $rc -eq 0 ] && int_done=$((int_done + 1))
        [ $rc -eq 130 ] || [ $rc -eq 0 ] || fail "$name: SIGINT after ${delay} ms: exit $rc (want 130)"
        local left; left=$(temps)
        [ -z "$left" ] || fail "$name: SIGINT after ${delay} ms left temporaries: $left"
      else
        [ $rc -eq 137 ] && kill_hit=$((kill_hit + 1))
        find "$T/out" \( -name '*.tmp-*' -o -name '.*.partial-*' \) -prune -exec rm -rf {} +
      fi
      check_intact "$name" "$target"
      eval "$old" >/dev/null 2>&1  # back to the earlier output for the next trial
    done
  done
  echo "$name: run ${ms_new} ms; SIGINT: $int_hit interrupted (exit 130, no temporaries), $int_done finished first; SIGKILL: $kill_hit killed; earlier output intact in all $((2 * TRIALS))"
}

O=$T/out
run_case ndf "$O/ndf.npy" "$BIN ndf $T/g.x3p --resolution 65 -o $O/ndf.npy" \
  "$BIN ndf $T/g.x3p --resolution 513 -o $O/ndf.npy --preview $O/ndf.png"
run_case render "$O/a.png" "$BIN render --alpha 0.3 --size 32 --spp 1 -o $O/a.png" \
  "$BIN render --alpha 0.3 --size 96 --spp 16 -o $O/a.png -o $O/a.exr"
run_case convert "$O/c.npy" "$BIN convert $T/g.x3p $O/c.npy" \
  "$BIN convert $T/b.x3p $O/c.npy --level poly3 --preview $O/c.png"
run_case texture "$O/t.exr" "$BIN texture $T/b.x3p --texel 32um --resolution 33 -o $O/t.exr --no-preview" \
  "$BIN texture $T/b.x3p --texel 16um --resolution 65 -o $O/t.exr"
run_case predict "$O/rep/summary.json" "$BIN predict $T/g.x3p -o $O/rep --no-render --resolution 65 --quiet" \
  "$BIN predict $T/g.x3p -o $O/rep --resolution 129 --render-width 32 --spp 2 --quiet"
echo ok
