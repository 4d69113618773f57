#!/usr/bin/env bash
# Regenerates the Westin 1992 simulation figures of docs/validation.md and docs/westin.md with
# the tool itself (microbrdf simulate, brdf slice --sh, plot):
#  1. W92 Fig. 6: Gaussian mirror surface (sigma 10 um, tau 65 um, F = 1, 8.3 mm tile, 2.1 M
#     triangles) in the plane of incidence at theta_i = 0/30/45/60/75 deg: direct ray-traced
#     estimate (all bounces and one bounce), the SH matrix at lmax 15, He 1991 (geometric-optics
#     limit) and Beckmann + Smith;
#  2. Q against the number of rays on a traced scene (acceptance: slope -1/2);
#  3. parallel cylinders: slices with the plane of incidence along and across the axes;
#  4. velvet and woven cloth (hierarchical: the thread BRDF is itself simulated);
#  5. visible fraction G1 and free travel probability vs angle (Smith, Sun 2002).
# Usage: scripts/make-westin-figures.sh [BIN]     (about 5 minutes on 2 cores)
set -euo pipefail
BIN=${1:-build/bin/microbrdf}
IMG=docs/img
S=examples/scenes
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
mkdir -p "$IMG"

# Worst relative deviation per theta_i of the in-plane CSV columns A from REF, over points with
# REF above 5 % of its peak and theta_r < 70 deg. Usage: inplane_table CSV TITLE A:REF...
inplane_table() {
  python3 - "$@" <<'PY'
import csv, sys
from collections import defaultdict
g = defaultdict(list)
for r in csv.DictReader(open(sys.argv[1])):
    g[float(r["theta_i_deg"])].append(r)
print(sys.argv[2])
pairs = [p.split(":") for p in sys.argv[3:]]
for ti, rs in sorted(g.items()):
    col = lambda k: [float(r[k]) for r in rs]
    tr = col("theta_r_deg")
    def worst(a, ref):
        pk = max(ref)
        return max(abs(x / y - 1) for x, y, t in zip(a, ref, tr) if y > 0.05 * pk and t < 70)
    print(f"{ti:5.0f} | " + " | ".join(f"{worst(col(a), col(ref)):.3f}" for a, ref in pairs))
PY
}

# 1. Fig. 6
"$BIN" simulate $S/westin_fig6.json --lmax 15 --rays 8000000 --seed 1 -o "$W/fig6.shbrdf" \
  --json >"$W/fig6.json"
python3 -c "import json; j=json.load(open('$W/fig6.json')); print('fig6 SH: Q %.3g, %d rays, %.0f s, %.3g exits/s' % (j['q'], j['incident_rays'], j['seconds'], j['exit_rays_per_second']))"
"$BIN" simulate $S/westin_fig6.json --in-plane 0,30,45,60,75 --isotropic --gonio-rays 1000000 \
  --he-sigma 10um --he-tau 65um --single-scatter --sh "$W/fig6.shbrdf" \
  --plot "$IMG/westin_fig6.png" --csv "$IMG/westin_fig6.csv" -q
inplane_table "$IMG/westin_fig6.csv" \
  "theta_i | 1 bounce vs Smith | 1 bounce vs He | all vs Smith | all vs He | SH vs all  (worst, ref > 5 % of peak, theta_r < 70)" \
  simulated_single:beckmann_smith simulated_single:he1991 simulated:beckmann_smith \
  simulated:he1991 sh:simulated

# 1b. The same surface (512^2, 524 288 triangles) with aluminium facets at 550 nm; the references
#     carry the same Fresnel term at the half-vector angle.
"$BIN" simulate $S/gaussian_aluminium.json --in-plane 0,30,45,60,75 --isotropic --gonio-rays 1000000 \
  --he-sigma 10um --he-tau 65um --single-scatter --plot "$IMG/westin_fig6_al.png" \
  --csv "$W/fig6_al.csv" -q
inplane_table "$W/fig6_al.csv" "aluminium: theta_i | 1 bounce vs Smith | 1 bounce vs He | all vs Smith" \
  simulated_single:beckmann_smith simulated_single:he1991 simulated:beckmann_smith

