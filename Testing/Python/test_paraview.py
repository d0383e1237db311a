# SPDX-License-Identifier: GPL-3.0-or-later
"""A real client: Debian's ParaView 5.11 (pvbatch) opens a .vtp written by
Penumbra, finds its arrays, colors by them and saves a screenshot.

python3-paraview conflicts with python3-vtk9 as a package, so build.sh unpacks
it into <build>/_deps/python3-paraview and pvbatch gets it on PYTHONPATH."""
import os
import shutil
import subprocess
import time

import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

from conftest import BUILD_DIR, SOURCE_DIR, run_penumbra

PVBATCH_SCRIPT = r'''
import sys
from paraview.simple import *
reader = XMLPolyDataReader(FileName=[sys.argv[1]])
reader.UpdatePipeline()
names = list(reader.CellData.keys()) + list(reader.PointData.keys())
print("ARRAYS", ",".join(names))
view = CreateView("RenderView")
view.ViewSize = [400, 400]
display = Show(reader, view)
array = sys.argv[3]
association = "POINTS" if array in reader.PointData.keys() else "CELLS"
ColorBy(display, (association, array))
display.RescaleTransferFunctionToDataRange(True)
ResetCamera(view)
SaveScreenshot(sys.argv[2], view, ImageResolution=[400, 400])
print("SAVED")
'''


def _pvbatch(*arguments):
    """Run pvbatch with ParaView's Python modules; returns its output."""
    pvbatch = shutil.which("pvbatch")
    assert pvbatch, "pvbatch missing: build.sh test installs Debian's paraview"
    modules = os.path.join(BUILD_DIR, "_deps", "python3-paraview", "usr", "lib", "python3",
                           "dist-packages")
    assert os.path.isdir(os.path.join(modules, "paraview")), "python3-paraview not unpacked"
    env = dict(os.environ, PYTHONPATH=modules)
    # pvbatch sometimes fails to open the Xvfb display on a loaded machine
    # ("bad X server connection", seen in 3 of 6 suite runs with other jobs
    # running, never when run alone); that is the test machine, not the
    # file, so only that failure is retried.
    for attempt in range(3):
        result = subprocess.run(
            [pvbatch, "--force-offscreen-rendering"] + [str(a) for a in arguments],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True, timeout=300)
        if result.returncode == 0 or "bad X server connection" not in result.stdout:
            break
        time.sleep(2.0)
    assert result.returncode == 0, result.stdout
    return result.stdout


def _pixels(png):
    reader = vtkPNGReader()
    reader.SetFileName(str(png))
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    # PNG rows are read bottom-up: flip to top-down.
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, -1)[::-1, :, :3]


def _pvbatch_color(tmp_path, vtp, array):
    script = tmp_path / "color.py"
    script.write_text(PVBATCH_SCRIPT)
    png = tmp_path / ("paraview-%s.png" % array)
    output = _pvbatch(script, vtp, png, array)
    assert "SAVED" in output, output
    arrays = [l for l in output.splitlines() if l.startswith("ARRAYS")][0]
    pixels = _pixels(png).reshape(-1, 3)
    return arrays, {tuple(p) for p in pixels[::7]}


@pytest.fixture(scope="module")
def cornell_solution(tmp_path_factory):
    vtp = tmp_path_factory.mktemp("solution") / "cornell.vtp"
    assert run_penumbra("solve", "cornell", "-o", vtp, "--quiet").returncode == 0
    return vtp


def test_pvbatch_colors_a_solution_by_radiance(tmp_path, cornell_solution):
    arrays, colors = _pvbatch_color(tmp_path, cornell_solution, "Radiance")
    for name in ("Radiance", "RadianceErrorEstimate", "SurfaceId", "DiscontinuityOrder"):
        assert name in arrays
    # Smoothly varying radiance: many distinct colors.
    assert len(colors) > 50


def test_pvbatch_colors_a_scene_by_reflectance(tmp_path):
    import penumbra
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
    vtp = tmp_path / "scene.vtp"
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(vtp))
    writer.SetInputData(penumbra.load_scene("cornell"))
    writer.SetDataModeToBinary()
    assert writer.Write()
    arrays, colors = _pvbatch_color(tmp_path, vtp, "Reflectance")
    assert "Reflectance" in arrays and "Emission" in arrays
    # One color per distinct reflectance magnitude, besides the background.
    assert len(colors) >= 4


def test_paraview_example_renders_the_cornell_box_from_its_camera(tmp_path, cornell_solution):
    script = os.path.join(SOURCE_DIR, "Examples", "ParaView", "render_cornell.py")
    png = tmp_path / "cornell-paraview.png"
    output = _pvbatch(script, cornell_solution, png)
    assert "wrote" in output, output
    pixels = _pixels(png).astype(float)
    height, width, _ = pixels.shape
    # From the Cornell camera: the red wall fills the left edge, the green
    # wall the right edge, the back wall the centre, the light the top centre.
    left = pixels[height // 2, : width // 20].mean(axis=0)
    right = pixels[height // 2, -width // 20:].mean(axis=0)
    centre = pixels[height // 3, width // 2]
    light = pixels[int(0.14 * height), width // 2]
    assert left[0] > 1.5 * left[1] and left[0] > 1.5 * left[2], left
    assert right[1] > 1.3 * right[0] and right[1] > 1.3 * right[2], right
    assert centre.min() > 60, centre
    assert light.min() == 255, light
