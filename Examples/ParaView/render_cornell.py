# SPDX-License-Identifier: GPL-3.0-or-later
"""Render a solved Cornell box from the Cornell camera with ParaView.

    penumbra solve cornell -o cornell.vtp
    pvbatch Examples/ParaView/render_cornell.py cornell.vtp cornell-paraview.png

Penumbra's `Radiance` is view-independent outgoing radiance, so the picture is
the radiance itself, shown unlit: a Python Calculator scales it by an exposure
(the 99th percentile of the radiance, so that the light does not set it),
applies the sRGB curve, and the result is displayed as direct RGB colors
(Map Scalars off). The same steps work interactively in the ParaView GUI:
Filters > Python Calculator with the expression below, color by the result,
untick "Map Scalars", and set the camera from CAMERA.
"""
import sys

from paraview import servermanager
from paraview.simple import (CreateView, PythonCalculator, SaveScreenshot, Show,
                             XMLPolyDataReader)
from vtkmodules.util.numpy_support import vtk_to_numpy

# The Cornell box data set's camera (metres): a 35 mm lens on 25 mm film.
CAMERA = {"position": [0.278, 0.273, -0.800], "focal_point": [0.278, 0.273, 0.0],
          "view_up": [0.0, 1.0, 0.0], "view_angle": 39.3076}


def show_radiance(source, size=600, view=None):
    """Show the Radiance of `source` (a ParaView proxy of a solution) from the
    Cornell camera, exposed and unlit, in `view` (default: a new render view
    of size x size pixels; size None keeps the view's); returns (view, exposure)."""
    radiance = vtk_to_numpy(servermanager.Fetch(source).GetPointData().GetArray("Radiance"))
    exposure = float(sorted(radiance.max(axis=1))[int(0.99 * (len(radiance) - 1))]) or 1.0
    display_color = PythonCalculator(Input=source, ArrayName="DisplayColor")
    # (np is the numpy the Python Calculator evaluates its expression with.)
    display_color.Expression = "np.clip(Radiance / %r, 0.0, 1.0) ** (1.0 / 2.2)" % exposure

    view = view or CreateView("RenderView")
    if size:
        view.ViewSize = [size, size]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    view.CameraPosition = CAMERA["position"]
    view.CameraFocalPoint = CAMERA["focal_point"]
    view.CameraViewUp = CAMERA["view_up"]
    view.CameraViewAngle = CAMERA["view_angle"]
    display = Show(display_color, view)
    display.ColorArrayName = ["POINTS", "DisplayColor"]
    display.MapScalars = 0  # the values are colors already
    display.Ambient = 1.0  # unlit: radiance already contains the lighting
    display.Diffuse = 0.0
    return view, exposure


def main(vtp, png, size=600):
    reader = XMLPolyDataReader(FileName=[vtp])
    reader.UpdatePipeline()
    view, exposure = show_radiance(reader, size)
    SaveScreenshot(png, view, ImageResolution=[size, size])
    print("wrote %s (exposure %.4g)" % (png, exposure))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: pvbatch render_cornell.py SOLUTION.vtp OUTPUT.png")
    main(sys.argv[1], sys.argv[2])
