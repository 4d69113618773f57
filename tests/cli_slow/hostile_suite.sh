#!/usr/bin/env bash
# The hostile suite: several hundred variants of hostile input across the eight classes of
# failure a hostile user finds (docs/guide.md, "Limits on numbers and files"):
#   1 crashes (absurd numbers: NaN, inf, 1e300, negatives, tiny spacings; corrupt files)
#   2 the file-size limit (ulimit -f: SIGXFSZ / EFBIG reported like a full disk)
#   3 budgets and hangs (huge counts, --max-memory, inputs that ask for gigabytes or hours)
#   4 JSON that is large and flat or deep (linear-time parsing)
#   5 messages (naming the file or flag at fault; data used where it does not apply)
#   6 data loss and injection (outputs equal to inputs, names with quotes, newlines and bytes
#     that are not UTF-8 in exported files, signals mid-run)
#   7 Python (the same from the module: exceptions of its own classes naming the file)
#   8 MPI (a stopped rank, SIGINT to mpirun)
# Each variant asserts: no crash (exit < 128, except the deliberate signals, which must exit
# 128 + N), a clean refusal (exit 1 or 2) or a run that says what it changed, a message naming
# the file or flag, max RSS under 1 GiB (GNU time), under 10 s (timeout), and no temporary
# (*.tmp-*, *partial-*) left. Prints a tally per class; exits 1 if any variant failed.
# usage: hostile_suite.sh BIN DATA_DIR [FILTER]  (FILTER: run only variants whose name matches)
set -u
BIN=$(realpath "$1")
DATA=$(realpath "$2")
FILTER=${3:-}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
PY=/usr/bin/python3
PYDIR=$(cd "$(dirname "$BIN")/.." && pwd)/python  # build/bin/microbrdf -> build/python
MPIRUN=$(command -v mpirun || true)
T=$(mktemp -d)
W=$T/w    # each variant runs in a fresh copy of this folder
IN=$T/in  # inputs, made once
PIDS_TO_KILL=()
cleanup() {
  local p
  for p in "${PIDS_TO_KILL[@]}"; do kill -KILL "$p" 2>/dev/null; done
  rm -rf "$T"
}
trap cleanup EXIT
. "$ROOT/tests/cli/lib/hostile_expect.bash"  # hostile_budget_kib
[ -x /usr/bin/time ] || { echo "SKIP: GNU time (/usr/bin/time) is not installed"; exit 0; }
mkdir -p "$IN" "$W"

declare -A N OK
FAILED=()
CLASS_NAME=([1]="crashes" [2]="file-size limit" [3]="budgets and hangs" [4]="large and deep JSON"
  [5]="messages" [6]="data loss, injection, signals" [7]="Python" [8]="MPI")
for c in 1 2 3 4 5 6 7 8; do N[$c]=0; OK[$c]=0; done
T_START=$SECONDS

# ---- the harness -------------------------------------------------------------------------------
# v CLASS NAME EXPECT NEEDLE -- COMMAND...
#   EXPECT  refuse  exit 1 or 2
#           usage   exit 2
#           fail    exit 1
#           ok      exit 0
#           said    exit 1 or 2, or exit 0 with NEEDLE on stderr (a clamped run that says so)
#           either  exit 0 (CHECK then says whether the result is right), or 1 or 2 with NEEDLE
#           sig:N   exit 128 + N (a deliberate signal; temporaries must still be gone)
#   NEEDLE  an extended regular expression stderr must match: the file or flag at fault
#           ("-" for none, only with ok)
# The command runs in $W (a fresh folder holding nothing but what the variant puts there), with
# stdout in $T/out and stderr in $T/err. After it, CHECK (if set, a shell snippet) runs in $W.
CHECK=""
v() {
  local cls=$1 name=$2 expect=$3 needle=$4
  shift 5
  if [ -n "$FILTER" ] && ! [[ "$name" =~ $FILTER ]]; then CHECK=""; return 0; fi
  N[$cls]=$((N[$cls] + 1))
  rm -rf "$W"
  mkdir -p "$W"
  local why=""
  (cd "$W" && exec timeout -k 2 10 /usr/bin/time -o "$T/usage" -f '%M %e' "$@") \
    >"$T/out" 2>"$T/err" </dev/null
  local rc=$?
  local kib=0 secs=0
  [ -s "$T/usage" ] && read -r kib secs < <(tail -n 1 "$T/usage")
  rm -f "$T/usage"
  if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
    why="did not end within 10 s"
  elif [ "${expect%%:*}" = sig ]; then
    [ $rc -eq $((128 + ${expect#sig:})) ] || why="exit $rc (want $((128 + ${expect#sig:})))"
  elif [ $rc -ge 128 ]; then
    why="crashed: exit $rc (signal $((rc - 128)))"
  else
    case $expect in
      refuse) [ $rc -eq 1 ] || [ $rc -eq 2 ] || why="exit $rc (want a refusal, 1 or 2)" ;;
      usage) [ $rc -eq 2 ] || why="exit $rc (want 2)" ;;
      fail) [ $rc -eq 1 ] || why="exit $rc (want 1)" ;;
      ok) [ $rc -eq 0 ] || why="exit $rc (want 0)" ;;
      said | either) [ $rc -le 2 ] || why="exit $rc" ;;
    esac
  fi
  if [ -z "$why" ] && [ "$needle" != - ] && ! { [ "$expect" = either ] && [ $rc -eq 0 ]; } &&
    ! grep -Eq -- "$needle" "$T/err"; then
    why="stderr does not match /$needle/"
  fi
  if [ -z "$why" ] && grep -Eq "internal error|std::|terminate called|Assertion|Segmentation" "$T/err"; then
    why="internal error or bare library message"
  fi
  [ -z "$why" ] && [ "$kib" -ge 1048576 ] && why="max RSS $((kib / 1024)) MiB (over 1 GiB)"
  # Under --max-memory B (B >= 64 MiB), the whole process stays under 1.5 B. Smaller budgets
  # are below the process's own start-up size (about 25 MiB of libraries) and are only checked
  # for a refusal.
  local budget_kib
  budget_kib=$(hostile_budget_kib "$@")
  budget_kib=${budget_kib:-0}
  if [ -z "$why" ] && [ "$budget_kib" -ge 65536 ] && [ "$kib" -gt $((budget_kib * 3 / 2)) ]; then
    why="max RSS $((kib / 1024)) MiB (over 1.5 x --max-memory)"
  fi
  if [ -z "$why" ]; then
    local left
    left=$(find "$W" "$IN" \( -name '*.tmp-*' -o -name '*partial-*' \) 2>/dev/null | head -3)
    [ -n "$left" ] && why="temporaries left: $left"
  fi
  if [ -z "$why" ] && [ -n "$CHECK" ]; then
    local msg
    msg=$(cd "$W" && eval "$CHECK" 2>&1) || why="check failed: ${msg:0:300}"
  fi
  CHECK=""
  if [ -z "$why" ]; then
    OK[$cls]=$((OK[$cls] + 1))
  else
    FAILED+=("[$cls] $name: $why; stderr: $(head -c 300 "$T/err" | tr '\n' ' ')")
    echo "FAIL [$cls] $name: $why"
  fi
  return 0
}

