"""Shared by the plugin's pvbatch / pvpython tests and the demo (docs/paraview.md).

The plugin, a view with a fixed camera on a black background, the LOx post mesh with one
transfer function written twice (in ParaView's terms for the plugin, in cellfx's JSON for the
scan-line reference, derived here independently of the plugin's converter), cellfx's own
scan-line reference through the `cellfx render` command, and image comparison with stated
tolerances.
"""
import json
import os
import subprocess

import numpy as np
from paraview import simple
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.util.numpy_support import numpy_to_vtk

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("CELLFX_PARAVIEW_BUILD", os.path.join(ROOT, "build-paraview"))
PLUGIN = os.path.join(BUILD, "lib", "paraview-5.11", "plugins", "CellfxVolume", "CellfxVolume.so")
CELLFX = os.path.join(BUILD, "samples", "cellfx")
OUT = os.environ.get("CELLFX_PARAVIEW_OUT", os.path.join(BUILD, "paraview-out"))

IMAGE_SIZE = (240, 180)


class TransferFunction:
    """One transfer function in ParaView's terms: RGB colour nodes (s, r, g, b), opacity nodes
    (s, a), both piecewise linear, and the scalar opacity unit distance."""

    def __init__(self, color_nodes, opacity_nodes, unit_distance):
        self.color_nodes, self.opacity_nodes, self.unit_distance = color_nodes, opacity_nodes, unit_distance


# The LOx post (content/meshes/lox_post): 8,750 tetrahedra around a post with a hole, so rays
# cross the mesh, leave it and enter it again (non-convex: xmpvo is the exact sort).
MESH = os.path.join(ROOT, "content", "meshes", "lox_post", "post.vtk")
FIELD = "Pressure"  # 0.355 .. 1.641
# Up to ~6 optical depths across the mesh.
TF = TransferFunction([(0.355, 0.10, 0.25, 0.90), (0.9, 0.15, 0.85, 0.40), (1.2, 1.00, 0.85, 0.10), (1.642, 1.00, 0.10, 0.05)],
                      [(0.355, 0.10), (1.0, 0.35), (1.642, 0.90)], 0.5)
