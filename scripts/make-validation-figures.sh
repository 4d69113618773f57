#!/usr/bin/env bash
# Regenerates the geometric-NDF figures of docs/validation.md with the tool itself.
# Usage: [SECTIONS="2 4"] scripts/make-validation-figures.sh [BIN] [EXTRA_SURFACES_DIR]
# Part 3 reads the bundled scans (tests/data) and, when EXTRA_SURFACES_DIR holds it, x3p-2.x3p
# (3.2 MB, not bundled; tests/data/README.md says where it comes from).
# SECTIONS picks the numbered parts below (default: all); 2 and 4 depend on the brushed presets.
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
EXTRA=${2:-}
FIXTURES=tests/data
IMG=docs/img
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
mkdir -p "$IMG"
want() { [[ " ${SECTIONS:-1 2 3 4} " == *" $1 "* ]]; }

# 1. Filtered rms slope vs filter sigma on a Gaussian surface:
#    alpha_f = alpha tau^2 / (tau^2 + 4 s^2), alpha = 2 sigma / tau; rms slope = alpha_f / sqrt 2.
if want 1; then
"$BIN" generate gaussian --nx 1024 --ny 1024 --spacing 0.25um --sigma 0.1um --tau 2um --seed 7 -o "$W/g.x3p" 2>/dev/null
echo "sigma_um,measured_x,measured_y,theory" >"$W/sweep.csv"
for s in 0.1 0.25 0.5 0.75 1 1.5 2 3; do
  "$BIN" ndf "$W/g.x3p" --level none --filter-sigma "${s}um" --resolution 513 -o "$W/n.npy" --json 2>/dev/null |
    python3 -c "import json,sys,math; j=json.load(sys.stdin); s=$s; t=2.0; a=2*0.1/t
