#!/usr/bin/env bash
# Runs each libFuzzer harness of tests/fuzz/ for FUZZ_SECONDS (default 60), one at a time, at low
# priority: `make fuzz`, or `scripts/fuzz.sh [TARGET...]` after `cmake --build --preset fuzz`.
# New inputs go to build-fuzz/corpus/TARGET (the committed seeds in tests/fuzz/corpus/ are only
# read); a crash is written to build-fuzz/artifacts/TARGET/ and stops the run with exit status 1.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
secs=${FUZZ_SECONDS:-60}
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(asm object iss nff machine debugger pipeline schedule sweep)
# Allocation stacks cost a tenth of the time of the allocation-heavy targets (pipeline, schedule).
export ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=0}
status=0
for t in "${targets[@]}"; do
  bin=$root/build-fuzz/tests/fuzz/fuzz_$t
  [ -x "$bin" ] || { echo "fuzz.sh: $bin missing (cmake --preset fuzz && cmake --build --preset fuzz)"; exit 2; }
  work=$root/build-fuzz/corpus/$t art=$root/build-fuzz/artifacts/$t/
  mkdir -p "$work" "$art"
  dict=()
  [ -f "$root/tests/fuzz/dict/$t.dict" ] && dict=(-dict="$root/tests/fuzz/dict/$t.dict")
  echo "== fuzz_$t: ${secs} s"
  nice -n 19 "$bin" "${dict[@]}" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$art" "$work" "$root/tests/fuzz/corpus/$t" || status=1
done
exit $status
