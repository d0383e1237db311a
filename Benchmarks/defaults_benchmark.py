#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Choosing a default: one setting of vtkPenumbraSolver over several scenes.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Benchmarks/defaults_benchmark.py \
        --setting ExactPowerFraction --values 1 0.1 0.05 0.01 [--runs 3] [--scenes ...]

For each scene and value, solves with vtkPenumbraSolver (every other setting at its
default; median wall time of --runs solves, 2 threads) and measures the displayed radiance
(linear over the output triangles) at 4,000 random points of all receiving surfaces
(area-weighted) against a converged solve of the same scene: every shot exact, shooting to
1e-4 unshot power, sampling tolerance 5e-4, display subdivision 4. The error is |value -
reference| relative to the reference's mean over the points of the same surface (so that a
dim surface counts as much as a bright one), all channels: the RMS, 99th percentile and
maximum. The Cornell box, where a solve with every shot exact takes too
long, is compared with the Mitsuba 3 path-traced reference of Benchmarks/reference
instead (floor and back wall pixels; the reference's own noise is 0.17%). Prints a Markdown table
and draws the error against time per scene into --out/defaults_<setting>.png.

With --direct, the interreflections are off and the error is that of the displayed floor
radiance against exact values at 4,000 random floor points (first channel), on the
built-in strip, occluder, seven and blind.

Scenes: the built-in cornell, seven and blind; "baffle", a floor lit only by a half-lit
panel (a light shines on the panel's upper part over a black baffle that hides it from the
floor and casts the panel's shadow onto it); "room100", penumbra.generators.box_room(100).
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

from penumbra.generators import scene_from_polygons

HERE = os.path.dirname(os.path.abspath(__file__))
POINTS = 4000
INTEGER_SETTINGS = ("SubdivisionLevel",)
REFERENCE = {"ExactPowerFraction": 0.0, "UnshotFraction": 1e-4, "SamplingTolerance": 5e-4,
             "SubdivisionLevel": 4}


def load(name):
    import penumbra
    from penumbra.generators import box_room

    if name == "baffle":
        from penumbra.generators import half_lit_panel

        validator = penumbra.vtkPenumbraSceneValidator()
        validator.SetInputData(half_lit_panel())
        return penumbra.run_filter(validator)
    if name == "room100":
        return box_room(100, seed=1)
    return penumbra.load_scene(name)


def solve(scene, settings, threads=2):
    import penumbra
    from vtkmodules.vtkCommonCore import vtkSMPTools
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    vtkSMPTools.Initialize(threads)
    solver = penumbra.vtkPenumbraSolver()
    solver.SetInputData(scene)
    for key, value in settings.items():
        getattr(solver, "Set" + key)(value)
    start = time.perf_counter()
    output = penumbra.run_filter(solver)
    seconds = time.perf_counter() - start
    result = vtkPolyData()
    result.ShallowCopy(output)
    return result, seconds


def random_points(result, count, seed=11):
    """Area-weighted random points on the result's triangles, their surface ids and the
    result's displayed radiance there."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    lines = result.GetNumberOfLines()
    ids = vtk_to_numpy(result.GetCellData().GetArray("SurfaceId"))[lines:]
    triangles = vtk_to_numpy(result.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    xyz = vtk_to_numpy(result.GetPoints().GetData()).astype(float)
    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance")).astype(float)
    a, b, c = (xyz[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    rng = np.random.default_rng(seed)
    chosen = rng.choice(len(area), size=count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    w = 1 - u - v
    t = triangles[chosen]
    points = w[:, None] * xyz[t[:, 0]] + u[:, None] * xyz[t[:, 1]] + v[:, None] * xyz[t[:, 2]]
    values = (w[:, None] * radiance[t[:, 0]] + u[:, None] * radiance[t[:, 1]]
              + v[:, None] * radiance[t[:, 2]])
    return points, ids[chosen], values


def displayed(result, points, surfaces):
    """The result's displayed radiance at points of the given surfaces."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkGenericCell, vtkStaticCellLocator

    sys.path.insert(0, HERE)
    from compare_cornell import surface_mesh

    radiance = vtk_to_numpy(result.GetPointData().GetArray("Radiance")).astype(float)
    out = np.full((len(points), 3), np.nan)
    cell = vtkGenericCell()
    pcoords, weights = [0.0, 0.0, 0.0], [0.0] * 8
    for surface in np.unique(surfaces):
        mesh = surface_mesh(result, int(surface))
        locator = vtkStaticCellLocator()
        locator.SetDataSet(mesh)
        locator.BuildLocator()
        for k in np.nonzero(surfaces == surface)[0]:
            if locator.FindCell(list(points[k]), 1e-7, cell, pcoords, weights) >= 0:
                out[k] = sum(weights[n] * radiance[cell.GetPointId(n)] for n in range(3))
    return out


def errors(result, reference_sample):
    points, surfaces, expected = reference_sample
    shown = displayed(result, points, surfaces)
    valid = np.all(np.isfinite(shown), axis=1)
    relative = []
    for surface in np.unique(surfaces[valid]):
        mine = valid & (surfaces == surface)
        mean = expected[mine].mean(axis=0)
        lit = mean > 0
        if lit.any():
            relative.append((np.abs(shown[mine][:, lit] - expected[mine][:, lit])
                             / mean[lit]).ravel())
    return np.concatenate(relative)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--setting", required=True, help="a vtkPenumbraSolver setting")
    parser.add_argument("--values", required=True, nargs="+", type=float)
    parser.add_argument("--scenes", nargs="+")
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--direct", action="store_true",
                        help="direct light only, against exact values at 4,000 random floor "
                             "points (the built-in strip, occluder, seven and blind)")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "build",
                                                      "benchmarks"))
    args = parser.parse_args(argv)
    if not args.scenes:
        args.scenes = (["strip", "occluder", "seven", "blind"] if args.direct
                       else ["cornell", "seven", "blind", "baffle", "room100"])
    os.makedirs(args.out, exist_ok=True)
    sys.path.insert(0, HERE)
    rows = []
    print("| scene | %s | time (s) | points | RMS | p99 | max | reference |" % args.setting)
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for name in args.scenes:
        scene = load(name)
        sample = None
        if args.direct:
            from speed_accuracy import exact_radiance, floor_points
            floor = floor_points(scene, POINTS)
            exact = exact_radiance(scene, floor)
        elif name != "cornell":
            reference, _ = solve(scene, REFERENCE)
            sample = random_points(reference, POINTS)
        for value in args.values:
            settings = {args.setting: int(value) if args.setting in INTEGER_SETTINGS else value}
            if args.direct:
                settings["Indirect"] = False
            times = []
            for _ in range(args.runs):
                result, seconds = solve(scene, settings)
                times.append(seconds)
            if args.direct:
                from speed_accuracy import displayed_radiance
                shown = displayed_radiance(result, floor)
                valid = np.isfinite(shown)
                e, against = np.abs(shown[valid] - exact[valid]) / exact[valid].mean(), "exact"
            elif sample is None:
                from speed_accuracy import cornell_errors
                e, against = cornell_errors(result), "Mitsuba"
            else:
                e, against = errors(result, sample), "converged"
            row = (name, value, statistics.median(times), result.GetNumberOfPoints(),
                   100 * np.sqrt(np.mean(e ** 2)), 100 * np.percentile(e, 99), 100 * e.max(),
                   against)
            rows.append(row)
            print("| %s | %g | %.2f | %d | %.3g%% | %.3g%% | %.3g%% | %s |" % row, flush=True)
    chart(rows, args.setting, os.path.join(args.out, "defaults_%s.png" % args.setting))
    return 0


def chart(rows, setting, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4.5))
    for name in dict.fromkeys(r[0] for r in rows):
        mine = [r for r in rows if r[0] == name]
        axes.loglog([r[2] for r in mine], [r[4] for r in mine], "o-", label=name)
        for r in mine:
            axes.annotate("%g" % r[1], (r[2], r[4]), fontsize=7)
    axes.set_xlabel("time (s)")
    axes.set_ylabel("RMS error against the converged solve (%)")
    axes.set_title("vtkPenumbraSolver %s" % setting)
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    print("chart:", path)


if __name__ == "__main__":
    sys.exit(main())
