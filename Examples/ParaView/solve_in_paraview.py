# SPDX-License-Identifier: GPL-3.0-or-later
"""Build and solve the Cornell box inside ParaView with the Penumbra plugin.

    pvbatch Examples/ParaView/solve_in_paraview.py PLUGIN OUTPUT.png [SCENE]

PLUGIN is PenumbraParaView.xml (<prefix>/lib/penumbra/paraview after
`cmake --install`, or build/lib/penumbra/paraview in the build tree); SCENE a
built-in scene name (default cornell) or an .obj/.vtp scene file. The same
pipeline in the GUI: Tools > Manage Plugins > Load New (the plugin), then
Sources > Penumbra > Penumbra Scene, Filters > Penumbra > Penumbra Solve,
Apply. Prints the solution's size and writes a picture from the Cornell
camera (see render_cornell.py).
"""
import os
import sys

from paraview import servermanager, simple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_cornell import show_radiance  # noqa: E402


def main(plugin, png, scene="cornell", size=600):
    simple.LoadPlugin(plugin)  # adds PenumbraScene and PenumbraSolve to paraview.simple
    if os.path.isfile(scene):
        source = simple.PenumbraScene(FileName=scene)
    else:
        source = simple.PenumbraScene(Scene=scene)
    solve = simple.PenumbraSolve(Input=source)
    solve.UpdatePipeline()
    result = servermanager.Fetch(solve)
    print("solved: %d points, %d triangles, %d boundary lines"
          % (result.GetNumberOfPoints(), result.GetNumberOfPolys(), result.GetNumberOfLines()))
    view, exposure = show_radiance(solve, size)
    simple.SaveScreenshot(png, view, ImageResolution=[size, size])
    print("wrote %s (exposure %.4g)" % (png, exposure))
    return solve


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: pvbatch solve_in_paraview.py PenumbraParaView.xml OUTPUT.png [SCENE]")
    main(*sys.argv[1:])
