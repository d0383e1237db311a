# SPDX-License-Identifier: GPL-3.0-or-later
"""A real client: Debian's ParaView 5.11 (pvbatch) opens a .vtp written by
Penumbra, finds its arrays, colors by them and saves a screenshot.

python3-paraview conflicts with python3-vtk9 as a package, so build.sh unpacks
it into <build>/_deps/python3-paraview and pvbatch gets it on PYTHONPATH."""
import os
import shutil
import subprocess

import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

from conftest import BUILD_DIR, run_penumbra

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


def _pvbatch_color(tmp_path, vtp, array):
    pvbatch = shutil.which("pvbatch")
    assert pvbatch, "pvbatch missing: build.sh test installs Debian's paraview"
    modules = os.path.join(BUILD_DIR, "_deps", "python3-paraview", "usr", "lib", "python3",
                           "dist-packages")
    assert os.path.isdir(os.path.join(modules, "paraview")), "python3-paraview not unpacked"
    script = tmp_path / "color.py"
    script.write_text(PVBATCH_SCRIPT)
    png = tmp_path / ("paraview-%s.png" % array)
    env = dict(os.environ, PYTHONPATH=modules)
    result = subprocess.run([pvbatch, "--force-offscreen-rendering", str(script), str(vtp),
                             str(png), array], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert result.returncode == 0, result.stdout
    assert "SAVED" in result.stdout, result.stdout
    arrays = [l for l in result.stdout.splitlines() if l.startswith("ARRAYS")][0]
    reader = vtkPNGReader()
    reader.SetFileName(str(png))
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
    return arrays, {tuple(p[:3]) for p in pixels[::7]}


def test_pvbatch_colors_a_solution_by_radiance(tmp_path):
    vtp = tmp_path / "cornell.vtp"
    assert run_penumbra("solve", "cornell", "-o", vtp, "--quiet").returncode == 0
    arrays, colors = _pvbatch_color(tmp_path, vtp, "Radiance")
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