print(f\"{s},{j['slope_rms_x']},{j['slope_rms_y']},{a*t*t/(t*t+4*s*s)/math.sqrt(2)}\")" >>"$W/sweep.csv"
done
"$BIN" ndf "$W/g.x3p" --level none --method naive --resolution 513 -o "$W/n.npy" --json 2>/dev/null |
  python3 -c "import json,sys; j=json.load(sys.stdin); print('naive rms slope x', j['slope_rms_x'])"
cp "$W/sweep.csv" "$IMG/ndf_filter_sweep.csv"
"$BIN" plot "$W/sweep.csv" --x sigma_um --y measured_x,measured_y,theory --style markers,markers,line \
  --label "filtered NDF along x","filtered NDF along y","theory 2 sigma tau / (tau^2 + 4 s^2) / sqrt 2" \
  --title "Gaussian surface sigma = 0.1 um, tau = 2 um: rms slope of the filtered NDF" \
  --xlabel "filter sigma s (um)" --ylabel "rms slope" -o "$IMG/ndf_filter_sweep.png"
fi

# 2. Naive vs filtered for the brushed presets (Dong Fig. 5 / Fig. 9 comparisons), and the
#    ellipsoid and Beckmann fits of the filtered NDFs (Dong Fig. 12).
want 2 || want 4 && "$BIN" generate brushed --preset stainless4 --seed 1 -o "$W/stainless4.x3p" 2>/dev/null
want 2 && for preset in stainless4 aluminium4; do
  [ -f "$W/$preset.x3p" ] || "$BIN" generate brushed --preset "$preset" --seed 1 -o "$W/$preset.x3p" 2>/dev/null
  for m in naive filtered; do
    "$BIN" ndf "$W/$preset.x3p" --level none --method $m -o "$W/${preset}_$m.npy" \
      --preview "$IMG/ndf_${preset}_$m.png" --zoom --json 2>/dev/null >"$W/${preset}_$m.summary"
  done
  "$BIN" slice "$W/${preset}_naive.npy" "$W/${preset}_filtered.npy" --label naive,filtered --azimuth 0,90 --log \
    --theta-max 45deg -o "$IMG/ndf_${preset}_slices.png"
  for model in ellipsoid beckmann; do
    "$BIN" fit "$W/${preset}_filtered.npy" --model $model --json 2>/dev/null |
      python3 -c "import json,sys; j=json.load(sys.stdin); p=j['params']
print('fit $preset $model: alpha (%.4f, %.4f)' % (p['alpha_x'], p['alpha_y']),
      {k: round(v, 3) for k, v in j.items() if isinstance(v, float)})"
  done
done

# 3. Real scans.
# plu-1-heights.plu is plu-1.plu without its camera image (the same heights): figures keep "plu-1".
want 3 && for path in "$EXTRA/x3p-2.x3p" "$FIXTURES/metropro-1.dat" "$FIXTURES/plu-1-heights.plu"; do
  [ -f "$path" ] || continue
  f=$(basename "$path")
  stem=${f%.*}
  stem=${stem%-heights}
  for m in naive filtered; do
    "$BIN" ndf "$path" --method $m -o "$W/${stem}_$m.npy" --preview "$IMG/ndf_${stem}_$m.png" --zoom \
      --json 2>/dev/null >"$W/${stem}_$m.summary"
  done
  "$BIN" slice "$W/${stem}_naive.npy" "$W/${stem}_filtered.npy" --label naive,filtered --azimuth 0,90 --log \
    --theta-max 20deg -o "$IMG/ndf_${stem}_slices.png"
done

# 4. Kirchhoff D_K of the stainless #4 preset next to the geometric NDFs (Dong Figs. 8-9):
#    filtered (1 um), naive, D_K without window and with a Hann window (555 nm, 70 x 53 um tiles).
#    The previews of the geometric NDFs are part 2's ndf_stainless4_{filtered,naive}.png.
if want 4; then
  K=(--level none --resolution 1025 --zoom --json)  # as part 2 (defaults), plus the zoom panel
  "$BIN" ndf "$W/stainless4.x3p" "${K[@]}" -o "$W/k_filtered.npy" 2>/dev/null >"$W/k_filtered.summary"
  "$BIN" ndf "$W/stainless4.x3p" "${K[@]}" --method naive -o "$W/k_naive.npy" 2>/dev/null >"$W/k_naive.summary"
  for win in none hann; do
    "$BIN" ndf "$W/stainless4.x3p" "${K[@]}" --method kirchhoff --window $win -o "$W/k_dk_$win.npy" \
      --preview "$IMG/val_dk_ss4_dk_$win.png" 2>/dev/null >"$W/k_dk_$win.summary"
  done
  KS=("$W/k_filtered.npy" "$W/k_naive.npy" "$W/k_dk_none.npy" "$W/k_dk_hann.npy" --label "filtered 1 um,naive,D_K no window,D_K Hann" --log)
  "$BIN" slice "${KS[@]}" --azimuth 90 --theta-max 45deg -o "$IMG/val_dk_ss4_across.png"
  "$BIN" slice "${KS[@]}" --azimuth 0 --theta-max 3deg -o "$IMG/val_dk_ss4_along.png"
  for m in filtered naive dk_none dk_hann; do
    python3 -c "import json,sys; j=json.load(open(sys.argv[1]))
print('D_K comparison $m: alpha x %.4f y %.4f' % (j['beckmann_alpha_x'], j['beckmann_alpha_y']))" "$W/k_$m.summary"
  done
fi

# Summary table of widths (Beckmann alpha = sqrt 2 x rms slope).
echo "| input | method | alpha x | alpha y | elements used | skipped |"
echo "|---|---|---|---|---|---|"
for j in "$W"/*_naive.summary "$W"/*_filtered.summary; do
  case $(basename "$j") in k_*) continue ;; esac
  python3 - "$j" <<'PY'
import json, sys, os
j = json.load(open(sys.argv[1]))
name = os.path.basename(sys.argv[1]).rsplit('_', 1)[0]
print(f"| {name} | {j['method']} | {j['beckmann_alpha_x']:.4f} | {j['beckmann_alpha_y']:.4f} | {j['samples_used']} | {j['samples_skipped']} |")
PY
done
