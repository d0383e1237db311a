#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Display resampling: output size and accuracy of the uniform and the adaptive display.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/display_benchmark.py \\
        [--scenes room1000 room1000direct cornell strip occluder seven blind]
        [--tolerances 0.02 0.01 0.005] [--compact 0.001 0.002 0.005] [--compact-levels 2]

Each scene is solved once with vtkPenumbraSolver's defaults (the direct-light scenes strip,
occluder, seven and blind with the interreflections off; "room1000" is
penumbra.generators.box_room(1000, seed=1), as in scale_benchmark.py, and "room1000direct"
the same room with the interreflections off), and the samples are reconstructed for
display several times from the same solve: with the reconstructor's defaults (the compact
display), uniformly (DisplayTolerance 0, SubdivisionLevel 2: the dense display; and 4),
adaptively at each of --tolerances, compacted from the uniform display of each of
--compact-levels (SubdivisionLevel) at each of --compact (CompactTolerance), and densely as
the reference. Every display but the default one has CompactIndirectTolerance 0, and
CompactTolerance 0 unless compacted. For each display it prints the output
triangles, the size of the .vtp the command line writes (binary, zlib), the time of the
reconstructor, and the displayed radiance (linear over the output triangles) at 4,000
random points (area-weighted over all surfaces) against:

- the same solve's dense display (uniform SubdivisionLevel 8; 6 for room1000, whose level 8
  would not fit in memory): the display's own error, everything else being equal. Its
  own deviation from the cubic is 1/16 (1/9) of level 2's;
- for the direct-light scenes (room1000direct too), exact values at 4,000 random floor
  points (as defaults_benchmark.py --direct); for the Cornell box, the Mitsuba 3 reference (as
  compare_cornell.py): the whole solution's error, of which the display is one part.

Errors are relative to the reference's mean over the points of the same surface, all
channels: RMS, 99th percentile and maximum.
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DIRECT = ("strip", "occluder", "seven", "blind", "room1000direct")
POINTS = 4000


def stages_of(name):
    """The solve of a scene up to the reconstructor: (scene, the stage the
    reconstructor reads, direct only)."""
    from vtkmodules.vtkCommonExecutionModel import vtkTrivialProducer

    import penumbra
    from penumbra.generators import box_room
    from penumbra.pipeline import build_pipeline

    room = name.startswith("room1000")
    scene = box_room(1000, seed=1) if room else penumbra.load_scene(name)
    source = vtkTrivialProducer()
    source.SetOutput(scene)
    direct = name in DIRECT
    stages = build_pipeline(source.GetOutputPort(), indirect=not direct)
    last = stages["evaluator"] if direct else stages["shooter"]
    penumbra.run_filter(last)
    return scene, last


def display(samples, tolerance, level, compact=0.0):
    """The reconstructor's output from the solved samples, and its time (level None:
    the reconstructor's defaults)."""
    import penumbra
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    reconstructor = penumbra.vtkPenumbraRadianceReconstructor()
    reconstructor.SetInputConnection(samples.GetOutputPort())
    if level is not None:
        reconstructor.SetDisplayTolerance(tolerance)
        reconstructor.SetSubdivisionLevel(level)
        reconstructor.SetCompactTolerance(compact)
        reconstructor.SetCompactIndirectTolerance(0.0)
    start = time.perf_counter()
    output = penumbra.run_filter(reconstructor)
    seconds = time.perf_counter() - start
    result = vtkPolyData()
    result.ShallowCopy(output)
    return result, seconds


def vtp_megabytes(result):
    from penumbra.export import write_vtp

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "result.vtp")
        write_vtp(result, path)
        return os.path.getsize(path) / 1e6


def statistics(e):
    return 100 * np.sqrt(np.mean(e ** 2)), 100 * np.percentile(e, 99), 100 * e.max()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+",
                        default=["room1000", "cornell"] + list(DIRECT))
    parser.add_argument("--tolerances", nargs="+", type=float, default=[0.02, 0.01, 0.005])
    parser.add_argument("--compact", nargs="+", type=float, default=[0.001, 0.002, 0.005])
    parser.add_argument("--compact-levels", nargs="+", type=int, default=[2],
                        help="the uniform levels the compact displays are merged from")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args(argv)
    from vtkmodules.vtkCommonCore import vtkSMPTools

    vtkSMPTools.Initialize(args.threads)
    sys.path.insert(0, HERE)
    from defaults_benchmark import errors, random_points
    from speed_accuracy import cornell_errors, displayed_radiance, exact_radiance, floor_points

    print("| scene | display | triangles | .vtp | reconstructor | against dense: RMS / p99 / "
          "max | against exact or Mitsuba: RMS / p99 / max |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name in args.scenes:
        scene, samples = stages_of(name)
        dense, _ = display(samples, 0.0, 6 if name.startswith("room1000") else 8)
        reference = random_points(dense, POINTS)
        del dense
        if name in DIRECT:
            floor = floor_points(scene, POINTS)
            exact = exact_radiance(scene, floor)
        displays = ([("default", 0.0, None, 0.0), ("uniform 2", 0.0, 2, 0.0),
                     ("uniform 4", 0.0, 4, 0.0)]
                    + [("tolerance %g" % t, t, 2, 0.0) for t in args.tolerances]
                    + [("compact %g from %d" % (c, level), 0.0, level, c)
                       for level in args.compact_levels for c in args.compact])
        for label, tolerance, level, compact in displays:
            result, seconds = display(samples, tolerance, level, compact)
            against = "%.3g%% / %.3g%% / %.3g%%" % statistics(errors(result, reference))
            if name in DIRECT:
                shown = displayed_radiance(result, floor)
                valid = np.isfinite(shown)
                e = np.abs(shown[valid] - exact[valid]) / exact[valid].mean()
                truth = "%.3g%% / %.3g%% / %.3g%% (exact)" % statistics(e)
            elif name == "cornell":
                truth = "%.3g%% / %.3g%% / %.3g%% (Mitsuba)" % statistics(cornell_errors(result))
            else:
                truth = ""
            print("| %s | %s | %d | %.1f MB | %.1f s | %s | %s |" % (
                name, label, result.GetNumberOfPolys(), vtp_megabytes(result), seconds, against,
                truth), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
