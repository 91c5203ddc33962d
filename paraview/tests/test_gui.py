"""The plugin in ParaView's GUI: loaded at start-up from PV_PLUGIN_PATH, the LOx post shown as
"cellfx Volume" in the GUI's own render view.

    PV_PLUGIN_PATH=<plugin folder> paraview --script=paraview/tests/test_gui.py --exit

(paraview/run.sh gui). The GUI's exit status does not carry the script's, so the result goes to
pvcellfx.OUT/gui_result.txt, which run.sh checks: "ok" and the checks, or "FAIL" and why.
"""
import os
import sys

sys.path.insert(0, os.environ["CELLFX_PARAVIEW_TESTS"])  # the GUI's --script has no __file__
import pvcellfx as pc  # noqa: E402
from paraview import simple  # noqa: E402

os.makedirs(pc.OUT, exist_ok=True)
result = os.path.join(pc.OUT, "gui_result.txt")
try:
    reader = simple.LegacyVTKReader(FileNames=[pc.MESH])
    display = simple.Show(reader)
    types = display.GetProperty("Representation").Available
    assert "cellfx Volume" in types, "no \"cellfx Volume\" among the representations: %s" % types
    display.SetRepresentationType("cellfx Volume")
    simple.ColorBy(display, ("POINTS", pc.FIELD))
    view = simple.GetActiveViewOrCreate("RenderView")
    view.ResetCamera()
    simple.Render(view)
    image = pc.screenshot(view, pc.out("gui_lox.png"), 400, 300)
    display.UpdatePropertyInformation()
    cells = display.GetProperty("CellfxLastCellCount").GetData()
    assert cells == 8750, "cellfx drew %d cells, not the LOx post's 8750" % cells
    # The volume changes the picture: the centre (the post's ring) differs from the corner
    # (the GUI's background).
    assert abs(image[150, 120] - image[5, 5]).max() > 0.1, "the volume is not in the picture"
    with open(result, "w") as f:
        f.write("ok: representation listed, 8750 cells drawn, picture in %s\n" % pc.out("gui_lox.png"))
except Exception as e:  # noqa: BLE001 - everything goes to the result file
    with open(result, "w") as f:
        f.write("FAIL: %s\n" % e)