# ---- inputs ------------------------------------------------------------------------------------
gen() { "$BIN" "$@" >/dev/null 2>"$T/gen_err" || { echo "setup failed: $* : $(cat "$T/gen_err")"; exit 1; }; }
gen generate gaussian --nx 64 --ny 64 --spacing 0.5um --sigma 0.1um --tau 2um --seed 1 -o "$IN/scan.npy"
gen generate gaussian --nx 64 --ny 64 --spacing 0.5um --sigma 0.1um --tau 2um --seed 2 -o "$IN/scan.x3p"
gen generate gaussian --nx 256 --ny 256 --spacing 0.5um --sigma 0.1um --tau 2um --seed 3 -o "$IN/big.x3p"
gen tabulate --model ggx --alpha 0.3 --resolution 65 -o "$IN/ndf.npy"
gen export bsdf --model ggx --alpha 0.3 --n 1.2 --k 3.5 --theta-i 4 --ndf-grid 8 --samples 8 \
  --wavelengths 3 -o "$IN/g.bsdf"
cp "$ROOT/examples/scenes/cylinders.json" "$IN/cylinders.json"
$PY "$ROOT/tests/cli/make_goniometer.py" "$IN/gonio.csv" --alpha 0.2 0.3 --rings 12 >/dev/null \
  || { echo "setup failed: goniometer CSV"; exit 1; }
$PY - "$IN" <<'PY' || { echo "setup failed: python inputs"; exit 1; }
import json, struct, sys
import numpy as np
t = sys.argv[1]
scene = lambda objs, tile="100x100um": json.dumps(
    {"tile": tile, "materials": {"m": {"type": "mirror"}, "d": {"type": "lambert", "albedo": 0.5}},
     "objects": objs})
open(t + "/scene.json", "w").write(scene([{"type": "plane", "material": "d"}]))
# Geometry of absurd size, one field at a time (Embree asserts on rays it cannot represent).
absurd = {
    "sphere_r": {"type": "spheres", "radius": "1e308um", "pitch": "50um", "material": "m"},
    "plane_z": {"type": "plane", "z": "1e300m", "material": "m"},
    "plane_far": {"type": "plane", "z": "1e6m", "material": "m"},
    "fibre_len": {"type": "fibers", "radius": "1um", "length": "1e300m", "count": 3, "material": "m"},
    "cyl_r": {"type": "cylinders", "radius": "1e300m", "count": 2, "material": "m"},
    "hf_zscale": {"type": "heightfield", "file": "scan.npy", "z_scale": 1e300, "material": "m"},
    "hf_sigma": {"type": "heightfield", "generate": {"kind": "gaussian", "nx": 32, "spacing": "1um",
                 "sigma": "1e300m", "tau": "5um"}, "material": "m"},
    "hf_tau": {"type": "heightfield", "generate": {"kind": "gaussian", "nx": 32, "spacing": "1um",
               "sigma": "0.1um", "tau": "1e300m"}, "material": "m"},
    "hf_spacing": {"type": "heightfield", "generate": {"kind": "gaussian", "nx": 32, "spacing": "1e-300m",
                   "sigma": "0.1um", "tau": "5um"}, "material": "m"},
    "nan_r": {"type": "spheres", "radius": "nanum", "pitch": "50um", "material": "m"},
    "sphere_z": {"type": "spheres", "radius": "5um", "pitch": "50um", "z": "-1e300m", "material": "m"},
    "weave_crimp": {"type": "weave", "pitch": "20um", "radius": "4um", "crimp": "1e300m", "material": "m"},
    "neg_r": {"type": "cylinders", "radius": "-1um", "count": 2, "material": "m"},
}
for k, o in absurd.items():  # height fields: a tile of their own extent (32 samples of 1 um)
    open(f"{t}/absurd_{k}.json", "w").write(scene([o], "32x32um" if k.startswith("hf_") else "100x100um"))
open(t + "/tile_huge.json", "w").write(scene([{"type": "plane", "material": "d"}], "1e300x1e300m"))
open(t + "/tile_tiny.json", "w").write(scene([{"type": "plane", "material": "d"}], "1e-300x1e-300m"))
open(t + "/albedo_nan.json", "w").write(scene([{"type": "plane", "material": "n"}]).replace(
    '"d": {', '"n": {"type": "lambert", "albedo": NaN}, "d": {'))
# Large flat JSON: 3 MB of {} (and of []) where an array belongs, and a sidecar likewise.
flat = ", ".join(["{}"] * 750000)
open(t + "/flat_scene.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [' + flat + "]}")
open(t + "/flat_extra.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [{"type": "plane", '
    '"material": "m"}], "notes": [' + flat + "]}")
open(t + "/flat_arrays.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [{"type": "plane", '
    '"material": "m"}], "notes": [' + ", ".join(["[]"] * 750000) + "]}")
open(t + "/flat_numbers.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [{"type": "plane", '
    '"material": "m"}], "notes": [' + ", ".join(["1e300"] * 500000) + "]}")
open(t + "/flat_keys.json", "w").write(
    '{"tile": "100x100um", "materials": {"m": {"type": "mirror"}}, "objects": [{"type": "plane", '
    '"material": "m"}], "notes": {' + ", ".join(f'"k{i}": {{}}' for i in range(200000)) + "}}")
open(t + "/albedo_big.json", "w").write(scene([{"type": "plane", "material": "n"}]).replace(
    '"d": {', '"n": {"type": "lambert", "albedo": 1e300}, "d": {'))
open(t + "/deep_scene.json", "w").write('{"tile": "100x100um", "x": ' + "[" * 100000 + "]" * 100000 + "}")
z = np.random.default_rng(5).normal(0, 1e-7, (32, 32))
for name, side in {
        "flat_side": '{"dx_m": 1e-6, "notes": [' + flat + "]}",
        "deep_side": '{"dx_m": 1e-6, "x": ' + "[" * 100000 + "]" * 100000 + "}",
        "long_side": '{"dx_m": 1e-6, "notes": "' + "a" * 3000000 + '"}',
        "nan_side": '{"dx_m": NaN}',
        "neg_side": '{"dx_m": -1e-6}',
        "huge_side": '{"dx_m": 1e300}',
        "tiny_side": '{"dx_m": 1e-300}',
        "str_side": '{"dx_m": "1um"}',
        "bom_side": '\ufeff{"dx_m": 1e-6}',
        "nul_side": '{"dx_m": 1e-6\u0000}',
        "cut_side": '{"dx_m": 1e-',
        "utf8_side": '{"dx_m": 1e-6, "note": "\udcff"}'}.items():
    np.save(f"{t}/{name}.npy", z)
    open(f"{t}/{name}.json", "wb").write(side.encode("utf-8", "surrogateescape"))
