#!/usr/bin/env bash
# `make demo`: the main job on bundled data. For now (foundation): generate a brushed surface,
# convert a bundled real scan, print statistics, write height-map previews.
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
echo "Results are in $(cd "$OUT" && pwd):"
for f in brushed_stainless4.x3p brushed_stainless4.png metropro-1.x3p metropro-1.png statistics.json; do
  echo "  $OUT/$f"
done
