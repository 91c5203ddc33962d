"""The plugin's demo (scripts/paraview.sh runs it on one and on two MPI ranks).

    pvbatch paraview/demo.py [FRAMES]

Renders two shipped meshes with the "cellfx Volume" representation (absorption-exact and
absorption) and with ParaView's own "Volume" representation (projected tetrahedra, which cuts
every cell into tetrahedra first), one transfer function for all, and writes to out/paraview/:
  <mesh>_<renderer>_<N>rank.png     each picture, and <mesh>_side_by_side_<N>rank.png
  timings_<N>rank.json              the first frame and the median of FRAMES new views
  timings.md                        the table of every run so far (docs/paraview.md quotes it)
Each timed frame is a new view (the camera orbits 5 degrees), waited for to the end (the
composited image on two ranks, glFinish on one): wall milliseconds per frame.
"""
import glob
import json
import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "tests"))
import numpy as np  # noqa: E402
import pvcellfx as pc  # noqa: E402
from paraview import simple  # noqa: E402

OUT = os.path.join(pc.ROOT, "out", "paraview")
W, H = 480, 360
FRAMES = int(sys.argv[1]) if len(sys.argv) > 1 else 8

# The NASA blunt fin (PLOT3D, 37,479 hexahedra, a structured grid), density.
FIN_TF = pc.TransferFunction([(0.19, 0.23, 0.30, 0.75), (1.2, 0.55, 0.69, 1.00), (2.4, 0.87, 0.87, 0.87),
                              (3.6, 0.96, 0.60, 0.48), (4.98, 0.71, 0.02, 0.15)],
                             [(0.19, 0.25), (1.2, 0.08), (2.4, 0.02), (3.6, 0.3), (4.98, 0.9)], 1.0)
FIN_CAMERA = {"position": (3.5, -16.0, 16.0), "focal_point": (3.3, 4.2, 2.8), "view_up": (0.0, 0.0, 1.0),
              "view_angle": 40.0}

MESHES = {
    "lox_post": ("LOx post, 8,750 tetrahedra", lambda: simple.LegacyVTKReader(FileNames=[pc.MESH]), pc.FIELD, pc.TF,
                 pc.CAMERA),
    "blunt_fin": ("blunt fin, 37,479 hexahedra (structured)",
                  lambda: simple.PLOT3DReader(FileName=os.path.join(pc.ROOT, "content/meshes/blunt_fin/bluntfinxyz.bin"),
                                              QFileName=[os.path.join(pc.ROOT, "content/meshes/blunt_fin/bluntfinq.bin")]),
                  "Density", FIN_TF, FIN_CAMERA),
}
# name: (representation, render path or mapper)
RENDERERS = {
    "cellfx_absorption-exact": ("cellfx Volume", "absorption-exact"),
    "cellfx_absorption": ("cellfx Volume", "absorption"),
    "projected_tetra": ("Volume", "Projected tetra"),
}


def orbit(camera, degrees):
    """The camera turned by `degrees` about the vertical through its focal point."""
    f = np.array(camera["focal_point"])
    p = np.array(camera["position"]) - f
    a = math.radians(degrees)
    p = np.array([p[0] * math.cos(a) - p[1] * math.sin(a), p[0] * math.sin(a) + p[1] * math.cos(a), p[2]])
    return dict(camera, position=tuple(f + p))


def frame_ms(view):
    start = time.perf_counter()
    simple.Render(view)
    view.GetRenderWindow().WaitForCompletion()
    return 1000.0 * (time.perf_counter() - start)


def main():
    ranks = simple.servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    os.makedirs(OUT, exist_ok=True)
    pc.load_plugin()
    view = pc.make_view(W, H)
    timings = {"ranks": ranks, "frames": FRAMES, "size": [W, H], "results": []}
    for mesh, (label, make_reader, field, tf, camera) in MESHES.items():
        reader = make_reader()
        reader.UpdatePipeline()
        cells = reader.GetDataInformation().GetNumberOfCells()
        # ParaView's own volume representation fails on a multiblock of structured grids (the
        # PLOT3D reader's output): it gets the blocks merged into one unstructured grid.
        merged = simple.MergeBlocks(Input=reader)
        pictures = []
        for name, (representation, choice) in RENDERERS.items():
            source = merged if representation == "Volume" else reader
            display = pc.show_volume(source, view, representation=representation,
                                     path=choice if representation == "cellfx Volume" else "absorption-exact",
                                     camera=camera, field=field, tf=tf)
            if representation == "Volume":
                display.SelectMapper = choice
            first = frame_ms(view)
            times = []
            for i in range(FRAMES):
                pc.set_camera(view, orbit(camera, 5.0 * (i + 1)))
                times.append(frame_ms(view))
            pc.set_camera(view, camera)
            path = os.path.join(OUT, "%s_%s_%drank.png" % (mesh, name, ranks))
            pictures.append(pc.screenshot(view, path, W, H))
            result = {"mesh": mesh, "label": label, "cells": cells, "renderer": name, "first_frame_ms": first,
                      "median_ms": statistics.median(times), "min_ms": min(times)}
            timings["results"].append(result)
            print("%-10s %-26s first frame %7.0f ms, then median %7.0f ms (min %7.0f) over %d new views" % (
                mesh, name, first, result["median_ms"], result["min_ms"], FRAMES), flush=True)
            simple.Hide(source, view)
        pc.write_png(np.concatenate(pictures, axis=1), os.path.join(OUT, "%s_side_by_side_%drank.png" % (mesh, ranks)))
    with open(os.path.join(OUT, "timings_%drank.json" % ranks), "w") as f:
        json.dump(timings, f, indent=1)
    write_table()


def write_table():
    runs = {}
    for path in sorted(glob.glob(os.path.join(OUT, "timings_*rank.json"))):
        with open(path) as f:
            run = json.load(f)
        runs[run["ranks"]] = run
    lines = ["| mesh | renderer | " + " | ".join("%d rank%s: first / median ms" % (r, "" if r == 1 else "s")
                                                 for r in sorted(runs)) + " |",
             "| --- | --- |" + " ---: |" * len(runs)]
    keys = [(r["mesh"], r["label"], r["renderer"]) for r in next(iter(runs.values()))["results"]] if runs else []
    for mesh, label, renderer in keys:
        cells = []
        for r in sorted(runs):
            match = [x for x in runs[r]["results"] if x["mesh"] == mesh and x["renderer"] == renderer]
            cells.append("%.0f / %.0f" % (match[0]["first_frame_ms"], match[0]["median_ms"]) if match else "-")
        lines.append("| %s | %s | %s |" % (label, renderer.replace("_", " "), " | ".join(cells)))
    any_run = next(iter(runs.values()), None)
    header = ("Made by `bash scripts/paraview.sh` (paraview/demo.py): %dx%d, %d new views per renderer (5 degrees "
              "apart), wall ms per frame waited to the end.\n\n" % (W, H, any_run["frames"] if any_run else 0))
    with open(os.path.join(OUT, "timings.md"), "w") as f:
        f.write(header + "\n".join(lines) + "\n")


main()
