#!/usr/bin/env bash
# The Debian package: built with CPack from the build tree, installed with dpkg -i, its CLI and
# Python module run from /usr, then removed with dpkg -r leaving none of its files behind.
# Needs root and dpkg; exits 77 (skipped) otherwise, or when a microbrdf package is already
# installed (the test does not touch a system's own installation).
#   bash package.sh BUILD_DIR VERSION WORK_DIR
set -u
BUILD=$1 VERSION=$2 WORK=$3
fail() { echo "FAIL: $*"; exit 1; }
skip() { echo "SKIP: $*"; exit 77; }
now() { date +%s.%N; }
secs() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$(now)"; }

[ "$(id -u)" -eq 0 ] || skip "dpkg -i needs root"
command -v dpkg >/dev/null && command -v dpkg-shlibdeps >/dev/null || skip "needs dpkg and dpkg-shlibdeps (dpkg-dev)"
if dpkg-query -W -f='${Status}' microbrdf 2>/dev/null | grep -q "install ok"; then
  skip "a microbrdf package is already installed"
fi
for f in /usr/bin/microbrdf /usr/lib/python3/dist-packages/microbrdf /usr/include/microbrdf; do
  [ ! -e "$f" ] || skip "$f exists (an installation outside dpkg)"
done

# dpkg refuses to run while apt or another dpkg holds its lock: wait for it (up to 5 min).
dpkg_wait() {
  local i out
  for i in $(seq 60); do
    if out=$("$@" 2>&1); then printf '%s\n' "$out"; return 0; fi
    printf '%s\n' "$out" | grep -q "lock" || { printf '%s\n' "$out"; return 1; }
    sleep 5
  done
  printf '%s\n' "$out"
  return 1
}

rm -rf "$WORK" && mkdir -p "$WORK" || fail "cannot make $WORK"
WORK=$(cd "$WORK" && pwd) BUILD=$(cd "$BUILD" && pwd)
t=$(now)
cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK" >"$WORK/cpack.log" 2>&1 ||
  fail "cpack: $(tail -20 "$WORK/cpack.log")"
DEB=$(ls "$WORK"/microbrdf_"$VERSION"_*.deb 2>/dev/null | head -1)
[ -n "$DEB" ] || fail "no microbrdf_${VERSION}_*.deb in $WORK: $(ls "$WORK")"
echo "package: $(secs "$t") s, $(basename "$DEB") $(du -h "$DEB" | cut -f1), installed size $(dpkg-deb -f "$DEB" Installed-Size) KiB"

# The control fields: name, version, section, maintainer, and Depends from dpkg-shlibdeps (the
# C library and the libraries of the dependencies) plus python3 and numpy for the module.
dpkg-deb -f "$DEB" Package Version Section Maintainer Depends | tee "$WORK/control.txt"
[ "$(dpkg-deb -f "$DEB" Package)" = microbrdf ] || fail "Package field"
[ "$(dpkg-deb -f "$DEB" Version)" = "$VERSION" ] || fail "Version field"
[ -n "$(dpkg-deb -f "$DEB" Section)" ] && [ -n "$(dpkg-deb -f "$DEB" Maintainer)" ] || fail "Section/Maintainer"
DEPENDS=$(dpkg-deb -f "$DEB" Depends)
for p in libc6 libstdc++6 libgomp1 libfftw3-double3 libzip4 libhdf5 libembree3 libopenmpi3 python3-numpy "python3 (>="; do
  echo "$DEPENDS" | grep -q "$p" || fail "Depends lacks $p: $DEPENDS"
done
cleanup() { dpkg-query -W microbrdf >/dev/null 2>&1 && dpkg_wait dpkg --purge microbrdf >/dev/null; }
trap cleanup EXIT
dpkg_wait dpkg -i "$DEB" >"$WORK/dpkg-i.log" || fail "dpkg -i: $(tail -20 "$WORK/dpkg-i.log")"
dpkg -L microbrdf >"$WORK/files.txt" || fail "dpkg -L"
grep -qx /usr/lib/python3/dist-packages/microbrdf/__init__.py "$WORK/files.txt" ||
  fail "the Python module is not in /usr/lib/python3/dist-packages: $(grep -m3 python "$WORK/files.txt")"

