#!/usr/bin/env bash
# Installs the Debian packages cellfx builds and runs with. Idempotent: quiet when all are
# present. Run as root on Debian 12 (or with sudo available).
#   scripts/setup.sh fuzz       also installs clang and libFuzzer for scripts/fuzz.sh
#   scripts/setup.sh vtk        also installs VTK's Python bindings for scripts/compare_vtk.sh:
#                               python3-vtk9 (VTK 9.1), unless python3-paraview is installed,
#                               whose pvpython brings VTK 9.2 (the two conflict: both ship
#                               vtkmodules); numpy, xvfb and xauth either way
#   scripts/setup.sh paraview   also installs ParaView 5.11 with its headers, MPI and Xvfb for
#                               the ParaView plugin (scripts/paraview.sh, docs/paraview.md;
#                               conflicts with python3-vtk9; with it the vtk group uses pvpython)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri   # headless OpenGL 4.5 (EGL, Mesa llvmpipe)
  libepoxy-dev libglfw3-dev libglm-dev libstb-dev     # GL loader, windows, maths, images
  nlohmann-json3-dev catch2 libbenchmark-dev          # JSON, tests, micro-benchmarks
  libimgui-dev                                        # the samples' tuning panel (Dear ImGui; samples only)
  xvfb xauth                                          # a real GLFW window in tests, without a display
  gnuplot-nox                                         # cellfx bench accuracy: the time-against-error plot
)

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

# Optional groups, only when named on the command line.
for group in "$@"; do
  case "$group" in
    fuzz) packages+=(clang-14 libclang-rt-14-dev llvm-14) ;; # libFuzzer, sanitizer runtimes, llvm-symbolizer
    vtk) # the VTK comparison (VTK needs an X display even offscreen): ParaView's VTK if it is there
      installed python3-paraview || [[ " $* " == *" paraview "* ]] || packages+=(python3-vtk9)
      packages+=(python3-numpy xvfb xauth) ;;
    # paraview-dev's CMake config needs python3-paraview, the MPI headers, GLEW and FreeType's
    # headers without declaring them; python3-paraview conflicts with python3-vtk9 (both ship
    # vtkmodules), so this group is not for a machine that has python3-vtk9.
    paraview) packages+=(paraview paraview-dev python3-paraview mpi-default-dev openmpi-bin libglew-dev libfreetype-dev) ;;
    *) echo "setup.sh: unknown package group \"$group\" (known: fuzz, vtk, paraview)" >&2; exit 2 ;;
  esac
done

# python3-paraview and python3-vtk9 both ship vtkmodules: stop rather than let apt remove one
# (the vtk group takes python3-paraview's VTK where it is installed, above).
for group in "$@"; do
  if [ "$group" = paraview ] && installed python3-vtk9; then
    echo "setup.sh: the paraview group needs python3-paraview, which conflicts with the installed python3-vtk9" \
      "(the vtk group); use a machine or container without it" >&2
    exit 1
  fi
done

missing=()
for p in "${packages[@]}"; do
  installed "$p" || missing+=("$p")
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
