#!/usr/bin/env bash
# Under mpirun the scan-set commands and simulate give the same files as one process, bit for
# bit, and one process gives the same with 1 and 2 threads: ndf (naive, filtered, kirchhoff),
# texture (texel fits), predict (NDF tables, previews, summary.json), info and simulate (matrix
# of coefficients). The JSON says how the work
# was shared ("mpi": ranks, scans or blocks per rank). docs/scale.md, "Determinism".
set -u
BIN=$1
MPIRUN=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# Root in containers/CI; more ranks than cores on small machines.
MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)
one() { OMP_NUM_THREADS=$1 "${@:2}"; }

# Seven scans of different sizes (the queue hands them out in any order).
for i in 1 2 3 4 5 6 7; do
  $BIN generate gaussian --nx 96 --ny $((48 + 8 * i)) --spacing 0.5um --sigma 0.2um --tau 3um \
    --seed $i -o "$T/s$i.x3p" >/dev/null 2>&1 || fail "generate $i"
done
SCANS=("$T"/s?.x3p)

same() {  # same FILE_A FILE_B WHAT
  cmp -s "$1" "$2" || fail "$3: $1 and $2 differ"
}

for m in naive filtered kirchhoff; do
  # D_K uses threads only for problems above 2^17 samples + nodes: 385^2 nodes are.
  res=129; [ $m = kirchhoff ] && res=385
  args=(ndf "${SCANS[@]}" --method "$m" --resolution $res)
  # (D_K by the midpoint rule: the exact rule needs ~56 points per triangle on these 0.5 um grids)
  [ $m = kirchhoff ] && args+=(--dk-integration midpoint)
  one 1 $BIN "${args[@]}" -o "$T/$m.1.npy" 2>/dev/null || fail "$m, 1 thread"
  one 2 $BIN "${args[@]}" -o "$T/$m.2.npy" 2>/dev/null || fail "$m, 2 threads"
  one 1 "${MPI[@]}" $BIN "${args[@]}" -o "$T/$m.mpi.npy" --json >"$T/$m.json" 2>"$T/$m.err" \
    || { cat "$T/$m.err"; fail "$m under mpirun"; }
  same "$T/$m.1.npy" "$T/$m.2.npy" "ndf $m, 1 vs 2 threads"
  same "$T/$m.1.npy" "$T/$m.mpi.npy" "ndf $m, 1 process vs 3 ranks"
  # One progress line per scan, from rank 0 only.
  [ "$(grep -c '\] ' "$T/$m.err")" = 7 ] || { cat "$T/$m.err"; fail "$m: progress lines"; }
done

targs=(texture "${SCANS[@]:0:3}" --texel 14um --no-preview)
one 1 $BIN "${targs[@]}" -o "$T/t1.exr" >/dev/null 2>&1 || fail "texture, 1 thread"
one 2 $BIN "${targs[@]}" -o "$T/t2.exr" >/dev/null 2>&1 || fail "texture, 2 threads"
one 1 "${MPI[@]}" $BIN "${targs[@]}" -o "$T/tm.exr" --json >"$T/texture.json" 2>/dev/null \
  || fail "texture under mpirun"
same "$T/t1.exr" "$T/t2.exr" "texture, 1 vs 2 threads"
same "$T/t1.exr" "$T/tm.exr" "texture, 1 process vs 3 ranks"

# predict: the per-scan stage (reading, statistics, previews, NDF shares) over the ranks; the
# summary's numbers (apart from "timing" and "mpi") and the NDF tables are the same. The
# per-scan stage runs on OpenMP's threads: 1 or 2 of them give the same summary. --threads
# (the fits' solver threads) gives the same inputs and NDFs; the fits agree for equal --threads.
pargs=(predict "${SCANS[@]:0:4}" --resolution 129 --kirchhoff --dk-integration midpoint
  --patch 20x20um --no-render --quiet)
one 1 $BIN "${pargs[@]}" --threads 1 -o "$T/p1" >/dev/null 2>&1 || fail "predict, 1 thread"
one 2 $BIN "${pargs[@]}" --threads 1 -o "$T/p2" >/dev/null 2>&1 || fail "predict, 2 threads"
one 2 $BIN "${pargs[@]}" --threads 2 -o "$T/p3" >/dev/null 2>&1 || fail "predict, --threads 2"
one 1 "${MPI[@]}" $BIN "${pargs[@]}" --threads 1 -o "$T/pm" --json >"$T/predict.json" \
  2>"$T/predict.err" || { cat "$T/predict.err"; fail "predict under mpirun"; }
for f in ndf_naive.npy ndf_filtered.npy ndf_kirchhoff.npy img/height_01.png img/height_04.png; do
  same "$T/p1/$f" "$T/p2/$f" "predict $f, 1 vs 2 threads"
  same "$T/p1/$f" "$T/p3/$f" "predict $f, --threads 1 vs 2"
  same "$T/p1/$f" "$T/pm/$f" "predict $f, 1 process vs 3 ranks"
done

$BIN info "${SCANS[@]}" --json >"$T/info1.json" 2>/dev/null || fail "info"
"${MPI[@]}" $BIN info "${SCANS[@]}" --json >"$T/infom.json" 2>/dev/null || fail "info, mpirun"

