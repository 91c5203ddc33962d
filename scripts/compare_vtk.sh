#!/usr/bin/env bash
# cellfx beside VTK 9.1's unstructured-grid volume mappers (projected tetrahedra, ZSweep, Bunyk
# ray casting) on one mesh, in one run: `cellfx bench render` first (every path, checked against
# the scan-line renderer, --json), then the same mesh, orbit, image size and transfer function in
# VTK (scripts/compare_vtk.py under xvfb-run), then one table of cells/s and ratios.
#   bash scripts/compare_vtk.sh FILE [Q_FILE] [cellfx bench render options]
#   e.g. bash scripts/compare_vtk.sh ../shared/data/spx/spx.inp --sort xmpvo,centroid
# Installs python3-vtk9, xvfb and xauth if missing (scripts/setup.sh vtk). Writes the JSON, the
# mesh as VTK (cellfx convert) and view 0 of every renderer as PNG into
# $CELLFX_COMPARE_OUT (default out/compare_vtk/<mesh name>). CELLFX_VTK_SECONDS=S stops each VTK
# mapper's timing after the view that passes S seconds (ZSweep takes minutes per frame on a
# million tetrahedra). Exit status: cellfx's (1 if a frame failed its check). Never part of the
# test suite: docs/performance.md, "Against VTK".
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -ge 1 ] || { sed -n '2,14p' "$0"; exit 2; }

files=("$1"); shift
if [ $# -ge 1 ] && [ "${1#--}" = "$1" ]; then files+=("$1"); shift; fi

bash "$root/scripts/setup.sh" vtk
cellfx="${CELLFX:-$root/build/samples/cellfx}"
if [ ! -x "$cellfx" ]; then
  cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$root/build" --target cellfx_cli
fi

name="$(basename "${files[0]}")"
out="${CELLFX_COMPARE_OUT:-$root/out/compare_vtk/${name%.*}}"
mkdir -p "$out/images"

status=0
"$cellfx" bench render "${files[@]}" "$@" --json "$out/cellfx.json" --images "$out/images" || status=$?
[ -s "$out/cellfx.json" ] || exit "${status:-1}"
field="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["mesh"]["field"])' "$out/cellfx.json")"
"$cellfx" convert "${files[@]}" --scalar "$field" --out "$out/mesh.vtk"
xvfb-run -a -s "-screen 0 1280x1024x24" /usr/bin/python3 "$root/scripts/compare_vtk.py" \
  --json "$out/cellfx.json" --mesh "$out/mesh.vtk" --images "$out/images" --out-json "$out/vtk.json" \
  --markdown "$out/table.md" \
  --seconds "${CELLFX_VTK_SECONDS:-0}"
exit "$status"
