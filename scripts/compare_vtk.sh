#!/usr/bin/env bash
# cellfx beside VTK's unstructured-grid volume mappers (projected tetrahedra, ZSweep, Bunyk
# ray casting) on one mesh, in one run: `cellfx bench render` first (every path, checked against
# the scan-line renderer, --json), then the same mesh, orbit, image size and transfer function in
# VTK (scripts/compare_vtk.py under xvfb-run), then one table of cells/s and ratios.
#   bash scripts/compare_vtk.sh FILE [Q_FILE] [cellfx bench render options]
#   e.g. bash scripts/compare_vtk.sh ../shared/data/spx/spx.inp --sort xmpvo,centroid
# VTK: python3-vtk9's (VTK 9.1, /usr/bin/python3) or, on a machine with python3-paraview instead
# (the two conflict), ParaView's pvpython (VTK 9.2); CELLFX_VTK_PYTHON=CMD picks another. Installs
# what is missing (scripts/setup.sh vtk: python3-vtk9 only without python3-paraview; numpy, xvfb,
# xauth). Says which VTK it ran, and the JSON and the table record it. Writes the JSON, the
# mesh as VTK (cellfx convert) and view 0 of every renderer as PNG into
# $CELLFX_COMPARE_OUT (default out/compare_vtk/<mesh name>). CELLFX_VTK_SECONDS=S stops each VTK
# mapper's timing after the view that passes S seconds (ZSweep takes minutes per frame on a
# million tetrahedra). Exit status: cellfx's (1 if a frame failed its check). Never part of the
# test suite: docs/performance.md, "Against VTK".
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -ge 1 ] || { sed -n '2,16p' "$0"; exit 2; }

files=("$1"); shift
if [ $# -ge 1 ] && [ "${1#--}" = "$1" ]; then files+=("$1"); shift; fi

bash "$root/scripts/setup.sh" vtk
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
if [ -n "${CELLFX_VTK_PYTHON:-}" ]; then
  vtk_python="$CELLFX_VTK_PYTHON" vtk_from="CELLFX_VTK_PYTHON ($CELLFX_VTK_PYTHON)"
elif installed python3-vtk9; then
  vtk_python=/usr/bin/python3 vtk_from="python3-vtk9 (/usr/bin/python3)"
elif installed python3-paraview && command -v pvpython >/dev/null; then
  vtk_python="$(command -v pvpython)" vtk_from="python3-paraview (pvpython)"
else
  echo "compare_vtk.sh: no VTK with Python: install python3-vtk9 or python3-paraview (scripts/setup.sh vtk)" >&2
  exit 1
fi
echo "compare_vtk.sh: VTK from $vtk_from"
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
xvfb-run -a -s "-screen 0 1280x1024x24" $vtk_python "$root/scripts/compare_vtk.py" \
  --json "$out/cellfx.json" --mesh "$out/mesh.vtk" --images "$out/images" --out-json "$out/vtk.json" \
  --markdown "$out/table.md" --vtk-from "$vtk_from" \
  --seconds "${CELLFX_VTK_SECONDS:-0}"
exit "$status"
