#!/usr/bin/env bash
# Installs the Debian packages microbrdf builds and tests with. Idempotent: when every package
# is already installed it returns in well under a second and touches nothing; `apt-get update`
# runs only when something is missing. Needs root (or sudo) only in that case.
#
#   scripts/install-deps.sh            build and test dependencies (what `make test` and CI need)
#   scripts/install-deps.sh --report   the same plus headless Chromium and Node.js: `make demo`
#                                      screenshots the HTML report (scripts/screenshot-report.sh),
#                                      and the browser test (label "browser" of `make test`,
#                                      skipped without them) drives Chromium with puppeteer-core,
#                                      installed from npm by scripts/install-browser-test.sh
# Wherever npm is available, the Khronos glTF-Validator for the glTF test (tests/gltf/run.sh) is
# installed from npm too (scripts/install-gltf-validator.sh); without it that test is skipped.
# So is three.js for the report's glTF view (scripts/install-report-js.sh; cmake embeds it at
# configure time); without it the report leaves that view out and says why.
set -euo pipefail

REPORT=0
for arg in "$@"; do
  case "$arg" in
    --report) REPORT=1 ;;
    -h | --help)
      sed -n '2,9p' "$0"
      exit 0
      ;;
    *)
      echo "install-deps: unknown option '$arg' (--report)" >&2
      exit 2
      ;;
  esac
done

PACKAGES=(
  build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev clang-format
  libeigen3-dev        # linear algebra
  libfftw3-dev         # FFTs (ACF, PSD, generators)
  libopenexr-dev       # float EXR height images
  libtiff-dev          # 32-bit float TIFF height images
  libpng-dev           # previews
  libzip-dev           # x3p container
  libpugixml-dev       # x3p main.xml
  libssl-dev           # MD5 of x3p members (OpenSSL EVP)
  libhdf5-dev          # Zygo .datx
  libcli11-dev         # command line
  nlohmann-json3-dev   # JSON output and sidecars
  libfmt-dev           # formatting
  colord-data          # CIE 1931 colour matching functions and D65 (tables generated at build time)
  libcairo2-dev        # plots (PNG and SVG)
  libceres-dev         # non-linear least squares (NDF fits)
  libembree-dev        # ray tracing: Westin micro-scenes and the preview renderer (Embree 3)
  libtinyobjloader-dev # OBJ meshes for the renderer
  libgtest-dev libgmock-dev libbenchmark-dev
  dpkg-dev file        # make package: dpkg-shlibdeps (its Depends), file (CPack finds binaries)
  ccache               # compiler cache (used by CMake when present; speeds rebuilds)
  time                 # /usr/bin/time: max RSS of each hostile-input case in the CLI tests
  libopenmpi-dev openmpi-bin # scale-out: the same binary alone or under mpirun
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib python3-pil # Python module + tests
  python3-scipy        # the numpy/scipy peers of bench/peers/ (bench/whole_process.py, their test)
)
# Only for `make demo`: the report screenshot (kept out of the CI set, it is large).
REPORT_PACKAGES=(
  chromium             # headless browser for scripts/screenshot-report.sh
  fonts-dejavu-core    # a font for the report's text in that browser
  nodejs               # runs the browser test (tests/browser/report_test.mjs)
)
if [ "$REPORT" -eq 1 ]; then
  PACKAGES+=("${REPORT_PACKAGES[@]}")
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# npm comes with some Node.js builds and is a package of its own in Debian's.
if [ "$REPORT" -eq 1 ] && ! command -v npm >/dev/null; then
  missing+=(npm)
fi
# puppeteer-core for the browser test: with --report, or whenever Chromium and npm are already
# there (so `make test` runs that test on a machine that has a browser). A failure (no network)
# only means the browser test is skipped, saying so.
browser_test() {
  if [ "$REPORT" -eq 1 ] || { [ -x /usr/bin/chromium ] && command -v npm >/dev/null; }; then
    "$(dirname "$0")/install-browser-test.sh" ||
      echo "install-deps: puppeteer-core not installed; the browser test will be skipped" >&2
  fi
}
# The glTF-Validator, whenever npm is there (its own node_modules; a failure only skips the test).
gltf_validator() {
  if command -v npm >/dev/null; then
    "$(dirname "$0")/install-gltf-validator.sh" ||
      echo "install-deps: gltf-validator not installed; the glTF test will be skipped" >&2
  fi
}
# three.js for the report's glTF view, whenever npm is there (a failure only leaves the view out).
report_js() {
  if command -v npm >/dev/null; then
    "$(dirname "$0")/install-report-js.sh" ||
      echo "install-deps: three.js not installed; reports will leave the glTF view out" >&2
  fi
}
if [ ${#missing[@]} -eq 0 ]; then
  browser_test
  gltf_validator
  report_js
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; install them as root" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
browser_test
gltf_validator
report_js
echo "install-deps: done" >&2
