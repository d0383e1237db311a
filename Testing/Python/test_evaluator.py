# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraRadianceEvaluator: closed-form values through the filter, thread-count
independence, settings and error paths."""
import math
import subprocess
import sys

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

import penumbra

RAY_CAST = penumbra.vtkPenumbraRadianceEvaluator.RAY_CAST
from penumbra.pipeline import point_samples as samples


def corner_form_factor(a, b, c):
    """Differential area to a parallel a x b rectangle at distance c, above a corner."""
    x, y = a / c, b / c
    return (x / math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
            + y / math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))) / (2 * math.pi)


def parallel_rectangle_form_factor(px, pz, x0, x1, z0, z1, height):
    """A point under an axis-aligned rectangle: sum of signed corner rectangles."""
    total = 0.0
    for xa, sx in ((x1, 1), (x0, -1)):
        for za, sz in ((z1, 1), (z0, -1)):
            dx, dz = xa - px, za - pz
            total += sx * sz * math.copysign(1, dx) * math.copysign(1, dz) * corner_form_factor(
                abs(dx), abs(dz), height)
    return total


def cell_of(scene, predicate):
    for i in range(scene.GetNumberOfCells()):
        if predicate(np.array(scene.GetCell(i).GetPoints().GetData())):
            return i
    raise LookupError


def evaluate(scene, sample_data, **settings):
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputData(0, sample_data)
    evaluator.SetSceneData(scene)
    for name, value in settings.items():
        getattr(evaluator, "Set" + name)(value)
    return penumbra.run_filter(evaluator)


def quads_scene(quads, reflectance, emission):
    data = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    polys = vtkCellArray()
    for quad in quads:
        polys.InsertNextCell(len(quad))
        for p in quad:
            polys.InsertCellPoint(pts.InsertNextPoint(p))
    data.SetPoints(pts)
    data.SetPolys(polys)
    for name, values in (("Reflectance", reflectance), ("Emission", emission)):
        array = vtkDoubleArray()
        array.SetName(name)
        array.SetNumberOfComponents(3)
        for v in values:
            array.InsertNextTuple3(*v)
        data.GetCellData().AddArray(array)
    return data


def test_cornell_floor_point_matches_closed_form():
    """Cornell floor and light only (metres, light at 548.8 mm, facing down):
    F = 0.0142070 at (278, 0, 279.5) mm (design.md), recomputed here."""
    floor = [(0.5528, 0, 0), (0, 0, 0), (0, 0, 0.5592), (0.5496, 0, 0.5592)]
    light = [(0.343, 0.5488, 0.227), (0.343, 0.5488, 0.332), (0.213, 0.5488, 0.332),
             (0.213, 0.5488, 0.227)]
    rho, le = (0.725, 0.71, 0.68), (17.0, 12.0, 4.0)
    scene = quads_scene([floor, light], [rho, (0, 0, 0)], [(0, 0, 0), le])
    x = (0.278, 0.0, 0.2795)
    f = parallel_rectangle_form_factor(x[0], x[2], 0.213, 0.343, 0.227, 0.332, 0.5488)
    assert abs(f - 0.0142070) < 5e-8
    result = evaluate(scene, samples([x], 0))
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))[0]
    assert np.allclose(radiance, np.array(rho) * np.array(le) * f, rtol=1e-12, atol=0)
    assert result.GetPointData().GetScalars().GetName() == "Radiance"


def test_cornell_blocks_shadow_the_floor():
    """The same point in the full box lies 12 mm in front of the tall block,
    which hides part of the light: less than the unoccluded value, not zero."""
    scene = penumbra.load_scene("cornell")
    floor = cell_of(scene, lambda p: np.allclose(p[:, 1], 0) and np.ptp(p[:, 0]) > 0.5)
    x = (0.278, 0.0, 0.2795)
    unoccluded = 0.725 * 17 * parallel_rectangle_form_factor(
        x[0], x[2], 0.213, 0.343, 0.227, 0.332, 0.5483)
    red = vtk_to_numpy(evaluate(scene, samples([x], floor)).GetPointData().GetArray("Radiance"))[0, 0]
    assert 0.2 * unoccluded < red < 0.95 * unoccluded


def test_ray_cast_converges_to_exact():
    """RAY_CAST approaches EXACT as its tolerance shrinks (seven occluders floor)."""
    scene = penumbra.load_scene("seven")
    floor = cell_of(scene, lambda p: np.allclose(p[:, 1], 0))
    rng = np.random.default_rng(11)
    pts = np.column_stack([rng.uniform(-1, 1, 300), np.zeros(300), rng.uniform(-1, 1, 300)])
    exact = vtk_to_numpy(evaluate(scene, samples(pts, floor)).GetPointData().GetArray("Radiance"))
    errors = []
    for tolerance in (1e-1, 1e-2, 1e-3):
        ray = evaluate(scene, samples(pts, floor), Method=RAY_CAST,
                       RayCastTolerance=tolerance)
        values = vtk_to_numpy(ray.GetPointData().GetArray("Radiance"))
        errors.append(np.sqrt(np.mean((values - exact) ** 2)) / exact.mean())
    print("ray-cast RMS error relative to the mean, tolerance 1e-1, 1e-2, 1e-3:", errors)
    assert errors[2] < errors[0] and errors[2] < 0.01


def test_emission_is_included_on_emitters_and_can_be_left_out():
    scene = penumbra.load_scene("cornell")
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    light = int(np.nonzero(emission.max(axis=1))[0][0])
    centre = np.array(scene.GetCell(light).GetPoints().GetData()).mean(axis=0)
    with_emission = evaluate(scene, samples([centre], light))
    radiance = vtk_to_numpy(with_emission.GetPointData().GetArray("Radiance"))[0]
    assert np.allclose(radiance, emission[light])  # the light sees no other emitter
    without = evaluate(scene, samples([centre], light), IncludeEmission=False)
    assert np.allclose(vtk_to_numpy(without.GetPointData().GetArray("Radiance"))[0], 0)


SCRIPT = r'''
import sys
import numpy as np
from vtkmodules.vtkCommonCore import vtkSMPTools
vtkSMPTools.Initialize(int(sys.argv[1]))
from vtkmodules.util.numpy_support import vtk_to_numpy
import penumbra
sys.path.insert(0, sys.argv[2])
from test_evaluator import samples, evaluate, cell_of
scene = penumbra.load_scene("seven")
floor = cell_of(scene, lambda p: np.allclose(p[:, 1], 0))
rng = np.random.default_rng(5)
pts = np.column_stack([rng.uniform(-1.5, 1.5, 4000), np.zeros(4000), rng.uniform(-1.5, 1.5, 4000)])
out = evaluate(scene, samples(pts, floor))
np.save(sys.argv[3], vtk_to_numpy(out.GetPointData().GetArray("Radiance")))
print(vtkSMPTools.GetEstimatedNumberOfThreads())
'''


def test_one_and_two_threads_give_identical_output(tmp_path):
    import os
    here = os.path.dirname(os.path.abspath(__file__))
    results = []
    for threads in (1, 2):
        out = tmp_path / ("t%d.npy" % threads)
        run = subprocess.run([sys.executable, "-c", SCRIPT, str(threads), here, str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             universal_newlines=True)
        assert run.returncode == 0, run.stderr
        results.append(np.load(out))
    assert np.array_equal(results[0], results[1])
    assert results[0].max() > 0 and np.isfinite(results[0]).all() and results[0].min() >= 0


def test_settings_and_print_self():
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    assert evaluator.GetMethod() == evaluator.EXACT
    evaluator.SetMethod(7)
    assert evaluator.GetMethod() == evaluator.RAY_CAST
    evaluator.SetRayCastTolerance(0)
    assert evaluator.GetRayCastTolerance() == 1e-9
    evaluator.AddShooterId(3)
    text = str(evaluator)
    for fragment in ("Method: RAY_CAST", "RayCastTolerance: 1e-09", "IncludeEmission: On",
                     "ShooterIds: 3"):
        assert fragment in text


def test_errors_name_the_problem():
    scene = penumbra.load_scene("cornell")
    bad = samples([(0.1, 0, 0.1)], 99)
    with pytest.raises(penumbra.PenumbraError, match="sample point 0 has SurfaceId 99"):
        evaluate(scene, bad)
    no_ids = samples([(0.1, 0, 0.1)], 0)
    no_ids.GetCellData().RemoveArray("SurfaceId")
    with pytest.raises(penumbra.PenumbraError, match="no 'SurfaceId'"):
        evaluate(scene, no_ids)
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputData(0, samples([(0.1, 0, 0.1)], 0))
    evaluator.SetSceneData(scene)
    evaluator.AddShooterId(1000)
    with pytest.raises(penumbra.PenumbraError, match="ShooterIds: 1000"):
        penumbra.run_filter(evaluator)


def test_empty_samples_give_empty_output():
    result = evaluate(penumbra.load_scene("cornell"), vtkPolyData())
    assert result.GetNumberOfPoints() == 0


def shooter_function(x_cuts, radiance_of_x, y=1.0, z0=-0.5, z1=0.5):
    """Triangles of the shooter quad [x_cuts[0], x_cuts[-1]] x [z0, z1] at
    height y facing down, split at x_cuts, with point Radiance given by
    radiance_of_x(x) (3 channels): a piecewise-linear function across x."""
    data = vtkPolyData()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    polys = vtkCellArray()
    values = vtkDoubleArray()
    values.SetName("Radiance")
    values.SetNumberOfComponents(3)
    ids = vtkIntArray()
    ids.SetName("SurfaceId")
    for x in x_cuts:
        for z in (z0, z1):
            pts.InsertNextPoint(x, y, z)
            values.InsertNextTuple3(*radiance_of_x(x))
    for k in range(len(x_cuts) - 1):
        a, b, c, d = 2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3   # (x_k,z0) (x_k,z1) (x_k+1,z0) (x_k+1,z1)
        for tri in ((a, b, d), (a, d, c)):  # facing down (-y)
            polys.InsertNextCell(3)
            for p in tri:
                polys.InsertCellPoint(p)
            ids.InsertNextValue(1)
    data.SetPoints(pts)
    data.SetPolys(polys)
    data.GetPointData().AddArray(values)
    data.GetCellData().AddArray(ids)
    return data


def half_lit_scene():
    floor = [(-3, 0, -3), (-3, 0, 3), (3, 0, 3), (3, 0, -3)]
    shooter = [(-0.5, 1, -0.5), (0.5, 1, -0.5), (0.5, 1, 0.5), (-0.5, 1, 0.5)]
    return quads_scene([floor, shooter], [(0.5, 0.5, 0.5), (0, 0, 0)], [(0, 0, 0), (0, 0, 0)])


def evaluate_with_function(scene, sample_data, function, method=None, tolerance=None):
    evaluator = penumbra.vtkPenumbraRadianceEvaluator()
    evaluator.SetInputData(0, sample_data)
    evaluator.SetSceneData(scene)
    evaluator.SetShooterRadianceData(function)
    if method is not None:
        evaluator.SetMethod(method)
    if tolerance is not None:
        evaluator.SetRayCastTolerance(tolerance)
    return vtk_to_numpy(penumbra.run_filter(evaluator).GetPointData().GetArray("Radiance"))


def test_constant_function_on_port_2_equals_emission():
    scene = half_lit_scene()
    xs = np.linspace(-1.5, 1.5, 31)
    pts = samples([(x, 0, 0.1) for x in xs], 0)
    via_function = evaluate_with_function(
        scene, pts, shooter_function([-0.5, 0.0, 0.5], lambda x: (2.0, 2.0, 2.0)))
    emitting = quads_scene([[(-3, 0, -3), (-3, 0, 3), (3, 0, 3), (3, 0, -3)],
                            [(-0.5, 1, -0.5), (0.5, 1, -0.5), (0.5, 1, 0.5), (-0.5, 1, 0.5)]],
                           [(0.5, 0.5, 0.5), (0, 0, 0)], [(0, 0, 0), (2.0, 2.0, 2.0)])
    via_emission = vtk_to_numpy(evaluate(emitting, pts).GetPointData().GetArray("Radiance"))
    assert np.allclose(via_function, via_emission, rtol=1e-12, atol=1e-15)


def test_half_lit_shooter_shifts_the_peak_and_methods_agree():
    """Paper Figs. 7/8: a shooter lit on one half (x > 0) casts an asymmetric bump
    whose peak moves toward the bright half; exact and ray-cast agree."""
    scene = half_lit_scene()
    xs = np.linspace(-1.5, 1.5, 121)
    pts = samples([(x, 0, 0.0) for x in xs], 0)
    half = shooter_function([-0.5, -0.01, 0.01, 0.5], lambda x: (1.0,) * 3 if x > 0 else (0.0,) * 3)
    exact = evaluate_with_function(scene, pts, half)[:, 0]
    constant = evaluate_with_function(scene, pts, shooter_function([-0.5, 0.5], lambda x: (1.0,) * 3))[:, 0]
    assert abs(xs[np.argmax(constant)]) < 0.03
    assert xs[np.argmax(exact)] > 0.2
    ray = evaluate_with_function(scene, pts, half, method=RAY_CAST,
                                 tolerance=1e-4)[:, 0]
    difference = np.max(np.abs(ray - exact)) / exact.max()
    print("half-lit shooter: peak at x = %.3f (constant: %.3f); ray-cast vs exact max "
          "difference %.2e of the peak" % (xs[np.argmax(exact)], xs[np.argmax(constant)], difference))
    assert difference < 5e-3
