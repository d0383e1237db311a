# SPDX-License-Identifier: GPL-3.0-or-later
"""The standard radiosity baseline (vtkPenumbraStandardRadiositySolver) through VTK,
penumbra.solve(method="standard") and the command line: the furnace through
the VTK conversion, the energy identity in the field data, progress events,
the output contract, and one-line errors."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

import penumbra
from conftest import run_penumbra
from test_evaluator import quads_scene


def furnace_box(rho, emission):
    """The unit cube, six quads facing inside, one material everywhere."""
    quads = []
    for axis in range(3):
        for side in (0.0, 1.0):
            corners = []
            for u, v in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, u, v
                corners.append(tuple(p))
            # (u, v, axis) is right-handed: this winding faces +axis; reverse it on side 1.
            quads.append(corners if side == 0.0 else corners[::-1])
    return quads_scene(quads, [rho] * 6, [emission] * 6)


def test_furnace_through_vtk():
    rho = (0.3, 0.5, 0.7)
    result = penumbra.solve(furnace_box(rho, (1.0, 1.0, 1.0)), method="standard",
                            unshot_fraction=1e-7, patch_size=0.5, element_size=0.25,
                            maximum_subdivision_depth=0)
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
    expected = 1.0 / (1.0 - np.array(rho))
    # Closed convex box: every vertex's form factors sum to 1, so only the
    # unshot 1e-7 of the power (amplified at most 1 / (1 - 0.7) times) is missing.
    assert np.abs(radiance / expected - 1.0).max() < 1e-5


def field(data, name):
    array = data.GetFieldData().GetArray(name)
    return np.array([array.GetComponent(0, k) for k in range(array.GetNumberOfComponents())])


def test_energy_balance_and_report():
    solver = penumbra.vtkPenumbraStandardRadiositySolver()
    source = penumbra.vtkPenumbraSceneSource()
    source.SetSceneName("cornell")
    solver.SetInputConnection(source.GetOutputPort())
    solver.SetElementSize(0.1)
    solver.SetUnshotFraction(1e-2)
    progress = []
    solver.AddObserver(vtkCommand.ProgressEvent,
                       lambda caller, _event: progress.append(caller.GetProgress()))
    out = penumbra.run_filter(solver)
    emitted = field(out, "EmittedPower")
    balance = (field(out, "AbsorbedPower") + field(out, "EscapedPower") + field(out, "UnshotPower")
               + field(out, "ResidualPower"))
    assert np.allclose(balance, emitted, rtol=1e-12)
    assert field(out, "UnshotFraction")[0] <= 1e-2
    assert field(out, "Shots")[0] > 0 and field(out, "SolveSeconds")[0] > 0
    # One triangle per element, more where T-vertices are fanned.
    assert 0 < field(out, "Elements")[0] <= out.GetNumberOfPolys()
    assert field(out, "Rays")[0] > 0 and field(out, "Vertices")[0] > 0
    assert progress[0] == 0.0 and progress[-1] == 1.0 and progress == sorted(progress)


def test_output_contract():
    out = penumbra.solve("occluder", method="standard", element_size=0.1)
    assert out.GetNumberOfPolys() > 0 and out.GetNumberOfLines() > 0
    radiance = out.GetPointData().GetScalars()
    assert radiance.GetName() == "Radiance" and radiance.GetNumberOfComponents() == 3
    values = vtk_to_numpy(radiance)
    assert np.isfinite(values).all() and values.min() >= 0.0 and values.max() > 0.0
    cells = out.GetCellData()
    lines = out.GetNumberOfLines()
    surface = vtk_to_numpy(cells.GetArray("SurfaceId"))
    order = vtk_to_numpy(cells.GetArray("DiscontinuityOrder"))
    source = vtk_to_numpy(cells.GetArray("SourceId"))
    assert set(surface) == {0, 1, 2}
    assert (order[:lines] == -1).all() and (source[:lines] == -1).all()
    for k in range(lines, out.GetNumberOfCells()):
        assert out.GetCellType(k) == 5  # VTK_TRIANGLE


def test_printself_and_empty_input():
    solver = penumbra.vtkPenumbraStandardRadiositySolver()
    text = str(solver)
    for name in ("PatchSize: 0.5", "ElementSize: 0.05", "ShooterSamples: 4",
                 "FormFactorMode: ANALYTIC_VISIBILITY", "SubdivisionThreshold: 0.2",
                 "MaximumSubdivisionDepth: 3", "UnshotFraction: 0.001", "MaximumShots: 10000"):
        assert name in text
    solver.SetInputData(vtkPolyData())
    assert penumbra.run_filter(solver).GetNumberOfCells() == 0


def test_bad_input_and_settings():
    scene = furnace_box((1.5, 0.5, 0.5), (1.0, 1.0, 1.0))
    solver = penumbra.vtkPenumbraStandardRadiositySolver()
    solver.SetInputData(scene)
    with pytest.raises(penumbra.PenumbraError, match="cell 0"):
        penumbra.run_filter(solver)
    with pytest.raises(penumbra.PenumbraError, match="unknown method"):
        penumbra.solve("strip", method="hierarchical")
    with pytest.raises(penumbra.PenumbraError, match="element_size"):
        penumbra.solve("strip", element_size=0.1)
    with pytest.raises(penumbra.PenumbraError, match="form_factor"):
        penumbra.solve("strip", method="standard", form_factor="exact")


def test_cli_method_standard(tmp_path):
    help_text = run_penumbra("solve", "--help").stdout
    assert "--method" in help_text and "standard" in help_text
    vtp = tmp_path / "occluder.vtp"
    result = run_penumbra("solve", "occluder", "--method", "standard", "--element-size", "0.1",
                          "-o", vtp, "--threads", 2)
    assert result.returncode == 0, result.stderr
    assert "shots" in result.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(vtp))
    reader.Update()
    data = reader.GetOutput()
    assert data.GetNumberOfPolys() > 0
    assert data.GetPointData().GetArray("Radiance").GetNumberOfComponents() == 3
    assert data.GetCellData().GetArray("SurfaceId") is not None
    bad = run_penumbra("solve", "occluder", "--method", "standard", "--direct-only",
                       "-o", tmp_path / "x.vtp")
    assert bad.returncode != 0 and len(bad.stderr.strip().splitlines()) == 1
    bad = run_penumbra("solve", "occluder", "--element-size", "0.1", "-o", tmp_path / "x.vtp")
    assert bad.returncode != 0 and "--method standard" in bad.stderr
