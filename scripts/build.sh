#!/usr/bin/env bash
# Configures and builds cellfx into build/ (or $CELLFX_BUILD_DIR). Extra arguments go to cmake.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${CELLFX_BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${CELLFX_BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build"
