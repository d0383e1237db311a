# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraRadianceReconstructor through the pipeline: contract, positivity,
agreement with exact values, Linear mode, errors."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData

import penumbra


def direct_pipeline(scene_name, mode=None, minimum_angle=20.0, level=3, tolerance=0.0,
                    compact=0.0):
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
    reconstructor.SetCompactTolerance(compact)
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


def _line_lengths(out):
    """Total length of the lines per (SurfaceId, DiscontinuityOrder, SourceId)."""
    xyz = vtk_to_numpy(out.GetPoints().GetData()).astype(float)
    cells = out.GetCellData()
    lengths = {}
    connectivity = vtk_to_numpy(out.GetLines().GetData())
    k, line = 0, 0
    while k < len(connectivity):
        ids = connectivity[k + 1:k + 1 + connectivity[k]]
        key = tuple(int(cells.GetArray(name).GetValue(line))
                    for name in ("SurfaceId", "DiscontinuityOrder", "SourceId"))
        lengths[key] = lengths.get(key, 0.0) + np.linalg.norm(np.diff(xyz[ids], axis=0),
                                                              axis=1).sum()
        k += connectivity[k] + 1
        line += 1
    return lengths


def _check_watertight_with_contract(out, samples, outline):
    """`out` has every surface's `outline` (total length of its edges used by one
    triangle, as _boundary_length gives it) and no edge used by three triangles,
    the boundary lines of `samples` (as many or fewer: lines of one kind that
    continue each other are joined, their total length kept), and the point
    arrays of the contract."""
    for surface, (length, overused) in _boundary_length(out).items():
        assert overused == 0
        assert length == pytest.approx(outline[surface][0], rel=1e-9)
    assert out.GetNumberOfLines() <= samples.GetNumberOfLines()
    lengths, expected = _line_lengths(out), _line_lengths(samples)
    assert lengths.keys() == expected.keys()
    for key, length in expected.items():
        assert lengths[key] == pytest.approx(length, rel=1e-9), key
    for name in ("Radiance", "Irradiance", "RadianceErrorEstimate"):
        values = vtk_to_numpy(out.GetPointData().GetArray(name))
        assert values.shape == (out.GetNumberOfPoints(), 3) and values.min() >= 0


