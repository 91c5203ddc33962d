#!/usr/bin/env bash
# Renders the README's sample pictures (docs/images/sample_<name>.png, sample_panel.png) with each sample's
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
# The tuning panel (README, docs/samples.md): night_valley with the panel, GPU timing on, the
# frame-time graph after 30 frames and the accuracy check of the first frame at full size (the
# run waits for it before its last frame, which shows the result; minutes on llvmpipe).
"$build/samples/night_valley" --headless --frames 30 --width 1024 --height 860 --time 4 --no-overlay --panel --accuracy \
  --set view.gpu_timing=true --save "$out/tuned.json" --out "$out/panel" >/dev/null
cp "$out/panel/frame_0029.png" "$root/docs/images/sample_panel.png"
echo "wrote docs/images/sample_panel.png"
