#!/usr/bin/env bash
# Runs one libFuzzer target for a fixed time from a fresh corpus seeded with
# configs (tests/fuzz/CMakeLists.txt registers it with ctest; docs/fuzzing.md).
# Usage: run_fuzzer.sh FUZZER WORKDIR SECONDS MAX_LEN DICT SEED_DIR CONFIG_DIR...
#   DICT        libFuzzer dictionary (tests/fuzz/pomlab.dict)
#   SEED_DIR    committed seeds of this target (every file in it)
#   CONFIG_DIR  folders whose *.cfg and *.arch files are seeds too
# Fails (exit 1) on any crash, leak, undefined behaviour, timeout or memory
# blow-up; the input that did it is left in WORKDIR with the command that
# replays it.
set -euo pipefail
fuzzer=$1 work=$2 seconds=$3 max_len=$4 dict=$5 seed_dir=$6
shift 6
rm -rf "$work"
mkdir -p "$work/corpus" "$work/seeds" "$work/tmp"
# the targets' copies of the configs (left behind only by a crash) stay here
export TMPDIR="$work/tmp"
n=0
for f in "$seed_dir"/*; do
  [ -f "$f" ] || continue
  cp "$f" "$work/seeds/seed-$(basename "$f")"
  n=$((n + 1))
done
for d in "$@"; do
  for f in "$d"/*.cfg "$d"/*.arch; do
    [ -f "$f" ] || continue
    cp "$f" "$work/seeds/$(basename "$d")-$(basename "$f")"
    n=$((n + 1))
  done
done
echo "$(basename "$fuzzer"): $n seeds, ${seconds} s, inputs up to ${max_len} bytes"
# -seed fixes the mutation sequence; the budget is wall time, so how far a
# run gets depends on the machine. -timeout: a hang per input; -rss_limit_mb
# and -malloc_limit_mb: a memory blow-up (both fail the run).
if "$fuzzer" -seed=1 -max_total_time="$seconds" -max_len="$max_len" -timeout=10 \
  -rss_limit_mb=2048 -malloc_limit_mb=1024 -dict="$dict" -print_final_stats=1 \
  -artifact_prefix="$work/" "$work/corpus" "$work/seeds" >"$work/log" 2>&1; then
  grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)|^#[0-9]+.*DONE' "$work/log" || true
  echo "$(basename "$fuzzer"): no crash, leak, hang or undefined behaviour"
  exit 0
fi
tail -n 60 "$work/log"
for a in "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-* "$work"/slow-unit-*; do
  [ -f "$a" ] || continue
  echo "finding: $a (replay: $fuzzer $a)"
done
exit 1
