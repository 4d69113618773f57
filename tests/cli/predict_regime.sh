#!/usr/bin/env bash
# predict names the scattering regime of its scans with the numbers that decided it
# (summary.json "regime"), and warns (method_outside_validity) when its slices and renders use
# the geometric NDF on a smooth surface: a polished scan (metropro-1, Sq 13 nm at 555 nm) is
# Rayleigh-Rice and warns; a brushed one is not and does not; D_K for the renders silences it.
set -u
BIN=$1
DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
$BIN predict "$DATA/metropro-1.dat" --metal Al --no-render --resolution 257 -o "$T/smooth" \
  2>"$T/err1" || fail "predict smooth: $(cat "$T/err1")"
$BIN generate brushed --nx 384 --ny 256 -o "$T/b.npy" 2>/dev/null || fail generate
$BIN predict "$T/b.npy" --metal Al --no-render --resolution 257 -o "$T/brushed" 2>"$T/err2" ||
  fail "predict brushed: $(cat "$T/err2")"
$BIN predict "$DATA/metropro-1.dat" --metal Al --no-render --resolution 129 --kirchhoff \
  --render-ndf kirchhoff --dk-stack single -o "$T/dk" 2>"$T/err3" ||
  fail "predict --kirchhoff: $(cat "$T/err3")"
grep -q "regime: rayleigh-rice at normal incidence" "$T/err1" || fail "no regime line: $(cat "$T/err1")"
/usr/bin/python3 - "$T" <<'PY' || fail "regime records"
import json, math, sys
t = sys.argv[1]
def load(name):
    s = json.load(open(f"{t}/{name}/summary.json"))
    return s["regime"], [w["code"] for w in s["warnings"]]
smooth, w1 = load("smooth")
brushed, w2 = load("brushed")
dk, w3 = load("dk")
# The Rayleigh parameter from the record's own sigma, by its formula.
for p in smooth["per_incidence"]:
    g = (4 * math.pi * smooth["sigma_m"] * math.cos(math.radians(p["theta_i_deg"])) / 555e-9) ** 2
    assert abs(p["rayleigh_parameter"] / g - 1) < 1e-12, (p, g)
    assert p["method"] == "rayleigh-rice" and not p["used_is_valid"], p
    assert "Rayleigh parameter" in p["reason"], p
assert smooth["used"] == "geometric" and "method_outside_validity" in w1, w1
assert [p["theta_i_deg"] for p in smooth["per_incidence"]] == [0, 20, 45, 70]
assert "rayleigh-rice" not in brushed["methods"], brushed
assert "method_outside_validity" not in w2, w2
assert dk["used"] == "kirchhoff" and "method_outside_validity" not in w3, (dk["used"], w3)
assert all(p["used_is_valid"] for p in dk["per_incidence"])
print("metropro-1:", [(p["theta_i_deg"], round(p["rayleigh_parameter"], 4)) for p in smooth["per_incidence"]],
      "brushed:", brushed["methods"], [round(p["rayleigh_parameter"], 2) for p in brushed["per_incidence"]])
PY
echo ok
