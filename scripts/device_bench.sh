#!/usr/bin/env bash
# The GPU figures the open performance issues ask for, in one short run on a machine with an
# NVIDIA GPU (docs/performance.md, "On a GPU"): the game-frame table (`bench effects
# --only-cpu`, the same table as on llvmpipe: cellfx's CPU, the driver's, GL state) and the
# million-tetrahedron duct at 1920×1080 (`bench render`, every path checked against the
# scan-line reference). Run from the checkout's root with .device/ from scripts/device_pack.sh:
#   bash scripts/device_bench.sh [OUT_DIR]     # OUT_DIR: $OUT, else out/device
# Writes effects.json, duct.json and log.txt into OUT_DIR. Takes 5–8 minutes on one GPU; each
# step is cut off after CELLFX_STEP_SECONDS (default 240) so the figures already taken come back.
# On a machine with cellfx's packages installed it runs the same with whatever GL it finds.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
out="${1:-${OUT:-$root/out/device}}"
mkdir -p "$out"
step_seconds="${CELLFX_STEP_SECONDS:-240}"
exec > >(tee "$out/log.txt") 2>&1

[ -x .device/cellfx ] || { echo "device_bench.sh: no .device/cellfx (run scripts/device_pack.sh and carry .device)"; exit 1; }
# GLVND's libraries where the image has none (unpacking over an installed GL would replace it).
if ! ldconfig -p | grep -q 'libEGL.so.1 '; then
  for f in .device/debs/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
nvidia_json=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$nvidia_json" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia_json"
export LD_LIBRARY_PATH="$root/.device/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cellfx="$root/.device/cellfx"

command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
nproc
status=0
run_step() { # name, then the command
  local name="$1"; shift
  echo "== $name: $*"
  local start=$SECONDS
  timeout "$step_seconds" "$@" || { local rc=$?; echo "== $name: exit status $rc"; status=1; }
  echo "== $name: $((SECONDS - start)) s"
}
run_step "game frame" "$cellfx" bench effects --only-cpu --frames 60 --json "$out/effects.json"
run_step "duct mesh" "$cellfx" convert --synthetic duct --cells 1000000 --out /tmp/cellfx_duct_1m.vtk
run_step "duct at 1920x1080" "$cellfx" bench render /tmp/cellfx_duct_1m.vtk --size 1920x1080 --views 4 \
  --sort xmpvo --json "$out/duct.json"
exit "$status"
