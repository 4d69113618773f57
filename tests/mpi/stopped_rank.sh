#!/usr/bin/env bash
# A rank stopped (SIGSTOP) in the middle of a run under 3 ranks: the watchdog ends the run after
# --mpi-timeout with one message naming the stopped rank (its number, pid and host), a non-zero
# exit, no output nor temporary, and no process left. A worker stopped, then rank 0 stopped
# (the others notice). Busy ranks are not taken for stopped ones: a run whose items each take
# longer than the timeout, and a command rank 0 runs alone while the others wait, finish with
# the output of a plain run. docs/scale.md, "Stopped ranks".
set -u
BIN=$(realpath "$1")
MPIRUN=$2
T=$(mktemp -d)
STOPPED=()
cleanup() {
  local p
  for p in "${STOPPED[@]}"; do kill -KILL "$p" 2>/dev/null; done
  rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }
MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)

# A bad value is a usage error naming the flag (no mpirun needed).
$BIN --mpi-timeout soon info /dev/null >/dev/null 2>"$T/err"
rc=$?
[ $rc -eq 2 ] && grep -q -- "--mpi-timeout.*expected e.g. 60s" "$T/err" \
  || fail "--mpi-timeout soon: exit $rc: $(cat "$T/err")"
MICROBRDF_MPI_TIMEOUT=-5s $BIN info /dev/null >/dev/null 2>"$T/err"
[ $? -eq 2 ] && grep -q -- "--mpi-timeout" "$T/err" || fail "MICROBRDF_MPI_TIMEOUT=-5s accepted"

# Twelve scans: about 10 s of work under 3 ranks on a loaded machine, so a stop lands mid-run.
for i in $(seq 1 12); do
  $BIN generate gaussian --nx 384 --ny 384 --spacing 0.5um --sigma 0.2um --tau 3um --seed $i \
    -o "$T/s$i.x3p" >/dev/null 2>&1 || fail "generate $i"
done
SCANS=("$T"/s*.x3p)

# The pid of rank R of the run that writes OUT, once it is running (empty after 20 s).
rank_pid() {
  local out=$1 r=$2 p k
  for ((k = 0; k < 200; k++)); do
    for p in $(pgrep -f -- "$out"); do
      [ "$(cat /proc/$p/comm 2>/dev/null)" = microbrdf ] || continue
      tr '\0' '\n' </proc/$p/environ 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$r" \
        && { echo "$p"; return; }
    done
    sleep 0.1
  done
}

stopped_case() {  # stopped_case RANK WHAT
  local r=$1 what=$2 out="$T/stop$1.npy"
  local t0=$SECONDS
  timeout 120 "${MPI[@]}" $BIN --mpi-timeout 3s ndf "${SCANS[@]}" --method filtered \
    --filter-sigma 2um --resolution 257 -o "$out" >"$T/out.txt" 2>"$T/err.txt" &
  local job=$!
  local pid; pid=$(rank_pid "$out" "$r")
  [ -n "$pid" ] || fail "$what: rank $r never started"
  # Once rank 0 has printed its first line, every rank is past MPI_Init and runs its watchdog
  # (started before any command output).
  local k
  for ((k = 0; k < 400; k++)); do [ -s "$T/err.txt" ] && break; sleep 0.05; done
  kill -STOP "$pid" || fail "$what: could not stop rank $r"
  STOPPED+=("$pid")
  local t_stop=$SECONDS
  wait $job
  local rc=$? t1=$SECONDS
  [ $rc -ne 0 ] || fail "$what: exit 0 with a stopped rank (the run ended before the stop?)"
  [ $rc -ne 124 ] || fail "$what: still waiting after 120 s"
  [ $((t1 - t_stop)) -le 15 ] || fail "$what: ended $((t1 - t_stop)) s after the stop (timeout 3 s)"
  grep -q "microbrdf ndf: error: --mpi-timeout: MPI rank $r (pid $pid on .*) has not responded for 3 s (stopped or hung)" "$T/err.txt" \
    || { cat "$T/err.txt"; fail "$what: no message naming rank $r"; }
  [ ! -e "$out" ] || fail "$what: output written"
  ls -a "$T" | grep -q "tmp-\|partial" && fail "$what: temporary left"
  sleep 1
  [ -d /proc/$pid ] && [ "$(cut -d' ' -f3 /proc/$pid/stat 2>/dev/null)" != Z ] \
    && fail "$what: the stopped rank $r (pid $pid) is still there"
  pgrep -f -- "$out" >/dev/null && fail "$what: a process of the run is still there"
  echo "$what: rank $r stopped after $((t_stop - t0)) s; exit $rc $((t1 - t_stop)) s later: $(grep "error: " "$T/err.txt" | head -1)"
}
stopped_case 2 "worker stopped"
stopped_case 0 "rank 0 stopped"

# Busy is not stopped. Items that each take several times the 1 s timeout (1025^2 D_K tables,
# 3.5 s a scan on an idle 2-core machine; 513^2 ones took 0.94 s there, under the timeout; the
# JSON's seconds per scan say so): the run completes, with the table of a plain run.
$BIN ndf "${SCANS[@]:0:3}" --method kirchhoff --resolution 1025 --dk-stack single -o "$T/plain.npy" \
  >/dev/null 2>&1 || fail "plain ndf"
t0=$SECONDS
timeout 120 "${MPI[@]}" $BIN --mpi-timeout 1s ndf "${SCANS[@]:0:3}" --method kirchhoff --dk-stack single \
  --resolution 1025 -o "$T/busy.npy" --json >"$T/out.txt" 2>"$T/err.txt" \
  || { cat "$T/err.txt"; fail "busy ranks taken for stopped ones (ndf, --mpi-timeout 1s)"; }
cmp -s "$T/plain.npy" "$T/busy.npy" || fail "busy run: not the plain run's table"
per_scan=$(/usr/bin/python3 -c "
import json, sys
m = json.load(open(sys.argv[1]))['mpi']
print(min(s / n for s, n in zip(m['seconds_per_rank'], m['scans_per_rank']) if n))" "$T/out.txt") \
  || fail "busy run: no JSON"
/usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > 1 else 1)" "$per_scan" \
  || fail "busy run: scans took $per_scan s each, not longer than the 1 s timeout (machine too fast?)"
echo "ndf with scans of $per_scan s each (timeout 1 s): completed in $((SECONDS - t0)) s, same table"
# A command rank 0 runs alone (render) while ranks 1-2 wait at the end, for longer than the 1 s
# timeout (the render's own "seconds" say so).
t0=$SECONDS
MICROBRDF_MPI_TIMEOUT=1s timeout 120 "${MPI[@]}" $BIN render --alpha 0.3 --size 128 --spp 256 \
  --threads 1 -o "$T/alone.png" --json >"$T/out.txt" 2>"$T/err.txt" \
  || { cat "$T/err.txt"; fail "waiting ranks taken for stopped ones (render, 1 s)"; }
[ -s "$T/alone.png" ] || fail "render under mpirun wrote no image"
secs=$(/usr/bin/python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['seconds'])" "$T/out.txt")
/usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > 1.5 else 1)" "$secs" \
  || fail "render took $secs s, not longer than the 1 s timeout (machine too fast?)"
echo "render of $secs s on rank 0 alone, ranks 1-2 waiting, timeout 1 s: completed in $((SECONDS - t0)) s"
echo ok
