#!/usr/bin/env bash
# The toy model (tests/toy/toy_ndf.cpp, added through the registry alone) as a user runs it:
# tabulate, fit, brdf slice and export bsdf take --model toy --roughness R like any built-in
# model; the values are checked against numpy's isotropic GGX of the same roughness.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN fit --help | grep -q "toy" || fail "fit --help does not list the toy model"
$BIN tabulate --help | grep -q -- "--roughness" || fail "tabulate has no --roughness flag"

# tabulate: the point samples are numpy's GGX of alpha 0.2, renormalised.
$BIN tabulate --model toy --roughness 0.2 --resolution 257 -o "$T/t.npy" >"$T/out" 2>"$T/err" \
  || fail "tabulate: $(cat "$T/err")"
/usr/bin/python3 - "$T/t.npy" <<'PY' || fail "tabulate: the table is not the toy's D"
import sys, numpy as np
t = np.load(sys.argv[1]); n = t.shape[0]
m = -1 + 2 * np.arange(n) / (n - 1); x, y = np.meshgrid(m, m)
r2 = x * x + y * y; z2 = np.clip(1 - r2, 0, None)
d = np.where(r2 < 1, 1 / (np.pi * 0.04 * ((x * x + y * y) / 0.04 + z2) ** 2), 0)
d /= d.sum() * (2 / (n - 1)) ** 2
err = np.abs(t - d).max() / d.max()
print("max relative difference", err)
sys.exit(0 if err < 1e-12 else 1)
PY

# fit: the roughness comes back, in the JSON under the model's own parameter name.
$BIN fit "$T/t.npy" --model toy --json >"$T/fit.json" 2>"$T/err" || fail "fit: $(cat "$T/err")"
/usr/bin/python3 - "$T/fit.json" <<'PY' || fail "fit: $(cat "$T/fit.json")"
import json, sys
j = json.load(open(sys.argv[1]))
r = j["params"]["roughness"]
print("fitted roughness", r)
sys.exit(0 if j["model"] == "toy" and abs(r / 0.2 - 1) < 1e-6 and j["converged"] else 1)
PY

# brdf slice: the peak of the in-plane slice of a toy lobe equals the GGX lobe's.
for m in "toy --roughness 0.2" "ggx --alpha 0.2"; do
  set -- $m
  $BIN brdf slice --model "$@" --metal Al --theta-i 30deg -o "$T/$1.csv" >/dev/null 2>"$T/err" \
    || fail "brdf slice --model $1: $(cat "$T/err")"
done
cmp -s <(tail -n +2 "$T/toy.csv") <(tail -n +2 "$T/ggx.csv") \
  || fail "brdf slice: the toy lobe differs from GGX of the same roughness"

# export bsdf: a tabulated .bsdf of the toy lobe, every field the same bytes as GGX's of the same
# roughness but the description (which names the model).
$BIN export bsdf --model toy --roughness 0.2 --metal Al -o "$T/toy.bsdf" >/dev/null 2>"$T/err" \
  || fail "export bsdf: $(cat "$T/err")"
test -s "$T/toy.bsdf" || fail "export bsdf wrote nothing"
$BIN export bsdf --model ggx --alpha 0.2 --metal Al -o "$T/ggx.bsdf" >/dev/null 2>"$T/err" \
  || fail "export bsdf --model ggx: $(cat "$T/err")"
/usr/bin/python3 - "$T/toy.bsdf" "$T/ggx.bsdf" <<'PY' || fail "export bsdf: the toy's tables differ from GGX's"
import struct, sys
def fields(path):  # Mitsuba's tensor_file: header, then per field name, shape, dtype, offset
    b = open(path, "rb").read()
    assert b[:12] == b"tensor_file\0"
    (count,) = struct.unpack_from("<I", b, 14)
    pos, out, sizes = 18, {}, {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 8, 8: 8, 9: 2, 10: 4, 11: 8}
    for _ in range(count):
        (n,) = struct.unpack_from("<H", b, pos); name = b[pos + 2:pos + 2 + n].decode(); pos += 2 + n
        ndim, dtype, offset = struct.unpack_from("<HBQ", b, pos); pos += 11
        shape = struct.unpack_from("<%dQ" % ndim, b, pos); pos += 8 * ndim
        size = sizes[dtype]
        for s in shape: size *= s
        out[name] = b[offset:offset + size]
    return out
a, g = fields(sys.argv[1]), fields(sys.argv[2])
diff = [k for k in a if k != "description" and a[k] != g.get(k)]
print("fields", sorted(a), "differing:", diff)
sys.exit(0 if sorted(a) == sorted(g) and len(a) > 3 and not diff else 1)
PY

# A parameter of another model is refused, naming the flag.
$BIN tabulate --model ggx --alpha 0.2 --roughness 0.2 -o "$T/x.npy" >/dev/null 2>"$T/err"
test $? -eq 2 || fail "--roughness with ggx: exit $? (want 2)"
grep -q -- "--roughness does not belong to the ggx model" "$T/err" || fail "message: $(cat "$T/err")"
test ! -e "$T/x.npy" || fail "a refused run left an output"
echo "toy model: tabulate, fit, brdf slice, export bsdf OK"
