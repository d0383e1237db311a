# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraRadianceReconstructor through the pipeline: contract, positivity,
agreement with exact values, Linear mode, errors."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData

import penumbra


def direct_pipeline(scene_name, mode=None, minimum_angle=20.0, level=3, tolerance=0.0):
    """The direct light of a built-in scene, reconstructed (uniformly at
    `level` with the default tolerance 0, else adaptively)."""
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
    reconstructor.SetDisplayTolerance(tolerance)
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
    reconstructor.SetDisplayTolerance(5)
    assert reconstructor.GetDisplayTolerance() == 1
    text = str(reconstructor)
    for setting in ("Mode: CLOUGH_TOCHER", "SubdivisionLevel: 64", "DisplayTolerance: 1",
                    "TargetEdgeLength",
                    "EnforceNonNegativity: On", "ComputeErrorEstimate: On"):
        assert setting in text


def _triangles(out):
    """Output triangles (point ids) and their surface ids."""
    lines = out.GetNumberOfLines()
    triangles = vtk_to_numpy(out.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    surfaces = vtk_to_numpy(out.GetCellData().GetArray("SurfaceId"))[lines:]
    return triangles, surfaces


def _boundary_length(out):
    """Per surface: the total length of the edges used by one triangle, and the
    number of edges used by more than two."""
    triangles, surfaces = _triangles(out)
    xyz = vtk_to_numpy(out.GetPoints().GetData()).astype(float)
    result = {}
    for surface in np.unique(surfaces):
        mine = triangles[surfaces == surface]
        edges = np.sort(np.concatenate([mine[:, [0, 1]], mine[:, [1, 2]], mine[:, [2, 0]]]),
                        axis=1)
        unique, counts = np.unique(edges, axis=0, return_counts=True)
        once = unique[counts == 1]
        length = np.linalg.norm(xyz[once[:, 0]] - xyz[once[:, 1]], axis=1).sum()
        result[int(surface)] = (length, int((counts > 2).sum()))
    return result


def _floor_deviation(out, dense, mean):
    """The largest |display - cubic| on the floor (surface 0) relative to
    `mean`: at 3,000 random vertices of a dense uniform output, whose values are
    the cubic's there, the display of `out` linear over its triangles."""
    from vtkmodules.vtkCommonDataModel import (vtkCellArray, vtkGenericCell,
                                               vtkStaticCellLocator)
    from vtkmodules.util.numpy_support import numpy_to_vtkIdTypeArray

    triangles, surfaces = _triangles(out)
    floor = vtkPolyData()
    floor.SetPoints(out.GetPoints())
    cells = np.hstack([np.full((int((surfaces == 0).sum()), 1), 3),
                       triangles[surfaces == 0]]).astype(np.int64).ravel()
    polys = vtkCellArray()
    polys.SetCells(len(cells) // 4, numpy_to_vtkIdTypeArray(cells, deep=True))
    floor.SetPolys(polys)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(floor)
    locator.BuildLocator()
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance")).astype(float)
    dense_triangles, dense_surfaces = _triangles(dense)
    candidates = np.unique(dense_triangles[dense_surfaces == 0])
    chosen = np.random.default_rng(3).choice(candidates, size=3000, replace=False)
    dense_xyz = vtk_to_numpy(dense.GetPoints().GetData()).astype(float)
    cubic = vtk_to_numpy(dense.GetPointData().GetArray("Radiance")).astype(float)
    cell, pcoords, weights = vtkGenericCell(), [0.0] * 3, [0.0] * 8
    worst = 0.0
    for k in chosen:
        found = locator.FindCell(list(dense_xyz[k]), 1e-9, cell, pcoords, weights)
        assert found >= 0
        shown = sum(weights[n] * radiance[cell.GetPointId(n)] for n in range(3))
        worst = max(worst, float(np.max(np.abs(shown - cubic[k]) / mean)))
    return worst


def test_adaptive_display_is_watertight_and_within_tolerance():
    """DisplayTolerance: every surface as watertight as its sample mesh (the same
    outline, no edge used by three triangles), the boundary lines carried
    through, the arrays of the contract, and the display within the tolerance
    of the cubic at independent points, a smaller tolerance giving no larger
    deviation."""
    samples, evaluator, _ = direct_pipeline("occluder", level=1)
    dense, _, _ = direct_pipeline("occluder", level=8)
    outline = _boundary_length(samples)
    # The floor's mean, area-weighted over the sample triangles.
    triangles, surfaces = _triangles(samples)
    xyz = vtk_to_numpy(samples.GetPoints().GetData()).astype(float)
    radiance = vtk_to_numpy(samples.GetPointData().GetArray("Radiance")).astype(float)
    floor = triangles[surfaces == 0]
    a, b, c = (xyz[floor[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    mean = (area[:, None] * radiance[floor].mean(axis=1)).sum(axis=0) / area.sum()
    previous = (np.inf, 0)
    for tolerance in (0.02, 0.005):
        out, _, _ = direct_pipeline("occluder", tolerance=tolerance)
        for surface, (length, overused) in _boundary_length(out).items():
            assert overused == 0
            assert length == pytest.approx(outline[surface][0], rel=1e-9)
        assert out.GetNumberOfLines() == samples.GetNumberOfLines()
        for name in ("Radiance", "Irradiance", "RadianceErrorEstimate"):
            values = vtk_to_numpy(out.GetPointData().GetArray(name))
            assert values.shape == (out.GetNumberOfPoints(), 3) and values.min() >= 0
        deviation = _floor_deviation(out, dense, mean)
        assert deviation <= 1.05 * tolerance
        assert deviation <= previous[0] and out.GetNumberOfPolys() >= previous[1]
        previous = (deviation, out.GetNumberOfPolys())
    # Coarser than the dense display, finer than the samples.
    assert samples.GetNumberOfPolys() < previous[1] < dense.GetNumberOfPolys()
