#!/usr/bin/env bash
# Sets up, builds and runs cellfx on the default content: a summary of the NASA blunt-fin mesh
# and a headless render of it to out/blunt_fin.png, then the fog valley scene to
# out/fog_valley.png (frame statistics printed).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" -DCELLFX_BUILD_TESTS=OFF
cellfx="${CELLFX_BUILD_DIR:-$root/build}/samples/cellfx"
mesh="$root/content/meshes/blunt_fin"
mkdir -p "$root/out"

"$cellfx" info "$mesh/bluntfinxyz.bin" "$mesh/bluntfinq.bin"
echo
"$cellfx" render "$mesh/bluntfinxyz.bin" "$mesh/bluntfinq.bin" --path scanline --scalar density \
  --tf "$root/content/transfer_functions/cool_warm.json" --size 640x400 \
  --camera "eye=3.5,-16,16,target=3.3,4.2,2.8,up=0,0,1,fov=40" --background 0.08,0.08,0.1 \
  --out "$root/out/blunt_fin.png"
echo
"$cellfx" render "$root/content/scenes/fog_valley.json" --out "$root/out/fog_valley.png"
