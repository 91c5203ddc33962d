#!/usr/bin/python3
"""VTK's unstructured-grid volume mappers on the mesh, orbit, image size and transfer function
of a `cellfx bench render --json` run, timed the same way, printed beside cellfx's renderers.
`compare_vtk.py --summary DIR...` prints the ratios of several compare_vtk.sh runs as one table.

Run by scripts/compare_vtk.sh (which makes the JSON, the mesh file and the images it reads), under
xvfb-run (VTK on Debian needs an X display even for offscreen windows), with python3-vtk9's VTK 9.1
(/usr/bin/python3) or python3-paraview's VTK 9.2 (pvpython); the version goes into the JSON and
the tables.

Renderers: vtkProjectedTetrahedraMapper (PT: Shirley-Tuchman projection, Wylie et al.'s GPU form,
cells sorted by centroid depth), vtkUnstructuredGridVolumeZSweepMapper (ZSweep, CPU) and
vtkUnstructuredGridVolumeRayCastMapper (Bunyk's ray caster, CPU, all threads). The two CPU ones
integrate with vtkUnstructuredGridPreIntegration, VTK's default for point scalars. All three get
the mesh cut into tetrahedra by vtkDataSetTriangleFilter (as ParaView does before every
unstructured volume mapper; PT and Bunyk accept nothing else); cells per second are counted
against the mesh's own cells, the figure cellfx reports.

Transfer function (docs/performance.md, "Against VTK"): cellfx's point [s, r, g, b, sigma] emits
colour*sigma and absorbs sigma per unit length. VTK's mappers read the scalar opacity o(s) as an
attenuation o/u per unit length, u the ScalarOpacityUnitDistance (PT: alpha = 1 - exp(-o*d/u) over
a tetrahedron's thickness d, vtkglProjectedTetrahedraFS.glsl; ZSweep and Bunyk: attenuation
o/u in vtkUnstructuredGridPartialPreIntegration), with colour c emitted in proportion to it. So
the colour is c(s), o(s) = sigma(s)*u, and u = 1/max(sigma) keeps o in [0, 1] for PT, which stores
it in 8 bits.

Memory: per mapper, the bytes it holds per mesh cell: what the process's heap holds in use
(glibc's mallinfo2: arena and mmap'd blocks in use) after the warm-up frame less before it, so the
mapper's own arrays and, on Mesa's llvmpipe (where GL buffers are the driver's heap), its GL
buffers; the growth of resident memory over the same frame beside it. What does not grow with the
mesh (the shaders llvmpipe compiles, the GL's first-use state) is paid before, by a mapper of the
same class drawing the mesh's first tetrahedron alone in the same window. On a GPU the GL buffers sit
in the GPU's memory and only the first figure's CPU part shows. The mesh cut into tetrahedra (the
mappers' input, which ParaView keeps too) is reported apart (vtkDataObject::GetActualMemorySize).
cellfx's bytes per cell are its GL buffers (bench render's memory table).

Timing: per mapper one warm-up frame of view 0 (building the mapper's structures), then one frame
per view: vtkRenderWindow.Render() and WaitForCompletion() (glFinish), wall time, median. With
--seconds S a mapper stops after the first view that ends past S seconds of timed frames (ZSweep
takes minutes per frame on a million tetrahedra); the table says over how many views it ran.
"""
import argparse
import ctypes
import json
import math
import os
import statistics
import sys
import time

import vtk
from vtk.util import numpy_support


def log(text):
    print(text, flush=True)


class _Mallinfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks",
                 "keepcost")]


def heap_in_use():
    """Bytes the process's glibc heap holds in use (allocated chunks plus mmap'd blocks), or None."""
    try:
        mallinfo2 = ctypes.CDLL(None).mallinfo2
    except (OSError, AttributeError):
        return None
    mallinfo2.restype = _Mallinfo2
    info = mallinfo2()
    return info.uordblks + info.hblkhd


def resident():
    """The process's resident memory in bytes (/proc/self/statm)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def transfer_function(points):
    """cellfx's points (field units) -> VTK colour and opacity functions, and the unit distance."""
    sigma_max = max(p[4] for p in points)
    unit = 1.0 / sigma_max if sigma_max > 0 else 1.0
    color = vtk.vtkColorTransferFunction()
    color.SetColorSpaceToRGB()
    opacity = vtk.vtkPiecewiseFunction()
    span = max(points[-1][0] - points[0][0], abs(points[0][0]), 1e-30)
    last_s = None
    clamped = False
    for s, r, g, b, sigma in points:
        # A repeated s is a step in cellfx; VTK keeps one point per s, so the step's upper side
        # moves up by a millionth of the range.
        if last_s is not None and s <= last_s:
            s = last_s + 1e-6 * span
        last_s = s
        rgb = [min(max(c, 0.0), 1.0) for c in (r, g, b)]
        clamped = clamped or rgb != [r, g, b]
        color.AddRGBPoint(s, *rgb)
        opacity.AddPoint(s, sigma * unit)
    if clamped:
        log("  note: colours above 1 clamped to 1 (PT stores colour in 8 bits)")
    return color, opacity, unit


