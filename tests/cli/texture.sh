#!/usr/bin/env bash
# `microbrdf texture` as a user runs it: fit mode on generated brushed scans (texel image + preview,
# --json keys), synthesis from the fitted .exr and from --along/--across strips (size, seed
# reproducible, statistics kept), and clear errors with a non-zero exit and no output file.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

for s in 1 2; do
  $BIN generate brushed --preset stainless4 --nx 768 --ny 512 --seed $s -o "$T/s$s.x3p" \
    >/dev/null 2>&1 || fail "generate $s"
done

# --- fit mode: 2 scans of 6 x 4 texels of 14 um, laid side by side along x.
$BIN texture "$T/s1.x3p" "$T/s2.x3p" --texel 14um --json -o "$T/texels.exr" >"$T/fit.json" \
  2>"$T/fit.err" || { cat "$T/fit.err"; fail "texture fit"; }
[ -s "$T/texels.exr" ] || fail "no texel image"
[ -s "$T/texels.png" ] || fail "no preview"
python3 - "$T/fit.json" <<'PY' || fail "fit JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["mode"] == "fit", j["mode"]
assert (j["nx"], j["ny"]) == (12, 4), (j["nx"], j["ny"])
assert abs(j["texel_m"] - 14e-6) < 1e-12
assert j["valid"] + j["failed"] == 48 and j["valid"] >= 40, j
for k in ("alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z"):
    c = j["channels"][k]
    assert all(x in c for x in ("mean", "std", "min", "max")), c
assert 1e-4 <= j["channels"]["alpha_x"]["mean"] < j["channels"]["alpha_y"]["mean"] < 2
assert len(j["meta"]["scans"]) == 2 and j["meta"]["scans"][1]["offset"] == 6
# Widths below a node of the 129^2 tables (brushed texels along the scratches) come from the
# texels' normals; the counts are reported.
assert j["alpha_zoomed"] >= 40 and j["alpha_lifted_to_min"] <= 2, j
PY
grep -q "2 scan" "$T/fit.err" || fail "no progress on stderr"

# --- synthesis from the texel image: same seed -> same file; statistics kept.
$BIN texture "$T/texels.exr" --size 64 --seed 3 -o "$T/a.exr" --no-preview --json >"$T/a.json" \
  2>/dev/null || fail "synthesis"
$BIN texture "$T/texels.exr" --size 64 --seed 3 -o "$T/b.exr" --no-preview >/dev/null 2>&1 \
  || fail "synthesis again"
cmp -s "$T/a.exr" "$T/b.exr" || fail "same seed, different texture"
[ ! -e "$T/a.png" ] || fail "--no-preview wrote a preview"
python3 - "$T/fit.json" "$T/a.json" <<'PY' || fail "synthesis JSON"
import json, sys
f, a = (json.load(open(p)) for p in sys.argv[1:])
assert a["mode"] == "synthesis" and (a["nx"], a["ny"]) == (64, 64) and a["seed"] == 3
assert a["failed"] == 0
for k in ("alpha_x", "alpha_y", "theta_x"):
    e, s = f["channels"][k], a["channels"][k]
    assert abs(s["mean"] - e["mean"]) <= 0.02 * e["std"] + 1e-9, (k, s, e)
    assert abs(s["std"] / e["std"] - 1) < 0.02, (k, s, e)
# Histogram matching: every channel within the exemplar's range.
for k, e in f["channels"].items():
    s = a["channels"][k]
    assert e["min"] <= s["min"] and s["max"] <= e["max"], (k, s, e)
h = a["meta"]["histogram"]
assert all(h[k]["spectrum_change"] < 0.05 for k in h), h
PY

# --- strips: along = scans laid along x, across = laid along y; --pitch changes the pitch.
$BIN texture --along "$T/s1.x3p" "$T/s2.x3p" --across "$T/s1.x3p" "$T/s2.x3p" --texel 14um \
  --size 32 --pitch 28um -o "$T/strip.exr" --texels-out "$T/ex" --json >"$T/strip.json" \
  2>/dev/null || fail "strips"
[ -s "$T/ex.along.exr" ] && [ -s "$T/ex.across.exr" ] || fail "--texels-out"
python3 - "$T/strip.json" <<'PY' || fail "strip JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["texel_m"] - 28e-6) < 1e-12
al, ac = j["exemplars"]["along"], j["exemplars"]["across"]
assert (al["nx"], al["ny"]) == (12, 4), al
assert (ac["nx"], ac["ny"]) == (6, 8), ac
assert "alpha_lifted_to_min" in al and "alpha_zoomed" in ac, al
PY

# --- errors: exit non-zero, say why, write nothing.
expect_fail() {
  local what=$1; shift
  if "$BIN" texture "$@" >"$T/out" 2>"$T/err"; then fail "$what: exit 0"; fi
  [ -s "$T/err" ] || fail "$what: no message"
}
expect_fail "missing scan" "$T/none.x3p" --texel 14um -o "$T/bad.exr"
expect_fail "texel bigger than the scan" "$T/s1.x3p" --texel 100um -o "$T/bad.exr"
expect_fail "bare length" "$T/s1.x3p" --texel 14 -o "$T/bad.exr"
expect_fail "along without across" --along "$T/s1.x3p" --size 16 -o "$T/bad.exr"
$BIN texture "$T/s1.x3p" --texel 28um -o "$T/small.exr" --no-preview >/dev/null 2>&1 \
  || fail "small fit"
expect_fail "exemplar too small" "$T/small.exr" --size 16 -o "$T/bad.exr"
[ ! -e "$T/bad.exr" ] || fail "partial output after an error"
ls "$T" | grep -q tmp && fail "temporary file left behind"
$BIN texture --help | grep -q "Examples" || fail "help"
echo ok
