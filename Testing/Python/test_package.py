# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python package: wrapped classes, settings, scene loading and its errors,
and the progress a solve reports."""
import math
import os

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import penumbra
from conftest import SCENE_DIR


def test_classes_are_wrapped():
    for name in ("vtkPenumbraSceneSource", "vtkPenumbraOBJReader", "vtkPenumbraSceneValidator"):
        obj = getattr(penumbra, name)()
        assert obj.GetClassName() == name
        assert obj.IsA("vtkPolyDataAlgorithm")


def test_scene_catalogue():
    names = [name for name, _ in penumbra.scenes()]
    assert {"cornell", "strip", "occluder", "seven", "blind"} <= set(names)
    assert all(description for _, description in penumbra.scenes())


def test_print_self_lists_every_setting():
    validator = penumbra.vtkPenumbraSceneValidator()
    text = str(validator)
    for setting in ("PlanarityTolerance: 1e-06", "DegeneracyTolerance: 1e-09", "LastErrorMessage"):
        assert setting in text
    assert "SceneName: cornell" in str(penumbra.vtkPenumbraSceneSource())
    assert "FileName" in str(penumbra.vtkPenumbraOBJReader())


def test_clamped_settings():
    validator = penumbra.vtkPenumbraSceneValidator()
    validator.SetPlanarityTolerance(5.0)
    assert validator.GetPlanarityTolerance() == 1.0
    validator.SetDegeneracyTolerance(-1.0)
    assert validator.GetDegeneracyTolerance() == 0.0


@pytest.mark.parametrize("name", ["cornell", "strip", "occluder", "seven", "blind"])
def test_builtin_scenes_follow_the_contract(name):
    scene = penumbra.load_scene(name)
    assert scene.GetNumberOfPolys() == scene.GetNumberOfCells() > 0
    for array in ("Reflectance", "Emission"):
        values = vtk_to_numpy(scene.GetCellData().GetArray(array))
        assert values.shape == (scene.GetNumberOfCells(), 3)
        assert np.isfinite(values).all()
    reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))
    assert ((reflectance >= 0) & (reflectance < 1)).all()
    assert vtk_to_numpy(scene.GetCellData().GetArray("Emission")).max() > 0


def test_cornell_light_area_and_position():
    scene = penumbra.load_scene("cornell")
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    lights = np.nonzero(emission.max(axis=1) > 0)[0]
    assert len(lights) == 1
    cell = scene.GetCell(int(lights[0]))
    points = np.array([cell.GetPoints().GetPoint(i) for i in range(cell.GetNumberOfPoints())])
    # Shoelace area in the ceiling plane: 130 mm x 105 mm.
    x, z = points[:, 0], points[:, 2]
    area = 0.5 * abs(np.dot(x, np.roll(z, 1)) - np.dot(z, np.roll(x, 1)))
    assert math.isclose(area, 0.130 * 0.105, rel_tol=1e-12)
    assert np.allclose(emission[lights[0]], (17, 12, 4))
    assert 0.5478 <= points[:, 1].min() < 0.5488


def _square_scene(reflectance=(0.5, 0.5, 0.5)):
    points = vtkPoints()
    cells = vtkCellArray()
    cells.InsertNextCell(4)
    for p in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)):
        cells.InsertCellPoint(points.InsertNextPoint(p))
    scene = vtkPolyData()
    scene.SetPoints(points)
    scene.SetPolys(cells)
    for name, value in (("Reflectance", reflectance), ("Emission", (1, 1, 1))):
        array = vtkDoubleArray()
        array.SetName(name)
        array.SetNumberOfComponents(3)
        array.InsertNextTuple3(*value)
        scene.GetCellData().AddArray(array)
    return scene


def _write(scene, path):
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(scene)
    assert writer.Write()
    return str(path)


def test_load_scene_from_vtp(tmp_path):
    scene = penumbra.load_scene(_write(_square_scene(), tmp_path / "square.vtp"))
    assert scene.GetNumberOfCells() == 1


def test_load_scene_from_obj():
    scene = penumbra.load_scene(os.path.join(SCENE_DIR, "box.obj"))
    assert scene.GetNumberOfCells() > 0
    assert vtk_to_numpy(scene.GetCellData().GetArray("Emission")).max() > 0


def test_bad_vtp_scene_names_the_cell(tmp_path):
    path = _write(_square_scene(reflectance=(0.5, 1.5, 0.5)), tmp_path / "bad.vtp")
    with pytest.raises(penumbra.PenumbraError, match=r"cell 0: Reflectance green is 1.5"):
        penumbra.load_scene(path)


def test_unknown_scene_lists_the_builtin_names():
    with pytest.raises(penumbra.PenumbraError, match="cornell"):
        penumbra.load_scene("no-such-scene")


def test_bad_obj_names_file_and_line(tmp_path):
    path = tmp_path / "broken.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n")
    with pytest.raises(penumbra.PenumbraError, match=r"broken.obj:4"):
        penumbra.load_scene(str(path))


def test_progress_never_moves_back():
    """The solve reports its progress stage by stage, the secondary shooters'
    second pass of the mesher and the evaluator in a share of its own: the
    fraction never decreases and ends at 1 (the Cornell box has that pass)."""
    reports = []
    result = penumbra.solve("cornell", threads=2,
                            progress=lambda stage, fraction: reports.append((stage, fraction)))
    assert result.GetFieldData().GetArray("SecondaryShootersSeconds").GetValue(0) > 0.0
    fractions = [fraction for _, fraction in reports]
    assert all(b >= a for a, b in zip(fractions, fractions[1:])), reports
    assert fractions[-1] == 1.0
    assert any(stage.startswith("secondary shooters") for stage, _ in reports)


def test_sample_budget_too_small_is_reported():
    """A sample budget that stops the refinement before the tolerance is met
    is not silent: the evaluator keeps a warning, the solver passes it on
    named by its stage, and penumbra.solve issues it as a PenumbraWarning."""
    expected = r"evaluator: .*sample budget.*MaximumSamples 500 "
    with pytest.warns(penumbra.PenumbraWarning, match=expected) as record:
        penumbra.solve("occluder", threads=2, indirect=False, maximum_samples=500)
    assert len(record) == 1
    # The default budget is enough for the built-in scene: no warning.
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", penumbra.PenumbraWarning)
        penumbra.solve("occluder", threads=2, indirect=False)
