"""The plugin under MPI: two pvbatch ranks, the data redistributed by ParaView on a k-d tree and
the ranks' images composited by IceT in visibility order.

    xvfb-run -a -s "-screen 0 1280x1024x24" mpirun --allow-run-as-root -np 2 \\
        -x LD_PRELOAD=build-paraview/lib/libcellfx_expat_fix.so pvbatch paraview/tests/test_two_ranks.py

(scripts/paraview.sh --test runs it so.) Needs test_one_rank.py's images in pvcellfx.OUT.
Checks, for the LOx post and the seam mesh (large cells across the cut), absorption-exact,
absorption, scanline (each rank's CPU image composited over the framebuffer like the GL paths')
and auto (checked with the tolerance of the path it picked on rank 0; each rank measures and
picks for its own cells):
  - rank 0 drew part of the cells, not all (the mesh is split across the ranks);
  - the composite equals cellfx's scan-line reference within the path's own tolerance plus the
    8-bit compositing margin (pvcellfx.mpi_tolerance): the bound the one-rank image meets, so a
    seam along the cut would fail it;
  - and, for the GL paths, equals the one-rank image within twice the path's per-pixel tolerance
    plus that margin.
Prints, for comparison, the seam mesh with the cells on the ranks' boundary given whole to one
rank (CellfxSplitBoundaryCells off, as ParaView's own volume representation does).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvcellfx as pc  # noqa: E402
from paraview import simple  # noqa: E402

W, H = pc.IMAGE_SIZE


def cells_drawn(display):
    display.UpdatePropertyInformation()
    return display.GetProperty("CellfxLastCellCount").GetData()


def main():
    ranks = simple.servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    print("ranks:", ranks)
    if ranks != 2:
        print("FAIL  expected 2 ranks (mpirun -np 2 pvbatch ...)")
        sys.exit(1)
    pc.load_plugin()
    view = pc.make_view(W, H)

    cases = [("lox", simple.LegacyVTKReader(FileNames=[pc.MESH]), pc.CAMERA, pc.FIELD, pc.TF),
             ("seam", simple.LegacyVTKReader(FileNames=[pc.out("seam_mesh.vtk")]), pc.SEAM_CAMERA, pc.SEAM_FIELD,
              pc.SEAM_TF)]
    for name, reader, camera, field, tf in cases:
        reader.UpdatePipeline()
        cells = reader.GetDataInformation().GetNumberOfCells()
        display = pc.show_volume(reader, view, camera=camera, field=field, tf=tf)
        one_rank = pc.read_png(pc.out("one_rank_%s_absorption-exact.png" % name))
        reference = pc.read_pfm(pc.out("scanline_%s_absorption.pfm" % name))
        for path in ("absorption-exact", "absorption", "scanline", "auto"):
            display.CellfxRenderPath = path
            image = pc.screenshot(view, pc.out("two_ranks_%s_%s.png" % (name, path)), W, H)
            drawn = cells_drawn(display)
            pc.check((0 < drawn < cells, "%s %s: rank 0 drew %d cells (pieces) of the %d" % (name, path, drawn, cells)))
            checked = pc.checked_path(path, display)
            if path in ("absorption-exact", "absorption"):
                expected = one_rank if path == "absorption-exact" else pc.read_png(pc.out("one_rank_%s_absorption.png" % name))
                pc.check(pc.compare("two ranks %s %s vs one rank" % (name, path), image, expected,
                                    pc.mpi_tolerance(path, True)))
            pc.check(pc.compare("two ranks %s %s vs scan-line" % (name, path), image, reference,
                                pc.mpi_tolerance(checked, False)))
        if name == "seam":
            # For comparison (not a check): boundary cells given whole to one rank, as ParaView's
            # own volume representation does.
            display.CellfxRenderPath = "absorption-exact"
            display.CellfxSplitBoundaryCells = 0
            image = pc.screenshot(view, pc.out("two_ranks_seam_unsplit.png"), W, H)
            print("info  " + pc.compare("two ranks seam, boundary cells unsplit, vs scan-line", image, reference,
                                        pc.mpi_tolerance("absorption-exact", False), write_images=False)[1])
            display.CellfxSplitBoundaryCells = 1
        simple.Hide(reader, view)

    if pc.failures:
        print("%d check(s) failed" % len(pc.failures))
        sys.exit(1)
    print("all checks passed")


main()