# Goniometer CSVs: negative values, a BOM, bad rows, one half vector, all below the horizon,
# measured at 1000 nm only, 10^6 rows.
head = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n"
rows = open(t + "/gonio.csv").read().splitlines()
body = rows[1:]
open(t + "/neg.csv", "w").write(head + "\n".join(r.rsplit(",", 1)[0] + ",-1.5" for r in body) + "\n")
open(t + "/someneg.csv", "w").write(head + "\n".join(body[:-1] + [body[-1].rsplit(",", 1)[0] + ",-0.5"]) + "\n")
open(t + "/bom.csv", "w", encoding="utf-8").write("\ufeff" + head + "\n".join(body) + "\n")
open(t + "/badrow.csv", "w").write(head + "\n".join(body[:5] + ["7,8,nine,10,550,1"] + body[5:]) + "\n")
open(t + "/shortrow.csv", "w").write(head + "\n".join(body[:5] + ["7,8"] + body[5:]) + "\n")
open(t + "/nanrow.csv", "w").write(head + "\n".join(body[:5] + ["10,0,10,180,550,nan"] + body[5:]) + "\n")
open(t + "/infrow.csv", "w").write(head + "\n".join(body[:5] + ["10,0,10,180,550,inf"] + body[5:]) + "\n")
open(t + "/hugeangle.csv", "w").write(head + "\n".join(body[:5] + ["1e300,0,10,180,550,1"] + body[5:]) + "\n")
open(t + "/nulrow.csv", "w").write(head + "\n".join(body[:5] + ["10,0,10\x00,180,550,1"] + body[5:]) + "\n")
open(t + "/onehalf.csv", "w").write(head + "".join("10,0,10,180,550,%g\n" % (1 + i) for i in range(50)))
open(t + "/below.csv", "w").write(head + "".join("95,0,95,180,550,%g\n" % (1 + i) for i in range(50)))
open(t + "/nm1000.csv", "w").write(head + "\n".join(r.rsplit(",", 2)[0] + ",1000," + r.rsplit(",", 1)[1] for r in body) + "\n")
open(t + "/headonly.csv", "w").write(head)
open(t + "/empty.csv", "w").write("")
with open(t + "/million.csv", "w") as f:
    f.write(head)
    line = "".join(body[i % len(body)] + "\n" for i in range(1000))
    for _ in range(1000):
        f.write(line)
# MERL tables: all negative (the header, then 90*90*180*3 doubles of -1).
n = 90 * 90 * 180
open(t + "/neg.binary", "wb").write(struct.pack("<3i", 90, 90, 180) + np.full(3 * n, -1.0).tobytes())
open(t + "/nan.binary", "wb").write(struct.pack("<3i", 90, 90, 180) + np.full(3 * n, np.nan).tobytes())
# An RGL .bsdf whose spectra are all negative, and one with a NaN: fields located from the header.
def tensor_fields(b):
    count = struct.unpack("<I", b[14:18])[0]
    at, out = 18, {}
    for _ in range(count):
        ln = struct.unpack("<H", b[at:at + 2])[0]; at += 2
        name = b[at:at + ln].decode(); at += ln
        ndim, dtype, off = struct.unpack("<HBQ", b[at:at + 11]); at += 11
        shape = struct.unpack("<%dQ" % ndim, b[at:at + 8 * ndim]); at += 8 * ndim
        out[name] = (dtype, off, int(np.prod(shape)))
    return out
src = bytearray(open(t + "/g.bsdf", "rb").read())
dt, off, cnt = tensor_fields(src)["spectra"]
neg = bytearray(src)
neg[off:off + 4 * cnt] = (-np.abs(np.frombuffer(bytes(src[off:off + 4 * cnt]), "<f4")) - 1).astype("<f4").tobytes()
open(t + "/neg.bsdf", "wb").write(neg)
nanb = bytearray(src)
nanb[off:off + 4] = struct.pack("<f", float("nan"))
open(t + "/nan.bsdf", "wb").write(nanb)
PY
head -c 3000 "$IN/scan.x3p" >"$IN/cut.x3p"
head -c 150 "$IN/scan.npy" >"$IN/cut.npy" && cp "$IN/scan.json" "$IN/cut.json"
head -c 1000 "$IN/g.bsdf" >"$IN/cut.bsdf"
head -c 5000 "$IN/neg.binary" >"$IN/cut.binary"
printf '\xef\xbb\xbf' | cat - "$IN/scan.npy" >"$IN/bom.npy" && cp "$IN/scan.json" "$IN/bom.json"
head -c 4096 /dev/zero >"$IN/zeros.x3p"
printf '{"objects": [' >"$IN/cut_scene.json"
printf '\0' >"$IN/nul.json"
cp "$IN/scan.npy" "$IN/a.npy" && cp "$IN/scan.json" "$IN/a.json"
echo "inputs made in $((SECONDS - T_START)) s"

