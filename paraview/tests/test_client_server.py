"""The plugin through ParaView's client/server split: a pvpython client connected to a pvserver
of two MPI ranks, which read, redistribute, render and composite; the client gets the image.

    pvpython paraview/tests/test_client_server.py PORT

with `mpirun -np 2 pvserver --server-port=PORT` running (scripts/paraview.sh --test starts it).
The plugin is loaded on both sides (the client needs its proxy definitions). Needs
test_one_rank.py's images in pvcellfx.OUT. Checks the LOx post, absorption-exact, against the
one-rank image and the scan-line reference, as test_two_ranks.py does.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvcellfx as pc  # noqa: E402
from paraview import simple  # noqa: E402

W, H = pc.IMAGE_SIZE


def main():
    port = int(sys.argv[1])
    simple.Connect("127.0.0.1", port)
    ranks = simple.servermanager.ActiveConnection.GetNumberOfDataPartitions()
    pc.load_plugin(remote=True)
    view = pc.make_view(W, H)
    reader = simple.LegacyVTKReader(FileNames=[pc.MESH])
    pc.show_volume(reader, view)
    image = pc.screenshot(view, pc.out("client_server_lox_absorption-exact.png"), W, H)
    results = [
        (ranks == 2, "server ranks: %d (expected 2)" % ranks),
        pc.compare("client/server lox absorption-exact vs one rank", image,
                   pc.read_png(pc.out("one_rank_lox_absorption-exact.png")), pc.mpi_tolerance("absorption-exact", True)),
        pc.compare("client/server lox absorption-exact vs scan-line", image,
                   pc.read_pfm(pc.out("scanline_lox_absorption.pfm")), pc.mpi_tolerance("absorption-exact", False)),
    ]
    for result in results:
        pc.check(result)
    simple.Disconnect()
    if pc.failures:
        sys.exit(1)
    print("all checks passed")


main()