def _floor_mean(out):
    """The area-weighted mean of |Radiance| over the floor's (surface 0)
    triangles of `out`, per channel."""
    triangles, surfaces = _triangles(out)
    xyz = vtk_to_numpy(out.GetPoints().GetData()).astype(float)
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance")).astype(float)
    floor = triangles[surfaces == 0]
    a, b, c = (xyz[floor[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    return (area[:, None] * np.abs(radiance[floor]).mean(axis=1)).sum(axis=0) / area.sum()


def _floor_locator(out):
    """A cell locator over the floor's (surface 0) output triangles of `out`."""
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkStaticCellLocator
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
    return locator


def _locate(locator, point):
    """The triangle holding `point` (within 1e-9) and its interpolation
    weights. The closest cell rather than FindCell: vtkStaticCellLocator's
    FindCell misses some points that lie exactly on an edge of flat data."""
    from vtkmodules.vtkCommonCore import mutable
    from vtkmodules.vtkCommonDataModel import vtkGenericCell

    cell, closest = vtkGenericCell(), [0.0] * 3
    cell_id, sub_id, distance2 = mutable(0), mutable(0), mutable(0.0)
    locator.FindClosestPoint(list(point), closest, cell, cell_id, sub_id, distance2)
    assert cell_id >= 0 and distance2 <= 1e-18, "no triangle within 1e-9 of %s" % (point,)
    pcoords, weights = [0.0] * 3, [0.0] * 8
    cell.EvaluatePosition(list(point), closest, sub_id, pcoords, distance2, weights)
    return cell, weights


def _floor_deviation(out, dense, mean):
    """The largest |display - cubic| on the floor (surface 0) relative to
    `mean`: at 3,000 random vertices of a dense uniform output, whose values are
    the cubic's there, the display of `out` linear over its triangles."""
    locator = _floor_locator(out)
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance")).astype(float)
    dense_triangles, dense_surfaces = _triangles(dense)
    candidates = np.unique(dense_triangles[dense_surfaces == 0])
    chosen = np.random.default_rng(3).choice(candidates, size=3000, replace=False)
    dense_xyz = vtk_to_numpy(dense.GetPoints().GetData()).astype(float)
    cubic = vtk_to_numpy(dense.GetPointData().GetArray("Radiance")).astype(float)
    worst = 0.0
    for k in chosen:
        cell, weights = _locate(locator, dense_xyz[k])
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
    mean = _floor_mean(samples)
    previous = (np.inf, 0)
    for tolerance in (0.02, 0.005):
        out, _, _ = direct_pipeline("occluder", tolerance=tolerance)
        _check_watertight_with_contract(out, samples, outline)
        deviation = _floor_deviation(out, dense, mean)
        assert deviation <= 1.05 * tolerance
        assert deviation <= previous[0] and out.GetNumberOfPolys() >= previous[1]
        previous = (deviation, out.GetNumberOfPolys())
    # Coarser than the dense display, finer than the samples.
    assert samples.GetNumberOfPolys() < previous[1] < dense.GetNumberOfPolys()


def _floor_display(out, points):
    """The display of `out` (linear over its triangles) at points on the floor."""
    locator = _floor_locator(out)
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance")).astype(float)
    shown = np.empty((len(points), 3))
    for k, p in enumerate(points):
        cell, weights = _locate(locator, p)
        shown[k] = sum(weights[n] * radiance[cell.GetPointId(n)] for n in range(3))
    return shown


def _vertex_deviation(out, base, mean):
    """The largest |display of `out` - value of `base`| on the floor (surface
    0) relative to `mean`, over the vertices of `base` that have no twin at
    their position (a twin is the other side of a discontinuity line, where the
    display has two values); `out`'s display is located by barycentric
    coordinates over all its floor triangles."""
    triangles, surfaces = _triangles(out)
    xyz = vtk_to_numpy(out.GetPoints().GetData()).astype(float)
    radiance = vtk_to_numpy(out.GetPointData().GetArray("Radiance")).astype(float)
    floor = triangles[surfaces == 0]
    base_triangles, base_surfaces = _triangles(base)
    base_xyz = vtk_to_numpy(base.GetPoints().GetData()).astype(float)
    base_radiance = vtk_to_numpy(base.GetPointData().GetArray("Radiance")).astype(float)
    vertices = np.unique(base_triangles[base_surfaces == 0])
    _, first, counts = np.unique(np.round(base_xyz[vertices], 9), axis=0, return_index=True,
                                 return_counts=True)
    single = vertices[first[counts == 1]]
    # The floor is the plane y = 0 of the built-in scenes: (x, z) coordinates.
    a, b, c = (xyz[floor[:, k]][:, [0, 2]] for k in range(3))
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    worst = 0.0
    for chunk in np.array_split(single, max(1, len(single) // 200)):
        q = base_xyz[chunk][:, [0, 2]][:, None, :]
        w0 = ((b[:, 0] - q[..., 0]) * (c[:, 1] - q[..., 1])
              - (b[:, 1] - q[..., 1]) * (c[:, 0] - q[..., 0])) / area
        w1 = ((c[:, 0] - q[..., 0]) * (a[:, 1] - q[..., 1])
              - (c[:, 1] - q[..., 1]) * (a[:, 0] - q[..., 0])) / area
        w2 = 1.0 - w0 - w1
        margin = np.minimum(np.minimum(w0, w1), w2)
        best = margin.argmax(axis=1)
        rows = np.arange(len(chunk))
        assert (margin[rows, best] >= -1e-9).all()
        t = floor[best]
        shown = (w0[rows, best, None] * radiance[t[:, 0]] + w1[rows, best, None] * radiance[t[:, 1]]
                 + w2[rows, best, None] * radiance[t[:, 2]])
        worst = max(worst, float(np.max(np.abs(shown - base_radiance[chunk]) / mean)))
    return worst


def test_compact_display_is_watertight_within_tolerance_and_as_accurate():
    """CompactTolerance: the display merged from the level-2 one keeps every
    surface's outline (no edge used by three triangles) and every boundary
    line, carries the arrays of the contract, stays within the tolerance of
    the level-2 display at the level-2 vertices (merged, kept or never
    created), merges more at a larger tolerance, and at 5e-4 (the default) is
    as accurate as the level-2 display against exact values at random floor
    points (RMS within 10%)."""
    from penumbra.pipeline import point_samples

    samples, _, source = direct_pipeline("occluder", level=1)
    level2, _, _ = direct_pipeline("occluder", level=2)
    outline = _boundary_length(samples)
    # The floor's mean as the merging takes it: the samples' area mean.
    mean = _floor_mean(samples)
    # Exact values at random floor points.
    triangles, surfaces = _triangles(level2)
    corners = vtk_to_numpy(level2.GetPoints().GetData()).astype(float)[
        triangles[surfaces == 0].ravel()]
    low, high = corners.min(axis=0), corners.max(axis=0)
    points = np.random.default_rng(11).uniform(low + 1e-3 * (high - low),
                                               high - 1e-3 * (high - low), size=(2000, 3))
    points[:, 1] = corners[0, 1]
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputData(0, point_samples(points, 0))
    evaluator.SetSceneConnection(source.GetOutputPort())
    exact = vtk_to_numpy(penumbra.run_filter(evaluator).GetPointData().GetArray("Radiance"))

    def rms(out):
        return np.sqrt(np.mean(((_floor_display(out, points) - exact) / exact.mean(axis=0)) ** 2))

    previous = level2.GetNumberOfPolys()
    for tolerance in (5e-4, 5e-3):
        out, _, _ = direct_pipeline("occluder", level=2, compact=tolerance)
        _check_watertight_with_contract(out, samples, outline)
        assert _vertex_deviation(out, level2, mean) <= tolerance * (1 + 1e-6)
        assert out.GetNumberOfPolys() < previous
        previous = out.GetNumberOfPolys()
        if tolerance == 5e-4:
            assert rms(out) <= 1.1 * rms(level2)




def test_compact_display_on_the_coarse_level_stays_within_its_tolerance():
    """Interreflections shot on the coarse level (the Cornell box on 4,000
    points): the shooter reports the scene's mean indirect radiance, and the
    display may then also move by CompactIndirectTolerance times it, per
    channel. The default display stays within the larger of that and
    CompactTolerance times the floor's mean of the dense display at every
    floor vertex of the dense one, in under half its triangles and fewer than
    without the indirect part; both parts 0 give the dense display (4
    triangles per sample triangle)."""
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer
    from penumbra.pipeline import build_pipeline

    source = vtkTrivialProducer()
    source.SetOutput(penumbra.load_scene("cornell"))
    stages = build_pipeline(source.GetOutputPort())
    stages["shooter"].SetMaximumIndirectSamples(4000)
    shot = penumbra.run_filter(stages["shooter"])
    fields = shot.GetFieldData()
    assert fields.GetArray("IndirectSpacing").GetValue(0) > 0.0
    indirect = np.array([fields.GetArray("MeanIndirectRadiance").GetComponent(0, c)
                         for c in range(3)])
    assert (indirect > 0.0).all()
    sample_triangles = shot.GetNumberOfPolys()

    def display(**settings):
        reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
        reconstructor.SetInputConnection(stages["shooter"].GetOutputPort())
        for name, value in settings.items():
            getattr(reconstructor, "Set" + name)(value)
        result = vtkPolyData()
        result.ShallowCopy(penumbra.run_filter(reconstructor))
        return result

    dense = display(CompactTolerance=0.0, CompactIndirectTolerance=0.0)
    assert dense.GetNumberOfPolys() == 4 * sample_triangles
    level1 = display(SubdivisionLevel=1, CompactTolerance=0.0, CompactIndirectTolerance=0.0)
    out = display()
    relative_only = display(CompactIndirectTolerance=0.0)
    defaults = penumbra.vtkPenumbraRadianceReconstructor()
    tolerance = np.maximum(defaults.GetCompactTolerance() * _floor_mean(level1),
                           defaults.GetCompactIndirectTolerance() * indirect)
    deviation = _vertex_deviation(out, dense, tolerance)
    print("coarse-level Cornell box: %d dense, %d compact (%d without the indirect part), "
          "largest deviation %.3f of the tolerance" % (
              dense.GetNumberOfPolys(), out.GetNumberOfPolys(), relative_only.GetNumberOfPolys(),
              deviation))
    assert deviation <= 1.0 + 1e-6
    assert out.GetNumberOfPolys() < 0.5 * dense.GetNumberOfPolys()
    assert out.GetNumberOfPolys() < relative_only.GetNumberOfPolys()


def reconstruct_samples(name):
    """The stored samples Testing/Data/Samples/NAME.vtp and their display."""
    import os
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                    "Data", "Samples", name + ".vtp"))
    reader.Update()
    samples = reader.GetOutput()
    values = vtk_to_numpy(samples.GetPointData().GetArray("Radiance"))
    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputData(samples)
    out = penumbra.run_filter(reconstructor)
    return values, vtk_to_numpy(out.GetPointData().GetArray("Radiance"))


def test_degenerate_stencil_stays_in_range():
    """Samples of a shelf next to the foot of a row of books, as solved
    (with interreflections) in a furnished office: a contact line and
    shadow lines nearly coincide there, so some points' fitting stencils
    lie almost on one line with the two sides of a discontinuity
    interleaved on it. An unguarded least-squares gradient there is a
    million times steeper than the data support, and the display showed 40
    where no sample exceeds 0.24; it must stay near the samples' range."""
    values, display = reconstruct_samples("degenerate_stencil")
    span = values.max() - values.min()
    assert display.max() <= values.max() + 0.25 * span
    assert display.min() >= values.min() - 0.25 * span


def test_graded_mesh_does_not_overshoot():
    """Samples of a wall above the corner of a bookcase standing 1 cm in
    front of it, as solved in a furnished office: around the corner's
    shadow the samples lie a fraction of a millimetre apart, and some of
    those points are also corners of triangles 30 cm long where the light is
    smooth. Their gradients, right for the small triangles, made the cubic
    climb to four times the wall's light along the long edges; the display
    must stay near the samples' range."""
    values, display = reconstruct_samples("graded_mesh")
    span = values.max() - values.min()
    assert display.max() <= values.max() + 0.25 * span
    assert display.min() >= values.min() - 0.25 * span


def test_sliver_turned_clockwise_is_repaired_with_a_warning():
    """A sample triangle whose apex lies 1e-17 on the wrong side of its long
    edge (as rounding leaves a sampler's sliver after a change of frame) is
    merged into its neighbour with one warning; the reconstruction of a
    linear field stays exact, and the constrained line through it is kept."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray

    xyz = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.5, -1e-17, 0.0), (0.5, 1.0, 0.0),
           (0.5, -1.0, 0.0)]
    a, b, c, e, d = range(5)
    points = vtkPoints()
    points.SetDataTypeToDouble()
    radiance = vtkDoubleArray()
    radiance.SetName("Radiance")
    radiance.SetNumberOfComponents(3)
    field = lambda x, y: 1.0 + 2.0 * x + 3.0 * y
    for p in xyz:
        points.InsertNextPoint(p)
        radiance.InsertNextTuple3(field(p[0], p[1]), field(p[0], p[1]), field(p[0], p[1]))
    lines, polys = vtkCellArray(), vtkCellArray()
    lines.InsertNextCell(2, [a, b])
    for tri in ((b, a, d), (a, b, c), (a, c, e), (c, b, e)):
        polys.InsertNextCell(3, tri)
    mesh = vtkPolyData()
    mesh.SetPoints(points)
    mesh.SetLines(lines)
    mesh.SetPolys(polys)
    mesh.GetPointData().AddArray(radiance)
    surface, order = vtkIntArray(), vtkIntArray()
    surface.SetName("SurfaceId")
    order.SetName("DiscontinuityOrder")
    for k in range(5):
        surface.InsertNextValue(0)
        order.InsertNextValue(1 if k == 0 else -1)
    mesh.GetCellData().AddArray(surface)
    mesh.GetCellData().AddArray(order)

    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputData(mesh)
    reconstructor.SetSubdivisionLevel(2)
    reconstructor.SetCompactTolerance(0.0)
    out = penumbra.run_filter(reconstructor)
    warnings = [reconstructor.GetWarning(k) for k in range(reconstructor.GetNumberOfWarnings())]
    assert len(warnings) == 1 and "repaired 1 sample triangle" in warnings[0], warnings
    xy = vtk_to_numpy(out.GetPoints().GetData())
    values = vtk_to_numpy(out.GetPointData().GetArray("Radiance"))
    assert np.abs(values[:, 0] - field(xy[:, 0], xy[:, 1])).max() < 1e-9
    assert out.GetNumberOfLines() >= 1
