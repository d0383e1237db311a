#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Radiance (rtrace -I) as a peer, first on CIE 171:2006 case 5.3.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/radiance_peer.py
        [--runs 3] [--out build/benchmarks]

Radiance comes from PyPI's pyradiance (Benchmarks/reference/setup_radiance.sh,
run here if its venv is missing). A Penumbra scene becomes Radiance
primitives (Benchmarks/radiance_scene.py: each polygon a `polygon`, same
vertex order so that Radiance's front is Penumbra's; an emitter's material
`light` with its Emission as radiance, the others `plastic` with their
Reflectance, no specularity). `rtrace -I` then gives the irradiance at
points (W m^-2 per channel for radiance in W sr^-1 m^-2).

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
import sys
import tempfile
import time

import numpy as np

from radiance_scene import REPO, make_octree, radiance_bin, rtrace_irradiance


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
    octree = make_octree(binaries, scene, tempfile.mkdtemp(prefix="penumbra-radiance-"))
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
