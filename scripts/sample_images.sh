#!/usr/bin/env bash
# Renders the README's sample pictures (docs/images/sample_<name>.png) with each sample's
# --headless mode: the frame loop its window runs, stats line included. Needs a build
# (scripts/build.sh). Usage: bash scripts/sample_images.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-${CELLFX_BUILD_DIR:-$root/build}}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
# name and scene time of the picture (the third frame, so the stats line has a frame before it)
for spec in fog_valley:0 campfire:3.3 searchlight:3 aurora:0 fem_viewer:0 night_valley:4; do
  name="${spec%%:*}" time="${spec#*:}"
  "$build/samples/$name" --headless --frames 3 --width 480 --height 360 --time "$time" --out "$out/$name" >/dev/null
  cp "$out/$name/frame_0002.png" "$root/docs/images/sample_$name.png"
  echo "wrote docs/images/sample_$name.png"
done
