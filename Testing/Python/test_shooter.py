# SPDX-License-Identifier: GPL-3.0-or-later
"""vtkPenumbraProgressiveShooter through the composed pipeline: furnace, energy
balance, thread independence, settings and errors."""
import os
import subprocess
import sys

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy

import penumbra
from test_evaluator import quads_scene

CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
INWARD_FACES = [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (3, 2, 6, 7), (0, 3, 7, 4), (1, 5, 6, 2)]


def furnace(rho=0.5, le=1.0):
    quads = [[CORNERS[i] for i in face] for face in INWARD_FACES]
    for quad in quads:  # independent check of the winding: normals face the centre
        q = np.array(quad, dtype=float)
        assert np.dot(np.cross(q[1] - q[0], q[2] - q[0]), 0.5 - q.mean(axis=0)) > 0
    return quads_scene(quads, [(rho,) * 3] * 6, [(le,) * 3] * 6)


def field(result, name):
    array = result.GetFieldData().GetArray(name)
    return np.array([array.GetComponent(0, c) for c in range(array.GetNumberOfComponents())])


def test_furnace_converges_to_closed_form_and_balances_energy():
    rho, le = 0.5, 1.0
    # The strong first shots exact (as the filter's default), the rest fast.
    result = penumbra.solve(furnace(rho, le), unshot_fraction=1e-6, exact_power_fraction=0.05)
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
    expected = le / (1 - rho)
    worst = np.abs(radiance / expected - 1).max()
    print("furnace: worst relative error %.2e over %d output points" % (worst, len(radiance)))
    assert worst < 1e-4
    emitted = field(result, "EmittedPower")
    balance = field(result, "AbsorbedPower") + field(result, "UnshotPower") + field(result, "EscapedPower") \
        + field(result, "ResidualPower")
    assert np.allclose(balance, emitted, rtol=1e-6, atol=0)
    # A closed box lets nothing escape (test_conservation.py has more).
    assert (np.abs(field(result, "EscapedPower")) / emitted).max() < 1e-4


SCRIPT = r'''
import sys
import numpy as np
import penumbra
result = penumbra.solve("occluder", threads=int(sys.argv[1]), subdivision_level=1)
from vtkmodules.util.numpy_support import vtk_to_numpy
np.save(sys.argv[2], vtk_to_numpy(result.GetPointData().GetArray("Radiance")))
'''


