"""The plugin in one pvbatch process, against cellfx's own scan-line reference.

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch paraview/tests/test_one_rank.py

Checks, each printed with its measured numbers:
  - every render path (absorption-exact, absorption, pcp-exact, mip, scanline, and auto with the
    tolerance of the path it picked, printed with why) on the LOx post against the
    scan-line reference of its optical model, same camera, same transfer function written
    independently in cellfx's JSON (pvcellfx.write_cellfx_transfer_function);
  - the seam mesh (pvcellfx.make_seam_mesh) the same way, for the two-rank test;
  - the volume stops at opaque geometry: the whole mesh in front of an opaque plane through it
    equals the mesh clipped at that plane (ParaView's exact Clip) in front of the same plane;
  - a screenshot twice the view's size, which ParaView renders as 2 x 2 off-axis tiles, equals
    the view rendered at that size in one piece; with auto the tiles are drawn without the
    scan-line renderer (it takes no off-axis view) and meet the exact tolerance;
  - the mesh is converted once: moving the camera and editing the opacity function do not
    convert it again, moving the actor (Position) does, once.
Writes the images the two-rank and client/server tests compare with into pvcellfx.OUT.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvcellfx as pc  # noqa: E402
from paraview import simple  # noqa: E402

W, H = pc.IMAGE_SIZE


def main():
    pc.load_plugin()
    os.makedirs(pc.OUT, exist_ok=True)
    view = pc.make_view(W, H)

    # Every path against its scan-line model; the one-rank images the MPI tests compare with.
    reader = simple.LegacyVTKReader(FileNames=[pc.MESH])
    display = pc.show_volume(reader, view)
    for path in pc.PATHS:
        display.CellfxRenderPath = path
        image = pc.screenshot(view, pc.out("one_rank_lox_%s.png" % path), W, H)
        reference = pc.scanline_reference(pc.out("scanline_lox_%s.pfm" % pc.MODEL[path]), W, H, model=pc.MODEL[path])
        pc.check(pc.compare("one rank %s vs scan-line" % path, image, reference, pc.PATH_TOLERANCE[pc.checked_path(path, display)]))

    # The mesh was converted once for all those frames; a new camera and a new opacity function
    # do not convert it again, a moved actor does.
    display.CellfxRenderPath = "absorption-exact"
    conversions = pc.mesh_conversions(display)
    view.CameraPosition = [5.0, 3.0, 4.0]
    simple.Render(view)
    pc.set_camera(view, pc.CAMERA)
    simple.GetOpacityTransferFunction(pc.FIELD).Points = [0.355, 0.2, 0.5, 0.0, 1.642, 0.6, 0.5, 0.0]
    simple.Render(view)
    after_view_and_function = pc.mesh_conversions(display)
    display.Position = [0.0, 0.0, 0.25]
    simple.Render(view)
    after_move = pc.mesh_conversions(display)
    pc.check((conversions == 1 and after_view_and_function == 1 and after_move == 2,
           "mesh conversions: %d after every path, %d after a new camera and opacity function, %d after moving "
           "the actor (expected 1, 1, 2)" % (conversions, after_view_and_function, after_move)))
    display.Position = [0.0, 0.0, 0.0]
    pc.set_transfer_function()
    simple.Hide(reader, view)

    # The seam mesh, one rank, for the two-rank test's comparison.
    seam_file = pc.make_seam_mesh(pc.out("seam_mesh.vtk"))
    seam = simple.LegacyVTKReader(FileNames=[seam_file])
    seam_display = pc.show_volume(seam, view, camera=pc.SEAM_CAMERA, field=pc.SEAM_FIELD, tf=pc.SEAM_TF)
    reference = pc.scanline_reference(pc.out("scanline_seam_absorption.pfm"), W, H, camera=pc.SEAM_CAMERA,
                                      mesh=seam_file, field=pc.SEAM_FIELD, tf=pc.SEAM_TF)
    for path in ("absorption-exact", "absorption"):
        seam_display.CellfxRenderPath = path
        image = pc.screenshot(view, pc.out("one_rank_seam_%s.png" % path), W, H)
        pc.check(pc.compare("one rank seam mesh %s vs scan-line" % path, image, reference, pc.PATH_TOLERANCE[path]))
    simple.Hide(seam, view)

    # Opaque geometry stops the volume: whole mesh + plane == clipped mesh + plane.
    simple.Show(reader, view)
    pc.set_camera(view, pc.CAMERA)
    plane = pc.show_opaque_plane(view)
    whole = pc.screenshot(view, pc.out("depth_whole_mesh.png"), W, H)
    simple.Hide(reader, view)
    clipped = pc.clip_in_front_of_plane(reader)
    pc.show_volume(clipped, view)
    front = pc.screenshot(view, pc.out("depth_clipped_mesh.png"), W, H)
    pc.check(pc.compare("stopped by an opaque plane vs clipped at it", whole, front, pc.DEPTH_TOLERANCE))
    simple.Hide(clipped, view)
    simple.Hide(plane, view)

    # Tiles: a screenshot 2 x the view's size is rendered as 2 x 2 off-axis tiles.
    simple.Show(reader, view)
    pc.set_camera(view, pc.CAMERA)
    tiled = pc.screenshot(view, pc.out("tiles_2x2.png"), 2 * W, 2 * H)
    view.ViewSize = [2 * W, 2 * H]
    whole = pc.screenshot(view, pc.out("tiles_whole.png"), 2 * W, 2 * H)
    pc.check(pc.compare("2 x 2 tiles vs one piece", tiled, whole, pc.TILE_TOLERANCE))

    # auto with tiles: the scan-line renderer takes no off-axis view, so the tiles are measured
    # and drawn without it (a GL path); the picture still meets the exact paths' tolerance
    # against the scan-line reference at that size.
    display = simple.GetDisplayProperties(reader, view)
    display.CellfxRenderPath = "auto"
    view.ViewSize = [W, H]
    tiled = pc.screenshot(view, pc.out("tiles_2x2_auto.png"), 2 * W, 2 * H)
    picked, reason = pc.chosen_path(display)
    print("info  auto, last tile: " + reason, flush=True)
    pc.check((picked in ("absorption-exact",) and "scanline left out: an off-axis view" in reason,
              "auto on off-axis tiles drew with %s, the scan-line renderer left out" % picked))
    reference = pc.scanline_reference(pc.out("scanline_lox_2x.pfm"), 2 * W, 2 * H)
    pc.check(pc.compare("2 x 2 tiles, auto, vs scan-line", tiled, reference, pc.PATH_TOLERANCE["absorption-exact"]))
    display.CellfxRenderPath = "absorption-exact"

    if pc.failures:
        print("%d check(s) failed" % len(pc.failures))
        sys.exit(1)
    print("all checks passed")


main()
