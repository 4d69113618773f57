#!/usr/bin/env bash
# Spherical-harmonic BRDF files as a user handles them: `brdf sh-project` writes a .shbrdf,
# `brdf info --sh` summarises it (JSON keys), `brdf slice --sh` tabulates it and agrees with the
# analytic model it came from, reciprocity of the SH slices, damping, and clear errors (missing,
# truncated, not-a-shbrdf files; --sh combined with a model) with a non-zero exit and no output.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN brdf sh-project --model ggx --alpha 0.35 --metal Al --lmax 14 -o "$T/g.shbrdf" --json \
  >"$T/proj.json" 2>"$T/proj.err" || fail "sh-project"
head -c 8 "$T/g.shbrdf" | grep -q MBSHBRDF || fail "no MBSHBRDF magic"
$BIN brdf info --sh "$T/g.shbrdf" --json >"$T/info.json" || fail "info --json"
$BIN brdf info --sh "$T/g.shbrdf" >"$T/info.txt" || fail "info text"
grep -q "lmax 14" "$T/info.txt" || fail "info text lacks lmax"
for t in 20 50; do
  $BIN brdf slice --sh "$T/g.shbrdf" --theta-i ${t}deg --samples 181 -o "$T/s$t.csv" \
    --json >"$T/s$t.json" || fail "slice --sh $t"
  $BIN brdf slice --model ggx --alpha 0.35 --metal Al --theta-i ${t}deg --samples 181 \
    -o "$T/a$t.csv" >/dev/null || fail "slice analytic $t"
done
$BIN brdf slice --sh "$T/g.shbrdf" --l-filter 8 --filter-width 3 --theta-i 30 --plane out \
  --plot "$T/d.png" >/dev/null || fail "slice --sh damped plot"
[ -s "$T/d.png" ] || fail "no plot"
python3 - "$T" <<'PY' || fail "SH files, info and slices"
import json, sys
T = sys.argv[1]
info = json.load(open(f"{T}/info.json"))
assert info["lmax"] == 14 and info["size"] == 14 * 15 // 2, info
assert info["isotropic"] is True
assert info["file_bytes"] > 105 * 105 * 8
alb = {round(e["theta_i_deg"]): e["albedo"] for e in info["albedo"]}
proj = json.load(open(f"{T}/proj.json"))
assert abs(proj["albedo"][0]["albedo"] - alb[0]) < 1e-12
assert 0.7 < alb[0] < 0.9 and 0.6 < alb[60] < 0.9, alb   # aluminium, GGX 0.35
assert 0.6 < info["hemispherical_albedo"] < 0.9
assert "projection of" in info["meta"]["source"]
def load(name):
    rows = [r for r in open(f"{T}/{name}") if not r.startswith("#")]
    import csv
    return {round(float(r["angle_deg"]), 6): float(r["brdf_per_sr"]) for r in csv.DictReader(rows)}
for t in (20, 50):
    s, a = load(f"s{t}.csv"), load(f"a{t}.csv")
    peak = max(a.values())
    # away from the horizon the lmax-14 expansion follows the analytic lobe within 3 % of its peak
    bad = [(k, s[k], a[k]) for k in a if abs(k) < 75 and abs(s[k] - a[k]) > 0.03 * peak]
    assert not bad, bad[:5]
    js = json.load(open(f"{T}/s{t}.json"))
    apeak = max((k for k in a if abs(k) < 80), key=a.get)  # off-specular peak of the lobe
    assert js["sh"].endswith("g.shbrdf") and abs(js["peak_angle_deg"] - apeak) < 5, (js, apeak)
# reciprocity: f(wi = 20 deg, wo = 50 deg mirror side) == f(wi = 50, wo = 20)
s20, s50 = load("s20.csv"), load("s50.csv")
assert abs(s20[50.0] - s50[20.0]) < 1e-9 * max(1, s20[50.0]), (s20[50.0], s50[20.0])
PY