CAMERA = {"position": (4.2, -5.1, 4.4), "focal_point": (0.0, 0.0, 0.45), "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}

# The seam mesh (make_seam_mesh): a Delaunay tetrahedralisation of 48 random points in a
# 3 x 2 x 2 box (no four on a plane, so no flat cells), so that the cut between two ranks
# (ParaView puts it just before a point, at the median along x) runs through large cells; a field rising along x
# through a sharp blue-to-red change and strong extinction, seen from the +x side, so that a
# cell composited in the wrong order across the seam changes the picture.
SEAM_FIELD = "s"
SEAM_TF = TransferFunction([(0.0, 0.1, 0.2, 1.0), (1.4, 0.1, 0.3, 1.0), (1.7, 1.0, 0.15, 0.05), (3.6, 1.0, 0.9, 0.1)],
                           [(0.0, 0.5), (3.6, 0.9)], 0.6)
SEAM_CAMERA = {"position": (7.0, 3.4, 2.9), "focal_point": (1.5, 1.0, 1.0), "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}

PATHS = ["absorption-exact", "absorption", "pcp-exact", "mip", "scanline", "auto"]
# The scan-line model each path is compared with (auto picks among emission-absorption paths).
MODEL = {"absorption-exact": "absorption", "absorption": "absorption", "pcp-exact": "emission", "mip": "max",
         "scanline": "absorption", "auto": "absorption"}


def load_plugin(remote=False):
    """Loads the plugin into this process (and, connected to a server, there too)."""
    if not os.path.exists(PLUGIN):
        raise SystemExit("no plugin at %s: build it first (bash scripts/paraview.sh)" % PLUGIN)
    simple.LoadPlugin(PLUGIN, remote=False, ns=globals())
    if remote:
        simple.LoadPlugin(PLUGIN, remote=True, ns=globals())


def make_view(width, height):
    simple._DisableFirstRenderCameraReset()  # as ParaView's own traces do: keep the camera we set
    view = simple.CreateRenderView()
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    return view


def set_camera(view, camera):
    view.CameraPosition = list(camera["position"])
    view.CameraFocalPoint = list(camera["focal_point"])
    view.CameraViewUp = list(camera["view_up"])
    view.CameraViewAngle = camera["view_angle"]
    view.CameraParallelProjection = 0


def camera_spec(camera):
    """The same camera for `cellfx render --camera` (vertical field of view, as VTK's)."""
    f = lambda v: ",".join("%.17g" % x for x in v)
    return "eye=%s,target=%s,up=%s,fov=%.17g,near=0.01,far=1000" % (
        f(camera["position"]), f(camera["focal_point"]), f(camera["view_up"]), camera["view_angle"])


def set_transfer_function(field=FIELD, tf=TF):
    """ParaView's colour map and opacity function for `field`: RGB, piecewise linear, fixed range."""
    lut = simple.GetColorTransferFunction(field)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.ColorSpace = "RGB"
    lut.RGBPoints = [x for node in tf.color_nodes for x in node]
    pwf = simple.GetOpacityTransferFunction(field)
    pwf.Points = [x for s, a in tf.opacity_nodes for x in (s, a, 0.5, 0.0)]
    return lut, pwf


def show_volume(source, view, representation="cellfx Volume", path="absorption-exact", sort="xmpvo", camera=CAMERA,
                field=FIELD, tf=TF):
    """Shows `source` in `view` (and puts the camera back: a first Show resets it)."""
    display = simple.Show(source, view)
    display.SetRepresentationType(representation)
    simple.ColorBy(display, ("POINTS", field))
    set_transfer_function(field, tf)
    display.ScalarOpacityUnitDistance = tf.unit_distance
    if representation == "cellfx Volume":
        display.CellfxRenderPath = path
        display.CellfxSort = sort
    set_camera(view, camera)
    return display


def write_cellfx_transfer_function(path, tf=TF):
    """The same function as cellfx JSON, derived here and not by the plugin: colour linear
    between the colour nodes, extinction the opacity (linear between its nodes) over the unit
    distance, at every node of either."""
    cs = [n[0] for n in tf.color_nodes]
    points = []
    for s in sorted(set(cs) | set(n[0] for n in tf.opacity_nodes)):
        rgb = [float(np.interp(s, cs, [n[k] for n in tf.color_nodes])) for k in (1, 2, 3)]
        a = float(np.interp(s, [n[0] for n in tf.opacity_nodes], [n[1] for n in tf.opacity_nodes]))
        points.append([s] + rgb + [a / tf.unit_distance])
    with open(path, "w") as f:
        json.dump({"points": points, "description": "the plugin tests' transfer function"}, f)


def scanline_reference(out_pfm, width, height, camera=CAMERA, model="absorption", mesh=MESH, field=FIELD, tf=TF):
    """cellfx's CPU scan-line renderer, same mesh, camera and function, composited over black."""
    tf_path = os.path.splitext(out_pfm)[0] + "_tf.json"
    write_cellfx_transfer_function(tf_path, tf)
    subprocess.run([CELLFX, "render", mesh, "--path", "scanline", "--model", model, "--scalar", field, "--tf", tf_path,
                    "--camera", camera_spec(camera), "--size", "%dx%d" % (width, height), "--out", out_pfm],
                   check=True, stdout=subprocess.DEVNULL)
    return read_pfm(out_pfm)


def make_seam_mesh(path):
    """Writes the seam mesh (see SEAM_TF) as a legacy VTK file both ParaView and cellfx read."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    from vtkmodules.vtkFiltersCore import vtkDelaunay3D
    from vtkmodules.vtkIOLegacy import vtkUnstructuredGridWriter
    points = vtkPoints()
    for p in np.random.RandomState(7).uniform((0.0, 0.0, 0.0), (3.0, 2.0, 2.0), (48, 3)):
        points.InsertNextPoint(tuple(p))
    cloud = vtkPolyData()
    cloud.SetPoints(points)
    tets = vtkDelaunay3D()
    tets.SetInputData(cloud)
    tets.Update()
    mesh = tets.GetOutput()
    points = vtk_to_numpy(mesh.GetPoints().GetData())
    values = numpy_to_vtk(np.ascontiguousarray(points[:, 0] + 0.3 * points[:, 1]), deep=True)
    values.SetName(SEAM_FIELD)
    mesh.GetPointData().AddArray(values)
    writer = vtkUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(mesh)
    writer.Write()
    return path


def show_opaque_plane(view, camera=CAMERA, size=8.0):
    """An opaque grey square through the focal point, facing the camera."""
    f = np.array(camera["focal_point"])
    n = np.array(camera["position"]) - f
    n /= np.linalg.norm(n)
    u = np.cross(n, camera["view_up"])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    origin = f - 0.5 * size * (u + v)
    plane = simple.Plane(Origin=list(origin), Point1=list(origin + size * u), Point2=list(origin + size * v))
    display = simple.Show(plane, view)
    display.ColorArrayName = ["POINTS", ""]  # solid colour
    display.DiffuseColor = [0.5, 0.5, 0.5]
    display.AmbientColor = [0.5, 0.5, 0.5]
    return plane


def clip_in_front_of_plane(source, camera=CAMERA):
    """The part of `source` between the camera and show_opaque_plane's plane, cut exactly."""
    f = np.array(camera["focal_point"])
    n = np.array(camera["position"]) - f
    clip = simple.Clip(Input=source, ClipType="Plane")
    clip.ClipType.Origin = list(f)
    clip.ClipType.Normal = list(n / np.linalg.norm(n))
    clip.Crinkleclip = 0
    clip.Invert = 0  # keep the side the normal points to: towards the camera
    return clip


def mesh_conversions(display):
    display.UpdatePropertyInformation()
    return display.GetProperty("CellfxMeshConversions").GetData()


def out(name):
    return os.path.join(OUT, name)


def read_png(path):
    """RGB in [0, 1], shape (height, width, 3), bottom row first (as VTK and PFM store rows)."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    return pixels[:, :, :3].astype(np.float64) / 255.0


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if kind == b"PF" else 1
    return data.reshape(h, w, channels).astype(np.float64)


def write_png(pixels, path):
    """Writes (height, width, 3) values in [0, 1], bottom row first."""
    h, w, _ = pixels.shape
    data = np.ascontiguousarray((np.clip(pixels, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8).reshape(-1, 3))
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(data, deep=True))
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()


def screenshot(view, path, width, height):
    simple.SaveScreenshot(path, view, ImageResolution=[width, height])
    return read_png(path)


class Tolerance:
    """Per pixel and channel, a fraction of the reference's peak plus an absolute part (8-bit
    steps); the mean likewise; and the fraction of pixels allowed beyond the per-pixel bound."""

    def __init__(self, pixel, mean, beyond, pixel_abs=1.0 / 255.0, mean_abs=0.5 / 255.0):
        self.pixel, self.mean, self.beyond, self.pixel_abs, self.mean_abs = pixel, mean, beyond, pixel_abs, mean_abs


# Against the scan-line reference: the path's own tolerance (docs/absorption.md,
# docs/accuracy.md) plus the 8-bit framebuffer (1/255 per pixel, 0.5/255 mean).
PATH_TOLERANCE = {
    "absorption-exact": Tolerance(0.015, 0.001, 0.01),
    "absorption": Tolerance(0.04, 0.004, 0.01),
    "pcp-exact": Tolerance(0.015, 0.001, 0.01),
    "mip": Tolerance(0.015, 0.001, 0.01),
    # The reference itself, through an 8-bit framebuffer (and, under MPI, cells split at the
    # ranks' boundaries: exact for these tetrahedral meshes, the field linear in each piece).
    "scanline": Tolerance(0.001, 0.0001, 0.0),
}


def chosen_path(display):
    """The path the last frame on this process drew with ("auto"'s pick) and why."""
    display.UpdatePropertyInformation()
    return display.GetProperty("CellfxChosenPath").GetData(), display.GetProperty("CellfxChoiceReason").GetData()


def checked_path(path, display):
    """The path whose tolerance a frame drawn with `path` is checked with: itself, or for auto
    the path it picked (one that meets auto's default accuracy, or the test fails)."""
    picked, reason = chosen_path(display)
    if path != "auto":
        check((picked == path, "the frame was drawn with %s (%s asked)" % (picked, path)))
        return path
    print("info  auto: " + reason, flush=True)
    check((picked in ("scanline", "absorption-exact"),
           "auto picked %s, a path within its default accuracy (scanline or absorption-exact)" % picked))
    return picked if picked in PATH_TOLERANCE else "scanline"
# Clipped mesh against scene depth: both exact (segments end at the plane, or the cells do),
# different pre-integration lookups: the exact path's tolerance.
DEPTH_TOLERANCE = PATH_TOLERANCE["absorption-exact"]
# Tiles against one piece: the same rays; only 8-bit rounding of floats that differ in the
# last bits may differ, by one step.
TILE_TOLERANCE = Tolerance(0.0, 0.0, 0.0, pixel_abs=1.01 / 255.0, mean_abs=0.05 / 255.0)


# Two ranks: each rank's image is 8-bit before IceT blends it, IceT blends in 8 bits and the
# result is rounded again (measured: at most 4 steps where both ranks contribute).
MPI_MARGIN = (4.01 / 255.0, 0.5 / 255.0)  # per pixel, mean


def mpi_tolerance(path, against_one_rank):
    """Against the scan-line reference: the path's own tolerance plus MPI_MARGIN. Against the
    one-rank image: each image is within the path's tolerance of the exact picture, and their
    pre-integration lookups differ (each rank's table spans its own longest cell; a split cell
    is looked up in two pieces), so twice the per-pixel part. A seam would break either."""
    t = PATH_TOLERANCE[path]
    pixel = 2.0 * t.pixel if against_one_rank else t.pixel
    # Split cells add silhouette edges where the ranks' pieces meet the mesh's boundary, and a
    # pixel centre on such an edge goes to either side (measured on the seam mesh: 0.2-0.4% of
    # the pixels, along its outline, for every path): 1% beyond, as the GL paths have anyway.
    return Tolerance(pixel, t.mean, max(t.beyond, 0.01), pixel_abs=MPI_MARGIN[0], mean_abs=MPI_MARGIN[1])


def compare(name, actual, expected, tolerance, write_images=True):
    """Returns (ok, a one-line report). Writes NAME_actual/expected/diff.png (diff x10) when not
    ok (and write_images)."""
    assert actual.shape == expected.shape, (actual.shape, expected.shape)
    expected = np.minimum(expected, 1.0)  # an 8-bit framebuffer saturates (emission can exceed 1)
    peak = float(expected.max())
    delta = np.abs(actual - expected)
    bound = tolerance.pixel * peak + tolerance.pixel_abs
    beyond = float(np.mean(np.any(delta > bound, axis=2)))
    mean = float(delta.mean())
    ok = peak > 0.05 and beyond <= tolerance.beyond and mean <= tolerance.mean * peak + tolerance.mean_abs
    report = "%s: peak %.3f, max |diff| %.4f (%.2f%% of peak), mean %.5f (%.3f%% of peak), %.3f%% of pixels beyond %.4f" % (
        name, peak, float(delta.max()), 100.0 * float(delta.max()) / peak, mean, 100.0 * mean / peak, 100.0 * beyond, bound)
    if not ok and write_images:
        os.makedirs(OUT, exist_ok=True)
        stem = os.path.join(OUT, name.replace(" ", "_"))
        write_png(actual, stem + "_actual.png")
        write_png(expected, stem + "_expected.png")
        write_png(np.minimum(delta * 10.0, 1.0), stem + "_diff.png")
        report += " -> images in " + OUT
    return ok, report


failures = []  # the reports of the checks that failed in this process


def check(ok_report):
    """Prints one check's (ok, report) and keeps the report if it failed; returns ok."""
    ok, report = ok_report
    print(("ok    " if ok else "FAIL  ") + report, flush=True)
    if not ok:
        failures.append(report)
    return ok
