# SPDX-License-Identifier: GPL-3.0-or-later
"""`cmake --install` into a fresh prefix gives Debian's layout, a working
`python3 -m penumbra` and `penumbra` script, and a CMake package that a
downstream C++ project (Examples/Cxx) finds with find_package(Penumbra)."""
import os
import subprocess
import sys

from conftest import BUILD_DIR, SOURCE_DIR


def _run(command, **kwargs):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, timeout=800, **kwargs)
    assert result.returncode == 0, "%s failed:\n%s" % (" ".join(command), result.stdout)
    return result.stdout


def test_install_layout_and_downstream_project(tmp_path):
    prefix = tmp_path / "prefix"
    _run(["cmake", "--install", BUILD_DIR, "--prefix", str(prefix)])
    libs = os.listdir(prefix / "lib")
    assert any(name.startswith("libvtkPenumbraFilters") for name in libs), libs
    assert any(name.startswith("libpenumbraTransport") for name in libs), libs
    package = prefix / "lib" / "python3" / "dist-packages" / "penumbra"
    assert (package / "__init__.py").is_file() and (package / "cli.py").is_file()
    assert (prefix / "bin" / "penumbra").is_file()
    assert (prefix / "lib" / "cmake" / "penumbra" / "PenumbraConfig.cmake").is_file()

    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(prefix / "lib" / "python3" / "dist-packages")
    out = _run(["/usr/bin/python3", "-m", "penumbra", "scenes"], cwd="/", env=env)
    assert "cornell" in out
    env.pop("PYTHONPATH")
    out = _run([str(prefix / "bin" / "penumbra"), "--version"], cwd="/", env=env)
    assert out.startswith("penumbra ")

    # The installed ParaView plugin runs the installed command.
    plugin = prefix / "lib" / "penumbra" / "paraview" / "PenumbraParaView.xml"
    assert plugin.is_file()
    from xml.etree import ElementTree
    scripts = [p.get("default_values") for p in ElementTree.parse(plugin).iter()
               if p.get("name") == "Script"]
    assert len(scripts) == 2
    for script in scripts:
        command = script.split("COMMAND = ", 1)[1].splitlines()[0]
        assert os.path.samefile(eval(command), prefix / "bin" / "penumbra")

    # A downstream C++ project, configured against the installed package only.
    build = tmp_path / "example-build"
    _run(["cmake", "-S", os.path.join(SOURCE_DIR, "Examples", "Cxx"), "-B", str(build),
          "-G", "Ninja", "-DCMAKE_PREFIX_PATH=%s" % prefix])
    _run(["cmake", "--build", str(build)])
    out = _run([str(build / "PenumbraExample"), str(tmp_path / "example.vtp")], cwd=str(tmp_path))
    assert (tmp_path / "example.vtp").stat().st_size > 0, out
    # The example solved the box: radiance everywhere, finite, non-negative, lit.
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(tmp_path / "example.vtp"))
    reader.Update()
    radiance = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("Radiance"))
    assert len(radiance) > 1000 and (radiance >= 0).all() and radiance.max() > 0
    # ... and shot the interreflections down to the default unshot fraction.
    field = reader.GetOutput().GetFieldData()
    assert field.GetArray("Shots").GetValue(0) > 0
    assert field.GetArray("UnshotFraction").GetValue(0) <= 1e-3
