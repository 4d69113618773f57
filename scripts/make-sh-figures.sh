#!/usr/bin/env bash
# Regenerates the spherical-harmonic BRDF figures of docs/validation.md (Westin 1992) with the
# tool itself: convergence of the SH expansion of a GGX lobe with lmax and Gibbs damping, and
# the estimator's convergence measure Q against the number of incident directions.
# Usage: scripts/make-sh-figures.sh [BIN]
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
IMG=docs/img
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
mkdir -p "$IMG"
MODEL=(--model ggx --alpha 0.15 --metal Al)

# 1. In-plane slices at theta_i = 45 deg: analytic vs projections at lmax 10, 20, 30, and lmax 30
#    with Gibbs damping (l_filter 20, width 5).
"$BIN" brdf slice "${MODEL[@]}" --theta-i 45deg --samples 361 -o "$W/ref.csv" >/dev/null
for L in 10 20 30; do
  "$BIN" brdf sh-project "${MODEL[@]}" --lmax $L -o "$W/l$L.shbrdf" --json >"$W/l$L.json" 2>/dev/null
  "$BIN" brdf slice --sh "$W/l$L.shbrdf" --theta-i 45deg --samples 361 -o "$W/l$L.csv" >/dev/null
done
"$BIN" brdf slice --sh "$W/l30.shbrdf" --l-filter 20 --filter-width 5 --theta-i 45deg --samples 361 \
  -o "$W/d30.csv" >/dev/null
python3 - "$W" <<'PY'
import csv, sys
W = sys.argv[1]
def col(name):
    rows = [r for r in open(f"{W}/{name}.csv") if not r.startswith("#")]
    return [(float(r["angle_deg"]), float(r["brdf_per_sr"])) for r in csv.DictReader(rows)]
cols = {n: col(n) for n in ["ref", "l10", "l20", "l30", "d30"]}
with open(f"{W}/slices.csv", "w") as f:
    f.write("angle_deg,analytic,lmax10,lmax20,lmax30,lmax30_damped\n")
    for i in range(len(cols["ref"])):
        f.write(",".join([f"{cols['ref'][i][0]:.4f}"] + [f"{cols[n][i][1]:.6g}" for n in cols]) + "\n")
# errors for the docs: max |SH - analytic| over |theta_o| <= 75 deg, relative to the peak
ref = cols["ref"]; peak = max(v for a, v in ref if abs(a) <= 75)
for n in ["l10", "l20", "l30", "d30"]:
    e = max(abs(v - r[1]) for (a, v), r in zip(cols[n], ref) if abs(a) <= 75)
    print(f"{n}: max error {e / peak * 100:.1f} % of the peak {peak:.3f} /sr")
PY
"$BIN" plot "$W/slices.csv" --x angle_deg --y analytic,lmax10,lmax20,lmax30,lmax30_damped \
  --style line,dotted,dashed,line,dashed \
  --label "GGX 0.15 Al (analytic)","SH lmax 10","SH lmax 20","SH lmax 30","SH lmax 30 damped 20/5" \
  --title "Spherical-harmonic expansion of a GGX lobe, theta_i = 45 deg, plane of incidence" \
  --xlabel "theta_o (deg, mirror at +45)" --ylabel "BRDF (1/sr)" -o "$IMG/sh_slices_ggx.png"

# 2. Q (W92 eq. 27 with 1/J^2) vs N, synthetic estimator (exits sampled from GGX 0.3 Al), lmax 8,
#    mean of 4 seeds per N.
echo "n,q,n_half" >"$W/q.csv"
for n in 100 300 1000 3000 10000 30000 100000; do
  qs=""
  for s in 1 2 3 4; do
    qs="$qs $("$BIN" brdf sh-estimate --model ggx --alpha 0.3 --metal Al --lmax 8 --incident $n \
      --seed $s --json 2>/dev/null | python3 -c 'import json,sys; print(json.load(sys.stdin)["q"])')"
  done
  python3 -c "import sys; q=[float(x) for x in '$qs'.split()]; m=sum(q)/len(q); print(f'$n,{m},{0}')" >>"$W/q.csv"
done
python3 - "$W/q.csv" <<'PY'
import math, sys
rows = [l.strip().split(",") for l in open(sys.argv[1])][1:]
n = [float(r[0]) for r in rows]; q = [float(r[1]) for r in rows]
lx = [math.log(x) for x in n]; ly = [math.log(y) for y in q]
mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
slope = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
c = q[0] * math.sqrt(n[0])
with open(sys.argv[1], "w") as f:
    f.write("n,q,n_half\n")
    for a, b in zip(n, q):
        f.write(f"{a:.0f},{b:.6g},{c / math.sqrt(a):.6g}\n")
print(f"Q log-log slope over N = {n[0]:.0f}..{n[-1]:.0f}: {slope:.3f}")
for a, b in zip(n, q):
    print(f"  N = {a:.0f}: Q = {b:.4g}")
PY
"$BIN" plot "$W/q.csv" --x n --y q,n_half --style markers,dashed --logx --logy \
  --label "Q (mean of 4 seeds)","Q(100) x (N/100)^-1/2" \
  --title "Convergence measure Q of the SH estimator (GGX 0.3 Al, lmax 8)" \
  --xlabel "incident directions N" --ylabel "Q = sum |M - M^T| / J^2" -o "$IMG/sh_q_convergence.png"
cp "$W/q.csv" "$IMG/sh_q_convergence.csv"
