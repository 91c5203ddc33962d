#!/usr/bin/env bash
# Sets up, builds and runs the whole cellfx test suite through ctest. GL tests are included:
# without a GPU they run headless on Mesa llvmpipe.
#   CELLFX_SANITIZE=1  builds with AddressSanitizer + UBSan into build-asan/ instead (samples
#                      included: the sample tests run them). CI runs both.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
if [ "${CELLFX_SANITIZE:-0}" = 1 ]; then
  export CELLFX_BUILD_DIR="${CELLFX_BUILD_DIR:-$root/build-asan}"
  export CELLFX_BUILD_TYPE=RelWithDebInfo
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}" # Mesa's drivers keep allocations to exit
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
  bash "$root/scripts/build.sh" -DCELLFX_BUILD_TESTS=ON -DCELLFX_SANITIZE=ON
else
  bash "$root/scripts/build.sh" -DCELLFX_BUILD_TESTS=ON
fi
cd "${CELLFX_BUILD_DIR:-$root/build}"
# --no-tests=error: a build that registered no tests fails rather than passing empty.
ctest --output-on-failure --no-tests=error -j "$(nproc)"
