#!/usr/bin/env bash
# --filter-sigma auto under mpirun: every rank runs the sweep itself, so all agree on the sigma;
# the table, the curve and the chosen sigma are the same as one process gives with 1 and 2
# threads (docs/scale.md, "Determinism").
set -u
BIN=$1
MPIRUN=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)

for i in 1 2 3; do
  $BIN generate gaussian --nx 128 --ny $((96 + 16 * i)) --spacing 50nm --sigma 0.1um --tau 1um \
    --seed $i -o "$T/s$i.x3p" >/dev/null 2>&1 || fail "generate $i"
done
args=(ndf "$T"/s?.x3p --filter-sigma auto --patch whole --resolution 129 --sweep-resolution 65)
OMP_NUM_THREADS=1 $BIN "${args[@]}" -o "$T/one.npy" --json >"$T/one.out" 2>/dev/null ||
  fail "one process"
OMP_NUM_THREADS=2 $BIN "${args[@]}" -o "$T/two.npy" --json >"$T/two.out" 2>/dev/null ||
  fail "two threads"
"${MPI[@]}" $BIN "${args[@]}" -o "$T/mpi.npy" --json >"$T/mpi.out" 2>"$T/mpi.err" ||
  fail "mpirun: $(cat "$T/mpi.err")"
for r in two mpi; do
  cmp -s "$T/one.npy" "$T/$r.npy" || fail "$r: table differs"
  cmp -s "$T/one_filter_sigma.csv" "$T/${r}_filter_sigma.csv" || fail "$r: curve differs"
done
/usr/bin/python3 - "$T" <<'PY' || fail "chosen sigma / curve differ"
import json, sys
t = sys.argv[1]
j = [json.load(open(t + "/" + n + ".out")) for n in ("one", "two", "mpi")]
a = [x["filter_sigma_auto"] for x in j]
assert a[0]["curve"] == a[1]["curve"] == a[2]["curve"]
assert j[0]["filter_sigma_m"] == j[1]["filter_sigma_m"] == j[2]["filter_sigma_m"]
assert j[2]["mpi"]["ranks"] == 3, j[2]["mpi"]
PY
echo OK
