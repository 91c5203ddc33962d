#!/usr/bin/env bash
# Sets up, builds and runs the whole cellfx test suite (GL tests included: they run headless
# on Mesa llvmpipe when there is no GPU).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" -DCELLFX_BUILD_TESTS=ON
build="${CELLFX_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure -j "$(nproc)"
