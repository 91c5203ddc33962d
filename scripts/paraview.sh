#!/usr/bin/env bash
# cellfx inside ParaView (docs/paraview.md). On a fresh Debian 12 machine, as root:
#   bash scripts/paraview.sh          installs ParaView 5.11 (scripts/setup.sh paraview), builds
#                                     the plugin into build-paraview/ and runs the demo: two
#                                     shipped meshes drawn by cellfx and by ParaView's projected
#                                     tetrahedra, on one and on two MPI ranks; pictures and the
#                                     timings table in out/paraview/
#   bash scripts/paraview.sh --test   the same install and build, then the plugin's tests
#                                     (ctest -L paraview: conversions, one rank, two ranks,
#                                     client/server)
# Not for a machine with python3-vtk9: python3-paraview conflicts with it.
#   CELLFX_PARAVIEW_BUILD=DIR   build folder (default build-paraview/)
#   CELLFX_DEMO_FRAMES=N        new views timed per renderer in the demo (default 8)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
export CELLFX_PARAVIEW_BUILD="${CELLFX_PARAVIEW_BUILD:-$root/build-paraview}"
case "${1:-}" in
  "" | --test) ;;
  *) echo "usage: bash scripts/paraview.sh [--test]" >&2; exit 2 ;;
esac

bash "$root/scripts/setup.sh" paraview
cmake -S "$root" -B "$CELLFX_PARAVIEW_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCELLFX_BUILD_PARAVIEW=ON -DCELLFX_BUILD_TESTS=OFF >/dev/null
# The plugin and what its tests and demo run: the cellfx command (the scan-line reference), the
# conversion tests and the expat fix; not the samples' windows.
cmake --build "$CELLFX_PARAVIEW_BUILD" --target CellfxVolume cellfx_cli cellfx_paraview_tests cellfx_expat_fix

if [ "${1:-}" = --test ]; then
  ctest --test-dir "$CELLFX_PARAVIEW_BUILD/paraview" -L paraview --output-on-failure --no-tests=error
  exit
fi

frames="${CELLFX_DEMO_FRAMES:-8}"
echo "paraview.sh: one rank"
bash "$root/paraview/run.sh" demo 1 "$frames"
echo "paraview.sh: two MPI ranks"
bash "$root/paraview/run.sh" demo 2 "$frames"
echo "paraview.sh: pictures and timings in $root/out/paraview/:"
cat "$root/out/paraview/timings.md"
