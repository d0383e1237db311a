# SPDX-License-Identifier: GPL-3.0-or-later
"""The examples the README shows run as written."""
import os
import subprocess
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from conftest import SOURCE_DIR


def test_python_cornell_example(tmp_path):
    out = tmp_path / "example.vtp"
    script = os.path.join(SOURCE_DIR, "Examples", "Python", "cornell_scene.py")
    result = subprocess.run([sys.executable, script, str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert result.returncode == 0, result.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    assert reader.GetOutput().GetCellData().GetArray("Reflectance") is not None
    assert reader.GetOutput().GetNumberOfCells() > 0


def test_readme_python_snippet_is_the_example():
    """The README quotes Examples/Python/solve_cornell.py; keep them in step."""
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    example = open(os.path.join(SOURCE_DIR, "Examples", "Python", "solve_cornell.py")).read()
    body = example.split('"""', 2)[2].strip()
    assert body in readme


def _code_block(text, language):
    return text.split("```%s\n" % language, 1)[1].split("```", 1)[0]


def test_readme_cxx_snippet_is_the_example():
    """The README's C++ block is a contiguous excerpt of Examples/Cxx/PenumbraExample.cxx
    (built and run by test_install)."""
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    source = open(os.path.join(SOURCE_DIR, "Examples", "Cxx", "PenumbraExample.cxx")).read()
    excerpt = [line.strip() for line in _code_block(readme, "cpp").splitlines() if line.strip()]
    lines = [line.strip() for line in source.splitlines()]
    starts = [k for k in range(len(lines)) if lines[k:k + len(excerpt)] == excerpt]
    assert excerpt and starts, "the README's C++ block is not in the example"


def test_readme_commands_match_ci():
    """.ci/run calls exactly the README's test command."""
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    ci = open(os.path.join(SOURCE_DIR, ".ci", "run")).read()
    assert "./build.sh test" in readme and "./build.sh test" in ci.splitlines()[-1]
    assert "./build.sh run" in readme


def test_python_compose_filters_example(tmp_path):
    out = tmp_path / "seven.vtp"
    script = os.path.join(SOURCE_DIR, "Examples", "Python", "compose_filters.py")
    result = subprocess.run([sys.executable, script, "seven", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert result.returncode == 0, result.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    assert reader.GetOutput().GetPointData().GetArray("Radiance") is not None


def test_work_plane_example(tmp_path):
    """The lighting example: 400 sensors, a CSV with their illuminance and a map."""
    script = os.path.join(SOURCE_DIR, "Examples", "Python", "work_plane_illuminance.py")
    png, table = tmp_path / "plane.png", tmp_path / "plane.csv"
    result = subprocess.run([sys.executable, script, str(png), str(table)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=300)
    assert result.returncode == 0, result.stdout
    lines = table.read_text().splitlines()
    assert lines[0].endswith("irradiance_r,irradiance_g,irradiance_b") and len(lines) == 401
    lux = [float(line.split(",")[6]) for line in lines[1:]]
    assert min(lux) > 0.0 and png.stat().st_size > 0


def test_readme_solve_snippet_runs(tmp_path):
    readme = open(os.path.join(SOURCE_DIR, "README.md")).read()
    blocks = [b.split("```", 1)[0] for b in readme.split("```python\n")[1:]]
    snippet = [b for b in blocks if "penumbra.solve(" in b]
    assert snippet, "the README shows penumbra.solve"
    result = subprocess.run([sys.executable, "-c", snippet[0], str(tmp_path / "cornell.vtp")],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=300, cwd=str(tmp_path))
    assert result.returncode == 0, result.stdout
    assert "triangles" in result.stdout
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(tmp_path / "cornell.vtp"))
    reader.Update()
    assert reader.GetOutput().GetPointData().GetArray("Radiance") is not None
