#!/usr/bin/env bash
# Installs the Debian packages cellfx builds and runs with. Idempotent: quiet when all are
# present. Run as root on Debian 12 (or with sudo available).
#   scripts/setup.sh fuzz   also installs clang and libFuzzer for scripts/fuzz.sh
#   scripts/setup.sh vtk    also installs VTK 9.1's Python bindings for scripts/compare_vtk.sh
#                           (conflicts with python3-paraview: both ship vtkmodules)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri   # headless OpenGL 4.5 (EGL, Mesa llvmpipe)
  libepoxy-dev libglfw3-dev libglm-dev libstb-dev     # GL loader, windows, maths, images
  nlohmann-json3-dev catch2 libbenchmark-dev          # JSON, tests, micro-benchmarks
  xvfb xauth                                          # a real GLFW window in tests, without a display
  gnuplot-nox                                         # cellfx bench accuracy: the time-against-error plot
)

# Optional groups, only when named on the command line.
for group in "$@"; do
  case "$group" in
    fuzz) packages+=(clang-14 libclang-rt-14-dev llvm-14) ;; # libFuzzer, sanitizer runtimes, llvm-symbolizer
    vtk) packages+=(python3-vtk9 python3-numpy xvfb xauth) ;; # the VTK comparison (VTK 9.1 needs an X display)
    *) echo "setup.sh: unknown package group \"$group\" (known: fuzz, vtk)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup.sh: missing packages (${missing[*]}) and not root" >&2; exit 1; }
  sudo="sudo"
fi
echo "setup.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
