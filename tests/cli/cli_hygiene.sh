#!/usr/bin/env bash
# The command line's manners, checked the way a user meets them: every usage error exits 2 and
# names the flag or file; cheap problems are found before any heavy work (and before any output
# is created); `info --keep-going` reports unreadable files and fails at the end; progress is
# drawn (with carriage returns) only on a terminal; values that do not exist print as "n/a".
set -u
BIN=$1 DATA=$2 REPO_DATA=$3
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
ENV="$REPO_DATA/envmaps/blender_studio.exr"
usage() {  # usage NAME PATTERN -- COMMAND...: exit code 2 and PATTERN in the message
  local name=$1 pattern=$2; shift 3
  "$@" >"$T/out" 2>"$T/err"; local rc=$?
  [ $rc -eq 2 ] || fail "$name: exit $rc, not 2: $(cat "$T/err")"
  grep -q -e "$pattern" "$T/err" || fail "$name: message lacks '$pattern': $(cat "$T/err")"
}

# --- Usage errors exit 2, whatever part of the CLI finds them.
usage "no input" "required" -- $BIN info
usage "unknown flag" "--frobnicate" -- $BIN info "$DATA/test.gwy" --frobnicate
usage "missing input file" "nope.x3p" -- $BIN info "$T/nope.x3p"
usage "missing input (ndf)" "nope.x3p" -- $BIN ndf "$T/nope.x3p" -o "$T/n.npy"
usage "missing input (fit)" "nope.npy" -- $BIN fit "$T/nope.npy" --model ggx
usage "missing input (slice)" "nope.npy" -- $BIN slice "$T/nope.npy" -o "$T/s.png"
usage "missing input (brdf)" "nope.npy" -- $BIN brdf slice --metal Al --ndf "$T/nope.npy" -o "$T/b.csv"
usage "missing scene (simulate)" "nope.json" -- $BIN simulate "$T/nope.json" -o "$T/o.shbrdf"
# A file that exists but cannot be parsed is a failure while working: exit 1.
head -c 3000 /dev/urandom >"$T/junk.sur"
$BIN info "$T/junk.sur" >/dev/null 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "junk.sur" "$T/err" || fail "corrupt file: exit $rc, not 1: $(cat "$T/err")"
# The message names the flag that is wrong, not the one that is missing.
usage "negative alpha" "--alpha" -- $BIN render --scene sphere --model ggx --alpha -0.1 -o "$T/a.png"
grep -q "must be in (0, 10\]" "$T/err" || fail "negative alpha: message: $(cat "$T/err")"
grep -q "give the roughness" "$T/err" && fail "negative alpha: blames a missing roughness"
usage "alpha-y not a number" "--alpha-y" -- $BIN tabulate --model ggx --alpha-x 0.1 --alpha-y abc -o "$T/t.npy"

# --- Cheap checks before heavy work: a bad output, environment map or metal is refused at
# once, with every problem listed, and nothing is created.
usage "render output extension" "unknown extension '.jpg'" -- \
  $BIN render --scene sphere --model ggx --alpha 0.2 --size 512 --spp 4096 -o "$T/r.jpg"
usage "render output folder" "does not exist" -- \
  $BIN render --scene sphere --model ggx --alpha 0.2 -o "$T/no/such/dir/r.png"
echo "not an image" >"$T/env.exr"
usage "render envmap signature" "--envmap" -- \
  $BIN render --scene sphere --model ggx --alpha 0.2 --size 512 --spp 4096 --envmap "$T/env.exr" -o "$T/r.png"
grep -q "OpenEXR or Radiance" "$T/err" || fail "envmap: message: $(cat "$T/err")"
usage "render metal" "--metal" -- $BIN render --scene sphere --model ggx --alpha 0.2 --metal Kryptonite -o "$T/r.png"
# Several problems are reported together.
usage "render several" "--envmap.*--metal" -- \
  $BIN render --scene sphere --model ggx --alpha 0.2 --envmap "$T/missing.hdr" --metal Kryptonite -o "$T/r.png"
ls "$T" | grep -q "^r\." && fail "render wrote an output despite a usage error"
# predict checks the environment map before its (long) NDF and fit stages.
start=$(date +%s)
usage "predict envmap" "--envmap" -- \
  $BIN predict "$DATA/sample-land.x3p" --envmap "$T/missing.exr" -o "$T/p"
