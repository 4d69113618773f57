#!/usr/bin/env bash
# generate -> info --json -> convert round trips, the JSON keys scripts rely on, and every
# bundled real file through info.
set -u
BIN=$1 DATA=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

$BIN generate gaussian --nx 512 --ny 512 --sigma 0.2um --tau 2um --seed 3 -o "$T/g.x3p" --preview "$T/g.png" \
  || fail "generate"
[ -s "$T/g.png" ] || fail "no preview"
$BIN info --json --level none "$T/g.x3p" >"$T/info.json" || fail "info --json"
python3 - "$T/info.json" <<'PY' || fail "info JSON"
import json, sys, math
j = json.load(open(sys.argv[1]))
s = j["surfaces"][0]
for k in ["path", "nx", "ny", "dx_m", "dy_m", "valid_fraction", "mean_m", "sq_m", "sa_m", "skewness", "kurtosis",
          "slope_rms_x", "slope_rms_y", "corr_length_x_m", "corr_length_y_m", "corr_length_m"]:
    assert k in s, k
assert s["nx"] == 512 and abs(s["dx_m"] - 110e-9) < 1e-15
assert abs(s["sq_m"] / 0.2e-6 - 1) < 0.01, s["sq_m"]
assert abs(s["corr_length_m"] / 2e-6 - 1) < 0.05, s["corr_length_m"]
assert abs(s["slope_rms_x"] / (2**0.5 * 0.1) - 1) < 0.05, s["slope_rms_x"]
PY

# Round trips through every writable format keep the statistics exactly.
for ext in gwy npy xyz txt; do
  $BIN convert "$T/g.x3p" "$T/g.$ext" 2>/dev/null || fail "convert to $ext"
  $BIN info --json --level none "$T/g.$ext" >"$T/$ext.json" || fail "info $ext"
  python3 - "$T/info.json" "$T/$ext.json" <<'PY' || fail "round trip via $ext"
import json, sys
a = json.load(open(sys.argv[1]))["surfaces"][0]; b = json.load(open(sys.argv[2]))["surfaces"][0]
for k in ["nx", "ny", "dx_m", "dy_m", "sq_m", "slope_rms_x", "corr_length_x_m"]:
    assert a[k] == b[k], (k, a[k], b[k])
PY
done

# Every bundled real file reads.
for f in "$DATA"/*.x3p "$DATA"/*.dat "$DATA"/*.datx "$DATA"/*.sur "$DATA"/*.gwy; do
  $BIN info "$f" >/dev/null 2>"$T/err" || fail "info $f: $(cat "$T/err")"
done

# A scan set from a manifest, processed one by one.
printf '# two scans\n%s\n%s\n' "$DATA/sur-2.sur" "$DATA/test.gwy" >"$T/scans.txt"
$BIN info --json "@$T/scans.txt" >"$T/set.json" 2>/dev/null || fail "manifest"
python3 -c "import json,sys; assert len(json.load(open('$T/set.json'))['surfaces']) == 2" || fail "manifest count"
echo "ok"