cat >"$T/scene.json" <<'J'
{"materials": {"m": {"type": "mirror", "metal": "Al"}},
 "objects": [{"type": "heightfield", "material": "m",
   "generate": {"kind": "gaussian", "nx": 64, "ny": 64, "spacing": "8um", "sigma": "10um",
                "tau": "65um", "seed": 2}}]}
J
sargs=(simulate "$T/scene.json" --lmax 6 --rays 36000 --points 12 --seed 5 -q)
$BIN "${sargs[@]}" --threads 1 -o "$T/sim1.shbrdf" || fail "simulate, 1 thread"
$BIN "${sargs[@]}" --threads 2 -o "$T/sim2.shbrdf" || fail "simulate, 2 threads"
"${MPI[@]}" $BIN "${sargs[@]}" --threads 2 -o "$T/simm.shbrdf" --json >"$T/sim.json" \
  || fail "simulate under mpirun"

# Commands (and modes) that run on rank 0 alone finish under mpirun too, writing once.
timeout 120 "${MPI[@]}" $BIN generate gaussian --nx 64 --ny 64 --spacing 1um --sigma 0.1um \
  --tau 4um -o "$T/solo.x3p" >/dev/null 2>&1 || fail "generate under mpirun"
[ -s "$T/solo.x3p" ] || fail "generate under mpirun: no file"
timeout 120 "${MPI[@]}" $BIN simulate "$T/scene.json" --in-plane 0,45 --gonio-rays 4000 \
  --csv "$T/plane.csv" -q >/dev/null 2>&1 || fail "simulate --in-plane under mpirun"
[ -s "$T/plane.csv" ] || fail "simulate --in-plane under mpirun: no CSV"

/usr/bin/python3 - "$T" <<'PY' || fail "JSON / matrices"
import json, struct, sys
T = sys.argv[1]
def matrix(p):  # the coefficients after the JSON header (the header holds timings)
    b = open(p, "rb").read()
    assert b[:8] == b"MBSHBRDF", p
    n = struct.unpack("<I", b[8:12])[0]
    return b[12 + n:]
m1 = matrix(f"{T}/sim1.shbrdf")
assert len(m1) > 0
assert m1 == matrix(f"{T}/sim2.shbrdf"), "simulate: 1 vs 2 threads differ"
assert m1 == matrix(f"{T}/simm.shbrdf"), "simulate: 1 process vs 3 ranks differ"
s = json.load(open(f"{T}/sim.json"))["mpi"]
assert s["ranks"] == 3 and len(s["blocks_per_rank"]) == 3, s
assert sum(s["blocks_per_rank"]) == 3000 // 256 + 1, s   # 36000 rays / 12 points = 3000 dirs
for m in ("naive", "filtered", "kirchhoff"):
    j = json.load(open(f"{T}/{m}.json"))["mpi"]
    assert j["ranks"] == 3 and sum(j["scans_per_rank"]) == 7, (m, j)
    assert len(j["seconds_per_rank"]) == 3, (m, j)
    # rank 0 takes one scan at a time and answers the others within a millisecond: seven scans
    # reach more than one rank
    assert sum(1 for k in j["scans_per_rank"] if k > 0) >= 2, (m, j)
t = json.load(open(f"{T}/texture.json"))["mpi"]
assert t["ranks"] == 3 and sum(t["scans_per_rank"]) == 3, t
def summary(d):
    j = json.load(open(f"{T}/{d}/summary.json"))
    for k in ("timing", "mpi"):
        j.pop(k)
    return j
p1 = summary("p1")
assert p1 == summary("p2"), "predict summary: 1 vs 2 threads differ"
p3 = summary("p3")
# The whole summary, fits included: the fits' sums are folded in a fixed order.
assert p1 == p3, "predict summary: --threads 1 vs 2 differ: " + str(
    [k for k in p1 if p1[k] != p3.get(k)])
assert p1 == summary("pm"), "predict summary: 1 process vs 3 ranks differ"
assert len(p1["inputs"]) == 4 and "kirchhoff" in p1["ndf"], p1.keys()
p = json.load(open(f"{T}/predict.json"))["mpi"]
assert p["ranks"] == 3 and sum(p["scans_per_rank"]) == 4 and len(p["seconds_per_rank"]) == 3, p
assert json.load(open(f"{T}/pm/summary.json"))["mpi"] == p
assert json.load(open(f"{T}/p1/summary.json"))["mpi"]["scans_per_rank"] == [4]
a = json.load(open(f"{T}/info1.json"))
b = json.load(open(f"{T}/infom.json"))
assert a["surfaces"] == b["surfaces"], "info: records differ"
assert [r["path"] for r in b["surfaces"]] == sorted(r["path"] for r in b["surfaces"])
assert a["mpi"]["ranks"] == 1 and b["mpi"]["ranks"] == 3
for j in (a["mpi"], b["mpi"], t):
    assert len(j["scans_per_rank"]) == j["ranks"] == len(j["seconds_per_rank"]), j
assert len(s["seconds_per_rank"]) == 3, s
PY
echo ok
