#!/usr/bin/env bash
# `fit --model mixture:A+B` as a user runs it: a two-lobe table written by numpy (a narrow GGX
# core and a wide Beckmann tail), the joint fit's JSON (weight and both lobes' parameters),
# the fitted table (--table) exported as a tabulated .bsdf, and the refusals.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

/usr/bin/python3 - "$T/two.npy" <<'PY' || fail "python could not write the table"
import json, sys, numpy as np
n = 257
m = -1 + 2 * np.arange(n) / (n - 1)
x, y = np.meshgrid(m, m)
np.seterr(all="ignore")  # (the formulas overflow outside the disk, where D is 0)
r2 = x * x + y * y
z2 = np.clip(1 - r2, 1e-300, None)
ggx = 1 / (np.pi * 0.05 ** 2 * (r2 / 0.05 ** 2 + z2) ** 2)
beck = np.exp(-r2 / (z2 * 0.3 ** 2)) / (np.pi * 0.3 ** 2 * z2 ** 2)
D = np.where(r2 < 1, 0.6 * ggx + 0.4 * beck, 0)
D /= D.sum() * (2 / (n - 1)) ** 2
np.save(sys.argv[1], D)
json.dump({"format": "microbrdf-ndf", "version": 1, "resolution": n, "method": "numpy",
           "sampling": "point"}, open(sys.argv[1][:-4] + ".json", "w"))
PY

$BIN fit "$T/two.npy" --model mixture:ggx+beckmann --table "$T/fit.npy" --json >"$T/out.json" \
  2>"$T/err" || fail "fit: $(cat "$T/err")"
/usr/bin/python3 - "$T/out.json" "$T/fit.npy" "$T/two.npy" <<'PY' || fail "mixture fit: $(cat "$T/out.json")"
import json, sys, numpy as np
j = json.load(open(sys.argv[1]))
p = j["params"]
print("weight", p["weight"], "core", p["lobe1"]["params"]["alpha_x"], "tail",
      p["lobe2"]["params"]["alpha_x"], "hellinger", j["hellinger"])
assert j["model"] == "mixture:ggx+beckmann" and j["converged"], j
assert p["lobe1"]["model"] == "ggx" and p["lobe2"]["model"] == "beckmann", p
assert abs(p["weight"] - 0.6) < 0.006, p
assert abs(p["lobe1"]["params"]["alpha_x"] / 0.05 - 1) < 0.01, p
assert abs(p["lobe2"]["params"]["alpha_y"] / 0.3 - 1) < 0.01, p
# The fitted table is the fit the errors were measured on: close to the input.
f, t = np.load(sys.argv[2]), np.load(sys.argv[3])
assert f.shape == t.shape and np.abs(f - t).max() < 0.01 * t.max(), np.abs(f - t).max() / t.max()
PY
$BIN export bsdf --ndf "$T/fit.npy" --metal Al -o "$T/fit.bsdf" >/dev/null 2>"$T/err" \
  || fail "export bsdf of the fitted table: $(cat "$T/err")"
test -s "$T/fit.bsdf" || fail "export bsdf wrote nothing"

# Refusals: an unknown lobe, a mixture given where a distribution is needed.
$BIN fit "$T/two.npy" --model mixture:ggx+phong >/dev/null 2>"$T/err"
test $? -eq 1 -o $? -eq 2 || fail "mixture:ggx+phong accepted"
grep -q "mixture:A+B" "$T/err" || fail "message: $(cat "$T/err")"
$BIN tabulate --model mixture:ggx+beckmann --alpha 0.1 -o "$T/x.npy" >/dev/null 2>"$T/err"
test $? -ne 0 || fail "tabulate took a mixture"
test ! -e "$T/x.npy" || fail "a refused run left an output"
echo "fit mixture OK"
