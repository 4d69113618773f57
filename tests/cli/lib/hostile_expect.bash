# Sourced by the hostile-input scripts (not a test itself): `hostile_run` runs one hostile case
# and checks what every such case must show (docs: the error contract in architecture.md):
#  - the expected exit code (or any non-zero one), never a signal;
#  - a message on stderr matching a pattern (the file or the flag), and no "internal error" or
#    bare std:: text;
#  - at most LIMIT_SECONDS of wall time (default 10) and a max RSS under 1 GiB, and under 1.5 x
#    the budget when the command line gives --max-memory;
#  - no temporary outputs (*.tmp-PID-N, .*.partial-PID) left in the folder HOSTILE_DIR.
# Needs: fail() and HOSTILE_DIR defined by the caller; GNU time at /usr/bin/time.
# Prints one line per case: exit code, max RSS, seconds and the command.

# Bytes of a --max-memory value (K/M/G suffixes, powers of 1024), or empty when absent.
hostile_budget_kib() {
  local prev="" a
  for a in "$@"; do
    if [ "$prev" = --max-memory ]; then
      case $a in
        *G) echo $(( ${a%G} * 1024 * 1024 ));;
        *M) echo $(( ${a%M} * 1024 ));;
        *K) echo "${a%K}";;
        *) echo $(( a / 1024 ));;
      esac
      return
    fi
    prev=$a
  done
}

# hostile_run CODE PATTERN -- CMD...   (CODE: a number or "nz" for any non-zero exit; PATTERN
# empty: any message; VMEM_LIMIT_KIB: a `ulimit -v` for the command)
hostile_run() {
  local code=$1 pat=$2; shift 3
  local limit=${LIMIT_SECONDS:-10} usage="$HOSTILE_DIR/.usage"
  (ulimit -v "${VMEM_LIMIT_KIB:-unlimited}" && exec timeout -s KILL $((limit * 3)) \
    /usr/bin/time -o "$usage" -f '%M %e' "$@") >"$HOSTILE_DIR/.out" 2>"$HOSTILE_DIR/.err"
  local rc=$? kib secs
  read -r kib secs < <(tail -n 1 "$usage") || fail "no resource usage (killed?) from: $*"
  printf 'case: exit %d, max RSS %d MiB, %s s: %s\n' "$rc" $((kib / 1024)) "$secs" "$*"
  local err
  err=$(cat "$HOSTILE_DIR/.err")
  [ "$rc" -lt 128 ] || fail "ended by signal $((rc - 128)) from: $*: $err"
  if [ "$code" = nz ]; then [ "$rc" -ne 0 ] || fail "exit 0 from: $*"; else
    [ "$rc" -eq "$code" ] || fail "exit $rc (want $code) from: $*: $err"; fi
  [ -z "$pat" ] || grep -q -- "$pat" "$HOSTILE_DIR/.err" ||
    fail "message does not match '$pat' from: $*: $err"
  grep -q "internal error\|std::" "$HOSTILE_DIR/.err" && fail "internal error / std:: from: $*: $err"
  [ "$kib" -lt 1048576 ] || fail "max RSS $((kib / 1024)) MiB (over 1 GiB) from: $*"
  local budget
  budget=$(hostile_budget_kib "$@")
  [ -z "$budget" ] || [ "$kib" -lt $((budget * 3 / 2)) ] ||
    fail "max RSS $((kib / 1024)) MiB over 1.5 x --max-memory from: $*"
  awk -v s="$secs" -v l="$limit" 'BEGIN { exit !(s <= l) }' || fail "took $secs s (over $limit s): $*"
  local left
  left=$(find "$HOSTILE_DIR" -name '*.tmp-*' -o -name '*.partial*' -o -name '*.old-*' | head -n 3)
  [ -z "$left" ] || fail "temporaries left by: $*: $left"
  return 0
}
