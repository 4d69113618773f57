#!/usr/bin/env bash
# The rule docs/guide.md states for output paths ("Output files and folders"), command by
# command: an output's folder must exist (else exit 2 before any work, naming the folder and
# `mkdir -p`, nothing created); an output folder is created inside an existing folder, with or
# without a trailing slash; a path through a file is refused naming it.
# Usage: output_folders.sh BIN
set -uo pipefail
BIN=$(realpath "$1")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cd "$T"
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# A small scan and NDF for the commands that read one.
"$BIN" generate gaussian --sigma 0.2um --tau 2um --nx 64 --ny 64 --seed 1 -o g.x3p >/dev/null 2>&1 ||
  { echo "generate failed"; exit 1; }
GGX=(--model ggx --alpha 0.2 --metal Al)

# Outputs in a folder that does not exist: refused with exit 2, the folder named with mkdir -p,
# nothing created.
refused() {  # NAME FOLDER COMMAND...
  local name=$1 folder=$2
  shift 2
  "$@" >.stdout 2>err
  local rc=$?
  [ "$rc" = 2 ] || fail "$name: exit $rc, expected 2 ($(cat err))"
  grep -q "folder $folder does not exist (create it first: mkdir -p $folder)" err ||
    fail "$name: message does not name $folder with mkdir -p: $(cat err)"
  [ ! -e "$folder" ] || fail "$name: created $folder"
}
refused "predict -o out/land" out "$BIN" predict g.x3p --no-render -o out/land
refused "predict -o out/land/" out "$BIN" predict g.x3p --no-render -o out/land/
refused "export mitsuba -o a/b/" a "$BIN" export mitsuba "${GGX[@]}" -o a/b/
refused "export pbrt -o a/b" a "$BIN" export pbrt "${GGX[@]}" -o a/b
refused "export bsdf -o nodir/x.bsdf" nodir "$BIN" export bsdf "${GGX[@]}" -o nodir/x.bsdf
refused "export gltf -o nodir/x.glb" nodir "$BIN" export gltf "${GGX[@]}" -o nodir/x.glb
refused "render -o nodir/x.png" nodir "$BIN" render --scene sphere "${GGX[@]}" --size 8 --spp 1 -o nodir/x.png

# Output folders inside an existing folder: created, with or without a trailing slash.
for o in scene scene2/; do
  "$BIN" export mitsuba "${GGX[@]}" -o "$o" >/dev/null 2>err || fail "export mitsuba -o $o: $(cat err)"
  [ -f "${o%/}/scene.xml" ] || fail "export mitsuba -o $o: no ${o%/}/scene.xml"
done
mkdir -p deep
"$BIN" predict g.x3p --no-render -o deep/rep/ >/dev/null 2>err || fail "predict -o deep/rep/: $(cat err)"
[ -f deep/rep/summary.json ] || fail "predict -o deep/rep/: no summary.json"
ls -A deep | grep -v '^rep$' && fail "predict -o deep/rep/ left something beside rep"
# ... and replaced by a second run (a trailing slash must not turn the folder into its parent).
"$BIN" predict g.x3p --no-render -o deep/rep/ >/dev/null 2>err || fail "predict -o deep/rep/ again: $(cat err)"
[ -f deep/rep/summary.json ] && [ ! -e deep/rep/rep ] || fail "predict -o deep/rep/ again: wrong layout"

# A path through a file: refused naming it.
touch plain
"$BIN" export mitsuba "${GGX[@]}" -o plain/x/ >/dev/null 2>err
[ $? = 2 ] && grep -q "plain is not a folder" err || fail "a path through a file: $(cat err)"

[ "$fails" = 0 ] && echo "output folders: every case as docs/guide.md states"
exit $((fails > 0))
