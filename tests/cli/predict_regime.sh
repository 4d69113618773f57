#!/usr/bin/env bash
# predict names the scattering regime of its scans with the numbers that decided it
# (summary.json "regime") and, by default (--theory auto), predicts the BRDF with the theory valid
# there: a polished scan (metropro-1, Sq 13 nm at 555 nm) gets Rayleigh-Rice from its PSD, a
# Gaussian surface of sigma 20 nm gets D_K (computed without --kirchhoff), and so does a brushed
# one (Sq 200 nm): geometric at normal incidence, but its 70 deg slice keeps a specular part
# (g = 2.4), where only Kirchhoff holds. Forcing the geometric NDF on the polished scan warns (method_outside_validity);
# --render-ndf kirchhoff still means D_K.
set -u
BIN=$1
DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
FAST=(--no-render --resolution 129 --theta-i 20,45,70)
$BIN predict "$DATA/metropro-1.dat" --metal Al "${FAST[@]}" -o "$T/smooth" 2>"$T/err1" ||
  fail "predict smooth: $(cat "$T/err1")"
$BIN predict "$DATA/metropro-1.dat" --metal Al "${FAST[@]}" --theory geometric -o "$T/forced" \
  2>"$T/err4" || fail "predict forced: $(cat "$T/err4")"
$BIN generate brushed --nx 384 --ny 256 -o "$T/b.npy" 2>/dev/null || fail generate
$BIN predict "$T/b.npy" --metal Al "${FAST[@]}" --dk-stack wavelength -o "$T/brushed" 2>"$T/err2" ||
  fail "predict brushed: $(cat "$T/err2")"
$BIN predict "$T/b.npy" --metal Al "${FAST[@]}" --theory geometric -o "$T/brushed_geometric" \
  2>"$T/err7" || fail "predict brushed geometric: $(cat "$T/err7")"
$BIN generate gaussian --sigma 20nm --tau 2um --nx 320 --ny 320 --spacing 250nm --seed 3 \
  -o "$T/g.npy" 2>/dev/null || fail generate
$BIN predict "$T/g.npy" --metal Al "${FAST[@]}" --dk-stack wavelength --patch 40um \
  -o "$T/mid" 2>"$T/err5" || fail "predict mid: $(cat "$T/err5")"
$BIN predict "$DATA/metropro-1.dat" --metal Al "${FAST[@]}" --kirchhoff \
  --render-ndf kirchhoff --dk-stack single -o "$T/dk" 2>"$T/err3" ||
  fail "predict --kirchhoff: $(cat "$T/err3")"
$BIN predict "$DATA/metropro-1.dat" --metal Al "${FAST[@]}" --theory bogus -o "$T/x" 2>"$T/err6" &&
  fail "an unknown theory was accepted"
grep -q "auto" "$T/err6" || fail "the refusal does not list the theories: $(cat "$T/err6")"
grep -q "regime: rayleigh-rice at normal incidence" "$T/err1" || fail "no regime line: $(cat "$T/err1")"
grep -q "theory: rayleigh-rice (auto" "$T/err1" || fail "no theory line: $(cat "$T/err1")"
grep -q "theory: kirchhoff D_K" "$T/err5" || fail "D_K not computed for auto: $(cat "$T/err5")"
/usr/bin/python3 - "$T" <<'PY' || fail "regime records"
import json, math, sys
t = sys.argv[1]
def load(name):
    s = json.load(open(f"{t}/{name}/summary.json"))
    return s, s["regime"], [w["code"] for w in s["warnings"]]
s1, smooth, w1 = load("smooth")
s4, forced, w4 = load("forced")
s2, brushed, w2 = load("brushed")
sb, forced_b, wb = load("brushed_geometric")
s5, mid, w5 = load("mid")
s3, dk, w3 = load("dk")
# The Rayleigh parameter from the record's own sigma, by its formula.
for p in smooth["per_incidence"]:
    g = (4 * math.pi * smooth["sigma_m"] * math.cos(math.radians(p["theta_i_deg"])) / 555e-9) ** 2
    assert abs(p["rayleigh_parameter"] / g - 1) < 1e-12, (p, g)
    assert p["method"] == "rayleigh-rice" and p["used_is_valid"], p
    assert "Rayleigh parameter" in p["reason"], p
assert [p["theta_i_deg"] for p in smooth["per_incidence"]] == [0, 20, 45, 70]
th = smooth["theory"]
assert th["requested"] == "auto" and th["chosen"] == "rayleigh-rice", th
assert "0.0912" in th["why"] and th["psd_scans"] == 1, th
# The PSD's Sq is the scan's (levelled) Sq.
assert abs(th["psd_sq_m"] / smooth["sigma_m"] - 1) < 1e-6, (th, smooth["sigma_m"])
# metropro-1: tau about 140 um on a 700 um field, so no room for tiles of 32 tau: one periodogram,
# and the summary says why.
assert th["psd_tiles"] == 1 and "whole scan" in th["psd_tile_choice"], th
assert smooth["used"] == "rayleigh-rice" and "method_outside_validity" not in w1, w1
labels = {m["key"]: m["label"] for m in s1["brdf"]["models"]}
assert "Rayleigh-Rice" in labels["measured"] and "geometric" in labels, labels
# Forced geometric on the polished scan: outside validity, and the warning says how to get it.
assert forced["theory"]["requested"] == "geometric" and forced["used"] == "geometric"
assert "method_outside_validity" in w4, w4
assert not any(p["used_is_valid"] for p in forced["per_incidence"])
assert [p["method"] for p in brushed["per_incidence"]] == ["geometric"] * 3 + ["kirchhoff"], brushed
assert brushed["theory"]["chosen"] == "kirchhoff" and "not at theta_i 70 deg" in brushed["theory"]["why"]
assert "method_outside_validity" not in w2, w2
# Forced geometric there warns about 70 deg only.
assert [p["used_is_valid"] for p in forced_b["per_incidence"]] == [True] * 3 + [False], forced_b
assert "method_outside_validity" in wb, wb
# sigma 20 nm: g = 0.205 at 555 nm, Kirchhoff; D_K was computed although --kirchhoff was not given.
assert mid["per_incidence"][0]["method"] == "kirchhoff", mid["per_incidence"][0]
assert mid["theory"]["chosen"] == "kirchhoff" and "kirchhoff" in s5["ndf"], (mid["theory"], s5["ndf"].keys())
assert "D_K" in {m["key"]: m["label"] for m in s5["brdf"]["models"]}["measured"]
assert dk["used"] == "kirchhoff" and dk["theory"]["requested"] == "kirchhoff", dk["theory"]
assert "method_outside_validity" not in w3, w3
assert all(p["used_is_valid"] for p in dk["per_incidence"])
print("metropro-1:", th["why"], "| sigma 20 nm:", mid["theory"]["why"])
PY
echo ok