# sh-estimate: a white Lambertian plane gives albedo 1 within 1 % (docs/theory.md §6.3), the same result
# for any thread count, and Q falls as N^-1/2 over two decades.
OMP_NUM_THREADS=2 $BIN brdf sh-estimate --lambertian 1 --lmax 6 --incident 400000 --seed 3 --json \
  -o "$T/lam.shbrdf" >"$T/lam.json" 2>/dev/null || fail "sh-estimate --lambertian"
OMP_NUM_THREADS=1 $BIN brdf sh-estimate --lambertian 1 --lmax 6 --incident 400000 --seed 3 --json \
  >"$T/lam1.json" 2>/dev/null || fail "sh-estimate one thread"
for n in 400 4000 40000; do
  $BIN brdf sh-estimate --model ggx --alpha 0.3 --metal Al --lmax 8 --incident $n --seed 5 \
    --json >"$T/q$n.json" 2>/dev/null || fail "sh-estimate ggx $n"
done
python3 - "$T" <<'PY' || fail "sh-estimate results"
import json, math, sys
T = sys.argv[1]
j, j1 = json.load(open(f"{T}/lam.json")), json.load(open(f"{T}/lam1.json"))
assert j["q"] == j1["q"] and j["m_10_10"] == j1["m_10_10"], "thread count changed the result"
assert abs(j["m_10_10"] - 4 / 3) < 0.01 * 4 / 3, j["m_10_10"]
for e in j["albedo"]:
    if e["theta_i_deg"] <= 60:
        assert abs(e["albedo"] - 1) < 0.01, e
q = [json.load(open(f"{T}/q{n}.json"))["q"] for n in (400, 4000, 40000)]
slope = (math.log(q[2]) - math.log(q[0])) / math.log(100)
assert abs(slope + 0.5) < 0.1, (q, slope)
PY
$BIN brdf info --sh "$T/lam.shbrdf" --json | python3 -c "import json,sys; j=json.load(sys.stdin); \
assert j['meta']['incident_count'] == 400000 and 'q' in j['meta'], j['meta']" || fail "meta of estimate"

# Errors: exit non-zero, a message naming the file, and no output written.
$BIN brdf slice --sh "$T/missing.shbrdf" -o "$T/x.csv" 2>"$T/e1" && fail "missing file accepted"
grep -q "missing.shbrdf" "$T/e1" || fail "error does not name the missing file"
head -c 500 "$T/g.shbrdf" >"$T/cut.shbrdf"
$BIN brdf info --sh "$T/cut.shbrdf" 2>"$T/e2" && fail "truncated file accepted"
grep -q "cut.shbrdf.*truncated" "$T/e2" || fail "truncation not reported: $(cat "$T/e2")"
$BIN brdf slice --sh "$T/info.json" -o "$T/x.csv" 2>"$T/e3" && fail "JSON accepted as shbrdf"
grep -q "MBSHBRDF" "$T/e3" || fail "wrong-format message"
$BIN brdf slice --sh "$T/g.shbrdf" --model ggx --alpha 0.2 -o "$T/x.csv" 2>"$T/e4" \
  && fail "--sh with --model accepted"
grep -q "give one BRDF, not --model/--alpha, --sh" "$T/e4" || fail "--sh/--model message"
$BIN brdf slice --sh "$T/g.shbrdf" --l-filter 3 -o "$T/x.csv" 2>/dev/null \
  && fail "--l-filter without width accepted"
[ ! -e "$T/x.csv" ] || fail "partial output written"
$BIN brdf sh-project --model ggx --alpha 0.3 --metal Al --lmax 0 -o "$T/y.shbrdf" 2>/dev/null \
  && fail "lmax 0 accepted"
[ ! -e "$T/y.shbrdf" ] || fail "output written on error"
ls "$T" | grep -q tmp && fail "temporary file left behind"
echo ok