# From /usr, with no trace of the build tree in the environment.
cd "$WORK" || fail "cd $WORK"
out=$(env -u PYTHONPATH -u LD_LIBRARY_PATH /usr/bin/microbrdf --version) || fail "/usr/bin/microbrdf --version"
[ "$out" = "microbrdf $VERSION" ] || fail "/usr/bin/microbrdf --version: $out"
# Bytecode on (no -B, no PYTHONDONTWRITEBYTECODE): as root python3 writes it beside the module,
# where dpkg does not know it; the prerm must remove it for dpkg -r to leave nothing.
out=$(env -u PYTHONPATH -u PYTHONDONTWRITEBYTECODE /usr/bin/python3 -c "import microbrdf; print(microbrdf.__version__, microbrdf.__file__)") ||
  fail "python3 -c 'import microbrdf' from the package"
[ "$out" = "$VERSION /usr/lib/python3/dist-packages/microbrdf/__init__.py" ] || fail "import microbrdf: $out"
[ -d /usr/lib/python3/dist-packages/microbrdf/__pycache__ ] || fail "python3 wrote no bytecode: the prerm is not tested"
# Every library an installed binary links directly (DT_NEEDED) comes from a package in Depends.
: >"$WORK/needed.txt"
while read -r f; do
  [ -f "$f" ] && head -c 4 "$f" | grep -q ELF || continue
  ldd "$f" >"$WORK/ldd.txt" 2>&1
  grep -q "not found" "$WORK/ldd.txt" && fail "$f: $(grep 'not found' "$WORK/ldd.txt")"
  for soname in $(readelf -d "$f" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
    # "libx.so.1 => /path (addr)", or "/path/ld-linux-x86-64.so.2 (addr)" for the loader
    lib=$(awk -v s="$soname" '$1 == s && $2 == "=>" {print $3} substr($1, length($1) - length(s)) == "/" s {print $1}' "$WORK/ldd.txt")
    [ -n "$lib" ] || fail "$f: ldd does not resolve $soname"
    echo "$lib" >>"$WORK/needed.txt"
  done
done <"$WORK/files.txt"
# One dpkg -S for all (it reads the whole database each time). dpkg knows a library by the path
# its package ships, /lib/... or /usr/lib/... (merged /usr): try the path ldd printed, then the
# resolved one.
sort -u "$WORK/needed.txt" -o "$WORK/needed.txt"
dpkg -S $(cat "$WORK/needed.txt") 2>/dev/null >"$WORK/owners.txt"
while read -r lib; do
  grep -q ": $lib\$" "$WORK/owners.txt" || realpath "$lib"
done <"$WORK/needed.txt" >"$WORK/needed-real.txt"
[ -s "$WORK/needed-real.txt" ] && dpkg -S $(cat "$WORK/needed-real.txt") 2>/dev/null >>"$WORK/owners.txt"
[ "$(wc -l <"$WORK/owners.txt")" -ge "$(wc -l <"$WORK/needed.txt")" ] ||
  fail "dpkg -S does not know every library: $(cat "$WORK/needed.txt")"
for pkg in $(cut -d: -f1 "$WORK/owners.txt" | sort -u); do
  echo "$DEPENDS" | grep -q "\b$pkg\b" || fail "a binary needs a library of package '$pkg', not in Depends"
done
echo "Depends covers the $(wc -l <"$WORK/needed.txt") libraries the binaries need ($(cut -d: -f1 "$WORK/owners.txt" | sort -u | wc -l) packages)"

dpkg_wait dpkg -r microbrdf >"$WORK/dpkg-r.log" || fail "dpkg -r: $(tail -20 "$WORK/dpkg-r.log")"
grep -i "warning" "$WORK/dpkg-r.log" && fail "dpkg -r warned"
left=""
while read -r f; do
  # Folders other packages share (/usr, /usr/lib, ...) stay; the package's own files and folders go.
  if [ -f "$f" ] || [ -L "$f" ]; then left="$left $f"; fi
  case "$f" in */microbrdf) [ -e "$f" ] && left="$left $f" ;; esac
done <"$WORK/files.txt"
[ -z "$left" ] || fail "left after dpkg -r (remove by hand before the next run):$left"
echo "files in the package: $(wc -l <"$WORK/files.txt") paths, none left after dpkg -r"
# dpkg -r keeps the package's record (state config-files: its postrm, for a purge); --purge drops it.
dpkg_wait dpkg --purge microbrdf >"$WORK/dpkg-purge.log" || fail "dpkg --purge: $(tail -20 "$WORK/dpkg-purge.log")"
! dpkg-query -W microbrdf >/dev/null 2>&1 || fail "dpkg still lists microbrdf after --purge"
trap - EXIT
echo "OK"