[ -e "$T/p" ] && fail "predict created its output folder despite a usage error"
usage "predict metal" "--metal" -- $BIN predict "$DATA/sample-land.x3p" --metal Kryptonite -o "$T/p"
usage "predict scan" "nope.x3p" -- $BIN predict "$T/nope.x3p" -o "$T/p"
[ $(( $(date +%s) - start )) -lt 60 ] || fail "predict's usage errors took more than a minute"

# --- info --keep-going: unreadable files are reported, the rest is described, exit 1 at the end.
mkdir "$T/scans"
cp "$DATA/test.gwy" "$DATA/ISO5436-sample1_bin.x3p" "$T/scans/"
head -c 3000 /dev/urandom >"$T/scans/junk.sur"
head -c 400 "$DATA/sur-2.sur" >"$T/scans/cut.sur"
$BIN info "$T/scans" --level none >"$T/out" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] || fail "info without --keep-going on a bad folder: exit $rc"
$BIN info --keep-going --json --level none "$T/scans" >"$T/j" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] || fail "info --keep-going: exit $rc, not 1"
grep -q "junk.sur" "$T/err" && grep -q "cut.sur" "$T/err" || fail "keep-going: failures not named: $(cat "$T/err")"
grep -q "2 of 4 files could not be read" "$T/err" || fail "keep-going: no summary: $(cat "$T/err")"
python3 - "$T/j" <<'PY' || fail "keep-going JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert len(j["surfaces"]) == 2, j["surfaces"]
assert sorted(f["path"].rsplit("/", 1)[1] for f in j["failed"]) == ["cut.sur", "junk.sur"], j["failed"]
assert all(f["error"] for f in j["failed"])
PY
$BIN info --keep-going "$DATA/test.gwy" "$T/nope.gwy" >"$T/out" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "nope.gwy" "$T/err" && grep -q "test.gwy" "$T/out" || fail "keep-going with a missing file: rc $rc"

# --- Progress: no carriage return in a redirected log; redrawn in place on a terminal.
R=(--scene sphere --model ggx --alpha 0.3 --size 24 --spp 4 --threads 2 --envmap "$ENV")
$BIN render "${R[@]}" -o "$T/p1.png" 2>"$T/log" >/dev/null || fail "render: $(cat "$T/log")"
grep -q $'\r' "$T/log" && fail "carriage return in a redirected log"
grep -q "render: 100%" "$T/log" || fail "no final progress line in the log: $(cat "$T/log")"
[ "$(grep -c "%" "$T/log")" -le 4 ] || fail "the log gets more than 4 progress lines: $(cat "$T/log")"
MICROBRDF_PROGRESS=terminal $BIN render "${R[@]}" -o "$T/p2.png" 2>"$T/tty" >/dev/null || fail "render (terminal)"
grep -q $'\r' "$T/tty" || fail "no carriage return in terminal mode"
if command -v script >/dev/null; then  # a real pseudo-terminal, without the override
  script -qec "$BIN render ${R[*]} -o $T/p3.png >/dev/null" /dev/null >"$T/pty" 2>&1 || fail "render under script"
  grep -q $'\r'"microbrdf render:" "$T/pty" || fail "no redrawn progress on a terminal"
fi
$BIN render "${R[@]}" --quiet -o "$T/p4.png" 2>"$T/quiet" >/dev/null || fail "render --quiet"
[ -s "$T/quiet" ] && fail "--quiet still prints: $(cat "$T/quiet")"

# --- Values that do not exist print as n/a, never nan or inf.
$BIN generate cylinders -o "$T/c.x3p" >"$T/out" 2>"$T/err" || fail "generate cylinders: $(cat "$T/err")"
grep -qiw -e "nan" -e "inf" -e "nan m" "$T/err" && fail "generate prints nan/inf: $(cat "$T/err")"
grep -q "n/a" "$T/err" || fail "generate cylinders: no n/a for the correlation length: $(cat "$T/err")"
$BIN info "$T/c.x3p" >"$T/out" 2>"$T/err" || fail "info cylinders"
grep -qiw -e "nan" -e "-nan" "$T/out" && fail "info prints nan: $(cat "$T/out")"
echo ok
