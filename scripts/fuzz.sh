#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (ASan + UBSan) into build-fuzz/ and runs
# each for a bounded time, seeded from tests/fuzz/corpus/<target>/. Fails when any target
# crashes, hangs, leaks, runs out of memory or trips a sanitizer; the input that did it is
# kept in build-fuzz/artifacts/<target>/ (replay: build-fuzz/tests/fuzz/fuzz_<target> FILE).
# Prints a summary per target. See docs/robustness.md.
#   scripts/fuzz.sh [TARGET...]     vtk_legacy plot3d avs_ucd transfer_function height_field_png
#                                   scene (default: all)
#   CELLFX_FUZZ_SECONDS=60          run time per target
#   CELLFX_FUZZ_TIMEOUT=10          seconds one input may take before it counts as a hang
#   CELLFX_FUZZ_MALLOC_MB=512       largest single allocation allowed
#   CELLFX_FUZZ_RSS_MB=2048         memory limit of the process
#   CELLFX_FUZZ_FLAGS="..."         more libFuzzer flags (e.g. -use_value_profile=1)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${CELLFX_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${CELLFX_FUZZ_SECONDS:-60}"
timeout="${CELLFX_FUZZ_TIMEOUT:-10}"
malloc_mb="${CELLFX_FUZZ_MALLOC_MB:-512}"
rss_mb="${CELLFX_FUZZ_RSS_MB:-2048}"
all_targets=(vtk_legacy plot3d avs_ucd transfer_function height_field_png scene)
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  [ -f "$root/tests/fuzz/fuzz_$t.cpp" ] || { echo "fuzz.sh: unknown target \"$t\" (known: ${all_targets[*]})" >&2; exit 2; }
done

bash "$root/scripts/setup.sh" fuzz
cxx=clang++-14 cc=clang-14
command -v "$cxx" >/dev/null || { cxx=clang++; cc=clang; }
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCELLFX_FUZZ=ON -DCELLFX_BUILD_TESTS=OFF -DCELLFX_BUILD_SAMPLES=OFF >/dev/null
cmake --build "$build"

symbolizer="$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)"
[ -n "$symbolizer" ] && export ASAN_SYMBOLIZER_PATH="$symbolizer"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

mkdir -p "$build/logs"
summary=()
failed=0
for t in "${targets[@]}"; do
  work="$build/corpus/$t" artifacts="$build/artifacts/$t" log="$build/logs/$t.log"
  mkdir -p "$work" "$artifacts"
  dict=()
  [ -f "$root/tests/fuzz/$t.dict" ] && dict=(-dict="$root/tests/fuzz/$t.dict")
  echo "fuzz.sh: fuzz_$t for ${seconds} s (log: $log)"
  status=0
  # New inputs go into the first folder (build tree); the committed seeds are only read.
  # shellcheck disable=SC2086
  "$build/tests/fuzz/fuzz_$t" "$work" "$root/tests/fuzz/corpus/$t" "${dict[@]}" \
    -max_total_time="$seconds" -timeout="$timeout" -malloc_limit_mb="$malloc_mb" -rss_limit_mb="$rss_mb" \
    -artifact_prefix="$artifacts/" -print_final_stats=1 ${CELLFX_FUZZ_FLAGS:-} >"$log" 2>&1 </dev/null || status=$?
  stat() { grep -m1 "^stat::$1:" "$log" | awk '{print $2}'; }
  done_line="$(grep -E '^#[0-9]+[[:space:]]+(DONE|INITED|NEW|REDUCE|pulse)' "$log" | tail -1 || true)"
  cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$done_line")"
  ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$done_line")"
  corp="$(sed -n 's/.* corp: \([0-9]*\).*/\1/p' <<<"$done_line")"
  execs="$(stat number_of_executed_units)"
  result=ok
  if [ "$status" -ne 0 ]; then
    failed=1
    result="FAILED ($(grep -m1 -oE 'ERROR: (libFuzzer|AddressSanitizer|LeakSanitizer): [a-zA-Z-]+|runtime error|fuzz_[a-z_0-9]+: .{0,60}' "$log" || echo "exit $status"))"
    artifact="$(grep -m1 -oE 'Test unit written to [^ ]+' "$log" | cut -d' ' -f5 || true)"
    [ -n "$artifact" ] && result="$result, input: $artifact"
    echo "--- end of $log:"
    tail -40 "$log"
  fi
  summary+=("$(printf '%-18s %-8s execs %-10s exec/s %-7s cov %-6s ft %-7s corpus %-6s peak rss %s MB' "$t" \
    "$([ "$status" -eq 0 ] && echo ok || echo FAILED)" "${execs:-?}" "$(stat average_exec_per_sec)" "${cov:-?}" "${ft:-?}" \
    "${corp:-?}" "$(stat peak_rss_mb)")")
  [ "$result" != ok ] && summary+=("  $result")
done

echo
echo "fuzz.sh summary (${seconds} s per target):"
printf '%s\n' "${summary[@]}"
exit "$failed"