# ---- 1. crashes: every numeric option with numbers that are not numbers or not sane ----------
# option table: COMMAND|OPTION|KIND, KIND = len (a length > 0), len0 (a length >= 0, where a
# tiny one is harmless), pair (two lengths, AxBunit), pos (a positive number), fin (any finite
# number), ang (an angle), cnt (a count), frac (a number in [0, 1]); the values tried depend on
# the kind, and none of them is valid.
BASE_NDF="ndf $IN/scan.npy --resolution 65 -o out.npy"
BASE_KIR="ndf $IN/scan.npy --method kirchhoff --resolution 65 --wavelength 555nm -o out.npy"
BASE_GEN="generate gaussian --nx 32 --ny 32 -o out.x3p"
BASE_BRU="generate brushed --nx 64 --ny 32 -o out.x3p"
BASE_GRA="generate grating --nx 32 --ny 32 -o out.x3p"
BASE_TAB="tabulate --model ggx --alpha 0.3 --resolution 33 -o out.npy"
BASE_SLI="slice $IN/ndf.npy -o out.svg"
BASE_BRD="brdf slice --model ggx --alpha 0.3 --metal Al -o out.csv"
BASE_BRN="brdf slice --model ggx --alpha 0.3 --k 3.5 -o out.csv"
BASE_BRR="brdf slice --model ggx --alpha 0.3 -o out.csv"
BASE_REN="render --alpha 0.3 --size 8 --spp 1 -o out.png"
BASE_SIM="simulate $IN/scene.json --rays 2000 --lmax 4 -o out.shbrdf"
BASE_TEX="texture $IN/big.x3p --texel 16um --resolution 17 -o out.exr"
BASE_MEA="measured ndf $IN/gonio.csv --resolution 33 -o out.npy"
BASE_EXP="export bsdf --model ggx --alpha 0.3 --n 1.2 --k 3.5 --theta-i 4 --ndf-grid 8 --samples 8 --wavelengths 3 -o out.bsdf"
BASE_SUN="sun ftp --s 1 -o out.csv"
BASE_SSL="sun slice --s 2 --theta-i 30deg --n 0.2 --k 3.0 -o out.csv"
BASE_PRE="predict $IN/scan.x3p --no-render --resolution 65 -o outdir"
OPTIONS=(
  "$BASE_NDF|--spacing|len" "$BASE_NDF|--filter-sigma|len" "$BASE_NDF|--resolution|cnt"
  "$BASE_NDF|--min-support|frac" "$BASE_NDF|--instrument-fwhm|ang"
  "$BASE_KIR|--wavelength|len" "$BASE_KIR|--patch|pair" "$BASE_KIR|--accuracy|frac"
  "$BASE_GEN|--nx|cnt" "$BASE_GEN|--spacing|len" "$BASE_GEN|--sigma|len0" "$BASE_GEN|--tau|len"
  "$BASE_GEN|--angle|ang" "$BASE_BRU|--alpha-along|pos" "$BASE_BRU|--scratch-depth|len0"
  "$BASE_BRU|--scratch-width|len0" "$BASE_GRA|--amplitude|len0" "$BASE_GRA|--period|len"
  "$BASE_TAB|--alpha|pos" "$BASE_TAB|--phi|ang" "$BASE_TAB|--resolution|cnt"
  "$BASE_SLI|--azimuth|ang" "$BASE_SLI|--theta-max|ang"
  "$BASE_BRD|--theta-i|ang" "$BASE_BRD|--wavelength|len" "$BASE_BRD|--samples|cnt"
  "$BASE_BRN|--n|pos" "$BASE_BRR|--r0|frac"
  "$BASE_REN|--size|cnt" "$BASE_REN|--spp|cnt" "$BASE_REN|--max-depth|cnt"
  "$BASE_REN|--env-scale|pos" "$BASE_REN|--brush-angle|ang" "$BASE_REN|--uv-scale|pos"
  "$BASE_REN|--exposure|fin"
  "$BASE_SIM|--lmax|cnt" "$BASE_SIM|--rays|cnt" "$BASE_SIM|--points|cnt" "$BASE_SIM|--branches|cnt"
  "$BASE_SIM|--max-depth|cnt" "$BASE_SIM|--time|pos"
  "$BASE_TEX|--texel|len" "$BASE_TEX|--filter-sigma|len" "$BASE_TEX|--size|cnt" "$BASE_TEX|--pitch|len"
  "$BASE_MEA|--theta-d|ang" "$BASE_MEA|--kernel|ang" "$BASE_MEA|--wavelength|len"
  "$BASE_MEA|--resolution|cnt"
  "$BASE_EXP|--theta-i|cnt" "$BASE_EXP|--samples|cnt" "$BASE_EXP|--wavelengths|cnt"
  "$BASE_SUN|--s|pos" "$BASE_SUN|--theta-step|ang" "$BASE_SSL|--theta-i|ang"
  "$BASE_PRE|--filter-sigma|len" "$BASE_PRE|--render-width|cnt" "$BASE_PRE|--texel|len"
  "$BASE_PRE|--wavelength|len"
)
values_of() {
  case $1 in
    len) echo "nanm -1um 1e300m 1e-300m" ;;
    len0) echo "infm -1um 1e300m" ;;
    pair) echo "nanx1um 1x-1um 1e300x1e300m 1e-300x1e-300m" ;;
    fin) echo "nan -inf 1e300" ;;
    pos) echo "nan -1 1e300" ;;
    ang) echo "nandeg 1e300deg" ;;
    cnt) echo "-1 1e300 18446744073709551615" ;;
    frac) echo "nan -1 1e300" ;;
  esac
}
for entry in "${OPTIONS[@]}"; do
  IFS='|' read -r base opt kind <<<"$entry"
  for val in $(values_of "$kind"); do
    case $kind in
      cnt) cls=3 ;;
      *) cls=1 ;;
    esac
    [ "$kind" = cnt ] && [ "$val" = -1 ] && cls=1
    # The base command without its own value of the option (given twice, CLI11 would refuse it
    # for that reason alone).
    b=$(sed -E "s/(^| )$opt [^ ]+//" <<<"$base")
    # shellcheck disable=SC2086
    v $cls "${b%% *} $opt $val" said "$opt" -- $BIN $b "$opt" "$val"
  done
done
# Global options.
for val in -1 0 nan 1e300 18446744073709551615T lots; do
  v 3 "--max-memory $val" refuse "--max-memory" -- $BIN --max-memory "$val" info "$IN/scan.npy"
done
for val in -1s nan inf 1e300h soon; do
  v 8 "--mpi-timeout $val" usage "--mpi-timeout" -- $BIN --mpi-timeout "$val" info "$IN/scan.npy"
done
# The reproducers of the issue and their relatives.
v 1 "ndf --spacing 1e-30m" said "--spacing|scan.npy" -- $BIN ndf "$IN/scan.npy" --spacing 1e-30m -o out.npy
v 1 "ndf filtered --spacing 1e-30m" said "--spacing|scan.npy" -- $BIN ndf "$IN/scan.npy" --method filtered --spacing 1e-30m -o out.npy
v 1 "predict --spacing 1e-30m" said "--spacing|scan.npy" -- $BIN predict "$IN/scan.npy" --spacing 1e-30m --no-render --resolution 65 -o outdir
v 1 "info --spacing 1e-30m" said "--spacing|scan.npy" -- $BIN info "$IN/scan.npy" --spacing 1e-30m
v 1 "convert --spacing 1e300m" said "--spacing|scan.npy" -- $BIN convert "$IN/scan.npy" out.x3p --spacing 1e300m
for k in sphere_r sphere_z weave_crimp plane_z fibre_len cyl_r hf_zscale hf_sigma hf_tau hf_spacing nan_r neg_r; do
  v 1 "simulate absurd $k" said "absurd_$k.json" -- bash -c "cp '$IN/scan.npy' '$IN/scan.json' . && cp '$IN/absurd_$k.json' . && exec '$BIN' simulate absurd_$k.json --rays 2000 --lmax 4 -o out.shbrdf"
done
v 1 "simulate tile 1e300 m" said "tile_huge.json" -- $BIN simulate "$IN/tile_huge.json" --rays 2000 --lmax 4 -o out.shbrdf
v 1 "simulate tile 1e-300 m" said "tile_tiny.json" -- $BIN simulate "$IN/tile_tiny.json" --rays 2000 --lmax 4 -o out.shbrdf
v 1 "simulate albedo NaN" refuse "albedo_nan.json" -- $BIN simulate "$IN/albedo_nan.json" --rays 2000 --lmax 4 -o out.shbrdf
v 1 "simulate albedo 1e300" refuse "albedo_big.json" -- $BIN simulate "$IN/albedo_big.json" --rays 2000 --lmax 4 -o out.shbrdf
# Corrupt and truncated files: refused naming them.
for f in cut.x3p cut.npy bom.npy zeros.x3p; do
  v 1 "info $f" refuse "$f" -- $BIN info "$IN/$f"
  v 1 "ndf $f" refuse "$f" -- $BIN ndf "$IN/$f" --resolution 65 -o out.npy
