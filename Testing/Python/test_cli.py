# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line: help, scene list, the main job, and one-line errors."""
import os

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from conftest import BUILD_DIR, SCENE_DIR, run_penumbra


def test_help_lists_commands():
    result = run_penumbra("--help")
    assert result.returncode == 0
    for command in ("solve", "scenes", "render"):
        assert command in result.stdout
    solve_help = run_penumbra("solve", "--help")
    assert solve_help.returncode == 0 and "--threads" in solve_help.stdout


def test_scenes_lists_builtin_scenes():
    result = run_penumbra("scenes")
    assert result.returncode == 0
    names = [line.split()[0] for line in result.stdout.splitlines() if line.strip()]
    assert {"cornell", "strip", "occluder", "seven", "blind"} <= set(names)


def test_solve_cornell_writes_vtp_and_png(tmp_path):
    vtp, png = tmp_path / "cornell.vtp", tmp_path / "cornell.png"
    result = run_penumbra("solve", "cornell", "-o", vtp, "--png", png, "--threads", 2,
                          cwd=str(tmp_path))
    assert result.returncode == 0, result.stderr
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(vtp))
    reader.Update()
    data = reader.GetOutput()
    assert data.GetNumberOfPolys() > 0 and data.GetNumberOfLines() > 0
    for name in ("Radiance", "RadianceErrorEstimate"):
        assert data.GetPointData().GetArray(name).GetNumberOfComponents() == 3
    for name in ("SurfaceId", "DiscontinuityOrder", "SourceId"):
        assert data.GetCellData().GetArray(name) is not None
    radiance = vtk_to_numpy(data.GetPointData().GetArray("Radiance"))
    assert np.isfinite(radiance).all() and radiance.min() >= 0 and radiance.max() > 0
    image = vtkPNGReader()
    image.SetFileName(str(png))
    image.Update()
    pixels = vtk_to_numpy(image.GetOutput().GetPointData().GetScalars())
    assert image.GetOutput().GetDimensions()[:2] == (512, 512)
    # A picture, not a blank: red and green walls both show.
    r, g, b = (pixels[:, k].astype(float) for k in range(3))
    red = (r > 60) & (r > 1.5 * g) & (r > 1.5 * b)
    green = (g > 40) & (g > 1.2 * r) & (g > 1.5 * b)
    assert red.mean() > 0.05 and green.mean() > 0.05


def test_solve_obj_scene(tmp_path):
    result = run_penumbra("solve", os.path.join(SCENE_DIR, "box.obj"), "-o", tmp_path / "box.vtp")
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "box.vtp").stat().st_size > 0


def _assert_one_line_error(result, fragment):
    assert result.returncode != 0
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("penumbra: error:") and fragment in lines[0], lines[0]


def test_unknown_scene_is_a_one_line_error(tmp_path):
    _assert_one_line_error(run_penumbra("solve", "nowhere", "-o", tmp_path / "x.vtp"),
                           "unknown scene 'nowhere'")


def test_missing_file_is_a_one_line_error(tmp_path):
    _assert_one_line_error(run_penumbra("solve", tmp_path / "absent.obj", "-o",
                                        tmp_path / "x.vtp"), "not found")


def test_invalid_obj_is_a_one_line_error(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 0 0\nf 1 2 3\n")
    _assert_one_line_error(run_penumbra("solve", bad, "-o", tmp_path / "x.vtp"), "cell 0")
    assert not (tmp_path / "x.vtp").exists()


def test_bad_threads_setting(tmp_path):
    result = run_penumbra("solve", "cornell", "-o", tmp_path / "x.vtp", "--threads", "0")
    assert result.returncode != 0 and "--threads" in result.stderr


def test_module_runs_from_any_directory(tmp_path):
    result = run_penumbra("--version", cwd="/")
    assert result.returncode == 0 and result.stdout.startswith("penumbra ")


def test_installed_script_in_build_tree(tmp_path):
    import subprocess
    script = os.path.join(BUILD_DIR, "bin", "penumbra")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    result = subprocess.run([script, "scenes"], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, universal_newlines=True)
    assert result.returncode == 0, result.stderr
    assert "cornell" in result.stdout


def _read_vtp(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def test_scene_command_writes_the_validated_scene(tmp_path):
    out = tmp_path / "box.vtp"
    result = run_penumbra("scene", os.path.join(SCENE_DIR, "box.obj"), "-o", out)
    assert result.returncode == 0, result.stderr
    scene = _read_vtp(out)
    assert scene.GetNumberOfCells() > 0
    for name in ("Reflectance", "Emission"):
        assert scene.GetCellData().GetArray(name).GetNumberOfComponents() == 3


def test_set_changes_a_solver_setting(tmp_path):
    """--set reaches the solver: direct light only gives no shots, and the
    adaptive display at DisplayTolerance 0.05 fewer output points than the
    default uniform one."""
    default = tmp_path / "default.vtp"
    coarse = tmp_path / "coarse.vtp"
    assert run_penumbra("solve", "occluder", "-o", default, "--quiet",
                        "--set", "Indirect=off").returncode == 0
    assert run_penumbra("solve", "occluder", "-o", coarse, "--quiet", "--set", "indirect=off",
                        "--set", "DisplayTolerance=0.05").returncode == 0
    assert _read_vtp(default).GetFieldData().GetArray("Shots") is None
    assert _read_vtp(coarse).GetNumberOfPoints() < _read_vtp(default).GetNumberOfPoints()


def test_coarse_level_is_reported(tmp_path):
    """Interreflections shot on the coarse level (here the Cornell box's on
    at most 4,000 points) are not silent: the summary after the solve says
    so, with the points and the lattice's spacing; the default solve does
    not."""
    out = tmp_path / "coarse.vtp"
    result = run_penumbra("solve", "cornell", "-o", out, "--set", "MaximumIndirectSamples=4000")
    assert result.returncode == 0, result.stderr
    lines = [line for line in result.stdout.splitlines() if "coarse level" in line]
    assert len(lines) == 1, result.stdout
    field = _read_vtp(out).GetFieldData()
    points = int(field.GetArray("IndirectSamples").GetValue(0))
    assert 0 < points <= 4000 + int(field.GetArray("IndirectSeparatePoints").GetValue(0))
    assert ("%d points" % points) in lines[0]
    default = run_penumbra("solve", "cornell", "-o", tmp_path / "default.vtp")
    assert "coarse level" not in default.stdout


def test_bad_set_is_a_one_line_error(tmp_path):
    out = tmp_path / "x.vtp"
    _assert_one_line_error(run_penumbra("solve", "cornell", "-o", out, "--set", "Nonsense=1"),
                           "Nonsense=1")
    _assert_one_line_error(run_penumbra("solve", "cornell", "-o", out, "--set",
                                        "SamplingTolerance=2"), "outside its range")
    _assert_one_line_error(run_penumbra("solve", "cornell", "-o", out, "--set",
                                        "Indirect=maybe"), "Indirect")


def test_settings_and_scenes_as_json():
    import json
    settings = json.loads(run_penumbra("settings", "--json").stdout)
    solver = {s["name"]: s for s in settings["vtkPenumbraSolver"]}
    assert solver["UnshotFraction"]["minimum"] is not None and "doc" in solver["UnshotFraction"]
    scenes = json.loads(run_penumbra("scenes", "--json").stdout)
    assert "cornell" in [s["name"] for s in scenes]
