#!/usr/bin/env bash
# `make demo`: the main job on bundled data: a synthetic brushed surface and a real scan through
# statistics, height previews, naive and filtered NDFs and NDF slices. (It grows into
# `microbrdf predict` with renders and a report.)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
OUT=${2:-demo-out}
DATA=tests/data
mkdir -p "$OUT"

echo "== 1. A synthetic brushed stainless #4 surface (Dong 2015 Fig. 12 widths)"
"$BIN" generate brushed --preset stainless4 --seed 1 -o "$OUT/brushed_stainless4.x3p" \
  --preview "$OUT/brushed_stainless4.png"

echo
echo "== 2. A real Zygo MetroPro scan, converted to x3p (plane levelled)"
"$BIN" convert "$DATA/metropro-1.dat" "$OUT/metropro-1.x3p" --level plane --preview "$OUT/metropro-1.png"

echo
echo "== 3. Statistics"
"$BIN" info "$OUT/metropro-1.x3p" --level none
"$BIN" info "$OUT/brushed_stainless4.x3p" --level none
"$BIN" info --json "$DATA"/*.x3p "$DATA"/*.dat "$DATA"/*.datx "$DATA"/*.sur "$DATA"/*.gwy >"$OUT/statistics.json"

echo
echo "== 4. Normal distribution functions (Dong 2015 sec. 5.1): naive vs filtered (1 um)"
for m in naive filtered; do
  "$BIN" ndf "$OUT/brushed_stainless4.x3p" --level none --method $m -o "$OUT/ndf_brushed_$m.npy" \
    --preview "$OUT/ndf_brushed_$m.png" --zoom
done
"$BIN" slice "$OUT/ndf_brushed_naive.npy" "$OUT/ndf_brushed_filtered.npy" --label naive,filtered \
  --azimuth 0,90 --log --theta-max 30deg -o "$OUT/ndf_brushed_slices.png"
"$BIN" ndf "$DATA/metropro-1.dat" -o "$OUT/ndf_metropro-1.npy" --preview "$OUT/ndf_metropro-1.png" --zoom

echo
echo "Results are in $(cd "$OUT" && pwd):"
for f in brushed_stainless4.x3p brushed_stainless4.png metropro-1.x3p metropro-1.png statistics.json \
  ndf_brushed_naive.npy ndf_brushed_naive.png ndf_brushed_filtered.npy ndf_brushed_filtered.png \
  ndf_brushed_slices.png ndf_metropro-1.npy ndf_metropro-1.png; do
  echo "  $OUT/$f"
done