done
for f in cut.bsdf cut.binary; do
  v 1 "measured ndf $f" refuse "$f" -- $BIN measured ndf "$IN/$f" --resolution 33 -o out.npy
  v 1 "export bsdf $f" refuse "$f" -- $BIN export bsdf "$IN/$f" -o out.bsdf
done
v 1 "simulate truncated scene" refuse "cut_scene.json" -- $BIN simulate "$IN/cut_scene.json" --rays 2000 -o out.shbrdf
v 1 "simulate NUL scene" refuse "nul.json" -- $BIN simulate "$IN/nul.json" --rays 2000 -o out.shbrdf
for s in nan neg huge tiny str nul cut; do
  v 1 "sidecar $s" refuse "${s}_side" -- $BIN info "$IN/${s}_side.npy"
done
v 1 "sidecar with a BOM" either "bom_side" -- $BIN info "$IN/bom_side.npy"
v 1 "render --ndf truncated table" refuse "cut.npy" -- $BIN render --ndf "$IN/cut.npy" --size 8 --spp 1 -o out.png
v 1 "fit truncated table" refuse "cut.npy" -- $BIN fit "$IN/cut.npy"

# ---- 2. the file-size limit ------------------------------------------------------------------
# ulimit -f 20 (blocks of 1 KiB here) and outputs larger than that: reported like a full disk,
# naming the output, exit 1, no temporary.
fsz() {  # fsz NAME NEEDLE -- command...
  local name=$1 needle=$2
  shift 3
  v 2 "ulimit -f: $name" fail "$needle" -- bash -c 'ulimit -f 20; exec "$@"' _ "$@"
}
fsz "ndf" "out.npy" -- $BIN ndf "$IN/big.x3p" --resolution 257 -o out.npy
fsz "ndf exr" "out.exr" -- $BIN ndf "$IN/big.x3p" --resolution 1025 -o out.exr
fsz "tabulate" "out.npy" -- $BIN tabulate --model ggx --alpha 0.3 --resolution 257 -o out.npy
fsz "convert" "out.npy" -- $BIN convert "$IN/big.x3p" out.npy
fsz "convert xyz" "out.xyz" -- $BIN convert "$IN/big.x3p" out.xyz
fsz "generate" "out.npy" -- $BIN generate gaussian --nx 256 --ny 256 -o out.npy
GRID=(--theta-i 4 --ndf-grid 16 --samples 32 --wavelengths 3)
fsz "export bsdf" "out.bsdf" -- $BIN export bsdf --model ggx --alpha 0.3 --n 1.2 --k 3.5 "${GRID[@]}" -o out.bsdf
fsz "export mitsuba" "outdir|\.bsdf" -- $BIN export mitsuba --ndf "$IN/ndf.npy" --metal Al "${GRID[@]}" -o outdir
fsz "measured ndf" "out.npy" -- $BIN measured ndf "$IN/gonio.csv" --resolution 257 -o out.npy
fsz "predict" "outdir" -- $BIN predict "$IN/scan.x3p" --no-render --resolution 257 -o outdir
fsz "simulate" "out.shbrdf" -- $BIN simulate "$IN/scene.json" --rays 2000 --lmax 40 -o out.shbrdf
fsz "render exr" "out.exr" -- $BIN render --alpha 0.3 --size 600 --spp 1 -o out.exr
fsz "texture" "out.exr" -- $BIN texture "$IN/big.x3p" --texel 8um --resolution 17 --size 256 -o out.exr
fsz "brdf slice" "out.csv" -- $BIN brdf slice --model ggx --alpha 0.3 --metal Al --samples 20001 -o out.csv
fsz "info --preview" "out.png" -- $BIN info "$IN/big.x3p" --preview out.png
fsz "sh-project" "out.shbrdf" -- $BIN brdf sh-project --model ggx --alpha 0.3 --metal Al --lmax 24 -o out.shbrdf

# ---- 3. budgets and hangs --------------------------------------------------------------------
v 3 "max-memory 256M filter-sigma 1000m" said "filter-sigma|max-memory|memory budget" -- $BIN --max-memory 256M ndf "$IN/scan.npy" --filter-sigma 1000m -o out.npy
v 3 "filter-sigma 1000m" said "filter-sigma" -- $BIN ndf "$IN/scan.npy" --filter-sigma 1000m -o out.npy
v 3 "spacing 1pm" said "spacing|memory" -- $BIN --max-memory 256M ndf "$IN/scan.npy" --spacing 1pm -o out.npy
v 3 "spacing 1pm filtered" said "spacing|filter-sigma|memory" -- $BIN ndf "$IN/big.x3p" --spacing 1pm -o out.npy
v 3 "simulate --rays -1" refuse "--rays" -- $BIN simulate "$IN/scene.json" --rays -1 -o out.shbrdf
v 3 "simulate plane at 1e6 m" said "absurd_plane_far.json" -- $BIN simulate "$IN/absurd_plane_far.json" --rays 20000 --lmax 4 -o out.shbrdf
v 3 "goniometer 1e6 rows, --max-memory 64M" said "million.csv|memory" -- $BIN --max-memory 64M measured ndf "$IN/million.csv" --resolution 65 -o out.npy
v 3 "goniometer 1e6 rows" either "million.csv" -- $BIN measured ndf "$IN/million.csv" --resolution 65 -o out.npy
v 3 "max-memory 16M ndf" said "memory budget|max-memory" -- $BIN --max-memory 16M ndf "$IN/big.x3p" --resolution 2049 -o out.npy
v 3 "max-memory 16M render" said "memory|max-memory" -- $BIN --max-memory 16M render --alpha 0.3 --size 4096 --spp 1 -o out.png
v 3 "max-memory 8M tabulate 8193" said "memory|max-memory" -- $BIN --max-memory 8M tabulate --model ggx --alpha 0.3 --resolution 8193 -o out.npy
v 3 "max-memory 512M render 16384 px" said "--size|memory|max-memory" -- $BIN --max-memory 512M render --alpha 0.3 --size 16384 --spp 1 -o out.png
v 3 "simulate --points huge" refuse "--points" -- $BIN simulate "$IN/scene.json" --rays 2000 --points 2147483647 -o out.shbrdf
v 3 "simulate --lmax 100000" refuse "--lmax" -- $BIN simulate "$IN/scene.json" --rays 2000 --lmax 100000 -o out.shbrdf
v 3 "sun simulate-ftp huge samples" said "--samples" -- $BIN sun simulate-ftp --s 1 --samples 18446744073709551615 -o out.csv
v 3 "brdf sh-estimate huge incident" said "--incident" -- $BIN brdf sh-estimate --lambertian 1 --lmax 4 --incident 18446744073709551615
v 3 "texture --size huge" said "--size|memory" -- $BIN texture "$IN/big.x3p" --texel 16um --resolution 17 --size 1000000 -o out.exr
v 3 "generate 1e5 squared" said "--nx|memory" -- $BIN generate gaussian --nx 100000 --ny 100000 -o out.npy
v 3 "threads 1e6" said "threads" -- $BIN render --alpha 0.3 --size 8 --spp 1 --threads 1000000 -o out.png

