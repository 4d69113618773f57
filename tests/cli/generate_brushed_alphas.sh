#!/usr/bin/env bash
# `generate brushed --preset X --alpha-along A --alpha-across B`: the preset's depth modulation is
# kept and the base is solved with the same calibration the preset uses (1.6x / 1.8x rms over
# fitted width), so (1) asking for the preset's own widths reproduces the preset bit for bit and
# (2) the ellipsoid fitted to the filtered NDF of the result has about the widths asked for.
# Before the calibration was applied, (2) came out 36 % / 42 % narrower than asked
# (same seeds: mean fitted (0.0129, 0.144) for (0.02, 0.25)).
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# (1) Same parameters as the presets: identical surfaces.
for p in "stainless4 0.007 0.14" "aluminium4 0.02 0.47"; do
  set -- $p
  $BIN generate brushed --preset "$1" --nx 256 --ny 128 --seed 4 -o "$T/a.npy" >/dev/null 2>&1 \
    || fail "generate $1"
  $BIN generate brushed --preset "$1" --alpha-along "$2" --alpha-across "$3" --nx 256 --ny 128 \
    --seed 4 -o "$T/b.npy" >/dev/null 2>&1 || fail "generate $1 with alphas"
  cmp -s "$T/a.npy" "$T/b.npy" || fail "$1: asking for its own widths gives another surface"
done

# (2) Widths other than the preset's: 0.02 along / 0.25 across on stainless #4, three seeds of
# 1024 x 512 samples (113 x 56 um, about two modulation correlation lengths along, so single
# seeds scatter by up to 15 %: measured (0.0224, 0.287), (0.0210, 0.249), (0.0192, 0.241)).
# The mean over the seeds must be within 12 % of the request, every seed within 25 %.
for s in 1 2 3; do
  $BIN generate brushed --preset stainless4 --alpha-along 0.02 --alpha-across 0.25 --nx 1024 \
    --ny 512 --seed $s -o "$T/s$s.x3p" >/dev/null 2>&1 || fail "generate seed $s"
  $BIN ndf "$T/s$s.x3p" --level none --method filtered -o "$T/s$s.npy" >/dev/null 2>&1 \
    || fail "ndf seed $s"
  $BIN fit "$T/s$s.npy" --model ellipsoid --json >"$T/f$s.json" 2>/dev/null || fail "fit seed $s"
done
python3 - "$T"/f?.json <<'PY' || fail "fitted widths"
import json, sys
want = (0.02, 0.25)
fits = [json.load(open(p))["params"] for p in sys.argv[1:]]
got = [(f["alpha_x"], f["alpha_y"]) for f in fits]
for g in got:
    for x, w in zip(g, want):
        assert abs(x / w - 1) < 0.25, (got, want)
for i, w in enumerate(want):
    mean = sum(g[i] for g in got) / len(got)
    assert abs(mean / w - 1) < 0.12, (i, mean, w, got)
PY
echo ok