def read_mesh(path, field):
    reader = vtk.vtkUnstructuredGridReader()
    reader.SetFileName(path)
    reader.ReadAllScalarsOn()
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfCells() == 0:
        sys.exit(f"compare_vtk.py: {path}: VTK read no cells")
    if grid.GetPointData().GetArray(field) is None:
        sys.exit(f"compare_vtk.py: {path}: no point field '{field}'")
    grid.GetPointData().SetActiveScalars(field)
    if all(grid.GetCellType(c) == vtk.VTK_TETRA for c in range(grid.GetNumberOfCells())):
        return grid
    tets = vtk.vtkDataSetTriangleFilter()
    tets.SetInputData(grid)
    tets.TetrahedraOnlyOn()
    tets.Update()
    out = tets.GetOutput()
    out.GetPointData().SetActiveScalars(field)
    return out


def make_mapper(name, grid):
    if name == "vtk-pt":
        mapper = vtk.vtkProjectedTetrahedraMapper()
    elif name == "vtk-zsweep":
        mapper = vtk.vtkUnstructuredGridVolumeZSweepMapper()
        mapper.AutoAdjustSampleDistancesOff()  # one ray per pixel, whatever a frame costs
        mapper.SetImageSampleDistance(1.0)
    else:
        mapper = vtk.vtkUnstructuredGridVolumeRayCastMapper()
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetImageSampleDistance(1.0)
    mapper.SetInputData(grid)
    mapper.SetScalarModeToUsePointData()
    return mapper


def set_camera(renderer, view):
    cam = renderer.GetActiveCamera()
    cam.SetPosition(*view["eye"])
    cam.SetFocalPoint(*view["target"])
    cam.SetViewUp(*view["up"])
    cam.SetViewAngle(view["fov_y_degrees"])
    cam.SetClippingRange(view["near"], view["far"])


def png_pixels(path):
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    array = numpy_support.vtk_to_numpy(image.GetPointData().GetScalars())
    return array.reshape(h, w, -1)[:, :, :3].astype("float64") / 255.0


def difference(a, b):
    """Mean |a - b| over the pixels either covers, in % of b's peak (RGB over black)."""
    covered = (a.max(axis=2) > 0) | (b.max(axis=2) > 0)
    peak = b.max()
    if peak <= 0 or not covered.any():
        return float("nan")
    return 100.0 * abs(a - b)[covered].mean() / peak


