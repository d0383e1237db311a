#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Radiance (rtrace -I) as a peer, first on CIE 171:2006 case 5.3.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/radiance_peer.py
        [--runs 3] [--out build/benchmarks]

Radiance comes from PyPI's pyradiance (Benchmarks/reference/setup_radiance.sh,
run here if its venv is missing). A Penumbra scene becomes Radiance
primitives: each polygon a `polygon` (same vertex order: Radiance's front is
Penumbra's), an emitter's material `light` with its Emission as radiance, the
others `plastic` with their Reflectance (no specularity). `rtrace -I` then
gives the irradiance at points (W m^-2 per channel for radiance in
W sr^-1 m^-2).

Case 5.3 (penumbra.generators.black_room: a black room, one ceiling source)
checks the conversion against Lambert's exact formula: a wrong front side
or unit would show as an error of order one, not as the fraction of a
percent that shrinks as the source subdivision is refined. It compares, at
256 floor and 192 wall points, Radiance's direct calculation over a ladder
of settings (-ds source subdivision, -dj jitter; -ab 0 as the room is black)
with Penumbra's sensors at the same points. Prints a table and draws a
chart (--out/radiance_cie53.png).
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def radiance_bin():
    """The folder of the Radiance binaries (the venv is made if missing)."""
    done = subprocess.run([os.path.join(HERE, "reference", "setup_radiance.sh")],
                          stdout=subprocess.PIPE, universal_newlines=True, check=True)
    return done.stdout.strip().splitlines()[-1]


def write_rad(scene, path):
    """The scene vtkPolyData as Radiance primitives (see the module doc)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reflectance = vtk_to_numpy(scene.GetCellData().GetArray("Reflectance"))
    emission = vtk_to_numpy(scene.GetCellData().GetArray("Emission"))
    with open(path, "w") as out:
        for i in range(scene.GetNumberOfCells()):
            cell = scene.GetCell(i)
            points = [cell.GetPoints().GetPoint(k) for k in range(cell.GetNumberOfPoints())]
            if emission[i].max() > 0.0:
                out.write("void light m%d\n0\n0\n3 %.17g %.17g %.17g\n\n" % ((i,) + tuple(emission[i])))
            else:
                out.write("void plastic m%d\n0\n0\n5 %.17g %.17g %.17g 0 0\n\n"
                          % ((i,) + tuple(reflectance[i])))
            out.write("m%d polygon p%d\n0\n0\n%d %s\n\n"
                      % (i, i, 3 * len(points), " ".join("%.17g %.17g %.17g" % p for p in points)))


def rtrace_irradiance(binaries, octree, points, options):
    """rtrace -I at points (n x 6: position, normal); returns (n x 3, seconds)."""
    env = dict(os.environ, RAYPATH=".:" + os.path.join(os.path.dirname(binaries), "lib"))
    text = "".join("%.17g %.17g %.17g %.17g %.17g %.17g\n" % tuple(p) for p in points)
    start = time.perf_counter()
    done = subprocess.run([os.path.join(binaries, "rtrace"), "-h", "-I", "-n", "2"] + options
                          + [octree], input=text, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, env=env, check=True)
    seconds = time.perf_counter() - start
    values = np.array([[float(v) for v in line.split()] for line in done.stdout.splitlines()
                       if line.strip()])
    return values, seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(REPO, "build", "benchmarks"))
    args = parser.parse_args(argv)
    import penumbra
    import penumbra.sensors
    from penumbra.generators import black_room

    sys.path.insert(0, os.path.join(REPO, "Testing", "Python"))
    from test_irradiance import LUMINANCE, SOURCE, lambert_irradiance

    binaries = radiance_bin()
    scene = black_room(luminance=LUMINANCE)
    work = tempfile.mkdtemp(prefix="penumbra-radiance-")
    write_rad(scene, os.path.join(work, "scene.rad"))
    octree = os.path.join(work, "scene.oct")
    with open(octree, "wb") as out:
        subprocess.run([os.path.join(binaries, "oconv"), os.path.join(work, "scene.rad")],
                       stdout=out, check=True)
    grid = np.arange(0.125, 4.0, 0.25)
    sets = {
        "floor": np.array([(x, 0.0, z, 0, 1, 0) for x in grid for z in grid], dtype=float),
        "wall": np.array([(0.0, y, z, 1, 0, 0) for y in np.arange(0.125, 3.0, 0.25) for z in grid],
                         dtype=float),
    }
    ladder = [["-ab", "0", "-ds", "0.2"], ["-ab", "0", "-ds", "0.05"],
              ["-ab", "0", "-ds", "0.01"], ["-ab", "0", "-ds", "0.2", "-dj", "0.7"],
              ["-ab", "0", "-ds", "0.01", "-dj", "0.7"]]
    rows = []
    for name, points in sets.items():
        exact = np.array([lambert_irradiance(p[:3], p[3:], SOURCE, LUMINANCE) for p in points])

        def error(values):
            return np.abs(values - exact).max() / exact.mean(), \
                np.sqrt(((values - exact) ** 2).mean()) / exact.mean()

        for options in ladder:
            times = []
            for _ in range(args.runs):
                values, seconds = rtrace_irradiance(binaries, octree, points, options)
                times.append(seconds)
            rows.append((name, "Radiance rtrace -I " + " ".join(options),
                         *error(values[:, 0]), statistics.median(times)))
        times = []
        for _ in range(args.runs):
            start = time.perf_counter()
            values = penumbra.sensors.evaluate(None, scene, points[:, :3], points[:, 3:])
            times.append(time.perf_counter() - start)
        rows.append((name, "Penumbra sensors", *error(values[:, 0]), statistics.median(times)))
    print("CIE 171:2006 case 5.3 at %d floor and %d wall points: largest and RMS error "
          "relative to the mean exact value" % (len(sets["floor"]), len(sets["wall"])))
    print("| surface | program and settings | largest error | RMS error | time (s) |")
    print("| --- | --- | --- | --- | --- |")
    for name, what, largest, rms, seconds in rows:
        print("| %s | %s | %.4f%% | %.4f%% | %.3f |" % (name, what, 100 * largest, 100 * rms, seconds))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    os.makedirs(args.out, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharex=True)
    for axis, name in zip(axes, sets):
        mine = [r for r in rows if r[0] == name]
        axis.barh(range(len(mine)), [max(100 * r[2], 1e-10) for r in mine],
                  color=["tab:orange" if r[1].startswith("Penumbra") else "tab:blue" for r in mine])
        axis.set_yticks(range(len(mine)))
        axis.set_yticklabels([r[1].replace("Radiance rtrace -I ", "rtrace ") for r in mine],
                             fontsize=8)
        axis.invert_yaxis()
        axis.set_xscale("log")
        axis.set_xlabel("largest error / mean (%)")
        axis.set_title("CIE 5.3, %s" % name)
    fig.tight_layout()
    path = os.path.join(args.out, "radiance_cie53.png")
    fig.savefig(path, dpi=90)
    print("wrote", path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