# ---- 4. large and deep JSON ------------------------------------------------------------------
# Within 10 s (linear parsing), read (extra keys are ignored) or refused naming the file.
for f in flat_scene flat_extra flat_arrays flat_numbers flat_keys; do
  v 4 "simulate $f" either "$f.json" -- $BIN simulate "$IN/$f.json" --rays 2000 --lmax 4 -o out.shbrdf
done
v 4 "simulate deep_scene" refuse "deep_scene.json: JSON nested deeper" -- $BIN simulate "$IN/deep_scene.json" --rays 2000 --lmax 4 -o out.shbrdf
for f in flat_side long_side; do
  v 4 "info $f" either "${f}.json" -- $BIN info "$IN/$f.npy"
  v 4 "ndf $f" either "${f}.json" -- $BIN ndf "$IN/$f.npy" --resolution 65 -o out.npy
done
v 4 "info deep_side" refuse "deep_side.json: JSON nested deeper" -- $BIN info "$IN/deep_side.npy"
# JSON must be UTF-8: a byte that is not is refused, naming the file (NUL-free, so not binary).
v 4 "info sidecar not UTF-8" refuse "utf8_side.json" -- $BIN info "$IN/utf8_side.npy"
v 4 "simulate scene not UTF-8" refuse "utf8_scene.json" -- bash -c "printf '{\"name\": \"caf\\xe9\", \"tile\": \"1x1mm\", \"materials\": {\"m\": {\"type\": \"mirror\"}}, \"objects\": [{\"type\": \"plane\", \"material\": \"m\"}]}' >utf8_scene.json && exec $BIN simulate utf8_scene.json --rays 1000 --lmax 4 -o out.shbrdf"
v 4 "flat sidecar as --ndf" either "flat_side" -- $BIN render --ndf "$IN/flat_side.npy" --size 8 --spp 1 -o out.png

# ---- 5. messages -----------------------------------------------------------------------------
v 5 "goniometer all negative" refuse "neg.csv" -- $BIN measured ndf "$IN/neg.csv" --resolution 33 -o out.npy
v 5 "goniometer one negative" said "someneg.csv" -- $BIN measured ndf "$IN/someneg.csv" --resolution 33 -o out.npy
v 5 "goniometer BOM" ok - -- $BIN measured ndf "$IN/bom.csv" --resolution 33 -o out.npy
v 5 "goniometer bad row" refuse "badrow.csv" -- $BIN measured ndf "$IN/badrow.csv" --resolution 33 -o out.npy
v 5 "goniometer short row" refuse "shortrow.csv" -- $BIN measured ndf "$IN/shortrow.csv" --resolution 33 -o out.npy
v 5 "goniometer NaN value" said "nanrow.csv" -- $BIN measured ndf "$IN/nanrow.csv" --resolution 33 -o out.npy
v 5 "goniometer inf value" said "infrow.csv" -- $BIN measured ndf "$IN/infrow.csv" --resolution 33 -o out.npy
v 5 "goniometer angle 1e300" said "hugeangle.csv" -- $BIN measured ndf "$IN/hugeangle.csv" --resolution 33 -o out.npy
v 5 "goniometer NUL in a row" refuse "nulrow.csv" -- $BIN measured ndf "$IN/nulrow.csv" --resolution 33 -o out.npy
v 5 "goniometer one half vector" refuse "onehalf.csv" -- $BIN measured ndf "$IN/onehalf.csv" --resolution 33 -o out.npy
v 5 "goniometer below the horizon" refuse "below.csv" -- $BIN measured ndf "$IN/below.csv" --resolution 33 -o out.npy
v 5 "goniometer at 1000 nm used at 550 nm" said "nm1000.csv.*(1000|wavelength)" -- $BIN measured ndf "$IN/nm1000.csv" --resolution 33 -o out.npy
v 5 "goniometer header only" refuse "headonly.csv" -- $BIN measured ndf "$IN/headonly.csv" --resolution 33 -o out.npy
v 5 "goniometer empty" refuse "empty.csv" -- $BIN measured ndf "$IN/empty.csv" --resolution 33 -o out.npy
v 5 "bsdf negative" refuse "neg.bsdf" -- $BIN measured ndf "$IN/neg.bsdf" --resolution 33 -o out.npy
v 5 "bsdf NaN" said "nan.bsdf" -- $BIN measured ndf "$IN/nan.bsdf" --resolution 33 -o out.npy
v 5 "MERL all negative" refuse "neg.binary" -- $BIN measured ndf "$IN/neg.binary" --resolution 33 -o out.npy
v 5 "MERL all NaN" refuse "nan.binary" -- $BIN measured ndf "$IN/nan.binary" --resolution 33 -o out.npy
v 5 "MERL negative export" refuse "neg.binary" -- $BIN export bsdf "$IN/neg.binary" -o out.bsdf
v 5 "--kernel 1e300deg" refuse "--kernel" -- $BIN measured ndf "$IN/gonio.csv" --kernel 1e300deg --resolution 33 -o out.npy
v 5 "compare flat tables" refuse "ndf.npy|zero" -- bash -c "$PY -c 'import numpy as np; np.save(\"zero.npy\", np.zeros((65, 65)))' && exec $BIN measured compare zero.npy '$IN/ndf.npy'"
v 5 "render zero NDF" refuse "zero.npy" -- bash -c "$PY -c 'import numpy as np; np.save(\"zero.npy\", np.zeros((65, 65)))' && exec $BIN render --ndf zero.npy --size 8 --spp 1 -o out.png"
v 5 "missing input" usage "nope.x3p" -- $BIN ndf "$IN/nope.x3p" -o out.npy
v 5 "output folder missing" refuse "nodir" -- $BIN ndf "$IN/scan.npy" -o nodir/out.npy
v 5 "unknown extension" refuse "out.xyzzy" -- $BIN ndf "$IN/scan.npy" -o out.xyzzy

