# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line for daily use: exit codes, quality presets and the
tolerance, `penumbra info`, and `penumbra render` with a camera, including the
automatic view from inside a closed room (a baseline image)."""
import os
import re

import numpy as np
import pytest
from vtkmodules.test import Testing

import penumbra
from penumbra import generators
from penumbra.export import write_vtp
from penumbra.rendering import interior_view, make_render_window
from conftest import BASELINE_DIR, run_penumbra


def test_exit_codes_tell_usage_from_input_errors(tmp_path):
    # 2: the command was used wrongly; 1: the input (or the solve) is bad.
    usage = [("solve", "strip"), ("solve", "strip", "-o", tmp_path / "a.vtp", "--quality", "best"),
             ("solve", "strip", "-o", tmp_path / "a.vtp", "--tolerance", "5"),
             ("solve", "strip", "-o", tmp_path / "a.vtp", "--method", "standard", "--quality",
              "draft"),
             ("render", tmp_path / "none.vtp", "-o", tmp_path / "a.png", "--camera", "1,2:3,4,5"),
             ("nosuchcommand",)]
    for args in usage:
        result = run_penumbra(*args)
        assert result.returncode == 2, (args, result.stderr)
    scene = tmp_path / "scene.vtp"
    assert run_penumbra("scene", "strip", "-o", scene).returncode == 0
    for args in [("solve", tmp_path / "missing.obj", "-o", tmp_path / "a.vtp"),
                 ("info", tmp_path / "missing.vtp"),
                 ("render", tmp_path / "missing.vtp", "-o", tmp_path / "a.png")]:
        result = run_penumbra(*args)
        assert result.returncode == 1, (args, result.stderr)
        assert len(result.stderr.strip().splitlines()) == 1
    result = run_penumbra("render", scene, "-o", tmp_path / "a.png", "--camera", "0,1,2:0,1,2")
    assert result.returncode == 2 and "coincide" in result.stderr


def _info(path):
    result = run_penumbra("info", path)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_quality_presets_and_tolerance_reach_the_solver(tmp_path):
    from penumbra.settings import QUALITY_PRESETS

    counts = {}
    for quality in ("draft", "normal", "high"):
        out = tmp_path / ("%s.vtp" % quality)
        result = run_penumbra("solve", "strip", "-o", out, "--quality", quality, "-q",
                              "--threads", "2")
        assert result.returncode == 0, result.stderr
        text = _info(out)
        for name, value in QUALITY_PRESETS[quality].items():
            assert re.search(r"\b%s=%g\b" % (name, value), text), (name, text)
        counts[quality] = int(re.search(r"exact evaluations \(direct light\): (\d+)",
                                        text).group(1))
    # high's finer spacing reaches the evaluator: the strip's evenly lit floor is
    # sampled twice as densely along each edge (about 4 times the evaluations).
    assert counts["high"] > 2 * counts["normal"] and counts["normal"] >= counts["draft"], counts
    # An explicit tolerance wins over the preset's.
    out = tmp_path / "both.vtp"
    assert run_penumbra("solve", "strip", "-o", out, "--quality", "high", "--tolerance", "0.02",
                        "-q", "--threads", "2").returncode == 0
    assert "SamplingTolerance=0.02 " in _info(out)


def test_compact_reaches_the_solver_and_shrinks_the_output(tmp_path):
    """The default output is compact; --compact [T] sets CompactTolerance (2e-3 when
    given no value) and merges more; --dense and --compact 0 give the dense display (every
    sample triangle cut in 4, both tolerances 0); a tolerance outside [0, 1] and --dense
    with --compact are usage errors."""
    from penumbra.info import read_result

    triangles = {}
    for name, extra, recorded in (
            ("dense", ("--dense",), "CompactTolerance=0 CompactIndirectTolerance=0 "),
            ("zero", ("--compact", "0"), "CompactTolerance=0 CompactIndirectTolerance=0 "),
            ("default", (), "CompactTolerance=0.0005 CompactIndirectTolerance=0.01 "),
            ("compact", ("--compact",), "CompactTolerance=0.002 ")):
        out = tmp_path / ("%s.vtp" % name)
        result = run_penumbra("solve", "occluder", "-o", out, "--direct-only", "-q",
                              "--threads", "2", *extra)
        assert result.returncode == 0, result.stderr
        triangles[name] = read_result(str(out)).GetNumberOfPolys()
        assert recorded in _info(out), _info(out)
    assert triangles["zero"] == triangles["dense"], triangles
    assert triangles["default"] < 0.8 * triangles["dense"], triangles
    assert triangles["compact"] < 0.5 * triangles["default"], triangles
    result = run_penumbra("solve", "occluder", "-o", tmp_path / "bad.vtp", "--compact", "2")
    assert result.returncode == 2 and "compact" in result.stderr, result.stderr
    result = run_penumbra("solve", "occluder", "-o", tmp_path / "bad.vtp", "--compact",
                          "1e-3", "--dense")
    assert result.returncode == 2 and "--dense" in result.stderr, result.stderr


def test_info_reports_the_record_of_the_solve(tmp_path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from penumbra.info import energy_balance, read_result

    out = tmp_path / "cornell.vtp"
    result = run_penumbra("solve", "cornell", "-o", out, "-q", "--threads", "2",
                          "--quality", "draft")
    assert result.returncode == 0, result.stderr
    assert "estimated error" in result.stdout and "absorbed" in result.stdout
    text = _info(out)
    data = read_result(str(out))
    assert "surfaces: %d (1 emitting)" % data.GetFieldData().GetArray(
        "SurfaceReflectance").GetNumberOfTuples() in text
    assert "%d triangles" % data.GetNumberOfPolys() in text
    # The balance is a partition of the emitted power.
    balance = energy_balance(data)
    assert abs(sum(balance.values()) - 1.0) < 1e-9, balance
    emitted = vtk_to_numpy(data.GetFieldData().GetArray("EmittedPower"))
    assert "emitted power: %.6g" % emitted.ravel()[0] in text
    stages = [float(s) for s in re.findall(r"(?:mesher|evaluator|secondary shooters|shooter|"
                                           r"reconstructor) ([0-9.]+) s", text)]
    solve = float(re.search(r"\(solve ([0-9.]+) s\)", text).group(1))
    assert len(stages) == 5 and sum(stages) <= solve + 0.02
    # A scene is not a result, and says so.
    scene = tmp_path / "scene.vtp"
    assert run_penumbra("scene", "cornell", "-o", scene).returncode == 0
    assert "not a solved result" in _info(scene)


@pytest.fixture(scope="module")
def closed_room():
    return generators.box_room(60)


def test_automatic_view_of_a_closed_room_is_from_inside(closed_room):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    view = interior_view(closed_room)
    assert view is not None
    eye = np.array(view["position"])
    bounds = np.array(closed_room.GetBounds()).reshape(3, 2)
    assert (bounds[:, 0] < eye).all() and (eye < bounds[:, 1]).all()
    # Not inside any of the room's boxes (cells after the room and its light,
    # five per box): outside each box's bounding box.
    points = vtk_to_numpy(closed_room.GetPoints().GetData())
    cells = vtk_to_numpy(closed_room.GetPolys().GetData()).reshape(-1, 5)[:, 1:]
    for first in range(7, len(cells), 5):
        corners = points[cells[first:first + 5].ravel()]
        inside = (corners.min(axis=0) < eye) & (eye < corners.max(axis=0))
        assert not inside.all()
    # The view looks at a wall, horizontally, from in front of it.
    direction = np.array(view["focal_point"]) - eye
    assert abs(direction[1]) < 1e-9 and np.linalg.norm(direction) > 0.5
    # The Cornell box is open at the front: no inside view, the framing one.
    assert interior_view(penumbra.load_scene("cornell")) is None


def test_closed_room_renders_its_interior(closed_room, tmp_path):
    Testing.VTK_TEMP_DIR = str(tmp_path)
    window = make_render_window(closed_room, camera="auto", size=(300, 300))
    window.Render()
    Testing.compareImage(window, os.path.join(BASELINE_DIR, "TestRenderClosedRoom.png"),
                         threshold=0.15)


def test_render_with_an_explicit_camera(closed_room, tmp_path):
    path = tmp_path / "room.vtp"
    assert write_vtp(closed_room, path)
    picture = tmp_path / "room.png"
    result = run_penumbra("render", path, "-o", picture, "--camera", "1,1.5,1:5,1,5",
                          "--fov", "80", "--size", "64", "48")
    assert result.returncode == 0, result.stderr
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(str(picture))
    reader.Update()
    assert reader.GetOutput().GetDimensions()[:2] == (64, 48)