# 2. Q vs rays on the traced Fig. 6 surface at W92's polygon count (524 288 triangles), lmax 15.
echo "rays,q" >"$IMG/westin_q.csv"
for R in 20000 63000 200000 630000 2000000; do
  "$BIN" simulate $S/gaussian_aluminium.json --lmax 15 --rays $R --points 4 --seed 7 \
    -o "$W/q.shbrdf" --json -q >"$W/q.json"
  python3 -c "import json; j=json.load(open('$W/q.json')); print('%d,%.6g' % (j['incident_rays'], j['q']))" \
    >>"$IMG/westin_q.csv"
done
python3 - "$IMG/westin_q.csv" <<'PY'
import csv, math, sys
r = list(csv.DictReader(open(sys.argv[1])))
x = [math.log(float(a["rays"])) for a in r]; y = [math.log(float(a["q"])) for a in r]
n = len(x); mx = sum(x) / n; my = sum(y) / n
s = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
print(f"Q vs rays: log-log slope {s:.3f} over {float(r[0]['rays']):.0f}..{float(r[-1]['rays']):.0f}")
PY
"$BIN" plot "$IMG/westin_q.csv" --x rays --y q --style linemarkers --logx --logy \
  --title "W92 Q on a traced Gaussian aluminium surface (lmax 15)" --xlabel "incident rays" \
  --ylabel "Q = sum|M - M^T| / J^2" -o "$IMG/westin_q.png"

# 3. Parallel cylinders: anisotropy.
"$BIN" simulate $S/cylinders.json --lmax 15 --rays 4000000 --seed 1 -o "$W/cyl.shbrdf" -q
"$BIN" simulate $S/cylinders.json --in-plane 30,60 --phi-i 0 --gonio-rays 400000 \
  --sh "$W/cyl.shbrdf" --plot "$IMG/westin_cylinders_along.png" --csv "$W/along.csv" -q
"$BIN" simulate $S/cylinders.json --in-plane 30,60 --phi-i 90 --gonio-rays 400000 \
  --sh "$W/cyl.shbrdf" --plot "$IMG/westin_cylinders_across.png" --csv "$W/across.csv" -q

# 4. Velvet; cloth with a simulated thread BRDF (W92 section 5.4).
"$BIN" simulate $S/velvet.json --lmax 12 --rays 1000000 --seed 1 -o "$W/velvet.shbrdf" --json -q \
  >"$W/velvet.json"
"$BIN" simulate $S/velvet.json --in-plane 0,45,75 --isotropic --gonio-rays 300000 --cone 6deg \
  --sh "$W/velvet.shbrdf" --plot "$IMG/westin_velvet.png" --csv "$W/velvet.csv" -q
cp $S/cloth.json "$W/cloth.json"
"$BIN" simulate $S/cloth_threads.json --lmax 12 --rays 2000000 --seed 1 -o "$W/threads.shbrdf" -q
"$BIN" simulate "$W/cloth.json" --lmax 12 --rays 1000000 --seed 1 -o "$W/cloth.shbrdf" --json -q \
  >"$W/cloth_sim.json"
"$BIN" simulate "$W/cloth.json" --in-plane 30,60 --gonio-rays 200000 --cone 6deg \
  --sh "$W/cloth.shbrdf" --plot "$IMG/westin_cloth.png" --csv "$W/cloth.csv" -q
for f in velvet cloth_sim; do
  python3 -c "import json; j=json.load(open('$W/$f.json')); print('$f: albedo %.4f, depth-capped %.4f, Q %.3g, %.0f s' % (j['mean_exit_energy'], j['energy_depth_capped'], j['q'], j['seconds']))"
done

# 5. Visibility on the Fig. 6 surface at 512^2 (Dong 2015 Fig. 6 left; Sun 2002 FTP in 2-D).
"$BIN" simulate $S/gaussian_aluminium.json --visibility --visibility-samples 40000 \
  --he-sigma 10um --he-tau 65um --csv "$IMG/westin_visibility.csv" --plot "$IMG/westin_visibility.png" -q
ls -la "$IMG"/westin_*