# ---- 6. data loss, injection, signals --------------------------------------------------------
same() {  # same NAME KEEP -- command... (run in $W on copies a.npy/a.json (and sub/a.npy);
  # KEEP: the files that must survive unchanged)
  local name=$1 keep=$2 f
  shift 3
  CHECK="true"
  for f in $keep; do CHECK="$CHECK && cmp -s $f '$IN/$(basename "$f")'"; done
  v 6 "output = input: $name" refuse "a\.npy|a\.json|g\.bsdf|sub|-o|output" -- bash -c 'cp "$0"/a.npy "$0"/a.json "$0"/g.bsdf . && mkdir sub && cp a.npy a.json sub/ && exec "$@"' "$IN" "$@"
}
same "ndf" "a.npy a.json" -- $BIN ndf a.npy -o a.npy
same "ndf via ./" "a.npy a.json" -- $BIN ndf a.npy -o ./a.npy
same "ndf via sub/.." "a.npy a.json" -- $BIN ndf a.npy -o sub/../a.npy
same "ndf, second of a set" "a.npy a.json" -- $BIN ndf "$IN/scan.npy" a.npy -o a.npy
same "convert" "a.npy a.json" -- $BIN convert a.npy a.npy
same "convert level" "a.npy a.json" -- $BIN convert a.npy a.npy --level plane
same "texture" "a.npy a.json" -- $BIN texture a.npy --texel 8um -o a.npy
same "export bsdf" "g.bsdf" -- $BIN export bsdf g.bsdf -o g.bsdf
# Into the .bsdf's own folder: the scene references the file where it is (no copy onto itself).
CHECK="cmp -s g.bsdf '$IN/g.bsdf' && grep -q 'g.bsdf' scene.xml"
v 6 "export mitsuba into the input's folder: the .bsdf kept and referenced" ok - -- bash -c 'cp "$0"/g.bsdf . && exec "$@"' "$IN" $BIN export mitsuba --bsdf g.bsdf -o .
same "predict into the input's folder" "sub/a.npy sub/a.json" -- $BIN predict sub/a.npy --no-render --resolution 65 -o sub
same "symlink to input" "a.npy a.json" -- bash -c "ln -s a.npy link.npy && exec $BIN ndf a.npy -o link.npy"
same "hard link to input" "a.npy a.json" -- bash -c "ln a.npy hard.npy && ln a.json hard.json && exec $BIN ndf a.npy -o hard.npy"
# Names with quotes, backslashes, newlines, XML specials and bytes that are not UTF-8 in
# exported scenes: escaped so that the file parses back to the same name, or refused.
for nm in 'q"uote' 'back\slash' $'new\nline' 'amp&<lt>' $'lat\xe9in' 'sp ace' "it's"; do
  q=$(printf %q "$nm")
  CHECK="$PY $HERE/hostile_names.py check-pbrt out $(printf %q "$nm.bsdf")"
  v 6 "export pbrt name $q" either "--bsdf|bsdf" -- bash -c 'cp "$1" "$2.bsdf" && exec "$0" export pbrt --bsdf "$2.bsdf" -o out' "$BIN" "$IN/g.bsdf" "$nm"
  CHECK="$PY $HERE/hostile_names.py check-mitsuba out $(printf %q "$nm.bsdf")"
  v 6 "export mitsuba name $q" either "--bsdf|bsdf" -- bash -c 'cp "$1" "$2.bsdf" && exec "$0" export mitsuba --bsdf "$2.bsdf" -o out' "$BIN" "$IN/g.bsdf" "$nm"
  CHECK="test -s $(printf %q "$nm.npy") && test -s $(printf %q "$nm.json")"
  v 6 "ndf output name $q" ok - -- $BIN ndf "$IN/scan.npy" --resolution 65 -o "$nm.npy"
done
v 6 "output name with a NUL-like escape" ok - -- $BIN ndf "$IN/scan.npy" --resolution 65 -o 'x\0y.npy'
# Signals mid-run: exit 128 + N, no temporary, an earlier output kept.
sigrun() {  # sigrun SIG DELAY NAME -- command...
  local sig=$1 delay=$2 name=$3
  shift 4
  CHECK="[ ! -e out.npy ] || cmp -s out.npy '$IN/ndf.npy' || $PY -c 'import numpy as np; np.load(\"out.npy\")'"
  v 6 "$sig mid-run: $name" "sig:$(kill -l "$sig")" - -- bash -c 'cp "$0"/ndf.npy out.npy; set -m; "${@:3}" & p=$!; sleep "$2"; kill -s "$1" $p; wait $p' "$IN" "$sig" "$delay" "$@"
}
for sig in INT TERM HUP; do
  sigrun $sig 0.5 "ndf" -- $BIN ndf "$IN/big.x3p" "$IN/big.x3p" "$IN/big.x3p" "$IN/big.x3p" --method kirchhoff --resolution 1025 -o out.npy
  sigrun $sig 0.5 "predict" -- $BIN predict "$IN/big.x3p" --resolution 257 --spp 16 -o outdir
  sigrun $sig 0.3 "render" -- $BIN render --alpha 0.3 --size 512 --spp 64 -o out.png
done

