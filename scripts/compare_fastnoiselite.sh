#!/usr/bin/env bash
# cellfx's noise beside FastNoise Lite, one call per sample, side by side in one process:
# perlin2, perlin3 and 4-octave fBm (docs/noise.md, "Against FastNoise Lite").
#   bash scripts/compare_fastnoiselite.sh FASTNOISELITE_DIR [ROUNDS]
# FASTNOISELITE_DIR is a checkout of FastNoise Lite (github.com/Auburn/FastNoiseLite, MIT) that
# you provide; its Cpp/FastNoiseLite.h is included. This script downloads nothing. It builds
# cellfx's fx library if needed ($CELLFX_BUILD_DIR, default build/, Release as scripts/build.sh
# makes it; configure that directory with -DCMAKE_CXX_FLAGS=-march=native to compare native builds
# of both), compiles scripts/compare_fastnoiselite.cpp with -O3 -march=native into
# $CELLFX_COMPARE_OUT (default out/compare_fastnoiselite) and runs it, ROUNDS rounds (15).
# Never part of the test suite, CI or the README's two commands.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -ge 1 ] || { sed -n '2,11p' "$0"; exit 2; }
header="$1/Cpp/FastNoiseLite.h"
[ -f "$header" ] || { echo "compare_fastnoiselite: no $header (pass the FastNoise Lite checkout)" >&2; exit 2; }
rounds="${2:-15}"

build="${CELLFX_BUILD_DIR:-$root/build}"
if [ ! -f "$build/fx/libcellfx_fx.a" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" --target cellfx_fx
out="${CELLFX_COMPARE_OUT:-$root/out/compare_fastnoiselite}"
mkdir -p "$out"
"${CXX:-g++}" -std=c++17 -O3 -march=native -isystem "$1/Cpp" -I"$root/fx/include" \
  "$root/scripts/compare_fastnoiselite.cpp" "$build/fx/libcellfx_fx.a" -lpthread -o "$out/compare_fastnoiselite"
echo "cellfx library: $build/fx/libcellfx_fx.a ($(grep -m1 '^CMAKE_CXX_FLAGS:' "$build/CMakeCache.txt" || true))"
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
"$out/compare_fastnoiselite" "$rounds"
