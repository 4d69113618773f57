#!/usr/bin/env bash
# run_doc_blocks.py catches what it is for: small pages, each with one defect, must fail (a shown
# number changed, a pycon value changed, a failing command, a block without a label, a command
# hidden in a text block, a `make` line not marked), and their correct twins must pass; skips are
# counted with their reasons. Usage: runner_self_test.sh SOURCE BUILD
set -uo pipefail
SOURCE=$(realpath "$1")
BUILD=$(realpath "$2")
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0
RUN=(/usr/bin/python3 "$SOURCE/tests/docs/run_doc_blocks.py" --source "$SOURCE" --build "$BUILD")
F='```'

expect() {  # WANTED_STATUS NAME: the page $T/NAME.md
  "${RUN[@]}" "$T/$2.md" >"$T/$2.log" 2>&1
  local rc=$?
  if [ "$rc" != "$1" ]; then
    echo "FAIL: $2: exit $rc, expected $1"
    sed 's/^/  | /' "$T/$2.log" | tail -15
    fails=$((fails + 1))
  fi
}

# The shown output of a console block: the real digits pass, one changed digit fails.
good_info=$(cd "$SOURCE" && "$BUILD/bin/microbrdf" info tests/data/metropro-1.dat | grep Sq)
printf '%s\n' "${F}console" '$ microbrdf info tests/data/metropro-1.dat' '...' "$good_info" '...' "$F" >"$T/console_ok.md"
sed 's/13\.33 nm/13.34 nm/' "$T/console_ok.md" >"$T/console_changed.md"
grep -q "13.34 nm" "$T/console_changed.md" || { echo "FAIL: the fixture lost its number"; fails=$((fails + 1)); }
expect 0 console_ok
expect 1 console_changed

# A pycon session: the computed value passes, another fails.
printf '%s\n' "${F}pycon" '>>> import microbrdf as mb' \
  '>>> mb.statistics(mb.read_surface("tests/data/metropro-1.dat"))["nx"]' '640' "$F" >"$T/pycon_ok.md"
sed 's/^640$/641/' "$T/pycon_ok.md" >"$T/pycon_changed.md"
expect 0 pycon_ok
expect 1 pycon_changed

# sh blocks: a file a block makes is there for the next block of the page; a failing command
# fails the page; an `expect` annotation is checked.
printf '%s\n' "${F}sh" 'microbrdf generate gaussian --sigma 0.1um --tau 1um --nx 32 --ny 32 -o g.x3p' "$F" \
  '' '<!-- doc-test: expect "grid +32 x 32 samples" -->' "${F}sh" 'microbrdf info g.x3p' "$F" >"$T/sh_ok.md"
printf '%s\n' "${F}sh" 'microbrdf info missing.x3p' "$F" >"$T/sh_missing_file.md"
sed 's/32 x 32 samples/33 x 32 samples/' "$T/sh_ok.md" >"$T/sh_expect_changed.md"
expect 0 sh_ok
expect 1 sh_missing_file
expect 1 sh_expect_changed

# Blocks that must be labelled or marked.
printf '%s\n' "$F" 'microbrdf info tests/data/metropro-1.dat' "$F" >"$T/no_label.md"
printf '%s\n' "${F}text" 'microbrdf info tests/data/metropro-1.dat' "$F" >"$T/hidden_command.md"
printf '%s\n' "${F}sh" 'make demo' "$F" >"$T/make_unmarked.md"
printf '%s\n' '<!-- doc-test: skip: builds the project -->' "${F}sh" 'make demo' "$F" >"$T/make_skipped.md"
expect 1 no_label
expect 1 hidden_command
expect 1 make_unmarked
expect 0 make_skipped
grep -q "SKIP .*: builds the project" "$T/make_skipped.log" && grep -q "1 skipped" "$T/make_skipped.log" ||
  { echo "FAIL: the skip is not counted with its reason"; fails=$((fails + 1)); }

[ "$fails" = 0 ] && echo "run_doc_blocks.py: every defect caught, every twin passed"
exit $((fails > 0))
