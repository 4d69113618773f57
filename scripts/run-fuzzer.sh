#!/usr/bin/env bash
# Runs one libFuzzer binary for a bounded time on a scratch copy of its seed corpus.
# Usage: run-fuzzer.sh FUZZER SEED_DIR SECONDS [MAX_LEN]. Non-zero exit on a crash, leak, hang
# (>10 s per input) or memory blow-up (> 2 GB), with the reproducer left in the scratch
# directory. MAX_LEN (default 256 KiB) is the largest input tried; seeds longer are cut to it.
set -euo pipefail
fuzzer=$(realpath "$1") seeds=$(realpath -m "$2") secs=$3 max_len=${4:-262144}
work=$(mktemp -d "${TMPDIR:-/tmp}/microbrdf-fuzz.XXXXXX")
mkdir -p "$work/corpus"
[ -d "$seeds" ] && cp -r "$seeds"/. "$work/corpus/" 2>/dev/null || true
cd "$work"
echo "fuzzing $(basename "$fuzzer") for ${secs}s (scratch: $work)"
"$fuzzer" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
  -print_final_stats=1 corpus 2>fuzz.log || { tail -n 60 fuzz.log; echo "FUZZ FAILURE: reproducer in $work"; exit 1; }
grep -E "stat::number_of_executed_units|stat::peak_rss_mb" fuzz.log || true
rm -rf "$work"
