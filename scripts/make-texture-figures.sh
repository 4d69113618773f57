#!/usr/bin/env bash
# Figures for docs/texture.md, docs/fitting.md and docs/validation.md, made by the tool
# itself: Dong Fig. 12 fits of the brushed presets (ellipsoid vs Beckmann), Fig. 11-style texel
# NDFs, the texel parameter image of a strip and a synthesised texture.
# Usage: scripts/make-texture-figures.sh [BIN] [OUTDIR]   (defaults: build/bin/microbrdf, docs/img)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
IMG=${2:-docs/img}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
mkdir -p "$IMG"

# --- Dong Fig. 12 on the full presets (2048 x 1024, filtered 1 um, N = 1025).
for preset in stainless4 aluminium4; do
  "$BIN" generate brushed --preset $preset --seed 1 -o "$T/$preset.x3p" >/dev/null 2>&1
  "$BIN" ndf "$T/$preset.x3p" --level none --method filtered -o "$T/$preset.npy" 2>/dev/null
  for model in ellipsoid beckmann; do
    "$BIN" fit "$T/$preset.npy" --model $model --json --report "$T/fit_${preset}_$model" \
      >"$T/fit_${preset}_$model.json"
    if [ $preset = stainless4 ]; then
      cp "$T/fit_${preset}_$model/compare.png" "$IMG/fit_${preset}_${model}_compare.png"
      cp "$T/fit_${preset}_$model/slices.png" "$IMG/fit_${preset}_${model}_slices.png"
    fi
    python3 - "$T/fit_${preset}_$model.json" $preset $model <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
p = j["params"]
print(f"{sys.argv[2]} {sys.argv[3]}: alpha ({p['alpha_x']:.4f}, {p['alpha_y']:.4f}) "
      f"theta ({p['theta_x']:.4f}, {p['theta_y']:.4f}, {p['theta_z']:.4f}) "
      f"rel L2 {j['relative_l2_error']:.3f} hellinger {j['hellinger']:.3f}")
PY
  done
done

# --- Dong Fig. 11: NDFs of four 53 um texels (482^2 samples) of stainless #4, side by side.
for s in 1 2 3 4; do
  "$BIN" generate brushed --preset stainless4 --nx 482 --ny 482 --seed $((10 + s)) \
    -o "$T/texel$s.x3p" >/dev/null 2>&1
  "$BIN" ndf "$T/texel$s.x3p" --method filtered --resolution 257 -o "$T/texel$s.npy" \
    --preview "$IMG/texture_texel_ndf_$s.png" --zoom 2>/dev/null
  "$BIN" fit "$T/texel$s.npy" --model ellipsoid --sampling node --json |
    python3 -c "import json,sys; j=json.load(sys.stdin); p=j['params']; print('texel $s:', \
'alpha (%.4f, %.4f) theta_x %.4f theta_y %.4f theta_z %.4f' % (p['alpha_x'], p['alpha_y'], \
p['theta_x'], p['theta_y'], p['theta_z']))"
done

# --- Texel parameter images of an "along" strip (10 scans of 70 x 53 um laid along x) and
# a synthesised 256^2 texture from it and an "across" strip.
for s in $(seq 1 10); do
  "$BIN" generate brushed --preset stainless4 --nx 640 --ny 480 --seed $((100 + s)) \
    -o "$T/along$s.x3p" >/dev/null 2>&1
  "$BIN" generate brushed --preset stainless4 --nx 640 --ny 480 --seed $((200 + s)) \
    -o "$T/across$s.x3p" >/dev/null 2>&1
done
"$BIN" texture --along "$T"/along*.x3p --across "$T"/across*.x3p --texel 13.2um --size 512 \
  --seed 1 -o "$T/syn.exr" --texels-out "$T/ex" --preview "$T/syn_big.png" --preview-size 110 --json \
  >"$T/syn.json" 2>/dev/null
python3 - "$T/syn.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
for role, e in j["exemplars"].items():
    print(role, e["nx"], "x", e["ny"], "texels,", e["failed"], "failed;",
          {k: round(v["mean"], 5) for k, v in e["channels"].items()})
print("synthesised", {k: (round(v["mean"], 5), round(v["std"], 5)) for k, v in j["channels"].items()})
PY
cp "$T/syn_big.png" "$IMG/texture_synth_stainless4.png"
"$BIN" texture "$T"/along*.x3p --texel 13.2um -o "$T/texels_along.exr" \
  --preview "$IMG/texture_texels_stainless4.png" --preview-size 300 >/dev/null 2>&1
ls -la "$IMG"/texture_* "$IMG"/fit_stainless4_*