def test_one_and_two_threads_give_identical_output(tmp_path):
    results = []
    for threads in (1, 2):
        out = tmp_path / ("t%d.npy" % threads)
        run = subprocess.run([sys.executable, "-c", SCRIPT, str(threads), str(out)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             universal_newlines=True, timeout=600)
        assert run.returncode == 0, run.stderr
        results.append(np.load(out))
    assert np.array_equal(results[0], results[1])


def test_settings_clamp_and_print():
    shooter = penumbra.vtkPenumbraProgressiveShooter()
    shooter.SetUnshotFraction(2)
    assert shooter.GetUnshotFraction() == 1
    shooter.SetOpeningAngle(0)
    assert shooter.GetOpeningAngle() == 0.01
    text = str(shooter)
    for setting in ("UnshotFraction", "MaximumShots", "ExactPowerFraction", "OpeningAngle"):
        assert setting + ":" in text


def test_missing_radiance_is_an_error():
    source = penumbra.vtkPenumbraSceneSource()
    mesher = penumbra.vtkPenumbraDiscontinuityMesher()
    mesher.SetInputConnection(source.GetOutputPort())
    shooter = penumbra.vtkPenumbraProgressiveShooter()
    shooter.SetInputConnection(0, mesher.GetOutputPort())
    shooter.SetSceneConnection(source.GetOutputPort())
    with pytest.raises(penumbra.PenumbraError, match="'Radiance'"):
        penumbra.run_filter(shooter)


def staged(scene, **shooter_settings):
    """The composed pipeline's stages on `scene` (a vtkPolyData), the
    shooter's settings applied (vtk setter name without 'Set' -> value)."""
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer
    from penumbra.pipeline import build_pipeline
    source = vtkTrivialProducer()
    source.SetOutput(scene)
    stages = build_pipeline(source.GetOutputPort())
    for name, value in shooter_settings.items():
        getattr(stages["shooter"], "Set" + name)(value)
    stages["source"] = source
    return stages


def test_coarse_level_keeps_the_furnace_closed_form():
    """Shooting on the coarse level (penumbra::IndirectLevel) of a furnace:
    a constant restricts and interpolates exactly, so L = L^e / (1 - rho)
    still holds, and the energy still balances."""
    rho, le = 0.5, 1.0
    stages = staged(furnace(rho, le), MaximumIndirectSamples=60, UnshotFraction=1e-6,
                    ExactPowerFraction=0.05)
    result = penumbra.run_filter(stages["shooter"])
    spacing = field(result, "IndirectSpacing")[0]
    shot_on = field(result, "IndirectSamples")[0]
    print("coarse furnace: spacing %.3f, %d points shot on, %d samples"
          % (spacing, shot_on, result.GetNumberOfPoints()))
    assert spacing > 0 and shot_on <= 60 < result.GetNumberOfPoints()
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
    worst = np.abs(radiance / (le / (1 - rho)) - 1).max()
    print("coarse furnace: worst relative error %.2e" % worst)
    assert worst < 1e-4
    emitted = field(result, "EmittedPower")
    balance = field(result, "AbsorbedPower") + field(result, "UnshotPower") + field(result, "EscapedPower") \
        + field(result, "ResidualPower")
    assert np.allclose(balance, emitted, rtol=1e-6, atol=0)


def test_coarse_level_converges_to_every_sample_on_cornell():
    """The Cornell box's interreflections on coarse levels of growing size
    approach those computed at every sample (same direct light, same
    shooter settings): the absorbed power converges monotonically, and the
    mean error at the samples falls. (Measured: the samples' mean error is
    21% of the mean indirect radiance on 1/64 of the samples, 4% on 1/2;
    it is largest at the blocks' contact with the floor, which the lattice
    does not follow.)"""
    stages = staged(penumbra.load_scene("cornell"), MaximumIndirectSamples=0)
    stages["evaluator"].SetSamplingTolerance(0.01)
    direct = penumbra.run_filter(stages["evaluator"])
    samples = direct.GetNumberOfPoints()
    every = penumbra.run_filter(stages["shooter"])
    reference = vtk_to_numpy(every.GetPointData().GetArray("Radiance")).copy()
    absorbed = field(every, "AbsorbedPower")
    mean = (reference - vtk_to_numpy(direct.GetPointData().GetArray("Radiance"))).mean()
    gaps, errors = [], []
    for budget in (samples // 64, samples // 16, samples // 4, samples // 2):
        stages["shooter"].SetMaximumIndirectSamples(budget)
        result = penumbra.run_filter(stages["shooter"])
        assert field(result, "IndirectSpacing")[0] > 0
        radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
        errors.append(np.abs(radiance - reference).mean() / mean)
        gaps.append(np.abs(field(result, "AbsorbedPower") / absorbed - 1).max())
        print("Cornell, %d of %d samples shot on: mean error %.4f of the mean indirect, "
              "absorbed power off by %.2e" % (field(result, "IndirectSamples")[0], samples,
                                              errors[-1], gaps[-1]))
    # The gap falls with every finer level. What is left at 1/2 (2.6e-3,
    # measured 2026-12-04) is mostly the ceiling behind the light, hung
    # 0.5 mm below it: the samples follow the light's cover lines
    # (penumbraCovers.h) and find it dark, while the lattice's triangles
    # straddling the light's outline shoot and receive as if partly lit.
    # Before the cover lines the samples leaked there too, and the two agreed
    # to 1e-3 (measured 1.2e-3, 4.7e-4 and 6.0e-4, 7.1e-4 at 1/4 and 1/2).
    assert gaps[1] < gaps[0] and gaps[2] < gaps[1] and gaps[3] < gaps[2]
    assert gaps[3] <= 3e-3
    assert errors[-1] < errors[0] / 2


def test_solve_passes_the_large_scene_settings():
    """penumbra.solve(maximum_indirect_samples=, reuse_transport=) reaches the
    shooter: the furnace is shot on at most that many points, in fewer shots
    when the six walls (six orientations) are swept together through the
    recorded transport, and both still give L = L^e / (1 - rho)."""
    rho, le = 0.5, 1.0
    shots = {}
    for across in (False, True):
        result = penumbra.solve(furnace(rho, le), unshot_fraction=1e-6, exact_power_fraction=0.05,
                                maximum_indirect_samples=60, reuse_transport=across)
        assert 0 < field(result, "IndirectSamples")[0] <= 60
        radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance"))
        worst = np.abs(radiance / (le / (1 - rho)) - 1).max()
        shots[across] = field(result, "Shots")[0]
        print("solve, across orientations %s: %d shots, worst relative error %.2e"
              % (across, shots[across], worst))
        assert worst < 1e-4
    assert shots[True] < shots[False]
