#!/usr/bin/env bash
# `microbrdf ndf --method kirchhoff`: the integral of D_K before normalising is in the JSON, and a
# departure from 1 above 2% warns on stderr and sets raw_integral_warning. Point samples of a
# table coarser than lambda_q / (2 L) miss or double the speckle (--dk-supersample 1); the
# default cell averages integrate to 1.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 48 x 36 um of a gently rough surface at 0.12 um: at N = 129 the node spacing (0.0156) is above
# lambda_q / (2 L) = 0.0058, so the automatic S is 3.
$BIN generate gaussian --nx 400 --ny 300 --spacing 0.12um --sigma 0.02um --tau 3um --seed 2 \
  -o "$T/g.x3p" 2>/dev/null || fail generate
for ss in 1 auto; do
  $BIN ndf "$T/g.x3p" --method kirchhoff --dk-integration midpoint --level none --resolution 129 \
    --dk-supersample $ss -o "$T/k$ss.npy" --json >"$T/k$ss.out" 2>"$T/k$ss.err" ||
    fail "ndf --dk-supersample $ss: $(cat "$T/k$ss.err")"
done
/usr/bin/python3 - "$T" <<'PY' || fail "raw integral / warning"
import json, os, sys
d = sys.argv[1]
p, a = (json.load(open(os.path.join(d, f"k{s}.out")))["kirchhoff"] for s in ("1", "auto"))
perr, aerr = (open(os.path.join(d, f"k{s}.err")).read() for s in ("1", "auto"))
print(f"raw integral: point samples {p['raw_integral']:.4f}, cell averages "
      f"({a['supersample']} x {a['supersample']}) {a['raw_integral']:.4f}")
assert p["supersample"] == 1 and a["supersample"] == 3, (p["supersample"], a["supersample"])
assert abs(p["raw_integral"] - 1) > 0.02 and p["raw_integral_warning"], p
assert "integrated to" in perr, perr
assert abs(a["raw_integral"] - 1) < 0.01 and not a["raw_integral_warning"], a
assert "integrated to" not in aerr, aerr
assert a["integration"] == "midpoint"
PY
# Bad values name the flag.
$BIN ndf "$T/g.x3p" --method kirchhoff --dk-supersample 2 -o "$T/x.npy" 2>"$T/err" &&
  fail "even --dk-supersample accepted"
grep -q -- "--dk-supersample" "$T/err" || fail "error does not name --dk-supersample"
$BIN ndf "$T/g.x3p" --method kirchhoff --dk-integration simpson -o "$T/x.npy" 2>"$T/err" &&
  fail "unknown --dk-integration accepted"
grep -q "simpson" "$T/err" || fail "error does not name the bad integration"
# The stack over lambda_q (13 tables of 8.4 MB at 1025^2) is checked against --max-memory before
# it is allocated, naming the file; one table fits the same budget.
$BIN --max-memory 64M ndf "$T/g.x3p" --method kirchhoff --resolution 1025 -o "$T/s.npy" \
  2>"$T/err" && fail "a 96 MiB stack accepted under --max-memory 64M"
grep -q "g.x3p: needs .* for the D_K tables over lambda_q" "$T/err" || fail "message: $(cat "$T/err")"
[ -e "$T/s.npy" ] && fail "a refused stack left its file"
$BIN --max-memory 64M ndf "$T/g.x3p" --method kirchhoff --resolution 1025 --dk-stack single \
  -o "$T/s.npy" 2>"$T/err" || fail "one table under 64M: $(cat "$T/err")"
echo "ok"