# ---- 7. Python -------------------------------------------------------------------------------
if PYTHONPATH=$PYDIR $PY -c "import microbrdf" 2>/dev/null; then
  pyv() {  # pyv NAME EXPECT NEEDLE CODE  (CODE raises: EXPECT refuse means a clean exception)
    local name=$1 expect=$2 needle=$3 code=$4
    v 7 "python: $name" "$expect" "$needle" -- env PYTHONPATH="$PYDIR" IN="$IN" $PY -c "
import os, sys, microbrdf as mb
IN = os.environ['IN']
try:
$(printf '%s\n' "$code" | sed 's/^/    /')
except (mb.FileError, mb.InputError) as e:
    print(type(e).__name__ + ': ' + str(e), file=sys.stderr); sys.exit(1)
"
  }
  pyv "NUL in a path" refuse "InputError: path: .*NUL" "mb.read_surface(IN + '/scan.npy\x00.x3p')"
  pyv "NUL in an output path" refuse "InputError: path: .*NUL" "mb.tabulate(resolution=33).save('t.npy\x00.exr')"
  pyv "NUL in a scene path" refuse "InputError: scene: .*NUL" "mb.simulate(IN + '/scene.json\x00x', rays=100)"
  pyv "NUL in scan list" refuse "InputError: surface: .*NUL" "mb.ndf([IN + '/scan.npy', IN + '/scan.x3p\x00'], resolution=33)"
  pyv "surrogate path" refuse "InputError: path: the path cannot be encoded" "mb.read_surface(IN + '/\ud800.x3p')"
  pyv "undecodable missing path" refuse "FileError: .*gone.xff.x3p: no such file" "mb.read_surface(os.fsdecode(os.fsencode(IN) + b'/gone\xff.x3p'))"
  pyv "sidecar not UTF-8" either "FileError: .*utf8_side" "s = mb.read_surface(IN + '/utf8_side.npy'); print(s.metadata); sys.exit(0 if isinstance(s.metadata['comment'], str) else 3)"
  pyv "sidecar flat 3 MB" either "FileError: .*flat_side" "mb.read_surface(IN + '/flat_side.npy')"
  pyv "scene not UTF-8" either "FileError: .*bad_utf8.json" "open('bad_utf8.json', 'wb').write(b'{\"name\": \"caf\xe9\", \"tile\": \"1x1mm\", \"materials\": {\"m\": {\"type\": \"mirror\"}}, \"objects\": [{\"type\": \"plane\", \"material\": \"m\"}]}'); mb.simulate('bad_utf8.json', rays=100, lmax=2, points=4)"
  pyv "scene flat 3 MB" refuse "FileError: .*flat_scene.json" "mb.simulate(IN + '/flat_scene.json', rays=100, lmax=2)"
  pyv "slice samples 2**40" refuse "InputError: samples: needs" "mb.tabulate(resolution=33).slice(samples=2**40)"
  pyv "resampled 2**24" refuse "InputError: resolution: needs" "mb.tabulate(resolution=33).resampled(2**24)"
  pyv "albedo n 10**6" refuse "InputError: albedo: n must" "mb.brdf(model='ggx', alpha=0.3, metal='Al').albedo([0, 0, 1.0], n=10**6)"
  pyv "export_bsdf grids" refuse "InputError: wavelengths: needs" "mb.export_bsdf('o.bsdf', model='ggx', alpha=0.3, n=1.2, k=3.5, isotropic=False, theta_i=512, phi_i=512, samples=512, wavelengths=512)"
  pyv "ndf spacing 1e-30" either "spacing|scan.npy" "mb.ndf(IN + '/scan.npy', spacing=1e-30, resolution=33)"
  pyv "ndf filter_sigma 1e3" either "filter_sigma|scan.npy|memory" "mb.ndf(IN + '/scan.npy', filter_sigma=1e3, resolution=33)"
  pyv "simulate absurd sphere" refuse "absurd_sphere_r.json" "mb.simulate(IN + '/absurd_sphere_r.json', rays=2000, lmax=4)"
  pyv "simulate plane z 1e300" refuse "absurd_plane_z.json" "mb.simulate(IN + '/absurd_plane_z.json', rays=2000, lmax=4)"
  pyv "measured negative CSV" refuse "neg.csv" "mb.measured_ndf(IN + '/neg.csv', resolution=33)"
  pyv "truncated x3p" refuse "FileError: .*cut.x3p" "mb.read_surface(IN + '/cut.x3p')"
  pyv "render size 2**20" refuse "InputError: (size|render)" "mb.render(mb.brdf(model='ggx', alpha=0.3, metal='Al'), size=2**20, spp=1)"
  pyv "tabulate resolution 2**40" refuse "InputError: resolution" "mb.tabulate(resolution=2**40)"
  pyv "predict NUL out_dir" refuse "InputError: out_dir: .*NUL" "mb.predict(IN + '/scan.x3p', 'out\x00dir', no_render=True)"
else
  echo "note: the Python module is not built ($PYDIR): class 7 skipped"
fi

# ---- 8. MPI ----------------------------------------------------------------------------------
if [ -n "$MPIRUN" ]; then
  MPI=("$MPIRUN" --allow-run-as-root --oversubscribe -np 3)
  # A rank stopped with SIGSTOP 2 s into the run: the watchdog names it within --mpi-timeout
  # (2 s) and ends the job; every process gone.
  mpistop() {  # mpistop RANK
    local r=$1
    CHECK="[ ! -e out.npy ]"
    # Rank R is stopped once rank 0 has printed its first line: every rank is then past
    # MPI_Init and runs its watchdog (started before any command output).
    v 8 "stopped rank $r" fail "--mpi-timeout: MPI rank $r \(pid [0-9]+ on .*\) has not responded" -- bash -c '
      "$@" 2>run.err & job=$!
      for k in $(seq 1 200); do [ -s run.err ] && break; sleep 0.05; done
      for p in $(pgrep -f -- "$PWD/out.npy"); do
        [ "$(cat /proc/$p/comm 2>/dev/null)" = microbrdf ] || continue
        tr "\0" "\n" </proc/$p/environ 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK='"$r"'" && pid=$p
      done
      kill -STOP "$pid"; wait $job; rc=$?; kill -KILL "$pid" 2>/dev/null; cat run.err >&2; exit $rc' _ \
      "${MPI[@]}" "$BIN" --mpi-timeout 2s ndf "$IN/big.x3p" "$IN/big.x3p" "$IN/big.x3p" "$IN/big.x3p" \
      "$IN/big.x3p" "$IN/big.x3p" --method kirchhoff --resolution 1025 -o "$W/out.npy"
  }
  mpistop 1
  mpistop 2
  mpistop 0
  CHECK="[ ! -e out.npy ]"
  # Direct sums (4e9 terms a scan, over 10 s on any machine): still running when the signal comes.
  v 8 "SIGINT to mpirun" said "interrupt" -- bash -c 'set -m; "$@" & job=$!; sleep 2.5; kill -INT $job; wait $job' _ \
    "${MPI[@]}" "$BIN" ndf "$IN/big.x3p" "$IN/big.x3p" "$IN/big.x3p" --method kirchhoff --direct --resolution 257 -o "$W/out.npy"
  v 8 "mpi bad scan" fail "cut.x3p" -- "${MPI[@]}" "$BIN" ndf "$IN/scan.x3p" "$IN/cut.x3p" "$IN/scan.x3p" --resolution 65 -o out.npy
  v 8 "mpi NUL scene" fail "nul.json" -- "${MPI[@]}" "$BIN" simulate "$IN/nul.json" --rays 1000 -o out.shbrdf
  v 8 "mpi flat scene" said "flat_scene.json" -- "${MPI[@]}" "$BIN" simulate "$IN/flat_scene.json" --rays 1000 --lmax 4 -o out.shbrdf
  # (the limit on the ranks alone: mpirun's own PMIx files would exceed it first)
  v 8 "mpi ulimit -f" fail "out.npy" -- "${MPI[@]}" bash -c 'ulimit -f 20; exec "$@"' _ "$BIN" ndf "$IN/big.x3p" "$IN/scan.x3p" --resolution 257 -o out.npy
  v 8 "mpi output = input" refuse "a.npy|-o" -- bash -c 'cp "$0"/a.npy "$0"/a.json . && exec "$@"' "$IN" "${MPI[@]}" "$BIN" ndf a.npy -o a.npy
else
  echo "note: mpirun not found: class 8 (MPI) limited to the flag checks"
fi

# ---- tally -----------------------------------------------------------------------------------
echo
echo "hostile suite: $((SECONDS - T_START)) s"
printf '%-5s %-32s %8s %8s\n' class name variants passed
total=0 passed=0
for c in 1 2 3 4 5 6 7 8; do
  printf '%-5s %-32s %8d %8d\n' "$c" "${CLASS_NAME[$c]}" "${N[$c]}" "${OK[$c]}"
  total=$((total + N[$c]))
  passed=$((passed + OK[$c]))
done
printf '%-5s %-32s %8d %8d\n' all "" "$total" "$passed"
if [ ${#FAILED[@]} -gt 0 ]; then
  echo
  echo "${#FAILED[@]} variants failed:"
  printf '  %s\n' "${FAILED[@]}"
  exit 1
fi
echo ok
