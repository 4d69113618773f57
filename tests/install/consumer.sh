#!/usr/bin/env bash
# `cmake --install` into a fresh prefix, then a program outside the tree (this folder's
# CMakeLists.txt + main.cpp) built against it twice, with find_package(microbrdf CONFIG) and with
# pkg-config; both read a scan and estimate its NDF through the installed library, and the
# installed CLI and Python module run from the prefix.
#   bash consumer.sh BUILD_DIR VERSION DATA_DIR WORK_DIR
# WORK_DIR is emptied first; it stays the same between runs so ccache can reuse the consumer's
# compiles (any change to an installed header or flag still recompiles).
set -u
BUILD=$1 VERSION=$2 DATA=$3 WORK=$4
HERE=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
now() { date +%s.%N; }
secs() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$(now)"; }
CCACHE=$(command -v ccache || true)

rm -rf "$WORK" && mkdir -p "$WORK" || fail "cannot make $WORK"
WORK=$(cd "$WORK" && pwd) BUILD=$(cd "$BUILD" && pwd) DATA=$(cd "$DATA" && pwd)
P=$WORK/prefix

# --- the install itself: layout, SONAME, the version in every place it is written
t=$(now)
cmake --install "$BUILD" --prefix "$P" >"$WORK/install.log" 2>&1 || fail "cmake --install: $(tail -5 "$WORK/install.log")"
echo "install: $(secs "$t") s, $(du -sh "$P" | cut -f1)"
SOVERSION=$(echo "$VERSION" | cut -d. -f1-2)  # 0.x: major.minor (cmake/install.cmake)
for f in bin/microbrdf include/microbrdf/version.hpp include/microbrdf/ndf_estimate.hpp \
  "lib/libmicrobrdf.so.$VERSION" "lib/libmicrobrdf.so.$SOVERSION" lib/libmicrobrdf.so \
  lib/cmake/microbrdf/microbrdfConfig.cmake lib/cmake/microbrdf/microbrdfConfigVersion.cmake \
  lib/cmake/microbrdf/microbrdfTargets.cmake lib/pkgconfig/microbrdf.pc; do
  [ -e "$P/$f" ] || fail "not installed: $f"
done
readelf -d "$P/lib/libmicrobrdf.so" | grep -q "SONAME.*\[libmicrobrdf.so.$SOVERSION\]" ||
  fail "SONAME is not libmicrobrdf.so.$SOVERSION: $(readelf -d "$P/lib/libmicrobrdf.so" | grep SONAME)"
[ "$("$P/bin/microbrdf" --version)" = "microbrdf $VERSION" ] ||
  fail "installed microbrdf --version: '$("$P/bin/microbrdf" --version)', want 'microbrdf $VERSION'"
# The public headers include only the standard library, Eigen, nlohmann_json and each other:
# what the CMake package's find_dependency and the .pc file's Requires provide.
bad=$(grep -ho '#include *[<"][^>"]*[>"]' "$P"/include/microbrdf/*.hpp | sed 's/#include *//' | sort -u |
  grep -v '^<[a-z_]*>$' | grep -v -e '^<Eigen/' -e '^<nlohmann/' -e '^"microbrdf/' || true)
[ -z "$bad" ] || fail "public headers include what the package does not provide: $bad"

