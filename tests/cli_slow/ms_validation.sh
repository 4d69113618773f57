#!/usr/bin/env bash
# Multiple scattering against the ray tracer (docs/validation.md, "Multiple scattering"): the
# table's script on a 256^2 tile with fewer rays (about a minute), asserting that on the rougher
# surface (rms slope 0.6) the random walk's albedo is within 3 % of the traced one and closer to
# it than single scattering at every angle of incidence.
set -u
BIN=$1
fail() { echo "FAIL: $*"; exit 1; }
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PYDIR=$(cd "$(dirname "$BIN")/.." && pwd)/python  # build/bin/microbrdf -> build/python
PYTHONPATH=$PYDIR /usr/bin/python3 -c "import microbrdf" 2>/dev/null || { echo "SKIP: no Python module"; exit 0; }
PYTHONPATH=$PYDIR /usr/bin/python3 "$ROOT/scripts/ms_validation.py" --bin "$BIN" --size 256 \
  --rays 100000 --walks 64 --check || fail "ms_validation.py --check"
echo OK
