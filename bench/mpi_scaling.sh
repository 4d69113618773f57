#!/usr/bin/env bash
# Scan sets over MPI ranks on this machine (docs/benchmarks.md, "Scale-out"): `ndf --method
# filtered` of 20 scans of 640 x 480 at 110 nm with 1 rank and with 2 ranks (one OpenMP thread
# each), back to back in one run, plus 1 process with 2 threads for reference; then the largest
# resident set of every rank for 20 and for 200 distinct scans (470 MB of x3p files). Wall and
# CPU seconds (user + system, all ranks) of each run and the load average around each round are
# printed: on a machine shared with other work, wall-time ratios follow the scheduler as much as
# the code. Scans are generated in a temporary directory and removed afterwards.
#   bench/mpi_scaling.sh build/bin/microbrdf [repeats]
set -eu
BIN=$(realpath "$1")
REPEATS=${2:-2}
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
mkdir -p "$T/s20" "$T/s200"
for i in $(seq -w 1 200); do  # 200 distinct scans (2.35 MB each); the first 20 are the small set
  "$BIN" generate gaussian --nx 640 --ny 480 --spacing 110nm --sigma 0.1um --tau 1um --seed "$((10#$i))" \
    -o "$T/s200/s$i.x3p" >/dev/null 2>&1
done
for i in $(seq -w 1 200 | head -n 20); do ln -s "$T/s200/s$i.x3p" "$T/s20/s$i.x3p"; done
echo "cores: $(nproc); load before: $(cut -d' ' -f1-3 /proc/loadavg)"

# Wall seconds of a command (its stdout, the --json object, goes to $T/last.json); its CPU
# seconds (user + system, all ranks: they are mpirun's children) go to $T/last.cpu.
wall() {
  /usr/bin/time -f "%e %U %S" -o "$T/time.txt" "$@" >"$T/last.json" 2>"$T/err.txt" \
    || { echo "failed: $*" >&2; cat "$T/err.txt" >&2; return 1; }
  read -r e u s <"$T/time.txt"
  echo "$u + $s" | bc >"$T/last.cpu"
  echo "$e"
}
# CPU seconds per scan spent in the per-scan work (read, level, estimate) from the "mpi" block.
per_scan() {
  /usr/bin/python3 -c 'import json,sys; m=json.load(open(sys.argv[1]))["mpi"]; print("%.3f" % (sum(m["seconds_per_rank"]) / sum(m["scans_per_rank"])))' "$T/last.json"
}
ARGS=(ndf --method filtered -o "$T/out.npy" --json)
for r in $(seq 1 "$REPEATS"); do
  l0=$(cut -d' ' -f1 /proc/loadavg)
  a=$(OMP_NUM_THREADS=1 wall "${MPIRUN[@]}" -np 1 "$BIN" "${ARGS[@]}" "$T"/s20/*.x3p)
  wa=$(per_scan) ca=$(cat "$T/last.cpu")
  b=$(OMP_NUM_THREADS=1 wall "${MPIRUN[@]}" -np 2 "$BIN" "${ARGS[@]}" "$T"/s20/*.x3p)
  wb=$(per_scan) cb=$(cat "$T/last.cpu")
  c=$(OMP_NUM_THREADS=2 wall "$BIN" "${ARGS[@]}" "$T"/s20/*.x3p)
  d=$(OMP_NUM_THREADS=1 wall "$BIN" "${ARGS[@]}" "$T"/s20/*.x3p)
  wd=$(per_scan) cd=$(cat "$T/last.cpu")
  l1=$(cut -d' ' -f1 /proc/loadavg)
  echo "round $r (load $l0 -> $l1): 1 rank ${a} s, 2 ranks ${b} s (ratio $(echo "scale=2; $a / $b" | bc)); plain process 1 thread ${d} s, 2 threads ${c} s; CPU seconds (user + sys) 1 rank ${ca}, 2 ranks ${cb}, plain 1 thread ${cd}; per-scan work (wall, inside the items) ${wa} s (1 rank), ${wb} s (2 ranks), ${wd} s (plain, 1 thread)"
done

# Largest resident set per rank (GNU time inside each rank).
for set in s20 s200; do
  rm -f "$T"/rss.*
  OMP_NUM_THREADS=1 "${MPIRUN[@]}" -np 2 sh -c \
    '/usr/bin/time -f "%M" -o "$0/rss.$OMPI_COMM_WORLD_RANK" "$@"' "$T" \
    "$BIN" "${ARGS[@]}" "$T/$set"/*.x3p >"$T/last.json" 2>/dev/null
  echo "$set: max RSS per rank (KiB): rank 0 $(cat "$T/rss.0"), rank 1 $(cat "$T/rss.1"); scans per rank $(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["mpi"]["scans_per_rank"])' "$T/last.json")"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