# --- the Python module from the prefix (when the build has it)
if [ -d "$BUILD/python/microbrdf" ]; then
  PYDIR=$(ls -d "$P"/lib/python3*/*-packages 2>/dev/null | head -1)
  [ -n "$PYDIR" ] || fail "no Python package folder under $P/lib"
  out=$(cd "$WORK" && PYTHONPATH=$PYDIR /usr/bin/python3 -c \
    "import microbrdf, sys; print(microbrdf.__version__); print(microbrdf.__file__)" 2>&1) ||
    fail "import microbrdf from $PYDIR: $out"
  [ "$(echo "$out" | sed -n 1p)" = "$VERSION" ] || fail "microbrdf.__version__: $out"
  case "$(echo "$out" | sed -n 2p)" in "$PYDIR"/microbrdf/*) ;; *) fail "imported from elsewhere: $out" ;; esac
fi

# --- the consumer with find_package(microbrdf CONFIG)
t=$(now)
cmake -S "$HERE" -B "$WORK/cmake-build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$P" \
  ${CCACHE:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CCACHE} >"$WORK/configure.log" 2>&1 ||
  fail "consumer configure: $(tail -20 "$WORK/configure.log")"
grep -q "microbrdf_DIR:PATH=$P/lib/cmake/microbrdf" "$WORK/cmake-build/CMakeCache.txt" ||
  fail "find_package found another microbrdf: $(grep microbrdf_DIR "$WORK/cmake-build/CMakeCache.txt")"
cmake --build "$WORK/cmake-build" >"$WORK/build.log" 2>&1 || fail "consumer build: $(tail -30 "$WORK/build.log")"
echo "consumer (find_package): configure + build $(secs "$t") s"
ldd "$WORK/cmake-build/consumer" | grep -q "libmicrobrdf.so.$SOVERSION => $P/lib/" ||
  fail "consumer does not load the installed library: $(ldd "$WORK/cmake-build/consumer" | grep microbrdf)"

SCAN=$DATA/sample-land.x3p
"$WORK/cmake-build/consumer" "$SCAN" 257 >"$WORK/consumer.txt" 2>&1 || fail "consumer run: $(cat "$WORK/consumer.txt")"
cat "$WORK/consumer.txt"
"$P/bin/microbrdf" ndf "$SCAN" --method naive --resolution 257 -o "$WORK/ndf.npy" --json >"$WORK/cli.json" ||
  fail "installed microbrdf ndf"
python3 - "$WORK/consumer.txt" "$WORK/cli.json" "$VERSION" <<'PY' || fail "consumer result"
import json, sys
got = dict(line.split(None, 1) for line in open(sys.argv[1]).read().splitlines())
cli = json.load(open(sys.argv[2]))
assert got["version"] == sys.argv[3], got["version"]
# The scan's grid (tests/data/README.md: 918 x 256) and the normalisation of an NDF table,
# sum D Delta^2 = 1, summed by the consumer itself.
assert (int(got["nx"]), int(got["ny"])) == (918, 256), (got["nx"], got["ny"])
assert abs(float(got["integral"]) - 1) < 1e-3, got["integral"]
# The same numbers as the installed CLI on the same scan (the same library code, levelled alike).
assert int(got["samples_used"]) == cli["samples_used"] > 0, (got["samples_used"], cli["samples_used"])
for k in ["slope_rms_x", "slope_rms_y"]:
    assert abs(float(got[k]) / cli[k] - 1) < 1e-7, (k, got[k], cli[k])
PY

# --- the same program with pkg-config's flags (the headers need C++20; the rpath is only so it
# runs from the prefix without LD_LIBRARY_PATH)
export PKG_CONFIG_PATH=$P/lib/pkgconfig
[ "$(pkg-config --modversion microbrdf)" = "$VERSION" ] || fail "pkg-config --modversion: $(pkg-config --modversion microbrdf 2>&1)"
[ "$(realpath "$(pkg-config --variable=prefix microbrdf)")" = "$(realpath "$P")" ] ||
  fail "pkg-config prefix $(pkg-config --variable=prefix microbrdf) is not $P"
t=$(now)
# shellcheck disable=SC2046  # pkg-config's output is a list of flags
$CCACHE g++ -std=c++20 -O2 $(pkg-config --cflags microbrdf) -c "$HERE/main.cpp" -o "$WORK/consumer-pc.o" \
  >"$WORK/pc.log" 2>&1 || fail "compile with pkg-config --cflags: $(tail -20 "$WORK/pc.log")"
# shellcheck disable=SC2046
g++ "$WORK/consumer-pc.o" -o "$WORK/consumer-pc" $(pkg-config --libs microbrdf) -Wl,-rpath,"$P/lib" \
  >"$WORK/pc.log" 2>&1 || fail "link with pkg-config --libs: $(tail -20 "$WORK/pc.log")"
echo "consumer (pkg-config): build $(secs "$t") s"
"$WORK/consumer-pc" "$SCAN" 257 >"$WORK/consumer-pc.txt" 2>&1 || fail "pkg-config consumer run: $(cat "$WORK/consumer-pc.txt")"
cmp -s "$WORK/consumer.txt" "$WORK/consumer-pc.txt" || fail "pkg-config consumer printed other numbers"
echo "OK"