def write_markdown(path, run, results, pt, zs, vtk_note):
    """One row per renderer: the figures of both JSONs, ratios of cells/s against PT and ZSweep."""
    mesh = run["mesh"]
    types = ", ".join(f"{n:,} {t}" for t, n in mesh["cell_types"].items())
    lines = [f"{' + '.join(os.path.basename(f) for f in mesh['files'])}, field {mesh['field']}: {types}; "
             f"{run['image']['width']}x{run['image']['height']}, {len(run['views'])} views; {vtk_note}",
             "",
             "| renderer | ms/frame | cells/s | × VTK PT | × ZSweep | CPU ms | GPU ms | bytes/cell | check (worst mean, % of peak) | views |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |"]
    def ratio(cps, ref):
        return f"{cps / ref:.2f}" if ref else "—"
    def num(x, fmt="{:.0f}"):
        return "—" if x is None else fmt.format(x)
    for r in run["renderers"]:
        check = r.get("check")
        verdict = "reference" if check is None else \
            ("ok " if check["passed"] else "FAIL ") + f"{max(f['mean_percent'] for f in check['frames']):.3f}"
        lines.append(f"| {r['name']} | {r['median_ms']:.0f} | {r['cells_per_second']:.3g} | "
                     f"{ratio(r['cells_per_second'], pt)} | {ratio(r['cells_per_second'], zs)} | {num(r['cpu_ms'])} | "
                     f"{num(r['gpu_ms'])} | {r['bytes_per_cell']:.0f} | {verdict} | {len(r['ms'])} |")
    for r in results:
        lines.append(f"| {r['name']} | {r['median_ms']:.0f} | {r['cells_per_second']:.3g} | "
                     f"{ratio(r['cells_per_second'], pt)} | {ratio(r['cells_per_second'], zs)} | — | — | "
                     f"{num(r['bytes_per_cell'])} | "
                     f"{r['mean_difference_percent_vs_scanline']:.2f}% vs scan-line, view 0 | {len(r['ms'])} |")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def summary(directories):
    """The issue's ratios across meshes: cells/s of each cellfx path over VTK PT's (scan-line also
    over ZSweep's), from the cellfx.json and vtk.json that compare_vtk.sh left in each directory."""
    paths = ["absorption-exact (xmpvo)", "pcp-exact", "absorption (xmpvo)", "mip", "pcp"]
    print("| mesh | cells | " + " | ".join(f"{p} × PT" for p in paths) +
          " | scan-line × PT | scan-line × ZSweep | xmpvo / centroid, absorption-exact frame |")
    print("| --- | ---: |" + " ---: |" * (len(paths) + 3))
    for d in directories:
        with open(os.path.join(d, "cellfx.json")) as f:
            run = json.load(f)
        with open(os.path.join(d, "vtk.json")) as f:
            vtk_run = json.load(f)
        cps = {r["name"]: r["cells_per_second"] for r in run["renderers"] + vtk_run["renderers"]}
        ms = {r["name"]: r["median_ms"] for r in run["renderers"]}
        pt, zs = cps.get("vtk-pt"), cps.get("vtk-zsweep")
        def ratio(name, ref):
            return f"{cps[name] / ref:.2f}" if name in cps and ref else "—"
        exact = ms.get("absorption-exact (xmpvo)"), ms.get("absorption-exact (centroid)")
        sorts = f"{exact[0] / exact[1]:.2f}" if all(exact) else "—"
        mesh = run["mesh"]
        types = ", ".join(f"{n:,} {t}" for t, n in mesh["cell_types"].items())
        print(f"| {os.path.basename(os.path.normpath(d))} | {types} | " + " | ".join(ratio(p, pt) for p in paths) +
              f" | {ratio('scanline', pt)} | {ratio('scanline', zs)} | {sorts} |")
    return 0


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--summary":
        return summary(sys.argv[2:])
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json", required=True, help="cellfx bench render --json output")
    parser.add_argument("--mesh", required=True, help="the mesh as VTK legacy (cellfx convert)")
    parser.add_argument("--images", required=True, help="cellfx bench render --images directory; VTK's go there too")
    parser.add_argument("--renderers", default="vtk-pt,vtk-zsweep,vtk-bunyk")
    parser.add_argument("--out-json", help="write VTK's figures here")
    parser.add_argument("--markdown", help="write the side-by-side table here as Markdown")
    parser.add_argument("--vtk-from", default="", help="where this VTK comes from, for the record (compare_vtk.sh)")
    parser.add_argument("--seconds", type=float, default=0.0,
                        help="per mapper, stop timing views once this many seconds are spent (0: all views)")
    args = parser.parse_args()

    with open(args.json) as f:
        run = json.load(f)
    cells = run["mesh"]["cells"]
    width, height = run["image"]["width"], run["image"]["height"]
    views = run["views"]

    grid = read_mesh(args.mesh, run["mesh"]["field"])
    color, opacity, unit = transfer_function(run["transfer_function"]["points"])
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    version = vtk.vtkVersion.GetVTKVersion()
    input_bytes = 1024 * grid.GetActualMemorySize()
    vtk_note = f"VTK {version}" + (f" from {args.vtk_from}" if args.vtk_from else "") + \
        f", its input (the mesh in tetrahedra) {input_bytes / cells:.0f} B/cell"
    log(f"vtk {version}{' from ' + args.vtk_from if args.vtk_from else ''}, python {sys.version.split()[0]}: "
        f"{grid.GetNumberOfCells()} tetrahedra for the mesh's {cells} cells ({input_bytes / cells:.0f} B/cell); "
        f"ScalarOpacityUnitDistance {unit:.6g}")

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    window.SetMultiSamples(0)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0.0, 0.0, 0.0)
    window.AddRenderer(renderer)
    window.Render()
    caps = [line.split(":", 1)[1].strip() for line in window.ReportCapabilities().splitlines()
            if line.startswith("OpenGL renderer string") or line.startswith("OpenGL version string")]
    log("  gl: " + ", ".join(caps))

    reference = os.path.join(args.images, "scanline.png")
    results = []
    for name in args.renderers.split(","):
        mapper = make_mapper(name, grid)
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        renderer.AddVolume(volume)

        def frame(view):
            set_camera(renderer, view)
            start = time.perf_counter()
            window.Render()
            window.WaitForCompletion()
            return 1e3 * (time.perf_counter() - start)

        # The fixed costs first (Memory, above): the first tetrahedron alone, through the same class.
        renderer.RemoveVolume(volume)
        one = vtk.vtkUnstructuredGrid()
        one.Allocate(1)
        ids = vtk.vtkIdList()
        grid.GetCellPoints(0, ids)
        one.SetPoints(grid.GetPoints())
        one.InsertNextCell(grid.GetCellType(0), ids)
        one.GetPointData().SetScalars(grid.GetPointData().GetScalars())
        small = vtk.vtkVolume()
        small.SetMapper(make_mapper(name, one))
        small.SetProperty(prop)
        renderer.AddVolume(small)
        frame(views[0])
        renderer.RemoveVolume(small)
        renderer.AddVolume(volume)

        heap_before, resident_before = heap_in_use(), resident()
        first = frame(views[0])
        heap_after, resident_after = heap_in_use(), resident()
        held = None if heap_before is None else (heap_after - heap_before) / cells
        grown = (resident_after - resident_before) / cells
        times = []
        for v in views:
            times.append(frame(v))
            if args.seconds > 0 and sum(times) > 1e3 * args.seconds:
                break
        frame(views[0])
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        png = os.path.join(args.images, name + ".png")
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(png)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
        renderer.RemoveVolume(volume)

        ms = statistics.median(times)
        diff = difference(png_pixels(png), png_pixels(reference)) if os.path.exists(reference) else float("nan")
        results.append({"name": name, "ms": times, "median_ms": ms, "cells_per_second": cells / (ms * 1e-3),
                        "first_frame_ms": first, "mean_difference_percent_vs_scanline": diff,
                        "bytes_per_cell": held, "resident_growth_bytes_per_cell": grown})
        log(f"  {name:<12} {ms:10.2f} ms/frame  {cells / (ms * 1e-3):12.4g} cells/s  first {first:.0f} ms  "
            f"{len(times)} of {len(views)} views; view 0 vs cellfx scan-line: mean |diff| {diff:.2f}% of peak; "
            f"holds {'?' if held is None else f'{held:.0f}'} B/cell (heap after its first frame), "
            f"resident +{grown:.0f} B/cell")

    if args.out_json:
        with open(args.out_json, "w") as f:
            json.dump({"vtk": version, "vtk_from": args.vtk_from, "python": sys.version.split()[0],
                       "input_bytes_per_cell": input_bytes / cells, "unit_distance": unit, "renderers": results},
                      f, indent=2)

    # Everything side by side: cellfx's renderers, then VTK's, with ratios of cells/s.
    by_name = {r["name"]: r for r in results}
    rows = [(r["name"], r["median_ms"], r["cells_per_second"], len(r["ms"]), r["bytes_per_cell"]) for r in run["renderers"]]
    rows += [(r["name"], r["median_ms"], r["cells_per_second"], len(r["ms"]), r["bytes_per_cell"]) for r in results]
    pt = by_name.get("vtk-pt", {}).get("cells_per_second")
    zs = by_name.get("vtk-zsweep", {}).get("cells_per_second")
    print()
    print(f"{run['mesh']['files'][0]}: {cells} cells {run['mesh']['cell_types']}, {width}x{height}, "
          f"{len(views)} views; cells/s against the mesh's own cells; {vtk_note}")
    print(f"  {'renderer':<30} {'ms/frame':>10} {'cells/s':>12} {'x VTK PT':>9} {'x ZSweep':>9} {'views':>6} {'B/cell':>7}")
    for name, ms, cps, timed, per_cell in rows:
        ratio = lambda ref: f"{cps / ref:9.2f}" if ref else f"{'-':>9}"
        held = f"{per_cell:7.0f}" if per_cell is not None else f"{'-':>7}"
        print(f"  {name:<30} {ms:10.2f} {cps:12.4g} {ratio(pt)} {ratio(zs)} {timed:6d} {held}")
    print("  B/cell: cellfx's GL buffers (bench render); VTK's, its heap's growth over the mapper's first frame")
    if args.markdown:
        write_markdown(args.markdown, run, results, pt, zs, vtk_note)
    failed = [r["name"] for r in run["renderers"] if not r.get("check", {}).get("passed", True)]
    if failed:
        print("  cellfx frames outside their tolerance: " + ", ".join(failed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
