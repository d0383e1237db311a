# SPDX-License-Identifier: GPL-3.0-or-later
"""A Penumbra scene as Radiance primitives, and Radiance's irradiance at points.

Shared by Benchmarks/radiance_peer.py and Benchmarks/speed_accuracy.py.
Radiance comes from PyPI's pyradiance, whose wheel bundles the binaries
(oconv, rtrace) and their library files; Benchmarks/reference/
setup_radiance.sh installs it into build/_deps/radiance-venv.

The conversion (write_rad): each polygon cell becomes a `polygon` with the
same vertex order, so Radiance's front side (right-hand rule) is Penumbra's.
A non-emitting cell's material is `plastic` with its Reflectance and no
specularity (Lambertian, reflectance per channel). An emitting cell is a
light source of radiance Emission (W sr^-1 m^-2 per channel, emitted on the
front side only): `light` when it does not reflect, else `illum` whose
alternate material is a `plastic` of its Reflectance, so that the direct
calculation samples it as a source while the indirect rays that hit it see
a reflector (the Cornell box's light reflects 78%). Radiance's `plastic`
reflects on both sides where Penumbra's surfaces reflect on the front only;
in the scenes measured no lit back face is seen. `rtrace -I` gives the
irradiance at a point for a given surface normal in W m^-2 per channel, so
a Lambertian surface's outgoing radiance is reflectance * E / pi.
"""
import glob
import os
import subprocess
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
RADIANCE_VENV = os.path.join(REPO, "build", "_deps", "radiance-venv")


def installed_bin(venv=RADIANCE_VENV):
    """The folder of the Radiance binaries in an existing venv, or None."""
    found = sorted(glob.glob(os.path.join(venv, "lib", "python3*", "site-packages", "pyradiance",
                                          "bin", "rtrace")))
    return os.path.dirname(found[-1]) if found else None


def radiance_bin():
    """The folder of the Radiance binaries (the venv is made if missing)."""
    done = subprocess.run([os.path.join(HERE, "reference", "setup_radiance.sh")],
                          stdout=subprocess.PIPE, universal_newlines=True, check=True)
    return done.stdout.strip().splitlines()[-1]


def environment(binaries):
    """The environment the binaries need: RAYPATH to their library files
    (rtrace reads rayinit.cal from there)."""
    return dict(os.environ, RAYPATH=".:" + os.path.join(os.path.dirname(binaries), "lib"))


def write_rad(scene, path):
    """The scene vtkPolyData as Radiance primitives (see the module doc)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    with open(path, "w") as out:
        for i in range(scene.GetNumberOfCells()):
            cell = scene.GetCell(i)
            points = [cell.GetPoints().GetPoint(k) for k in range(cell.GetNumberOfPoints())]
            diffuse = "5 %.17g %.17g %.17g 0 0" % tuple(reflectance[i])
            if emission[i].max() > 0.0 and reflectance[i].max() > 0.0:
                out.write("void plastic r%d\n0\n0\n%s\n\n" % (i, diffuse))
                out.write("void illum m%d\n1 r%d\n0\n3 %.17g %.17g %.17g\n\n"
                          % ((i, i) + tuple(emission[i])))
            elif emission[i].max() > 0.0:
                out.write("void light m%d\n0\n0\n3 %.17g %.17g %.17g\n\n"
                          % ((i,) + tuple(emission[i])))
            else:
                out.write("void plastic m%d\n0\n0\n%s\n\n" % (i, diffuse))
            out.write("m%d polygon p%d\n0\n0\n%d %s\n\n"
                      % (i, i, 3 * len(points), " ".join("%.17g %.17g %.17g" % p for p in points)))


def make_octree(binaries, scene, folder):
    """Writes the scene's primitives and their octree into `folder`; returns
    the octree's path."""
    source = os.path.join(folder, "scene.rad")
    octree = os.path.join(folder, "scene.oct")
    write_rad(scene, source)
    with open(octree, "wb") as out:
        subprocess.run([os.path.join(binaries, "oconv"), source], stdout=out, check=True,
                       env=environment(binaries))
    return octree


def rtrace_irradiance(binaries, octree, points, options, processes=2):
    """`rtrace -I` at points (n x 6: position, normal) with `processes`
    rendering processes (-n); returns (n x 3 irradiance, seconds). Rays and
    results pass as binary doubles (-fdd): formatting text would cost more
    than tracing in the fastest settings."""
    rays = np.ascontiguousarray(points, dtype="<f8")
    start = time.perf_counter()
    done = subprocess.run([os.path.join(binaries, "rtrace"), "-h", "-fdd", "-I", "-n",
                           str(processes)] + list(options) + [octree], input=rays.tobytes(),
                          stdout=subprocess.PIPE, env=environment(binaries), check=True)
    seconds = time.perf_counter() - start
    return np.frombuffer(done.stdout, dtype="<f8").reshape(-1, 3), seconds
