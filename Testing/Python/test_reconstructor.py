# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraRadianceReconstructor through the pipeline: contract, positivity,
agreement with exact values, Linear mode, errors."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData

import penumbra


def direct_pipeline(scene_name, mode=None, minimum_angle=20.0, level=3):
    source = penumbra.vtkPenumbraSceneSource()
    source.SetSceneName(scene_name)
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    mesher.SetMinimumAngle(minimum_angle)
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputConnection(0, mesher.GetOutputPort())
    evaluator.SetSceneConnection(source.GetOutputPort())
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputConnection(evaluator.GetOutputPort())
    reconstructor.SetSubdivisionLevel(level)
    if mode is not None:
        reconstructor.SetMode(mode)
    return penumbra.run_filter(reconstructor), evaluator, source


def test_output_contract_and_positivity():
    out, evaluator, source = direct_pipeline("seven")
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance"))
    error = vtk_to_numpy(out.GetPointData().GetArray("RadianceErrorEstimate"))
    assert radiance.shape[1] == 3 and error.shape == radiance.shape
    assert np.isfinite(radiance).all() and radiance.min() >= 0
    assert np.isfinite(error).all() and error.min() >= 0
    assert out.GetPointData().GetScalars().GetName() == "Radiance"
    assert out.GetNumberOfLines() > 0
    lines = out.GetNumberOfLines()
    orders = vtk_to_numpy(out.GetCellData().GetArray("DiscontinuityOrder"))
    assert set(np.unique(orders[:lines])) <= {-1, 0, 1, 2}
    # Level 3: nine output triangles per sample triangle.
    samples = evaluator.GetOutput().GetNumberOfPolys()
    assert out.GetNumberOfPolys() == 9 * samples


def test_samples_are_reproduced_exactly():
    """Output points at sample positions carry the evaluated sample values
    (checked against an independent exact evaluation at the output points)."""
    out, evaluator, source = direct_pipeline("occluder", level=2)
    probe = vtkPolyData()
    probe.ShallowCopy(out)
    probe.GetPointData().RemoveArray("Radiance")
    exact_filter = penumbra.vtkPenumbraRadianceEvaluator()
    exact_filter.SetInputData(0, probe)
    exact_filter.SetSceneConnection(source.GetOutputPort())
    exact_filter.AdaptiveSamplingOff()  # evaluate at the output points as they are
    exact = vtk_to_numpy(penumbra.run_filter(exact_filter).GetPointData().GetArray("Radiance"))
    reconstructed = vtk_to_numpy(out.GetPointData().GetArray("Radiance"))
    output_points = vtk_to_numpy(out.GetPoints().GetData())
    sample_points = vtk_to_numpy(evaluator.GetOutput().GetPoints().GetData())
    # Samples on boundary lines are evaluated 1e-9 of the surface's size inside
    # their own side (so that each side of a contact gets its own value); the
    # exact value on the line itself differs by about gradient * 1e-9 * size.
    lines = vtk_to_numpy(out.GetLines().GetData())
    on_lines = set()
    position = 0
    while position < len(lines):
        count = lines[position]
        on_lines.update(lines[position + 1:position + 1 + count].tolist())
        position += count + 1
    matched = 0
    for p in sample_points:
        at = np.nonzero(np.all(np.abs(output_points - p) < 1e-12, axis=1))[0]
        for k in at:
            tolerance = 1e-6 if k in on_lines else 1e-12
            assert reconstructed[k] == pytest.approx(exact[k], rel=tolerance, abs=1e-14)
            matched += 1
    assert matched >= len(sample_points)


def test_linear_mode_is_available():
    out, _, _ = direct_pipeline("occluder", mode=penumbra.vtkPenumbraRadianceReconstructor.LINEAR)
    assert out.GetNumberOfPolys() > 0


def test_missing_radiance_is_an_error():
    source = penumbra.vtkPenumbraSceneSource()
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputConnection(mesher.GetOutputPort())
    with pytest.raises(penumbra.PenumbraError, match="'Radiance'"):
        penumbra.run_filter(reconstructor)


def test_settings_clamp_and_print():
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetSubdivisionLevel(1000)
    assert reconstructor.GetSubdivisionLevel() == 64
    text = str(reconstructor)
    for setting in ("Mode: CLOUGH_TOCHER", "SubdivisionLevel: 64", "TargetEdgeLength",
                    "EnforceNonNegativity: On", "ComputeErrorEstimate: On"):
        assert setting in text
